"""A footstep planner of your own, in a dozen lines: the capture point of a periodic gait.

It implements the one planner contract (:mod:`lipmpcc.planners.base`): a ``name``, a ``rate_hz``,
``reset()`` and ``plan(inp: PlannerInput) -> StepPlan``. The same class runs unchanged in the 3D-LIP
loop (``own_planner_lip.py``) and on the full body in MuJoCo (``own_planner_fullbody.py``).

The DCM ξ = c + ċ/ω of the LIP about the stance foot p diverges as ξ(t) = p + (ξ₀ − p) e^{ωt}. At the
step's end it must sit at the offset b from the next foothold that the periodic gait with steps of
``step`` and feet ``width`` apart has: b = (step / (σ − 1), ∓ width / (σ + 1)) in the stance foot's
frame, σ = e^{ωT}. So the foothold is ξ(T) − b.
"""

import math

import numpy as np

from lipmpcc.planners.base import PlannerInput, StepPlan

__all__ = ["CapturePointPlanner"]


class CapturePointPlanner:
    """Steps of ``step`` [m] along the stance foot's heading, ``width`` [m] apart, every ``T`` [s]."""

    name, rate_hz = "my-capture-point", 25.0  # re-planned at 25 Hz during a swing (once per step on the LIP)

    def __init__(self, step: float = 0.15, width: float = 0.25, T: float = 0.4) -> None:
        self.step, self.width, self.T = step, width, T

    def reset(self) -> None:  # nothing to forget between runs
        pass

    def plan(self, inp: PlannerInput) -> StepPlan:
        sigma = math.exp(inp.omega * self.T)
        p = np.asarray(inp.stance_pos, dtype=float)[:2]
        left = max(self.T - inp.time_since_touchdown, 0.0)           # time left in this step [s]
        xi_end = p + (np.asarray(inp.dcm) - p) * math.exp(inp.omega * left)
        c, s = math.cos(inp.stance_yaw), math.sin(inp.stance_yaw)
        b = np.array([self.step / (sigma - 1.0), -inp.swing_side.sign * self.width / (sigma + 1.0)])
        return StepPlan(foothold=xi_end - np.array([c * b[0] - s * b[1], s * b[0] + c * b[1]]),
                        yaw=inp.stance_yaw, duration=self.T)
