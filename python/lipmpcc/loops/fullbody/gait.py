"""The full-body loop's gait: a small state machine over the support phases.

:class:`Gait` owns the gait's phase and timing; a planner (:class:`~lipmpcc.planners.base.FootstepSource`)
only says where and when the swing foot should land (:class:`~lipmpcc.planners.base.StepPlan`), from the
measured state it is given (:class:`~lipmpcc.planners.base.PlannerInput`). The modes
(:class:`GaitMode`):

1. ``STAND``: double support at the standing pose, when there is no planner.
2. ``SHIFT``: when walking, the run starts in double support and the COM shifts (quintic) towards
   the first stance foot for ``initial_shift`` seconds (skipped when that is 0).
3. ``SINGLE``: the swing foot follows a :class:`~lipmpcc.control.references.StepTrajectory` from its lift-off
   pose to the planned foothold; the torso yaws to the planned heading; the horizontal COM follows the
   LIP about the stance foot (:class:`~lipmpcc.control.references.LipComReference`, re-initialised from the
   measured COM state at each touch-down). Each planner update (at the planner's rate) moves the
   foothold and re-times the phase; changes are blended smoothly. A planned centre of pressure
   (``StepPlan.cop_offset``) moves the LIP's pivot.
4. Touch-down when the swing foot's contact is detected after ``touchdown_min_phase``, or when the
   phase reaches 1 (clock), whichever first (with ``LoopParams.touchdown_timing = "loop"``, and with the
   default ``"auto"`` for a planner that does not compensate the touch-down timing itself: when the phase
   reaches 1, the planned time, contact or not); then ``DOUBLE`` support for ``double_support`` seconds
   (when not 0) and the other foot lifts off.
"""

from __future__ import annotations

import enum
import math
import time

import numpy as np

from ...conventions import Side, parse_side
from ...exceptions import StateError
from ...planners.base import FootstepSource, PlannerInput, StepPlan
from ...sim.types import Measurement
from ..base import Course, touchdown_timing
from ...control.references import LipComReference, Quintic, StepTrajectory, SwingParams
from .angles import yaw_of
from .log import TouchDown
from .params import LoopParams

__all__ = ["GaitMode", "Gait"]

#: tolerance of the gait's time comparisons [s]
_EPS = 1e-9


class GaitMode(enum.Enum):
    """The support phase of the gait."""

    STAND = "stand"  #: double support, standing (no planner)
    SHIFT = "shift"  #: double support, the initial COM shift onto the first stance foot
    DOUBLE = "double"  #: double support between a touch-down and the next lift-off
    SINGLE = "single"  #: single support: the swing foot is in the air


class Gait:
    """The gait state and its transitions (see the module doc).

    Args:
        planner: the footstep planner; None to stand.
        params: the loop's :class:`~lipmpcc.loops.fullbody.LoopParams`.
        com_height: constant COM height of the references [m].
        mass: total robot mass [kg] (for the planner's input).
        max_steps: finish at this many touch-downs (None: never).
        course: the run's :class:`~lipmpcc.loops.base.Course`: every planner call is given its obstacles and,
            as ``course``, the stones ahead (when it has stones) or its path.

    Attributes:
        mode: the :class:`GaitMode`.
        stance: the stance foot (in double support: the foot that was or will be the stance foot);
            swing: the other foot; stance_index, swing_index: their rows in per-foot arrays (0 left, 1 right).
        stance_code: 0 in left stance, 1 in right stance, 2 in double support (:attr:`LoopLog.stance`).
        t_td: time of the last touch-down (or of the start of walking) [s].
        t_lift: time at which the swing foot lifts off in ``DOUBLE`` [s].
        lip: the LIP COM reference (in ``DOUBLE`` and ``SINGLE``).
        shift: the COM shift (in ``SHIFT``).
        step: the swing trajectory (in ``SINGLE``).
        last_plan: the planner's latest answer; next_plan_t: when it is asked next [s].
        torso_yaw_ref: the torso heading reference committed by the loop at each tick [rad].
        angular_momentum: the centroidal angular momentum of the last WBC tick (3,) [kg m²/s].
        ground_z: ground height under the feet at the start [m].
        finished: ``max_steps`` touch-downs happened.
        touchdowns, plans, plan_times: the support exchanges, the planner's answers with their time
            [s] and its wall time per call [s].
        plan_steps: the footstep index of each answer (``len(touchdowns)`` when it was asked).
        planned_durations: per touch-down, the duration [s] the last plan before it asked for.
    """

    def __init__(self, planner: FootstepSource | None, params: LoopParams, com_height: float, mass: float,
                 max_steps: int | None = None, course: Course | None = None) -> None:
        self.planner = planner
        self.course = Course() if course is None else course
        self._course_at: tuple[int, object] = (-1, None)
        self.params = params
        self.swing_params = params.swing or SwingParams()
        #: who times the touch-down ("planner" or "loop", LoopParams.touchdown_timing resolved for this planner)
        self.touchdown_timing = touchdown_timing(params.touchdown_timing, planner)
        self._min_phase = 1.0 if self.touchdown_timing == "loop" else params.touchdown_min_phase  # of a contact
        self._substep_contact = params.touchdown_contact == "substep"  # Measurement.touched, else .contact
        self.lip = LipComReference(com_height)
        self.omega = self.lip.omega
        self.mass = mass
        self.max_steps = max_steps
        self.plan_period = 1.0 / float(planner.rate_hz) if planner is not None else math.inf
        self.mode = GaitMode.STAND
        self.stance_code = 2
        self._set_stance(parse_side(params.first_stance))
        self.t_td = self.t_lift = 0.0
        self.shift: Quintic | None = None
        self.step: StepTrajectory | None = None
        self.last_plan: StepPlan | None = None
        self.next_plan_t = math.inf
        self.torso_yaw_ref = 0.0
        self.angular_momentum = np.zeros(3)
        self.ground_z = 0.0
        self.finished = False
        self.touchdowns: list[TouchDown] = []
        self.plans: list[tuple[float, StepPlan]] = []
        self.plan_times: list[float] = []
        self.plan_steps: list[int] = []
        self.planned_durations: list[float] = []
        self._step_contact = np.zeros(2)  # the LIP pivot at the step's start (the stance contact point)

    # ---- transitions ---------------------------------------------------------------------------
    def start(self, t0: float, m: Measurement) -> None:
        """The state at the run's first instant ``t0`` [s], from its measurement ``m``."""
        left, right = m.feet[0].position, m.feet[1].position
        self.t_td = self.t_lift = t0
        self.torso_yaw_ref = yaw_of(m.torso.rotation)
        self.ground_z = float(min(left[2], right[2]))
        if self.planner is None:
            return
        p = self.params
        stance_xy = m.feet[self.stance_index].position[:2]
        if p.initial_shift > 0.0:
            mid = 0.5 * (left[:2] + right[:2])
            target = mid + p.initial_shift_fraction * (stance_xy - mid)
            self.shift = Quintic(t0, t0 + p.initial_shift, m.com[:2], x1=target)
            self._set_mode(GaitMode.SHIFT)
        else:  # no shift: lift the first swing foot at once
            self.lip.reset(t0, m.com[:2], m.com_vel[:2], stance_xy)
            self._set_mode(GaitMode.DOUBLE)

    def update(self, t: float, m: Measurement) -> bool:
        """Advance the gait to time ``t`` [s] with the tick's measurement ``m``: end the COM shift,
        detect a touch-down, lift the swing foot, call the planner when due.

        Returns:
            True when the gait state changed (a lift-off, a touch-down or a planner call).
        """
        mode = self.mode
        changed = False
        if mode is GaitMode.SHIFT:
            if t >= self.shift.t1 - _EPS:
                changed = True
                self.end_shift(t, m)
        elif mode is GaitMode.SINGLE:
            changed = self._detect_touch_down(t, m)
            if self.finished:
                return True
        elif mode is GaitMode.DOUBLE and t >= self.t_lift - _EPS:
            changed = True
            self.start_swing(t, m)
        if self.mode is GaitMode.SINGLE and t >= self.next_plan_t - _EPS:
            changed = True
            self.replan(t, m)
        return changed

    def end_shift(self, t: float, m: Measurement) -> None:
        """End the initial COM shift at ``t`` [s]: start the LIP about the stance foot and the first swing."""
        self.t_td = t
        self._reset_lip(t, m)
        self.start_swing(t, m)

    def start_swing(self, t: float, m: Measurement) -> None:
        """Lift the swing foot at ``t`` [s] towards the planner's foothold (single support)."""
        foot = m.feet[self.swing_index]
        self._step_contact = self.lip.pivot
        plan = self.last_plan = self._plan(t, m)
        self.apply_cop(t, plan)
        t_end = max(self.t_td + plan.duration, t + self.swing_params.min_remaining)
        self.step = StepTrajectory(
            t_start=t,
            t_end=t_end,
            start_pos=foot.position,
            start_yaw=yaw_of(foot.rotation),
            target_pos=self._foothold(plan),
            target_yaw=plan.yaw,
            torso_start_yaw=self.torso_yaw_ref,
            torso_target_yaw=plan.yaw,
            params=self.swing_params,
        )
        self._set_mode(GaitMode.SINGLE)
        self.next_plan_t = t + self.plan_period

    def touch_down(self, t: float, m: Measurement, by_contact: bool) -> None:
        """The swing foot lands at ``t`` [s]: record it, swap the feet, restart the LIP about the new
        stance foot, then finish (``max_steps``), wait in double support, or lift the other foot."""
        swing, step = self.swing, self.step
        foot = m.feet[self.swing_index]
        self.touchdowns.append(
            TouchDown(
                t=t,
                side=swing,
                pos=foot.position.copy(),
                planned=step.target_pos[:2].copy(),
                yaw=yaw_of(foot.rotation),
                planned_yaw=step.target_yaw,
                by_contact=by_contact,
                duration=t - self.t_td,
            )
        )
        self.planned_durations.append(float(self.last_plan.duration) if self.last_plan is not None else math.nan)
        self.torso_yaw_ref = step.evaluate(t).torso_yaw
        self._set_stance(swing)
        self.t_td = t
        self._reset_lip(t, m)
        self.step = None
        if self.max_steps is not None and len(self.touchdowns) >= self.max_steps:
            self.finished = True
        elif self.params.double_support > 0.0:
            self._set_mode(GaitMode.DOUBLE)
            self.t_lift = t + self.params.double_support
        else:
            self.start_swing(t, m)

    def replan(self, t: float, m: Measurement) -> None:
        """Ask the planner again during the swing at ``t`` [s]; move the foothold and re-time the step."""
        plan = self.last_plan = self._plan(t, m)
        while self.next_plan_t <= t + _EPS:
            self.next_plan_t += self.plan_period
        if self.params.com_resync_on_plan:
            self._reset_lip(t, m)
        self.apply_cop(t, plan)
        self.step.update(
            t,
            target_pos=self._foothold(plan),
            target_yaw=plan.yaw,
            t_end=self.t_td + plan.duration,
            torso_target_yaw=plan.yaw,
        )

    def apply_cop(self, t: float, plan: StepPlan) -> None:
        """Turn the LIP COM reference about the plan's centre of pressure at ``t`` [s], if it has one."""
        if plan.cop_offset is not None:
            pivot = self._step_contact + plan.cop_offset
            if np.any(pivot != self.lip.pivot):
                self.lip.move_pivot(t, pivot)

    # ---- the planner ---------------------------------------------------------------------------
    def planner_input(self, t: float, m: Measurement) -> PlannerInput:
        """What the planner is given at ``t`` [s] (see :class:`~lipmpcc.planners.base.PlannerInput`)."""
        stance = self.stance
        on_ground, in_air = m.feet[self.stance_index], m.feet[self.swing_index]
        k = len(self.touchdowns)
        if self._course_at[0] != k:  # the stones ahead change at touch-down only
            self._course_at = (k, self.course.planner_course(k))
        return PlannerInput(
            t=t,
            com_pos=m.com,
            com_vel=m.com_vel,
            dcm=m.com[:2] + m.com_vel[:2] / self.omega,
            omega=self.omega,
            stance_side=stance,
            stance_pos=on_ground.position,
            stance_yaw=yaw_of(on_ground.rotation),
            swing_pos=in_air.position,
            swing_yaw=yaw_of(in_air.rotation),
            time_since_touchdown=t - self.t_td,
            step_index=len(self.touchdowns),
            torso_yaw=yaw_of(m.torso.rotation),
            angular_momentum=self.angular_momentum.copy(),
            mass=self.mass,
            course=self._course_at[1],  # type: ignore[arg-type]
            obstacles=self.course.obstacles,
        )

    def _plan(self, t: float, m: Measurement) -> StepPlan:
        inp = self.planner_input(t, m)
        w0 = time.perf_counter()
        plan = self.planner.plan(inp)
        self.plan_times.append(time.perf_counter() - w0)
        if not isinstance(plan, StepPlan):
            raise StateError("planner output", plan, "a StepPlan")
        self.plans.append((t, plan))
        self.plan_steps.append(len(self.touchdowns))
        return plan

    # ---- helpers -------------------------------------------------------------------------------
    def _detect_touch_down(self, t: float, m: Measurement) -> bool:
        """Touch down when the swing foot's contact comes after ``touchdown_min_phase`` or the phase
        reaches 1; True when it did."""
        tau = self.step.phase.tau(t)
        touched = m.touched if self._substep_contact and m.touched is not None else m.contact
        by_contact = touched[self.swing_index] and tau >= self._min_phase
        if not (by_contact or tau >= 1.0):
            return False
        self.touch_down(t, m, bool(by_contact))
        return True

    def _reset_lip(self, t: float, m: Measurement) -> None:
        """Restart the LIP COM reference at ``t`` [s] from the measured COM state about the stance foot."""
        self.lip.reset(t, m.com[:2], m.com_vel[:2], m.feet[self.stance_index].position[:2])

    def _set_mode(self, mode: GaitMode) -> None:
        self.mode = mode
        self.stance_code = self.stance_index if mode is GaitMode.SINGLE else 2

    def _set_stance(self, stance: Side) -> None:
        self.stance, self.swing = stance, stance.other
        self.stance_index, self.swing_index = stance.index, stance.other.index
        self.stance_code = self.stance_index if self.mode is GaitMode.SINGLE else 2

    def _foothold(self, plan: StepPlan) -> np.ndarray:
        """The swing foot's target (3,) [m]: the plan's foothold, ``landing_depth`` below the ground."""
        return np.array([plan.foothold[0], plan.foothold[1], self.ground_z - self.params.landing_depth])
