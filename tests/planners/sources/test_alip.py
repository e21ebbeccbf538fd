"""lipmpcc.planners.sources.alip: paper B's ALIP planners as footstep sources of the full-body loop.

The source's pieces (eq. 2 DCM, the contact-phase and landing models, the course extension) and its
plan() on hand-made planner inputs (no simulator): the step asked of the loop, the records, the
answer without a plan, bad arguments.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.loops.alip import AlipInitialState
from lipmpcc.models.alip import AlipParams
from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams
from lipmpcc.planners.base import PlannerInput, StepPlan
from lipmpcc.planners.sources.alip import (
    AlipFootstepSource,
    AlipSourceParams,
    ContactPhaseModel,
    LandingBiasModel,
    contact_dcm,
    extend_course,
)
from lipmpcc.terrain import approach_footholds, make_profile

A = AlipParams()


def _standing_input(course, t: float = 0.0) -> PlannerInput:
    """Standing on the left foot at rest (the reduced loop's start), ``t`` seconds into the first swing."""
    init = AlipInitialState.standing()
    com = np.array([*init.com, A.z_c])
    return PlannerInput(
        t=t, com_pos=com, com_vel=np.zeros(3), dcm=com[:2].copy(), omega=A.lam, stance_side="left",
        stance_pos=np.array([*init.stance, 0.0]), stance_yaw=0.0, swing_pos=np.array([*init.swing_foot, 0.0]),
        swing_yaw=0.0, time_since_touchdown=t, step_index=0, torso_yaw=0.0, mass=A.mass, course=course,
    )


def test_plan_from_standing_asks_for_the_planned_step_stretched_to_the_contact_phase() -> None:
    course = approach_footholds()
    src = AlipFootstepSource(AlipMpc(), course)
    plan = src.plan(_standing_input(course))
    assert isinstance(plan, StepPlan) and plan.ok and plan.yaw == 0.0 and plan.cop_offset is None
    rec = src.records[0]
    assert plan.record is rec and rec.role == "course" and rec.step_index == 0 and rec.stance_side == 1
    np.testing.assert_array_equal(rec.dcm, _standing_input(course).com_pos[:2])  # at rest: ξ = c
    # at lift-off the loop is asked for R = T / τ_c, τ_c the initial contact phase (0.9)
    assert 0.35 <= rec.planned_duration <= 0.65
    assert plan.duration == pytest.approx(rec.planned_duration / AlipSourceParams().contact_phase)
    # the right foot swings: it lands to the right of the stance foot, the preview alternates feet
    assert plan.foothold[1] < 0.0 and plan.preview.shape[1] == 4
    assert np.all(np.sign(plan.preview[:, 1]) == [-1, 1, -1, 1])
    # a re-plan within the swing is recorded too; reset forgets
    again = src.plan(_standing_input(course, t=0.04))
    assert len(src.records) == 2 and again.record.time_since_touchdown == pytest.approx(0.04)
    src.reset()
    assert src.records == [] and src.solver_failures == 0


def test_without_a_plan_the_source_aims_at_the_next_stone_and_counts_it() -> None:
    """From standing the first stone 1.35 m ahead is out of reach: the MPC has no plan and no
    fallback; the source answers the stone's centre with a "failed" status (a solver failure)."""
    stones = make_profile("I", L=0.3, W=0.0).head(4)
    src = AlipFootstepSource(AlipMpc(), stones)
    plan = src.plan(_standing_input(stones))
    assert not plan.ok and plan.status.startswith("failed")
    np.testing.assert_array_equal(plan.foothold, stones.centers[0])
    assert src.no_fallback_failures == {"approach": 0, "course": 1} and src.records[0].result is None
    assert math.isnan(src.records[0].z0[0])


def test_bad_arguments_are_named() -> None:
    course = approach_footholds()
    with pytest.raises(InvalidInputError, match="planner"):
        AlipFootstepSource(object(), course)
    with pytest.raises(InvalidInputError, match="course"):
        AlipFootstepSource(AlipMpc(), "stones")
    with pytest.raises(InvalidInputError, match="approach_steps"):
        AlipFootstepSource(AlipMpc(), course, approach_planner=AlipMpc(), approach_steps=len(course) + 1)
    with pytest.raises(ParameterError, match="params"):
        AlipFootstepSource(AlipMpc(), course, params="fast")
    for field, value in (("rate_hz", 0.0), ("contact_phase", 0.5), ("dcm_bias_gain", 2.0), ("hold_phase", 0.0)):
        with pytest.raises(ParameterError, match=field):
            dataclasses.replace(AlipSourceParams(), **{field: value})


@pytest.mark.slow
def test_contact_dcm_is_the_lip_dcm_plus_the_centroidal_momentum_term() -> None:
    m, zc = 48.0, 0.95
    lam = math.sqrt(9.81 / zc)
    c, v, p = np.array([0.1, -0.05, zc]), np.array([0.4, 0.2, 0.0]), np.array([0.02, 0.1])
    xi, L = contact_dcm(c, v, None, p, m, zc)
    np.testing.assert_allclose(L, m * np.cross(c - np.r_[p, 0.0], v), atol=1e-12)
    np.testing.assert_allclose(xi, c[:2] + v[:2] / lam, atol=1e-12)  # eq. 2 for a point mass at z_c
    k = np.array([1.0, -2.0, 0.3])
    xi_k, L_k = contact_dcm(c, v, k, p, m, zc)
    np.testing.assert_allclose(L_k - L, k, atol=1e-12)
    np.testing.assert_allclose(xi_k - xi, np.array([k[1], -k[0]]) / (lam * m * zc), atol=1e-12)


@pytest.mark.slow
def test_contact_phase_model_learns_a_linear_law_and_stays_in_bounds() -> None:
    model = ContactPhaseModel(0.9, (0.7, 1.0), window=12)
    assert model.predict(0.5) == pytest.approx(0.9)
    for d in np.linspace(0.2, 1.2, 12):
        model.update(float(d), 0.91 - 0.02 * float(d))
    assert model.predict(1.0) == pytest.approx(0.89, abs=2e-3)
    assert model.predict(0.3) > model.predict(1.1)
    assert 0.7 <= model.predict(1e3) <= 1.0


@pytest.mark.slow
def test_contact_phase_model_learns_the_duration_term() -> None:
    """Alternating long and short steps of the same travel: the phase law separates them."""
    model = ContactPhaseModel(0.9, (0.7, 1.0), window=12)
    for k in range(12):
        T = 0.43 if k % 2 else 0.65
        model.update(0.6, 0.88 - 0.1 * (T - 0.54), T)
    assert model.predict(0.6, 0.43) == pytest.approx(0.88 + 0.011, abs=1e-3)
    assert model.predict(0.6, 0.65) == pytest.approx(0.88 - 0.011, abs=1e-3)
    assert model.predict(0.6) == pytest.approx(0.88, abs=1e-3)  # duration unknown: the mean phase
    same = ContactPhaseModel(0.9, (0.7, 1.0), window=12)
    for _ in range(12):
        same.update(0.6, 0.88, 0.5)  # no spread in T: no duration term
    assert same.predict(0.6, 0.3) == pytest.approx(0.88, abs=1e-9)


@pytest.mark.slow
def test_landing_bias_model_sends_a_target_the_foot_lands_on() -> None:
    model = LandingBiasModel(window=8)
    gain = np.array([-0.015, 0.005])
    rng = np.random.default_rng(0)
    for _ in range(8):
        travel = rng.uniform([0.3, -0.5], [1.2, 0.5])
        model.update(travel, gain * travel)
    np.testing.assert_allclose(model.gain, gain, atol=2e-3)
    lift, target = np.array([0.0, 0.1]), np.array([1.1, -0.3])
    cmd = model.command(lift, target)
    landed = cmd + gain * (cmd - lift)  # the same proportional shortfall on the commanded swing
    np.testing.assert_allclose(landed, target, atol=2e-3)


@pytest.mark.slow
def test_extend_course_repeats_the_last_step_with_alternating_feet() -> None:
    stones = make_profile("I", 0, 0.4, 0.15).head(3)
    ext = extend_course(stones, 2)
    assert len(ext) == 5 and not np.any(ext.is_stone[3:]) and np.all(np.isinf(ext.sizes[3:]))
    d = stones.centers[2] - stones.centers[1]
    np.testing.assert_allclose(ext.centers[3] - ext.centers[2], [d[0], -d[1]])
    assert list(ext.sides[2:]) == [int(stones.sides[2]), -int(stones.sides[2]), int(stones.sides[2])]


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
def test_bad_source_params_are_named():
    import math

    import pytest

    from lipmpcc.exceptions import ParameterError
    from lipmpcc.planners.sources.alip import AlipSourceParams

    cases = (({"rate_hz": None}, r"rate_hz = None"), ({"contact_phase_bounds": "x"}, r"contact_phase_bounds = 'x'"),
             ({"contact_phase_bounds": (0.7, math.nan)}, r"contact_phase_bounds = .*NaN"),
             ({"relax_on_failure": "yes"}, r"relax_on_failure = 'yes': expected True or False"),
             ({"centroidal_momentum": None}, r"centroidal_momentum = None"), ({"heading": "north"}, r"heading = 'north'"),
             ({"contact_window": 2.5}, r"contact_window = 2.5"))
    for kw, match in cases:
        with pytest.raises(ParameterError, match=match):
            AlipSourceParams(**kw)


def test_plan_names_an_input_that_is_not_a_planner_input():
    import pytest

    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams
    from lipmpcc.planners.sources.alip import AlipFootstepSource
    from lipmpcc.terrain import approach_footholds, make_profile

    src = AlipFootstepSource(AlipMpc(), approach_footholds() + make_profile("I"))
    with pytest.raises(InvalidInputError, match=r"inp = 3"):
        src.plan(3)


def _step_one_input(course, plan: StepPlan, t_td: float, t: float, com_vel: np.ndarray) -> PlannerInput:
    """On the right foot (landed at ``plan.foothold`` at ``t_td``), ``t`` seconds after that touch-down."""
    com = np.array([plan.foothold[0] - 0.05, 0.5 * plan.foothold[1], A.z_c])
    init = AlipInitialState.standing()
    return PlannerInput(
        t=t_td + t, com_pos=com, com_vel=com_vel, dcm=com[:2].copy(), omega=A.lam, stance_side="right",
        stance_pos=np.array([plan.foothold[0], plan.foothold[1], 0.0]), stance_yaw=0.0,
        swing_pos=np.array([*init.stance, 0.0]), swing_yaw=0.0, time_since_touchdown=t, step_index=1,
        torso_yaw=0.0, mass=A.mass, course=course,
    )


@pytest.mark.parametrize("cop_range", [(0.0, 0.0), (0.04, 0.015)])
def test_settled_dcm_bias_is_learned_after_the_settling_time_from_the_dcm_carried_back(cop_range) -> None:
    """``dcm_settle_time``: the right swing's touch-down bias is learned at the first call that late
    into the next step, from the DCM then carried back to the touch-down along the new stance's LIP (about
    the stance point plus the last plan's centre-of-pressure offset, with a foot); with 0 it is learned at
    the touch-down from the DCM measured then."""
    course = approach_footholds()
    t_td, settle, gain = 0.45, 0.08, AlipSourceParams().dcm_bias_gain
    v0, v1 = np.array([0.5, -0.1, 0.0]), np.array([0.3, 0.05, 0.0])
    biases = {}
    for st in (0.0, settle):
        mpc = AlipMpc(AlipMpcParams.paper(cop_range=cop_range))
        src = AlipFootstepSource(mpc, course, params=AlipSourceParams(dcm_settle_time=st))
        plan = src.plan(_standing_input(course))
        z0_last, stance0 = src.records[-1].z0.copy(), src.records[-1].stance.copy()
        first = _step_one_input(course, plan, t_td, 0.0, v0)
        src.plan(first)
        if st > 0.0:
            np.testing.assert_array_equal(src.dcm_bias[-1], 0.0)  # not yet: within the settling time
            cop = src.records[-1].result.cop_offset  # the pivot's offset, from the call before
            later = _step_one_input(course, plan, t_td, settle, v1)
            src.plan(later)
            xi = later.com_pos[:2] + v1[:2] / A.lam
            pivot = later.stance_pos[:2] + cop
            xi_td = pivot + (xi - pivot) * math.exp(-A.lam * settle)
        else:
            xi_td = first.com_pos[:2] + v0[:2] / A.lam
        drift = (xi_td - stance0) * math.exp(-A.lam * t_td) - z0_last
        np.testing.assert_allclose(src.dcm_bias[-1], gain * np.clip(drift, -0.05, 0.05), atol=1e-9)
        np.testing.assert_array_equal(src.dcm_bias[1], 0.0)
        biases[st] = src.dcm_bias[-1].copy()
    assert float(np.max(np.abs(biases[0.0] - biases[settle]))) > 1e-3
    with pytest.raises(ParameterError, match="dcm_settle_time"):
        AlipSourceParams(dcm_settle_time=-0.01)
