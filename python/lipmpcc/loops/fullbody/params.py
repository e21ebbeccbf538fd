"""The full-body loop's parameters (:class:`LoopParams`): rates, COM height, gait timing, swing, threads."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...config import threads_enabled
from ...conventions import LEFT, RIGHT
from ...exceptions import ParameterError
from ...validation import check_field_types, finite_number
from ...control.references import SwingParams

__all__ = ["LoopParams", "MAX_RUN_DURATION", "MAX_RUN_STEPS", "TOUCHDOWN_CONTACTS", "TOUCHDOWN_TIMINGS"]


#: Longest simulated time of one full-body run [s] (an hour of simulated walking takes hours to compute).
MAX_RUN_DURATION = 3600.0
#: Most footsteps of one full-body run.
MAX_RUN_STEPS = 5000
#: :attr:`LoopParams.touchdown_timing`'s values
TOUCHDOWN_TIMINGS = ("planner", "loop", "auto")
#: :attr:`LoopParams.touchdown_contact`'s values
TOUCHDOWN_CONTACTS = ("substep", "tick")


@dataclass(frozen=True)
class LoopParams:
    """Parameters of :class:`~lipmpcc.loops.fullbody.FullBodyLoop` (times [s], lengths [m]).

    Attributes:
        sim_steps_per_wbc: simulation steps per WBC tick (5 → 400 Hz at 2 kHz; 1 → 2 kHz).
        com_height: constant COM height of the references [m]; None: the standing keyframe's.
        initial_shift: duration of the initial COM shift onto the first stance foot [s].
        initial_shift_fraction: where the COM goes in that shift, as a fraction of the way from the
            feet's midpoint to the first stance foot [-].
        first_stance: ``"left"`` or ``"right"``: the first stance foot.
        double_support: double-support time after each touch-down [s] (0: none).
        load_ramp: time over which a touching-down foot's normal-force bound ramps up [s].
        touchdown_min_phase: a swing-foot contact counts as touch-down after this phase [-].
        landing_depth: the swing foot aims this far below the ground height [m] (firm landing).
        swing: :class:`~lipmpcc.control.references.SwingParams` (apex height, freeze phase, ...).
        com_resync_on_plan: re-initialise the LIP COM reference from the measured COM state at every
            planner update (True) or only at touch-down (False).
        video_fps: frames per second of the recorded video (``video=True``).
        touchdown_timing: who times the touch-down: ``"planner"`` — the swing foot lands when its
            contact is detected after ``touchdown_min_phase`` (often a little before the planned time) or at
            the planned time, for a planner that learns that offset itself; ``"loop"`` — the loop keeps the
            planned time: a contact before it does not end the step, the foot lands when the plan said (to a
            WBC tick), so a planner that knows nothing of the robot's touch-down lands when it asks;
            ``"auto"`` (default) — ``"planner"`` for a planner that says it compensates the touch-down
            timing itself (``compensates_touchdown = True``: the shipped capture-point, MPCC and ALIP
            sources), else ``"loop"`` (:func:`~lipmpcc.loops.base.touchdown_timing`) — unless the robot's
            layout states ``touchdown_timing`` (:attr:`~lipmpcc.robots.RobotDescription.touchdown_timing`):
            then that, for every planner.
        touchdown_contact: which swing-foot contact ends a step: ``"tick"`` (default) — one in the state
            measured at the WBC tick (``Measurement.contact``); ``"substep"`` — one at any simulation step
            since the previous WBC tick (``Measurement.touched``: a toe that touches and bounces between two
            ticks lands when it first touches, as a 2 kHz contact sensor would see it; measured on Digit v3,
            not adopted: docs/design.md).
        helper_thread: while MuJoCo steps, log the tick and evaluate the next tick's references on a
            helper thread (None: when the process may use two CPUs or more and the environment
            variable ``LIPMPCC_LOOP_THREAD`` is not ``0``). Results do not depend on it.
    """

    sim_steps_per_wbc: int = 5
    com_height: float | None = None
    initial_shift: float = 0.6
    initial_shift_fraction: float = 0.6
    first_stance: str = RIGHT
    double_support: float = 0.0
    load_ramp: float = 0.0
    touchdown_min_phase: float = 0.6
    landing_depth: float = 0.0
    swing: SwingParams | None = None
    com_resync_on_plan: bool = False
    video_fps: float = 30.0
    helper_thread: bool | None = None
    touchdown_timing: str = "auto"
    touchdown_contact: str = "tick"

    def resolved_helper_thread(self) -> bool:
        """Whether :meth:`FullBodyLoop.run` uses its helper thread (see ``helper_thread``)."""
        if self.helper_thread is not None:
            return bool(self.helper_thread)
        return threads_enabled("LIPMPCC_LOOP_THREAD")

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if not (isinstance(self.sim_steps_per_wbc, (int, np.integer)) and 1 <= self.sim_steps_per_wbc <= 100):
            raise ParameterError("sim_steps_per_wbc", self.sim_steps_per_wbc, "an integer in [1, 100]")
        if self.swing is not None and not isinstance(self.swing, SwingParams):
            raise ParameterError("swing", self.swing, "a lipmpcc.control.references.SwingParams or None")
        if self.com_height is not None and not (finite_number("com_height", self.com_height, "m", error=ParameterError) > 0.0):
            raise ParameterError("com_height", self.com_height, "a positive height [m] or None")
        for name in ("initial_shift", "double_support", "load_ramp", "landing_depth"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ParameterError(name, v, "a non-negative finite number")
        if not 0.0 <= self.initial_shift_fraction <= 1.0:
            raise ParameterError("initial_shift_fraction", self.initial_shift_fraction, "a fraction in [0, 1]")
        if not 0.0 < self.touchdown_min_phase <= 1.0:
            raise ParameterError("touchdown_min_phase", self.touchdown_min_phase, "a phase in (0, 1]")
        if self.first_stance not in (LEFT, RIGHT):
            raise ParameterError("first_stance", self.first_stance, "'left' or 'right'")
        if not (math.isfinite(self.video_fps) and self.video_fps > 0.0):
            raise ParameterError("video_fps", self.video_fps, "a positive frame rate [Hz]")
        if self.touchdown_timing not in TOUCHDOWN_TIMINGS:
            raise ParameterError("touchdown_timing", self.touchdown_timing, "'planner', 'loop' or 'auto'")
        if self.touchdown_contact not in TOUCHDOWN_CONTACTS:
            raise ParameterError("touchdown_contact", self.touchdown_contact, "'substep' or 'tick'")
        if self.helper_thread is not None and not isinstance(self.helper_thread, (bool, np.bool_)):
            raise ParameterError("helper_thread", self.helper_thread, "True, False or None")
