"""lipmpcc.planners.sources.mpcc: paper A's MPCC as a footstep source, without the simulator.

Exchange-state prediction, step-timing compensation, the first θ_init, the step-in-place on a failure
with no previous plan, the COM-height check, the plan it hands the loop, bad parameters.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lipmpcc.conventions import LEFT, RIGHT
from lipmpcc.exceptions import NoFallbackPlanError, ParameterError
from lipmpcc.models.lip3d import Lip3dModel
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.base import PlannerInput, StepPlan
from lipmpcc.planners.mpcc import MpccParams
from lipmpcc.planners.sources.mpcc import MpccFootstepSource, MpccSourceParams


def _inp(t: float, t_td: float, step: int, com, vel, stance_pos, stance: str = RIGHT, yaw: float = 0.0) -> PlannerInput:
    com = np.asarray(com, dtype=float)
    vel = np.asarray(vel, dtype=float)
    return PlannerInput(
        t=t, com_pos=com, com_vel=vel, dcm=com[:2] + vel[:2] / 3.2, omega=3.2, stance_side=stance,
        stance_pos=np.asarray(stance_pos, dtype=float), stance_yaw=yaw, swing_pos=np.zeros(3), swing_yaw=yaw,
        time_since_touchdown=t - t_td, step_index=step, torso_yaw=yaw,
    )


def _params(H: float = 0.95) -> MpccParams:
    from lipmpcc.studies.path_following import FULLBODY_RECTANGLE

    return MpccParams.circle(model=Lip3dModel(T=0.4, H=H), rectangle=FULLBODY_RECTANGLE)


def test_exchange_state_prediction_matches_the_lip_ode() -> None:
    from scipy.integrate import solve_ivp

    prm = _params()
    src = MpccFootstepSource(LinePath((0, 0), (10, 0)), prm)
    p = np.array([0.1, -0.12, 0.0])
    c, v = np.array([0.05, -0.03, 0.95]), np.array([0.4, 0.15, 0.0])
    inp = _inp(1.13, 1.0, 2, c, v, p)
    x, t_left = src.predicted_exchange_state(inp)
    assert t_left == pytest.approx(0.4 - 0.13)
    w2 = prm.model.omega**2
    sol = solve_ivp(lambda t, s: [s[1], w2 * (s[0] - p[0]), s[3], w2 * (s[2] - p[1])], (0, t_left),
                    [c[0], v[0], c[1], v[1]], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(x[:4], sol.y[:, -1], atol=1e-7)
    assert x[4] == 0.0


def test_requested_duration_compensates_early_touchdowns() -> None:
    src = MpccFootstepSource(LinePath((0, 0), (10, 0)), _params(), source_params=MpccSourceParams(timing_gain=0.5))
    p0, p1 = [0.0, -0.13, 0.0], [0.05, 0.1, 0.0]
    a = src.plan(_inp(0.6, 0.6, 0, [0, -0.08, 0.95], [0, 0.2, 0], p0))
    assert a.duration == pytest.approx(0.4)  # nothing learnt yet
    # the step lasted 0.385 s instead of 0.4: the offset estimate moves half-way to −15 ms
    b = src.plan(_inp(0.985, 0.985, 1, [0.03, 0.0, 0.95], [0.1, -0.1, 0], p1, stance=LEFT))
    assert src.timing_offset == pytest.approx(-0.0075)
    assert b.duration == pytest.approx(0.4075)
    # re-plans in the same swing do not learn again
    c = src.plan(_inp(1.05, 0.985, 1, [0.04, 0.0, 0.95], [0.1, -0.1, 0], p1, stance=LEFT))
    assert c.duration == pytest.approx(0.4075) and src.timing_offset == pytest.approx(-0.0075)
    assert [r.step_index for r in src.records] == [0, 1, 1]
    assert all(r.status == "converged" for r in src.records)


def test_first_solve_starts_at_the_beginning_of_a_closed_path() -> None:
    """1.25 turns of a circle pass the start twice: θ_init must not jump to the second pass."""
    path = ArcPath.circle(2.0, start=(0.0, 0.0), heading=0.0, turns=1.25)
    src = MpccFootstepSource(path, _params())
    src.plan(_inp(0.6, 0.6, 0, [0.0, -0.06, 0.95], [0.0, 0.2, 0.0], [0.0, -0.13, 0.0]))
    res = src.records[0].result
    assert res is not None and res.theta_init < 0.3
    assert res.v_avg > 0.05  # it plans to move along the path, not to stop near its end


def test_a_failed_first_solve_steps_in_place_and_is_counted(monkeypatch) -> None:
    src = MpccFootstepSource(LinePath((0, 0), (10, 0)), _params())

    def fail(*args, **kw):
        raise NoFallbackPlanError("mpcc/sqp", "infeasible", 3, "test")

    monkeypatch.setattr(src.planner, "solve", fail)
    plan = src.plan(_inp(0.6, 0.6, 0, [0.0, -0.06, 0.95], [0.0, 0.0, 0.0], [0.0, -0.13, 0.0]))
    assert plan.status.startswith("failed")
    assert src.solver_failures == 1
    # the left foot (swing) lands to the left of the predicted COM, by the middle of the lateral range
    x0, _ = src.predicted_exchange_state(_inp(0.6, 0.6, 0, [0.0, -0.06, 0.95], [0.0, 0.0, 0.0], [0.0, -0.13, 0.0]))
    assert plan.foothold[1] - x0[2] == pytest.approx(0.5 * sum(src.params.rectangle.lateral))
    assert src.records[-1].result is None


def test_a_model_height_other_than_the_loops_is_flagged() -> None:
    src = MpccFootstepSource(LinePath((0, 0), (10, 0)), _params(H=0.8).with_(jit=False))  # ω = 3.50 1/s vs 3.2
    with pytest.warns(UserWarning, match="COM height"):
        src.plan(_inp(0.6, 0.6, 0, [0.0, -0.06, 0.95], [0.0, 0.2, 0.0], [0.0, -0.13, 0.0]))



def test_the_plan_is_the_first_mpcc_step_from_the_predicted_exchange_state() -> None:
    """The foothold is x_0 + u_0 of the MPCC solved from the predicted exchange, the preview its
    footsteps with the model's T, the COM target its next state; the record keeps the solve."""
    src = MpccFootstepSource(LinePath((0, 0), (10, 0)), _params())
    inp = _inp(0.7, 0.6, 0, [0.0, -0.06, 0.95], [0.2, 0.2, 0.0], [0.0, -0.13, 0.0])
    plan = src.plan(inp)
    assert isinstance(plan, StepPlan) and plan.ok and src.rate_hz == 15.0 and src.name == "mpcc"
    rec = src.records[-1]
    assert plan.record is rec and rec.status == "converged" and rec.step_index == 0
    x0, t_left = src.predicted_exchange_state(inp)
    np.testing.assert_array_equal(rec.x0, x0)
    assert rec.t_exchange == pytest.approx(0.7 + t_left) and t_left == pytest.approx(0.3)
    u = rec.result.u0
    np.testing.assert_allclose(plan.foothold, [x0[0] + u[0], x0[2] + u[1]])
    assert plan.yaw == pytest.approx(x0[4] + u[2])
    assert plan.foothold[1] > x0[2]  # the right foot stands: the left one lands to the left of the COM
    assert plan.preview.shape == (len(rec.result.footsteps), 4) and np.all(plan.preview[:, 3] == 0.4)
    np.testing.assert_array_equal(plan.com_target, rec.result.states[1, [0, 2]])
    assert src.solve_times == [rec.result.solve_time] and src.solver_failures == 0
    src.reset()
    assert src.records == [] and src.timing_offset == 0.0


def test_bad_source_parameters_are_named() -> None:
    with pytest.raises(ParameterError, match="params"):
        MpccFootstepSource(LinePath((0, 0), (10, 0)), "circle")
    for field, value in (("rate_hz", 0.0), ("timing_gain", 1.5), ("max_timing_offset", -0.01)):
        with pytest.raises(ParameterError, match=field):
            dataclasses.replace(MpccSourceParams(), **{field: value})


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
def test_bad_source_params_are_named():
    import math

    import pytest

    from lipmpcc.exceptions import ParameterError
    from lipmpcc.planners.sources.mpcc import MpccSourceParams

    for kw, match in (({"rate_hz": None}, r"rate_hz = None"), ({"timing_gain": "x"}, r"timing_gain = 'x'"),
                      ({"max_timing_offset": math.inf}, r"max_timing_offset = inf")):
        with pytest.raises(ParameterError, match=match):
            MpccSourceParams(**kw)


def test_bad_source_arguments_are_named():
    import pytest

    from lipmpcc.exceptions import ParameterError
    from lipmpcc.paths import ArcPath
    from lipmpcc.planners.mpcc import MpccParams
    from lipmpcc.planners.sources.mpcc import MpccFootstepSource

    path = ArcPath.circle(2.0)
    with pytest.raises(ParameterError, match=r"obstacles = 'cylinder'"):
        MpccFootstepSource(path, MpccParams(), obstacles="cylinder")
    with pytest.raises(ParameterError, match=r"source_params = "):
        MpccFootstepSource(path, MpccParams(), source_params={"rate_hz": 15})
    src = MpccFootstepSource(path, MpccParams(), obstacles=iter(()))
    with pytest.raises(ParameterError, match=r"inp = 'abc'"):
        src.plan("abc")


def test_exchange_mismatches_are_zero_on_the_lip_and_measure_an_offset() -> None:
    """A robot that ends the step exactly in the planned LIP state has no mismatch; 1 cm off in x and
    2 cm/s off in ẏ, the mismatch says so (the state is given at the exchange, t̃ = T, so x0 is it)."""
    for dx, dvy in ((0.0, 0.0), (0.01, 0.02)):
        src = MpccFootstepSource(LinePath((0, 0), (10, 0)), _params())
        a = src.plan(_inp(0.6, 0.6, 0, [0.0, -0.06, 0.95], [0.2, 0.2, 0.0], [0.0, -0.13, 0.0]))
        assert src.exchange_mismatches()[0].size == 0  # no step after a planned one yet
        s1 = src.records[-1].result.states[1]
        com = [s1[0] + dx, s1[2], 0.95]
        vel = [s1[1], s1[3] + dvy, 0.0]
        src.plan(_inp(1.0, 0.6, 1, com, vel, [a.foothold[0], a.foothold[1], 0.0], stance=LEFT, yaw=a.yaw))
        steps, mm = src.exchange_mismatches()
        assert steps.tolist() == [1] and mm.shape == (1, 5)
        np.testing.assert_allclose(mm[0], [dx, 0.0, 0.0, dvy, 0.0], atol=1e-9)
