"""lipmpcc.loops.fullbody.references: the whole-body references the gait gives (no MuJoCo)."""

from __future__ import annotations

import numpy as np
import pytest

from .handmade import FixedSteps, measurement


def test_references_follow_the_gait() -> None:
    """Standing: both feet, the standing COM; single support: the stance foot alone, the swing row
    written; with a load ramp the new stance foot's normal force is bounded just after touch-down."""
    from lipmpcc.conventions import GRAVITY
    from lipmpcc.loops.fullbody import Gait, LoopParams
    from lipmpcc.loops.fullbody.references import WholeBodyReferences

    gait = Gait(None, LoopParams(), com_height=0.9, mass=40.0)
    gait.start(0.0, measurement())
    refs = WholeBodyReferences(gait, np.zeros(0), np.array([0.01, 0.02]), 0.9, weight=40.0 * GRAVITY, load_ramp=0.1)
    r = refs.evaluate(0.5, 0.3)
    assert refs.ref.contact == (True, True) and r.torso_yaw == 0.3 and np.isnan(r.phase)
    np.testing.assert_array_equal(r.com, [0.01, 0.02, 0.9])
    np.testing.assert_allclose(refs.ref.torso_rot[:2, 0], [np.cos(0.3), np.sin(0.3)])

    planner = FixedSteps()
    gait = Gait(planner, LoopParams(initial_shift=0.0, double_support=0.05, touchdown_timing="planner"), com_height=0.9,
                mass=40.0)  # a touch-down at the contact
    refs = WholeBodyReferences(gait, np.zeros(0), np.zeros(2), 0.9, weight=40.0 * GRAVITY, load_ramp=0.1)
    gait.start(0.0, measurement())
    gait.update(0.0, measurement())  # right stance, left foot swings
    r = refs.evaluate(0.1, gait.torso_yaw_ref)
    assert refs.ref.contact == (False, True) and 0.0 < r.phase < 1.0
    np.testing.assert_array_equal(refs.ref.foot_pos[0], r.swing_pos)
    assert refs.ref.max_normal_force == (np.inf, np.inf)  # no touch-down yet
    gait.update(0.3, measurement(0.3))  # left foot lands (phase 0.75, in contact)
    refs.evaluate(0.32, gait.torso_yaw_ref)
    bound = refs.ref.max_normal_force
    assert bound[1] == np.inf and bound[0] == pytest.approx(0.2 * 1.5 * 40.0 * GRAVITY)
