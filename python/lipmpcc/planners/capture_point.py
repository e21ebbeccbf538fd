"""Capture-point (LIP/DCM) foot placement that tracks a commanded speed and yaw rate — no MPC.

At each call the planner predicts the DCM at the end of the step from the measured DCM ξ and the
stance foot p (LIP: ξ(t) = p + (ξ_now − p) e^{ω(T − t̃)}, t̃ the time since touch-down) and places the
swing foot so that, after the support exchange, the DCM sits at the offset of the nominal periodic gait
(SPEC §2, paper B):

    p_next = ξ_end − R(ψ_next) b,   b = [L/(σ − 1),  −s·w/(σ + 1)],   σ = e^{ωT},

with L = v·T the step length for the commanded speed v, w the nominal step width, s = +1 when the
left foot swings (−1 for the right) and ψ_next = ψ_stance + ψ̇·T the next heading for the commanded
yaw rate ψ̇. In the nominal gait this gives exactly steps of length L and speed L/T. The step relative
to the stance foot, in the next heading frame, is then clipped to a reachable rectangle whose lateral
bounds keep the legs from crossing, and the heading change per step is limited.

Three additions make it work on a full-body robot rather than on the LIP alone:

- **Step-timing adaptation.** When the nominal foothold is out of reach, the duration in
  [min_duration, max_duration] that minimises the clipping error (plus a small cost on T − T_nom) is
  returned instead; the loop re-times the swing (SPEC §2). This escapes the sideways drift a lateral
  push otherwise locks the clipped steps into.
- **Touch-down timing offset.** A swing foot usually meets the ground a little before the clock
  (τ ≈ 0.95): the planner learns the offset between actual and planned step durations from the touch-down
  times it sees and predicts the DCM at the step's *actual* end.
- **Speed integrator.** After each touch-down the forward-speed error over the last step is integrated
  into the step length (``speed_gain``), which absorbs the remaining mismatch between the robot and the
  LIP (COM height, leg masses, tracking errors).

The command (speed, yaw rate) is ramped with acceleration limits so that a run can start from rest.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..conventions import LEFT
from ..exceptions import InvalidInputError, ParameterError
from ..validation import check_field_types
from ..models.lip import STEP_DURATION, lip_solution
from ..rotations import wrap_angle
from .base import PlannerInput, StepPlan

__all__ = ["CapturePointParams", "CapturePointPlanner", "nominal_dcm_offset"]


@dataclass(frozen=True)
class CapturePointParams:
    """Parameters of :class:`CapturePointPlanner` (lengths [m], times [s], angles [rad]).

    Attributes:
        step_duration: step duration T (touch-down to touch-down) [s].
        step_width: nominal lateral distance between the feet w [m].
        max_step_forward, max_step_backward: bounds of the step along the heading [m].
        min_step_width, max_step_width: bounds of the lateral distance between the feet [m].
        max_yaw_step: largest heading change per step [rad].
        max_speed: largest commanded speed [m/s].
        max_yaw_rate: largest commanded yaw rate [rad/s].
        max_accel: ramp of the commanded speed [m/s²].
        max_yaw_accel: ramp of the commanded yaw rate [rad/s²].
        rate_hz: how often the loop calls the planner [Hz].
        min_duration, max_duration: range of step durations tried when the nominal step is not
            reachable (step-timing adaptation); equal to ``step_duration`` to keep T fixed [s].
        duration_weight: weight of (T − T_nom)² against the squared clipping error [1/s²·m²].
        speed_gain: integral gain of the speed correction, per step [-]: after each touch-down the
            correction grows by ``speed_gain`` × (commanded − measured forward speed over the last
            step); 0 disables it (pure LIP placement).
        max_speed_correction: bound of that correction [m/s].
        timing_gain: how fast the estimate of the touch-down timing offset (actual minus planned
            step duration, e.g. the swing foot touching the ground a little before the clock)
            follows each new touch-down, in [0, 1]; the DCM is predicted at the planned end of the
            step plus this offset [-]. 0 disables it.
        max_timing_offset: bound of that offset [s].
    """

    step_duration: float = STEP_DURATION
    step_width: float = 0.26
    max_step_forward: float = 0.55
    max_step_backward: float = 0.35
    min_step_width: float = 0.14
    max_step_width: float = 0.50
    max_yaw_step: float = 0.35
    max_speed: float = 1.0
    max_yaw_rate: float = 1.0
    max_accel: float = 0.6
    max_yaw_accel: float = 0.6
    rate_hz: float = 50.0
    min_duration: float = 0.3
    max_duration: float = 0.5
    duration_weight: float = 0.05
    speed_gain: float = 0.3
    max_speed_correction: float = 0.25
    timing_gain: float = 0.5
    max_timing_offset: float = 0.08

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        pos = {
            "step_duration": self.step_duration,
            "step_width": self.step_width,
            "max_step_forward": self.max_step_forward,
            "max_step_backward": self.max_step_backward,
            "min_step_width": self.min_step_width,
            "max_step_width": self.max_step_width,
            "max_yaw_step": self.max_yaw_step,
            "max_speed": self.max_speed,
            "max_yaw_rate": self.max_yaw_rate,
            "max_accel": self.max_accel,
            "max_yaw_accel": self.max_yaw_accel,
            "rate_hz": self.rate_hz,
            "min_duration": self.min_duration,
            "max_duration": self.max_duration,
        }
        for name, v in pos.items():
            if not (math.isfinite(v) and v > 0.0):
                raise ParameterError(name, v, "a positive finite number")
        if not self.min_duration <= self.step_duration <= self.max_duration:
            raise ParameterError(
                "step_duration",
                self.step_duration,
                f"within [min_duration, max_duration] = [{self.min_duration}, {self.max_duration}]",
            )
        if not (math.isfinite(self.timing_gain) and 0.0 <= self.timing_gain <= 1.0):
            raise ParameterError("timing_gain", self.timing_gain, "a gain in [0, 1]")
        for name in ("speed_gain", "max_speed_correction", "max_timing_offset"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ParameterError(name, v, "a non-negative finite number")
        if not (math.isfinite(self.duration_weight) and self.duration_weight >= 0.0):
            raise ParameterError("duration_weight", self.duration_weight, "a non-negative number")
        if self.min_step_width > self.max_step_width:
            raise ParameterError(
                "min_step_width", self.min_step_width, f"at most max_step_width = {self.max_step_width}"
            )
        if not self.min_step_width <= self.step_width <= self.max_step_width:
            raise ParameterError(
                "step_width",
                self.step_width,
                f"within [min_step_width, max_step_width] = [{self.min_step_width}, {self.max_step_width}]",
            )


def nominal_dcm_offset(
    step_length: float, step_width: float, omega: float, duration: float, swing_left: bool
) -> np.ndarray:
    """DCM relative to the new stance foot at the start of a step of the nominal periodic gait.

    ξ0 = [L/(σ − 1), −s·w/(σ + 1)] in the heading frame, σ = e^{ωT}, s = +1 when the new stance
    foot is the left one (SPEC §2).

    Args:
        step_length: L [m].
        step_width: w, lateral distance between the feet [m].
        omega: LIP ω [1/s].
        duration: T [s].
        swing_left: True when the foot being placed is the left one.
    """
    sigma = math.exp(omega * duration)
    s = 1.0 if swing_left else -1.0
    return np.array([step_length / (sigma - 1.0), -s * step_width / (sigma + 1.0)])


class CapturePointPlanner:
    """LIP capture-point footstep source tracking a commanded speed and yaw rate.

    Implements the planner contract, :class:`~lipmpcc.planners.base.FootstepSource`.

    Args:
        params: :class:`CapturePointParams`.
        speed: commanded forward speed along the heading [m/s].
        yaw_rate: commanded yaw rate [rad/s] (positive turns left).
        lateral_speed: commanded lateral speed [m/s] (positive to the left).
    """

    name = "capture-point"
    #: it learns the touch-down timing offset itself (``timing_gain``): the loop ends a step at the contact
    compensates_touchdown = True

    def __init__(
        self,
        params: CapturePointParams | None = None,
        speed: float = 0.0,
        yaw_rate: float = 0.0,
        lateral_speed: float = 0.0,
    ) -> None:
        self.params = params or CapturePointParams()
        self.rate_hz = self.params.rate_hz
        self._target = (0.0, 0.0, 0.0)
        self.set_command(speed, yaw_rate, lateral_speed)
        self.reset()

    def set_command(self, speed: float, yaw_rate: float = 0.0, lateral_speed: float = 0.0) -> None:
        """Set the commanded forward speed [m/s], yaw rate [rad/s] and lateral speed [m/s]."""
        p = self.params
        for name, v, lim in (
            ("speed", speed, p.max_speed),
            ("yaw_rate", yaw_rate, p.max_yaw_rate),
            ("lateral_speed", lateral_speed, p.max_speed),
        ):
            if not math.isfinite(v) or abs(v) > lim:
                raise ParameterError(name, v, f"a finite value with |{name}| <= {lim}")
        self._target = (float(speed), float(yaw_rate), float(lateral_speed))

    @property
    def command(self) -> tuple[float, float, float]:
        """Current (ramped) command: speed [m/s], yaw rate [rad/s], lateral speed [m/s]."""
        return self._v, self._yr, self._vy

    def reset(self) -> None:
        """Start the command ramp from rest and clear the speed correction."""
        self._v = 0.0
        self._yr = 0.0
        self._vy = 0.0
        self._t_last: float | None = None
        self._dv = 0.0
        self._dt_td = 0.0
        self._planned_duration: float | None = None
        self._last_step: tuple[int, float, np.ndarray, float] | None = None

    @property
    def timing_offset(self) -> float:
        """Current estimate of (actual − planned) step duration [s]."""
        return self._dt_td

    @property
    def speed_correction(self) -> float:
        """Current integral speed correction added to the commanded speed [m/s]."""
        return self._dv

    def _update_speed_correction(self, inp: PlannerInput) -> None:
        """At the first call of a new step, integrate the forward-speed error of the last step and
        update the touch-down timing offset."""
        p = self.params
        com = np.asarray(inp.com_pos, dtype=float)[:2]
        t_td = inp.t - inp.time_since_touchdown
        last = self._last_step
        if last is not None and inp.step_index == last[0]:
            return
        if last is not None and p.speed_gain > 0.0 and t_td - last[1] > 1e-3:
            heading = np.array([math.cos(inp.stance_yaw), math.sin(inp.stance_yaw)])
            v_meas = float(heading @ (com - last[2])) / (t_td - last[1])
            v_cmd = 0.5 * (self._v + last[3])  # mean command over the step (ramp)
            self._dv += p.speed_gain * (v_cmd - v_meas)
            self._dv = float(np.clip(self._dv, -p.max_speed_correction, p.max_speed_correction))
        if last is not None and self._planned_duration is not None and p.timing_gain > 0.0:
            err = (t_td - last[1]) - self._planned_duration
            self._dt_td += p.timing_gain * (err - self._dt_td)
            self._dt_td = float(np.clip(self._dt_td, -p.max_timing_offset, p.max_timing_offset))
        self._last_step = (inp.step_index, t_td, com.copy(), self._v)

    def _ramp(self, t: float) -> None:
        dt = 0.0 if self._t_last is None else max(0.0, t - self._t_last)
        self._t_last = t
        p = self.params
        v_t, yr_t, vy_t = self._target
        dv = p.max_accel * dt
        dyr = p.max_yaw_accel * dt
        self._v += float(np.clip(v_t - self._v, -dv, dv))
        self._vy += float(np.clip(vy_t - self._vy, -dv, dv))
        self._yr += float(np.clip(yr_t - self._yr, -dyr, dyr))

    def _place(
        self, inp: PlannerInput, T: float, swing_left: bool, yaw_next: float, heading_mid: float
    ) -> tuple[np.ndarray, float]:
        """Foothold for a step of duration ``T`` and its clipping error [m]."""
        p = self.params
        omega = inp.omega
        stance = np.asarray(inp.stance_pos, dtype=float)[:2]
        remaining = max(0.0, T + self._dt_td - inp.time_since_touchdown)
        xi = np.asarray(inp.dcm, dtype=float)[:2]
        xi_end = stance + (xi - stance) * math.exp(omega * remaining)
        c, s = math.cos(yaw_next), math.sin(yaw_next)
        R = np.array([[c, -s], [s, c]])
        T_eff = max(0.05, T + self._dt_td)  # the duration the step will actually have
        b = nominal_dcm_offset((self._v + self._dv) * T_eff, p.step_width, omega, T_eff, swing_left)
        b[1] -= self._vy * T_eff / (math.exp(omega * T_eff) - 1.0)
        foot = xi_end - R @ b
        # reachable rectangle about the stance foot, in the mid heading frame
        cm, sm = math.cos(heading_mid), math.sin(heading_mid)
        Rm = np.array([[cm, -sm], [sm, cm]])
        d = Rm.T @ (foot - stance)
        side = 1.0 if swing_left else -1.0
        dc = d.copy()
        dc[0] = float(np.clip(d[0], -p.max_step_backward, p.max_step_forward))
        dc[1] = side * float(np.clip(side * d[1], p.min_step_width, p.max_step_width))
        return stance + Rm @ dc, float(np.linalg.norm(d - dc))

    def plan(self, inp: PlannerInput) -> StepPlan:
        """Foothold, yaw and duration for the current swing foot from the measured DCM.

        The nominal duration is kept while the nominal foothold is reachable; otherwise the duration
        in [min_duration, max_duration] (and not already past) that minimises
        clip_error² + duration_weight·(T − T_nom)² is used.
        """
        if not isinstance(inp, PlannerInput):
            raise InvalidInputError("inp", inp, "a lipmpcc.planners.base.PlannerInput")
        t0 = time.perf_counter()
        p = self.params
        self._ramp(inp.t)
        self._update_speed_correction(inp)
        omega = inp.omega
        swing_left = inp.stance_side != LEFT
        stance = np.asarray(inp.stance_pos, dtype=float)[:2]
        T = p.step_duration
        dyaw = float(np.clip(self._yr * T, -p.max_yaw_step, p.max_yaw_step))
        yaw_next = float(inp.stance_yaw) + dyaw
        heading_mid = float(inp.stance_yaw) + 0.5 * dyaw
        foot, err = self._place(inp, T, swing_left, yaw_next, heading_mid)
        if err > 1e-6 and p.max_duration > p.min_duration:
            best = err**2
            t_min = max(p.min_duration, inp.time_since_touchdown)
            for Tc in np.linspace(p.min_duration, p.max_duration, 9):
                if Tc < t_min:
                    continue
                f_c, e_c = self._place(inp, float(Tc), swing_left, yaw_next, heading_mid)
                cost = e_c**2 + p.duration_weight * (Tc - p.step_duration) ** 2
                if cost < best - 1e-12:
                    best, foot, T = cost, f_c, float(Tc)
        self._planned_duration = T
        # COM at the end of the step predicted by the LIP about the stance foot
        remaining = max(0.0, T + self._dt_td - inp.time_since_touchdown)
        com = np.asarray(inp.com_pos, dtype=float)[:2]
        vel = np.asarray(inp.com_vel, dtype=float)[:2]
        com_target, _, _ = lip_solution(com, vel, stance, omega, remaining)
        return StepPlan(
            foothold=foot,
            yaw=float(wrap_angle(yaw_next)),
            duration=T,
            com_target=com_target,
            solve_time=time.perf_counter() - t0,
        )
