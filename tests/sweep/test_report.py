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


# ---------------------------------------------------------------------------- the point-foot bound
def test_point_foot_bound_formula_and_limits() -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.models.alip import min_forward_dcm_on_stones
    from lipmpcc.sweep.report import point_foot_bound

    lam = math.sqrt(9.81 / 0.9)
    z_nom = 0.4 / (math.exp(lam * 0.5) - 1.0)  # the periodic gait's initial DCM, L / (sigma - 1)
    # stance on stone 4 (x = 2.65 m), stones 5..7 ahead, near edges 0.1 m before their centres
    z_req = min_forward_dcm_on_stones(2.65, [2.95, 3.35, 3.75], lam, 0.65)
    impulsive = (z_nom - z_req) * 47.9 * lam * math.exp(lam * 0.15)  # an instantaneous push: DCM jump J/(m lam)
    assert point_foot_bound(0.15, 1e-7, 10, 7) == pytest.approx(impulsive, rel=1e-6)
    # a push held for dt acts as its impulse times (1 - e^{-lam dt}) / (lam dt) < 1: more impulse is needed
    x = lam * 0.1
    assert point_foot_bound(0.15, 0.1, 10, 7) == pytest.approx(impulsive * x / (1 - math.exp(-x)), rel=1e-9)
    # later in the step the DCM has run further ahead: e^{lam t_p}
    assert point_foot_bound(0.25, 0.1, 10, 7) / point_foot_bound(0.15, 0.1, 10, 7) == pytest.approx(math.exp(lam * 0.1))
    # more stones ahead: z_req grows a little (the series converges)
    assert point_foot_bound(0.15, 0.1, 10, 24) < point_foot_bound(0.15, 0.1, 10, 7) < point_foot_bound(0.15, 0.1, 10, 6)
    with pytest.raises(InvalidInputError, match="push_step"):
        point_foot_bound(0.15, 0.1, 3, 7)  # the stance is on the approach
    with pytest.raises(InvalidInputError, match="duration"):
        point_foot_bound(0.15, 0.0, 10, 7)


def test_point_foot_bound_against_the_alip(monkeypatch) -> None:
    """The derivation's nominal state is the runs', and a backward push just above the bound makes the point
    foot fall (the bound is necessary); the foot survives it."""
    from lipmpcc.models.alip import AlipParams
    from lipmpcc.push import Push
    from lipmpcc.studies.stone_course import push_stones
    from lipmpcc.studies.stepping_stones import run_case
    from lipmpcc.sweep.report import point_foot_bound

    monkeypatch.setenv("LIPMPCC_FAST", "1")
    a = AlipParams()
    log, _ = run_case("alip-mpc", push_stones(7), pushes=(), alip=a, cop_range=(0.0, 0.0))
    z_nom = 0.4 / (math.exp(a.lam * 0.5) - 1.0)
    assert log.z_initial[10][0] == pytest.approx(z_nom, abs=1e-3)  # stance on stone 4, swing towards stone 5
    J = point_foot_bound(0.15, 0.1, 10, 7, a.mass, a.z_c, a.g)
    push = [Push((-1.05 * J / 0.1, 0.0), 0.15, 0.1, step=10)]
    pushed, _ = run_case("alip-mpc", push_stones(7), pushes=push, alip=a, cop_range=(0.0, 0.0))
    assert pushed.fell, f"the point foot survived a backward push of {1.05 * J:.1f} N s > the bound {J:.1f} N s"


def test_report_draws_the_point_foot_bound(tmp_path) -> None:
    from lipmpcc.sweep.report import BOUND_LABEL, load_rows, point_foot_bound, point_foot_bounds

    raw = {"study": "push", "robot": "alip", "options": {"steps": 7},
           "planners": [{"label": "pf", "planner": "alip-mpc", "cop_range": [0.0, 0.0]},
                        {"label": "foot", "planner": "alip-mpc", "cop_range": [0.06, 0.025]}],
           "axes": {"impulse": {"unit": "N*s", "values": [10, 20]},
                    "direction": {"unit": "deg", "values": [0, 90, 180]},
                    "onset": {"unit": "fraction", "value": 0.3}}}
    spec = parse_spec(raw)
    store = ResultStore(tmp_path / "results.sqlite", spec)
    for c in spec.cases():
        imp, back = c["params"]["impulse"], math.cos(c["params"]["direction"]) < -0.5
        cop = c["options"]["cop_range"]
        fell = back and imp > 15 and not any(cop)
        store.record(c, {"status": "done", "wall_s": 1.0, "push": {"force_N": imp / 0.1, "impulse_Ns": imp},
                         "summary": {"fell": fell, "robot": "alip", "planner": "alip-mpc", "stones_total": 7,
                                     "model": {"mass_kg": 47.9, "z_c_m": 0.9, "g": 9.81, "cop_range_m": cop}}})
    store.close()
    meta, rows_ = load_rows(tmp_path)
    bounds = point_foot_bounds(meta, rows_)
    assert list(bounds) == ["pf"]  # the foot has no such bound
    assert bounds["pf"] == pytest.approx(point_foot_bound(0.15, 0.1, 10, 7))  # onset 0.3 x 0.5 s, the swing to stone 5
    text = write_report(tmp_path).read_text()
    assert f"{BOUND_LABEL} for `pf`: a backward push of more than {bounds['pf']:.2f} N s" in text
    assert (tmp_path / "recoverable_impulse_polar.png").is_file()


def test_no_point_foot_bound_off_the_stones_or_for_mixed_timings(tmp_path) -> None:
    from lipmpcc.sweep.report import load_rows, point_foot_bounds

    raw = {"study": "push", "robot": "alip", "options": {"steps": 7},
           "planners": [{"label": "pf", "planner": "alip-mpc", "cop_range": [0.0, 0.0]}],
           "axes": {"impulse": {"unit": "N*s", "values": [10]}, "direction": {"unit": "deg", "values": [0, 90, 180]},
                    "push_step": {"values": [3, 10]}}}
    spec = parse_spec(raw)
    for name, keep in (("approach", 3), ("mixed", None)):
        store = ResultStore(tmp_path / name / "results.sqlite", spec)
        for c in spec.cases():
            if keep is not None and c["params"]["push_step"] != keep:
                continue
            store.record(c, {"status": "done", "wall_s": 1.0, "push": {"force_N": 100.0, "impulse_Ns": 10.0},
                             "summary": {"fell": False, "robot": "alip", "planner": "alip-mpc", "stones_total": 7,
                                         "model": {"mass_kg": 47.9, "z_c_m": 0.9, "g": 9.81, "cop_range_m": [0, 0]}}})
        store.close()
        assert point_foot_bounds(*load_rows(tmp_path / name)) == {}, name
        assert "point-foot bound" not in write_report(tmp_path / name).read_text()
    tuned = {**raw, "planners": [{"label": "pf", "planner": "alip-mpc", "cop_range": [0.0, 0.0], "set": {"T_max": 0.8}}],
             "axes": {**raw["axes"], "push_step": {"value": 10}}}
    spec = parse_spec(tuned)
    store = ResultStore(tmp_path / "tuned" / "results.sqlite", spec)
    for c in spec.cases():
        store.record(c, {"status": "done", "wall_s": 1.0, "push": {"force_N": 100.0, "impulse_Ns": 10.0},
                         "summary": {"fell": False, "robot": "alip", "planner": "alip-mpc", "stones_total": 7,
                                     "model": {"mass_kg": 47.9, "z_c_m": 0.9, "g": 9.81, "cop_range_m": [0, 0]}}})
    store.close()
    assert point_foot_bounds(*load_rows(tmp_path / "tuned")) == {}, "T_max set: paper B's bound does not apply"


def test_report_counts_how_path_runs_ended_with_the_success_rate(tmp_path) -> None:
    """issue 31: completed and trailing are successes; stalled, incomplete and an unknown outcome are not;
    the stalled cases are listed with what bound them."""
    raw = {"study": "overtake", "planners": ["mpcc"], "options": {"steps": 12},
           "axes": {"obstacle_speed": {"values": [0.1, 0.2, 0.3, 0.4, 0.5]}}}
    spec = parse_spec(raw)
    store = ResultStore(tmp_path / "results.sqlite", spec)
    ends = ["completed", "trailing", "stalled", "incomplete", "teleported"]
    for c, o in zip(spec.cases(), ends):
        s = {"fell": False, "outcome": o, "reached_end": o == "completed", "progress_m": 1.0, "path_length_m": 40.0}
        if o == "stalled":
            s["stall"] = {"binding": {"text": "obstacle 0 (0.03 m) blocked the robot"}}
        store.record(c, {"status": "done", "summary": s, "wall_s": 1.0})
    store.close()
    text = write_report(tmp_path).read_text()
    assert "How the runs ended along their path" in text
    assert "| mpcc | 2/5 = 40 %" in text and "| stalled | incomplete | trailing | completed | teleported |" in text
    assert "obstacle 0 (0.03 m) blocked the robot" in text
