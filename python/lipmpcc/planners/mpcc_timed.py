"""Paper A's MPCC with the step durations as decision variables (issue 18: paper A + paper B's timing).

:mod:`lipmpcc.planners.mpcc` plans N footsteps of a fixed duration T. Here each step's duration
T_k ∈ [T_min, T_max] is a decision variable too, and the plan starts from the state measured *now*,
``t̃`` after the stance foot touched down, so that the planner can re-plan within a step (paper B's
z⁰ = ξ(t̃) e^{−λt̃}). Variables, with x_k = [x, ẋ, y, ẏ, θ_h], ϑ the path parameter:

- the head: τ (the remaining duration of the current step), v_pre (path progress during it) and s_b, the
  slack of the current step's barrier rows;
- per step k = 0..N−1: u_k = [uˣ, uʸ, u^θ] (foot offset from the COM at the exchange, heading change),
  v_k (path progress) and T_k (the duration of the step on that foot).

The problem::

    minimise   paper A's cost of the N stages (mpcc.build_problem, unchanged), its progress reward
               −ρ v_k² made −ρ (v_k T_nom / T_k)² (a reward on the path speed; ``reward_speed``)
               + α_σ Σ_k (e^{ωT_k} − e^{ωT_nom})²  +  α_σ (e^{ω(t̃+τ)} − e^{ωT_nom})²  (paper B's σ term)
    subject to x_0 = A(τ) x_now + B(τ) [p_stance − c_now, 0],  ϑ_0 = ϑ_now + v_pre   (rest of the step)
               x_{k+1} = A(T_k) x_k + B(T_k) u_k,  ϑ_{k+1} = ϑ_k + v_k            (3D-LIP map, cosh/sinh ωT_k)
               reachability (15), distance per step (16), θ and v bounds, foot clearance: as in mpcc.py
               CBF (17) for every obstacle with its centre at the planned time t_k = t + τ + Σ_{i<k} T_i
               b(x_0, t_0) + s_b ≥ (1 − γ) min(b(x_now, t), 0),  s_b ∈ [0, 2]      (the current step; + w_b s_b)
               τ_lo ≤ τ ≤ τ_hi,  T_min ≤ T_k ≤ T_max,  0 ≤ v_pre ≤ 2 v_max

ω = √(g/H) of the MPCC's model, whose T is the nominal duration T_nom; as for the ALIP planners,
τ_lo = max(T_min − t̃, min(τ_min, T_max − t̃), 0) and τ_hi = max(T_max − t̃, τ_lo), τ_min being
``min_time_to_touchdown`` (the step ends at T_max at the latest, unless t̃ is already past it).
Each duration enters as its offset d = T − T_min ∈ [0, T_max − T_min] [s]; the current step's as
d_τ ∈ [0, T_max − T_min], τ = τ_lo + d_τ (τ_hi − τ_lo) / (T_max − T_min), so that the bounds of the
variables stay fixed while the current step's range moves with t̃. The current step's barrier row is the
anchor of the CBF chain (x_0 is a variable now), not the CBF rate itself, which the fixed stance foot
cannot always keep beside a passing obstacle; and it is soft (``anchor_slack_weight``): a full body measured
deep in the grown obstacle may drift further in about its stance foot whatever τ, and the hard row made
the QP infeasible there.
Each obstacle's centre at t_k is its second-order Taylor expansion about the times of the initial guess
(exact for obstacles at constant velocity or along a straight path; on a curved path the error is
third order in the change of time).

**Two call modes.** ``solve(..., time_since_touchdown=None)`` plans at a support exchange: x_now is the
state there and the first foot is placed now (τ = v_pre = 0, no current-step terms). This is the call
of :class:`~lipmpcc.planners.mpcc.MpccPlanner`, and with T_min = T_max = T the problem *is* that
planner's (the durations are fixed and every other term is built by the same code), so it gives the
same footsteps (with ``reward_speed`` too: T_k = T_nom leaves −ρv² as it is). With
``time_since_touchdown`` and ``stance_foot`` it plans within the step.
:meth:`TimedMpccPlanner.plan` (the planner contract) uses the first on the LIP loop, which calls at
exchanges, and the second when built with ``within_step=True``.

Solvers, warm start, retries, fallback and failure counting are those of the MPCC: the condensed SQP
(:class:`~lipmpcc.solvers.condensed_sqp.CondensedSqp`, DAQP, states eliminated — here they are nonlinear
in the durations), and an IPOPT formulation of the same problem (states as variables) for the parity
tests and the benchmark.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field, replace
from typing import Sequence

import casadi as ca
import numpy as np

from ..contouring import errors as contouring_errors
from ..conventions import parse_side
from ..exceptions import ParameterError, StateError
from .._deprecated import forward
from ..exclusive import exclusive
from ..obstacles import Obstacle, barrier_params
from ..paths import Path
from ..solvers.condensed_sqp import CondensedSqp
from ..solvers.sqp_compiled import compiled_function
from .base import PlannerInput, StepPlan
from .liveness import barred_by, detour_pace, end_frame, hold_inputs, problem_path
from .mpcc import (
    FORMULATION_BUILDERS,
    NB,
    MpccParams,
    MpccResult,
    _mirror_lateral,
    build_ipopt,
    build_problem,
    build_sqp,
    obstacle_reach,
)
from .mpcc_driver import MpccDriver

__all__ = [
    "TimedMpccParams",
    "TimedMpccResult",
    "TimedMpccPlanner",
    "TimedFormulation",
    "timed_lip_step",
    "build_timed_problem",
    "n_timed_params",
    "NUT",
    "NHEAD",
]

NUT = 5  # stage variables: uˣ, uʸ, u^θ, v, d (duration offset T − T_min [s])
NHEAD = 3  # head variables: d_τ (the current step's remaining duration, scaled) [s], v_pre (progress during it) [m],
#            s_b (the slack of the current step's barrier rows) [-]
NOB = 12  # obstacle data per obstacle and stage: c̄ (2), ċ (2), ½c̈ (2), M (3), F (3)
_NSCAL = 8  # scalar parameters: side, t, τ_lo, τ_hi, v_pre on, t̃, current-step weight, anchor flag
_SLACK_MAX = 2.0  # bound of the barrier slack s_b: b ≥ −1 and (1 − γ) min(b, 0) ≤ 0, so 2 relaxes any row
_FD = 1e-3  # finite-difference step for the obstacles' velocity and acceleration [s]
_EIG_FLOOR = 1.0  # the SQP's Hessian eigenvalue floor (as the MPCC's)
_SOC_STEP = 0.03  # the SQP corrects rejected full steps shorter than this (CondensedSqp's second_order_correction)
_RATE_STOP = 0.5  # the SQP also stops when the steps left are estimated below tol / 2 (CondensedSqp's rate_stop)


def _number(name: str, v: object) -> float:
    """``v`` as a finite float (numpy scalars accepted), else ParameterError naming it."""
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(float(v)):
        raise ParameterError(name, v, "a finite number")
    return float(v)


@dataclass(frozen=True)
class TimedMpccParams:
    """Parameters of the MPCC with step durations as decision variables (immutable).

    Attributes:
        mpcc: the MPCC's own parameters (horizon, weights, bounds, obstacles, solver, ...); its
            model's T is the nominal step duration T_nom [s] and its H gives ω = √(g/H).
        T_min, T_max: bounds of every step's duration [s]; T_min = T_max gives paper A's fixed T.
        duration_weight: α_σ, weight of (e^{ωT} − e^{ωT_nom})² per step (paper B's σ term) [-].
        min_time_to_touchdown: the current step ends at least this long after the call, unless that
            is after T_max [s] (0 as the ALIP-MPC's; above the loop's re-planning period it postpones
            every touch-down to T_max, each re-plan pushing it on).
        reward_speed: paper A's progress reward −ρ v_k² becomes −ρ (v_k T_nom / T_k)², a reward on the
            path speed v_k / T_k (the same at T_k = T_nom): without it the cost does not see time, and
            nothing pulls the durations below T_nom to walk faster (e.g. to overtake).
        anchor_slack_weight: w_b, the weight of the slack s_b ∈ [0, 2] of the current step's barrier rows
            (the anchor of the CBF chain, within steps only), cost w_b s_b: the exact penalty of a soft row,
            which holds whenever it can (its multiplier below w_b), and when the measured state is so deep in
            the grown obstacle that no remaining time τ about the fixed stance foot can keep it, the plan
            comes as far out as the stance foot lets it instead of the QP failing; ``math.inf``: a hard row
            (s_b = 0) [1/unit of the barrier b].
    """

    mpcc: MpccParams = field(default_factory=MpccParams)
    T_min: float = 0.3
    T_max: float = 0.5
    duration_weight: float = 1.0
    min_time_to_touchdown: float = 0.0
    reward_speed: bool = True
    anchor_slack_weight: float = 1e4

    def __post_init__(self) -> None:
        if not isinstance(self.mpcc, MpccParams):
            raise ParameterError("mpcc", self.mpcc, "an MpccParams")
        lo, hi = _number("T_min", self.T_min), _number("T_max", self.T_max)
        if lo <= 0.0:
            raise ParameterError("T_min", self.T_min, "a step duration > 0 [s]")
        if lo > hi:
            raise ParameterError("T_min", self.T_min, f"<= T_max = {hi} [s]")
        if not lo <= self.T_nom <= hi:
            raise ParameterError("mpcc.model.T", self.T_nom, f"a nominal duration in [T_min, T_max] = [{lo}, {hi}] [s]")
        if _number("duration_weight", self.duration_weight) < 0.0:
            raise ParameterError("duration_weight", self.duration_weight, "a weight >= 0")
        if isinstance(self.anchor_slack_weight, bool) or not isinstance(self.anchor_slack_weight, numbers.Real) \
                or not float(self.anchor_slack_weight) >= 0.0:
            raise ParameterError("anchor_slack_weight", self.anchor_slack_weight, "a weight >= 0 (math.inf: a hard row)")
        m = _number("min_time_to_touchdown", self.min_time_to_touchdown)
        if not 0.0 <= m < hi:
            raise ParameterError("min_time_to_touchdown", self.min_time_to_touchdown, f"a time in [0, T_max = {hi}) [s]")
        object.__setattr__(self, "T_min", lo)
        object.__setattr__(self, "T_max", hi)

    @classmethod
    def fixed(cls, mpcc: MpccParams | None = None, **kw: object) -> "TimedMpccParams":
        """Paper A's fixed duration: T_min = T_max = the model's T."""
        m = mpcc if mpcc is not None else MpccParams()
        return cls(mpcc=m, T_min=m.model.T, T_max=m.model.T, **kw)

    def with_(self, **kw: object) -> "TimedMpccParams":
        """A copy with some fields replaced."""
        return replace(self, **kw)

    @property
    def T_nom(self) -> float:
        """The nominal step duration, the MPCC model's T [s]."""
        return self.mpcc.model.T

    @property
    def N(self) -> int:
        """The horizon [steps]."""
        return self.mpcc.N

    @property
    def omega(self) -> float:
        """ω = √(g/H) [1/s]."""
        return self.mpcc.model.omega

    @property
    def d_max(self) -> float:
        """Upper bound of a duration variable d: T_max − T_min, or 1 when they are equal (d then has no effect) [s]."""
        return self.T_max - self.T_min if self.T_max > self.T_min else 1.0

    @property
    def d_gain(self) -> float:
        """T = T_min + d_gain · d: 1, or 0 when T_min = T_max."""
        return 1.0 if self.T_max > self.T_min else 0.0

    def duration(self, d: np.ndarray | float) -> np.ndarray:
        """Step duration(s) T [s] of the duration variable(s) d [s]."""
        return self.T_min + self.d_gain * np.asarray(d, dtype=float)

    def offset(self, T: np.ndarray | float) -> np.ndarray:
        """The duration variable(s) d of duration(s) T [s], within bounds."""
        return np.clip(np.asarray(T, dtype=float) - self.T_min, 0.0, self.d_max) * self.d_gain


@dataclass
class TimedMpccResult(MpccResult):
    """One solve of :class:`TimedMpccPlanner` (an :class:`~lipmpcc.planners.mpcc.MpccResult`: ``states[0]``
    is the state at the coming exchange, ``footsteps[0]`` the foot placed there).

    Attributes:
        durations: (N,) planned step durations T_k [s].
        remaining: τ, the time from the call to the coming exchange [s] (0 when called at one).
        time_since_touchdown: t̃ of the call [s] (NaN when called at an exchange).
        exchange_times: (N+1,) planned times of the exchanges [s].
        x_now: the state the plan started from [x, ẋ, y, ẏ, heading].
        theta_now: ϑ of the measured COM [m] (ϑ_0 = theta_now + the progress during τ).
        anchor_slack: s_b, how far the current step's barrier rows were relaxed [-] (0: kept; see
            :attr:`TimedMpccParams.anchor_slack_weight`).
    """

    durations: np.ndarray = field(default_factory=lambda: np.zeros(0))
    remaining: float = 0.0
    time_since_touchdown: float = math.nan
    exchange_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    x_now: np.ndarray = field(default_factory=lambda: np.zeros(5))
    theta_now: float = 0.0
    anchor_slack: float = 0.0

    @property
    def step_duration(self) -> float:
        """The current step's duration from its touch-down, t̃ + τ [s] (T_0 when called at an exchange)."""
        if math.isnan(self.time_since_touchdown):
            return float(self.durations[0])
        return float(self.time_since_touchdown + self.remaining)


# ---------------------------------------------------------------------------------------------- model
def timed_lip_step(x: ca.SX | ca.MX, u: ca.SX | ca.MX, T: ca.SX | ca.MX, omega: float) -> ca.SX | ca.MX:
    """The 3D-LIP step map x⁺ = A(T) x + B(T) u with a symbolic duration T [s] (CasADi; the formulas of
    :class:`~lipmpcc.models.lip3d.Lip3dModel`'s A and B, whose T is a number)."""
    ch, sh = ca.cosh(omega * T), ca.sinh(omega * T)
    return ca.vertcat(
        x[0] + x[1] * sh / omega + u[0] * (1.0 - ch),
        x[1] * ch - u[0] * omega * sh,
        x[2] + x[3] * sh / omega + u[1] * (1.0 - ch),
        x[3] * ch - u[1] * omega * sh,
        x[4] + u[2],
    )


def _lip_step_numeric(prm: TimedMpccParams, x: np.ndarray, u: np.ndarray, T: float) -> np.ndarray:
    """The same map in numpy, A(T) x + B(T) u with Lip3dModel's matrices written out (the identity for T = 0)."""
    if T <= 0.0:
        return np.array(x, dtype=float)
    w = prm.omega
    ch, sh = math.cosh(w * T), math.sinh(w * T)
    a, b, c = sh / w, 1.0 - ch, -w * sh
    return np.array([x[0] + a * x[1] + b * u[0], ch * x[1] + c * u[0], x[2] + a * x[3] + b * u[1], ch * x[3] + c * u[1],
                     x[4] + u[2]])


def _lip_step_list(w: float, x: Sequence[float], ux: float, uy: float, uth: float, T: float) -> list[float]:
    """:func:`_lip_step_numeric` on Python floats, ω = ``w`` [1/s] and u = (ux, uy, uth) [m, m, rad] (the same
    operations in the same order, so the same numbers; a list, for the planner's inner loop)."""
    if T <= 0.0:
        return [x[0], x[1], x[2], x[3], x[4]]
    ch, sh = math.cosh(w * T), math.sinh(w * T)
    a, b, c = sh / w, 1.0 - ch, -w * sh
    return [x[0] + a * x[1] + b * ux, ch * x[1] + c * ux, x[2] + a * x[3] + b * uy, ch * x[3] + c * uy, x[4] + uth]


_TIMED_ROLLOUT = compiled_function("timed_lip_rollout")  # None without the compiled module


def n_timed_params(prm: TimedMpccParams, n_obstacles: int) -> int:
    """Length of the parameter vector for ``n_obstacles`` obstacles: the scalars, x_now (6: LIP state and
    ϑ_now), the stance foot (2), the expansion times t̄_k (N+1), (1 − γ) min(b(x_now), 0) per obstacle and the
    obstacle data per obstacle and stage (c̄, ċ, ½c̈, M, F)."""
    return _NSCAL + 6 + 2 + (prm.N + 1) + n_obstacles * (1 + (prm.N + 1) * NOB)


def _split(prm: TimedMpccParams, p: ca.SX | ca.MX, n_obs: int) -> dict:
    """Name the parts of the parameter vector (see :func:`n_timed_params`)."""
    N = prm.N
    o = _NSCAL
    d = {"side": p[0], "t": p[1], "tau_lo": p[2], "tau_hi": p[3], "pre_on": p[4], "t_since": p[5], "w_rem": p[6], "anchor": p[7]}
    d["x_now"] = p[o : o + 6]
    d["pivot"] = p[o + 6 : o + 8]
    o += 8
    d["t_bar"] = p[o : o + N + 1]
    o += N + 1
    d["b_now"] = p[o : o + n_obs]
    o += n_obs
    d["obs"] = p[o:]
    return d


def _times(prm: TimedMpccParams, head: Sequence, stages: Sequence, q: dict) -> tuple[object, list, list]:
    """τ, the durations T_k and the exchange times t_k (k = 0..N) as expressions of the variables."""
    tau = q["tau_lo"] + head[0] * (q["tau_hi"] - q["tau_lo"]) / prm.d_max
    Ts = [prm.T_min + prm.d_gain * uk[4] for uk in stages]
    ts = [q["t"] + tau]
    for Tk in Ts:
        ts.append(ts[-1] + Tk)
    return tau, Ts, ts


def _obstacle_vector(prm: TimedMpccParams, q: dict, ts: list, n_obs: int) -> ca.SX | ca.MX:
    """mpcc.py's parameter vector [side, per obstacle and stage: cx, cy, M, F], with each centre at the
    planned time t_k (Taylor expansion about t̄_k)."""
    N = prm.N
    parts = [q["side"]]
    for j in range(n_obs):
        for k in range(N + 1):
            o = (j * (N + 1) + k) * NOB
            d = q["obs"][o : o + NOB]
            dt = ts[k] - q["t_bar"][k]
            parts += [d[0] + dt * (d[2] + dt * d[4]), d[1] + dt * (d[3] + dt * d[5])]
            parts += [d[6 + i] for i in range(6)]
    return ca.vertcat(*parts)


def build_timed_problem(path: Path, prm: TimedMpccParams, head: ca.SX | ca.MX, xs: Sequence, us: Sequence,
                        p: ca.SX | ca.MX, n_obs: int, arrival: tuple[float, float, float, float] | None = None,
                        ) -> tuple[ca.SX | ca.MX, list, list[float], list[float]]:
    """Cost and constraint rows of the timed MPCC, shared by both solvers (the dynamics apart).

    Args:
        path: reference path.
        prm: parameters.
        head: [d_τ, v_pre, s_b] (the scaled remaining duration [s], the progress during it [m] and the slack
            of the current step's barrier rows [-]).
        xs: N+1 stage states (6-vectors: LIP state + ϑ) from the coming exchange on.
        us: N stage variables [uˣ, uʸ, u^θ, v, d].
        p: parameters (:func:`n_timed_params`).
        n_obs: number of obstacles.
        arrival: the arrival row at the path's end (:func:`lipmpcc.planners.mpcc.build_problem`).

    Returns:
        (cost, g, lbg, ubg): paper A's terms from :func:`lipmpcc.planners.mpcc.build_problem` with the
        obstacles at the planned times, the duration costs, ϑ_k ≤ ϑ_T (k = 0..N) and the current step's
        CBF rows.
    """
    q = _split(prm, p, n_obs)
    tau, Ts, ts = _times(prm, head, us, q)
    pe = _obstacle_vector(prm, q, ts, n_obs)
    cost, g, lbg, ubg = build_problem(path, prm.mpcc, xs, [uk[0:4] for uk in us], pe, dynamics=False,
                                      arrival=arrival)
    w = prm.omega
    sig_nom = math.exp(w * prm.T_nom)
    a = prm.duration_weight
    for Tk, uk in zip(Ts, us):
        cost += a * (ca.exp(w * Tk) - sig_nom) ** 2
        if prm.reward_speed:  # −ρ v² (in build_problem) + this = −ρ (v T_nom / T)²
            cost -= prm.mpcc.rho * uk[3] ** 2 * ((prm.T_nom / Tk) ** 2 - 1.0)
    cost += q["w_rem"] * a * (ca.exp(w * (q["t_since"] + tau)) - sig_nom) ** 2
    if math.isfinite(prm.anchor_slack_weight):
        cost += prm.anchor_slack_weight * head[2]
    g, lbg, ubg = list(g), list(lbg), list(ubg)
    for k in range(prm.N + 1):
        g.append(xs[k][5])
        lbg.append(-ca.inf)
        ubg.append(path.length)
    # the current step: b(x_0, t_0) + s_b ≥ (1 − γ) min(b(x_now, t), 0), the anchor of the CBF chain now that
    # x_0 is free: the exchange state outside the (grown) obstacle, or recovering as the CBF would from inside.
    # Not the CBF itself, (1 − γ) b(x_now): the foot under the robot is fixed until the exchange, and beside
    # a passing obstacle no remaining time τ may keep that rate. Soft (the slack s_b ≥ 0, cost w_b s_b): a
    # full body measured deep inside the grown obstacle may be drifting further in about its stance foot
    # whatever τ, and the row then asks what no plan can do (the QP was infeasible and the replayed old plans
    # diverged); the exact penalty keeps the row whenever it can be kept
    for j in range(n_obs):
        o = 1 + (j * (prm.N + 1)) * NB
        dx, dy = xs[0][0] - pe[o], xs[0][2] - pe[o + 1]
        b0 = pe[o + 2] * dx * dx + 2 * pe[o + 3] * dx * dy + pe[o + 4] * dy * dy - 1.0
        g.append(q["anchor"] * (b0 - q["b_now"][j] + head[2]))
        lbg.append(0.0)
        ubg.append(ca.inf)
    return cost, g, lbg, ubg


def _first_state(prm: TimedMpccParams, head: ca.SX | ca.MX, q: dict) -> ca.SX | ca.MX:
    """x_0 = [A(τ) x_now + B(τ) (p_stance − c_now), ϑ_now + v_pre] (the rest of the current step)."""
    tau = q["tau_lo"] + head[0] * (q["tau_hi"] - q["tau_lo"]) / prm.d_max
    xn = q["x_now"]
    u_pre = ca.vertcat(q["pivot"][0] - xn[0], q["pivot"][1] - xn[2], 0.0)
    return ca.vertcat(timed_lip_step(xn[0:5], u_pre, tau, prm.omega), xn[5] + q["pre_on"] * head[1])


def _bounds(prm: TimedMpccParams) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of [head, stage variables]."""
    h = prm.mpcc.rectangle.heading
    v, d = prm.mpcc.v_max, prm.d_max
    s_hi = _SLACK_MAX if math.isfinite(prm.anchor_slack_weight) else 0.0
    lo = np.concatenate([[0.0, 0.0, 0.0], np.tile([-np.inf, -np.inf, h[0], 0.0, 0.0], prm.N)])
    hi = np.concatenate([[d, 2.0 * v, s_hi], np.tile([np.inf, np.inf, h[1], v, d], prm.N)])
    return lo, hi


def _build_sqp(path: Path, prm: TimedMpccParams, n_obs: int, max_iter: int = 100, tol: float = 1e-4,
               arrival: tuple[float, float, float, float] | None = None) -> CondensedSqp:
    """The fast solver: :class:`CondensedSqp` on the condensed problem (states eliminated; they are
    nonlinear in the durations). Variables [d_τ, v_pre, s_b, then per step uˣ, uʸ, u^θ, v, d] (3 + 5N);
    parameters p (:func:`n_timed_params`). Unlike the fixed-T MPCC's, it tries the second-order correction
    of a full step shorter than 3 cm the merit function rejects (the rows are curved in the durations: the
    re-plans within a step otherwise halve their first, millimetre-sized step) and also stops when the
    contraction of its last two steps puts the solution within ``tol / 2`` (``rate_stop``)."""
    N = prm.N
    z = ca.SX.sym("z", NHEAD + NUT * N)
    p = ca.SX.sym("p", n_timed_params(prm, n_obs))
    q = _split(prm, p, n_obs)
    head = z[0:NHEAD]
    us = [z[NHEAD + NUT * k : NHEAD + NUT * (k + 1)] for k in range(N)]
    _, Ts, _ = _times(prm, head, us, q)
    xs = [_first_state(prm, head, q)]
    for k in range(N):
        xk, uk = xs[k], us[k]
        xs.append(ca.vertcat(timed_lip_step(xk[0:5], uk[0:3], Ts[k], prm.omega), xk[5] + uk[3]))
    cost, g, lbg, ubg = build_timed_problem(path, prm, head, xs, us, p, n_obs, arrival)
    lo, hi = _bounds(prm)
    return CondensedSqp("mpcc_timed_sqp", z, [p], cost, ca.vertcat(*g), lbg, ubg, lo, hi, max_iter=max_iter, tol=tol,
                        jit=prm.mpcc.jit, eig_floor=_EIG_FLOOR, second_order_correction=_SOC_STEP,
                        rate_stop=_RATE_STOP)


def _build_ipopt(path: Path, prm: TimedMpccParams, n_obs: int,
                 arrival: tuple[float, float, float, float] | None = None) -> dict:
    """The same problem with the states as variables, CasADi ``Opti`` + IPOPT (as paper A's formulation).

    Returns ``{"opti": Opti, "vars": (X (6, N+1), Z (3 + 5N), P)}``.
    """
    N = prm.N
    opti = ca.Opti()
    X = opti.variable(6, N + 1)
    Z = opti.variable(NHEAD + NUT * N)
    P = opti.parameter(n_timed_params(prm, n_obs))
    q = _split(prm, P, n_obs)
    head = Z[0:NHEAD]
    us = [Z[NHEAD + NUT * k : NHEAD + NUT * (k + 1)] for k in range(N)]
    xs = [X[:, k] for k in range(N + 1)]
    _, Ts, _ = _times(prm, head, us, q)
    cost, g, lbg, ubg = build_timed_problem(path, prm, head, xs, us, P, n_obs, arrival)
    opti.minimize(cost)
    opti.subject_to(X[:, 0] == _first_state(prm, head, q))
    for k in range(N):
        xk, uk = xs[k], us[k]
        opti.subject_to(X[0:5, k + 1] == timed_lip_step(xk[0:5], uk[0:3], Ts[k], prm.omega))
        opti.subject_to(X[5, k + 1] == xk[5] + uk[3])
    for gi, lo, hi in zip(g, lbg, ubg):
        if hi == ca.inf:
            opti.subject_to(gi >= lo)
        elif lo == -ca.inf:
            opti.subject_to(gi <= hi)
        else:
            opti.subject_to(opti.bounded(lo, gi, hi))
    lo, hi = _bounds(prm)
    for i in range(Z.shape[0]):
        if math.isfinite(lo[i]) or math.isfinite(hi[i]):
            opti.subject_to(opti.bounded(lo[i], Z[i], hi[i]))
    opti.solver("ipopt", {"print_time": False, "error_on_fail": False},
                {"print_level": 0, "sb": "yes", "max_iter": 500, "tol": 1e-8})
    return {"opti": opti, "vars": (X, Z, P)}


#: :func:`lipmpcc.planners.mpcc.build_sqp` / ``build_ipopt`` build the timed MPCC's solvers for its parameters
FORMULATION_BUILDERS[TimedMpccParams] = (_build_sqp, _build_ipopt)


def __getattr__(name: str) -> object:
    if name in _MOVED:  # the old pair of builders: the MPCC's one pair now builds both formulations
        return _forward(name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


_MOVED = {"build_timed_sqp": "build_sqp", "build_timed_ipopt": "build_ipopt"}
_forward, _ = forward(__name__, "lipmpcc.planners.mpcc", _MOVED)


# ---------------------------------------------------------------------------------------------- planner
@dataclass(frozen=True)
class _Call:
    """What one solve starts from (see :meth:`TimedMpccPlanner.solve`)."""

    x_now: np.ndarray  # [x, ẋ, y, ẏ, heading]
    theta_now: float
    pivot: np.ndarray  # current stance foot (2,)
    t_now: float
    t_since: float  # NaN at an exchange
    side: int  # side of the foot placed at the coming exchange
    tau_lo: float
    tau_hi: float
    d_max: float  # the scale of d_τ [s]
    shift: bool

    @property
    def within(self) -> bool:
        return not math.isnan(self.t_since)

    @property
    def theta(self) -> float:
        """ϑ of the measured COM [m] (the driver's name)."""
        return self.theta_now

    def d_tau(self, tau: float) -> float:
        """The variable d_τ of a remaining duration τ [s]."""
        span = self.tau_hi - self.tau_lo
        return float(np.clip((tau - self.tau_lo) / span, 0.0, 1.0)) * self.d_max if span > 0 else 0.0

    def tau(self, d: float) -> float:
        """The remaining duration τ [s] of the variable d_τ."""
        return self.tau_lo + float(d) * (self.tau_hi - self.tau_lo) / self.d_max


#: one solve attempt: (converged, status, iterations, cost, X (N+1, 6), Z (3 + 5N))
_Attempt = tuple[bool, str, int, float, np.ndarray, np.ndarray]


class TimedFormulation:
    """The MPCC with step durations as decision variables, the formulation of :class:`TimedMpccPlanner` for the
    driver (:class:`~lipmpcc.planners.mpcc_driver.MpccFormulation`): the variables Z are [d_τ, v_pre, s_b, then
    per step uˣ, uʸ, u^θ, v, d] (3 + 5N).

    Args:
        path: the reference path; problem_path: the path the problem is built on; params: the timed MPCC's.
    """

    label = "mpcc-timed"

    def __init__(self, path: Path, problem_path: Path, params: TimedMpccParams) -> None:
        self.path, self.problem_path, self.params, self.mpcc = path, problem_path, params, params.mpcc
        #: a warm-started plan that stands still with obstacles in the problem is tried again from the cold starts
        #: (:meth:`~lipmpcc.planners.mpcc_driver.MpccDriver._standing`) — when the durations vary: with
        #: T_min = T_max the problem is paper A's, whose planner does not (the same footsteps)
        self.restart_standing = params.T_max > params.T_min
        #: held behind an obstacle moving on along the path it trails: no stall detour (liveness.trailed); its plans
        #: do not creep round such an obstacle, so a stall's detour there was the only pass, timed by chance
        self.trail_moving_on = params.T_max > params.T_min
        #: the detour and the return from it walk at the nominal pace (no reward on the path speed:
        #: :func:`~lipmpcc.planners.liveness.detour_pace`) when the durations vary
        self.detour_nominal_pace = params.T_max > params.T_min

    def build(self, path: Path, n_obs: int, solver: str, at_end: bool = False, arrive: bool = False) -> dict:
        """The SQP (``{"sqp": CondensedSqp}``) or IPOPT formulation for ``n_obs`` obstacles on ``path``
        (``at_end``: the end mode's, with ``delta_min`` = 0; ``arrive``: the approach's, with ``delta_min`` = 0
        and the arrival row at the end of :attr:`path`: :meth:`~lipmpcc.planners.mpcc_driver.MpccDriver._end_mode`)."""
        prm = self.params.with_(mpcc=self.mpcc.with_(delta_min=0.0)) if at_end or arrive else self.params
        arrival = end_frame(self.path, self.mpcc.delta_min) if arrive else None
        if solver == "sqp":
            return {"sqp": build_sqp(path, prm, n_obs, arrival=arrival)}
        return build_ipopt(path, prm, n_obs, arrival=arrival)

    @staticmethod
    def select(x0: np.ndarray, obstacles: list[Obstacle], t_now: float) -> list[Obstacle]:
        """Every obstacle (the durations move the planned times: none is left out)."""
        return obstacles

    def reach(self) -> float:
        """:func:`~lipmpcc.planners.mpcc.obstacle_reach` of the MPCC's parameters [m]."""
        return obstacle_reach(self.mpcc)
    def call(self, x0: np.ndarray, side: int, t_now: float, t_since: float | None, stance_foot: np.ndarray | None,
             theta_init: float | None, shift: bool, last: TimedMpccResult | None) -> _Call:
        """Check and gather what a solve starts from: the current step's τ range and ϑ_now (eq. 19)."""
        prm = self.params
        t_now = float(t_now)
        if t_since is None:
            pivot, ts, lo, hi = np.array([x0[0], x0[2]]), math.nan, 0.0, 0.0
        else:
            ts = float(t_since)
            if not (math.isfinite(ts) and ts >= 0.0):
                raise StateError("time_since_touchdown", t_since, "a finite time >= 0 [s]")
            pivot = np.asarray(stance_foot if stance_foot is not None else [np.nan], dtype=float).reshape(-1)[:2]
            if pivot.shape != (2,) or not np.all(np.isfinite(pivot)):
                raise StateError("stance_foot", stance_foot, "the finite (x, y) of the current stance foot [m]")
            m = prm.min_time_to_touchdown
            # as the ALIP planners: not before t̃ + min_time_to_touchdown, not after T_max (unless t̃ is past it)
            lo = max(prm.T_min - ts, min(m, prm.T_max - ts), 0.0)
            hi = max(prm.T_max - ts, lo)
        if theta_init is None:  # the closest point, searched around the previous plan's ϑ of about here
            hint = None
            if last is not None:
                if math.isnan(ts):  # at an exchange: ϑ_1 of the previous one (ϑ_0 when re-planning it)
                    hint = float(last.theta[1 if shift else 0])
                else:  # within a step: ϑ at the exchange just passed, or ϑ_now of the same step
                    hint = float(last.theta[0] if shift else last.theta_now)
            theta_init = self.path._closest_near(np.array([x0[0], x0[2]]), hint)
        theta_init = float(np.clip(theta_init, 0.0, self.path.length))
        return _Call(x0, theta_init, pivot, t_now, ts, side, lo, hi, prm.d_max, shift)

    def parameters(self, call: _Call, obstacles: Sequence[Obstacle], Z: np.ndarray) -> np.ndarray:
        """The parameter vector of a solve from the guess ``Z`` (the obstacles expanded about its times)."""
        return self.parameter_vector(call, obstacles, self.times(call, Z))

    def parameter_vector(self, call: _Call, obstacles: Sequence[Obstacle], t_bar: np.ndarray) -> np.ndarray:
        """The parameter vector (:func:`n_timed_params`) of a solve, the obstacles expanded about ``t_bar``."""
        prm = self.params
        m = prm.mpcc
        within = call.within
        scal = [float(call.side), call.t_now, call.tau_lo, call.tau_hi, 1.0 if within else 0.0,
                call.t_since if within else 0.0, 1.0 if within else 0.0, 1.0 if within else 0.0]
        x6 = np.append(call.x_now, call.theta_now)
        obs = list(obstacles)  # checked by solve
        infl, infl_f = m.obstacle_inflation, m.foot_radius + m.obstacle_margin
        if not np.isfinite(t_bar).all():  # (a non-finite t_now) barrier_params' error, naming the times
            barrier_params(obs, t_bar, infl, infl_f)
        data = np.zeros((len(obs), len(t_bar), NOB))
        b_now = np.zeros(len(obs))
        if not obs:
            return np.concatenate([scal, x6, call.pivot, t_bar, b_now, data.reshape(-1)])
        bp = barrier_params(obs, t_bar, infl, infl_f, check=False)  # (n, N+1, 8): c, M, F at t̄
        bp_now = barrier_params(obs, np.array([call.t_now]), infl, infl_f, check=False)
        for j, ob in enumerate(obs):
            c0 = bp[j, :, 0:2]  # the centres at t̄
            cp, cm = (np.atleast_2d(ob.center(t_bar + d)) for d in (_FD, -_FD))
            data[j, :, 0:2] = c0
            data[j, :, 2:4] = (cp - cm) / (2 * _FD)
            data[j, :, 4:6] = 0.5 * (cp - 2 * c0 + cm) / _FD**2
            data[j, :, 6:12] = bp[j, :, 2:8]
            bn = bp_now[j, 0]
            d = np.array([call.x_now[0], call.x_now[2]]) - bn[0:2]
            b = bn[2] * d[0] ** 2 + 2 * bn[3] * d[0] * d[1] + bn[4] * d[1] ** 2 - 1.0
            b_now[j] = (1.0 - m.gamma) * min(b, 0.0)
        return np.concatenate([scal, x6, call.pivot, t_bar, b_now, data.reshape(-1)])

    def rollout(self, call: _Call, Z: np.ndarray) -> np.ndarray:
        """Stage states (N+1, 6) [LIP state, ϑ] of the variables Z from the call's state (ϑ capped at ϑ_T): by
        ``lipmpcc._sqp.timed_lip_rollout`` when it imports (the same operations in C++, the same numbers to the bit:
        ``tests/planners/test_mpcc_timed.py``), else by :meth:`rollout_reference`."""
        if _TIMED_ROLLOUT is None:
            return self.rollout_reference(call, Z)
        prm = self.params
        return _TIMED_ROLLOUT(self.first_state(call, Z), Z, NHEAD, NUT, prm.N, prm.omega, prm.T_min, prm.d_gain,
                              self.problem_path.length)

    def rollout_reference(self, call: _Call, Z: np.ndarray) -> np.ndarray:
        """:meth:`rollout` in Python (the readable reference of the compiled one)."""
        prm = self.params
        w, t_min, gain, length = prm.omega, prm.T_min, prm.d_gain, self.problem_path.length
        z = Z.tolist()
        x = self.first_state(call, Z).tolist()
        rows = [x]
        for k in range(prm.N):
            ux, uy, uth, v, d = z[NHEAD + NUT * k : NHEAD + NUT * (k + 1)]
            nxt = _lip_step_list(w, x, ux, uy, uth, t_min + gain * d)  # T = prm.duration(d)
            nxt.append(min(x[5] + v, length))
            rows.append(nxt)
            x = nxt
        return np.array(rows)

    def first_state(self, call: _Call, Z: np.ndarray) -> np.ndarray:
        """x_0 = [the LIP about the stance foot for τ, ϑ_now + v_pre] (6,) of the variables Z."""
        xn = call.x_now.tolist()
        p = call.pivot
        x0 = _lip_step_list(self.params.omega, xn, float(p[0]) - xn[0], float(p[1]) - xn[2], 0.0, call.tau(Z[0]))
        x0.append(min(call.theta_now + (float(Z[1]) if call.within else 0.0), self.problem_path.length))
        return np.array(x0)

    def head_guess(self, call: _Call, last: TimedMpccResult | None) -> np.ndarray:
        """[d_τ, v_pre, s_b]: τ from the previous plan (or T_nom); the progress to the previous plan's ϑ at the
        coming exchange (its ϑ_0 re-planning the same step, its ϑ_1 in the next one), without a plan of this
        step's kind, to ϑ of the COM predicted at the exchange; no slack."""
        if not call.within:
            return np.zeros(NHEAD)
        prev = last
        th = None
        if prev is None or not math.isfinite(prev.time_since_touchdown):
            tau = self.params.T_nom - call.t_since
        elif call.shift:
            tau, th = float(prev.durations[0]) - call.t_since, float(prev.theta[1])
        else:
            tau, th = float(prev.exchange_times[0]) - call.t_now, float(prev.theta[0])
        d_tau = call.d_tau(tau)
        if th is None:
            xn = call.x_now
            x_ex = _lip_step_numeric(self.params, xn, np.array([call.pivot[0] - xn[0], call.pivot[1] - xn[2], 0.0]),
                                     call.tau(d_tau))
            th = self.path._closest_near(np.array([x_ex[0], x_ex[2]]), call.theta_now)
        return np.array([d_tau, float(np.clip(th - call.theta_now, 0.0, 2.0 * self.params.mpcc.v_max)), 0.0])

    def guess(self, call: _Call, last: TimedMpccResult | None, cold: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Initial guess (X, Z): the shifted (or same) previous plan, or a march along the path at v_max/2
        (X, the states, only start IPOPT; as MpccPlanner's)."""
        prm = self.params
        N = prm.N
        head = self.head_guess(call, last)
        if last is not None and not cold:
            Up = np.column_stack([last.inputs, last.v, prm.offset(last.durations)])
            if call.shift:
                tail = np.r_[_mirror_lateral(Up[-1, :4], float(last.states[-2, 4])), Up[-1, 4]]
                Up = np.vstack([Up[1:], tail])
            Z = np.concatenate([head, Up.reshape(-1)])
            Xp = np.column_stack([last.states, last.theta])
            X = np.vstack([Xp[1:], Xp[-1:]]) if call.shift else Xp.copy()
            X[0] = self.first_state(call, Z)
            return X, Z
        x0 = self.first_state(call, np.concatenate([head, np.zeros(NUT * N)]))
        U = np.zeros((N, NUT))
        U[:, 4] = prm.offset(prm.T_nom)
        th = [min(x0[5] + 0.5 * prm.mpcc.v_max * k, self.path.length) for k in range(N + 1)]
        lat = 0.5 * sum(prm.mpcc.rectangle.lateral)
        side = call.side
        X = np.zeros((N + 1, 6))
        for k in range(N + 1):
            pk = self.path.position(th[k])
            X[k] = [pk[0], 0.0, pk[1], 0.0, x0[4], th[k]]
        X[0] = x0
        for k in range(N):
            U[k, 3] = th[k + 1] - th[k]
            U[k, 0] = -math.sin(x0[4]) * side * lat
            U[k, 1] = math.cos(x0[4]) * side * lat
            side = -side
        return X, np.concatenate([head, U.reshape(-1)])

    def times(self, call: _Call, Z: np.ndarray) -> np.ndarray:
        """The exchange times (N+1,) [s] of the variables Z."""
        prm = self.params
        t_min, gain = prm.T_min, prm.d_gain
        t0 = call.t_now + call.tau(Z[0])
        out, acc = [t0 + 0.0], 0.0
        for k, d in enumerate(Z[NHEAD + NUT - 1 :: NUT].tolist()):
            T = t_min + gain * d  # prm.duration(d)
            acc = T if k == 0 else acc + T  # the running sum of np.cumsum
            out.append(t0 + acc)
        return np.array(out)


    def solve_sqp(self, built: dict, call: _Call, p: np.ndarray, Xg: np.ndarray, Zg: np.ndarray) -> _Attempt:
        """One SQP solve from the guess ``Zg``."""
        sol = built["sqp"].solve(Zg, (p,))
        return sol.found, sol.status, sol.iterations, sol.cost, self.rollout(call, sol.u), sol.u.copy()

    def solve_ipopt(self, built: dict, call: _Call, p: np.ndarray, Xg: np.ndarray, Zg: np.ndarray) -> _Attempt:
        """One IPOPT solve from the guess (Xg, Zg)."""
        opti = built["opti"]
        X, Z, P = built["vars"]
        opti.set_value(P, p)
        opti.set_initial(X, Xg.T)
        opti.set_initial(Z, Zg)
        sol = opti.solve()
        st = sol.stats()
        Zs = np.clip(np.asarray(sol.value(Z), dtype=float).reshape(-1), *_bounds(self.params))
        Xs = self.rollout(call, Zs)
        # the cost of the returned (clipped) point: IPOPT may end a bound's tolerance (~1e-8) outside it, which
        # the slack's weight w_b makes ~1e-4 of cost
        cost = float(sol.value(opti.f, [X == Xs.T, Z == Zs]))
        return (bool(st.get("success", False)), str(st.get("return_status", "")), int(st.get("iter_count", -1)), cost,
                Xs, Zs)

    def vcols(self) -> np.ndarray:
        """The indices of the steps' path progress v in Z."""
        return NHEAD + 3 + NUT * np.arange(self.params.N)

    def with_progress(self, Z: np.ndarray, v: float) -> np.ndarray:
        """A copy of ``Z`` with v = ``v`` [m] at every step."""
        Zr = Z.copy()
        Zr[self.vcols()] = v
        return Zr

    def mean_progress(self, Z: np.ndarray) -> float:
        """The mean v of ``Z`` [m] (np.mean's sum over the count)."""
        vcols = self.vcols()
        return float(Z[vcols].sum() / len(vcols))

    def progress_start(self, call: _Call, best: np.ndarray, Zg: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The best solution with v = v_max / 2 ("stand still" is a local minimum of −ρv²)."""
        Zr = self.with_progress(best, 0.5 * self.mpcc.v_max)
        return self.rollout(call, Zr), Zr

    def result(self, call: _Call, X: np.ndarray, Z: np.ndarray, found: bool, status: str, iters: int, elapsed: float,
               cost: float, side: int = 0) -> TimedMpccResult:
        """The :class:`TimedMpccResult` of the states ``X`` and variables ``Z`` (its side: the call's)."""
        U = Z[NHEAD:].reshape(-1, NUT)
        states, theta, inputs = X[:, :5].copy(), X[:, 5].copy(), U[:, :3].copy()
        foot = states[:-1, [0, 2, 4]] + inputs  # [x + uˣ, y + uʸ, θ + u^θ]
        ref, phi = self.problem_path._frame(theta)  # position and slope, one evaluation (their numbers)
        e = contouring_errors(states[:, [0, 2]], ref, phi, check=False)  # our own finite arrays (checked by _attempt)
        return TimedMpccResult(
            found=found, status=status, iterations=iters, solve_time=elapsed, cost=cost, states=states, theta=theta,
            v=U[:, 3].copy(), inputs=inputs, footsteps=foot, e_contouring=e[:, 0], e_lag=e[:, 1],
            theta_init=float(theta[0]), stance_side=call.side, durations=np.asarray(self.params.duration(U[:, 4]), dtype=float),
            remaining=call.tau(Z[0]), time_since_touchdown=call.t_since, exchange_times=self.times(call, Z),
            x_now=call.x_now.copy(), theta_now=call.theta_now, anchor_slack=float(Z[2]),
        )

    def replay(self, call: _Call, last: TimedMpccResult, obstacles: Sequence[Obstacle] = ()) \
            -> tuple[np.ndarray, np.ndarray, int, list[int]]:
        """The previous plan (shifted by one step for a new step), replayed from the current state; when that
        replay walks into one of ``obstacles``, the steps after the coming exchange step in place instead
        (``held_by`` names them; :func:`~lipmpcc.planners.liveness.hold_inputs`, at T_nom)."""
        prev = last
        prm = self.params
        U = np.column_stack([prev.inputs, prev.v, prm.offset(prev.durations)])
        if call.shift:
            U = np.vstack([U[1:], np.r_[_mirror_lateral(U[-1, :4], float(prev.states[-2, 4])), U[-1, 4]]])
        Z = np.concatenate([self.head_guess(call, last), U.reshape(-1)])
        X = self.rollout(call, Z)
        held = barred_by(X[:, [0, 2]], self.times(call, Z), obstacles, prm.mpcc.obstacle_inflation) if obstacles else []
        if held:  # no way out: hold in place rather than walk into the obstacle (issue 31)
            rect = prm.mpcc.rectangle
            Uh = hold_inputs(X[0, :5], call.side, prm.N, prm.omega, prm.T_nom, rect.lateral, rect.forward)
            U = np.column_stack([Uh, np.zeros(prm.N), np.full(prm.N, float(prm.offset(prm.T_nom)))])
            Z = np.concatenate([Z[:NHEAD], U.reshape(-1)])
            Z[1] = 0.0  # no progress in the current step either
            X = self.rollout(call, Z)
        return X, Z, call.side, held


class TimedMpccPlanner(MpccDriver):
    """The MPCC with step durations as decision variables, with warm start and safe fallback (the driver
    :class:`~lipmpcc.planners.mpcc_driver.MpccDriver` of :class:`~lipmpcc.planners.mpcc.MpccPlanner` over
    :class:`TimedFormulation`).

    Args:
        path: reference path (arc-length parametrised).
        params: :class:`TimedMpccParams`.
        name: planner name used in summaries.
        within_step: how :meth:`plan` reads its input: False, the LIP loop's call at each support exchange
            (the foot is placed now; one solve per step); True, a call at any time during the step (the
            full-body loop's), planning from the measured state t̃ after touch-down.

    Attributes:
        rate_hz: how often a loop may call :meth:`plan` [Hz] (15 at exchanges as paper A, 25 within steps
            as paper B).
        failures, solves: failed solves (the fallback was used) and all solves.
        last: the last :class:`TimedMpccResult`.
        progress: the :class:`~lipmpcc.planners.liveness.ProgressMonitor` of the liveness rules.
        detour_solves: solves made in the detour mode (:mod:`lipmpcc.planners.liveness`).
    """

    def __init__(self, path: Path, params: TimedMpccParams | None = None, name: str = "mpcc-timed",
                 within_step: bool = False) -> None:
        if not isinstance(path, Path):
            raise ParameterError("path", path, "a lipmpcc.paths.Path")
        if params is not None and not isinstance(params, TimedMpccParams):
            raise ParameterError("params", params, "a TimedMpccParams")
        self.path = path
        self.params = params if params is not None else TimedMpccParams()
        self.name = name
        self.within_step = bool(within_step)
        self.rate_hz = 25.0 if self.within_step else 15.0
        m = self.params.mpcc
        #: the path the problem is built on (``path``, or continued past its end by the reach of N steps and
        #: the current step's progress, (N + 2) v_max: ``MpccParams.past_end``)
        self.problem_path = problem_path(path, m.past_end, (m.N + 2) * m.v_max)
        self._init_driver(TimedFormulation(path, self.problem_path, self.params))
        self._last_step = -1

    def reset(self) -> None:
        """Forget the previous plan (warm start and fallback) and the counts."""
        super().reset()
        self._last_step = -1

    # ---- problem data (the formulation's) ----------------------------------------------------------
    def _call(self, x0: np.ndarray, side: int, t_now: float, t_since: float | None, stance_foot: np.ndarray | None,
              theta_init: float | None, shift: bool) -> _Call:
        """:meth:`TimedFormulation.call` from this planner's previous plan."""
        return self.formulation.call(x0, side, t_now, t_since, stance_foot, theta_init, shift, self.last)

    def parameters(self, call: _Call, obstacles: Sequence[Obstacle], t_bar: np.ndarray) -> np.ndarray:
        """The parameter vector (:func:`n_timed_params`) of a solve, the obstacles expanded about ``t_bar``."""
        return self.formulation.parameter_vector(call, obstacles, t_bar)

    def rollout(self, call: _Call, Z: np.ndarray) -> np.ndarray:
        """Stage states (N+1, 6) [LIP state, ϑ] of the variables Z from the call's state (ϑ capped at ϑ_T)."""
        return self.formulation.rollout(call, Z)

    def _times(self, call: _Call, Z: np.ndarray) -> np.ndarray:
        """The exchange times (N+1,) [s] of the variables Z."""
        return self.formulation.times(call, Z)
    # ---- solving ------------------------------------------------------------------------------------
    @exclusive("planner")
    def solve(
        self,
        x0: np.ndarray,
        stance_side: int,
        obstacles: Sequence[Obstacle] = (),
        t_now: float = 0.0,
        time_since_touchdown: float | None = None,
        stance_foot: np.ndarray | None = None,
        theta_init: float | None = None,
        shift: bool = True,
    ) -> TimedMpccResult:
        """Plan N steps and their durations.

        Args:
            x0: [x, ẋ, y, ẏ, heading] measured now (at the support exchange when ``time_since_touchdown``
                is None) [m, m/s, rad].
            stance_side: side of the foot placed at the coming exchange (+1 left, −1 right).
            obstacles: moving obstacles (their clocks are ``t_now``'s).
            t_now: current time [s].
            time_since_touchdown: t̃ [s]; None plans at an exchange (paper A's call).
            stance_foot: (x, y) of the current stance foot [m] (needed with ``time_since_touchdown``).
            theta_init: ϑ of the measured COM [m]; default: the closest point, searched locally.
            shift: this solve is the first of a new step (warm start and fallback from the shifted
                previous plan), or it re-plans the same step (False).

        Returns:
            :class:`TimedMpccResult`.

        Raises:
            NoFallbackPlanError: the solve failed and there is no previous plan.
        """
        x0, obstacles = self._check_inputs(x0, stance_side, obstacles)
        return self._drive(x0, obstacles, t_now, lambda: self._call(x0, int(stance_side), t_now, time_since_touchdown,
                                                                   stance_foot, theta_init, shift))

    def _detour_solve(self, call: _Call, obstacles: list[Obstacle], s: float = 0.0) -> TimedMpccResult:
        return self._solve_detour(call.x_now, call.side, obstacles, call.t_now, call.t_since if call.within else None,
                                  call.pivot if call.within else None, call.theta_now, call.shift, s)

    def _solve_detour(self, x0: np.ndarray, side: int, obstacles: list[Obstacle], t_now: float,
                      t_since: float | None, stance_foot: np.ndarray | None, theta: float,
                      shift: bool, s: float = 0.0) -> TimedMpccResult:
        """The solve of the detour mode (:mod:`lipmpcc.planners.liveness`, as MpccPlanner's): the detour
        weights (or, ``s`` > 0, the return's), by a planner of its own warm-started from this one's plan."""
        if s not in self._detour_planners:
            prm = replace(self.params, mpcc=self.params.mpcc.with_(**self._detour_fields(s)))
            if self.formulation.detour_nominal_pace:
                prm = prm.with_(**detour_pace(prm))
            name = f"{self.name}-detour" if s == 0.0 else f"{self.name}-return"
            self._detour_planners[s] = TimedMpccPlanner(self.path, prm, name, self.within_step)
        sub = self._detour_planners[s]
        return self._via_detour(sub, lambda: sub.solve(x0, side, obstacles, t_now, t_since, stance_foot,
                                                       theta_init=theta, shift=shift), s)

    # ---- the planner contract -----------------------------------------------------------------------
    @exclusive("planner")
    def plan(self, inp: PlannerInput) -> StepPlan:
        """The planner contract: the swing foot's foothold, yaw and step duration.

        At exchanges (``within_step`` False, the LIP loop): the state ``[com x, ẋ, com y, ẏ, torso_yaw]``
        is the exchange's, the foot is placed now and ``duration`` is T_0, the first planned duration;
        later calls with the same ``step_index`` return the same plan. Within steps (``within_step``
        True): the state is measured now, ``inp.time_since_touchdown`` after the stance foot (at
        ``inp.stance_pos``, heading ``inp.stance_yaw``) touched down; the foot lands after the planned
        remaining time τ, and ``duration`` is t̃ + τ. ``record`` is the :class:`TimedMpccResult`; the
        preview rows are the N footholds with their durations.

        Raises:
            NoFallbackPlanError: the first solve failed.
            StateError: ``inp`` is not a :class:`PlannerInput`.
        """
        if not isinstance(inp, PlannerInput):
            raise StateError("inp", inp, "a lipmpcc.planners.base.PlannerInput (the loop's state at this call)")
        if not self.within_step and self._step_plan is not None and self._step_plan[0] == inp.step_index:
            return self._step_plan[1]
        side = parse_side(inp.stance_side).other.sign
        c, v = np.asarray(inp.com_pos, dtype=float), np.asarray(inp.com_vel, dtype=float)
        if self.within_step:
            x0 = np.array([c[0], v[0], c[1], v[1], float(inp.stance_yaw)])
            shift = int(inp.step_index) != self._last_step
            theta = self.path.closest_point([x0[0], x0[2]], theta_prev=0.0) if self.last is None else None
            res = self.solve(x0, side, inp.obstacles, float(inp.t), float(inp.time_since_touchdown),
                             np.asarray(inp.stance_pos, dtype=float)[:2], theta_init=theta, shift=shift)
            self._last_step = int(inp.step_index)
        else:
            x0 = np.array([c[0], v[0], c[1], v[1], float(inp.torso_yaw)])
            res = self.solve(x0, side, inp.obstacles, t_now=float(inp.t))
        fs = res.footsteps
        plan = StepPlan(
            foothold=fs[0, :2].copy(),
            yaw=float(fs[0, 2]),
            duration=res.step_duration,
            com_target=res.states[1, [0, 2]],
            preview=np.column_stack([fs, res.durations]),
            cost=res.cost,
            solve_time=res.solve_time,
            status=f"fallback ({res.status})" if res.used_fallback else "ok",
            record=res,
        )
        if not self.within_step:
            self._step_plan = (int(inp.step_index), plan)
        return plan
