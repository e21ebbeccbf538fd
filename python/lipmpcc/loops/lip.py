"""Reduced-order closed loop: the 3D-LIP walking under the MPCC (paper A on the LIP).

The planner re-solves at every support exchange. Between exchanges the point mass is
integrated exactly — ẍ = ω²(x − p) + F(t)/m with piecewise-constant push forces F — and
sampled every ``dt_log`` seconds for plots. Pushes act on the point mass, whose mass is
Digit's, 48 kg (:data:`DIGIT_MASS`).

Fall: the point mass "falls" when a step ends with the COM farther than ``MAX_REACH`` from
its stance foot or faster than ``MAX_SPEED``; the run stops there and ``fell``/``fall_step``
are logged.

Error definitions (logged per step k, at the support exchange):

- contouring error: signed distance from the COM to the path at the closest point ϑ_init
  (eq. 19); positive to the right of the path direction (same sign as ē_c);
- lag error: ē_l of the COM with respect to the path parameter the MPC committed to for
  this step in the previous solve, ϑ_1 of step k−1 (it shows whether the robot keeps up
  with its own time parametrisation);
- Cartesian error: ‖C x_k − y_d(ϑ_1 of step k−1)‖.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..contouring import errors as contouring_errors
from ..exceptions import ParameterError, SolverError, StateError
from ..metrics import max_abs, rms, timing_stats_ms
from ..obstacles import Obstacle
from ..planners.mpcc import MpccPlanner, MpccResult

DIGIT_MASS = 48.0  # [kg] Digit's total mass (paper A Fig. 3; the reference MJCF has 47.9 kg)
MAX_REACH = 1.0  # [m] horizontal COM-to-stance-foot distance beyond which the LIP has "fallen"
MAX_SPEED = 3.0  # [m/s] COM speed beyond which the LIP has "fallen"


@dataclass(frozen=True)
class Push:
    """A horizontal force on the point mass.

    Attributes:
        t_start: start time [s].
        duration: duration [s].
        force: (Fx, Fy) [N].
    """

    t_start: float
    duration: float
    force: tuple[float, float]

    def __post_init__(self) -> None:
        if not (math.isfinite(self.t_start) and self.t_start >= 0):
            raise ParameterError("t_start", self.t_start, "a start time >= 0 [s]")
        if not (math.isfinite(self.duration) and self.duration > 0):
            raise ParameterError("duration", self.duration, "a duration > 0 [s]")
        if len(self.force) != 2 or not all(math.isfinite(f) for f in self.force):
            raise ParameterError("force", self.force, "a finite (Fx, Fy) [N]")


def random_pushes(
    t_end: float, rng: np.random.Generator, magnitude: float = 50.0, duration: float = 0.1, max_gap: float = 2.0, t_first: float = 1.0
) -> list[Push]:
    """Paper A's disturbances: forces with magnitude ~ U[−magnitude, magnitude] [N] for
    ``duration`` [s], at random instants at most ``max_gap`` [s] apart. The direction is
    uniform in the horizontal plane."""
    pushes = []
    t = t_first + rng.uniform(0.0, max_gap)
    while t + duration < t_end:
        mag = rng.uniform(-magnitude, magnitude)
        ang = rng.uniform(0.0, 2 * math.pi)
        pushes.append(Push(float(t), duration, (mag * math.cos(ang), mag * math.sin(ang))))
        t += duration + rng.uniform(0.0, max_gap - duration)
    return pushes


@dataclass
class LipLog:
    """Everything the plots of paper A Figs. 5–6 need.

    Per step k (support exchange):
        t: (n+1,) times [s]; states: (n+1, 5) LIP states; footholds: (n, 3) world [x, y, heading];
        sides: (n,) stance side; theta_init: (n,) [m]; theta_plan: (n,) ϑ_1 of each solve [m];
        v_avg: (n,) (1/N) Σ v [m]; v_max [m]; e_contouring, e_lag, e_cartesian: (n+1,) [m];
        solve_time: (n,) [s]; status: list[str]; fallback: (n,) bool; plans: list[MpccResult].
    Continuous (every dt_log):
        tc: (m,) [s]; com: (m, 4) [x, ẋ, y, ẏ]; obstacles: (n_obs, m, 2) centres [m];
        clearance: (m,) min clearance of the robot footprint [m].
    """

    t: np.ndarray
    states: np.ndarray
    footholds: np.ndarray
    sides: np.ndarray
    theta_init: np.ndarray
    theta_plan: np.ndarray
    v_avg: np.ndarray
    v_max: float
    e_contouring: np.ndarray
    e_lag: np.ndarray
    e_cartesian: np.ndarray
    solve_time: np.ndarray
    status: list[str]
    fallback: np.ndarray
    tc: np.ndarray
    com: np.ndarray
    obstacles: np.ndarray
    clearance: np.ndarray
    pushes: list[Push] = field(default_factory=list)
    plans: list[MpccResult] = field(default_factory=list)
    path_length: float = 0.0
    theta_final: float = 0.0
    stopped_reason: str = ""
    fell: bool = False
    fall_step: int | None = None

    @property
    def steps(self) -> int:
        return len(self.footholds)


def _integrate_step(x0: np.ndarray, foot: np.ndarray, T: float, omega: float, t0: float, pushes: Sequence[Push], mass: float, dt: float):
    """Exact LIP motion over one step with piecewise-constant pushes.

    Returns (end state [x, ẋ, y, ẏ], sample times (m,), samples (m, 4)).
    """
    # breakpoints: regular samples plus push edges
    edges = {t0, t0 + T}
    for pu in pushes:
        for te in (pu.t_start, pu.t_start + pu.duration):
            if t0 < te < t0 + T:
                edges.add(te)
    nreg = max(1, int(round(T / dt)))
    for i in range(1, nreg):
        edges.add(t0 + i * T / nreg)
    ts = sorted(edges)
    state = np.array(x0[:4], dtype=float)
    out_t = [t0]
    out_x = [state.copy()]
    for ta, tb in zip(ts[:-1], ts[1:]):
        tm = 0.5 * (ta + tb)
        F = np.zeros(2)
        for pu in pushes:
            if pu.t_start <= tm < pu.t_start + pu.duration:
                F += pu.force
        h = tb - ta
        ch, sh = math.cosh(omega * h), math.sinh(omega * h)
        for i, (pi, vi) in enumerate(((0, 1), (2, 3))):
            p_eff = foot[i] - F[i] / (mass * omega**2)
            r0 = state[pi] - p_eff
            v0 = state[vi]
            state[pi] = p_eff + r0 * ch + v0 * sh / omega
            state[vi] = r0 * omega * sh + v0 * ch
        out_t.append(tb)
        out_x.append(state.copy())
    return state, np.array(out_t), np.array(out_x)


def simulate(
    planner: MpccPlanner,
    x0: np.ndarray,
    n_steps: int,
    obstacles: Sequence[Obstacle] = (),
    pushes: Sequence[Push] = (),
    first_side: int = 1,
    mass: float = DIGIT_MASS,
    dt_log: float = 0.02,
    stop_at_end: bool = True,
) -> LipLog:
    """Walk the 3D-LIP for ``n_steps`` steps under ``planner``.

    Args:
        planner: an :class:`MpccPlanner` (its path is the reference).
        x0: initial LIP state [x, ẋ, y, ẏ, heading].
        n_steps: number of steps.
        obstacles: moving obstacles (their clocks start at t = 0).
        pushes: forces on the point mass.
        first_side: side of the first stance foot (+1 left, −1 right).
        mass: point mass for the pushes [kg].
        dt_log: sampling of the continuous COM trajectory [s].
        stop_at_end: stop once the path parameter reaches the end of the path.

    Returns:
        :class:`LipLog`.

    Raises:
        NoFallbackPlanError: the very first solve failed.
    """
    x = np.asarray(x0, dtype=float)
    if x.shape != (5,) or not np.all(np.isfinite(x)):
        raise StateError("x0", x0, "a finite 5-vector [x, xdot, y, ydot, heading]")
    if not isinstance(n_steps, (int, np.integer)) or n_steps < 1:
        raise ParameterError("n_steps", n_steps, "an integer >= 1")
    if first_side not in (1, -1):
        raise ParameterError("first_side", first_side, "+1 (left) or -1 (right)")
    if not (math.isfinite(mass) and mass > 0):
        raise ParameterError("mass", mass, "a mass > 0 [kg]")
    path = planner.path
    prm = planner.params
    T, omega = prm.model.T, prm.model.omega
    obstacles = list(obstacles)
    pushes = list(pushes)
    side = first_side
    t = 0.0
    ts, states, feet, sides = [0.0], [x.copy()], [], []
    th_init, th_plan, vavg, stimes, status, fb, plans = [], [], [], [], [], [], []
    tc, com = [], []
    reason = "steps"
    fell_at: int | None = None
    for k in range(int(n_steps)):
        res = planner.solve(x, side, obstacles, t_now=t)
        plans.append(res)
        th_init.append(res.theta_init)
        th_plan.append(res.theta[1])
        vavg.append(res.v_avg)
        stimes.append(res.solve_time)
        status.append(res.status)
        fb.append(res.used_fallback)
        u = res.u0
        foot = np.array([x[0] + u[0], x[2] + u[1]])
        feet.append([foot[0], foot[1], x[4] + u[2]])
        sides.append(side)
        end, tt, xx = _integrate_step(x, foot, T, omega, t, pushes, mass, dt_log)
        if k == 0:
            tc.append(tt)
            com.append(xx)
        else:
            tc.append(tt[1:])
            com.append(xx[1:])
        x = np.array([end[0], end[1], end[2], end[3], x[4] + u[2]])
        if not np.all(np.isfinite(x)):
            raise SolverError("lip-sim", "non-finite state", k)
        # a "fall" of the point mass: it ends a step farther from its stance foot than a leg
        # reaches, or faster than a biped walks
        if np.hypot(x[0] - foot[0], x[2] - foot[1]) > MAX_REACH or np.hypot(x[1], x[3]) > MAX_SPEED:
            fell_at = k
        t += T
        side = -side
        ts.append(t)
        states.append(x.copy())
        if fell_at is not None:
            reason = "fell"
            break
        if stop_at_end and res.theta[1] >= path.length - 1e-6:
            reason = "end of path"
            break
    states_a = np.array(states)
    t_a = np.array(ts)
    feet_a = np.array(feet)
    tc_a = np.concatenate(tc)
    com_a = np.concatenate(com)
    # errors at the step instants
    pos = states_a[:, [0, 2]]
    th_c = np.array([path.closest_point(p, th_init[min(i, len(th_init) - 1)] if i else None) for i, p in enumerate(pos)])
    e_meas = contouring_errors(pos, path.position(th_c), path.slope(th_c))
    th_ref = np.concatenate([[th_init[0]], th_plan])
    e_ref = contouring_errors(pos, path.position(th_ref), path.slope(th_ref))
    e_cart = np.linalg.norm(pos - path.position(th_ref), axis=1)
    # obstacles and clearance along the continuous trajectory (body disk + stance feet)
    n_obs = len(obstacles)
    obs_c = np.zeros((n_obs, len(tc_a), 2))
    clearance = np.full(len(tc_a), np.inf)
    step_idx = np.clip(np.searchsorted(t_a, tc_a, side="right") - 1, 0, len(feet_a) - 1)
    for j, ob in enumerate(obstacles):
        obs_c[j] = np.atleast_2d(ob.center(tc_a))
        body = ob.clearance(com_a[:, [0, 2]], tc_a, prm.robot_radius)
        foot = ob.clearance(feet_a[step_idx, :2], tc_a, prm.foot_radius)
        clearance = np.minimum(clearance, np.minimum(body, foot))
    return LipLog(
        t=t_a,
        states=states_a,
        footholds=feet_a,
        sides=np.array(sides),
        theta_init=np.array(th_init),
        theta_plan=np.array(th_plan),
        v_avg=np.array(vavg),
        v_max=prm.v_max,
        e_contouring=e_meas[:, 0],
        e_lag=e_ref[:, 1],
        e_cartesian=e_cart,
        solve_time=np.array(stimes),
        status=status,
        fallback=np.array(fb, dtype=bool),
        tc=tc_a,
        com=com_a,
        obstacles=obs_c,
        clearance=clearance,
        pushes=pushes,
        plans=plans,
        path_length=path.length,
        theta_final=float(th_c[-1]),
        stopped_reason=reason,
        fell=fell_at is not None,
        fall_step=fell_at,
    )


def summarize(log: LipLog, obstacles: Sequence[Obstacle] = (), settle_time: float = 0.0) -> dict:
    """The summary.json metrics of a LIP run (issue contract names).

    Args:
        log: the run.
        obstacles: the run's obstacles (for ``overtook``).
        settle_time: errors are evaluated after this time [s] (the start-up transient).
    """
    after = log.t >= settle_time
    ec = log.e_contouring[after]
    el = log.e_lag[after]
    eca = log.e_cartesian[after]
    progress = float(log.theta_final)
    # overtaken: at the end, the robot's footprint is entirely ahead of every obstacle along the path
    overtook = False
    if len(obstacles):
        end_t = log.t[-1]
        overtook = all(
            ob.path is not None and progress > ob.s0 + ob.speed * end_t + max(ob.axes) + 0.2 for ob in obstacles
        )
    return {
        "push_recovery_s": push_recovery_times(log, 0.05),
        "steps": int(log.steps),
        "fell": bool(log.fell),
        "fall_step": log.fall_step,
        "solver_failures": int(np.sum(log.fallback)),
        "solve_ms": timing_stats_ms(log.solve_time),
        "contouring_error_max_m": max_abs(ec),
        "contouring_error_rms_m": rms(ec),
        "lag_error_rms_m": rms(el),
        "cartesian_error_max_m": max_abs(eca),
        "min_clearance_m": float(np.min(log.clearance)) if len(obstacles) else None,
        "overtook": bool(overtook),
        "progress_m": progress,
        "v_avg_mean": float(np.mean(log.v_avg)),
        "v_max": log.v_max,
        "duration_s": float(log.t[-1]),
        "error_settle_time_s": settle_time,
        "stopped_reason": log.stopped_reason,
    }


def push_recovery_times(log: LipLog, bound: float = 0.05) -> list[float]:
    """For each push, the time from its end to the first step instant at which the
    |contouring error| is below ``bound`` [m] (0 when it is already below; NaN when it never
    comes back before the end of the run). [s]"""
    out = []
    e = np.abs(log.e_contouring)
    for pu in log.pushes:
        t_end = pu.t_start + pu.duration
        idx = np.flatnonzero((log.t >= t_end) & (e < bound))
        if not np.any(log.t >= t_end):
            continue
        out.append(float(log.t[idx[0]] - t_end) if idx.size else float("nan"))
    return out
