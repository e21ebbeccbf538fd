"""Hand-made planner and measurements for the full-body loop's parts without MuJoCo (gait, references)."""

from __future__ import annotations

import numpy as np


class FixedSteps:
    """A footstep planner: 0.1 m ahead of the swing foot, 0.4 s steps, at 10 Hz; keeps its inputs."""

    name = "fixed"
    rate_hz = 10.0

    def __init__(self) -> None:
        self.inputs: list = []

    def reset(self) -> None:
        self.inputs.clear()

    def plan(self, inp):
        from lipmpcc.planners.base import StepPlan

        self.inputs.append(inp)
        return StepPlan(foothold=inp.swing_pos[:2] + np.array([0.1, 0.0]), yaw=0.0, duration=0.4)


def measurement(t: float = 0.0, contact: tuple[bool, bool] = (True, True), touched: tuple[bool, bool] | None = None):
    from lipmpcc.sim.types import FramePose, Measurement

    eye = np.eye(3)
    feet = (FramePose(np.array([0.0, 0.1, 0.0]), eye), FramePose(np.array([0.0, -0.1, 0.0]), eye))
    return Measurement(time=t, q=np.zeros(7), v=np.zeros(6), com=np.array([0.0, 0.0, 0.9]), com_vel=np.zeros(3),
                       torso=FramePose(np.array([0.0, 0.0, 1.0]), eye), feet=feet, contact=contact,
                       normal_force=(200.0, 200.0), touched=touched)
