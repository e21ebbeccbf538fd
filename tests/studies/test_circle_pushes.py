"""Paper B's four pushes while following the circle (lipmpcc.studies.circle_pushes)."""

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.studies.circle_pushes import (PUSH_NAMES, paper_b_circle_push, paper_b_circle_pushes,
                                           run_paper_b_circle)


def test_the_pushes_are_paper_b_s_forces_in_the_walking_frame():
    """Heading 90° (walking +y): forward +150 N is +y, backward −y, left (+75 N) is −x, right +x; 0.1–0.2 s
    after the touch-down, registered at the footstep (the LIP) or at the absolute time (a full body)."""
    fwd, back, left, right = paper_b_circle_pushes([0.0, 1.0, 2.0, 3.0, 4.0], [math.pi / 2] * 5, [1, 2, 3, 4])
    np.testing.assert_allclose(fwd.force, (0.0, 150.0), atol=1e-9)
    np.testing.assert_allclose(back.force, (0.0, -150.0), atol=1e-9)
    np.testing.assert_allclose(left.force, (-75.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(right.force, (75.0, 0.0), atol=1e-9)
    assert (fwd.step, fwd.t_start, fwd.t_end) == (1, pytest.approx(0.1), pytest.approx(0.2))
    p = paper_b_circle_push(1, 3.0, 0.0, 7, by_step=False, scale=2.0)
    assert p.step is None and p.t_start == pytest.approx(3.1) and p.t_end == pytest.approx(3.2)
    np.testing.assert_allclose(p.force, (-300.0, 0.0), atol=1e-9)


@pytest.mark.parametrize("kw, name", [
    (dict(steps=[1, 2, 3]), "steps"),
    (dict(steps=[1, 2, 3, 9]), "steps"),  # beyond the timeline
    (dict(steps=[1, 2, 3, 4], scale=-1.0), "scale"),
    (dict(steps=[1, 2, 3, 4], scale=float("nan")), "scale"),
])
def test_bad_pushes_are_refused_naming_the_argument(kw, name):
    with pytest.raises(InvalidInputError, match=name):
        paper_b_circle_pushes([0.0] * 5, [0.0] * 5, **kw)


def test_bad_pushed_steps_are_refused_before_any_run():
    with pytest.raises(InvalidInputError, match="increasing footsteps"):
        run_paper_b_circle("lip", steps=[10, 5, 20, 30])


def test_the_timed_mpcc_at_25_hz_survives_and_re_times_the_pushed_step_as_paper_b_fig7():
    """On the LIP (fast mode: 40 steps), the timed MPCC re-planned at 25 Hz survives the four pushes; the step
    during the forward push is shorter than nominal and than unpushed, during the backward push longer than
    unpushed; every push acts 0.1 s into its swing, along the walking frame of the pushed run."""
    run = run_paper_b_circle("lip", step_duration_range=(0.3, 0.5), replan_hz=25.0)
    assert run.survived and run.summary["replan_hz"] == 25.0 and run.summary["solver_failures"] == 0
    out = {o.name: o for o in run.pushes}
    assert list(out) == list(PUSH_NAMES)
    for o in run.pushes:
        assert o.phase == pytest.approx(0.1, abs=1e-9) and abs(o.heading_error) < 1e-6
    fwd, back = out["forward"], out["backward"]
    assert fwd.durations[1] < 0.4 - 0.03 and fwd.durations[1] < fwd.reference[1] - 0.03
    assert back.durations[1] > back.reference[1] + 0.01


def test_on_the_circle_the_outer_foot_lands_on_the_inner_lateral_bound_and_the_inner_foot_does_not():
    """Why the two feet's steps differ on the circle (docs/design.md): unpushed, on the LIP under the timed
    MPCC (25 Hz) on the counter-clockwise circle, the outer (right) foot lands on the reachability's inner
    lateral bound (0.05 m right of the COM, in the heading frame), the inner (left) foot off it; the steps
    standing on the inner foot, which end by placing the outer one, are the longer ones."""
    from lipmpcc.loops.lip import run_lip_loop
    from lipmpcc.planners.mpcc import MpccParams
    from lipmpcc.studies.path_scenarios import circle_path
    from lipmpcc.studies.path_params import timed_lip_planner

    path = circle_path((0.0, 0.0), 0.0)
    prm = MpccParams.circle()
    planner = timed_lip_planner(path, prm, (0.3, 0.5), within_step=True)
    log = run_lip_loop(planner, np.zeros(5), 12, path, first_side=1, com_height=prm.model.H, gravity=prm.model.g,
                       progress=False, replan_hz=25.0)
    d = np.diff(log.t)
    inner = prm.rectangle.lateral[0]
    for k in range(6, 11):
        foot, x = log.footholds[k + 1], log.states[k + 1]  # the foot placed at the end of step k, the COM there
        left = -math.sin(x[4]) * (foot[0] - x[0]) + math.cos(x[4]) * (foot[1] - x[2])
        if log.sides[k] > 0:  # standing on the left (inner) foot: the right foot is placed, on the bound
            assert left == pytest.approx(-inner, abs=1e-3)
            assert d[k] > d[k - 1] + 0.01
        else:  # standing on the right (outer) foot: the left foot is placed, off the bound
            assert left > inner + 0.003
