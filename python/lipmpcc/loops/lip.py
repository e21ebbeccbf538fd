"""Reduced-order closed loop: the 3D-LIP walking under a footstep planner (paper A on the LIP).

Any planner of the contract (:mod:`lipmpcc.planners.base`) drives it; :func:`simulate` runs paper A's
MPCC (:class:`~lipmpcc.planners.mpcc.MpccPlanner`), :func:`run_lip_loop` any planner.

**The planner call.** The point foot swings in no time, so the loop calls the planner once per step,
at each support exchange (paper A re-plans once per step), with a :class:`~lipmpcc.planners.base.PlannerInput`
built from the LIP state ``x = [x, ẋ, y, ẏ, θ]``: the COM at ``(x, y, H)`` with velocity ``(ẋ, ẏ, 0)``,
the DCM, ``torso_yaw = θ``; the stance foot is the one the mass pivoted on during the step that ends
(at the start: a foot under the initial COM), touched down ``time_since_touchdown`` ago (the length of
that step; 0 at the start); the swing foot, on the side opposite, lands now: the plan's foothold and
yaw place it (the new heading is the plan's yaw), and the plan's duration is how long the LIP then
pivots on it. The course is the path, when there is one, and the obstacles are passed on.

**Integration.** Between exchanges the point mass is integrated exactly — ẍ = ω²(x − p) + F(t)/m with
piecewise-constant push forces F (:class:`lipmpcc.push.Push`; a push with a ``step`` acts after the
exchange that starts that step) — and sampled every ``dt_log`` seconds for plots. Pushes act on the
point mass, whose mass is Digit's, 48 kg (:data:`DIGIT_MASS`).

**Fall.** The point mass "falls" when a step ends with the COM farther than ``MAX_REACH`` from its stance
foot or faster than ``MAX_SPEED``; the run stops there and ``fell``/``fall_step`` are logged.

**Errors** (logged per step k, at the support exchange, when the loop has a path):

- contouring error: signed distance from the COM to the path at the closest point ϑ_init
  (eq. 19); positive to the right of the path direction (same sign as ē_c);
- lag error: ē_l of the COM with respect to the path parameter the MPC committed to for
  this step in the previous solve, ϑ_1 of step k−1 (it shows whether the robot keeps up
  with its own time parametrisation);
- Cartesian error: ‖C x_k − y_d(ϑ_1 of step k−1)‖.

The MPCC's own fields (ϑ_init, ϑ_1, v̄, the solver status, the plans) come from each plan's ``record``
when it follows the :class:`~lipmpcc.loops.base.PathProgress` protocol (paper A's MPCC, timed or not);
for another planner they are NaN (and the lag and Cartesian errors with them) or empty. ``v_max`` is
the planner's ``params.v_max`` (or ``params.mpcc.v_max``), NaN when it has none.

**The run contract** (:mod:`lipmpcc.loops.base`): the loop takes a :class:`~lipmpcc.loops.base.Course`
and a :class:`~lipmpcc.loops.base.PushSchedule` (or the older ``path``, ``obstacles``, ``pushes``) and
its log carries a :class:`~lipmpcc.loops.base.RunRecord` (``LipLog.record``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
import numbers
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..contouring import errors as contouring_errors
from ..conventions import GRAVITY, Side, parse_side
from ..exceptions import InvalidInputError, NoFallbackPlanError, ParameterError, SolverError, StateError
from ..metrics import max_abs, rms, timing_stats_ms
from ..models.lip import dcm, lip_solution, omega
from ..obstacles import Obstacle
from ..paths import Path
from ..planners.base import FootstepSource, PlannerInput, StepPlan
from ..push import Push
from ..validation import count, finite_array, flag, non_negative_number, number_in, positive_number
from .base import Course, PathProgress, PushSchedule, RunRecord, has_path_progress, resolve_course, resolve_schedule
from .progress import step_bar

if TYPE_CHECKING:
    from ..planners.mpcc import MpccPlanner

__all__ = [
    "DIGIT_MASS",
    "MAX_REACH",
    "MAX_SPEED",
    "LipLog",
    "run_lip_loop",
    "simulate",
    "summarize",
    "duration_stats",
    "push_recovery_times",
    "random_pushes",
    "MAX_STEPS",
    "planner_v_max",
]

DIGIT_MASS = 48.0  # [kg] Digit's total mass (paper A Fig. 3; the reference MJCF has 47.9 kg)
MAX_REACH = 1.0  # [m] horizontal COM-to-stance-foot distance beyond which the LIP has "fallen"
MAX_SPEED = 3.0  # [m/s] COM speed beyond which the LIP has "fallen"


def random_pushes(
    t_end: float, rng: np.random.Generator, magnitude: float = 50.0, duration: float = 0.1, max_gap: float = 2.0, t_first: float = 1.0
) -> list[Push]:
    """Paper A's disturbances: forces with magnitude ~ U[−magnitude, magnitude] [N] for
    ``duration`` [s], at random instants at most ``max_gap`` [s] apart. The direction is
    uniform in the horizontal plane."""
    non_negative_number("t_end", t_end, "s", error=ParameterError)
    if not isinstance(rng, np.random.Generator):
        raise ParameterError("rng", rng, "a numpy.random.Generator (numpy.random.default_rng(seed))")
    non_negative_number("magnitude", magnitude, "N", error=ParameterError)
    positive_number("duration", duration, "s", error=ParameterError)
    number_in("max_gap", max_gap, duration, None, "s", error=ParameterError)
    non_negative_number("t_first", t_first, "s", error=ParameterError)
    pushes = []
    t = t_first + rng.uniform(0.0, max_gap)
    while t + duration < t_end:
        mag = rng.uniform(-magnitude, magnitude)
        ang = rng.uniform(0.0, 2 * math.pi)
        pushes.append(Push((mag * math.cos(ang), mag * math.sin(ang)), float(t), duration))
        t += duration + rng.uniform(0.0, max_gap - duration)
    return pushes


@dataclass
class LipLog:
    """Everything the plots of paper A Figs. 5–6 need.

    Per step k (support exchange):
        t: (n+1,) times [s]; states: (n+1, 5) LIP states; footholds: (n, 3) world [x, y, heading];
        sides: (n,) side of the foot placed (+1 left, −1 right); theta_init: (n,) [m];
        theta_plan: (n,) ϑ_1 of each solve [m]; theta_closest: (n+1,) the closest path parameter of each
        state (the run's progress; its last is ``theta_final``) [m]; v_avg: (n,) (1/N) Σ v [m]; v_max [m];
        e_contouring, e_lag, e_cartesian: (n+1,) [m]; solve_time: (n,) [s]; status: list[str];
        fallback: (n,) bool (the plan's status was not "ok"); plans: list of the records that follow
        :class:`~lipmpcc.loops.base.PathProgress` (:class:`~lipmpcc.planners.mpcc.MpccResult`);
        planned_durations: (n,) each plan's step duration [s] (the loop executes it: ``diff(t)``).
    Re-planned within steps (``replan_hz``): replan_solve_time: every solve's time [s]; replan_failures:
        solves whose status was not "ok". Step k's records are then those of its last plan, which set
        when step k ended and where step k+1's foot landed; ``footholds[0]`` is the starting stance foot.
    Continuous (every dt_log):
        tc: (m,) [s]; com: (m, 4) [x, ẋ, y, ẏ]; obstacles: (n_obs, m, 2) centres [m];
        clearance: (m,) min clearance of the robot footprint [m].
    The run contract: record: the :class:`~lipmpcc.loops.base.RunRecord` (footholds placed where planned,
        durations executed as planned).
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
    plans: list[PathProgress] = field(default_factory=list)
    path_length: float = 0.0
    theta_final: float = 0.0
    stopped_reason: str = ""
    fell: bool = False
    fall_step: int | None = None
    planned_durations: np.ndarray = field(default_factory=lambda: np.zeros(0))
    replan_solve_time: np.ndarray = field(default_factory=lambda: np.zeros(0))
    replan_failures: int = 0
    theta_closest: np.ndarray = field(default_factory=lambda: np.zeros(0))
    record: RunRecord | None = None

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        return len(self.footholds)


def _integrate_step(
    x0: np.ndarray, foot: np.ndarray, T: float, omega: float, t0: float, pushes: Sequence[Push], mass: float, dt: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact LIP motion over one step with piecewise-constant pushes (absolute times).

    Returns (end state [x, ẋ, y, ẏ], sample times (m,), samples (m, 4)).
    """
    # breakpoints: regular samples plus push edges
    edges = {t0, t0 + T}
    for pu in pushes:
        for te in (pu.t_start, pu.t_end):
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
            if pu.active(tm):
                F += pu.force_xy
        # a constant force shifts the pivot by −F/(m ω²)
        p_eff = foot - F / (mass * omega**2)
        c, v, _ = lip_solution(state[[0, 2]], state[[1, 3]], p_eff, omega, tb - ta, check=False)  # our own arrays
        state = np.array([c[0], v[0], c[1], v[1]])
        out_t.append(tb)
        out_x.append(state.copy())
    return state, np.array(out_t), np.array(out_x)


@dataclass
class _StepRecords:
    """Per-step records of a run (lists, one entry per step)."""

    feet: list[list[float]] = field(default_factory=list)
    sides: list[int] = field(default_factory=list)
    th_init: list[float] = field(default_factory=list)
    th_plan: list[float] = field(default_factory=list)
    v_avg: list[float] = field(default_factory=list)
    solve_time: list[float] = field(default_factory=list)
    status: list[str] = field(default_factory=list)
    fallback: list[bool] = field(default_factory=list)
    plans: list[PathProgress] = field(default_factory=list)
    durations: list[float] = field(default_factory=list)
    calls: list[tuple[float, int, StepPlan]] = field(default_factory=list)

    def add(self, plan: StepPlan, side: Side, foothold: np.ndarray | None = None, duration: float | None = None) -> None:
        """Record the plan of a step whose new foot is on ``side`` (re-planned within steps: the step's
        ``foothold`` [x, y, yaw] and executed ``duration`` [s], which its last plan did not choose)."""
        rec = plan.record
        mpcc = has_path_progress(rec)
        if mpcc:
            self.plans.append(rec)
        self.th_init.append(rec.theta_init if mpcc else math.nan)
        self.th_plan.append(rec.theta[1] if mpcc else math.nan)
        self.v_avg.append(rec.v_avg if mpcc else math.nan)
        self.solve_time.append(plan.solve_time)
        self.status.append(rec.status if mpcc else plan.status)
        self.fallback.append(not plan.ok)
        self.feet.append([plan.foothold[0], plan.foothold[1], plan.yaw] if foothold is None else list(foothold))
        self.sides.append(side.sign)
        self.durations.append(float(plan.duration if duration is None else duration))


class _LipRun:
    """One run of the LIP loop: the state, the pushes, the records, and its steps as methods."""

    def __init__(self, planner: FootstepSource, x0: np.ndarray, side: Side, course: Course, schedule: PushSchedule,
                 com_height: float, omega: float, mass: float, dt_log: float) -> None:
        self.planner = planner
        self.x = x0.copy()
        self.side = side  # side of the foot placed at the next exchange
        self.course, self.schedule = course, schedule
        self.path, self.obstacles = course.path, list(course.obstacles)
        self.absolute = list(schedule.absolute)  # pushes with absolute windows (the armed ones join them)
        self.H, self.omega, self.mass, self.dt_log = com_height, omega, mass, dt_log
        self.t = 0.0
        self.t_stance = 0.0  # when the stance foot touched down
        self.stance = np.array([x0[0], x0[2], x0[4]])  # at the start: under the COM
        self.swing = self.stance.copy()
        self.ts, self.states = [0.0], [self.x.copy()]
        self.rec = _StepRecords()
        self.tc: list[np.ndarray] = []
        self.com: list[np.ndarray] = []
        self.replan_times: list[float] = []
        self.replan_failures = 0

    def planner_input(self, k: int) -> PlannerInput:
        """What the planner is given at the exchange that starts step ``k``."""
        x = self.x
        pos, vel = np.array([x[0], x[2]]), np.array([x[1], x[3]])
        return PlannerInput(
            t=self.t,
            com_pos=np.array([x[0], x[2], self.H]),
            com_vel=np.array([x[1], x[3], 0.0]),
            dcm=dcm(pos, vel, self.omega),
            omega=self.omega,
            stance_side=self.side.other,
            stance_pos=np.array([self.stance[0], self.stance[1], 0.0]),
            stance_yaw=float(self.stance[2]),
            swing_pos=np.array([self.swing[0], self.swing[1], 0.0]),
            swing_yaw=float(self.swing[2]),
            time_since_touchdown=self.t - self.t_stance,
            step_index=k,
            torso_yaw=float(x[4]),
            angular_momentum=np.zeros(3),
            mass=self.mass,
            course=self.course.planner_course(k),
            obstacles=self.course.obstacles,
        )

    def _arm_pushes(self, k: int) -> None:
        """The pushes timed from the touch-down that starts step ``k``, made absolute (from now)."""
        self.absolute.extend(self.schedule.arm(k, self.t))

    def _ask(self, k: int) -> StepPlan:
        """The planner's answer at the time now, for step ``k`` (recorded for the run record)."""
        plan = self.planner.plan(self.planner_input(k))
        if not isinstance(plan, StepPlan):
            raise StateError("planner output", plan, "a StepPlan")
        self.rec.calls.append((self.t, k, plan))
        return plan

    def _fell(self, foot: np.ndarray) -> bool:
        """A "fall" of the point mass: it ends a step farther from its stance ``foot`` than a leg reaches,
        or faster than a biped walks."""
        x = self.x
        return bool(np.hypot(x[0] - foot[0], x[2] - foot[1]) > MAX_REACH or np.hypot(x[1], x[3]) > MAX_SPEED)

    def step(self, k: int) -> tuple[StepPlan, bool]:
        """Plan step ``k``, place the foot, integrate the LIP over the step; returns the plan and
        whether the point mass fell."""
        self._arm_pushes(k)
        plan = self._ask(k)
        self.rec.add(plan, self.side)
        foot = np.array([plan.foothold[0], plan.foothold[1]])
        end, tt, xx = _integrate_step(self.x, foot, plan.duration, self.omega, self.t, self.absolute, self.mass, self.dt_log)
        self.tc.append(tt if k == 0 else tt[1:])
        self.com.append(xx if k == 0 else xx[1:])
        self.x = np.array([end[0], end[1], end[2], end[3], plan.yaw])
        if not np.all(np.isfinite(self.x)):
            raise SolverError("lip-sim", "non-finite state", k)
        fell = self._fell(foot)
        self.swing, self.stance = self.stance, np.array(self.rec.feet[-1])
        self.t_stance = self.t
        self.t += plan.duration
        self.side = self.side.other
        self.ts.append(self.t)
        self.states.append(self.x.copy())
        return plan, fell


    def _advance(self, foot: np.ndarray, h: float) -> None:
        """Integrate the LIP for ``h`` [s] about ``foot`` (with the pushes), logging the samples."""
        end, tt, xx = _integrate_step(self.x, foot, h, self.omega, self.t, self.absolute, self.mass, self.dt_log)
        first = not self.tc
        self.tc.append(tt if first else tt[1:])
        self.com.append(xx if first else xx[1:])
        self.x = np.array([end[0], end[1], end[2], end[3], self.x[4]])
        self.t = float(tt[-1])
        if not np.all(np.isfinite(self.x)):
            raise SolverError("lip-sim", "non-finite state", len(self.rec.feet))

    def step_within(self, k: int, period: float) -> tuple[StepPlan, bool]:
        """Stance ``k`` re-planned every ``period`` [s] (paper B's within-step loop): each plan sets when
        the stance ends (``duration`` from its touch-down) and where the next foot lands; the foot lands
        when and where the last plan said. Returns the last plan and whether the point mass fell."""
        self._arm_pushes(k)
        foot, t_td, tol, first = self.stance.copy(), self.t, 1e-9, None
        while True:
            plan = self._ask(k)
            first = plan if first is None else first
            self.replan_times.append(plan.solve_time)
            self.replan_failures += int(not plan.ok)
            remaining = t_done = t_td + plan.duration - self.t
            if remaining > tol:
                t_done = min(period, remaining)
                self._advance(foot[:2], t_done)
            if t_done >= remaining - tol:
                break
        self.rec.add(plan, self.side.other, foothold=foot, duration=self.t - t_td)
        if has_path_progress(plan.record):  # ϑ at this stance's touch-down and (planned) at its end
            self.rec.th_init[-1] = float(getattr(first.record, "theta_now", first.record.theta_init))
            self.rec.th_plan[-1] = float(plan.record.theta[0])
        fell = self._fell(foot)
        self.swing, self.stance = self.stance, np.array([plan.foothold[0], plan.foothold[1], plan.yaw])
        self.x[4] = plan.yaw
        self.t_stance = self.t
        self.side = self.side.other
        self.ts.append(self.t)
        self.states.append(self.x.copy())
        return plan, fell


def _path_errors(path: Path | None, pos: np.ndarray, th_init: np.ndarray, th_plan: np.ndarray) -> tuple[np.ndarray, ...]:
    """(contouring error (n+1,), lag error (n+1,), Cartesian error (n+1,), ϑ of the last state, ϑ of every
    state (n+1,)) [m]: ϑ is the closest path parameter, each searched around the previous exchange's."""
    nan = np.full(len(pos), np.nan)
    if path is None:
        return nan, nan, nan, math.nan, nan
    hints = [None] + [th_init[min(i, len(th_init) - 1)] for i in range(1, len(pos))]
    th_c = np.array([path.closest_point(p, h if h is not None and math.isfinite(h) else None) for p, h in zip(pos, hints)])
    e_meas = contouring_errors(pos, path.position(th_c), path.slope(th_c))
    th_ref = np.concatenate([[th_init[0]], th_plan])
    if not np.all(np.isfinite(th_ref)):  # no committed path parameter (not an MPCC)
        return e_meas[:, 0], nan, nan, float(th_c[-1]), th_c
    e_ref = contouring_errors(pos, path.position(th_ref), path.slope(th_ref))
    e_cart = np.linalg.norm(pos - path.position(th_ref), axis=1)
    return e_meas[:, 0], e_ref[:, 1], e_cart, float(th_c[-1]), th_c


def _clearance(obstacles: Sequence[Obstacle], t: np.ndarray, tc: np.ndarray, com: np.ndarray, feet: np.ndarray,
               robot_radius: float, foot_radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Obstacle centres (n_obs, m, 2) and the least clearance (m,) of the body disk and the stance foot [m]."""
    obs_c = np.zeros((len(obstacles), len(tc), 2))
    clearance = np.full(len(tc), np.inf)
    step_idx = np.clip(np.searchsorted(t, tc, side="right") - 1, 0, len(feet) - 1)
    for j, ob in enumerate(obstacles):
        obs_c[j] = np.atleast_2d(ob.center(tc))
        body = ob.clearance(com[:, [0, 2]], tc, robot_radius)
        foot = ob.clearance(feet[step_idx, :2], tc, foot_radius)
        clearance = np.minimum(clearance, np.minimum(body, foot))
    return obs_c, clearance


#: Most steps a reduced-model run accepts (about an hour of LIP/ALIP loop on one core).
MAX_STEPS = 100_000


def _check_run(x0: np.ndarray, n_steps: int, first_side: Side | int | str, mass: float) -> tuple[np.ndarray, Side]:
    x = finite_array("x0", x0, (5,), error=StateError, what="a finite 5-vector [x, xdot, y, ydot, heading]")
    count("n_steps", n_steps, 1, MAX_STEPS, error=ParameterError)
    try:
        side = parse_side(first_side)
    except InvalidInputError:
        raise ParameterError("first_side", first_side, "+1 / 'left' or -1 / 'right'") from None
    positive_number("mass", mass, "kg", error=ParameterError)
    return x, side


def _check_world(path: Path | None, obstacles: Sequence[Obstacle], pushes: Sequence[Push]) -> tuple[list, list]:
    """The course of a run as lists, each item checked (ParameterError naming a bad one)."""
    if path is not None and not isinstance(path, Path):
        raise ParameterError("path", path, "a lipmpcc.paths.Path or None")
    out = []
    for name, items, cls in (("obstacles", obstacles, Obstacle), ("pushes", pushes, Push)):
        if isinstance(items, (str, bytes, cls)) or not hasattr(items, "__iter__"):
            raise ParameterError(name, items, f"a list of {cls.__module__}.{cls.__name__}")
        items = list(items)
        for i, it in enumerate(items):
            if not isinstance(it, cls):
                raise ParameterError(f"{name}[{i}]", it, f"a {cls.__module__}.{cls.__name__}")
        out.append(items)
    return out[0], out[1]


def _check_settings(com_height: float, gravity: float, dt_log: float, stop_at_end: bool, robot_radius: float,
                    foot_radius: float) -> None:
    """ParameterError naming a setting of :func:`run_lip_loop` of the wrong type or sign."""
    positive_number("com_height", com_height, "m", error=ParameterError)
    positive_number("gravity", gravity, "m/s^2", error=ParameterError)
    positive_number("dt_log", dt_log, "s", error=ParameterError)
    flag("stop_at_end", stop_at_end, error=ParameterError)
    non_negative_number("robot_radius", robot_radius, "m", error=ParameterError)
    non_negative_number("foot_radius", foot_radius, "m", error=ParameterError)


def run_lip_loop(
    planner: FootstepSource,
    x0: np.ndarray,
    n_steps: int,
    path: Path | None = None,
    obstacles: Sequence[Obstacle] = (),
    pushes: Sequence[Push] = (),
    first_side: Side | int | str = Side.LEFT,
    com_height: float = 0.9,
    gravity: float = GRAVITY,
    mass: float = DIGIT_MASS,
    dt_log: float = 0.02,
    stop_at_end: bool = True,
    robot_radius: float = 0.2,
    foot_radius: float = 0.1,
    progress: bool | None = None,
    replan_hz: float | None = None,
    course: Course | None = None,
    schedule: PushSchedule | None = None,
) -> LipLog:
    """Walk the 3D-LIP for ``n_steps`` steps under any footstep planner (reset first).

    Args:
        planner: a :class:`~lipmpcc.planners.base.FootstepSource`.
        x0: initial LIP state [x, ẋ, y, ẏ, heading].
        n_steps: number of steps.
        path: the path followed (the planner's course and the errors' reference), or None.
        obstacles: moving obstacles (their clocks start at t = 0), passed to the planner.
        pushes: forces on the point mass.
        first_side: side of the first foot placed (+1 / "left", −1 / "right").
        com_height, gravity: the LIP's H [m] and g [m/s²] (ω = √(g/H)).
        mass: point mass for the pushes [kg].
        dt_log: sampling of the continuous COM trajectory [s].
        stop_at_end: stop once the planned path parameter (an MPCC's ϑ_1) reaches the end of the path.
        robot_radius, foot_radius: the body and stance-foot disks of the clearance [m].
        progress: a progress bar of the steps on stderr (None: only on a terminal; False: never).
        replan_hz: re-plan within each step at this rate [Hz] (paper B's loop; a planner built to be
            called within steps, e.g. ``TimedMpccPlanner(..., within_step=True)``): the walk starts on a
            stance foot under the COM, every plan sets when the stance ends and where the next foot
            lands. None (default): one plan per step, at the exchange, the foot placed there.
        course: the run's :class:`~lipmpcc.loops.base.Course` (its path and obstacles), instead of ``path``
            and ``obstacles``.
        schedule: the run's :class:`~lipmpcc.loops.base.PushSchedule`, instead of ``pushes``.

    Returns:
        :class:`LipLog`.

    Raises:
        NoFallbackPlanError: the very first plan failed.
        InvalidInputError: both ``course`` and ``path``/``obstacles``, or both ``schedule`` and ``pushes``.
    """
    x, side = _check_run(x0, n_steps, first_side, mass)
    if not isinstance(planner, FootstepSource):
        raise InvalidInputError("planner", planner, "a FootstepSource (name, rate_hz, reset(), plan(inp))")
    obstacles, pushes = _check_world(path, obstacles, pushes)
    run_course, run_schedule = resolve_course(course, path, obstacles), resolve_schedule(schedule, pushes)
    _check_settings(com_height, gravity, dt_log, stop_at_end, robot_radius, foot_radius)
    period = _replan_period(planner, replan_hz)
    planner.reset()
    run = _LipRun(planner, x, side if period is None else side.other, run_course, run_schedule, com_height,
                  omega(com_height, gravity), mass, dt_log)
    with step_bar(int(n_steps), "LIP", progress) as bar:
        reason, fell_at = _walk(run, planner, run_course.path, int(n_steps), stop_at_end, bar, period)
    return _make_log(run, reason, fell_at, planner_v_max(planner), robot_radius, foot_radius)


def planner_v_max(planner: object) -> float:
    """The planner's largest path progress per step [m]: ``params.v_max`` or ``params.mpcc.v_max`` (paper A's
    MPCC, fixed-T or timed); NaN for a planner that has none."""
    params = getattr(planner, "params", None)
    for owner in (params, getattr(params, "mpcc", None)):
        v_max = getattr(owner, "v_max", None)
        if isinstance(v_max, numbers.Real) and not isinstance(v_max, bool):
            return v_max
    return math.nan


def _replan_period(planner: FootstepSource, replan_hz: float | None) -> float | None:
    """1 / ``replan_hz`` [s], checked: a rate in (0, 1000] Hz for a planner that plans within steps."""
    if replan_hz is None:
        return None
    rate = number_in("replan_hz", replan_hz, 0.0, 1000.0, "Hz", lo_open=True, error=ParameterError)
    if not getattr(planner, "within_step", False):
        raise InvalidInputError("replan_hz", replan_hz, "None for this planner (re-planning within steps needs one "
                                "built for it, e.g. TimedMpccPlanner(..., within_step=True))")
    return 1.0 / rate


def _walk(run: _LipRun, planner: FootstepSource, path: Path | None, n_steps: int, stop_at_end: bool,
          bar: object, period: float | None = None) -> tuple[str, int | None]:
    """The steps of :func:`run_lip_loop`: why the walk ended and the step of a fall (or None)."""
    reason, fell_at = "steps", None
    for k in range(n_steps):
        try:
            plan, fell = run.step(k) if period is None else run.step_within(k, period)
        except NoFallbackPlanError as exc:
            if k == 0:
                raise
            reason = f"planner failed with no fallback plan: {exc}"
            break
        if fell:
            fell_at, reason = k, "fell"
            break
        bar.update(1)  # type: ignore[attr-defined]
        rec = plan.record
        if stop_at_end and path is not None and has_path_progress(rec) and rec.theta[1] >= path.length - 1e-6:
            reason = "end of path"
            break
    return reason, fell_at


def _make_log(run: _LipRun, reason: str, fell_at: int | None, v_max: float, robot_radius: float,
              foot_radius: float) -> LipLog:
    r = run.rec
    states_a = np.array(run.states)
    t_a = np.array(run.ts)
    feet_a = np.array(r.feet)
    tc_a = np.concatenate(run.tc)
    com_a = np.concatenate(run.com)
    th_init, th_plan = np.array(r.th_init), np.array(r.th_plan)
    e_c, e_l, e_cart, theta_final, theta_c = _path_errors(run.path, states_a[:, [0, 2]], th_init, th_plan)
    obs_c, clearance = _clearance(run.obstacles, t_a, tc_a, com_a, feet_a, robot_radius, foot_radius)
    return LipLog(
        t=t_a,
        states=states_a,
        footholds=feet_a,
        sides=np.array(r.sides),
        theta_init=th_init,
        theta_plan=th_plan,
        v_avg=np.array(r.v_avg),
        v_max=v_max,
        e_contouring=e_c,
        e_lag=e_l,
        e_cartesian=e_cart,
        solve_time=np.array(r.solve_time),
        status=r.status,
        fallback=np.array(r.fallback, dtype=bool),
        tc=tc_a,
        com=com_a,
        obstacles=obs_c,
        clearance=clearance,
        pushes=run.absolute,
        plans=r.plans,
        path_length=run.path.length if run.path is not None else math.nan,
        theta_final=theta_final,
        theta_closest=theta_c,
        stopped_reason=reason,
        fell=fell_at is not None,
        fall_step=fell_at,
        planned_durations=np.array(r.durations, dtype=float),
        replan_solve_time=np.array(run.replan_times, dtype=float),
        replan_failures=run.replan_failures,
        record=RunRecord(touchdown_times=t_a[: len(feet_a)], sides=np.array(r.sides), planned_footholds=feet_a[:, :2],
                         footholds=feet_a[:, :2], planned_durations=np.array(r.durations, dtype=float),
                         durations=np.diff(t_a)[: len(feet_a)], pushes=tuple(run.absolute), plans=list(r.calls),
                         fell=fell_at is not None),
    )


def simulate(
    planner: "MpccPlanner",
    x0: np.ndarray,
    n_steps: int,
    obstacles: Sequence[Obstacle] = (),
    pushes: Sequence[Push] = (),
    first_side: int = 1,
    mass: float = DIGIT_MASS,
    dt_log: float = 0.02,
    stop_at_end: bool = True,
) -> LipLog:
    """Walk the 3D-LIP for ``n_steps`` steps under paper A's MPCC (:func:`run_lip_loop` with the
    planner's path, LIP model and radii).

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
    if not hasattr(planner, "path") or not hasattr(getattr(planner, "params", None), "model"):
        raise InvalidInputError("planner", planner, "an MpccPlanner (run_lip_loop takes any planner)")
    prm = planner.params
    return run_lip_loop(
        planner, x0, n_steps, planner.path, obstacles, pushes, first_side, prm.model.H, prm.model.g, mass, dt_log,
        stop_at_end, prm.robot_radius, prm.foot_radius,
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
    out = {
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
        "planned_durations_s": duration_stats(log.planned_durations),
        "executed_durations_s": duration_stats(np.diff(log.t), values=True),
    }
    if len(log.replan_solve_time):  # re-planned within steps: every solve counts
        out["solver_failures"] = int(log.replan_failures)
        out["solve_ms"] = timing_stats_ms(log.replan_solve_time)
        out["replans"] = int(len(log.replan_solve_time))
    return out


def duration_stats(durations: Sequence[float] | np.ndarray, values: bool = False) -> dict:
    """Statistics of step durations [s]: ``n``, ``min``, ``median``, ``max`` (None without steps) and,
    with ``values``, the durations themselves (``values``, in step order)."""
    d = np.asarray(durations, dtype=float).reshape(-1)
    some = d.size > 0
    out: dict = {"n": int(d.size), "min": float(np.min(d)) if some else None,
                 "median": float(np.median(d)) if some else None, "max": float(np.max(d)) if some else None}
    if values:
        out["values"] = [float(v) for v in d]
    return out


def push_recovery_times(log: LipLog, bound: float = 0.05) -> list[float]:
    """For each push, the time from its end to the first step instant at which the
    |contouring error| is below ``bound`` [m] (0 when it is already below; NaN when it never
    comes back before the end of the run). [s]"""
    out = []
    e = np.abs(log.e_contouring)
    for pu in log.pushes:
        t_end = pu.t_end
        idx = np.flatnonzero((log.t >= t_end) & (e < bound))
        if not np.any(log.t >= t_end):
            continue
        out.append(float(log.t[idx[0]] - t_end) if idx.size else float("nan"))
    return out
