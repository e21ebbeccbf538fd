"""ALIP-MPC: paper B's multi-step foot-placement MPC with adaptive step duration (§III).

Decision variables for the next ``N`` steps (k = 1..N), all in contact frames:
``sigma^k = exp(lambda T^k)``, the foothold ``u^k`` (relative to the previous foothold)
and the initial DCM of the following step ``z^k``::

    min  sum_k beta^k ( ||z^k - z_des^k||^2_{alpha_z} + alpha_sigma (sigma^k - sigma_des)^2
                        + ||u^k - u_des^k||^2_{alpha_u} )
    s.t. z^k = sigma^k z^{k-1} - u^k                         (8, bilinear)
         z_min <= z^k <= z_max                                (viable DCM, eq. 6)
         exp(lambda T_min) <= sigma^k <= exp(lambda T_max)
         u^k in the stone rectangle around u_des^k, within the kinematic limits

* ``u_des^1 = p_stone^1``, ``u_des^k = p_stone^k - p_TD^{k-1}`` (eq. 9) with the previous
  plan's footholds (the stone centre when there is none);
* ``z_des^k`` from eq. (5) with ``T_nom``. ``z^k`` is the initial DCM of step k+1, so by
  default (``dcm_target="next"``) eq. (5) takes step k+1's desired foothold ``u_des^{k+1}``
  and swing side (the stone after the horizon is read for k = N). ``"current"`` uses
  ``u_des^k``; on the ALIP that variant falls on several courses of profiles III and IV,
  where the stones change abruptly;
* ``z^0 = xi_meas(t) exp(-lambda t)`` (eq. 10), ``t`` the time since touch-down; the current
  step cannot end before ``t + min_time_to_touchdown``;
* ``beta^k = beta_base^(N-k)`` (paper: 10^(4-k), N = 4).

**A foot (our extension, off by default).** Paper B's ALIP pivots on a point; Digit stands on feet.
With ``cop_range`` > 0 the centre of pressure for the rest of the current step becomes a decision
variable ``d`` in a box about the contact point, weighted by ``alpha_cop``: the first step's dynamics
read ``z^1 = sigma^1 (z^0 - e^{-lambda t} d) + d - u^1`` (:func:`build_alip_nlp`). This is the ankle
strategy in the planner's own model: with a 0.12 x 0.05 m box, the ALIP model survives all four of
paper B's pushes, where the point foot cannot survive the backward one
(:func:`lipmpcc.models.alip.min_forward_dcm_on_stones`).

Solvers: ``"sqp"`` (default) is CasADi's ``sqpmethod`` with the ``qrqp`` active-set QP
solver, exact Hessian convexified by eigenvalue clipping, warm-started from the previous
plan; ``"ipopt"`` solves the identical NLP with IPOPT, as in the paper, for the benchmark.
Both are built once per parameter set; parameters travel as one ``p`` vector.

:class:`AlipMpc` implements the planner contract (:mod:`lipmpcc.planners.base`) through
:class:`~lipmpcc.planners.alip_common.AlipPlanner`: ``plan(PlannerInput) -> StepPlan``; the solve
itself is :meth:`AlipMpc.solve`. On a solver failure the planner falls back to its last successful
plan (held within the step, shifted after touch-downs; a plan whose status is not ``"ok"``) and
counts the failure; with no previous plan it raises :class:`~lipmpcc.exceptions.NoFallbackPlanError`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from ..exceptions import InvalidInputError, NoFallbackPlanError, ParameterError
from ..exclusive import exclusive
from ..validation import check_field_types
from ..models.alip import AlipParams, KinematicLimits, parse_side
from ..terrain import STEP_WIDTH, STONE_SIZE
from .alip_common import (
    AlipPlanner,
    AlipPlanResult,
    AlipStepParams,
    Stones,
    check_time_since_touchdown,
    check_xy,
    pad_stones,
    stone_arrays as _stone_arrays,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["AlipMpcParams", "AlipPlanResult", "AlipMpc", "PackedNlp", "build_alip_nlp", "call_nlp", "pack_nlp"]


def __getattr__(name: str) -> object:
    if name == "stone_arrays":  # moved to alip_common
        import warnings

        warnings.warn(
            "lipmpcc.planners.alip_mpc.stone_arrays moved to lipmpcc.planners.alip_common.stone_arrays; "
            "the old path is removed in lipmpcc 0.3",
            DeprecationWarning,
            stacklevel=2,
        )
        return _stone_arrays
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

SOLVERS = ("sqp", "ipopt")
STONE_BOUNDS = ("relative", "world")
STEP_REFERENCES = ("plan", "stones")


# ----------------------------------------------------------------------------- parameters
@dataclass(frozen=True)
class AlipMpcParams(AlipStepParams):
    """Parameters of the ALIP-MPC (paper B §V values by default).

    Attributes:
        horizon: number of future steps N.
        T_nom: nominal step duration [s]; T_min, T_max: bounds [s].
        limits: kinematic foothold limits relative to the stance foot [m].
        alpha_z, alpha_u: (x, y) weights on the initial DCM and the foothold.
        alpha_sigma: weight on sigma.
        beta_base: beta^k = beta_base^(N-k).
        w: nominal step width w [m] (w_l = +w, w_r = -w).
        stone_size: rectangle [m] used for stones given without a size.
        replan_period: planner period [s] (25 Hz); used by loops, not by the solve.
        min_time_to_touchdown: the current step lasts at least t + this [s] (capped at T_max).
        stone_bounds: "relative" (paper: a box on u^k around u_des^k) or "world" (the
            cumulative foothold of step k inside stone k, a linear constraint).
        dcm_target: "next" or "current", see the module docstring.
        solver: "sqp" or "ipopt".
        max_iter: solver iteration limit.
        tol: solver tolerance (on the objective scaled by 1/(beta^1 max alpha)).
        alip: ALIP constants (lambda = sqrt(g/z_c)).
        cop_range: half-extents (x, y) [m] of the box, centred on the stance contact point, in
            which the centre of pressure may be held for the rest of the current step (the ankle
            strategy of a robot with feet; world axes). (0, 0), the default, is paper B's point
            foot: the NLP is then exactly the paper's. See :func:`build_alip_nlp`.
        alpha_cop: (x, y) weights on that offset [1/m²] (in the units of alpha_z).
        step_reference: where eq. (9)'s desired steps u_des^k and eq. (5)'s z_des^k start from: ``"plan"``
            (paper B: footstep k-1 of the previous plan) or ``"stones"`` (the centre of stone k-1; footstep 0
            is the stance foot in both). With ``"plan"`` a re-solve at 25 Hz takes the last answer's footholds
            as its reference, and the plan can creep across the stones while the state hardly moves
            (docs/design.md, paper B on Digit v3).
        max_speed: the fastest nominal walk [m/s]: a desired step of forward length u_x gets the nominal duration
            T_k = min(max(T_nom, |u_x| / max_speed), T_max) in eq. (5)'s z_des^k and in sigma_des (the current
            step's), and the upper bound T_max + (T_k − T_nom) on a step's duration, T_k from the stones' spacing
            (stone k from stone k−1; the current step's from the stance foot): the same slack above the nominal
            as paper B's (:meth:`AlipMpc.longest_durations`); 0 (the default): T_nom and T_max for every step,
            paper B's. A robot whose ankle reaches its stop when the COM runs far past the stance foot (Digit v3 at
            L = 0.55 m, 1.1 m/s) walks long steps slower (docs/design.md).
    """

    horizon: int = 4
    T_nom: float = 0.5
    T_min: float = 0.35
    T_max: float = 0.65
    limits: KinematicLimits = field(default_factory=KinematicLimits)
    alpha_z: tuple[float, float] = (1e4, 2e4)
    alpha_u: tuple[float, float] = (1e4, 2e4)
    alpha_sigma: float = 1.0
    beta_base: float = 10.0
    w: float = STEP_WIDTH
    stone_size: tuple[float, float] = STONE_SIZE
    replan_period: float = 0.04
    min_time_to_touchdown: float = 0.0
    stone_bounds: str = "relative"
    dcm_target: str = "next"
    solver: str = "sqp"
    max_iter: int = 50
    tol: float = 1e-8
    alip: AlipParams = field(default_factory=AlipParams)
    cop_range: tuple[float, float] = (0.0, 0.0)
    alpha_cop: tuple[float, float] = (1e5, 1e5)
    step_reference: str = "plan"
    max_speed: float = 0.0

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if self.max_speed < 0.0:
            raise ParameterError("max_speed", self.max_speed, "a speed >= 0 [m/s] (0: T_nom for every step)")
        if not isinstance(self.horizon, (int, np.integer)) or isinstance(self.horizon, bool) or not 1 <= self.horizon <= 20:
            raise ParameterError("horizon", self.horizon, "an integer in [1, 20]")
        self._check_step_params(positive=("alpha_sigma", "beta_base", "tol"))
        for name in ("alpha_z", "alpha_u", "stone_size", "cop_range", "alpha_cop"):
            try:
                v = np.asarray(getattr(self, name), dtype=float)
            except (TypeError, ValueError):
                raise ParameterError(name, getattr(self, name), "two finite numbers > 0 (x, y)") from None
            lo_ok = np.all(v >= 0) if name == "cop_range" else np.all(v > 0)
            if v.shape != (2,) or not np.all(np.isfinite(v)) or not lo_ok:
                what = "two finite numbers >= 0 (x, y) [m]" if name == "cop_range" else "two finite numbers > 0 (x, y)"
                raise ParameterError(name, getattr(self, name), what)
            object.__setattr__(self, name, (float(v[0]), float(v[1])))
        if self.stone_bounds not in STONE_BOUNDS:
            raise ParameterError("stone_bounds", self.stone_bounds, "'relative' or 'world'")
        if self.step_reference not in STEP_REFERENCES:
            raise ParameterError("step_reference", self.step_reference, "'plan' or 'stones'")
        if self.solver not in SOLVERS:
            raise ParameterError("solver", self.solver, "'sqp' or 'ipopt'")
        if not isinstance(self.max_iter, (int, np.integer)) or self.max_iter < 1:
            raise ParameterError("max_iter", self.max_iter, "an integer >= 1")

    @classmethod
    def paper(cls, **overrides: object) -> "AlipMpcParams":
        """Paper B §V: N = 4, T in [0.35, 0.65] s (nominal 0.5 s), |x_TD| <= 0.6,
        0.1 <= |y_TD| <= 0.5 m, alpha_z = alpha_u = (1e4, 2e4), alpha_sigma = 1,
        beta^k = 10^(4-k), w = 0.28 m, stones 0.2 x 0.1 m; z_c = 0.9 m (our choice)."""
        return replace(cls(), **overrides)

    @property
    def uses_cop(self) -> bool:
        """True when the current step's centre of pressure is a decision variable (``cop_range`` > 0)."""
        return max(self.cop_range) > 0.0

    @property
    def n_x(self) -> int:
        """Number of NLP variables: 5 per step, plus the CoP offset (2) when :attr:`uses_cop`."""
        return 5 * self.horizon + (2 if self.uses_cop else 0)

    @property
    def sigma_bounds(self) -> tuple[float, float]:
        """(exp(λ T_min), exp(λ T_max))."""
        return math.exp(self.lam * self.T_min), math.exp(self.lam * self.T_max)

    @property
    def sigma_nom(self) -> float:
        """exp(λ T_nom)."""
        return math.exp(self.lam * self.T_nom)

    @property
    def betas(self) -> np.ndarray:
        """β^k = beta_base^(N−k), k = 1..N."""
        N = self.horizon
        return np.array([self.beta_base ** (N - 1 - k) for k in range(N)], dtype=float)


# ----------------------------------------------------------------------------- NLP
def build_alip_nlp(params: AlipMpcParams) -> dict[str, ca.SX | float]:
    """The NLP of paper B as CasADi expressions: ``x`` stacks per step
    ``(sigma^k, u^k, z^k)``; ``p = [z^0, z_des (2N), u_des (2N), sigma_des]``.

    With a foot (``params.cop_range`` > 0), ``x`` ends with the offset ``d`` (2,) [m] of the centre
    of pressure from the stance contact point, held for the rest of the current step, and ``p``
    ends with ``e^{-lambda t}``. The DCM about the pivot ``d`` diverges from it, so the first step's
    dynamics (8) become

        z^1 = sigma^1 (z^0 - e^{-lambda t} d) + d - u^1,

    (``z^0 e^{lambda t}`` is the DCM now; over the remaining ``T - t`` it moves away from ``d``), and
    the cost gains ``beta^1 ||d||^2_{alpha_cop}``. For constant COM height the angular momentum
    about the contact point does not depend on a horizontal shift of the pivot, so the later steps
    are unchanged.
    """
    N = params.horizon
    cop = params.uses_cop
    x = ca.SX.sym("x", params.n_x)
    p = ca.SX.sym("p", 2 + 4 * N + 1 + (1 if cop else 0))
    z_0 = p[0:2]
    z_des = p[2 : 2 + 2 * N]
    u_des = p[2 + 2 * N : 2 + 4 * N]
    sigma_des = p[2 + 4 * N]
    az = ca.DM(params.alpha_z)
    au = ca.DM(params.alpha_u)
    betas = params.betas
    scale = 1.0 / (betas[0] * max(max(params.alpha_z), max(params.alpha_u)))
    J = 0
    g = []
    z_prev = z_0
    d = x[5 * N : 5 * N + 2] if cop else None
    for k in range(N):
        sigma = x[5 * k]
        u = x[5 * k + 1 : 5 * k + 3]
        z = x[5 * k + 3 : 5 * k + 5]
        ez = z - z_des[2 * k : 2 * k + 2]
        eu = u - u_des[2 * k : 2 * k + 2]
        J += betas[k] * (ca.dot(az * ez, ez) + params.alpha_sigma * (sigma - sigma_des) ** 2 + ca.dot(au * eu, eu))
        if k == 0 and cop:
            e_t = p[2 + 4 * N + 1]
            g.append(z - sigma * (z_prev - e_t * d) - d + u)
            J += betas[0] * ca.dot(ca.DM(params.alpha_cop) * d, d)
        else:
            g.append(z - sigma * z_prev + u)
        z_prev = z
    if params.stone_bounds == "world":
        # footholds 2..N in the current contact frame: sum_{j<=k} u^j inside stone k
        p_k = x[1:3]
        for k in range(1, N):
            p_k = p_k + x[5 * k + 1 : 5 * k + 3]
            g.append(p_k)
    return {"x": x, "p": p, "f": J * scale, "g": ca.vertcat(*g), "scale": scale}


@dataclass(frozen=True)
class PackedNlp:
    """A CasADi ``nlpsol`` of the ALIP-MPC wrapped in a Function of ONE input vector
    ``v = [x0, p, lbx, ubx, lbg, ubg, lam_x0, lam_g0]`` and ONE output
    ``[x, f, lam_x, lam_g]``: converting numpy arrays to CasADi costs about 30 us each,
    so one vector instead of eight saves about 0.2 ms per call.

    Attributes:
        fun: the packed Function (its ``stats()`` are the solver's).
        nlpsol: the underlying solver.
        nx, ng, n_p: numbers of variables, constraints and parameters.
        name: "sqp" or "ipopt".
    """

    fun: ca.Function
    nlpsol: ca.Function
    nx: int
    ng: int
    n_p: int
    name: str

    def stats(self) -> dict:
        """The solver's statistics of the last call."""
        return self.fun.stats()


@lru_cache(maxsize=16)
def _solver(params: AlipMpcParams, solver: str) -> PackedNlp:
    return pack_nlp(build_alip_nlp(params), params, solver)


def pack_nlp(nlp: dict, params: AlipMpcParams, solver: str) -> PackedNlp:
    """The :class:`PackedNlp` of an NLP of :func:`build_alip_nlp`'s form (keys x, p, f, g) with the
    options of ``params`` (``solver``: "sqp" or "ipopt"); not cached (:func:`_solver` caches the library's)."""
    prob = {k: nlp[k] for k in ("x", "p", "f", "g")}
    if solver == "sqp":
        opts = {
            "qpsol": "qrqp",
            "qpsol_options": {"print_iter": False, "print_header": False, "print_info": False, "error_on_fail": False},
            "hessian_approximation": "exact",
            "convexify_strategy": "eigen-clip",
            "max_iter": int(params.max_iter),
            "tol_pr": params.tol,
            "tol_du": params.tol,
            "print_header": False,
            "print_iteration": False,
            "print_status": False,
            "print_time": False,
            "error_on_fail": False,
        }
        S = ca.nlpsol("alip_mpc_sqp", "sqpmethod", prob, opts)
    else:
        opts = {
            "ipopt.print_level": 0,
            "ipopt.sb": "yes",
            "ipopt.tol": params.tol,
            "ipopt.max_iter": max(int(params.max_iter), 200),
            "print_time": False,
            "error_on_fail": False,
        }
        S = ca.nlpsol("alip_mpc_ipopt", "ipopt", prob, opts)
    nx, ng, n_p = prob["x"].numel(), prob["g"].numel(), prob["p"].numel()
    v = ca.MX.sym("v", 3 * nx + n_p + 3 * ng + nx)
    sizes = {"x0": nx, "p": n_p, "lbx": nx, "ubx": nx, "lbg": ng, "ubg": ng, "lam_x0": nx, "lam_g0": ng}
    args, o = {}, 0
    for k, n in sizes.items():
        args[k] = v[o : o + n]
        o += n
    r = S(**args)
    fun = ca.Function(f"alip_mpc_{solver}_packed", [v], [ca.vertcat(r["x"], r["f"], r["lam_x"], r["lam_g"])])
    return PackedNlp(fun, S, nx, ng, n_p, solver)


def call_nlp(solver: PackedNlp, data: dict, x0: np.ndarray, lam_x0: np.ndarray, lam_g0: np.ndarray) -> dict:
    """Solve the NLP of :func:`build_alip_nlp` for ``data`` (from
    :meth:`AlipMpc.problem_data`) from the start point ``x0`` and multipliers.
    Returns x, f, lam_x, lam_g as numpy arrays."""
    v = np.concatenate([x0, data["p"], data["lbx"], data["ubx"], data["lbg"], data["ubg"], lam_x0, lam_g0])
    out = np.asarray(solver.fun(v), dtype=float).ravel()
    nx, ng = solver.nx, solver.ng
    return {"x": out[:nx], "f": float(out[nx]), "lam_x": out[nx + 1 : 2 * nx + 1], "lam_g": out[2 * nx + 1 : 2 * nx + 1 + ng]}


class _BufferedNlp:
    """A :class:`PackedNlp` called through a CasADi ``FunctionBuffer``: the input vector and the output are
    numpy arrays bound to the Function once, so a call converts nothing (a plain call converts the
    numpy vector to a ``DM`` and back, about 30 us of a 40 us solve). Same values as :func:`call_nlp`;
    its own solver memory, hence its own :meth:`stats`. One per planner (not shared between threads)."""

    def __init__(self, solver: PackedNlp) -> None:
        self.solver = solver
        fun = solver.fun
        self.v = np.empty(fun.size1_in(0))
        self.out = np.empty(fun.size1_out(0))
        self._buf, self._eval = fun.buffer()
        self._buf.set_arg(0, memoryview(self.v))
        self._buf.set_res(0, memoryview(self.out))

    def __call__(self, data: dict, x0: np.ndarray, lam_x0: np.ndarray, lam_g0: np.ndarray) -> dict:
        """As :func:`call_nlp` (x, f, lam_x, lam_g, copies of the output)."""
        v, o = self.v, 0
        for a in (x0, data["p"], data["lbx"], data["ubx"], data["lbg"], data["ubg"], lam_x0, lam_g0):
            v[o : o + a.size] = a
            o += a.size
        if o != v.size:
            raise InvalidInputError("NLP data", o, f"{v.size} numbers (x0, p, bounds, multipliers)")
        self._eval()
        out = self.out.copy()
        nx, ng = self.solver.nx, self.solver.ng
        return {"x": out[:nx], "f": float(out[nx]), "lam_x": out[nx + 1 : 2 * nx + 1], "lam_g": out[2 * nx + 1 : 2 * nx + 1 + ng]}

    def stats(self) -> dict:
        """The solver's statistics of the last call."""
        return self._buf.stats()


# ----------------------------------------------------------------------------- planner
@dataclass
class _Workspace:
    """Mutable state kept between calls (warm start, previous plan, counters)."""

    x: np.ndarray | None = None
    lam_x: np.ndarray | None = None
    lam_g: np.ndarray | None = None
    last_ok: AlipPlanResult | None = None
    touchdowns_since_ok: int = 0
    stance: np.ndarray | None = None
    stance_side: int | None = None


class AlipMpc(AlipPlanner):
    """Paper B's ALIP-MPC. Call it at 25 Hz during each swing.

    Any loop drives it through the planner contract, ``plan(PlannerInput) -> StepPlan`` (the
    reduced model of :mod:`lipmpcc.loops.alip`, the full body through
    :class:`~lipmpcc.planners.sources.alip.AlipFootstepSource`). The solve itself takes the measured
    DCM in the world frame (``dcm_from_com(com, com_vel, lam)`` or ``stance + dcm_from_alip(state)``),
    the stance foot and its side, the time since touch-down and the upcoming stones::

        mpc = AlipMpc()                     # AlipMpcParams.paper()
        res = mpc.solve(xi_world, stance_xy, "left", t, stones[k:k + mpc.stones_needed])
        res.next_foothold, res.step_duration, res.footholds, res.durations

    Attributes:
        params: frozen parameters.
        failures: number of solver failures so far (each answered by a fallback).
        solves: number of :meth:`solve` calls.
    """

    name = "alip-mpc"

    def __init__(self, params: AlipMpcParams | None = None, solver: str | None = None) -> None:
        p = AlipMpcParams.paper() if params is None else params
        if not isinstance(p, AlipMpcParams):
            raise ParameterError("params", params, "an AlipMpcParams")
        if solver is not None:
            p = replace(p, solver=solver)
        self.params = p
        self._solver = _solver(p, p.solver)
        # constants of every call, computed once
        b = p.dcm_bounds
        self._kin = {sd: p.limits.box(sd) for sd in (1, -1)}
        self._zb = {sd: (b.lower(sd), b.upper(sd)) for sd in (1, -1)}
        self._sig_bounds = p.sigma_bounds
        self._sig_nom = p.sigma_nom
        self._betas = p.betas
        self._lam = p.lam
        self._alpha_z, self._alpha_u = np.asarray(p.alpha_z), np.asarray(p.alpha_u)
        self._alpha_cop = np.asarray(p.alpha_cop)
        self._cop_range = np.asarray(p.cop_range)
        self._per_side = {sd: self._side_constants(sd) for sd in (1, -1)}
        self._ws = _Workspace()
        self._call: _BufferedNlp | None = None
        self.failures = 0
        self.solves = 0

    def _side_constants(self, side0: int) -> dict[str, np.ndarray]:
        """What the bounds of a call take from the stance side ``side0`` alone (the swing sides alternate):
        the swing side of steps 0..N, the kinematic box and the viable DCM of steps 0..N-1 as (N, 2) rows,
        and the step-width terms of eq. (5) (read-only arrays)."""
        prm = self.params
        N, w = prm.horizon, prm.w
        sides = np.array([-side0 * (-1) ** k for k in range(N + 1)])  # swing side of step k
        j = slice(1, N + 1) if prm.dcm_target == "next" else slice(0, N)
        out = {
            "sides": sides,
            "kin_lo": np.array([self._kin[int(sd)][0] for sd in sides[:N]]),
            "kin_hi": np.array([self._kin[int(sd)][1] for sd in sides[:N]]),
            "zb_lo": np.array([self._zb[-int(sd)][0] for sd in sides[:N]]),
            "zb_hi": np.array([self._zb[-int(sd)][1] for sd in sides[:N]]),
            "w_next": sides[1 : N + 1] * w / (self._sig_nom + 1.0),  # w_{l/r} of step k+1, eq. (5)
            "w_target": sides[j] * w,  # the nominal width taken off the target step
        }
        for a in out.values():
            a.flags.writeable = False
        return out

    @property
    def horizon(self) -> int:
        """N, the number of previewed steps."""
        return self.params.horizon

    @property
    def stones_needed(self) -> int:
        """Upcoming stones read per call: N, plus one for z_des^N (fewer are padded)."""
        return self.params.horizon + 1

    @property
    def has_foot(self) -> bool:
        """True with a centre-of-pressure box (``params.cop_range`` > 0)."""
        return self.params.uses_cop

    def reset(self) -> None:
        """Forget the previous plan and the warm start (a new run)."""
        self._ws = _Workspace()
        self.failures = 0
        self.solves = 0

    # -- problem data -------------------------------------------------------------------
    def problem_data(
        self,
        dcm_world: ArrayLike,
        stance_world: ArrayLike,
        stance_side: int | str,
        t_since_touchdown: float,
        stones: Stones,
    ) -> dict:
        """Parameter vector and bounds of the NLP for this call (no solve, no side effect
        on the warm start). Keys: p, lbx, ubx, lbg, ubg, z0, u_des, z_des, sides, stance, e_t."""
        prm = self.params
        N = prm.horizon
        xi = check_xy("dcm_world", dcm_world)
        st = check_xy("stance_world", stance_world, InvalidInputError)
        side0 = parse_side(stance_side)
        t = check_time_since_touchdown(t_since_touchdown)
        c, s = _stone_arrays(stones, prm.stone_size)
        c, s = pad_stones(c, s, N + 1, st)
        lam = self._lam
        e_t = math.exp(-lam * t)
        z0 = (xi - st) * e_t
        sides = self._per_side[int(side0)]["sides"].copy()  # swing side of step k
        u_ext = self._desired_steps(st, side0, c)
        u_des = u_ext[:N].copy()
        lbx, ubx, lbg, ubg, z_des = self._bounds(st, c, s, sides, u_ext, u_des, t, lam)
        n_p = 2 + 4 * N + 1 + (1 if prm.uses_cop else 0)
        pvec = np.empty(n_p)
        pvec[0:2] = z0
        pvec[2 : 2 + 2 * N] = z_des.ravel()
        pvec[2 + 2 * N : 2 + 4 * N] = u_des.ravel()
        pvec[2 + 4 * N] = self._sig_nom if prm.max_speed <= 0.0 else float(self.nominal_sigmas(u_ext[:1, 0], lam)[0])
        if prm.uses_cop:
            lbx[5 * N :] = -self._cop_range
            ubx[5 * N :] = self._cop_range
            pvec[2 + 4 * N + 1] = e_t
        return {
            "p": pvec,
            "lbx": lbx,
            "ubx": ubx,
            "lbg": lbg,
            "ubg": ubg,
            "z0": z0,
            "u_des": u_des,
            "z_des": z_des,
            "sides": sides,
            "stance": st,
            "e_t": e_t,
        }

    def nominal_durations(self, u_x: np.ndarray) -> np.ndarray:
        """Nominal durations T_k [s] of steps of forward lengths ``u_x`` [m] with :attr:`AlipMpcParams.max_speed`:
        T_k = min(max(T_nom, |u_x| / max_speed), T_max); T_nom for every step when max_speed is 0."""
        prm = self.params
        u = np.abs(np.asarray(u_x, float))
        if prm.max_speed <= 0.0:
            return np.full(u.shape, prm.T_nom)
        return np.minimum(np.maximum(prm.T_nom, u / prm.max_speed), max(prm.T_max, prm.T_nom))

    def nominal_sigmas(self, u_x: np.ndarray, lam: float) -> np.ndarray:
        """exp(λ T_k) of steps of forward lengths ``u_x`` [m] (:meth:`nominal_durations`)."""
        return np.exp(lam * self.nominal_durations(u_x))

    def longest_durations(self, u_x: np.ndarray) -> np.ndarray:
        """Upper bounds [s] on the durations of steps of forward lengths ``u_x`` [m]: T_max + (T_k − T_nom), T_k
        being the step's nominal duration (:meth:`nominal_durations`). A step that ``max_speed`` slows keeps paper
        B's authority to slow down further (T_max − T_nom; e^{λ(T_max − T_nom)} on σ), which a fixed T_max would
        cut to T_max − T_k (Digit v3 at L = 0.55 m: 0.04 s instead of 0.15 s; docs/design.md). T_max for every
        step when max_speed is 0 (paper B)."""
        prm = self.params
        return prm.T_max + (self.nominal_durations(u_x) - prm.T_nom)

    def _desired_steps(self, st: np.ndarray, side0: int, c: np.ndarray) -> np.ndarray:
        """u_des^k for k = 1..N+1 (eq. 9): the stone centre from the previous plan's foothold for the
        same footstep (else from the previous stone centre) [m]."""
        N = self.params.horizon
        prev = self._previous_footholds(st, side0) if self.params.step_reference == "plan" else None
        ref = np.empty((N + 1, 2))
        ref[0] = st
        ref[1:] = c[:N]
        if prev is not None:
            m = min(len(prev), N)
            ref[1 : 1 + m] = prev[:m]
        return c[: N + 1] - ref

    def _bounds(
        self, st: np.ndarray, c: np.ndarray, s: np.ndarray, sides: np.ndarray, u_ext: np.ndarray, u_des: np.ndarray,
        t: float, lam: float,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Variable bounds (lbx, ubx), constraint bounds (lbg, ubg) and z_des, all N steps at once."""
        prm = self.params
        N = prm.horizon
        n5 = 5 * N
        lbx = np.empty(prm.n_x)
        ubx = np.empty(prm.n_x)
        per = self._per_side[-int(sides[0])]  # the swing side of step k picks its kinematic box
        kin_lo, kin_hi = per["kin_lo"], per["kin_hi"]
        half = 0.5 * s[:N]
        if prm.stone_bounds == "world" and N > 1:
            # stone k > 0 bounds the cumulative foothold (general constraint), u^k only kinematic
            fin = np.isfinite(half[1:])
            rel = c[1:N] - st
            lbg = np.concatenate([np.zeros(2 * N), np.where(fin, rel - half[1:], -np.inf).ravel()])
            ubg = np.concatenate([np.zeros(2 * N), np.where(fin, rel + half[1:], np.inf).ravel()])
            half[1:] = np.inf
        else:
            lbg, ubg = np.zeros(2 * N), np.zeros(2 * N)
        lo = np.maximum(u_des - half, kin_lo)
        hi = np.minimum(u_des + half, kin_hi)
        empty = lo > hi
        if empty.any():  # unreachable region: closest reachable point
            pt = np.clip(u_des, kin_lo, kin_hi)
            lo = np.where(empty, pt, lo)
            hi = np.where(empty, pt, hi)
        # z^k is the initial DCM of step k+1: eq. (5) with the desired step of step k+1
        # ("next", default) or of step k ("current"); w_{l/r} is step k+1's swing side
        sig_nom = self._sig_nom
        j = slice(1, N + 1) if prm.dcm_target == "next" else slice(0, N)
        z_des = np.empty((N, 2))
        if prm.max_speed > 0.0:  # long steps at most max_speed: their own nominal duration
            sig = self.nominal_sigmas(u_ext[j, 0], lam)
            z_des[:, 0] = u_ext[j, 0] / (sig - 1.0)
            z_des[:, 1] = sides[1 : N + 1] * prm.w / (sig + 1.0) + (u_ext[j, 1] - per["w_target"]) / (sig - 1.0)
        else:
            z_des[:, 0] = u_ext[j, 0] / (sig_nom - 1.0)
            z_des[:, 1] = per["w_next"] + (u_ext[j, 1] - per["w_target"]) / (sig_nom - 1.0)
        L, U = lbx[:n5].reshape(N, 5), ubx[:n5].reshape(N, 5)
        L[:, 0], U[:, 0] = self._sig_bounds
        T_max0 = prm.T_max
        if prm.max_speed > 0.0:  # a step slowed by max_speed keeps its authority to slow down further
            # the course's pace: stone k from stone k-1 (the current step from the stance foot), not u_des^k,
            # which grows by the previous foothold's lag behind its stone (a braking step is not a faster gait)
            T_hi = self.longest_durations(c[:N, 0] - np.r_[st[0], c[: N - 1, 0]])
            U[:, 0] = np.exp(lam * T_hi)
            T_max0 = float(T_hi[0])
        # the current step: not before t + min_time_to_touchdown, not after its T_max (unless t is already past it)
        t_lo = max(prm.T_min, min(t + prm.min_time_to_touchdown, T_max0), t)
        t_hi = max(T_max0, t_lo)
        L[0, 0], U[0, 0] = math.exp(lam * t_lo), math.exp(lam * t_hi)
        L[:, 1:3], U[:, 1:3] = lo, hi
        L[:, 3:5], U[:, 3:5] = per["zb_lo"], per["zb_hi"]  # the viable initial DCM of step k+1
        return lbx, ubx, lbg, ubg, z_des

    def _previous_footholds(self, stance: np.ndarray, side: int) -> np.ndarray | None:
        ws = self._ws
        if ws.last_ok is None:
            return None
        shift = ws.touchdowns_since_ok + (1 if self._is_new_step(stance, side) else 0)
        f = ws.last_ok.footholds
        return f[shift:] if shift < len(f) else None

    def _is_new_step(self, stance: np.ndarray, side: int) -> bool:
        ws = self._ws
        if ws.stance is None:
            return False
        prev = ws.stance
        return side != ws.stance_side or bool(abs(stance[0] - prev[0]) > 1e-9 or abs(stance[1] - prev[1]) > 1e-9)

    def cost(self, x: np.ndarray, data: dict) -> float:
        """Paper objective (unscaled) at the stacked solution ``x``."""
        prm = self.params
        N = prm.horizon
        x = np.asarray(x, float)
        X = x[: 5 * N].reshape(N, 5)
        ez = X[:, 3:5] - data["z_des"]
        eu = X[:, 1:3] - data["u_des"]
        es = X[:, 0] - data["p"][2 + 4 * N]
        per = (ez**2 @ self._alpha_z) + prm.alpha_sigma * es**2 + (eu**2 @ self._alpha_u)
        c = float(self._betas @ per)
        if prm.uses_cop:
            c += float(self._betas[0] * (x[5 * N :] ** 2 @ self._alpha_cop))
        return c

    # -- solve --------------------------------------------------------------------------
    @exclusive("planner")
    def solve(
        self,
        dcm_world: ArrayLike,
        stance_world: ArrayLike,
        stance_side: int | str,
        t_since_touchdown: float,
        stones: Stones,
    ) -> AlipPlanResult:
        """Plan the next footholds and step durations.

        Args:
            dcm_world: measured DCM ``xi`` in the world frame [m] (see
                :func:`lipmpcc.models.alip.dcm_from_com`).
            stance_world: current stance foot position, world frame [m].
            stance_side: side of the stance foot ("left"/+1 or "right"/-1); the next
                swing foot is the other one.
            t_since_touchdown: time since the current stance foot touched down [s].
            stones: the upcoming stones, next one first (:class:`~lipmpcc.terrain.Stone` list,
                :class:`~lipmpcc.terrain.StoneSequence` or (n, 2) centres). Fewer than N are padded.

        Returns:
            :class:`AlipPlanResult`; ``fallback=True`` when the solver failed.

        Raises:
            NoFallbackPlanError: the solver failed and no previous plan exists.
        """
        t_start = time.perf_counter()
        data = self.problem_data(dcm_world, stance_world, stance_side, t_since_touchdown, stones)
        side0 = parse_side(stance_side)
        st = data["stance"]
        ws = self._ws
        new_step = self._is_new_step(st, side0)
        if new_step:
            ws.touchdowns_since_ok += 1
        ws.stance, ws.stance_side = st.copy(), side0
        x0, lam_x0, lam_g0 = self._warm_start(data, new_step)
        call = self._call
        if call is None or call.solver is not self._solver:  # first call (or a subclass's own NLP)
            call = self._call = _BufferedNlp(self._solver)
        t0 = time.perf_counter()
        sol = call(data, x0, lam_x0, lam_g0)
        solve_time = time.perf_counter() - t0
        stats = call.stats()
        self.solves += 1
        x = np.asarray(sol["x"], dtype=float).ravel()
        status = str(stats.get("return_status", "unknown"))
        iters = int(stats.get("iter_count", -1))
        ok = self._accept(stats, x, data)
        if ok:
            ws.x = x
            ws.lam_x = np.asarray(sol["lam_x"], float).ravel()
            ws.lam_g = np.asarray(sol["lam_g"], float).ravel()
            res = self._result(x, data, t_since_touchdown, status, iters, solve_time)
            ws.last_ok = res
            ws.touchdowns_since_ok = 0
        else:
            self.failures += 1
            ws.x = None  # re-initialise the warm start from the data next time
            res = self._fallback(data, float(t_since_touchdown), status, iters, solve_time)
        res.plan_time = time.perf_counter() - t_start
        return res

    def _warm_start(self, data: dict, new_step: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        N = self.params.horizon
        ws = self._ws
        lbx, ubx = data["lbx"], data["ubx"]
        n5 = 5 * N
        if ws.x is not None:
            X = ws.x[:n5].reshape(N, 5)
            lx = ws.lam_x[:n5].reshape(N, 5) if ws.lam_x is not None else None
            d = ws.x[n5:]
            ld = ws.lam_x[n5:] if ws.lam_x is not None else np.zeros(d.size)
            lg = ws.lam_g
            if new_step:
                X = np.vstack([X[1:], X[-1:]])
                lx = np.vstack([lx[1:], lx[-1:]]) if lx is not None else None
                d, ld = np.zeros(d.size), np.zeros(d.size)  # a new stance foot
                if lg is not None:  # shift the dynamics block (2 per step) and the stone block
                    dyn, rest = lg[: 2 * N], lg[2 * N :]
                    dyn = np.concatenate([dyn[2:], dyn[-2:]])
                    rest = np.concatenate([rest[2:], rest[-2:]]) if rest.size else rest
                    lg = np.concatenate([dyn, rest])
            x0 = np.clip(np.concatenate([X.ravel(), d]), lbx, ubx)
            lx0 = np.concatenate([lx.ravel(), ld]) if lx is not None else np.zeros(lbx.size)
            lg0 = lg if lg is not None else np.zeros(len(data["lbg"]))
            return x0, lx0, lg0
        # cold start: nominal sigma, desired footholds clipped, z from the dynamics
        x0 = np.zeros(lbx.size)  # the CoP offset (if any) starts at the contact point
        z = data["z0"]
        for k in range(N):
            sig = float(np.clip(self.params.sigma_nom, lbx[5 * k], ubx[5 * k]))
            u = np.clip(data["u_des"][k], lbx[5 * k + 1 : 5 * k + 3], ubx[5 * k + 1 : 5 * k + 3])
            z = sig * z - u
            x0[5 * k] = sig
            x0[5 * k + 1 : 5 * k + 3] = u
            x0[5 * k + 3 : 5 * k + 5] = np.clip(z, lbx[5 * k + 3 : 5 * k + 5], ubx[5 * k + 3 : 5 * k + 5])
            z = x0[5 * k + 3 : 5 * k + 5]
        return x0, np.zeros(lbx.size), np.zeros(len(data["lbg"]))

    def _accept(self, stats: dict, x: np.ndarray, data: dict) -> bool:
        """Converged, or stopped on a too-small step at a feasible point."""
        status = str(stats.get("return_status", ""))
        ok = bool(stats.get("success", False)) or status in (
            "Search_Direction_Becomes_Too_Small",
            "Solved_To_Acceptable_Level",
        )
        if not ok or not np.isfinite(x).all():
            return False
        tol_b = 1e-7
        if (x < data["lbx"] - tol_b).any() or (x > data["ubx"] + tol_b).any():
            return False
        if self.params.stone_bounds == "world":
            n2 = 2 * self.params.horizon
            cum = np.cumsum(x[: 5 * self.params.horizon].reshape(-1, 5)[:, 1:3], axis=0)[1:].ravel()
            if (cum < data["lbg"][n2:] - tol_b).any() or (cum > data["ubg"][n2:] + tol_b).any():
                return False
        return self.dynamics_residual(x, data["z0"], data["e_t"]) <= 1e-6

    def dynamics_residual(self, x: np.ndarray, z0: np.ndarray, e_t: float = 1.0) -> float:
        """max |z^k - sigma^k z^{k-1} + u^k| of a stacked solution [m] (for k = 1 with the CoP
        offset d, if any: z^1 - sigma^1 (z^0 - e_t d) - d + u^1, ``e_t = e^{-lambda t}``)."""
        x = np.asarray(x, float)
        N = self.params.horizon
        v = x[: 5 * N].reshape(N, 5).tolist()  # N = 4: Python floats cost less than numpy calls on 2-vectors
        d0, d1 = (float(x[5 * N]), float(x[5 * N + 1])) if x.size > 5 * N else (0.0, 0.0)
        z = np.asarray(z0, float)
        p0, p1 = float(z[0]) - e_t * d0, float(z[1]) - e_t * d1  # the DCM about the CoP, then z^k
        r = 0.0
        for k, (sig, u0, u1, zk0, zk1) in enumerate(v):
            e0, e1 = (d0, d1) if k == 0 else (0.0, 0.0)
            r = max(r, abs(zk0 - sig * p0 - e0 + u0), abs(zk1 - sig * p1 - e1 + u1))
            p0, p1 = zk0, zk1
        return r

    def _result(self, x: np.ndarray, data: dict, t: float, status: str, iters: int, solve_time: float) -> AlipPlanResult:
        N = self.params.horizon
        X = x[: 5 * N].reshape(N, 5)
        cop = x[5 * N :].copy() if x.size > 5 * N else np.zeros(2)
        sigma = X[:, 0].copy()
        u = X[:, 1:3].copy()
        z = X[:, 3:5].copy()
        durations = np.log(sigma) / self.params.lam
        footholds = data["stance"] + np.cumsum(u, axis=0)
        return self._plan_result(data, float(t), footholds, durations, u, z, sigma, True, status, self.cost(x, data),
                                 iters, solve_time, cop)

    def _fallback(self, data: dict, t: float, status: str, iters: int, solve_time: float) -> AlipPlanResult:
        """The last successful plan, shifted by the touch-downs since, its first step lasting at least
        ``t + min_time_to_touchdown``."""
        ws = self._ws
        last = ws.last_ok
        k = ws.touchdowns_since_ok
        if last is None or k >= len(last.footholds):
            raise NoFallbackPlanError(
                self.params.solver,
                status,
                iters,
                "the ALIP-MPC failed and there is no previous plan to fall back on",
            )
        f = np.vstack([last.footholds[k:], np.repeat(last.footholds[-1:], k, axis=0)])
        d = np.concatenate([last.durations[k:], np.repeat(last.durations[-1:], k)])
        uu = np.vstack([last.u[k:], np.repeat(last.u[-1:], k, axis=0)])
        zz = np.vstack([last.z[k:], np.repeat(last.z[-1:], k, axis=0)])
        ss = np.concatenate([last.sigma[k:], np.repeat(last.sigma[-1:], k)])
        d[0] = max(float(d[0]), t + self.params.min_time_to_touchdown)
        return self._plan_result(data, t, f, d, uu, zz, ss, False, f"fallback ({status})", float("nan"), iters,
                                 solve_time, np.zeros(2))

    def _plan_result(
        self, data: dict, t: float, footholds: np.ndarray, durations: np.ndarray, u: np.ndarray, z: np.ndarray,
        sigma: np.ndarray, success: bool, status: str, cost: float, iters: int, solve_time: float, cop: np.ndarray,
    ) -> AlipPlanResult:
        """The result of a solve (``success``) or a fallback, from its footholds, durations and steps."""
        T1 = float(durations[0])
        return AlipPlanResult(
            next_foothold=footholds[0].copy(),
            step_duration=T1,
            time_to_touchdown=T1 - t,
            footholds=footholds,
            durations=durations,
            u=u,
            z=z,
            sigma=sigma,
            z0=data["z0"].copy(),
            success=success,
            fallback=not success,
            status=status,
            cost=cost,
            iterations=iters,
            solve_time=solve_time,
            solver=self.params.solver,
            cop_offset=cop,
        )
