"""Model predictive contouring control on the 3D-LIP (paper A, eqs. 6–19).

Decision variables per stage (acados naming): the stage state ``x = [x, ẋ, y, ẏ, θ_h, ϑ]``
(3D-LIP state plus the path parameter ϑ, arc length [m]) and the stage input
``u = [uˣ, uʸ, u^θ, v]`` (foot offset, heading change, path progress per step)::

    minimise   Σ_{k<N} ‖ē(x_k, ϑ_k)‖²_Q̄ + ‖u_k‖²_R − ρ v_k²  +  ‖ē(x_N, ϑ_N)‖²_W̄
    subject to x_0 = x_init, ϑ_0 = ϑ_init                           (x_0 fixed by bounds)
               x_{k+1} = A x_k + B u_k,  ϑ_{k+1} = ϑ_k + v_k         (13), (5)
               lb_k ≤ Rot(θ_k + u^θ_k)ᵀ u_k ≤ ub_k                  (15), alternating sides
               δ_min² ≤ Δx_k² + Δy_k² ≤ δ_max²                      (16)
               b_{k+1}(x_{k+1}) ≥ (1 − γ) b_k(x_k)  for every obstacle (17)
               ϑ ∈ [0, ϑ_T], v ∈ [0, v_max]

ē = P(φ_d(ϑ)) (C x − y_d(ϑ)) are the contouring/lag errors. The Cartesian MPC is this
planner with Q̄ = αI, W̄ = βI (see :meth:`MpccParams.overtake_cartesian`) — not a second code
path.

Two solvers share the very same symbolic problem (:func:`build_problem`):

- ``"sqp"`` (default, :func:`build_sqp`): the generic
  :class:`~lipmpcc.solvers.condensed_sqp.CondensedSqp` on the condensed problem (the states
  eliminated) with the exact, convexified Hessian, DAQP for the QPs, JIT-compiled derivatives,
  warm-started from the shifted previous solution;
- ``"ipopt"`` (:func:`build_ipopt`): the paper's formulation, CasADi ``Opti`` + IPOPT (kept for the
  benchmark).

:class:`MpccPlanner` implements the planner contract (:mod:`lipmpcc.planners.base`): the LIP loop
(:mod:`lipmpcc.loops.lip`) calls :meth:`MpccPlanner.plan` at each support exchange. On solver
failure the planner returns the shifted previous plan (``used_fallback=True``, a plan whose status is
not ``"ok"``) and counts the failure; on a failure with no previous plan it raises
:class:`~lipmpcc.exceptions.NoFallbackPlanError`.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import Callable, Sequence

import casadi as ca
import numpy as np

from ..contouring import casadi_errors, errors as contouring_errors
from ..conventions import parse_side
from ..exceptions import ParameterError
from ..exclusive import exclusive
from ..models.lip3d import Lip3dModel, ReachabilityRectangle
from ..obstacles import Obstacle, barrier_params
from ..paths import Path
from ..solvers.condensed_sqp import CondensedSqp
from ..solvers.sqp_compiled import compiled_function
from ..validation import (
    choice,
    count,
    finite_array,
    finite_number,
    flag,
    non_negative_number,
    positive_number,
)
from .base import PlannerInput, StepPlan
from .liveness import barred_by, end_frame, hold_inputs, problem_path
from .mpcc_driver import MpccDriver
from .presets import MPCC_PRESET_FIELDS  # the presets' values, one definition (lipmpcc run --preset)

__all__ = [
    "MpccParams",
    "MpccResult",
    "MpccPlanner",
    "FixedStepFormulation",
    "FixedCall",
    "build_problem",
    "build_sqp",
    "build_ipopt",
    "FORMULATION_BUILDERS",
    "n_params",
    "obstacle_reach",
    "relevant_obstacles",
    "obstacle_capacity",
    "inert_obstacle",
    "rollout",
    "NX",
    "NU",
    "NB",
    "MAX_HORIZON",
]



def __getattr__(name: str) -> object:
    if name == "CondensedScp":  # the old MPCC-specific solver class
        import warnings

        warnings.warn(
            "lipmpcc.planners.mpcc.CondensedScp is deprecated: the solver is the generic "
            "lipmpcc.solvers.condensed_sqp.CondensedSqp, built for the MPCC by lipmpcc.planners.mpcc.build_sqp; "
            "removed in lipmpcc 0.3",
            DeprecationWarning,
            stacklevel=2,
        )
        return _CondensedScp
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


NX = 6  # stage state: LIP state (5) + path parameter
NU = 4  # stage input: ux, uy, u_theta, v
NB = 8  # barrier parameters per obstacle and stage: cx, cy, M (3), F (3)


#: Longest horizon accepted [steps] (the problem's size grows with N; paper A uses 5).
MAX_HORIZON = 100


def _pos(name: str, v: float, allow_zero: bool = False, unit: str = "") -> None:
    (non_negative_number if allow_zero else positive_number)(name, v, unit, error=ParameterError)


def _weights(name: str, value: object, n: int, expected: str) -> None:
    w = finite_array(name, value, (n,), error=ParameterError, what=expected)
    if np.any(w < 0):
        raise ParameterError(name, value, expected)


@dataclass(frozen=True)
class MpccParams:
    """Parameters of the MPCC (immutable).

    Attributes:
        N: horizon [steps].
        model: 3D-LIP (step duration T [s], height H [m]).
        rectangle: reachability rectangle (eq. 15).
        Q_bar: running weights (contouring, lag) [1/m²].
        W_bar: terminal weights (contouring, lag) [1/m²].
        R: input weights (uˣ, uʸ, u^θ).
        heading_weight: weight of the heading error, Σ_{k≥1} w (1 − cos(θ_k − φ_d(ϑ_k))), the
            planned heading against the path's tangent (0: paper A's cost, where only the heading
            change u^θ is weighted).
        lateral_nominal: the lateral foot offset l_nom [m] the input weight R_y is measured from: each stage's
            cost gains R_y (l_nom² − 2 l_nom σ l), l the new foot's offset from the COM across the new heading
            and σ the step's side, so that with R_x = R_y (paper A's presets) ‖u‖²_R becomes
            R_x f² + R_y (σ l − l_nom)² + R_θ (u^θ)², f the offset along the heading (0: paper A's ‖u‖²_R). With
            paper A's cost every step sits on the reachability's lateral lower bound, where a wider step costs
            2 R_y l_min δ, first order in δ: a dead band in the lateral tracking (docs/design.md, paper A on
            Digit v3, session 40).
        rho: progress reward ρ (eq. 6).
        v_max: max path progress per step [m].
        delta_min, delta_max: COM distance per step bounds [m] (eq. 16).
        gamma: CBF decay rate γ ∈ (0, 1) (eq. 17).
        robot_radius: radius of the robot's body disk around the COM [m].
        foot_radius: radius of the disk around a stance foot [m] (half of Digit's foot length).
        obstacle_margin: extra inflation of obstacles in the barriers, covering the motion
            between step instants [m].
        foot_clearance: keep each new foothold outside every obstacle (grown by
            foot_radius + obstacle_margin) at the start and end of its stance.
        solver: "sqp" (fast) or "ipopt" (paper's formulation).
        max_iter: solver iteration limit (IPOPT).
        jit: compile the SQP's CasADi functions to machine code with the system C compiler
            (once per process and problem, ~2 s; falls back to interpreted evaluation when no
            compiler works).
        restart_when_stalled: when the solution makes little progress (mean v < v_max/10),
            solve again from a guess with v = v_max/2 and keep the cheaper solution; and when the
            robot has stalled (its measured ϑ gained less than N v_max/20 over the last N steps,
            :mod:`lipmpcc.planners.liveness`), solve again from the cold starts and keep the
            cheapest (issue 31: the warm start kept the robot in the stand-still basin); stalled
            for twice as long, solve with the detour weights (paper A's overtaking preset) until
            past the stall (``detour_solves`` counts those solves).
        past_end: the planned ϑ may run past the path's end, along its end tangent, by the plan's reach
            N v_max (:func:`lipmpcc.planners.liveness.problem_path`): the progress reward does not vanish
            near the end (False: ϑ ≤ ϑ_T, paper A's constraint).
    """

    N: int = 5
    model: Lip3dModel = field(default_factory=Lip3dModel)
    rectangle: ReachabilityRectangle = field(default_factory=ReachabilityRectangle)
    Q_bar: tuple[float, float] = (300.0, 3.0)
    W_bar: tuple[float, float] = (300.0, 3.0)
    R: tuple[float, float, float] = (100.0, 100.0, 5.0)
    heading_weight: float = 0.0
    lateral_nominal: float = 0.0
    rho: float = 10.0
    v_max: float = 0.3
    delta_min: float = 0.03
    delta_max: float = 0.4
    gamma: float = 0.2
    robot_radius: float = 0.2
    foot_radius: float = 0.1
    obstacle_margin: float = 0.05
    foot_clearance: bool = True
    solver: str = "sqp"
    max_iter: int = 100
    restart_when_stalled: bool = True
    jit: bool = True
    past_end: bool = True

    def __post_init__(self) -> None:
        N = count("N", self.N, 1, MAX_HORIZON, error=ParameterError, what="an integer horizon")
        object.__setattr__(self, "N", N)  # np.int64 accepted, kept as an int
        if not isinstance(self.model, Lip3dModel):
            raise ParameterError("model", self.model, "a lipmpcc.models.lip3d.Lip3dModel")
        if not isinstance(self.rectangle, ReachabilityRectangle):
            raise ParameterError("rectangle", self.rectangle, "a lipmpcc.models.lip3d.ReachabilityRectangle")
        for name in ("Q_bar", "W_bar"):
            _weights(name, getattr(self, name), 2, "two non-negative weights (contouring, lag)")
        _weights("R", self.R, 3, "three non-negative weights (ux, uy, u_theta)")
        _pos("rho", self.rho, allow_zero=True)
        _pos("heading_weight", self.heading_weight, allow_zero=True)
        _pos("lateral_nominal", self.lateral_nominal, allow_zero=True, unit="m")
        _pos("v_max", self.v_max, unit="m")
        _pos("delta_min", self.delta_min, allow_zero=True, unit="m")
        _pos("delta_max", self.delta_max, unit="m")
        if self.delta_min >= self.delta_max:
            raise ParameterError("delta_min", self.delta_min, f"< delta_max = {self.delta_max}")
        gamma = finite_number("gamma", self.gamma, error=ParameterError)
        if not (0.0 < gamma < 1.0):
            raise ParameterError("gamma", self.gamma, "a CBF rate in (0, 1)")
        _pos("robot_radius", self.robot_radius, allow_zero=True, unit="m")
        _pos("foot_radius", self.foot_radius, allow_zero=True, unit="m")
        _pos("obstacle_margin", self.obstacle_margin, allow_zero=True, unit="m")
        for name in ("foot_clearance", "restart_when_stalled", "jit", "past_end"):
            flag(name, getattr(self, name), error=ParameterError)
        choice("solver", self.solver, ("sqp", "ipopt"), error=ParameterError)
        count("max_iter", self.max_iter, 1, error=ParameterError)

    # ---- paper A presets -------------------------------------------------------------------
    @classmethod
    def circle(cls, **kw: object) -> "MpccParams":
        """Paper A §IV-A: Q̄ = W̄ = diag(300, 3), ρ = 10, R = diag(100, 100, 5), v_max = 0.3, N = 5."""
        return cls(**{**MPCC_PRESET_FIELDS["circle"], **kw})

    @classmethod
    def overtake_cartesian(cls, **kw: object) -> "MpccParams":
        """Paper A §IV-B(a): Cartesian MPC, Q = W = 200 I, ρ = 50."""
        return cls(**{**MPCC_PRESET_FIELDS["cartesian"], **kw})

    @classmethod
    def overtake_mpcc(cls, **kw: object) -> "MpccParams":
        """Paper A §IV-B(b): MPCC, Q̄ = W̄ = diag(1, 1000), ρ = 50."""
        return cls(**{**MPCC_PRESET_FIELDS["overtake"], **kw})

    def with_(self, **kw: object) -> "MpccParams":
        """A copy with some fields replaced."""
        return replace(self, **kw)

    @property
    def obstacle_inflation(self) -> float:
        """How much each obstacle's semi-axes are grown in the barrier [m]."""
        return self.robot_radius + self.obstacle_margin


@dataclass
class MpccResult:
    """One MPCC solve.

    Attributes:
        found: the solver converged (False also when the fallback plan is returned).
        status: solver return status.
        iterations: solver iterations.
        solve_time: wall time of the solve, θ_init search included [s].
        cost: optimal cost (NaN on fallback).
        states: (N+1, 5) planned LIP states at step instants.
        theta: (N+1,) planned path parameter [m].
        v: (N,) path progress per step [m].
        inputs: (N, 3) planned [uˣ, uʸ, u^θ].
        footsteps: (N, 3) planned footholds [x, y, heading] in the world [m, m, rad].
        e_contouring: (N+1,) planned contouring errors ē_c [m].
        e_lag: (N+1,) planned lag errors ē_l [m].
        theta_init: ϑ_init used [m].
        stance_side: side of the first planned foothold (+1 left, −1 right).
        used_fallback: True when this is the shifted previous plan after a failure.
        held_by: on a fallback, the obstacles (indices in the solve's ``obstacles``) the replayed plan would
            have walked into (:func:`~lipmpcc.planners.liveness.barred_by`): the plan then steps in place
            (:func:`~lipmpcc.planners.liveness.hold_inputs`) instead; empty otherwise.
    """

    found: bool
    status: str
    iterations: int
    solve_time: float
    cost: float
    states: np.ndarray
    theta: np.ndarray
    v: np.ndarray
    inputs: np.ndarray
    footsteps: np.ndarray
    e_contouring: np.ndarray
    e_lag: np.ndarray
    theta_init: float
    stance_side: int
    used_fallback: bool = False
    held_by: list[int] = field(default_factory=list)

    @property
    def u0(self) -> np.ndarray:
        """The input to execute now, [uˣ, uʸ, u^θ]."""
        return self.inputs[0]

    @property
    def v_avg(self) -> float:
        """Average path update over the horizon, (1/N) Σ v [m] (paper A Fig. 6d/h)."""
        return float(np.mean(self.v))



# ----------------------------------------------------------------------------------------------
class _Rows:
    """Constraint rows g with their bounds, in the order they are added."""

    def __init__(self) -> None:
        self.g: list[ca.SX | ca.MX] = []
        self.lo: list[float] = []
        self.hi: list[float] = []

    def add(self, expr: ca.SX | ca.MX, lo: float, hi: float) -> None:
        self.g.append(expr)
        self.lo.append(lo)
        self.hi.append(hi)


def _ebar(xs: Sequence, on_path: list, k: int) -> ca.SX | ca.MX:
    """ē (contouring, lag) of stage k."""
    xk = xs[k]
    yd, phi = on_path[k]
    return casadi_errors(ca.vertcat(xk[0], xk[2]), yd, phi)


def _barrier(p: ca.SX | ca.MX, N: int, px, py, j: int, k: int, foot: bool = False) -> ca.SX | ca.MX:
    """Ellipse barrier b(p) of obstacle j at stage k (its parameters in p, see :func:`n_params`)."""
    o = 1 + (j * (N + 1) + k) * NB
    dx = px - p[o]
    dy = py - p[o + 1]
    m = o + (5 if foot else 2)
    return p[m] * dx * dx + 2 * p[m + 1] * dx * dy + p[m + 2] * dy * dy - 1.0


def _stage_cost(cost, prm: MpccParams, Qb: ca.DM, R: ca.DM, xs: Sequence, us: Sequence, on_path: list, k: int,
                side0: ca.SX | ca.MX | None = None):
    """``cost`` plus stage k's terms: ‖ē‖²_Q̄ + ‖u‖²_R − ρ v² (and the heading and lateral-nominal terms)."""
    uk, xn = us[k], xs[k + 1]
    e = _ebar(xs, on_path, k)
    ulip = uk[0:3]
    cost += ca.mtimes([e.T, Qb, e]) + ca.mtimes([ulip.T, R, ulip]) - prm.rho * uk[3] ** 2
    if prm.lateral_nominal > 0.0 and side0 is not None:
        # R_y (side·l − l_nom)² in place of R_y l², with l the lateral offset in the new heading frame
        psi = xs[k][4] + uk[2]
        lat = -ca.sin(psi) * uk[0] + ca.cos(psi) * uk[1]
        side = side0 * (1 if k % 2 == 0 else -1)
        l0 = prm.lateral_nominal
        cost += prm.R[1] * (l0 * l0 - 2.0 * l0 * side * lat)
    if prm.heading_weight > 0.0:  # the next heading against the path's tangent there
        cost += prm.heading_weight * (1.0 - ca.cos(xn[4] - on_path[k + 1][1]))
    return cost


def _stage_rows(rows: _Rows, prm: MpccParams, xs: Sequence, us: Sequence, p, side0, k: int, nob: int,
                dynamics: bool) -> None:
    """Stage k's constraint rows: dynamics (13, 5), reachability (15), distance (16), CBF (17), footholds."""
    N = prm.N
    xk, uk, xn = xs[k], us[k], xs[k + 1]
    if dynamics:  # (13) and (5)
        A, B = prm.model.A, prm.model.B
        for row in ca.vertsplit(xn[0:5] - (ca.mtimes(ca.DM(A), xk[0:5]) + ca.mtimes(ca.DM(B), uk[0:3]))):
            rows.add(row, 0.0, 0.0)
        rows.add(xn[5] - xk[5] - uk[3], 0.0, 0.0)
    # reachability rectangle (15) in the new heading frame; lateral side alternates
    rect = prm.rectangle
    inner, outer = rect.lateral
    psi = xk[4] + uk[2]
    c, s = ca.cos(psi), ca.sin(psi)
    side = side0 * (1 if k % 2 == 0 else -1)
    rows.add(c * uk[0] + s * uk[1], rect.forward[0], rect.forward[1])
    rows.add(side * (-s * uk[0] + c * uk[1]), inner, outer)
    # distance per step (16), squared to stay smooth
    rows.add((xn[0] - xk[0]) ** 2 + (xn[2] - xk[2]) ** 2, prm.delta_min**2, prm.delta_max**2)
    # discrete CBF (17) per obstacle, on the COM disk
    for j in range(nob):
        rows.add(_barrier(p, N, xn[0], xn[2], j, k + 1) - (1.0 - prm.gamma) * _barrier(p, N, xk[0], xk[2], j, k), 0.0, ca.inf)
    # the new foothold stays outside each obstacle during its stance (extension: the
    # paper's CBF guards the point mass only; a Digit foot lands up to ~0.35 m from it)
    if prm.foot_clearance:
        fx, fy = xk[0] + uk[0], xk[2] + uk[1]
        for j in range(nob):
            for kk in (k, k + 1):
                rows.add(_barrier(p, N, fx, fy, j, kk, foot=True), 0.0, ca.inf)


def _arrival_rows(rows: _Rows, prm: MpccParams, xs: Sequence, arrival: tuple[float, float, float, float]) -> None:
    """The arrival row: t · (ξ_1 − p_end) ≤ 0, the divergent component of motion ξ = c + ċ/ω [m] (the capture
    point) of the next planned exchange state x_1 behind the point p_end along the unit end tangent t
    (``arrival`` = (pˣ, pʸ, tˣ, tʸ)). A LIP whose ξ is behind a point can still stop before it (a step onto ξ
    stops it), and from any state with ξ behind it there is a step that keeps it behind: so the plans keep the
    robot able to stop at the end at every step, and brake when they must
    (:meth:`~lipmpcc.planners.mpcc_driver.MpccDriver._end_mode`).

    On x_1 only. The same row on every stage k = 1..N made the plans put off their progress (the plan's last
    stages, where the COM catches up with ϑ, run into the row first): the LIP's own plans from rest 0.85 m
    before the end with the overtaking weights stayed there, and on stages 1-2 they stopped 6-8 cm short. Nor a
    narrower envelope than capture's (ċ ≤ (L − c)/τ with τ = 3/ω, a gentler stop): it is the largest set from
    which the robot can stop at the end, and ``digit_like`` (timed, 0.8 m/s obstacle, 40 m line) left the
    narrower one by its tracking error, its solves failed (11) and it fell at the end."""
    px, py, tx, ty = arrival
    w = prm.model.omega
    x1 = xs[1]
    rows.add(tx * (x1[0] + x1[1] / w - px) + ty * (x1[2] + x1[3] / w - py), -ca.inf, 0.0)


def build_problem(path: Path, prm: MpccParams, xs: Sequence, us: Sequence, p: ca.SX | ca.MX,
                  dynamics: bool = True, arrival: tuple[float, float, float, float] | None = None,
                  ) -> tuple[ca.SX | ca.MX, list, list[float], list[float]]:
    """The MPCC as CasADi expressions, shared by both solvers.

    Args:
        path: reference path.
        prm: parameters.
        xs: N+1 stage states (6-vectors: LIP state + ϑ), SX or MX.
        us: N stage inputs (4-vectors: uˣ, uʸ, u^θ, v).
        p: parameter vector: [side_0, then per obstacle j and stage k: cx, cy, M (3), F (3)]
            (see :func:`lipmpcc.obstacles.barrier_params`).
        dynamics: include the dynamics rows (False when xs are already the rolled-out states).
        arrival: the path's end point and unit end tangent (pˣ, pʸ, tˣ, tʸ) [m, -]: the arrival row
            (:func:`_arrival_rows`, the approach to the end); None: none.

    Returns:
        (cost, g, lbg, ubg) with g a list of expressions and lbg/ubg lists of floats.
    """
    N = prm.N
    Qb = ca.diag(ca.DM(prm.Q_bar))
    Wb = ca.diag(ca.DM(prm.W_bar))
    R = ca.diag(ca.DM(prm.R))
    side0 = p[0]
    nob = (p.shape[0] - 1) // ((N + 1) * NB)
    # the path point and tangent angle at each stage's ϑ, built once (errors and heading term share them)
    on_path = []
    for xk in xs:
        yd, d = path.casadi_derivs(xk[5])
        on_path.append((yd, ca.atan2(d[1], d[0])))
    cost = 0
    rows = _Rows()
    for k in range(N):
        cost = _stage_cost(cost, prm, Qb, R, xs, us, on_path, k, side0)
        _stage_rows(rows, prm, xs, us, p, side0, k, nob, dynamics)
    if arrival is not None:
        _arrival_rows(rows, prm, xs, arrival)
    e = _ebar(xs, on_path, N)
    cost += ca.mtimes([e.T, Wb, e])
    return cost, rows.g, rows.lo, rows.hi


def n_params(prm: MpccParams, n_obstacles: int) -> int:
    """Length of the parameter vector p for ``n_obstacles`` obstacles."""
    return 1 + n_obstacles * (prm.N + 1) * NB


#: the builders (SQP, IPOPT) of the other formulations, by their parameters' type (each module registers its
#: own: :mod:`lipmpcc.planners.mpcc_timed` the timed MPCC's), so that one pair of builders serves them all
FORMULATION_BUILDERS: dict[type, tuple[Callable[..., CondensedSqp], Callable[..., dict]]] = {}


def build_sqp(path: Path, prm: MpccParams, n_obs: int, max_iter: int = 100, tol: float = 1e-4,
              arrival: tuple[float, float, float, float] | None = None) -> CondensedSqp:
    """The fast solver of the MPCC: :class:`~lipmpcc.solvers.condensed_sqp.CondensedSqp` on the condensed problem
    (with a :class:`~lipmpcc.planners.mpcc_timed.TimedMpccParams`, the timed MPCC's, states and durations
    condensed alike: :data:`FORMULATION_BUILDERS`).

    The LIP and path-parameter dynamics are linear, so the stage states are eliminated (x_k is an
    affine function of u_0..u_{k−1}); the decision variables are the N stage inputs [uˣ, uʸ, u^θ, v]
    (4N = 20 for N = 5), the parameters (x_0, p). ϑ_k ≤ ϑ_T (k = 1..N) become general rows (ϑ ≥ 0
    holds since v ≥ 0). The step tolerance 1e-4 is 0.1 mm / 0.1 mrad on the inputs. Its converged
    solutions match IPOPT's on the same problem when both reach the same local minimum. ``arrival``: the
    arrival row at the path's end (:func:`build_problem`).
    """
    other = FORMULATION_BUILDERS.get(type(prm))
    if other is not None:
        return other[0](path, prm, n_obs, max_iter, tol, arrival=arrival)
    N = prm.N
    u = ca.SX.sym("u", NU * N)
    x_0 = ca.SX.sym("x_0", NX)
    p = ca.SX.sym("p", n_params(prm, n_obs))
    A, B = ca.DM(prm.model.A), ca.DM(prm.model.B)
    xs = [x_0]
    us = [u[NU * k : NU * (k + 1)] for k in range(N)]
    for k in range(N):
        xk, uk = xs[k], us[k]
        xs.append(ca.vertcat(ca.mtimes(A, xk[0:5]) + ca.mtimes(B, uk[0:3]), xk[5] + uk[3]))
    cost, g, lbg, ubg = build_problem(path, prm, xs, us, p, dynamics=False, arrival=arrival)
    gk = ca.vertcat(*(g + [xs[k][5] for k in range(1, N + 1)]))
    lo = np.tile([-np.inf, -np.inf, prm.rectangle.heading[0], 0.0], N)
    hi = np.tile([np.inf, np.inf, prm.rectangle.heading[1], prm.v_max], N)
    return CondensedSqp(
        "mpcc_sqp", u, [x_0, p], cost, gk, lbg + [-np.inf] * N, ubg + [path.length] * N, lo, hi,
        max_iter=max_iter, tol=tol, jit=prm.jit,
    )


def build_ipopt(path: Path, prm: MpccParams, n_obs: int,
                arrival: tuple[float, float, float, float] | None = None) -> dict:
    """The paper's formulation: CasADi ``Opti`` (states and inputs as variables) with IPOPT (``arrival``: the
    arrival row at the path's end, :func:`build_problem`).

    Returns ``{"opti": Opti, "vars": (X, U, P, X0)}`` (with a
    :class:`~lipmpcc.planners.mpcc_timed.TimedMpccParams`, the timed MPCC's: ``{"opti", "vars": (X, Z, P)}``).
    """
    other = FORMULATION_BUILDERS.get(type(prm))
    if other is not None:
        return other[1](path, prm, n_obs, arrival=arrival)
    N = prm.N
    opti = ca.Opti()
    X = opti.variable(NX, N + 1)
    U = opti.variable(NU, N)
    P = opti.parameter(n_params(prm, n_obs))
    xs = [X[:, k] for k in range(N + 1)]
    us = [U[:, k] for k in range(N)]
    cost, g, lbg, ubg = build_problem(path, prm, xs, us, P, arrival=arrival)
    opti.minimize(cost)
    for gi, lo, hi in zip(g, lbg, ubg):
        if lo == hi:
            opti.subject_to(gi == lo)
        elif hi == ca.inf:
            opti.subject_to(gi >= lo)
        else:
            opti.subject_to(opti.bounded(lo, gi, hi))
    X0 = opti.parameter(NX)
    opti.subject_to(X[:, 0] == X0)
    for k in range(N):
        opti.subject_to(opti.bounded(prm.rectangle.heading[0], U[2, k], prm.rectangle.heading[1]))
        opti.subject_to(opti.bounded(0.0, U[3, k], prm.v_max))
    for k in range(1, N + 1):
        opti.subject_to(opti.bounded(0.0, X[5, k], path.length))
    opti.solver(
        "ipopt",
        {"print_time": False, "error_on_fail": False},
        {"print_level": 0, "sb": "yes", "max_iter": 500, "tol": 1e-8},
    )
    return {"opti": opti, "vars": (X, U, P, X0)}


#: [m] slack added to the reach of :func:`obstacle_reach` before an obstacle is left out of a solve
OBSTACLE_SELECT_MARGIN = 0.5
#: [m] how far from the COM :func:`inert_obstacle` stands (its barrier rows can never be active)
INERT_DISTANCE = 1e3


def obstacle_reach(prm: MpccParams) -> float:
    """How far from the COM at the solve [m] a plan's barriers can reach: the COM disk after N steps of at
    most δ_max (grown by the body inflation), or a foothold — the COM after N − 1 steps plus the largest
    foot offset of the reachability rectangle (grown by the foot inflation) — whichever is farther."""
    rect = prm.rectangle
    u_max = math.hypot(max(abs(rect.forward[0]), abs(rect.forward[1])), max(abs(rect.lateral[0]), abs(rect.lateral[1])))
    com = prm.N * prm.delta_max + prm.obstacle_inflation
    foot = (prm.N - 1) * prm.delta_max + u_max + prm.foot_radius + prm.obstacle_margin
    return max(com, foot)


def relevant_obstacles(prm: MpccParams, x0: np.ndarray, obstacles: Sequence[Obstacle], t_now: float,
                       margin: float = OBSTACLE_SELECT_MARGIN) -> list[Obstacle]:
    """The obstacles a plan from LIP state ``x0`` at ``t_now`` [s] could touch, in their order: those whose
    centre is within :func:`obstacle_reach` + their largest semi-axis + how far they move over the horizon
    (speed × N T) + ``margin`` [m] of the COM. The others cannot matter over the horizon: their barrier
    rows would only add work (and, 100 m away, values of 1e5 and more); they come back into the solve
    before the robot can reach them."""
    if not obstacles:
        return []
    t_now = finite_number("t_now", t_now, "s", error=ParameterError)  # the obstacles' tracks below do not check it
    reach = obstacle_reach(prm) + margin
    horizon = prm.N * prm.model.T
    p = np.array([x0[0], x0[2]], dtype=float)
    t = np.array([float(t_now)])
    out = []
    for ob in obstacles:
        speed = abs(ob.speed) if ob.path is not None else math.hypot(*ob.velocity)
        d = float(np.linalg.norm(ob._track(t)[0][0] - p))  # ob.center(t_now), without its checks
        if d <= reach + max(ob.axes) + speed * horizon:
            out.append(ob)
    return out


def obstacle_capacity(n: int) -> int:
    """The number of obstacle slots of the solver for ``n`` relevant obstacles: n up to 2, then the next
    power of two (a handful of solvers to build, whatever the number of obstacles nearby)."""
    return n if n <= 2 else 1 << (int(n) - 1).bit_length()


def inert_obstacle(x0: np.ndarray) -> Obstacle:
    """A filler for an unused obstacle slot: a 1 cm circle :data:`INERT_DISTANCE` from the COM (its barrier
    rows hold for every plan and never become active)."""
    return Obstacle.circle(0.01, position=(float(x0[0]) + INERT_DISTANCE, float(x0[2])))


#: one solve attempt: (converged, status, iterations, cost, X (N+1, 6), U (N, 4))
_Attempt = tuple[bool, str, int, float, np.ndarray, np.ndarray]


@dataclass(frozen=True)
class FixedCall:
    """What one fixed-step solve starts from (see :meth:`MpccPlanner.solve`)."""

    x0: np.ndarray  # [x, ẋ, y, ẏ, heading] at the support exchange
    theta: float  # ϑ_init [m]
    side: int  # side of the foot placed now
    t_now: float  # [s]
    shift: bool
    x0_full: np.ndarray  # [x0, ϑ_init]


class FixedStepFormulation:
    """Paper A's MPCC at the fixed step duration T, the formulation of :class:`MpccPlanner` for the driver
    (:class:`~lipmpcc.planners.mpcc_driver.MpccFormulation`): the decision variables U are the N stage
    inputs [uˣ, uʸ, u^θ, v] (N, 4).

    Args:
        path: the reference path; problem_path: the path the problem is built on; params: the MPCC's.
    """

    label = "mpcc"
    #: its plans walk on where the timed MPCC's stand still (MpccDriver._standing): no restart for them
    restart_standing = False
    #: its stall's detour also starts behind an obstacle moving on along the path (liveness.trailed): that detour
    #: is how it passed the slowest ones (LIP scene 13: with the rule it trailed, `trailing` at 13.6 m where it
    #: completed); kept as measured
    trail_moving_on = False

    def __init__(self, path: Path, problem_path: Path, params: MpccParams) -> None:
        self.path, self.problem_path, self.mpcc = path, problem_path, params
        self._reach: float | None = None

    def build(self, path: Path, n_obs: int, solver: str, at_end: bool = False, arrive: bool = False) -> dict:
        """The SQP (``{"sqp": CondensedSqp}``) or IPOPT formulation for ``n_obs`` obstacles on ``path``
        (``at_end``: the end mode's, with ``delta_min`` = 0; ``arrive``: the approach's, with ``delta_min`` = 0
        and the arrival row at the end of :attr:`path`: :meth:`~lipmpcc.planners.mpcc_driver.MpccDriver._end_mode`)."""
        prm = self.mpcc.with_(delta_min=0.0) if at_end or arrive else self.mpcc
        arrival = end_frame(self.path, self.mpcc.delta_min) if arrive else None
        if solver == "sqp":
            return {"sqp": build_sqp(path, prm, n_obs, arrival=arrival)}
        return build_ipopt(path, prm, n_obs, arrival=arrival)

    def select(self, x0: np.ndarray, obstacles: list[Obstacle], t_now: float) -> list[Obstacle]:
        """The obstacles a solve from LIP state ``x0`` at ``t_now`` [s] plans around (:func:`relevant_obstacles`),
        padded with :func:`inert_obstacle` up to :func:`obstacle_capacity` (one solver per capacity)."""
        near = relevant_obstacles(self.mpcc, x0, obstacles, t_now)
        cap = obstacle_capacity(len(near))
        return near + [inert_obstacle(x0)] * (cap - len(near)) if cap > len(near) else near

    def reach(self) -> float:
        """:func:`obstacle_reach` [m]."""
        if self._reach is None:
            self._reach = obstacle_reach(self.mpcc)
        return self._reach

    def call(self, x0: np.ndarray, side: int, t_now: float, theta_init: float | None, shift: bool,
             last: MpccResult | None) -> FixedCall:
        """The call's data; ϑ_init the closest point (eq. 19) searched around the previous plan's ϑ by default."""
        if theta_init is None:
            prev = None if last is None else float(last.theta[1 if shift else 0])
            theta_init = self.path._closest_near(np.array([x0[0], x0[2]], dtype=float), prev)
        theta_init = min(max(float(theta_init), 0.0), self.path.length)
        return FixedCall(x0, theta_init, side, t_now, shift, np.concatenate([x0, [theta_init]]))

    def parameters(self, call: FixedCall, obstacles: Sequence[Obstacle], U: np.ndarray | None = None) -> np.ndarray:
        """The parameter vector p for a solve at ``call.t_now`` [s]."""
        prm = self.mpcc
        times = call.t_now + prm.model.T * np.arange(prm.N + 1)
        bp = barrier_params(list(obstacles), times, prm.obstacle_inflation, prm.foot_radius + prm.obstacle_margin,
                            check=False)  # obstacles checked by solve, times ours
        return np.concatenate([[float(call.side)], bp.reshape(-1)])

    def guess(self, call: FixedCall, last: MpccResult | None, cold: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """The shifted previous solution (the new last step mirrors the old one laterally; the same one when
        re-planning the same step), or without one (or ``cold``) a march along the path at half speed."""
        prm = self.mpcc
        N = prm.N
        x0, theta0 = call.x0, call.theta
        if last is not None and not cold:
            X, U = np.empty((N + 1, NX)), np.empty((N, NU))
            k = 1 if call.shift else 0  # re-planning the same step (e.g. mid-swing on the full robot): k = 0
            X[: N + 1 - k, :5], X[: N + 1 - k, 5] = last.states[k:], last.theta[k:]
            U[: N - k, :3], U[: N - k, 3] = last.inputs[k:], last.v[k:]
            if call.shift:
                X[N] = X[N - 1]
                U[N - 1] = _mirror_lateral((*last.inputs[-1].tolist(), float(last.v[-1])), float(last.states[-2, 4]))
            X[0, :5] = x0
            X[0, 5] = theta0
            return X, U
        X = np.zeros((N + 1, NX))
        U = np.zeros((N, NU))
        side = call.side
        for k in range(N + 1):
            th = min(theta0 + 0.5 * prm.v_max * k, self.path.length)
            pk = self.path.position(th)
            X[k] = [pk[0], 0.0, pk[1], 0.0, x0[4], th]
        X[0, :5] = x0
        for k in range(N):
            U[k, 3] = X[k + 1, 5] - X[k, 5]
            h = X[k, 4]
            lat = side * 0.5 * sum(prm.rectangle.lateral)
            U[k, 0] = -math.sin(h) * lat
            U[k, 1] = math.cos(h) * lat
            side = -side
        return X, U

    def solve_sqp(self, built: dict, call: FixedCall, p: np.ndarray, Xg: np.ndarray, Ug: np.ndarray) -> _Attempt:
        """One SQP solve from the guess ``Ug``."""
        sqp: CondensedSqp = built["sqp"]
        sol = sqp.solve(Ug, (call.x0_full, p))
        U = sol.u.reshape(-1, NU)
        X = rollout(self.mpcc.model, call.x0_full, U)
        return sol.found, sol.status, sol.iterations, sol.cost, X, U

    def solve_ipopt(self, built: dict, call: FixedCall, p: np.ndarray, Xg: np.ndarray, Ug: np.ndarray) -> _Attempt:
        """One IPOPT solve from the guess (Xg, Ug)."""
        opti = built["opti"]
        X, U, P, X0 = built["vars"]
        opti.set_value(P, p)
        opti.set_value(X0, call.x0_full)
        opti.set_initial(X, Xg.T)
        opti.set_initial(U, Ug.T)
        sol = opti.solve()
        st = sol.stats()
        ok = bool(st.get("success", False))
        Xs = np.asarray(sol.value(X)).reshape(NX, -1).T
        Us = np.asarray(sol.value(U)).reshape(NU, -1).T
        return ok, str(st.get("return_status", "")), int(st.get("iter_count", -1)), float(sol.value(opti.f)), Xs, Us

    @staticmethod
    def with_progress(U: np.ndarray, v: float) -> np.ndarray:
        """A copy of ``U`` with v = ``v`` [m] at every step."""
        Ur = U.copy()
        Ur[:, 3] = v
        return Ur

    @staticmethod
    def mean_progress(U: np.ndarray) -> float:
        """The mean v of ``U`` [m]."""
        return float(np.add.reduce(U[:, 3])) / len(U)  # np.mean's numbers, without its overhead

    def progress_start(self, call: FixedCall, best: np.ndarray, Ug: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The warm-start guess's foot placements with v = v_max / 2."""
        U = self.with_progress(Ug, 0.5 * self.mpcc.v_max)
        return rollout(self.mpcc.model, np.r_[call.x0, call.theta], U, self.problem_path.length), U

    def result(self, call: FixedCall, X: np.ndarray, U: np.ndarray, found: bool, status: str, iters: int,
               elapsed: float, cost: float, side: int) -> MpccResult:
        """The :class:`MpccResult` of the stage states ``X`` and inputs ``U``."""
        states = X[:, :5].copy()
        theta = X[:, 5].copy()
        inputs = U[:, :3].copy()
        foot = states[:-1, [0, 2, 4]] + inputs  # [x + uˣ, y + uʸ, θ + u^θ]
        ref, phi = self.problem_path._frame(theta)  # position and slope, one evaluation
        e = contouring_errors(states[:, [0, 2]], ref, phi, check=False)  # our own arrays
        return MpccResult(found=found, status=status, iterations=iters, solve_time=elapsed, cost=cost, states=states,
                          theta=theta, v=U[:, 3].copy(), inputs=inputs, footsteps=foot, e_contouring=e[:, 0],
                          e_lag=e[:, 1], theta_init=call.theta, stance_side=side)

    def replay(self, call: FixedCall, last: MpccResult, obstacles: Sequence[Obstacle]) \
            -> tuple[np.ndarray, np.ndarray, int, list[int]]:
        """The previous plan shifted by one step (``call.shift``), replayed from the call's state; when it walks
        into one of ``obstacles``, stepping in place instead (:func:`~lipmpcc.planners.liveness.hold_inputs`)."""
        prm = self.mpcc
        U = np.column_stack([last.inputs, last.v])
        if call.shift:
            U = np.vstack([U[1:], _mirror_lateral(U[-1], last.states[-2, 4])])
        X = rollout(prm.model, np.r_[call.x0, call.theta], U, self.problem_path.length)
        side = -last.stance_side if call.shift else last.stance_side
        times = call.t_now + prm.model.T * np.arange(len(X))
        held = barred_by(X[:, [0, 2]], times, obstacles, prm.obstacle_inflation) if obstacles else []
        if held:  # no way out: hold in place rather than walk into the obstacle (issue 31)
            Uh = hold_inputs(call.x0, side, len(U), prm.model.omega, prm.model.T, prm.rectangle.lateral,
                             prm.rectangle.forward)
            U = np.column_stack([Uh, np.zeros(len(U))])
            X = rollout(prm.model, np.r_[call.x0, call.theta], U, self.problem_path.length)
        return X, U, side, held


class MpccPlanner(MpccDriver):
    """The MPCC of paper A on the 3D-LIP, with warm start and safe fallback (the driver
    :class:`~lipmpcc.planners.mpcc_driver.MpccDriver` over :class:`FixedStepFormulation`).

    Two faces: :meth:`solve` (the MPCC itself: a plan from a LIP state at a support exchange) and
    :meth:`plan` (the planner contract of :mod:`lipmpcc.planners.base`, for the LIP loop).

    Args:
        path: reference path (arc-length parametrised).
        params: :class:`MpccParams` (use a preset such as :meth:`MpccParams.circle`).
        name: planner name used in summaries.

    Attributes:
        rate_hz: how often a loop may call :meth:`plan` [Hz] (paper A: 15 Hz); it solves once per
            step and answers later calls of the same step with that plan.
        progress: the :class:`~lipmpcc.planners.liveness.ProgressMonitor` of the liveness rules.
        detour_solves: solves made in the detour mode (:mod:`lipmpcc.planners.liveness`).
    """

    rate_hz = 15.0

    def __init__(self, path: Path, params: MpccParams | None = None, name: str = "mpcc") -> None:
        if not isinstance(path, Path):
            raise ParameterError("path", path, "a lipmpcc.paths.Path")
        if params is not None and not isinstance(params, MpccParams):
            raise ParameterError("params", params, "an MpccParams or None")
        if not isinstance(name, str):
            raise ParameterError("name", name, "a string")
        self.path = path
        self.params = params if params is not None else MpccParams()
        self.name = name
        #: the path the problem is built on (``path``, or continued past its end: ``past_end``)
        self.problem_path = problem_path(path, self.params.past_end, self.params.N * self.params.v_max)
        self._init_driver(FixedStepFormulation(path, self.problem_path, self.params))

    def select_obstacles(self, x0: np.ndarray, obstacles: Sequence[Obstacle], t_now: float) -> list[Obstacle]:
        """The obstacles a solve from LIP state ``x0`` at ``t_now`` [s] plans around (:func:`relevant_obstacles`),
        padded with :func:`inert_obstacle` up to :func:`obstacle_capacity` (one solver per capacity)."""
        return self.formulation.select(x0, list(obstacles), t_now)

    def parameters(self, stance_side: int, obstacles: Sequence[Obstacle], t_now: float) -> np.ndarray:
        """The parameter vector p for a solve at time ``t_now`` [s]."""
        call = FixedCall(np.zeros(5), 0.0, stance_side, t_now, True, np.zeros(NX))
        return self.formulation.parameters(call, obstacles)


    @exclusive("planner")
    def solve(
        self,
        x0: np.ndarray,
        stance_side: int | None = None,
        obstacles: Sequence[Obstacle] = (),
        t_now: float = 0.0,
        theta_init: float | None = None,
        shift: bool = True,
    ) -> MpccResult:
        """Plan from LIP state ``x0`` at the start of a step.

        Args:
            x0: [x, ẋ, y, ẏ, heading] at the support exchange.
            stance_side: side of the foot placed now (+1 left, −1 right); required (None is refused
                with a ParameterError, after ``x0`` is checked).
            obstacles: moving obstacles, predicted from ``t_now`` over the horizon.
            t_now: current time [s].
            theta_init: path parameter to start from [m]; default: the closest point
                (eq. 19) searched locally around the previous ϑ.
            shift: this solve is one step after the previous one (True: warm start and
                fallback from the shifted previous plan), or it re-plans the same support
                exchange with fresher state (False, e.g. mid-swing re-planning at 15 Hz).

        Returns:
            :class:`MpccResult`; ``result.u0`` is the input to execute.
        """
        x0, obstacles = self._check_inputs(x0, stance_side, obstacles)
        t_now = finite_number("t_now", t_now, "s", error=ParameterError)
        if theta_init is not None:
            theta_init = finite_number("theta_init", theta_init, "m", error=ParameterError)
        shift = flag("shift", shift, error=ParameterError)
        return self._drive(x0, obstacles, t_now,
                           lambda: self.formulation.call(x0, stance_side, t_now, theta_init, shift, self.last))

    def _detour_solve(self, call: FixedCall, obstacles: list[Obstacle], s: float = 0.0) -> MpccResult:
        return self._solve_detour(call.x0, call.side, obstacles, call.t_now, call.theta, call.shift, s)

    def _solve_detour(self, x0: np.ndarray, stance_side: int, obstacles: list[Obstacle], t_now: float,
                      theta_init: float, shift: bool, s: float = 0.0) -> MpccResult:
        """The solve of the detour mode (:mod:`lipmpcc.planners.liveness`): the same problem with the detour
        weights (or, ``s`` > 0, the return's), by a planner of its own (its solvers built on first use)
        warm-started from this one's plan."""
        if s not in self._detour_planners:
            self._detour_planners[s] = MpccPlanner(self.path, self.params.with_(**self._detour_fields(s)),
                                                   name=f"{self.name}-detour" if s == 0.0 else f"{self.name}-return")
        sub = self._detour_planners[s]
        return self._via_detour(sub, lambda: sub.solve(x0, stance_side, obstacles, t_now, theta_init, shift), s)

    # ---- the planner contract ------------------------------------------------------------------
    @exclusive("planner")
    def plan(self, inp: PlannerInput) -> StepPlan:
        """The planner contract on the LIP: the foot placed at the support exchange ``inp`` describes.

        Reads the LIP state at the exchange from the input, ``x = [com x, ẋ, com y, ẏ, torso_yaw]``,
        and solves (:meth:`solve`, warm start shifted by one step) for the swing foot — the foot placed
        now, the side opposite ``inp.stance_side`` — with the input's obstacles predicted from
        ``inp.t``. Returns the first planned foothold ``x_0 + u_0``, heading ``θ_0 + u^θ_0``, the
        model's step duration T, the COM at the next exchange and the preview of the later footholds;
        ``record`` is the :class:`MpccResult`. Later calls with the same ``step_index`` return the same
        plan (one solve per step, paper A). On a full-body robot, where the call comes during the swing,
        use :class:`~lipmpcc.planners.sources.mpcc.MpccFootstepSource`, which predicts the state at the
        exchange.

        Raises:
            NoFallbackPlanError: the first solve failed.
        """
        if not isinstance(inp, PlannerInput):
            raise ParameterError("inp", inp, "a lipmpcc.planners.base.PlannerInput")
        if self._step_plan is not None and self._step_plan[0] == inp.step_index:
            return self._step_plan[1]
        x0 = np.array([inp.com_pos[0], inp.com_vel[0], inp.com_pos[1], inp.com_vel[1], inp.torso_yaw], dtype=float)
        res = self.solve(x0, parse_side(inp.stance_side).other.sign, inp.obstacles, t_now=float(inp.t))
        u = res.u0
        T = self.params.model.T
        fs = res.footsteps
        plan = StepPlan(
            foothold=np.array([x0[0] + u[0], x0[2] + u[1]]),
            yaw=float(x0[4] + u[2]),
            duration=T,
            com_target=res.states[1, [0, 2]],
            preview=np.column_stack([fs[:, 0], fs[:, 1], fs[:, 2], np.full(len(fs), T)]),
            cost=res.cost,
            solve_time=res.solve_time,
            status=f"fallback ({res.status})" if res.used_fallback else "ok",
            record=res,
        )
        self._step_plan = (int(inp.step_index), plan)
        return plan


class _CondensedScp:
    """The old interface of the MPCC's SQP (deprecated): :func:`build_sqp` behind ``solve(x_0, p, U0) ->
    (found, status, iterations, cost, U (N, 4))`` and ``rollout(x_0, U)``."""

    def __init__(self, path: Path, prm: MpccParams, n_obs: int, max_iter: int = 100, tol: float = 1e-4) -> None:
        self.path, self.prm = path, prm
        self.sqp = build_sqp(path, prm, n_obs, max_iter, tol)

    def __getattr__(self, name: str) -> object:
        return getattr(self.sqp, name)

    def rollout(self, x_0: np.ndarray, Ustage: np.ndarray) -> np.ndarray:
        return rollout(self.prm.model, x_0, Ustage)

    def solve(self, x_0: np.ndarray, p: np.ndarray, U0: np.ndarray) -> tuple[bool, str, int, float, np.ndarray]:
        sol = self.sqp.solve(U0, (x_0, p))
        return sol.found, sol.status, sol.iterations, sol.cost, sol.u.reshape(-1, NU)


def rollout(model: Lip3dModel, x_0: np.ndarray, U: np.ndarray, theta_max: float = math.inf) -> np.ndarray:
    """Stage states (N+1, 6) = [LIP state, ϑ] from x_0 (6,) and stage inputs U (N, 4);
    ϑ is capped at ``theta_max``. Computed by ``lipmpcc._sqp.lip_rollout`` when it imports (the same operations in
    C++, the same numbers to the bit: ``tests/planners/test_mpcc.py``), else by :func:`rollout_reference`."""
    a01, a11, b0, b1 = _lip_coefficients(model)
    if _LIP_ROLLOUT is not None:
        return _LIP_ROLLOUT(x_0, U, a01, a11, b0, b1, theta_max)
    return _rollout(x_0, U, a01, a11, b0, b1, theta_max)


def rollout_reference(model: Lip3dModel, x_0: np.ndarray, U: np.ndarray, theta_max: float = math.inf) -> np.ndarray:
    """:func:`rollout` in Python (the readable reference of the compiled one)."""
    return _rollout(x_0, U, *_lip_coefficients(model), theta_max)


_LIP_ROLLOUT = compiled_function("lip_rollout")  # None without the compiled module


def _rollout(x_0: np.ndarray, U: np.ndarray, a01: float, a11: float, b0: float, b1: float, theta_max: float) -> np.ndarray:
    """:func:`rollout` with the model's coefficients (:func:`_lip_coefficients`), in plain Python floats."""
    x = [float(v) for v in np.asarray(x_0, dtype=float).reshape(-1)]
    rows = [x]
    # x_{k+1} = A x_k + B u_k with A's and B's non-zero entries only, in plain floats (the planners' loops: a tenth
    # of the time of numpy's calls on 5-vectors): each entry a sum of at most three terms, the matrix products'
    # numbers to the bit where the BLAS rounds each product (this machine's OpenBLAS: 200 000 random states, and the
    # lip- bit-checks unchanged); tests/planners/test_mpcc.py checks them to 1e-15
    for ux, uy, uth, v in np.asarray(U, dtype=float)[:, :4].tolist():
        x = [(x[0] + a01 * x[1]) + b0 * ux, a11 * x[1] + b1 * ux, (x[2] + a01 * x[3]) + b0 * uy, a11 * x[3] + b1 * uy,
             x[4] + uth, min(x[5] + v, theta_max)]
        rows.append(x)
    return np.array(rows)


@functools.lru_cache(maxsize=64)
def _lip_coefficients(model: Lip3dModel) -> tuple[float, float, float, float]:
    """The entries of the model's A = blkdiag([[1, a01], [0, a11]] ×2, 1) and B (b0 = B[0, 0] = B[2, 1],
    b1 = B[1, 0] = B[3, 1], B[4, 2] = 1): (a01, a11, b0, b1), once per model."""
    A, B = model.A, model.B
    return float(A[0, 1]), float(A[1, 1]), float(B[0, 0]), float(B[1, 0])


def _mirror_lateral(u: np.ndarray, heading: float) -> np.ndarray:
    """A stage input [uˣ, uʸ, u^θ, v] with its lateral foot offset mirrored in the heading
    frame (the next foot is on the other side)."""
    c, s = math.cos(heading + u[2]), math.sin(heading + u[2])
    fwd = c * u[0] + s * u[1]
    lat = -(-s * u[0] + c * u[1])
    return np.array([c * fwd - s * lat, s * fwd + c * lat, u[2], u[3]])
