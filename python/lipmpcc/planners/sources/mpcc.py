"""Paper A's MPCC as a footstep source of the full-body loop (paper A Fig. 4).

The loop calls :meth:`MpccFootstepSource.plan` at 15 Hz (paper A). Each call:

1. predicts, with the LIP about the measured stance foot, the COM state at the coming support
   exchange, ``T − t̃`` ahead (t̃ the time since touch-down)::

       c(T) = p + (c − p) cosh ωτ + ċ sinh(ωτ)/ω,   ċ(T) = (c − p) ω sinh ωτ + ċ cosh ωτ,   τ = T − t̃

   with the heading of the stance foot;
2. solves the MPCC from that state for the swing foot (the next stance foot), with the obstacles
   predicted from the time of that exchange;
3. returns the first planned foothold x_0 + u_0 and heading θ_0 + u^θ_0, the step duration, the
   COM target (the planned state at the following exchange) and the preview of the next footholds.

The first solve of a swing is one step after the previous plan (warm start from the shifted plan);
the re-plans during the same swing refine it from fresher measurements (``shift=False``).

**Step timing.** The MPCC's LIP assumes steps of exactly ``T``; the loop's swing foot usually meets
the ground a little before its clock ends (touch-down is detected from contact). The source learns
the offset between the actual and the requested step durations from the touch-downs it sees
(exponential average with gain ``timing_gain``, bounded by ``max_timing_offset``) and asks the loop
for ``T − offset``, so that the real steps last ≈ T, as in the model (capture_point.py predicts the
DCM at the shifted end instead; here the model's T is kept for every step of the horizon).

**Path parameter.** The first solve's θ_init is the closest point to the predicted COM searched
around θ = 0 (a closed path, e.g. 1.25 turns of a circle, passes its start twice); the following
ones search around the previous plan (:meth:`~lipmpcc.paths.Path.closest_point`).

**Failures** are survived and counted: the MPCC's own fallback (the previous plan, replayed from the
new state) is used, and on a failure with no previous plan the source steps under the COM, half the
reachability rectangle's lateral range to the swing side; either plan's status is not ``"ok"``.

Every call is kept in :attr:`MpccFootstepSource.records` (:class:`MpccPlanRecord`, also each plan's
``record``) for the metrics and the figures of paper A.

**The timed MPCC** (paper A's MPCC with paper B's step timing; until issue 24 in ``sources/mpcc_timed.py``):
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
the foot meets the ground at the planned time t̃ + τ; once a re-plan asks to land now (τ = 0: the foot is late),
the step's later re-plans cannot put the clock's end later (:meth:`TimedMpccFootstepSource.clock_duration`). The
records and the plans' ``record`` keep the
planned t̃ + τ (``duration``); the :class:`~lipmpcc.planners.base.StepPlan` carries the clock's.

Every call is recorded as an :class:`~lipmpcc.planners.sources.mpcc.MpccPlanRecord` (``x0`` the planned
state at the coming exchange, ``t_exchange`` its time, ``duration`` t̃ + τ), so the metrics and figures of
paper A read it unchanged. Failures are survived and counted as in the fixed-T source.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from ...conventions import LEFT
from ...exceptions import NoFallbackPlanError, ParameterError
from ...validation import check_field_types
from ...models.lip import lip_solution
from ...obstacles import Obstacle
from ...paths import Path
from ..base import PlannerInput, StepPlan
from ...models.lip3d import ReachabilityRectangle
from ..mpcc import MpccParams, MpccPlanner, MpccResult
from ..mpcc_timed import TimedMpccParams, TimedMpccPlanner

__all__ = ["MpccSourceParams", "exchange_mismatches", "MpccPlanRecord", "MpccFootstepSource", "TimedMpccFootstepSource", "WITHIN_STEP_RATE_HZ",
           "REACH_TOLERANCE", "within_rectangle"]


#: [s] a timed plan whose remaining time τ is at most this asks to land now (τ at its bound 0: the foot is late)
_DUE = 1e-6

#: [m, rad] how far a foothold may lie outside the reachability rectangle before :func:`within_rectangle` moves it
#: (the SQP meets its rows to about 1e-6: a plan it converged on is handed over as it is)
REACH_TOLERANCE = 1e-3


def within_rectangle(foothold: np.ndarray, yaw: float, state: np.ndarray, swing_left: bool,
                     rect: ReachabilityRectangle, tol: float = REACH_TOLERANCE) -> tuple[np.ndarray, float, bool]:
    """The foothold (x, y) [m] and yaw [rad] brought within the reachability rectangle ``rect`` (eq. 15: the
    robot's own reach from its layout, :func:`~lipmpcc.studies.path_following.robot_rectangle`) about the
    predicted COM at the exchange, ``state`` = [x, ẋ, y, ẏ, heading]: the turn from the heading clipped to
    ``rect.heading``, the offset from the COM to ``rect.forward`` and, to the swing side, ``rect.lateral``, in
    the frame of the (clipped) new yaw, as the MPCC's rows read it. Nothing moves unless a bound is exceeded by
    more than ``tol``. Returns (foothold, yaw, clipped).

    A converged plan is within by construction; the fallback's replayed plan (its offsets applied to a state
    and a measured heading it did not plan for) and the step under the COM need not be: whatever the planner
    produced, the full body is handed a step its legs reach."""
    cx, cy, h = float(state[0]), float(state[2]), float(state[4])
    turn = math.remainder(float(yaw) - h, 2.0 * math.pi)
    turn_c = min(max(turn, rect.heading[0]), rect.heading[1])
    psi = h + turn_c
    c, s = math.cos(psi), math.sin(psi)
    dx, dy = float(foothold[0]) - cx, float(foothold[1]) - cy
    fwd, lat = c * dx + s * dy, -s * dx + c * dy
    side = 1.0 if swing_left else -1.0
    fwd_c = min(max(fwd, rect.forward[0]), rect.forward[1])
    lat_c = side * min(max(side * lat, rect.lateral[0]), rect.lateral[1])
    if max(abs(fwd_c - fwd), abs(lat_c - lat), abs(turn_c - turn)) <= tol:
        return np.asarray(foothold, dtype=float), float(yaw), False
    return np.array([cx + c * fwd_c - s * lat_c, cy + s * fwd_c + c * lat_c]), psi, True


@dataclass(frozen=True)
class MpccSourceParams:
    """Parameters of :class:`MpccFootstepSource` beyond the MPCC's (times [s]).

    Attributes:
        rate_hz: re-planning rate [Hz] (paper A: 15 Hz).
        timing_gain: how fast the estimate of (actual − requested) step duration follows each new
            touch-down, in [0, 1]; 0 disables the compensation (the loop is asked for T) [-].
        max_timing_offset: bound of that estimate [s].
    """

    rate_hz: float = 15.0
    timing_gain: float = 0.5
    max_timing_offset: float = 0.08

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if not (math.isfinite(self.rate_hz) and self.rate_hz > 0):
            raise ParameterError("rate_hz", self.rate_hz, "a positive re-planning rate [Hz]")
        if not (math.isfinite(self.timing_gain) and 0.0 <= self.timing_gain <= 1.0):
            raise ParameterError("timing_gain", self.timing_gain, "a gain in [0, 1]")
        if not (math.isfinite(self.max_timing_offset) and self.max_timing_offset >= 0.0):
            raise ParameterError("max_timing_offset", self.max_timing_offset, "a non-negative time [s]")


@dataclass(frozen=True)
class MpccPlanRecord:
    """One call of the source.

    Attributes:
        t: simulated time of the call [s].
        step_index: touch-downs before the call: the call is made in the swing that ends at the touch-down
            of 0-based index ``step_index``, and ``x0`` predicts the state there.
        time_since_touchdown: t̃ [s].
        x0: predicted LIP state [x, ẋ, y, ẏ, heading] at the coming exchange.
        t_exchange: predicted time of that exchange [s].
        duration: step duration asked of the loop [s].
        result: the MPCC solve (None when the first solve failed and the source stepped in place).
        status: ``"converged"``, ``"fallback"`` or ``"failed: ..."``.
    """

    t: float
    step_index: int
    time_since_touchdown: float
    x0: np.ndarray
    t_exchange: float
    duration: float
    result: MpccResult | None
    status: str


class MpccFootstepSource:
    """MPCC footstep planner for :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop`.

    Implements the planner contract, :class:`~lipmpcc.planners.base.FootstepSource`.

    Args:
        path: reference path.
        params: MPCC parameters (its model's T is the step duration, its H should be the loop's
            COM height).
        obstacles: moving obstacles (their clocks are the simulation time).
        source_params: :class:`MpccSourceParams` (rate, timing compensation).
        name: planner name for summaries (``"mpcc"`` or ``"cartesian"``).
        guard: every foothold handed to the loop is brought within the MPCC's reachability rectangle (the
            robot's own reach) about the predicted COM (:func:`within_rectangle`; ``clipped_steps`` counts the
            steps where that moved it); False: as planned.
    """

    #: it learns the executed-vs-requested touch-down offset itself: the loop ends a step at the contact
    compensates_touchdown = True

    def __init__(
        self,
        path: Path,
        params: MpccParams,
        obstacles: Sequence[Obstacle] = (),
        source_params: MpccSourceParams | None = None,
        name: str = "mpcc",
        guard: bool = True,
    ) -> None:
        if not isinstance(params, MpccParams):
            raise ParameterError("params", params, "an MpccParams")
        if source_params is not None and not isinstance(source_params, MpccSourceParams):
            raise ParameterError("source_params", source_params, "an MpccSourceParams or None")
        if isinstance(obstacles, (str, bytes, Obstacle)) or not hasattr(obstacles, "__iter__"):
            raise ParameterError("obstacles", obstacles, "a list of lipmpcc.obstacles.Obstacle")
        obstacles = list(obstacles)
        if not all(isinstance(ob, Obstacle) for ob in obstacles):
            raise ParameterError("obstacles", obstacles, "a list of lipmpcc.obstacles.Obstacle")
        self.path = path
        self.params = params
        self.source_params = source_params or MpccSourceParams()
        self.obstacles = list(obstacles)
        self.rate_hz = float(self.source_params.rate_hz)
        self.name = name
        if not isinstance(guard, bool):
            raise ParameterError("guard", guard, "True or False")
        self.guard = guard
        self.planner = MpccPlanner(path, params)
        self.reset()

    # ---- lifetime ----------------------------------------------------------------------------
    def reset(self) -> None:
        """Forget the previous plan, the records, the failure count and the timing estimate."""
        self.planner.reset()
        self.records: list[MpccPlanRecord] = []
        self.failures = 0
        self._last_step = -1
        self._t_td_prev: float | None = None
        self._requested: float | None = None
        self._offset = 0.0
        self._omega_checked = False
        self._clipped: set[int] = set()

    @property
    def clipped_steps(self) -> int:
        """Steps whose foothold (or yaw) was brought within the robot's reach (:func:`within_rectangle`)."""
        return len(self._clipped)

    def _reachable(self, foot: np.ndarray, yaw: float, state: np.ndarray, inp: PlannerInput,
                   swing_left: bool) -> tuple[np.ndarray, float]:
        """``foot`` (x, y) [m] and ``yaw`` [rad] within the reachability rectangle about the predicted exchange
        ``state`` (:func:`within_rectangle`; as they are without :attr:`guard`)."""
        if not self.guard:
            return foot, yaw
        foot, yaw, clipped = within_rectangle(foot, yaw, state, swing_left, self.params.rectangle)
        if clipped:
            self._clipped.add(int(inp.step_index))
        return foot, yaw

    def warm_up(self) -> None:
        """Build (and JIT-compile) the solvers now, outside a timed run, then :meth:`reset`.

        One solve from rest at the start of the path, heading along it.
        """
        p0 = self.path.position(0.0)
        x0 = np.array([p0[0], 0.0, p0[1], 0.0, float(self.path.slope(0.0))])
        try:
            self.planner.solve(x0, 1, self.obstacles, t_now=0.0, theta_init=0.0)
        except NoFallbackPlanError:
            pass  # the solvers are built all the same
        self.reset()

    # ---- results -----------------------------------------------------------------------------
    @property
    def solver_failures(self) -> int:
        """Solves that failed (the fallback plan or the step-in-place was used)."""
        return self.planner.failures + self.failures

    @property
    def solve_times(self) -> list[float]:
        """Wall time of every MPCC solve [s] (θ_init search included, as in paper A)."""
        return [r.result.solve_time for r in self.records if r.result is not None]

    @property
    def timing_offset(self) -> float:
        """Current estimate of (actual − requested) step duration [s]."""
        return self._offset

    def exchange_mismatches(self) -> tuple[np.ndarray, np.ndarray]:
        """How far the robot ends each step from the state the executed plan predicted.

        For each step k whose swing was planned (records with ``step_index`` k − 1) and re-planned
        after its touch-down (records with ``step_index`` k): the first call of step k predicts, from
        the robot measured at touch-down k − 1, the state ``x0`` at the coming exchange; the last plan of
        step k − 1 (the one executed) predicted that state as its ``states[1]``, with the LIP. On the
        LIP the two are equal; on a full body the difference is the model mismatch of one step
        (COM tracking, impact, foot placement and timing errors), propagated over T.

        Returns:
            ``steps`` (n,) the step indices k, and ``mismatch`` (n, 5): x0 − predicted,
            [x [m], ẋ [m/s], y [m], ẏ [m/s], heading [rad]] (world frame).
        """
        return exchange_mismatches(self.records)

    # ---- planning ----------------------------------------------------------------------------
    def predicted_exchange_state(self, inp: PlannerInput) -> tuple[np.ndarray, float]:
        """LIP state [x, ẋ, y, ẏ, heading] at the coming support exchange and the time left [s]."""
        T = self.params.model.T
        w = self.params.model.omega
        t_left = max(T - float(inp.time_since_touchdown), 0.0)
        c0 = np.asarray(inp.com_pos, dtype=float)[:2]
        v0 = np.asarray(inp.com_vel, dtype=float)[:2]
        c, v, _ = lip_solution(c0, v0, np.asarray(inp.stance_pos, dtype=float)[:2], w, t_left)
        return np.array([c[0], v[0], c[1], v[1], float(inp.stance_yaw)]), t_left

    def _update_timing(self, inp: PlannerInput) -> None:
        """At the first call of a step, learn (actual − requested) duration of the step just ended."""
        sp = self.source_params
        t_td = float(inp.t) - float(inp.time_since_touchdown)
        if self._t_td_prev is not None and self._requested is not None and sp.timing_gain > 0.0:
            err = (t_td - self._t_td_prev) - self._requested
            self._offset += sp.timing_gain * (err - self._offset)
            self._offset = float(np.clip(self._offset, -sp.max_timing_offset, sp.max_timing_offset))
        self._t_td_prev = t_td

    def step_under_com(self, x: float, y: float, heading: float, side: int) -> np.ndarray:
        """The foothold when there is no plan at all: under the COM (x, y) [m], half the reachability
        rectangle's lateral range to the swing ``side`` (+1 left), across ``heading`` [rad]."""
        lat = 0.5 * sum(self.params.rectangle.lateral) * side
        return np.array([x - math.sin(heading) * lat, y + math.cos(heading) * lat])

    def plan(self, inp: PlannerInput) -> StepPlan:
        """Foothold, heading and duration of the current swing foot from the MPCC (paper A Fig. 4)."""
        if not isinstance(inp, PlannerInput):
            raise ParameterError("inp", inp, "a lipmpcc.planners.base.PlannerInput")
        T = self.params.model.T
        if not self._omega_checked and math.isfinite(inp.omega):
            self._omega_checked = True
            w = self.params.model.omega
            if abs(inp.omega - w) > 0.01 * w:
                warnings.warn(
                    f"the MPCC's LIP has ω = {w:.3f} 1/s (H = {self.params.model.H:.3f} m) but the loop's COM reference "
                    f"uses ω = {inp.omega:.3f} 1/s: give the MPCC's model the loop's COM height",
                    stacklevel=2,
                )
        new_step = inp.step_index != self._last_step
        if new_step:
            self._update_timing(inp)
        duration = max(T - self._offset, 1e-3)
        self._requested = duration
        x0, t_left = self.predicted_exchange_state(inp)
        side = 1 if inp.stance_side != LEFT else -1  # the swing foot lands next: +1 when it is the left
        shift = new_step  # first solve of this swing: one step after the last plan
        self._last_step = inp.step_index
        t_ex = float(inp.t) + t_left
        theta_init = None
        if self.planner.last is None:  # start of the run: search near the start of the path
            theta_init = self.path.closest_point([x0[0], x0[2]], theta_prev=0.0)
        try:
            res = self.planner.solve(x0, side, self.obstacles, t_now=t_ex, theta_init=theta_init, shift=shift)
        except NoFallbackPlanError as exc:
            self.failures += 1
            h = x0[4]
            foot, h = self._reachable(self.step_under_com(x0[0], x0[2], h, side), float(h), x0, inp, side == 1)
            status = f"failed: {exc.status}"
            rec = MpccPlanRecord(float(inp.t), int(inp.step_index), float(inp.time_since_touchdown), x0, t_ex,
                                 duration, None, status)
            self.records.append(rec)
            return StepPlan(foot, float(h), duration, status=status, record=rec)
        status = "fallback" if res.used_fallback else res.status
        rec = MpccPlanRecord(float(inp.t), int(inp.step_index), float(inp.time_since_touchdown), x0, t_ex, duration,
                             res, status)
        self.records.append(rec)
        u = res.u0
        foothold, yaw = self._reachable(np.array([x0[0] + u[0], x0[2] + u[1]]), float(x0[4] + u[2]), x0, inp, side == 1)
        preview = np.column_stack([res.footsteps[:, 0], res.footsteps[:, 1], res.footsteps[:, 2], np.full(len(res.footsteps), T)])
        return StepPlan(
            foothold=foothold,
            yaw=yaw,
            duration=duration,
            com_target=res.states[1, [0, 2]],
            preview=preview,
            cost=res.cost,
            solve_time=res.solve_time,
            status="fallback" if res.used_fallback else "ok",
            record=rec,
        )


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
        guard: as for :class:`MpccFootstepSource`.
    """

    def __init__(self, path: Path, params: TimedMpccParams, obstacles: Sequence[Obstacle] = (),
                 rate_hz: float = WITHIN_STEP_RATE_HZ, name: str = "mpcc", timing_gain: float = 0.5,
                 max_timing_offset: float = 0.08, guard: bool = True) -> None:
        if not isinstance(params, TimedMpccParams):
            raise ParameterError("params", params, "a TimedMpccParams")
        source = MpccSourceParams(rate_hz=rate_hz, timing_gain=timing_gain, max_timing_offset=max_timing_offset)
        if params.min_time_to_touchdown > 1.0 / source.rate_hz + 1e-12:
            raise ParameterError("min_time_to_touchdown", params.min_time_to_touchdown,
                                 f"at most the re-planning period 1/{source.rate_hz:g} Hz [s] (else every step ends at T_max)")
        self.timed_params = params
        super().__init__(path, params.mpcc, obstacles, source, name, guard)
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
        first = int(inp.step_index) != self._last_step
        if first:
            self._update_timing(inp)
            self._committed = None
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
        # a plan that asks to land now (τ = 0, its bound) cannot put the step's clock end off (clock_duration)
        if not first and self._committed is None and float(res.remaining) <= _DUE:
            self._committed = self._requested
        clock = self.clock_duration(float(plan.duration), self._committed)
        foot, yaw = self._reachable(np.asarray(plan.foothold, dtype=float), float(plan.yaw), np.asarray(res.states[0], dtype=float),
                                    inp, inp.stance_side != LEFT)
        return StepPlan(foothold=foot, yaw=yaw, duration=clock, com_target=plan.com_target,
                        preview=plan.preview, cost=plan.cost, solve_time=plan.solve_time, status=plan.status, record=rec)

    def reset(self) -> None:
        """Forget the previous plan, the records, the failure count, the timing estimate and the step's commitment."""
        super().reset()
        self._committed: float | None = None

    def clock_duration(self, planned: float, committed: float | None = None) -> float:
        """The duration [s] asked of the loop's clock for a planned step duration ``planned`` [s]:
        ``planned`` − the learned offset (executed − requested), so that the foot meets the ground at the
        planned time, and not more than ``committed`` [s] (remembered as the request of this step).

        :meth:`plan` passes as ``committed`` the step's request made before its first plan that asks to land
        now (τ = 0, its lower bound: the foot is late, and the plan cannot ask for earlier): the re-plans that follow
        only because the foot has not met the ground yet may bring the end closer, never put it off. A plan with
        τ > 0 is the planner's own choice of time and is asked for as it is.

        Why (issue 31, ``digit_like``, timed 0.3–0.5 s, follow-path, random scene 11, fell at 55.7 s): the
        learned offset is negative on ``digit_like`` (the foot meets the ground before the clock's end: −0.076 s
        there). A foot not down at the planned time left the re-plans at τ = 0 ("land now"), each of which
        asked the clock for t̃ + 0.076 s, so every re-plan 40 ms later moved the swing's end on by 40 ms: the
        end ran ahead of the clock, the swing foot, re-timed at each re-plan, did not come down, and a step
        planned at 0.382 s landed after 0.598 s (T_max 0.5 s), on the foothold frozen at the swing's phase 0.85,
        0.29 m short of the last plan's, with the COM 0.09 m past it at 1.25 m/s. No plan exists from there (≥ T_min = 0.3 s more about that foot, then eq. 16's δ_max = 0.4 m per step: the QP is
        infeasible), 43 solves failed in a row, and the replayed plans ran the robot to its fall."""
        req = max(float(planned) - self._offset, 1e-3)
        if committed is not None:
            req = min(req, float(committed))
        self._requested = req
        return self._requested

    def _step_in_place(self, inp: PlannerInput, status: str) -> StepPlan:
        """No plan at all (the first solve failed): a step under the COM, half the reachability
        rectangle's lateral range to the swing side, at the nominal duration (or now, if later)."""
        self.failures += 1
        side = 1 if inp.stance_side != LEFT else -1
        h = float(inp.stance_yaw)
        c = np.asarray(inp.com_pos, dtype=float)
        x_now = np.array([c[0], 0.0, c[1], 0.0, h])
        foot, h = self._reachable(self.step_under_com(c[0], c[1], h, side), h, x_now, inp, side == 1)
        duration = max(self.params.model.T, float(inp.time_since_touchdown) + 1.0 / self.rate_hz)
        x0 = np.array([c[0], float(inp.com_vel[0]), c[1], float(inp.com_vel[1]), h])
        rec = MpccPlanRecord(float(inp.t), int(inp.step_index), float(inp.time_since_touchdown), x0,
                             float(inp.t) + duration - float(inp.time_since_touchdown), duration, None, status)
        self.records.append(rec)
        return StepPlan(foot, h, self.clock_duration(duration), status=status, record=rec)


def exchange_mismatches(records: Sequence[MpccPlanRecord]) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`MpccFootstepSource.exchange_mismatches` of a source's ``records`` (also of records kept after the
    source is gone, e.g. a run loaded from :mod:`lipmpcc.studies.run_cache`).

    Returns:
        ``steps`` (n,) the step indices k, and ``mismatch`` (n, 5): x0 − predicted,
        [x [m], ẋ [m/s], y [m], ẏ [m/s], heading [rad]] (world frame).
    """
    first: dict[int, MpccPlanRecord] = {}
    last: dict[int, MpccPlanRecord] = {}
    for rec in records:
        first.setdefault(rec.step_index, rec)
        if rec.result is not None:
            last[rec.step_index] = rec
    steps = [k for k in sorted(first) if k - 1 in last]
    out = np.array([first[k].x0 - last[k - 1].result.states[1] for k in steps], dtype=float).reshape(-1, 5)
    return np.array(steps, dtype=int), out
