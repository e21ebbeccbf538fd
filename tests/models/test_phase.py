"""lipmpcc.models.phase.PhaseClock: the swing phase τ(t), linear between re-timings, continuous through them."""

from __future__ import annotations

import pytest

from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.models.phase import PhaseClock


def test_phase_is_linear_and_clipped() -> None:
    c = PhaseClock(1.0, 1.4)
    assert c.t_end == 1.4 and c.duration == pytest.approx(0.4)
    assert c.tau(1.0) == 0.0 and c.tau(1.1) == pytest.approx(0.25) and c.tau(1.4) == pytest.approx(1.0)
    assert c.tau(0.5) == 0.0 and c.tau(2.0) == 1.0  # clipped outside the step
    assert c.rate() == pytest.approx(2.5) and c.tau_dot(1.2) == pytest.approx(2.5)
    assert c.tau_dot(1.4) == 0.0


def test_retime_keeps_the_phase_continuous_and_ends_at_the_new_time() -> None:
    """Paper B eq. 12: τ(t) = τ^i + (1 − τ^i)(t − t^i)/(T_des − t^i) from the re-timing on."""
    c = PhaseClock(0.0, 0.4)
    before = c.tau(0.2)
    c.retime(0.2, 0.3)  # the step is shortened from 0.4 to 0.3 s at half phase
    assert c.tau(0.2) == pytest.approx(before) == pytest.approx(0.5)
    assert c.tau(0.25) == pytest.approx(0.75) and c.tau(0.3) == pytest.approx(1.0)
    assert c.rate() == pytest.approx(0.5 / 0.1) and c.t_end == 0.3 and c.duration == pytest.approx(0.3)
    c.retime(0.25, 0.5)  # then lengthened
    assert c.tau(0.25) == pytest.approx(0.75) and c.tau(0.5) == pytest.approx(1.0)
    assert c.tau(0.375) == pytest.approx(0.875)


def test_a_finished_step_is_not_retimed() -> None:
    c = PhaseClock(0.0, 0.4)
    c.retime(0.5, 0.9)  # τ(0.5) = 1 already: nothing changes
    assert c.t_end == 0.4 and c.tau(0.45) == 1.0


def test_bad_times_are_named() -> None:
    with pytest.raises(ParameterError, match="t_end"):
        PhaseClock(1.0, 1.0)
    with pytest.raises(InvalidInputError, match="t_start"):
        PhaseClock(float("nan"), 1.0)
    with pytest.raises(InvalidInputError, match="t_end"):
        PhaseClock(0.0, "soon")
    c = PhaseClock(0.0, 0.4)
    with pytest.raises(ParameterError, match="later than the current time"):
        c.retime(0.2, 0.1)
    with pytest.raises(InvalidInputError, match="t"):
        c.retime(float("inf"), 0.5)
