"""lipmpcc.loops.fullbody.loop on the reference Digit v3 MJCF, unedited (bring your own Digit).

osudrl/roadrunner's ``digit-v3.xml`` (../shared, MIT): a slide+ball base, six closed loops (achilles,
toe-A and toe-B rods, ``<equality connect>``), passive shin and heel springs, 20 geared motors. The
runs of the digit_like walking tests, with the same criteria, through the same loop (MuJoCo 2 kHz,
C++ whole-body QP 400 Hz, capture-point steps): standing under four 50 N pushes, 10 m straight at
≥ 0.5 m/s, a full circle of radius 2 m, 20 steps in place. None may fall, and MuJoCo's loop
constraints (soft) must stay closed to 1 mm throughout. (The studies on Digit v3:
tests/studies/test_*_digit_v3.py; the controller: tests/control/test_wbc_digit_v3.py.)

Skipped when ../shared is absent (``shared_digit``). About 50 s of simulated time in all.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from .loop_watch import LOOP_TOLERANCE, LoopWatch
from .walking_checks import check_full_circle, check_steps_in_place, check_walked_10m_straight

pytestmark = [pytest.mark.slow, pytest.mark.shared_model]


@pytest.fixture(scope="module")
def digit(shared_digit):
    """The reference Digit v3 (tests/conftest.py: described once per session)."""
    return shared_digit


def _loop(robot, speed: float | None, yaw_rate: float = 0.0):
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.loops.fullbody.loop import FullBodyLoop

    planner = None if speed is None else CapturePointPlanner(speed=speed, yaw_rate=yaw_rate)
    loop = FullBodyLoop(robot, planner=planner)
    return loop, LoopWatch(loop.sim)


def test_the_file_is_taken_as_is(digit, shared_digit_xml: Path) -> None:
    """The description and the controller read the unedited file: slide+ball base, 6 loops, 4 passive
    springs, 20 geared motors bounded by gear × ctrlrange."""
    from lipmpcc.control.wbc import WholeBodyController

    assert digit.mjcf_path == shared_digit_xml and digit.closed_loops and digit.base_joint is None
    wbc = WholeBodyController(digit)
    assert wbc.model.base_kind == "slide+ball" and wbc.n_loops == 6 and wbc.spring_model == "rigid"
    assert wbc.params.cop_safety_factor == pytest.approx(0.6)  # the Digit v3 layout's override


def test_stands_5s_under_four_50N_pushes(digit) -> None:
    from lipmpcc.studies.walking import stand_pushes

    loop, watch = _loop(digit, None)
    res = loop.run(duration=5.0, pushes=stand_pushes(t_first=1.0, spacing=1.0))
    log = res.log
    assert not res.fell, f"fell at t = {res.fall_time:.2f} s"
    assert res.min_base_height > log.base_height[0] - 0.05
    # both feet down (a lateral push may unload the far foot below 1 N for a tick or two)
    assert np.mean(np.all(log.contact, axis=1)) > 0.995
    feet_drift = (np.linalg.norm(log.left_foot[-1] - log.left_foot[0])
                  + np.linalg.norm(log.right_foot[-1] - log.right_foot[0]))
    assert feet_drift < 0.01
    c = log.com[:, :2] - log.com[0, :2]
    assert np.max(np.linalg.norm(c, axis=1)) > 1e-3  # the pushes move it
    assert np.linalg.norm(c[-1]) < 0.01  # and it comes back
    assert res.qp_failures == 0
    assert watch.max < LOOP_TOLERANCE


def test_walks_10m_straight_at_least_half_a_metre_per_second(digit) -> None:
    loop, watch = _loop(digit, 0.6)
    check_walked_10m_straight(loop.run(duration=19.0))
    assert watch.max < LOOP_TOLERANCE


def test_walks_a_full_circle_of_radius_2m(digit) -> None:
    v, R = 0.5, 2.0
    loop, watch = _loop(digit, v, yaw_rate=v / R)
    check_full_circle(loop.run(duration=28.0), R)
    assert watch.max < LOOP_TOLERANCE


def test_twenty_steps_in_place(digit) -> None:
    loop, watch = _loop(digit, 0.0)
    check_steps_in_place(loop.run(n_steps=20), 20)
    assert watch.max < LOOP_TOLERANCE
