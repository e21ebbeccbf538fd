"""ALIP-QP: the one-step DCM step-timing QP of Khadiv et al. (T-RO 2020), paper B's baseline.

Variables ``x = (u_x, u_y, tau, b_x, b_y, s_1..s_4)``: the next foothold ``u`` relative
to the stance foot, ``tau = exp(omega T)`` and the DCM offset ``b`` (the DCM at
touch-down relative to the new foot, i.e. paper B's ``z^1``), plus 4 slacks >= 0 that
soften the bounds on ``b``::

    min  sum_i q_i (x_i - x_nom,i)^2
    s.t. u + b = z0 tau             z0 = (xi_meas - u_0) exp(-omega t)   (linear in tau)
         u_lo <= u <= u_hi,  tau_lo <= tau <= tau_hi                      (hard)
         b_lo - s_lo <= b <= b_hi + s_hi,  s >= 0                         (soft)

Two front ends share :class:`StepTimingQp` (solved with proxsuite's dense ProxQP):

* :class:`AlipQp` — paper B's stepping-stone baseline with the same planner contract
  (``plan(PlannerInput) -> StepPlan``), :meth:`~AlipQp.solve` API and result type as
  :class:`~lipmpcc.planners.alip_mpc.AlipMpc`:
  ``u_nom`` = next stone, ``tau_nom = exp(lambda T_nom)``, ``b_nom`` from eq. (5) (the
  MPC's ``z_des^1``), ``u`` bounded by the stone rectangle and the kinematic limits,
  ``b`` softly bounded by the viable-DCM intervals.
* :func:`dcm_vrp_step` — the original DcmVrpPlanner front end (nominal step from a
  desired velocity, step-length/width bounds, pelvis offset ``l_p``), used to check the
  published reference cases.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..conventions import GRAVITY
from ..exceptions import InvalidInputError, NoFallbackPlanError, ParameterError, SolverError, StateError
from ..exclusive import exclusive
from ..validation import check_field_types, finite_vector, is_finite_number, number_in
from ..models.alip import AlipParams, KinematicLimits, parse_side
from ..models.lip import omega
from ..terrain import STEP_WIDTH, STONE_SIZE
from .alip_common import (
    AlipPlanner,
    AlipPlanResult,
    AlipStepParams,
    Stones,
    check_time_since_touchdown,
    check_xy,
    pad_stones,
    stone_arrays,
)

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = [
    "StepTimingSolution",
    "StepTimingQp",
    "AlipQpParams",
    "AlipQp",
    "DcmVrpParams",
    "DcmVrpSolution",
    "dcm_vrp_step",
]

_INF = 1e20
N_VAR = 9


def _weights(name: str, w: Sequence[float]) -> tuple[float, ...]:
    try:
        a = np.asarray(w, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, w, "9 finite weights >= 0 (u_x, u_y, tau, b_x, b_y, 4 slacks)") from None
    if a.shape != (N_VAR,) or not np.all(np.isfinite(a)) or np.any(a < 0) or np.any(a[5:] <= 0) or a[2] <= 0:
        raise ParameterError(name, w, "9 finite weights >= 0 (u_x, u_y, tau, b_x, b_y, 4 slacks), tau and slacks > 0")
    return tuple(float(v) for v in a)


# ----------------------------------------------------------------------------- QP core
@dataclass
class StepTimingSolution:
    """Solution of one step-timing QP.

    Attributes:
        u: next foothold relative to the stance foot (QP frame) [m].
        tau: exp(omega T).
        duration: T = ln(tau)/omega [s].
        b: DCM offset at touch-down relative to the new foot [m].
        slacks: (4,) slacks of the soft b bounds [m] (b_x upper, b_x lower, b_y upper, b_y lower).
        success: ProxQP solved it.
        status: ProxQP status.
        iterations: ProxQP iterations.
        solve_time: wall time of the solve [s].
        cost: sum_i q_i (x_i - x_nom,i)^2.
    """

    u: np.ndarray
    tau: float
    duration: float
    b: np.ndarray
    slacks: np.ndarray
    success: bool
    status: str
    iterations: int
    solve_time: float
    cost: float


class StepTimingQp:
    """Khadiv's QP with a fixed structure (9 variables, 2 equalities, 4 soft-bound rows,
    box bounds), solved by proxsuite dense ProxQP."""

    def __init__(self, weights: Sequence[float], eps_abs: float = 1e-10) -> None:
        import proxsuite

        self.weights = np.array(_weights("weights", weights))
        number_in("eps_abs", eps_abs, 0.0, 1e-2, lo_open=True, hi_open=True, error=ParameterError, what="a tolerance")
        self._H = np.diag(self.weights)
        self._A = np.zeros((2, N_VAR))
        self._A[0, 0] = self._A[1, 1] = 1.0
        self._A[0, 3] = self._A[1, 4] = 1.0
        C = np.zeros((4, N_VAR))
        C[0, 3], C[0, 5] = 1.0, -1.0  # b_x - s1 <= bx_hi
        C[1, 3], C[1, 6] = 1.0, 1.0  # b_x + s2 >= bx_lo
        C[2, 4], C[2, 7] = 1.0, -1.0  # b_y - s3 <= by_hi
        C[3, 4], C[3, 8] = 1.0, 1.0  # b_y + s4 >= by_lo
        self._C = C
        self._b = np.zeros(2)
        self._l = np.array([-_INF, 0.0, -_INF, 0.0])  # b_x + s2 >= bx_lo, b_y + s4 >= by_lo
        self._u = np.array([0.0, _INF, 0.0, _INF])  # b_x - s1 <= bx_hi, b_y - s3 <= by_hi
        self._lbox = np.array([0.0, 0.0, 0.0, -_INF, -_INF, 0, 0, 0, 0], dtype=float)  # u_lo, tau_lo, b free, s >= 0
        self._ubox = np.array([0.0, 0.0, 0.0, _INF, _INF, _INF, _INF, _INF, _INF], dtype=float)
        self._qp = proxsuite.proxqp.dense.QP(N_VAR, 2, 4, True)
        self._qp.settings.eps_abs = float(eps_abs)
        self._qp.settings.eps_rel = 0.0
        self._qp.settings.verbose = False
        self._solved = proxsuite.proxqp.QPSolverOutput.PROXQP_SOLVED

    def solve(
        self,
        z0: Sequence[float],
        u_nom: Sequence[float],
        tau_nom: float,
        b_nom: Sequence[float],
        u_lo: Sequence[float],
        u_hi: Sequence[float],
        tau_lo: float,
        tau_hi: float,
        b_lo: Sequence[float],
        b_hi: Sequence[float],
    ) -> StepTimingSolution:
        """Solve for the given data (all in the QP frame, [m])."""
        z0 = np.asarray(z0, float)
        nom = np.array([u_nom[0], u_nom[1], tau_nom, b_nom[0], b_nom[1], 0, 0, 0, 0], dtype=float)
        vals = np.concatenate([z0, nom, u_lo, u_hi, [tau_lo, tau_hi], b_lo, b_hi])
        if vals.shape != (21,) or not np.isfinite(vals).all():
            raise InvalidInputError("QP data", vals.tolist(), "finite numbers")
        # vals = z0 (2), nom (9), u_lo (2), u_hi (2), tau_lo, tau_hi, b_lo (2), b_hi (2)
        if vals[11] > vals[13] or vals[12] > vals[14] or tau_lo > tau_hi or tau_lo < 1.0:
            raise InvalidInputError("bounds", (u_lo, u_hi, tau_lo, tau_hi), "u_lo <= u_hi and 1 <= tau_lo <= tau_hi")
        g = -self.weights * nom
        # the QP's data in the arrays made once (ProxQP's init copies them); only these entries change
        A, l, u, lbox, ubox = self._A, self._l, self._u, self._lbox, self._ubox
        A[0, 2], A[1, 2] = -z0[0], -z0[1]
        l[1], l[3] = vals[17], vals[18]
        u[0], u[2] = vals[19], vals[20]
        lbox[0:3] = vals[11], vals[12], vals[15]
        ubox[0:3] = vals[13], vals[14], vals[16]
        t0 = time.perf_counter()
        self._qp.init(self._H, g, A, self._b, self._C, l, u, lbox, ubox)
        self._qp.solve()
        dt = time.perf_counter() - t0
        r = self._qp.results
        x = np.array(r.x, dtype=float)
        ok = r.info.status == self._solved and np.all(np.isfinite(x))
        tau = float(x[2])
        return StepTimingSolution(
            u=x[0:2].copy(),
            tau=tau,
            duration=float("nan"),  # filled by the front end (needs omega)
            b=x[3:5].copy(),
            slacks=x[5:9].copy(),
            success=bool(ok),
            status=str(r.info.status).split(".")[-1],
            iterations=int(r.info.iter),
            solve_time=dt,
            cost=float(self.weights @ (x - nom) ** 2),
        )


# ----------------------------------------------------------------------------- paper B front end
@dataclass(frozen=True)
class AlipQpParams(AlipStepParams):
    """ALIP-QP parameters on stepping stones: paper B's limits and durations, Khadiv's
    published DcmVrpPlanner weights (u 10, tau 1, b 1000, slacks 1e6).

    With paper B's MPC weights instead (u and b both 1e4/2e4) the one-step QP cannot even
    start walking from standstill: at z^0 = 0 any forward step makes b negative, the QP
    splits the difference and the DCM runs away backwards within 4 steps.

    Attributes:
        T_nom, T_min, T_max: step durations [s].
        limits: kinematic foothold limits [m].
        weights: (u_x, u_y, tau, b_x, b_y, slack x4).
        w: nominal step width [m].
        stone_size: rectangle [m] for stones given without a size.
        replan_period: planner period [s] (used by loops).
        min_time_to_touchdown: the current step lasts at least t + this [s].
        eps_abs: ProxQP tolerance.
        dcm_target: "next" or "current" (see :class:`~lipmpcc.planners.alip_mpc.AlipMpcParams`).
        alip: ALIP constants.
    """

    T_nom: float = 0.5
    T_min: float = 0.35
    T_max: float = 0.65
    limits: KinematicLimits = field(default_factory=KinematicLimits)
    weights: tuple[float, ...] = (10.0, 10.0, 1.0, 1000.0, 1000.0, 1e6, 1e6, 1e6, 1e6)
    w: float = STEP_WIDTH
    stone_size: tuple[float, float] = STONE_SIZE
    replan_period: float = 0.04
    min_time_to_touchdown: float = 0.0
    eps_abs: float = 1e-9
    dcm_target: str = "next"
    alip: AlipParams = field(default_factory=AlipParams)

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        self._check_step_params(positive=("eps_abs",))
        object.__setattr__(self, "weights", _weights("weights", self.weights))
        size = finite_vector("stone_size", self.stone_size, 2, "m", error=ParameterError)
        if min(size) <= 0:
            raise ParameterError("stone_size", self.stone_size, "two finite numbers > 0 (x, y) [m]")

    @classmethod
    def paper(cls, **overrides: object) -> "AlipQpParams":
        """Paper B's limits and durations with Khadiv's reference weights."""
        return replace(cls(), **overrides)


class AlipQp(AlipPlanner):
    """Paper B's ALIP-QP baseline: one-step preview, same contract and API as :class:`AlipMpc`."""

    name = "alip-qp"
    horizon = 1
    stones_needed = 2  # the next stone (bounds, u_nom) and the one after (b_nom)

    def __init__(self, params: AlipQpParams | None = None) -> None:
        p = AlipQpParams.paper() if params is None else params
        if not isinstance(p, AlipQpParams):
            raise ParameterError("params", params, "an AlipQpParams")
        self.params = p
        self._qp = StepTimingQp(p.weights, p.eps_abs)
        # constants of every call, computed once: lambda, exp(lambda T_nom), per swing side the kinematic
        # box and the viable DCM bounds of the following step (swing side -side)
        self._lam = p.lam
        self._sig_nom = math.exp(self._lam * p.T_nom)
        bnd = p.dcm_bounds
        self._kin = {sd: p.limits.box(sd) for sd in (1, -1)}
        self._zb = {sd: (bnd.lower(-sd), bnd.upper(-sd)) for sd in (1, -1)}
        for pair in (*self._kin.values(), *self._zb.values()):
            for a in pair:
                a.flags.writeable = False
        self._last: AlipPlanResult | None = None
        self._stance: np.ndarray | None = None
        self._side: int | None = None
        self._touchdowns_since_ok = 0
        self.failures = 0
        self.solves = 0

    def reset(self) -> None:
        """Forget the previous plan (a new run)."""
        self._last, self._stance, self._side = None, None, None
        self._touchdowns_since_ok = 0
        self.failures = 0
        self.solves = 0

    @exclusive("planner")
    def solve(
        self,
        dcm_world: ArrayLike,
        stance_world: ArrayLike,
        stance_side: int | str,
        t_since_touchdown: float,
        stones: Stones,
    ) -> AlipPlanResult:
        """Same arguments and result as :meth:`AlipMpc.solve` (preview of one step).

        Raises:
            NoFallbackPlanError: the QP failed and there is no plan for this step to fall back on.
        """
        t_start = time.perf_counter()
        prm = self.params
        xi = check_xy("dcm_world", dcm_world)
        st = check_xy("stance_world", stance_world, InvalidInputError)
        side0 = parse_side(stance_side)
        t = check_time_since_touchdown(t_since_touchdown)
        c, s = stone_arrays(stones, prm.stone_size)
        c, s = pad_stones(c, s, 2, st)
        prev = self._stance
        if prev is not None and (side0 != self._side or abs(st[0] - prev[0]) > 1e-9 or abs(st[1] - prev[1]) > 1e-9):
            self._touchdowns_since_ok += 1
        self._stance, self._side = st.copy(), side0
        z0 = (xi - st) * math.exp(-self._lam * t)
        sol = self._qp.solve(z0, *self._qp_data(st, -side0, c, s, t))
        self.solves += 1
        if sol.success and sol.tau >= 1.0:
            res = self._result(sol, st, z0, t)
        else:
            res = self._fallback(sol, z0, t)
        res.plan_time = time.perf_counter() - t_start
        return res

    def _qp_data(self, st: np.ndarray, side: int, c: np.ndarray, s: np.ndarray, t: float) -> tuple:
        """The QP's nominal values and bounds (after z0): u_nom, tau_nom, b_nom, u_lo, u_hi, tau_lo,
        tau_hi, b_lo, b_hi, for a step of the swing foot ``side``."""
        prm = self.params
        lam = self._lam
        u_nom = c[0] - st
        kin_lo, kin_hi = self._kin[int(side)]
        lo = np.maximum(u_nom - 0.5 * s[0], kin_lo)
        hi = np.minimum(u_nom + 0.5 * s[0], kin_hi)
        empty = lo > hi
        if np.any(empty):
            pt = np.clip(u_nom, kin_lo, kin_hi)
            lo, hi = np.where(empty, pt, lo), np.where(empty, pt, hi)
        sig_nom = self._sig_nom
        # b = initial DCM of the following step (swing side -side): eq. (5) with the desired
        # step of that step ("next", stone 2 - stone 1) or of this one ("current")
        u_tgt = c[1] - c[0] if prm.dcm_target == "next" else u_nom
        side_tgt = -side if prm.dcm_target == "next" else side
        W = u_tgt[1] - side_tgt * prm.w
        b_nom = np.array([u_tgt[0] / (sig_nom - 1.0), -side * prm.w / (sig_nom + 1.0) + W / (sig_nom - 1.0)])
        # not before t + min_time_to_touchdown, not after T_max (unless t is already past it)
        t_lo = max(prm.T_min, min(t + prm.min_time_to_touchdown, prm.T_max), t)
        t_hi = max(prm.T_max, t_lo)
        b_lo, b_hi = self._zb[int(side)]
        return u_nom, sig_nom, b_nom, lo, hi, math.exp(lam * t_lo), math.exp(lam * t_hi), b_lo, b_hi

    def _result(self, sol: StepTimingSolution, st: np.ndarray, z0: np.ndarray, t: float) -> AlipPlanResult:
        T = math.log(sol.tau) / self._lam
        f = (st + sol.u).reshape(1, 2)
        res = AlipPlanResult(
            next_foothold=f[0].copy(),
            step_duration=T,
            time_to_touchdown=T - t,
            footholds=f,
            durations=np.array([T]),
            u=sol.u.reshape(1, 2),
            z=sol.b.reshape(1, 2),
            sigma=np.array([sol.tau]),
            z0=z0,
            success=True,
            fallback=False,
            status=sol.status,
            cost=sol.cost,
            iterations=sol.iterations,
            solve_time=sol.solve_time,
            solver="proxqp",
        )
        self._last = res
        self._touchdowns_since_ok = 0
        return res

    def _fallback(self, sol: StepTimingSolution, z0: np.ndarray, t: float) -> AlipPlanResult:
        """The plan of this step held (its duration at least ``t + min_time_to_touchdown``)."""
        self.failures += 1
        if self._last is None or self._touchdowns_since_ok > 0:
            raise NoFallbackPlanError("proxqp", sol.status, sol.iterations, "the ALIP-QP failed and no plan for this step exists")
        last = self._last
        T1 = max(last.step_duration, t + self.params.min_time_to_touchdown)
        return replace(
            last,
            step_duration=T1,
            time_to_touchdown=T1 - t,
            durations=np.array([T1]),
            z0=z0,
            success=False,
            fallback=True,
            status=f"fallback ({sol.status})",
            cost=float("nan"),
            iterations=sol.iterations,
            solve_time=sol.solve_time,
        )


# ----------------------------------------------------------------------------- Khadiv front end
@dataclass(frozen=True)
class DcmVrpParams:
    """Parameters of the original DcmVrpPlanner (Khadiv et al.), in its conventions.

    Attributes:
        l_min, l_max: step length bounds [m].
        w_min, w_max: step width bounds [m] (mirrored for a left stance foot).
        t_min, t_max: step duration bounds [s].
        l_p: default lateral distance between the feet (pelvis width) [m].
        ht: COM height [m] (omega = sqrt(g/ht)).
        weights: (u_x, u_y, tau, b_x, b_y, slack x4).
        t_nom: nominal step duration [s]; None -> (t_min + t_max)/2.
        g: gravity [m/s^2].
    """

    l_min: float
    l_max: float
    w_min: float
    w_max: float
    t_min: float
    t_max: float
    l_p: float
    ht: float
    weights: tuple[float, ...]
    t_nom: float | None = None
    g: float = GRAVITY

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if self.ht <= 0 or self.g <= 0:
            raise ParameterError("ht", self.ht, "a COM height > 0 [m]")
        if self.l_min > self.l_max:
            raise ParameterError("l_min, l_max", (self.l_min, self.l_max), "l_min <= l_max [m]")
        if self.w_min > self.w_max:
            raise ParameterError("w_min, w_max", (self.w_min, self.w_max), "w_min <= w_max [m]")
        if not 0 < self.t_min < self.t_max:
            raise ParameterError("t_min, t_max", (self.t_min, self.t_max), "0 < t_min < t_max [s]")
        if self.t_nom is not None and not (is_finite_number(self.t_nom) and self.t_min <= self.t_nom <= self.t_max):
            raise ParameterError("t_nom", self.t_nom, f"None or a duration in [{self.t_min}, {self.t_max}] [s]")
        object.__setattr__(self, "weights", _weights("weights", self.weights))

    @classmethod
    def reference(cls) -> "DcmVrpParams":
        """The DcmVrpPlanner unit-test set-up: bounds +-0.15 m, T in [0.1, 0.3] s,
        l_p = 0, COM height 0.20 m, weights (10, 10, 1, 1000, 1000, 1e6 x4)."""
        return cls(-0.15, 0.15, -0.15, 0.15, 0.1, 0.3, 0.0, 0.20, (10, 10, 1, 1000, 1000, 1e6, 1e6, 1e6, 1e6))

    @property
    def omega(self) -> float:
        """ω = √(g/ht) [1/s]."""
        return omega(self.ht, self.g)

    @property
    def nominal_time(self) -> float:
        """The nominal step duration [s]."""
        return 0.5 * (self.t_min + self.t_max) if self.t_nom is None else float(self.t_nom)

    @property
    def tau_nom(self) -> float:
        """exp(ω T_nom)."""
        return math.exp(self.omega * self.nominal_time)


@dataclass
class DcmVrpSolution:
    """Result of :func:`dcm_vrp_step`.

    Attributes:
        next_step: next foothold, world frame [m] (x, y).
        duration: step duration from touch-down [s].
        tau: exp(omega T).
        b: DCM offset [m] (local frame).
        slacks: (4,) slacks [m].
        t_nom, tau_nom, l_nom, w_nom, b_nom: nominal values used.
        qp: the raw QP solution.
    """

    next_step: np.ndarray
    duration: float
    tau: float
    b: np.ndarray
    slacks: np.ndarray
    t_nom: float
    tau_nom: float
    l_nom: float
    w_nom: float
    b_nom: np.ndarray
    qp: StepTimingSolution


def dcm_vrp_step(
    params: DcmVrpParams,
    stance_foot: Sequence[float],
    t_since_touchdown: float,
    left_in_contact: bool,
    v_des: Sequence[float],
    com: Sequence[float],
    com_vel: Sequence[float],
    yaw: float = 0.0,
    qp: StepTimingQp | None = None,
) -> DcmVrpSolution:
    """One call of Khadiv's DCM step-timing planner (DcmVrpPlanner conventions).

    Args:
        params: planner parameters.
        stance_foot: current stance foot (x, y[, z]) world [m].
        t_since_touchdown: time since its touch-down [s].
        left_in_contact: True if the left foot is the stance foot.
        v_des: desired (v_x, v_y[, ...]) [m/s], world frame.
        com, com_vel: COM (x, y[, z]) [m] and velocity [m/s], world frame.
        yaw: heading of the local frame [rad].
        qp: reuse a :class:`StepTimingQp` built with ``params.weights``.

    Raises:
        InvalidInputError / StateError: on malformed inputs.
        SolverError: when ProxQP fails (the original planner then returns the nominal step).
    """
    if not isinstance(params, DcmVrpParams):
        raise ParameterError("params", params, "a DcmVrpParams")
    foot = _xy("stance_foot", stance_foot, InvalidInputError)
    c = _xy("com", com, StateError)
    cv = _xy("com_vel", com_vel, StateError)
    vd = _xy("v_des", v_des, InvalidInputError)
    t = check_time_since_touchdown(t_since_touchdown)
    if not isinstance(left_in_contact, (bool, np.bool_)):
        raise InvalidInputError("left_in_contact", left_in_contact, "True or False")
    if not math.isfinite(float(yaw)):
        raise InvalidInputError("yaw", yaw, "a finite angle [rad]")
    om = params.omega
    R = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
    v_loc = R.T @ vd
    nom = _vrp_nominal(params, v_loc, left_in_contact)
    u_lo, u_hi, b_lo, b_hi = _vrp_bounds(params, left_in_contact)
    tau_lo = math.exp(om * max(params.t_min, t))
    tau_hi = max(math.exp(om * params.t_max), tau_lo)
    xi_loc = R.T @ (c + cv / om - foot)
    z0 = xi_loc * math.exp(-om * t)
    solver = qp if qp is not None else StepTimingQp(params.weights)
    sol = solver.solve(z0, nom["u"], nom["tau"], nom["b"], u_lo, u_hi, tau_lo, tau_hi, b_lo, b_hi)
    if not sol.success:
        raise SolverError("proxqp", sol.status, sol.iterations, "DcmVrpPlanner QP")
    sol.duration = math.log(sol.tau) / om
    return DcmVrpSolution(
        next_step=foot + R @ sol.u,
        duration=sol.duration,
        tau=sol.tau,
        b=sol.b,
        slacks=sol.slacks,
        t_nom=nom["t"],
        tau_nom=nom["tau"],
        l_nom=float(nom["u"][0]),
        w_nom=float(nom["u"][1]),
        b_nom=np.array(nom["b"]),
        qp=sol,
    )


def _vrp_nominal(params: DcmVrpParams, v_loc: np.ndarray, left_in_contact: bool) -> dict:
    """DcmVrpPlanner's nominal step (l, w), duration, tau and DCM offset b for the local velocity."""
    t_nom, tau_nom = params.nominal_time, params.tau_nom
    l_nom = v_loc[0] * t_nom
    w_nom = v_loc[1] * t_nom + (-params.l_p if left_in_contact else params.l_p)
    sign = 1.0 if left_in_contact else -1.0  # (-1)^contact_switcher
    bx_nom = l_nom / (tau_nom - 1.0)
    by_nom = sign * params.l_p / (1.0 + tau_nom) - v_loc[1] * t_nom / (1.0 - tau_nom)
    return {"t": t_nom, "tau": tau_nom, "u": (l_nom, w_nom), "b": (bx_nom, by_nom)}


def _vrp_bounds(params: DcmVrpParams, left_in_contact: bool) -> tuple[tuple[float, float], ...]:
    """DcmVrpPlanner's step bounds (u_lo, u_hi) and DCM-offset bounds (b_lo, b_hi), local frame."""
    om = params.omega
    tau_min = math.exp(om * params.t_min)
    bx_lo, bx_hi = params.l_min / (tau_min - 1.0), params.l_max / (tau_min - 1.0)
    den = 1.0 - math.exp(2.0 * om * params.t_min)
    by_in = params.l_p / (1.0 + tau_min) + (params.w_min - params.w_max * tau_min) / den
    by_out = params.l_p / (1.0 + tau_min) + (params.w_max - params.w_min * tau_min) / den
    if left_in_contact:
        w_lo, w_hi = -params.w_max - params.l_p, -params.w_min - params.l_p
        by_lo, by_hi = -by_in, -by_out
    else:
        w_lo, w_hi = params.w_min + params.l_p, params.w_max + params.l_p
        by_lo, by_hi = by_out, by_in
    return (params.l_min, w_lo), (params.l_max, w_hi), (bx_lo, by_lo), (bx_hi, by_hi)


def _xy(name: str, v: Sequence[float], err: type[InvalidInputError]) -> np.ndarray:
    try:
        a = np.asarray(v, dtype=float).ravel()
    except (TypeError, ValueError):
        raise err(name, v, "(x, y) or (x, y, z) finite numbers") from None
    if a.shape not in ((2,), (3,)) or not np.all(np.isfinite(a)):
        raise err(name, v, "(x, y) or (x, y, z) finite numbers")
    return a[:2]
