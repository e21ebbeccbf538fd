"""Reduced-order closed loop: the ALIP walking over a foothold sequence under a footstep planner.

Any planner of the contract (:mod:`lipmpcc.planners.base`) drives it: paper B's ALIP-MPC and
ALIP-QP, or your own. It is called at touch-down and then every ``replan_period`` (25 Hz) during
the swing, with a :class:`~lipmpcc.planners.base.PlannerInput` built from the ALIP state (the COM at
height z_c, its velocity, the DCM, λ as ω, the stance foot at z = 0, heading 0, the time since
touch-down) and, as its ``course``, the footholds still ahead (a
:class:`~lipmpcc.terrain.StoneSequence`, the swing foot's target first). The swing foot lands on the
latest planned foothold at the latest planned duration (variable). There is no swing-leg dynamics:
the foot goes where the last plan says. Each step the ALIP is integrated exactly (closed form,
piecewise-constant push forces, :class:`lipmpcc.push.Push`); a plan with a centre-of-pressure offset
turns the ALIP about the offset pivot for the rest of the step.

Failure criterion (the run stops, ``fell = True``), checked at every planner tick and at
every touch-down:

1. a foothold outside its stone rectangle (tolerance ``tol``);
2. a foothold outside the kinematic limits relative to the stance foot
   (``|x| <= 0.6``, ``0.1 <= |y| <= 0.5`` m on the swing side);
3. the DCM leaving the viable set: the initial DCM of the current step (measured DCM
   projected back to the touch-down, paper B eq. 10) outside the intervals of
   :func:`lipmpcc.models.alip.viability_bounds` (``T >= T_min``). Outside them no
   admissible step sequence, stones or not, can stop the DCM from diverging;
4. the planner failing with no plan to fall back on
   (:class:`~lipmpcc.exceptions.NoFallbackPlanError`).

A plan whose status is not ``"ok"`` (the planner answered without solving) is a solver failure:
of the planner under test, they are counted in ``solver_failures`` (with the failures of 4).

``fall_index`` is the index in the sequence of the footstep during which the failure is
found: for 1–2 the footstep that landed badly; for 3 the step that starts (or is under
way) with a non-viable DCM, like paper B's "fails at the 14th step because the 13th foot
placement yields an initial condition that cannot lead to viable states".

**The run contract** (:mod:`lipmpcc.loops.base`): the loop takes a :class:`~lipmpcc.loops.base.Course`
(its ``stones``; its obstacles are handed to the planner) and a :class:`~lipmpcc.loops.base.PushSchedule`
(or the older ``sequence`` and ``config.pushes``); its log carries a :class:`~lipmpcc.loops.base.RunRecord`
(``AlipLoopLog.record``). A plan record that follows :class:`~lipmpcc.loops.base.TimedRecord` (the ALIP
planners') gives the logged planner time and status.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..conventions import Side, parse_side
from ..exceptions import InvalidInputError, NoFallbackPlanError, ParameterError, StateError
from ..validation import check_field_types, finite_array, positive_number
from ..metrics import timing_stats_ms
from ..models.alip import (
    AlipParams,
    DcmBounds,
    KinematicLimits,
    alip_flow,
    alip_from_com,
    com_velocity_from_alip,
    dcm_from_alip,
    viability_bounds,
)
from ..planners.base import FootstepSource, PlannerInput, StepPlan
from ..push import Push
from ..terrain import STEP_WIDTH, StoneSequence, initial_feet
from .base import Course, PushSchedule, RunRecord, read_timed, resolve_schedule
from .progress import step_bar

__all__ = [
    "AlipLoopConfig",
    "AlipInitialState",
    "AlipLoopLog",
    "run_alip_loop",
    "loop_metrics",
]


def __getattr__(name: str) -> object:
    if name == "FootPlanner":  # the loop's own planner protocol, replaced by the one contract
        warnings.warn(
            "lipmpcc.loops.alip.FootPlanner is deprecated: planners implement lipmpcc.planners.base.FootstepSource",
            DeprecationWarning,
            stacklevel=2,
        )
        return FootstepSource
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@dataclass(frozen=True)
class AlipLoopConfig:
    """Loop settings.

    Attributes:
        alip: ALIP constants (must match the planner's).
        limits: kinematic limits used by the failure criterion [m].
        T_min: shortest step [s] in the viability bounds.
        replan_period: planner period [s] (paper B: 40 ms).
        pushes: forces on the COM (their horizontal part); a push with a ``step`` acts after the
            touch-down that starts that footstep.
        log_period: sampling period of the logged trajectories [s].
        tol: tolerance of the stone / kinematic / viability checks [m].
    """

    alip: AlipParams = field(default_factory=AlipParams)
    limits: KinematicLimits = field(default_factory=KinematicLimits)
    T_min: float = 0.35
    replan_period: float = 0.04
    pushes: tuple[Push, ...] = ()
    log_period: float = 0.01
    tol: float = 1e-6

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        for name in ("T_min", "replan_period", "log_period", "tol"):
            positive_number(name, getattr(self, name), error=ParameterError)
        if not all(isinstance(p, Push) for p in self.pushes):
            raise ParameterError("pushes", self.pushes, "a tuple of lipmpcc.push.Push")
        object.__setattr__(self, "pushes", tuple(self.pushes))


@dataclass(frozen=True)
class AlipInitialState:
    """Start of a run: stance foot, COM and COM velocity in the world frame [m, m/s]; the stance
    side as +1 (left) or −1 (right)."""

    stance: tuple[float, float]
    stance_side: int
    com: tuple[float, float]
    com_vel: tuple[float, float] = (0.0, 0.0)
    swing_foot: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        for name, unit in (("stance", "m"), ("com", "m"), ("com_vel", "m/s"), ("swing_foot", "m")):
            value = getattr(self, name)
            if value is not None or name != "swing_foot":
                finite_array(f"initial.{name}", value, (2,), unit, error=StateError, what="an (x, y) pair")
        try:
            parse_side(self.stance_side)
        except InvalidInputError:
            raise StateError("initial.stance_side", self.stance_side, "+1 / 'left' or -1 / 'right'") from None

    @classmethod
    def standing(cls, w: float = STEP_WIDTH, alip: AlipParams | None = None, T_nom: float = 0.5) -> "AlipInitialState":
        """Standing still on the left foot (the right foot swings first), feet at
        ``(0, +-w/2)``. The COM is at rest, shifted from the midpoint of the feet towards
        the stance foot to the in-place-stepping initial DCM ``-w/(e^{lambda T_nom} + 1)``
        (eq. 5 with L = W = 0): the ALIP has no double support in which to shift the
        weight, so the run starts where that shift ends. Starting at the midpoint would
        put the DCM 0.14 m out, on the edge of the viable set."""
        left, right = initial_feet(w)
        lam = (AlipParams() if alip is None else alip).lam
        y = left[1] - w / (math.exp(lam * T_nom) + 1.0)
        return cls(tuple(left), Side.LEFT.sign, (0.0, float(y)), (0.0, 0.0), tuple(right))  # type: ignore[arg-type]


@dataclass
class AlipLoopLog:
    """Everything a run produced (arrays indexed by sample, step or planner tick)."""

    sequence: StoneSequence
    t: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    dcm: np.ndarray
    sample_step: np.ndarray
    footholds: np.ndarray
    step_index: np.ndarray
    step_sides: np.ndarray
    durations: np.ndarray
    td_times: np.ndarray
    z_initial: np.ndarray
    in_stone: np.ndarray
    kin_ok: np.ndarray
    plan_t: np.ndarray
    plan_step: np.ndarray
    plan_t_step: np.ndarray
    plan_T: np.ndarray
    plan_foothold: np.ndarray
    solve_time: np.ndarray
    plan_time: np.ndarray
    plan_fallback: np.ndarray
    plan_status: list[str]
    start_stance: np.ndarray
    start_swing: np.ndarray | None
    fell: bool
    fall_index: int | None
    fall_reason: str
    fall_time: float | None
    completed: bool
    solver_failures: int
    pushes: tuple[Push, ...]
    push_windows: list[tuple[float, float, tuple[float, float]]]
    dcm_bounds: DcmBounds
    lam: float
    record: RunRecord | None = None

    @property
    def n_steps(self) -> int:
        """Number of footsteps landed."""
        return len(self.footholds)


@dataclass
class _Trace:
    """The lists a run fills: samples, touch-downs and planner ticks."""

    t: list[float] = field(default_factory=list)
    com: list[np.ndarray] = field(default_factory=list)
    com_vel: list[np.ndarray] = field(default_factory=list)
    dcm: list[np.ndarray] = field(default_factory=list)
    sample_step: list[int] = field(default_factory=list)
    footholds: list[np.ndarray] = field(default_factory=list)
    step_index: list[int] = field(default_factory=list)
    step_sides: list[int] = field(default_factory=list)
    durations: list[float] = field(default_factory=list)
    td_times: list[float] = field(default_factory=list)
    in_stone: list[bool] = field(default_factory=list)
    kin_ok: list[bool] = field(default_factory=list)
    z_initial: list[np.ndarray] = field(default_factory=list)
    plan_t: list[float] = field(default_factory=list)
    plan_step: list[int] = field(default_factory=list)
    plan_t_step: list[float] = field(default_factory=list)
    plan_T: list[float] = field(default_factory=list)
    plan_foothold: list[np.ndarray] = field(default_factory=list)
    solve_time: list[float] = field(default_factory=list)
    plan_time: list[float] = field(default_factory=list)
    plan_fallback: list[bool] = field(default_factory=list)
    plan_status: list[str] = field(default_factory=list)
    calls: list[tuple[float, int, StepPlan]] = field(default_factory=list)
    td_planned_T: list[float] = field(default_factory=list)

    def plan(self, t: float, k: int, t_step: float, plan: StepPlan, wall: float) -> None:
        """Record a planner tick (the solver's own status and timing when the record is an ALIP plan)."""
        timed = read_timed(plan.record)  # a TimedRecord (the ALIP planners') or None
        self.calls.append((t, k, plan))
        self.plan_t.append(t)
        self.plan_step.append(k)
        self.plan_t_step.append(t_step)
        self.plan_T.append(plan.duration)
        self.plan_foothold.append(np.asarray(plan.foothold, float))
        self.solve_time.append(plan.solve_time)
        self.plan_time.append(timed[0] if timed is not None else wall)
        self.plan_fallback.append(not plan.ok)
        self.plan_status.append(timed[1] if timed is not None else plan.status)


def _array(x: list, shape: tuple[int, ...], dtype: type = float) -> np.ndarray:
    return np.array(x, dtype=dtype) if x else np.zeros(shape, dtype=dtype)


class _AlipRun:
    """One run of the ALIP loop: the state, the push windows, the trace, and its steps as methods."""

    def __init__(self, planner: FootstepSource, course: Course, init: AlipInitialState, cfg: AlipLoopConfig,
                 approach_planner: FootstepSource | None, approach_steps: int, schedule: PushSchedule) -> None:
        self.planner, self.approach_planner, self.approach_steps = planner, approach_planner, approach_steps
        self.course, self.schedule = course, schedule
        self.sequence, self.init, self.cfg = course.stones, init, cfg
        self.prm = cfg.alip
        self.lam = self.prm.lam
        self.bounds = viability_bounds(self.lam, cfg.T_min, cfg.limits)
        self.stance = np.asarray(init.stance, float).copy()
        self.swing = self.stance.copy() if init.swing_foot is None else np.asarray(init.swing_foot, float).copy()
        self.side = parse_side(init.stance_side).sign
        self.s = alip_from_com(np.asarray(init.com, float) - self.stance, init.com_vel, self.prm)
        self.k = 0
        self.t_glob = 0.0
        self.t_step = 0.0
        self.failures = 0
        self.trace = _Trace(z_initial=[dcm_from_alip(self.s, self.prm)])
        self.windows: list[tuple[float, float, tuple[float, float]]] = [
            (p.t_start, p.t_end, p.force_xy) for p in schedule.absolute
        ]
        self.fell, self.fall_index, self.fall_reason, self.fall_time, self.completed = False, None, "", None, False
        self._ahead: tuple[int, StoneSequence] | None = None

    # ---- small steps -------------------------------------------------------------------------
    def log_sample(self) -> None:
        tr, s, prm = self.trace, self.s, self.prm
        tr.t.append(self.t_glob)
        tr.com.append(self.stance + s[0:2])
        tr.com_vel.append(com_velocity_from_alip(s, prm))
        tr.dcm.append(self.stance + dcm_from_alip(s, prm))
        tr.sample_step.append(self.k)

    def force_at(self, tg: float) -> np.ndarray:
        f = np.zeros(2)
        for a, b, fv in self.windows:
            if a <= tg < b:
                f += fv
        return f

    def register_pushes(self, step: int, start: float) -> None:
        """Arm the pushes of footstep ``step`` at its touch-down ``start`` [s]."""
        for p in self.schedule.arm(step, start):
            self.windows.append((p.t_start, p.t_end, p.force_xy))

    def fall(self, index: int, reason: str) -> None:
        self.fell, self.fall_index, self.fall_time, self.fall_reason = True, index, self.t_glob, reason

    def course_ahead(self) -> StoneSequence:
        """The footholds from the current swing foot's target on."""
        if self._ahead is None or self._ahead[0] != self.k:
            self._ahead = (self.k, self.course.stones_ahead(self.k))
        return self._ahead[1]

    def planner_input(self, dcm_w: np.ndarray) -> PlannerInput:
        s, prm = self.s, self.prm
        v = com_velocity_from_alip(s, prm)
        return PlannerInput(
            t=self.t_glob,
            com_pos=np.array([self.stance[0] + s[0], self.stance[1] + s[1], prm.z_c]),
            com_vel=np.array([v[0], v[1], 0.0]),
            dcm=dcm_w,
            omega=self.lam,
            stance_side=parse_side(self.side),
            stance_pos=np.array([self.stance[0], self.stance[1], 0.0]),
            stance_yaw=0.0,
            swing_pos=np.array([self.swing[0], self.swing[1], 0.0]),
            swing_yaw=0.0,
            time_since_touchdown=self.t_step,
            step_index=self.k,
            torso_yaw=0.0,
            angular_momentum=np.zeros(3),
            mass=prm.mass,
            course=self.course_ahead(),
            obstacles=self.course.obstacles,
        )

    # ---- the loop's steps --------------------------------------------------------------------
    def plan(self) -> StepPlan | None:
        """Check the DCM, then call the planner; None when the run stops here."""
        dcm_w = self.stance + dcm_from_alip(self.s, self.prm)
        z0 = (dcm_w - self.stance) * math.exp(-self.lam * self.t_step)
        if not self.bounds.contains(z0, -self.side, self.cfg.tol):
            self.fall(self.k, f"DCM left the viable set (initial DCM {np.round(z0, 4).tolist()} m) during footstep {self.k}")
            return None
        under_test = not (self.approach_planner is not None and self.k < self.approach_steps)
        active = self.planner if under_test else self.approach_planner
        w0 = time.perf_counter()
        try:
            plan = active.plan(self.planner_input(dcm_w))
        except NoFallbackPlanError as exc:
            self.failures += under_test
            self.fall(self.k, f"planner failed with no fallback plan: {exc}")
            return None
        wall = time.perf_counter() - w0
        if not isinstance(plan, StepPlan):
            raise StateError("planner output", plan, "a StepPlan")
        self.failures += under_test and not plan.ok
        self.trace.plan(self.t_glob, self.k, self.t_step, plan, wall)
        return plan

    def integrate(self, plan: StepPlan) -> bool:
        """Integrate to the next planner tick or to the touch-down; True at a touch-down."""
        cfg = self.cfg
        T_td = float(plan.duration)
        t_next = self.t_step + cfg.replan_period
        touchdown = T_td <= t_next + 1e-12
        t_target = max(T_td, self.t_step) if touchdown else t_next
        t_end_glob = self.t_glob + (t_target - self.t_step)
        cuts = {t_end_glob}
        for a, b, _ in self.windows:
            for c in (a, b):
                if self.t_glob < c < t_end_glob:
                    cuts.add(c)
        g = math.floor(self.t_glob / cfg.log_period + 1e-9) + 1
        while g * cfg.log_period < t_end_glob - 1e-12:
            cuts.add(g * cfg.log_period)
            g += 1
        # a planned centre-of-pressure offset (planner with a foot): the ALIP about the shifted pivot;
        # at constant height the angular momentum about it is the same (L_xy = m z_c (v_y, -v_x))
        cop = plan.cop_offset
        shifted = cop is not None and bool(np.any(cop))
        for c in sorted(cuts):
            dt = c - self.t_glob
            if dt > 0:
                if shifted:
                    s = self.s.copy()
                    s[0:2] -= cop
                    s = alip_flow(s, dt, self.prm, self.force_at(self.t_glob + 0.5 * dt))
                    s[0:2] += cop
                    self.s = s
                else:
                    self.s = alip_flow(self.s, dt, self.prm, self.force_at(self.t_glob + 0.5 * dt))
                self.t_glob = c
            self.log_sample()
        self.t_step = t_target
        return touchdown

    def touch_down(self, plan: StepPlan) -> bool:
        """The swing foot lands on the plan's foothold; True when the run stops here."""
        cfg, k, tr = self.cfg, self.k, self.trace
        foothold = np.asarray(plan.foothold, float).copy()
        u = foothold - self.stance
        swing_side = -self.side
        in_stone = (not bool(self.sequence.is_stone[k])) or self.sequence[k].contains(foothold, cfg.tol)
        kin_ok = cfg.limits.contains(u, swing_side, cfg.tol)
        tr.footholds.append(foothold)
        tr.step_index.append(k)
        tr.step_sides.append(swing_side)
        tr.durations.append(self.t_step)
        tr.td_planned_T.append(float(plan.duration))
        tr.td_times.append(self.t_glob)
        tr.in_stone.append(in_stone)
        tr.kin_ok.append(kin_ok)
        self.s = self.s.copy()
        self.s[0:2] -= u
        self.swing, self.stance = self.stance, foothold
        self.side = swing_side
        self.t_step = 0.0
        self.k += 1
        self.register_pushes(self.k, self.t_glob)
        tr.z_initial.append(dcm_from_alip(self.s, self.prm))
        if not in_stone or not kin_ok:
            where = "outside its stone" if not in_stone else "outside the kinematic limits"
            self.fall(k, f"foothold {np.round(foothold, 4).tolist()} of footstep {k} " + where)
            return True
        if not self.bounds.contains(tr.z_initial[-1], -self.side, cfg.tol):
            z = np.round(tr.z_initial[-1], 4).tolist()
            self.fall(self.k, f"DCM left the viable set (initial DCM {z} m) at the start of footstep {self.k}")
            return True
        if self.k >= len(self.sequence):
            self.completed = True
            return True
        return False

    def run(self, progress: bool | None = None) -> None:
        """Plan, integrate, land, until the last foothold or a failure (``progress``: a bar of the
        footholds, see :func:`~lipmpcc.loops.progress.step_bar`)."""
        self.log_sample()
        self.register_pushes(0, 0.0)
        max_time = 2.0 * len(self.sequence) + 5.0
        with step_bar(len(self.sequence), "ALIP", progress) as bar:
            while True:
                plan = self.plan()
                if plan is None:
                    return
                touchdown = self.integrate(plan)
                if self.t_glob > max_time:
                    self.fall(self.k, "time limit reached")
                    return
                if touchdown:
                    bar.update(1)
                    if self.touch_down(plan):
                        return

    def log(self) -> AlipLoopLog:
        tr, init = self.trace, self.init
        return AlipLoopLog(
            sequence=self.sequence,
            t=_array(tr.t, (0,)),
            com=_array(tr.com, (0, 2)),
            com_vel=_array(tr.com_vel, (0, 2)),
            dcm=_array(tr.dcm, (0, 2)),
            sample_step=_array(tr.sample_step, (0,), int),
            footholds=_array(tr.footholds, (0, 2)),
            step_index=_array(tr.step_index, (0,), int),
            step_sides=_array(tr.step_sides, (0,), int),
            durations=_array(tr.durations, (0,)),
            td_times=_array(tr.td_times, (0,)),
            z_initial=np.array(tr.z_initial),
            in_stone=_array(tr.in_stone, (0,), bool),
            kin_ok=_array(tr.kin_ok, (0,), bool),
            plan_t=_array(tr.plan_t, (0,)),
            plan_step=_array(tr.plan_step, (0,), int),
            plan_t_step=_array(tr.plan_t_step, (0,)),
            plan_T=_array(tr.plan_T, (0,)),
            plan_foothold=_array(tr.plan_foothold, (0, 2)),
            solve_time=_array(tr.solve_time, (0,)),
            plan_time=_array(tr.plan_time, (0,)),
            plan_fallback=_array(tr.plan_fallback, (0,), bool),
            plan_status=tr.plan_status,
            start_stance=np.asarray(init.stance, float),
            start_swing=None if init.swing_foot is None else np.asarray(init.swing_foot, float),
            fell=self.fell,
            fall_index=self.fall_index,
            fall_reason=self.fall_reason,
            fall_time=self.fall_time,
            completed=self.completed,
            solver_failures=int(self.failures),
            pushes=self.schedule.pushes,
            push_windows=self.windows,
            dcm_bounds=self.bounds,
            lam=self.lam,
            record=self.record(),
        )

    def record(self) -> RunRecord:
        """The run's :class:`~lipmpcc.loops.base.RunRecord` (the foot lands where and when the last plan said)."""
        tr = self.trace
        feet = _array(tr.footholds, (0, 2))
        return RunRecord(touchdown_times=_array(tr.td_times, (0,)), sides=_array(tr.step_sides, (0,), int),
                         planned_footholds=feet, footholds=feet, planned_durations=_array(tr.td_planned_T, (0,)),
                         durations=_array(tr.durations, (0,)),
                         pushes=tuple(Push.between(f, a, b) for a, b, f in self.windows), plans=list(tr.calls),
                         fell=self.fell)


def _check_run(
    planner: FootstepSource, sequence: StoneSequence, init: AlipInitialState, cfg: AlipLoopConfig,
    approach_planner: FootstepSource | None, approach_steps: int,
) -> None:
    if not isinstance(init, AlipInitialState):
        raise InvalidInputError("initial", init, "an AlipInitialState")
    if not isinstance(sequence, StoneSequence) or len(sequence) == 0:
        raise InvalidInputError("sequence", sequence, "a non-empty StoneSequence")
    if not isinstance(planner, FootstepSource):
        raise InvalidInputError("planner", planner, "a FootstepSource: name, rate_hz, reset() and plan(inp) (AlipMpc, AlipQp)")
    for name in ("stance", "com", "com_vel"):
        finite_array(f"initial.{name}", getattr(init, name), (2,), "m", error=InvalidInputError, what="(x, y)")
    if int(sequence.sides[0]) != -parse_side(init.stance_side).sign:
        raise InvalidInputError("sequence.sides[0]", int(sequence.sides[0]), "the foot opposite to the initial stance foot")
    pl_alip = getattr(getattr(planner, "params", None), "alip", None)
    if pl_alip is not None and pl_alip != cfg.alip:
        raise ParameterError("config.alip", cfg.alip, f"the planner's ALIP constants {pl_alip}")
    if approach_planner is not None and not isinstance(approach_planner, FootstepSource):
        raise InvalidInputError("approach_planner", approach_planner, "None or a FootstepSource")
    if not isinstance(approach_steps, (int, np.integer)) or not 0 <= approach_steps <= len(sequence):
        raise InvalidInputError("approach_steps", approach_steps, f"an integer in [0, {len(sequence)}]")


def run_alip_loop(
    planner: FootstepSource,
    sequence: StoneSequence | None = None,
    initial: AlipInitialState | None = None,
    config: AlipLoopConfig | None = None,
    approach_planner: FootstepSource | None = None,
    approach_steps: int = 0,
    progress: bool | None = None,
    course: Course | None = None,
    schedule: PushSchedule | None = None,
) -> AlipLoopLog:
    """Walk the ALIP over ``sequence`` with ``planner`` until the last foothold or a failure.

    Args:
        planner: a :class:`~lipmpcc.planners.base.FootstepSource` — ALIP-MPC, ALIP-QP or your
            own (reset at the start of the run).
        sequence: footholds in order (approach + stones); ``sequence.sides[0]`` must be
            the foot opposite to the initial stance.
        initial: start state (default: standing, left stance).
        config: loop settings.
        approach_planner: planner for the first ``approach_steps`` footsteps (None: use
            ``planner`` throughout). Like any planner it previews the footholds ahead,
            stones included. Sharing one approach planner gives every planner under test
            the same state when it takes over (paper B: "we try to ensure consistent
            initial conditions in each comparison test").
        approach_steps: number of footsteps driven by ``approach_planner``.
        progress: a progress bar of the footholds on stderr (None: only on a terminal; False: never).
        course: the run's :class:`~lipmpcc.loops.base.Course` instead of ``sequence``: its ``stones`` are the
            sequence, its obstacles go to the planner.
        schedule: the run's :class:`~lipmpcc.loops.base.PushSchedule` instead of ``config.pushes``.

    Returns:
        :class:`AlipLoopLog`.

    Raises:
        InvalidInputError: both or neither of ``sequence`` and ``course``; both ``schedule`` and
            ``config.pushes``.
    """
    cfg = AlipLoopConfig() if config is None else config
    if not isinstance(cfg, AlipLoopConfig):
        raise ParameterError("config", config, "an AlipLoopConfig")
    run_course = _alip_course(sequence, course)
    sequence = run_course.stones
    run_schedule = resolve_schedule(schedule, cfg.pushes)
    init = AlipInitialState.standing(alip=cfg.alip) if initial is None else initial
    _check_run(planner, sequence, init, cfg, approach_planner, approach_steps)
    planner.reset()
    if approach_planner is not None:
        approach_planner.reset()
    steps = int(approach_steps) if approach_planner is not None else 0
    run = _AlipRun(planner, run_course, init, cfg, approach_planner, steps, run_schedule)
    run.run(progress)
    return run.log()


def _alip_course(sequence: StoneSequence | None, course: Course | None) -> Course:
    """The run's course from ``sequence`` (the older form) or ``course`` (one of them, with stones)."""
    if course is None:
        if not isinstance(sequence, StoneSequence) or len(sequence) == 0:
            raise InvalidInputError("sequence", sequence, "a non-empty StoneSequence (or course=Course(stones=...))")
        return Course(stones=sequence)
    if not isinstance(course, Course):
        raise InvalidInputError("course", course, "a lipmpcc.loops.base.Course or None")
    if sequence is not None:
        raise InvalidInputError("course", course, "None when sequence is given (one or the other)")
    if course.stones is None:
        raise InvalidInputError("course.stones", None, "the stones the ALIP walks (a StoneSequence)")
    return course


def loop_metrics(log: AlipLoopLog) -> dict[str, object]:
    """Stone metrics of a run: landed stones, RMSE to the stone centres [m], stones
    violated, step durations on the stones [s], planner timing [ms]."""
    seq = log.sequence
    on = np.array([bool(seq.is_stone[i]) for i in log.step_index], dtype=bool)
    idx = log.step_index[on]
    errs = np.linalg.norm(log.footholds[on] - seq.centers[idx], axis=1) if idx.size else np.zeros(0)
    n_stones = int(np.sum(seq.is_stone))
    first_stone = int(np.argmax(seq.is_stone)) if n_stones else 0
    landed_ok = int(np.sum(log.in_stone[on] & log.kin_ok[on])) if idx.size else 0
    d = log.durations[on]
    fall_step = None
    if log.fell and log.fall_index is not None:
        fall_step = int(log.fall_index - first_stone + 1)
    return {
        "n_stones": n_stones,
        "steps_completed": landed_ok if not log.fell else int(max(0, min(landed_ok, (fall_step or 1) - 1))),
        "step_rmse_m": float(np.sqrt(np.mean(errs**2))) if errs.size else float("nan"),
        "step_error_max_m": float(np.max(errs)) if errs.size else float("nan"),
        "stones_violated": int(np.sum(~log.in_stone[on])) if idx.size else 0,
        "step_duration_min_s": float(np.min(d)) if d.size else float("nan"),
        "step_duration_max_s": float(np.max(d)) if d.size else float("nan"),
        "solve_ms": timing_stats_ms(log.solve_time),
        "plan_ms": timing_stats_ms(log.plan_time),
        "solver_failures": int(log.solver_failures),
        "fallback_ticks": int(np.sum(log.plan_fallback)),
        "fell": bool(log.fell),
        "fall_step": fall_step,
        "fall_reason": log.fall_reason,
        "completed": bool(log.completed),
    }
