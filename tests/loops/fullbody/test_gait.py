"""lipmpcc.loops.fullbody.gait: the gait state machine on hand-made measurements (no MuJoCo)."""

from __future__ import annotations

import pytest

from .handmade import FixedSteps, measurement


def test_gait_goes_shift_single_double_single_and_finishes() -> None:
    from lipmpcc.conventions import LEFT, RIGHT
    from lipmpcc.loops.fullbody import Gait, GaitMode, LoopParams

    planner = FixedSteps()
    p = LoopParams(initial_shift=0.2, double_support=0.1, touchdown_min_phase=0.6, touchdown_timing="planner")
    gait = Gait(planner, p, com_height=0.9, mass=40.0, max_steps=2)
    m = measurement()
    gait.start(0.0, m)
    assert gait.mode is GaitMode.SHIFT and gait.stance is RIGHT and gait.stance_code == 2

    assert not gait.update(0.1, m) and gait.mode is GaitMode.SHIFT and not planner.inputs
    assert gait.update(0.2, m)  # the shift ends: the left foot lifts, the planner is asked
    assert gait.mode is GaitMode.SINGLE and gait.swing is LEFT and gait.stance_code == 1
    first = planner.inputs[0]
    assert first.stance_side == RIGHT and first.step_index == 0 and first.time_since_touchdown == 0.0
    assert gait.step.t_end == pytest.approx(0.6)

    assert not gait.update(0.25, m)  # a contact before touchdown_min_phase is no touch-down
    assert gait.update(0.3, m) and len(planner.inputs) == 2  # the planner again, at 10 Hz
    assert gait.next_plan_t == pytest.approx(0.4)

    assert gait.update(0.48, m)  # phase 0.7 with contact: touch-down, then double support
    td = gait.touchdowns[0]
    assert td.side == LEFT and td.by_contact and td.duration == pytest.approx(0.28)
    assert gait.mode is GaitMode.DOUBLE and gait.stance is LEFT and gait.stance_code == 2
    assert gait.t_lift == pytest.approx(0.58)
    assert not gait.update(0.5, m) and len(planner.inputs) == 2

    assert gait.update(0.58, m) and gait.mode is GaitMode.SINGLE and gait.swing is RIGHT
    assert planner.inputs[-1].step_index == 1 and planner.inputs[-1].time_since_touchdown == pytest.approx(0.1)
    t_end = gait.step.t_end
    assert gait.update(t_end, measurement(t_end, contact=(True, False)))  # by the clock
    assert gait.finished and len(gait.touchdowns) == 2 and not gait.touchdowns[1].by_contact


def test_gait_stands_without_planner_and_lifts_at_once_without_shift() -> None:
    from lipmpcc.loops.fullbody import Gait, GaitMode, LoopParams

    standing = Gait(None, LoopParams(), com_height=0.9, mass=40.0)
    standing.start(0.0, measurement())
    assert standing.mode is GaitMode.STAND and not standing.update(5.0, measurement(5.0))

    planner = FixedSteps()
    gait = Gait(planner, LoopParams(initial_shift=0.0, first_stance="left"), com_height=0.9, mass=40.0)
    gait.start(1.0, measurement(1.0))
    assert gait.mode is GaitMode.DOUBLE
    assert gait.update(1.0, measurement(1.0)) and gait.mode is GaitMode.SINGLE and gait.stance_code == 0
    assert planner.inputs[0].stance_side == "left" and planner.inputs[0].mass == 40.0


@pytest.mark.parametrize("setting", ["substep", "tick"])
def test_a_contact_between_two_ticks_ends_the_step_only_when_substeps_count(setting: str) -> None:
    """``touchdown_contact="substep"`` lands the foot on ``Measurement.touched`` (a toe that touched and bounced off
    since the last tick); ``"tick"`` only on the contact of the measured state."""
    from lipmpcc.loops.fullbody import Gait, LoopParams

    p = LoopParams(initial_shift=0.0, touchdown_min_phase=0.6, touchdown_timing="planner", touchdown_contact=setting)
    gait = Gait(FixedSteps(), p, com_height=0.9, mass=40.0)
    gait.start(0.0, measurement())
    gait.update(0.0, measurement())
    swing = gait.swing_index
    bounced = tuple(i == swing for i in range(2))  # touched between the ticks, not in contact now
    airborne = tuple(i != swing for i in range(2))
    gait.update(0.1, measurement(0.1, contact=airborne, touched=bounced))
    assert not gait.touchdowns  # before touchdown_min_phase
    gait.update(0.3, measurement(0.3, contact=airborne, touched=bounced))
    if setting == "substep":
        assert len(gait.touchdowns) == 1 and gait.touchdowns[0].by_contact and gait.touchdowns[0].t == 0.3
    else:
        assert not gait.touchdowns
    with pytest.raises(Exception, match="touchdown_contact"):
        LoopParams(touchdown_contact="sometimes")
