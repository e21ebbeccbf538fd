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


@pytest.mark.parametrize("kw, name", [
    ({"foothold": "abc"}, "StepPlan.foothold = 'abc'"),
    ({"foothold": None}, "StepPlan.foothold = None"),
    ({"foothold": {"x": 1}}, "StepPlan.foothold"),
    ({"duration": None}, "StepPlan.duration = None"),
    ({"duration": "0.4"}, "StepPlan.duration = '0.4'"),
    ({"duration": True}, "StepPlan.duration = True"),
    ({"yaw": None}, "StepPlan.yaw = None"),
    ({"cop_offset": "ab"}, "StepPlan.cop_offset"),
    ({"com_target": (1.0,)}, "StepPlan.com_target"),
    ({"status": None}, "StepPlan.status"),
])
def test_a_step_plan_of_the_wrong_types_is_refused_naming_the_field(kw, name) -> None:
    args = {"foothold": (0.1, 0.0), "yaw": 0.0, "duration": 0.4, **kw}
    with pytest.raises(StateError, match=name.replace(".", r"\.").replace("(", r"\(")) as err:
        StepPlan(**args)
    assert "expected" in str(err.value)


@pytest.mark.parametrize("field, value", [
    ("t", None), ("t", math.nan), ("com_pos", "abc"), ("com_pos", np.zeros(2)), ("com_vel", [0.0, math.inf, 0.0]),
    ("dcm", np.zeros(3)), ("omega", 0.0), ("omega", "3.3"), ("stance_side", "middle"), ("stance_pos", None),
    ("stance_yaw", "0"), ("swing_pos", np.zeros(4)), ("time_since_touchdown", math.nan), ("step_index", -1),
    ("step_index", 1.5), ("step_index", True), ("torso_yaw", None), ("angular_momentum", np.zeros(2)), ("mass", -48.0),
])
def test_a_planner_input_checks_every_field(field, value) -> None:
    good = _input("left")
    kwargs = {f: getattr(good, f) for f in good.__dataclass_fields__}
    kwargs[field] = value
    with pytest.raises(StateError, match=f"PlannerInput.{field}"):
        PlannerInput(**kwargs)


def test_a_planner_input_takes_lists_and_numpy_scalars() -> None:
    inp = PlannerInput(t=np.float64(0.2), com_pos=[0.0, 0.0, 0.9], com_vel=(0, 0, 0), dcm=[0.0, 0.0], omega=np.float32(3.3),
                       stance_side="right", stance_pos=[0, 0, 0], stance_yaw=0, swing_pos=[0, 0.2, 0], swing_yaw=0.0,
                       time_since_touchdown=0.0, step_index=np.int64(3), torso_yaw=0.0, mass=48.0)
    assert inp.com_pos.dtype == float and inp.swing_pos.shape == (3,)


def test_check_rate_hz_bounds_and_types_a_planners_rate() -> None:
    from lipmpcc.exceptions import ParameterError
    from lipmpcc.planners.base import check_rate_hz

    class P:
        rate_hz: object = 25.0

    assert check_rate_hz(P(), 400.0) == 25.0
    for bad in ("25", None, math.nan, math.inf, 0.0, -1.0, 1e9, True):
        P.rate_hz = bad
        with pytest.raises(ParameterError, match=r"planner.rate_hz = .*<= 400 Hz"):
            check_rate_hz(P(), 400.0)
