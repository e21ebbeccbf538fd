"""lipmpcc.studies.stepping_stones on the reference Digit v3 MJCF, unedited: ALIP-MPC with Digit v3's
ankle across Profile I and III courses. Skipped when ../shared is absent."""

from __future__ import annotations

import pytest

pytestmark = [pytest.mark.slow, pytest.mark.shared_model]


@pytest.fixture(scope="module")
def digit(shared_digit):
    """The reference Digit v3 (tests/conftest.py: described once per session)."""
    return shared_digit


@pytest.mark.parametrize("profile, L, W", [("I", 0.2, 0.15), ("III", None, None)])
def test_alip_mpc_crosses_stones(digit, profile, L, W) -> None:
    """Paper B on the user's file: ALIP-MPC at 25 Hz with Digit v3's ankle (``alip_cop_range``) over
    Profile I (L, W) = (0.2, +0.15) and Profile III seed 0, 32 stones each, on a MuJoCo course whose
    stones collide like Digit v3's own floor (conaffinity 127: its right leg has contype 4). With the
    point foot it fell on Profile III."""
    from lipmpcc.studies.stepping_stones import simulate_full_body as simulate
    from lipmpcc.terrain import make_profile

    assert digit.alip_cop_range == (0.04, 0.024) and digit.alip_cop_safety_factor == 0.8
    run = simulate(digit, "alip-mpc", make_profile(profile, 0, L, W))
    m = run.metrics
    assert not m["fell"], f"fell at stone {m['fall_step']}"
    assert m["steps_completed"] == 32
    assert m["step_rmse_m"] <= 0.05 and m["stones_violated"] == 0
    assert m["solver_failures"] == 0
