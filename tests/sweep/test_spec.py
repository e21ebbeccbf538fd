"""lipmpcc.sweep.spec: the TOML specification, its validation and its cases."""

from __future__ import annotations

import math

import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.resources import data_path
from lipmpcc.sweep.spec import load_spec, parse_spec

BASE = {"study": "circle-push", "robot": "lip", "planners": ["mpcc", "cartesian"], "options": {"steps": 12},
        "axes": {"impulse": {"unit": "N*s", "values": [5, 10]}, "direction": {"unit": "deg", "range": [0, 90], "n": 3}}}


def spec(**changes):
    raw = {**BASE, **changes}
    return parse_spec(raw)


def test_cases_are_the_grid_times_the_planners_with_si_values_and_stable_ids() -> None:
    s = spec()
    cases = s.cases()
    assert len(cases) == 2 * 3 * 2
    assert len({c["id"] for c in cases}) == len(cases)
    assert [c["id"] for c in spec().cases()] == [c["id"] for c in cases]  # same spec, same ids
    dirs = sorted({c["params"]["direction"] for c in cases})
    assert dirs == pytest.approx([0.0, math.pi / 4, math.pi / 2])
    assert {c["planner"] for c in cases} == {"mpcc", "cartesian"}
    assert all(c["options"]["steps"] == 12 and c["study"] == "circle-push" for c in cases)


def test_random_draws_are_seeded_and_vary_together() -> None:
    axes = {"impulse": {"random": [1, 20]}, "seed": {"random": [0, 99]}}
    a = spec(axes=axes, draws=4, seed=3).points()
    assert a == spec(axes=axes, draws=4, seed=3).points()
    assert a != spec(axes=axes, draws=4, seed=4).points()
    assert len(a) == 4 and all(1 <= p["impulse"] <= 20 and isinstance(p["seed"], int) for p in a)


def test_the_spec_hash_follows_the_content() -> None:
    assert spec().hash == spec().hash
    assert spec().hash != spec(options={"steps": 13}).hash


def test_axes_that_are_options_reach_the_cases_options() -> None:
    s = parse_spec({"study": "overtake", "planners": ["mpcc"], "axes": {"obstacle_speed": {"values": [0.2, 0.4]}}})
    assert [c["options"]["obstacle_speed"] for c in s.cases()] == [0.2, 0.4]


@pytest.mark.parametrize(
    "changes, named",
    [
        ({"study": "walkabout"}, "study"),
        ({"axes": {"speedz": {"value": 1}}}, "speedz"),
        ({"axes": {"impulse": {"unit": "kg", "value": 1}}}, "axes.impulse.unit"),
        ({"axes": {"impulse": {"value": float("nan")}}}, "axes.impulse"),
        ({"axes": {"impulse": {"range": [5, 1], "n": 3}}}, "axes.impulse.range"),
        ({"axes": {"impulse": {"values": []}}}, "axes.impulse.values"),
        ({"axes": {"impulse": {"random": [3, 3]}}, "draws": 2}, "axes.impulse.random"),
        ({"axes": {"impulse": {"random": [1, 3]}}}, "draws"),
        ({"planners": ["alip-qp"]}, "planners"),
        ({"planners": []}, "planners"),
        ({"colour": "red"}, "colour"),
        ({"options": {"warp": 9}}, "options.warp"),
        ({"axes": {"force": {"value": 10}, "impulse": {"value": 1}}}, "axes"),
        ({"axes": {"direction": {"value": 0}}}, "axes"),
        ({"axes": {"obstacle_speed": {"value": 0.3}}}, "--obstacle-speed"),
        ({"study": "stones", "planners": ["alip-mpc"], "robot": "alip", "options": {},
          "axes": {"impulse": {"value": 5}}}, "axes.impulse"),
        ({"robot": "alip"}, "robot"),
        ({"axes": {"impulse": {"value": 5}, "duration": {"value": 0}}}, "axes.duration"),
        ({"timeout_s": 0}, "timeout_s"),
        ({"timeout_s": float("nan")}, "timeout_s"),
        ({"timeout_s": "10 min"}, "timeout_s"),
    ],
)
def test_a_malformed_spec_is_refused_in_one_line_naming_the_entry(changes, named) -> None:
    with pytest.raises(InvalidInputError) as err:
        spec(**changes)
    msg = str(err.value)
    assert named in msg and "\n" not in msg


def test_shipped_specs_load_by_name() -> None:
    for path in sorted(data_path("sweeps").glob("*.toml")):
        s = load_spec(path.stem)
        assert s.cases(), path


def test_a_missing_or_broken_file_is_refused(tmp_path) -> None:
    with pytest.raises(InvalidInputError, match="sweep spec"):
        load_spec(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("study = [")
    with pytest.raises(InvalidInputError, match="TOML"):
        load_spec(bad)


def test_the_timed_circle_spec_carries_replan_hz_to_the_run_options() -> None:
    """A planner table's ``replan_hz`` (with ``step_duration_range``) reaches the case's RunOptions fields;
    ``replan_hz`` without a range is refused before anything runs (the study would not read it)."""
    s = load_spec("timed_circle_push")
    timed = [c for c in s.cases() if c["planner"].startswith("timed")]
    assert len(timed) == 60 and all(c["options"]["replan_hz"] == 25 for c in timed)
    assert all(c["options"]["step_duration_range"] == [0.3, 0.5] for c in timed)
    with pytest.raises(InvalidInputError, match="replan"):
        spec(planners=[{"label": "x", "planner": "mpcc", "replan_hz": 25}])


@pytest.mark.parametrize("raw", [None, 3, "push", ["study", "push"]])
def test_a_spec_that_is_not_a_table_is_refused_in_one_line(raw) -> None:
    from lipmpcc.exceptions import InvalidInputError

    with pytest.raises(InvalidInputError, match="sweep spec"):
        parse_spec(raw)


def test_a_huge_grid_is_refused_before_it_is_expanded_and_allow_long_lets_a_big_one_through() -> None:
    import time

    from lipmpcc.exceptions import RunTooLongError
    from lipmpcc.sweep.spec import MAX_CASES, sweep_size

    base = {"name": "g", "study": "circle-push", "robot": "lip", "planners": ["mpcc"], "options": {"steps": 10}}
    huge = {**base, "axes": {"impulse": {"range": [0, 10], "n": 1_000_000}, "direction": {"range": [0, 6], "n": 1000}}}
    t0 = time.perf_counter()
    with pytest.raises(RunTooLongError, match=r"sweep = '1000000000 cases'.*CPU time.*--allow-long"):
        parse_spec(huge)
    assert time.perf_counter() - t0 < 20.0
    with pytest.raises(InvalidInputError, match="axes.impulse.n"):  # one axis past memory: refused even with allow_long
        parse_spec({**base, "axes": {"impulse": {"range": [0, 10], "n": 10**9}}}, allow_long=True)
    big = {**base, "draws": MAX_CASES + 1, "axes": {"seed": {"random": [0, 10**6]}}}
    spec_size = None
    with pytest.raises(RunTooLongError, match=f"{MAX_CASES + 1} cases"):
        parse_spec(big)
    spec = parse_spec({**base, "draws": 3, "axes": {"seed": {"random": [0, 10**6]}}})
    spec_size = sweep_size(spec)
    assert spec_size.cases == 3 and spec_size.cpu_s > 0


@pytest.mark.parametrize("options, name", [
    ({"stones": "missing.csv"}, "options.stones"),
    ({"path": "missing.csv"}, "options.path"),
    ({"obstacles": "missing.json"}, "options.obstacles"),
])
def test_every_file_the_spec_names_is_checked_up_front(tmp_path, options, name) -> None:
    study = "stones" if "stones" in options else "follow-path" if "path" in options else "overtake"
    raw = {"name": "f", "study": study, "planners": ["alip-mpc" if study == "stones" else "mpcc"], "options": options}
    if study != "stones":
        raw["robot"] = "lip"
    with pytest.raises(InvalidInputError, match=f"{name} = 'missing.*no such file"):
        parse_spec(raw)
    bad = tmp_path / "bad.txt"
    bad.write_text("not, a, course\n1, 2\n")
    with pytest.raises(InvalidInputError, match=f"{name} = .*bad.txt.*a file the study can read"):
        parse_spec({**raw, "options": {k: str(bad) for k in options}})


def test_robot_replaces_the_specifications_robot_with_its_own_store(tmp_path):
    """``lipmpcc sweep table_ii_digit --robot MODEL.xml``: the same cases on that model, under another hash."""
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.sweep import load_spec

    model = tmp_path / "digit-v3.xml"
    model.write_text("<mujoco/>")
    base, other = load_spec("table_ii_digit"), load_spec("table_ii_digit", robot=str(model))
    assert other.robot == str(model) and other.name.endswith("[on digit-v3]") and other.hash != base.hash
    assert [c["robot"] for c in other.cases()] == [str(model)] * len(base.cases()) == [str(model)] * 60
    assert [c["params"] for c in other.cases()] == [c["params"] for c in base.cases()]
    with pytest.raises(InvalidInputError, match="an existing MJCF file"):
        load_spec("table_ii_digit", robot=str(tmp_path / "absent.xml"))
    spec = tmp_path / "s.toml"
    spec.write_text('study = "stones"\nplanners = ["alip-mpc"]\n[axes]\nrobot = { values = ["digit_like"] }\n')
    with pytest.raises(InvalidInputError, match="axes.robot"):
        load_spec(spec, robot=str(model))
