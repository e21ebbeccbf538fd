"""The step phase τ(t) ∈ [0, 1] of a swing, re-timed when its planned end time changes (SPEC §2).

Paper B eqs. 12–13: between re-timings τ is linear in t; a new desired end time T_des re-slopes it
from the current (τ^i, t^i),

    τ(t) = τ^i + (1 − τ^i)(t − t^i)/(T_des − t^i),   τ̇ = (1 − τ^i)/(T_des − t^i),

so τ stays continuous and reaches 1 exactly at T_des. The swing references
(:class:`lipmpcc.control.references.StepTrajectory`) run on it, and a footstep planner that
replicates the loop's phase (:mod:`lipmpcc.planners.alip_source`) uses the same clock.
"""

from __future__ import annotations

import math

from ..exceptions import InvalidInputError, ParameterError
from ..validation import finite_number

__all__ = ["PhaseClock"]




class PhaseClock:
    """Step phase τ(t) ∈ [0, 1], re-timed when the desired end time changes (SPEC §2).

    Between re-timings τ is linear in t; :meth:`retime` re-slopes it from the current (τ^i, t^i)
    so that it reaches 1 exactly at the new desired end time.

    Args:
        t_start: lift-off time [s] (τ = 0).
        t_end: desired end time [s] (τ = 1), later than ``t_start``.
    """

    def __init__(self, t_start: float, t_end: float) -> None:
        t_start = finite_number("t_start", t_start)
        t_end = finite_number("t_end", t_end)
        if t_end <= t_start:
            raise ParameterError("t_end", t_end, f"a step end time later than its start t_start = {t_start}")
        self.t_start = t_start
        self._t_i = t_start
        self._tau_i = 0.0
        self._t_end = t_end

    @property
    def t_end(self) -> float:
        """Latest desired end time T_des [s]."""
        return self._t_end

    @property
    def duration(self) -> float:
        """Latest desired duration T_des − t_start [s]."""
        return self._t_end - self.t_start

    def segment(self) -> tuple[float, float, float]:
        """The current segment (t^i [s], τ^i, T_des [s]): τ(t) is a function of these alone."""
        return self._t_i, self._tau_i, self._t_end

    def rate(self) -> float:
        """τ̇ = (1 − τ^i)/(T_des − t^i) [1/s] of the current segment."""
        return (1.0 - self._tau_i) / (self._t_end - self._t_i)

    def tau(self, t: float) -> float:
        """τ(t), clipped to [0, 1]."""
        if self._t_end <= self._t_i:
            return 1.0
        tau = self._tau_i + (1.0 - self._tau_i) * (t - self._t_i) / (self._t_end - self._t_i)
        return min(1.0, max(0.0, tau))

    def tau_dot(self, t: float) -> float:
        """τ̇ at time ``t`` [1/s]; 0 once τ has reached 1."""
        if t >= self._t_end or self._t_end <= self._t_i:
            return 0.0
        return self.rate()

    def retime(self, t: float, t_end: float) -> None:
        """Re-slope τ at time ``t`` [s] so that it reaches 1 exactly at ``t_end`` [s].

        τ keeps its current value τ^i = τ(t) (continuity). ``t_end`` must be later than ``t``.
        """
        t = finite_number("t", t)
        t_end = finite_number("t_end", t_end)
        if t_end <= t:
            raise ParameterError("t_end", t_end, f"a step end time later than the current time {t}")
        tau = self.tau(t)
        if tau >= 1.0:
            return
        self._tau_i = tau
        self._t_i = t
        self._t_end = t_end
