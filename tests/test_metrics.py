"""lipmpcc.metrics: timing statistics [ms], RMS and largest absolute value, empty input included."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.metrics import max_abs, rms, timing_stats_ms


def test_timing_stats_are_in_milliseconds() -> None:
    s = timing_stats_ms([0.001 * k for k in range(1, 11)])  # 1 .. 10 ms
    assert s["n"] == 10 and isinstance(s["n"], int)
    assert s["median"] == pytest.approx(5.5) and s["max"] == pytest.approx(10.0)
    assert s["p90"] == pytest.approx(np.percentile(np.arange(1, 11), 90))
    assert s["median"] <= s["p90"] <= s["max"]
    assert timing_stats_ms(iter([0.002]))["median"] == pytest.approx(2.0)  # any iterable


def test_timing_stats_of_nothing_are_nan() -> None:
    s = timing_stats_ms([])
    assert s["n"] == 0 and all(math.isnan(s[k]) for k in ("median", "p90", "max"))


def test_rms_and_max_abs() -> None:
    assert rms([3.0, -4.0]) == pytest.approx(math.sqrt(12.5))
    assert rms(np.full(7, -2.0)) == pytest.approx(2.0)
    assert max_abs([0.5, -3.0, 2.0]) == 3.0
    assert max_abs((x for x in [-1.0])) == 1.0
    assert math.isnan(rms([])) and math.isnan(max_abs([]))
    assert math.isnan(rms([1.0, float("nan")]))  # NaN propagates: a failed sample is not hidden


def test_wilson_interval_lives_here_and_in_the_sweep_report() -> None:
    from lipmpcc.metrics import wilson_interval
    from lipmpcc.sweep import report

    assert report.wilson_interval is wilson_interval
    lo, hi = wilson_interval(19, 20)
    assert 0.75 < lo < 0.95 < hi <= 1.0
