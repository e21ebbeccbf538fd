"""The timed MPCC (paper A's MPCC with paper B's step timing) as a footstep source of the full-body loop.

:class:`TimedMpccFootstepSource` is :class:`~lipmpcc.planners.sources.mpcc.MpccFootstepSource` with a
:class:`~lipmpcc.planners.mpcc_timed.TimedMpccPlanner` built to be called within steps. The loop calls it
at 25 Hz (paper B's rate). Each call plans from the state measured *now*, t̃ after the stance foot's
touch-down: the remaining time τ of the current step is a decision variable, so the plan's ``duration``
is t̃ + τ, and the loop's phase clock re-times the swing to it (as for the ALIP-MPC). There is no LIP
prediction to the exchange: a foot that meets the ground early starts the next step, whose first call
plans from the state measured then.

**Step timing.** The loop's swing foot meets the ground before its phase clock ends (touch-down is
detected from contact): on ``digit_like`` about 10 % early, e.g. 0.325 s for a plan of 0.36 s. Each plan
then lands its foot, chosen for the COM state at the planned exchange, when the COM is still behind that
state: the robot slows, and the next plans ask for longer steps from the slower state (without the
compensation below, the 0.8 m/s overtaking asked 0.35 s steps where the LIP asks 0.30 s, and the LIP
loop made to touch down at 90 % of each asked duration reproduces that: 0.350 s asked, 0.81 m/s). As
:class:`~lipmpcc.planners.sources.mpcc.MpccFootstepSource` does for fixed T, the source learns the
offset between the executed and the requested step durations from the touch-downs it sees (gain
``timing_gain``, bounded by ``max_timing_offset``) and asks the loop's clock for t̃ + τ − offset, so that
the foot meets the ground at the planned time t̃ + τ. The records and the plans' ``record`` keep the
planned t̃ + τ (``duration``); the :class:`~lipmpcc.planners.base.StepPlan` carries the clock's.

Every call is recorded as an :class:`~lipmpcc.planners.sources.mpcc.MpccPlanRecord` (``x0`` the planned
state at the coming exchange, ``t_exchange`` its time, ``duration`` t̃ + τ), so the metrics and figures of
paper A read it unchanged. Failures are survived and counted as in the fixed-T source.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

import numpy as np

from ...conventions import LEFT
from ...exceptions import NoFallbackPlanError, ParameterError
from ...obstacles import Obstacle
from ...paths import Path
from ..base import PlannerInput, StepPlan
from ..mpcc_timed import TimedMpccParams, TimedMpccPlanner
from .mpcc import MpccFootstepSource, MpccPlanRecord, MpccSourceParams

__all__ = ["TimedMpccFootstepSource", "WITHIN_STEP_RATE_HZ"]

#: paper B's re-planning rate within a step [Hz]
WITHIN_STEP_RATE_HZ = 25.0


class TimedMpccFootstepSource(MpccFootstepSource):
    """Timed MPCC footstep planner for :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop`
    (the planner contract, :class:`~lipmpcc.planners.base.FootstepSource`).

    Args:
        path: reference path.
        params: :class:`~lipmpcc.planners.mpcc_timed.TimedMpccParams` (the MPCC preset and [T_min, T_max]);
            its ``min_time_to_touchdown`` must not exceed the re-planning period, or every step would
            be pushed to T_max.
        obstacles: moving obstacles (their clocks are the simulation time).
        rate_hz: re-planning rate [Hz] (default 25, paper B).
        name: planner name for summaries.
        timing_gain: how fast the estimate of (executed − requested) step duration follows each
            touch-down, in [0, 1]; 0 asks the loop for the planned t̃ + τ as it is (see the module doc) [-].
        max_timing_offset: bound of that estimate [s].
    """

    def __init__(self, path: Path, params: TimedMpccParams, obstacles: Sequence[Obstacle] = (),
                 rate_hz: float = WITHIN_STEP_RATE_HZ, name: str = "mpcc", timing_gain: float = 0.5,
                 max_timing_offset: float = 0.08) -> None:
        if not isinstance(params, TimedMpccParams):
            raise ParameterError("params", params, "a TimedMpccParams")
        source = MpccSourceParams(rate_hz=rate_hz, timing_gain=timing_gain, max_timing_offset=max_timing_offset)
        if params.min_time_to_touchdown > 1.0 / source.rate_hz + 1e-12:
            raise ParameterError("min_time_to_touchdown", params.min_time_to_touchdown,
                                 f"at most the re-planning period 1/{source.rate_hz:g} Hz [s] (else every step ends at T_max)")
        self.timed_params = params
        super().__init__(path, params.mpcc, obstacles, source, name)
        self.planner = TimedMpccPlanner(path, params, name=name, within_step=True)  # type: ignore[assignment]
        self.reset()

    def warm_up(self) -> None:
        """Build the solvers now (one solve from rest at the start of the path), then :meth:`reset`."""
        p0 = self.path.position(0.0)
        x0 = np.array([p0[0], 0.0, p0[1], 0.0, float(self.path.slope(0.0))])
        try:
            self.planner.solve(x0, 1, self.obstacles, t_now=0.0, time_since_touchdown=0.0,
                               stance_foot=np.array(p0, dtype=float), theta_init=0.0)
        except NoFallbackPlanError:
            pass  # the solvers are built all the same
        self.reset()

    def plan(self, inp: PlannerInput) -> StepPlan:
        """Foothold, heading and duration of the current swing from the timed MPCC: the loop's clock is
        asked for t̃ + τ − the learned timing offset (see the module doc)."""
        if not isinstance(inp, PlannerInput):
            raise ParameterError("inp", inp, "a lipmpcc.planners.base.PlannerInput")
        if int(inp.step_index) != self._last_step:
            self._update_timing(inp)
        self._last_step = int(inp.step_index)
        t_since = float(inp.time_since_touchdown)
        inp = replace(inp, obstacles=tuple(self.obstacles))  # the source's obstacles (the loop's input has none)
        try:
            plan = self.planner.plan(inp)
        except NoFallbackPlanError as exc:
            return self._step_in_place(inp, f"failed: {exc.status}")
        res = plan.record
        status = "fallback" if res.used_fallback else res.status
        rec = MpccPlanRecord(float(inp.t), int(inp.step_index), t_since, np.asarray(res.states[0], dtype=float).copy(),
                             float(inp.t) + float(res.remaining), float(plan.duration), res, status)
        self.records.append(rec)
        clock = self.clock_duration(float(plan.duration))
        return StepPlan(foothold=plan.foothold, yaw=plan.yaw, duration=clock, com_target=plan.com_target,
                        preview=plan.preview, cost=plan.cost, solve_time=plan.solve_time, status=plan.status, record=rec)

    def clock_duration(self, planned: float) -> float:
        """The duration [s] asked of the loop's clock for a planned step duration ``planned`` [s]:
        ``planned`` − the learned offset (executed − requested), so that the foot meets the ground at the
        planned time (remembered as the request of this step)."""
        self._requested = max(float(planned) - self._offset, 1e-3)
        return self._requested

    def _step_in_place(self, inp: PlannerInput, status: str) -> StepPlan:
        """No plan at all (the first solve failed): a step under the COM, half the reachability
        rectangle's lateral range to the swing side, at the nominal duration (or now, if later)."""
        self.failures += 1
        side = 1 if inp.stance_side != LEFT else -1
        h = float(inp.stance_yaw)
        c = np.asarray(inp.com_pos, dtype=float)
        foot = self.step_under_com(c[0], c[1], h, side)
        duration = max(self.params.model.T, float(inp.time_since_touchdown) + 1.0 / self.rate_hz)
        x0 = np.array([c[0], float(inp.com_vel[0]), c[1], float(inp.com_vel[1]), h])
        rec = MpccPlanRecord(float(inp.t), int(inp.step_index), float(inp.time_since_touchdown), x0,
                             float(inp.t) + duration - float(inp.time_since_touchdown), duration, None, status)
        self.records.append(rec)
        return StepPlan(foot, h, self.clock_duration(duration), status=status, record=rec)
