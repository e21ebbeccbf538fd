"""Paper A's MPCC as a footstep source of the full-body loop (paper A Fig. 4).

The loop calls :meth:`MpccFootstepSource.plan` at 15 Hz (paper A). Each call:

1. predicts, with the LIP about the current stance foot, the COM state at the coming support
   exchange (after the remaining ``T − t̃`` of the step);
2. solves the MPCC from that state, for the swing foot (the next stance foot), with the
   obstacles predicted from the time of that exchange;
3. returns the first planned foothold and heading, the step duration T, the COM target and the
   preview of the following footholds.

The first solve after a touch-down is one step after the previous plan (warm start from the
shifted plan); the re-plans during the same swing refine it (warm start from the unshifted plan).
A planner failure is survived: the MPCC's own fallback (the previous plan) is used and counted,
and on a failure with no previous plan the source steps in place under the COM.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..exceptions import NoFallbackPlanError, ParameterError
from ..obstacles import Obstacle
from ..paths import Path
from ..sim.fullbody_loop import LEFT, PlannerInput, StepPlan
from .mpcc import MpccParams, MpccPlanner


class MpccFootstepSource:
    """MPCC footstep planner for :class:`~lipmpcc.sim.fullbody_loop.FullBodyLoop`.

    Args:
        path: reference path.
        params: MPCC parameters (its model's T is the step duration).
        obstacles: moving obstacles (their clocks are the simulation time).
        rate_hz: re-planning rate [Hz] (paper A: 15 Hz).
        name: planner name for summaries (``"mpcc"`` or ``"cartesian"``).
    """

    def __init__(
        self,
        path: Path,
        params: MpccParams,
        obstacles: Sequence[Obstacle] = (),
        rate_hz: float = 15.0,
        name: str = "mpcc",
    ) -> None:
        if not (math.isfinite(rate_hz) and rate_hz > 0):
            raise ParameterError("rate_hz", rate_hz, "a positive re-planning rate [Hz]")
        self.path = path
        self.params = params
        self.obstacles = list(obstacles)
        self.rate_hz = float(rate_hz)
        self.name = name
        self.planner = MpccPlanner(path, params)
        self.results: list = []
        self.times: list[float] = []
        self.failures = 0
        self._last_step = -1

    def reset(self) -> None:
        self.planner.reset()
        self.results = []
        self.times = []
        self.failures = 0
        self._last_step = -1

    def predicted_exchange_state(self, inp: PlannerInput) -> tuple[np.ndarray, float]:
        """LIP state [x, ẋ, y, ẏ, heading] at the coming support exchange and the time left [s]."""
        T = self.params.model.T
        w = self.params.model.omega
        t_left = max(T - float(inp.time_since_touchdown), 0.0)
        ch, sh = math.cosh(w * t_left), math.sinh(w * t_left)
        x = np.empty(5)
        for i, (pi, vi) in enumerate(((0, 1), (2, 3))):
            r0 = float(inp.com_pos[i] - inp.stance_pos[i])
            v0 = float(inp.com_vel[i])
            x[pi] = inp.stance_pos[i] + r0 * ch + v0 * sh / w
            x[vi] = r0 * w * sh + v0 * ch
        x[4] = float(inp.stance_yaw)
        return x, t_left

    def plan(self, inp: PlannerInput) -> StepPlan:
        T = self.params.model.T
        x0, t_left = self.predicted_exchange_state(inp)
        side = 1 if inp.stance_side != LEFT else -1  # the swing foot lands next: +1 when it is the left
        shift = inp.step_index != self._last_step  # first solve of this swing: one step after the last plan
        self._last_step = inp.step_index
        try:
            res = self.planner.solve(x0, side, self.obstacles, t_now=float(inp.t) + t_left, shift=shift)
        except NoFallbackPlanError as exc:
            self.failures += 1
            lat = 0.5 * sum(self.params.rectangle.lateral) * side
            h = x0[4]
            foot = np.array([x0[0] - math.sin(h) * lat, x0[2] + math.cos(h) * lat])
            return StepPlan(foot, h, T, status=f"failed: {exc.status}")
        self.results.append(res)
        self.times.append(res.solve_time)
        u = res.u0
        foothold = np.array([x0[0] + u[0], x0[2] + u[1]])
        preview = np.column_stack([res.footsteps[:, 0], res.footsteps[:, 1], res.footsteps[:, 2], np.full(len(res.footsteps), T)])
        return StepPlan(
            foothold=foothold,
            yaw=float(x0[4] + u[2]),
            duration=T,
            com_target=res.states[1, [0, 2]],
            preview=preview,
            cost=res.cost,
            solve_time=res.solve_time,
            status="fallback" if res.used_fallback else res.status,
        )

    @property
    def solver_failures(self) -> int:
        """Solves that failed (the fallback plan or the step-in-place was used)."""
        return self.planner.failures + self.failures
