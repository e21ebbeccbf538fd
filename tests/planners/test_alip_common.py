"""lipmpcc.planners.alip_common: the ALIP planners on the planner contract, their shared result,
stone handling and parameter validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.conventions import Side
from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.planners.alip_common import AlipPlanResult, pad_stones, stone_arrays
from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams
from lipmpcc.planners.alip_qp import AlipQp, AlipQpParams
from lipmpcc.planners.base import FootstepSource, PlannerInput, StepPlan
from lipmpcc.terrain import StoneSequence

PRM = AlipMpcParams.paper()
LAM = PRM.lam
SIG = math.exp(LAM * PRM.T_nom)
STANCE = np.array([0.0, 0.14])  # left foot


def course(n: int = 6, L: float = 0.4, w: float = 0.28) -> StoneSequence:
    """Stones of a periodic gait from STANCE, the first for the right foot."""
    c, p, side, sides = [], STANCE.copy(), -1, []
    for _ in range(n):
        p = p + np.array([L, side * w])
        c.append(p.copy())
        sides.append(side)
        side = -side
    return StoneSequence(np.array(c), np.tile([0.2, 0.1], (n, 1)), np.array(sides), np.ones(n, bool))


def periodic_dcm(L: float = 0.4, w: float = 0.28, t: float = 0.0) -> np.ndarray:
    """World DCM of the periodic gait ``t`` [s] after the touch-down of a right-swing step."""
    return STANCE + np.array([L / (SIG - 1), -w / (SIG + 1)]) * math.exp(LAM * t)


def inp(dcm: np.ndarray, t: float = 0.0, stones: StoneSequence | None = None, yaw: float = 0.0) -> PlannerInput:
    return PlannerInput(
        t=1.0 + t, com_pos=np.r_[STANCE, 0.9], com_vel=np.zeros(3), dcm=np.asarray(dcm, float), omega=LAM,
        stance_side=Side.LEFT, stance_pos=np.r_[STANCE, 0.0], stance_yaw=yaw, swing_pos=np.array([0.0, -0.14, 0.0]),
        swing_yaw=yaw, time_since_touchdown=t, step_index=3, torso_yaw=yaw, course=stones,
    )


@pytest.mark.parametrize("make", [AlipMpc, AlipQp])
def test_plan_is_the_contract_and_matches_solve(make):
    """plan(PlannerInput) answers with a StepPlan carrying the solve's result: the same foothold and
    duration as solve() from the same data on a fresh planner."""
    a, b = make(), make()
    assert isinstance(a, FootstepSource) and a.rate_hz == pytest.approx(25.0)
    plan = a.plan(inp(periodic_dcm(t=0.08), 0.08, course(), yaw=0.3))
    res = b.solve(periodic_dcm(t=0.08), STANCE, "left", 0.08, course())
    assert isinstance(plan, StepPlan) and isinstance(plan.record, AlipPlanResult)
    assert plan.ok and plan.status == "ok" and not plan.record.fallback
    np.testing.assert_array_equal(plan.foothold, res.next_foothold)
    assert plan.duration == res.step_duration and plan.yaw == 0.3  # the ALIP planners keep the stance yaw
    assert plan.cop_offset is None  # a point foot
    assert plan.preview.shape == (len(res.footholds), 4)
    np.testing.assert_array_equal(plan.preview[:, 3], res.durations)
    # in the periodic gait the plan is the next stone, at the nominal duration
    np.testing.assert_allclose(plan.foothold, course().centers[0], atol=1e-6)


def test_planner_with_a_foot_returns_its_cop_offset():
    mpc = AlipMpc(AlipMpcParams.paper(cop_range=(0.06, 0.025)))
    plan = mpc.plan(inp(periodic_dcm(t=0.1) + np.array([-0.04, 0.0]), 0.1, course()))
    assert plan.cop_offset is not None and plan.cop_offset.shape == (2,)
    np.testing.assert_array_equal(plan.cop_offset, plan.record.cop_offset)
    assert plan.cop_offset[0] < -1e-3  # a DCM behind the periodic one: the CoP moves back to slow it less


def test_failed_solve_is_a_non_ok_plan():
    """A solve that fails is answered by the previous plan with a status that is not "ok"."""
    m = AlipMpc(AlipMpcParams.paper(max_iter=3))
    first = m.plan(inp(periodic_dcm(), 0.0, course()))
    assert first.ok
    held = m.plan(inp(STANCE + np.array([1.5, 0.0]), 0.04, course()))  # far outside the viable set
    assert not held.ok and held.status.startswith("fallback") and held.record.fallback
    np.testing.assert_array_equal(held.foothold, first.foothold)
    assert m.failures == 1


def test_old_positional_plan_warns_and_is_solve():
    with pytest.warns(DeprecationWarning, match=r"AlipQp\.solve"):
        old = AlipQp().plan(periodic_dcm(), STANCE, "left", 0.0, course())
    new = AlipQp().solve(periodic_dcm(), STANCE, "left", 0.0, course())
    assert isinstance(old, AlipPlanResult)
    np.testing.assert_array_equal(old.next_foothold, new.next_foothold)


def test_plan_needs_the_stones_ahead():
    with pytest.raises(InvalidInputError, match="course"):
        AlipMpc().plan(inp(periodic_dcm(), 0.0, None))


def test_stone_arrays_and_padding():
    seq = course(3)
    c, s = stone_arrays(seq)
    np.testing.assert_array_equal(c, seq.centers)
    c2, s2 = stone_arrays([seq[0], seq[1]])
    np.testing.assert_array_equal(c2, seq.centers[:2])
    c3, s3 = stone_arrays(seq.centers[:1], default_size=(0.3, 0.2))
    np.testing.assert_array_equal(s3, [[0.3, 0.2]])
    # padding repeats the last step with its lateral part mirrored, as free regions
    cp, sp = pad_stones(c[:2], s[:2], 4, STANCE)
    d = c[1] - c[0]
    np.testing.assert_allclose(cp[2], c[1] + [d[0], -d[1]])
    np.testing.assert_allclose(cp[3], cp[2] + [d[0], d[1]])
    assert np.all(np.isinf(sp[2:])) and np.all(np.isfinite(sp[:2]))
    # more stones than needed: the first n
    np.testing.assert_array_equal(pad_stones(c, s, 2, STANCE)[0], c[:2])


def test_stone_arrays_old_path_warns():
    import lipmpcc.planners.alip_mpc as old

    with pytest.warns(DeprecationWarning, match="alip_common"):
        f = old.stone_arrays
    assert f is stone_arrays


@pytest.mark.parametrize("cls", [AlipMpcParams, AlipQpParams])
@pytest.mark.parametrize(
    "kw, word",
    [
        ({"T_min": 0.7}, "T_min, T_nom, T_max"),
        ({"T_min": 0.5, "T_nom": 0.5, "T_max": 0.5}, "T_min < T_max"),
        ({"w": -0.1}, "w"),
        ({"replan_period": float("nan")}, "replan_period"),
        ({"min_time_to_touchdown": 0.7}, "min_time_to_touchdown"),
        ({"dcm_target": "later"}, "dcm_target"),
        ({"limits": "wide"}, "limits"),
        ({"alip": "digit"}, "alip"),
    ],
)
def test_shared_parameter_validation(cls, kw, word):
    """Both planners' parameters validate their common fields the same way."""
    with pytest.raises(ParameterError, match=word):
        cls(**kw)


def test_shared_derived_values():
    for p in (AlipMpcParams.paper(), AlipQpParams.paper()):
        assert p.lam == pytest.approx(math.sqrt(9.81 / 0.9))
        b = p.dcm_bounds
        assert b.x[1] == pytest.approx(0.6 / (math.exp(p.lam * 0.35) - 1.0))


def test_plan_names_an_input_that_is_not_a_planner_input():
    import pytest

    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.planners.alip_mpc import AlipMpc
    from lipmpcc.planners.alip_qp import AlipQp

    for planner in (AlipMpc(), AlipQp()):
        with pytest.raises(InvalidInputError, match=r"inp = None: expected a lipmpcc.planners.base.PlannerInput"):
            planner.plan(None)
