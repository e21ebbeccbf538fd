"""Liveness of the MPCC planners: notice a stall from the measured progress along the path (issue 31).

The MPCC's progress reward −ρ v² has zero slope at v = 0, so "stand still" is a local minimum, and the
warm start (the shifted previous plan) keeps a planner in it long after the reason has gone. Measured on
a straight 14 m path with one pedestrian crossing 3.3 m ahead (``follow-path``, paper A's ``circle``
weights, the LIP): the robot stops in front of the crossing, and every later solve returns the plan
v = (0, 0, 0, 0, v_max), a slow backward gait (the distance-per-step bound δ_min forbids standing still
and the barrier forbids stepping towards the pedestrian); the closest point ϑ_init follows the COM
backwards. The plan's *mean* v is v_max / N = 0.2 v_max, above the old restart test (mean v < v_max / 10),
so no restart was tried; a cold multi-start from the very same state finds a plan that walks on and costs
less (0.97 against 1.15). The cause is the solver's basin, not the cost.

:class:`ProgressMonitor` watches the measured path parameter ϑ_init of each solve against time and says
when the robot has gained less than ``min_progress`` [m] over the last ``window`` [s]: the planners then
solve again from their cold starts (march along the path, v = 0 and v = v_max, and for the SQP the
interior-point solution of the lifted problem) and keep the cheapest converged plan — the same cost, so
a robot that waits for a good reason (the barrier of an obstacle still on the path) keeps waiting, and
one that was only stuck walks on. The rule engages only on a stall, so runs that never stall (paper A's
studies) are unchanged bit for bit.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

from ..exceptions import ParameterError
from ..validation import finite_number, positive_number

__all__ = ["ProgressMonitor", "stall_window", "stall_progress"]


def stall_window(N: int, T: float) -> float:
    """The time over which a planner judges its progress [s]: its horizon, N steps of T [s]."""
    return float(N) * float(T)


def stall_progress(N: int, v_max: float) -> float:
    """The least progress over :func:`stall_window` that is not a stall [m]: a tenth of v_max [m] per step
    (the threshold of the planners' older restart test, mean v < v_max / 10), over N steps."""
    return 0.1 * float(v_max) * float(N)


@dataclass
class ProgressMonitor:
    """The measured path parameter of each solve against time, and whether the robot has stalled.

    Attributes:
        window: how far back progress is judged [s].
        min_progress: the least gain of ϑ over ``window`` that is not a stall [m].
        history: (t [s], ϑ [m]) of the solves in the last ``window`` (and the one just before it).
    """

    window: float
    min_progress: float
    history: deque = field(default_factory=deque)

    def __post_init__(self) -> None:
        self.window = positive_number("window", self.window, "s", error=ParameterError)
        self.min_progress = positive_number("min_progress", self.min_progress, "m", error=ParameterError)

    def reset(self) -> None:
        """Forget the history (a new run)."""
        self.history.clear()

    def record(self, t: float, theta: float) -> None:
        """Add the solve at time ``t`` [s] from path parameter ``theta`` [m]; a time before the last one
        (a new run on the same planner) starts the history again."""
        t = finite_number("t", t, "s", error=ParameterError)
        theta = finite_number("theta", theta, "m", error=ParameterError)
        if self.history and t < self.history[-1][0]:
            self.history.clear()
        self.history.append((t, theta))
        # keep one record at or before t - window (the reference of the judgement)
        while len(self.history) > 2 and self.history[1][0] <= t - self.window:
            self.history.popleft()

    def stalled(self) -> bool:
        """The last record gained less than ``min_progress`` over the ``window`` before it (False until the
        history spans the window)."""
        if len(self.history) < 2:
            return False
        t0, th0 = self.history[0]
        t1, th1 = self.history[-1]
        return t1 - t0 >= self.window - 1e-9 and th1 - th0 < self.min_progress
