"""lipmpcc.planners.base: the planner contract (what a planner is given, what it returns, the protocol)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.conventions import Side
from lipmpcc.exceptions import StateError
from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan


def _input(stance: Side | str) -> PlannerInput:
    return PlannerInput(t=0.2, com_pos=np.array([0.0, 0.0, 0.9]), com_vel=np.zeros(3), dcm=np.zeros(2), omega=3.3,
                        stance_side=stance, stance_pos=np.zeros(3), stance_yaw=0.0, swing_pos=np.zeros(3), swing_yaw=0.0,
                        time_since_touchdown=0.1, step_index=2, torso_yaw=0.0)


def test_the_swing_side_is_the_other_foot() -> None:
    assert _input(Side.LEFT).swing_side is Side.RIGHT
    assert _input("right").swing_side is Side.LEFT and _input("right").swing_side.sign == 1
    inp = _input("left")
    assert inp.course is None and inp.obstacles == () and math.isnan(inp.mass) and inp.angular_momentum is None
    with pytest.raises(AttributeError):
        inp.t = 1.0  # frozen


def test_a_step_plan_normalises_and_checks_its_fields() -> None:
    plan = StepPlan([[0.3], [-0.1]], 0.2, 0.4, cop_offset=(0.01, 0.0))
    assert plan.foothold.shape == (2,) and plan.foothold.dtype == float and plan.ok
    assert plan.cop_offset.shape == (2,) and plan.preview is None and plan.record is None
    assert not StepPlan((0.0, 0.0), 0.0, 0.4, status="fallback (previous plan)").ok
    for kw, name in (
        ({"foothold": (0.0, 0.0, 0.0)}, "foothold"),
        ({"foothold": (np.nan, 0.0)}, "foothold"),
        ({"yaw": math.inf}, "yaw"),
        ({"duration": 0.0}, "duration"),
        ({"duration": math.nan}, "duration"),
        ({"cop_offset": (0.01,)}, "cop_offset"),
    ):
        args = {"foothold": (0.0, 0.0), "yaw": 0.0, "duration": 0.4, **kw}
        with pytest.raises(StateError, match=f"StepPlan.{name}"):
            StepPlan(**args)


def test_any_object_with_name_rate_reset_and_plan_is_a_footstep_source() -> None:
    class Fixed:
        name, rate_hz = "fixed", 10.0

        def reset(self) -> None:
            pass

        def plan(self, inp: PlannerInput) -> StepPlan:
            return StepPlan(inp.stance_pos[:2] + [0.1, -0.2 * inp.swing_side.sign], 0.0, 0.4)

    class NoReset:
        name, rate_hz = "half", 10.0

        def plan(self, inp: PlannerInput) -> StepPlan:  # pragma: no cover - never called
            raise AssertionError

    assert isinstance(Fixed(), FootstepSource) and not isinstance(NoReset(), FootstepSource)
    np.testing.assert_allclose(Fixed().plan(_input("left")).foothold, [0.1, 0.2])
