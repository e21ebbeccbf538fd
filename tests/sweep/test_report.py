"""lipmpcc.sweep.report: Wilson intervals, survival tables, the largest recoverable impulse, report.md."""

from __future__ import annotations

import math

import pytest

from lipmpcc.sweep.report import recoverable_impulse, survival_by, wilson_interval, write_report
from lipmpcc.sweep.spec import parse_spec
from lipmpcc.sweep.store import ResultStore


def test_wilson_interval_known_values() -> None:
    lo, hi = wilson_interval(5, 10)
    assert (lo, hi) == pytest.approx((0.2366, 0.7634), abs=1e-4)
    assert wilson_interval(0, 10)[0] == 0.0 and wilson_interval(10, 10)[1] == pytest.approx(1.0)
    assert all(math.isnan(x) for x in wilson_interval(0, 0))


def rows():
    out = []
    for d, imps in ((0.0, (5, 10, 15)), (math.pi, (5, 10, 15))):
        for imp in imps:
            ok = imp <= (10 if d == 0.0 else 5)
            out.append({"status": "done", "planner": "a", "p_direction": d, "impulse_Ns": float(imp), "survived": int(ok)})
    out.append({"status": "error", "planner": "a", "p_direction": 0.0, "impulse_Ns": 20.0, "survived": None})
    return out


def test_survival_by_and_recoverable_impulse() -> None:
    table = survival_by(rows(), "impulse_Ns")
    assert table[("a", 5.0)] == (2, 2) and table[("a", 10.0)] == (1, 2) and ("a", 20.0) not in table
    assert recoverable_impulse(rows()) == {("a", 0.0): 10.0, ("a", round(math.pi, 9)): 5.0}


def test_report_from_a_store(tmp_path) -> None:
    raw = {"study": "circle-push", "planners": ["mpcc", "cartesian"], "options": {"steps": 12},
           "axes": {"impulse": {"values": [2, 4]}, "direction": {"unit": "deg", "values": [0, 120, 240]}}}
    spec = parse_spec(raw)
    store = ResultStore(tmp_path / "results.sqlite", spec)
    for c in spec.cases():
        imp = c["params"]["impulse"]
        store.record(c, {"status": "done", "summary": {"fell": imp > 3 and c["planner"] == "cartesian"},
                         "push": {"force_N": imp / 0.1, "impulse_Ns": imp}, "wall_s": 1.0})
    store.close()
    path = write_report(tmp_path)
    text = path.read_text()
    assert "Survival against push impulse" in text and "Largest recoverable impulse" in text
    assert "| 120 | 2 | 4 |" in text  # cartesian falls above 3 N s, mpcc never
    assert "| cartesian | 6/12" not in text and "6/6 = 100 %" in text
    assert (tmp_path / "survival_vs_impulse.png").is_file() and (tmp_path / "recoverable_impulse_polar.png").is_file()
