"""`lipmpcc run SCENARIO`: an option the scenario does not read is a one-line usage error (exit 2) naming
the option and the scenario; every option it reads is accepted (issue 14)."""

from __future__ import annotations

import dataclasses
import json

import pytest

from lipmpcc import studies
from lipmpcc.cli import EXIT_USAGE, build_parser, main
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.studies import OptionNotApplicableError, RunOptions, check_options
from lipmpcc.studies.applicability import APPLICABILITY, FULL, REDUCED, SCENARIO_ROBOTS, flag, options_help

#: a value of every option (what the CLI would fill)
SAMPLE = {
    "planner": None,  # set per scenario below
    "robot": "digit_like",
    "obstacle_speed": 0.3,
    "path": "wp.csv",
    "obstacles": "obs.json",
    "steps": 3,
    "seed": 4,
    "out": "o",
    "profile": "II",
    "L": 0.3,
    "W": 0.1,
    "stones": "stones.csv",
    "layout": "my.lipmpcc.toml",
    "cop_range": (0.0, 0.0),
    "duration": 2.0,
    "video": True,
    "video_format": "gif",
    "viewer": "fast",
    "speed": 0.4,
    "yaw_rate": 0.1,
    "allow_long": True,
    "step_duration_range": (0.3, 0.5),
    "replan_hz": 25.0,
    "preset": None,  # per scenario: PRESET
    "set": None,  # per scenario: SET
    "push_set": "paper-a",  # paper-b with --seed is refused (a RULE)
}
PLANNER = {"circle": "mpcc", "circle-push": "mpcc", "overtake": "cartesian", "follow-path": "mpcc", "stones": "alip-mpc",
           "push": "alip-qp", "walk": "capture-point", "stand": "capture-point", "stone-field": "stone-field-milp"}
ROBOT = {REDUCED: {"circle": "lip", "circle-push": "lip", "overtake": "lip", "follow-path": "lip", "stones": "alip",
                   "push": "alip", "stone-field": "alip"},
         FULL: "digit_like"}
#: a preset and --set values of each scenario's default planner
PRESET = {"circle": "overtake", "circle-push": "cartesian", "overtake": "circle", "follow-path": "overtake",
          "stones": "paper-b", "push": "paper-b"}
SET = {"circle": {"q_c": 50.0}, "circle-push": {"rho": 5.0}, "overtake": {"v_max": 0.2}, "follow-path": {"q_c": 20.0},
       "stones": {"alpha_sigma": 2.0}, "push": {"horizon": 3}}

# The examples, and the set-ups in which a scenario ignores an option it reads elsewhere.
REFUSED = [
    (dict(scenario="circle", obstacle_speed=0.3), "--obstacle-speed", ""),
    (dict(scenario="circle-push", obstacle_speed=0.3), "--obstacle-speed", ""),
    (dict(scenario="overtake", profile="II"), "--profile", ""),
    (dict(scenario="circle", cop_range=(0.05, 0.02)), "--cop-range", ""),
    (dict(scenario="circle", robot="lip", video=True), "--video", "with --robot lip"),
    (dict(scenario="overtake", video=True), "--video", "with --robot lip"),  # the LIP is the default
    (dict(scenario="stones", robot="alip", video=True), "--video", "with --robot alip"),
    (dict(scenario="push", video=True), "--video", "with --robot alip"),
    (dict(scenario="circle", duration=3.0), "--duration", "with --robot lip"),
    (dict(scenario="stones", robot="alip", duration=3.0), "--duration", ""),
    (dict(scenario="stones", robot="digit_like", duration=3.0), "--duration", ""),
    (dict(scenario="push", robot="digit_like", duration=3.0), "--duration", ""),
    (dict(scenario="circle", stones="s.csv"), "--stones", ""),
    (dict(scenario="push", stones="s.csv"), "--stones", ""),
    (dict(scenario="push", profile="II"), "--profile", ""),
    (dict(scenario="stand", speed=0.5), "--speed", ""),
    (dict(scenario="stand", yaw_rate=0.1), "--yaw-rate", ""),
    (dict(scenario="stand", steps=4), "--steps", ""),
    (dict(scenario="stand", planner="capture-point"), "--planner", ""),
    (dict(scenario="circle", seed=1), "--seed", ""),
    (dict(scenario="overtake", seed=0), "--seed", ""),  # 0 given is given
    (dict(scenario="push", seed=1), "--seed", ""),
    (dict(scenario="walk", seed=1), "--seed", ""),
    (dict(scenario="stand", seed=1), "--seed", ""),
    (dict(scenario="stones", seed=1), "--seed", "with profile I"),
    (dict(scenario="stones", profile="I", seed=1), "--seed", "with profile I"),
    (dict(scenario="stones", stones="s.csv", seed=1), "--seed", "with --stones"),
    (dict(scenario="stones", profile="III", L=0.3), "--L", "with --profile III"),
    (dict(scenario="stones", stones="s.csv", W=0.1), "--W", "with --stones"),
    (dict(scenario="stones", stones="s.csv", profile="I"), "--profile", "with --stones"),
    (dict(scenario="overtake", obstacles="o.json", obstacle_speed=0.3), "--obstacle-speed", "with --obstacles"),
    (dict(scenario="walk", path="wp.csv"), "--path", ""),
    (dict(scenario="stones", obstacles="o.json"), "--obstacles", ""),
    (dict(scenario="circle", speed=0.5), "--speed", ""),
    (dict(scenario="stones", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="push", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="walk", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="stand", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="walk", preset="circle"), "--preset", ""),
    (dict(scenario="stand", set={"rho": 1.0}), "--set", ""),
    (dict(scenario="follow-path", path="p.csv", obstacle_speed=0.3), "--obstacle-speed", ""),
    (dict(scenario="follow-path", path="p.csv", seed=1), "--seed", ""),
    (dict(scenario="follow-path", path="p.csv", profile="II"), "--profile", ""),
    (dict(scenario="follow-path", path="p.csv", duration=3.0), "--duration", "with --robot lip"),
    (dict(scenario="circle", push_set="paper-b"), "--push-set", ""),
    (dict(scenario="push", push_set="paper-a"), "--push-set", ""),
    (dict(scenario="circle-push", push_set="paper-b", seed=3), "--seed", "with --push-set paper-b"),
    (dict(scenario="stone-field", push_set="paper-a"), "--push-set", "with --push-set paper-a"),
]


def _id(case: tuple) -> str:
    kw, option, _ = case
    return f"{kw['scenario']}{option}"


@pytest.mark.parametrize("kw, option, context", REFUSED, ids=[_id(c) for c in REFUSED])
def test_an_option_the_scenario_does_not_read_is_refused_naming_both(kw, option, context) -> None:
    with pytest.raises(OptionNotApplicableError) as e:
        check_options(RunOptions(**kw))
    msg = str(e.value)
    assert msg.startswith(f"{option} does not apply to scenario {kw['scenario']!r}{(' ' + context) if context else ''} ")
    assert "(it applies to: " in msg and "\n" not in msg
    assert e.value.name == option and e.value.scenario == kw["scenario"]
    assert isinstance(e.value, InvalidInputError) and isinstance(e.value, ValueError)


def test_the_message_says_where_the_option_applies() -> None:
    with pytest.raises(OptionNotApplicableError, match=r"\(it applies to: overtake without --obstacles, stone-field\)$"):
        check_options(RunOptions("circle", obstacle_speed=0.3))
    with pytest.raises(OptionNotApplicableError, match=r"\(it applies to: circle-push with --push-set paper-a, stones with profile II-IV, stone-field\)$"):
        check_options(RunOptions("walk", seed=3))
    with pytest.raises(OptionNotApplicableError, match=r"circle, circle-push, overtake, follow-path, walk, stand on a full-body robot\)$"):
        check_options(RunOptions("circle", robot="lip", duration=2.0))
    with pytest.raises(OptionNotApplicableError,
                       match=r"\(it applies to: circle, circle-push, overtake, follow-path\)$"):
        check_options(RunOptions("stones", step_duration_range=(0.3, 0.5)))


def _applicable_cases() -> list[tuple[str, str, str]]:
    return [(option, scenario, kind) for option, where in APPLICABILITY.items()
            for scenario, kinds in where.items() for kind in sorted(kinds)]


@pytest.mark.parametrize("option, scenario, kind", _applicable_cases())
def test_every_option_is_accepted_where_the_table_says_it_applies(option, scenario, kind, monkeypatch) -> None:
    robot = ROBOT[kind] if kind == FULL else ROBOT[kind][scenario]
    value = PLANNER[scenario] if option == "planner" else robot if option == "robot" else SAMPLE[option]
    value = PRESET[scenario] if option == "preset" else SET[scenario] if option == "set" else value
    kw = {"scenario": scenario, "robot": robot, option: value}
    if scenario == "follow-path" and option != "path":
        kw["path"] = "p.csv"  # required
    if option == "video_format":
        kw["video"] = True
    if option == "viewer":  # the display is checked after the table (tests/studies/test_viewer.py)
        monkeypatch.setattr("lipmpcc.studies.viewer.check_display", lambda what="--viewer": None)
    if option == "layout":  # the file and --robot PATH.xml are checked after the table (tests/test_cli.py)
        monkeypatch.setattr("lipmpcc.studies.applicability._use_layout", lambda opts: None)
    if option == "replan_hz":  # read with the timed MPCC only (RULES)
        kw["step_duration_range"] = (0.3, 0.5)
    if scenario == "stones" and option in ("L", "W"):
        kw["profile"] = "I"
    if scenario == "stones" and option in ("profile", "seed"):
        kw["profile"] = "IV"
    if scenario == "stone-field" and option == "push_set":
        kw["push_set"] = "paper-b"  # paper-a is refused (a RULE)
    check_options(RunOptions(**kw))


def test_every_option_with_all_of_its_companions_is_accepted() -> None:
    """The paper's set-ups with every option they read at once."""
    check_options(RunOptions("overtake", planner="mpcc", robot="digit_like", obstacle_speed=0.5, path="p.csv",
                             steps=5, duration=3.0, video=True, out="o"))
    check_options(RunOptions("circle-push", planner="mpcc", robot="lip", path="p.csv", obstacles="o.json", steps=5, seed=2))
    check_options(RunOptions("stones", planner="alip-mpc", robot="digit_like", profile="II", seed=3, steps=4,
                             cop_range=(0.04, 0.015), video=True))
    check_options(RunOptions("stones", robot="alip", profile="I", L=0.3, W=-0.1, steps=4))
    check_options(RunOptions("stones", stones="s.csv", steps=4, cop_range=(0.0, 0.0)))
    check_options(RunOptions("push", planner="alip-qp", robot="alip", steps=12, cop_range=(0.0, 0.0)))
    check_options(RunOptions("walk", robot="digit_like", planner="capture-point", steps=6, duration=5.0, speed=0.4,
                             yaw_rate=0.1, video=True))
    check_options(RunOptions("stand", robot="digit_like", duration=1.5, video=True))
    check_options(RunOptions("follow-path", planner="cartesian", robot="digit_like", path="p.csv", obstacles="o.json",
                             steps=5, duration=3.0, video=True, preset="overtake", set={"q_c": 30.0, "heading_weight": 5.0}))
    check_options(RunOptions("stones", planner="alip-qp", robot="alip", preset="paper-b-qp", set={"tau": 2.0, "slack": 1e5}))
    for scenario in studies.names():
        check_options(RunOptions(scenario, path="p.csv" if scenario == "follow-path" else None))  # the defaults


def test_the_table_covers_every_registered_scenario_and_every_option() -> None:
    assert set(SCENARIO_ROBOTS) == set(studies.names())
    fields = {f.name for f in dataclasses.fields(RunOptions)} - {"scenario", "extra"}
    assert set(APPLICABILITY) == fields
    parser_flags = {a.option_strings[0] for a in build_parser()._subparsers._group_actions[0].choices["run"]._actions
                    if a.option_strings and a.option_strings[0] != "-h"}
    assert parser_flags == {flag(o) for o in APPLICABILITY} | {"--replace"}  # --replace: the output folder's


def test_run_help_lists_each_scenarios_options_from_the_table(capsys) -> None:
    text = options_help()
    assert all(f"  {s} " in text for s in studies.names())
    stand = text.split("  stand ")[1]
    assert "--duration --video" in stand and "--speed" not in stand and "--steps" not in stand
    with pytest.raises(SystemExit) as e:
        main(["run", "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "options by scenario" in out and "--seed (with profile II-IV)" in out
    assert "--obstacle-speed (without --obstacles)" in out
    assert "--step-duration-range" in out and "--step-duration-range (--robot lip only)" not in out
    assert "on a full body also: --duration --video" in out


@pytest.mark.parametrize("kw", [dict(scenario="walk", robot="lip", speed=0.4), dict(scenario="stand", robot="alip", video=True),
                                dict(scenario="circle", robot="alip", video=True), dict(scenario="stones", robot="lip")])
def test_a_robot_the_scenario_cannot_run_is_left_to_the_study(kw) -> None:
    """--robot applies everywhere: its value is checked by the study (exit 1, "--robot"), not as an option."""
    check_options(RunOptions(**kw))


def test_a_robot_the_scenario_cannot_run_is_a_robot_error(tmp_path, capsys) -> None:
    assert main(["run", "walk", "--robot", "lip", "--speed", "0.4", "--out", str(tmp_path / "o")]) == 1
    assert capsys.readouterr().err.startswith("lipmpcc: error: --robot = 'lip'")


def test_an_unknown_scenario_is_refused_by_the_check() -> None:
    with pytest.raises(InvalidInputError, match="scenario"):
        check_options(RunOptions("jog"))


def test_seed_not_given_is_none_and_the_run_uses_seed_0() -> None:
    assert RunOptions("circle-push").seed is None and RunOptions("circle-push").rng_seed == 0
    assert RunOptions("circle-push", seed=7).rng_seed == 7
    ns = build_parser().parse_args(["run", "circle"])
    assert ns.seed is None


def test_the_python_api_refuses_before_running(tmp_path) -> None:
    with pytest.raises(OptionNotApplicableError, match="--obstacle-speed does not apply to scenario 'circle'"):
        studies.run(RunOptions("circle", obstacle_speed=0.3, steps=1000000, out=str(tmp_path)))
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    "args, option",
    [
        (["circle", "--obstacle-speed", "0.3"], "--obstacle-speed"),
        (["overtake", "--profile", "II"], "--profile"),
        (["circle", "--cop-range", "0", "0"], "--cop-range"),
        (["circle", "--robot", "lip", "--video"], "--video"),
        (["stones", "--robot", "alip", "--duration", "2"], "--duration"),
        (["circle", "--stones", "s.csv"], "--stones"),
        (["stand", "--speed", "0.5"], "--speed"),
        (["stand", "--steps", "3"], "--steps"),
        (["overtake", "--seed", "3"], "--seed"),
        (["push", "--profile", "II"], "--profile"),
        (["stones", "--profile", "II", "--L", "0.3"], "--L"),
        (["stones", "--stones", "FILE", "--profile", "I"], "--profile"),
    ],
)
def test_cli_exits_2_with_one_line(tmp_path, capsys, args, option) -> None:
    out = tmp_path / "o"
    assert main(["run", *args, "--out", str(out)]) == EXIT_USAGE
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1
    assert lines[0].startswith(f"lipmpcc: error: {option} does not apply to scenario {args[0]!r}")
    assert "Traceback" not in err and not out.exists()


@pytest.mark.parametrize(
    "args, check",
    [
        (["circle", "--robot", "lip", "--steps", "4"], lambda s: s["steps"] == 4 and "seed" not in s),
        (["circle-push", "--steps", "4", "--seed", "5"], lambda s: s["steps"] == 4),
        (["overtake", "--planner", "mpcc", "--obstacle-speed", "0.4", "--steps", "4"],
         lambda s: s["obstacle_speeds_mps"] == [0.4]),
        (["stones", "--profile", "II", "--seed", "2", "--steps", "2"], lambda s: s["seed"] == 2 and s["n_stones"] == 2),
        (["stones", "--profile", "III", "--steps", "2"], lambda s: s["seed"] == 0),  # not given: seed 0
        (["stones", "--profile", "I", "--L", "0.3", "--W", "0.1", "--steps", "2"], lambda s: s["L"] == 0.3 and s["W"] == 0.1),
    ],
)
def test_short_runs_with_applicable_options_still_succeed(tmp_path, args, check) -> None:
    out = tmp_path / "o"
    assert main(["run", *args, "--out", str(out)]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["scenario"] == args[0] and check(s)


@pytest.mark.parametrize("option", ["planner", "robot", "path", "obstacles", "profile", "stones"])
@pytest.mark.parametrize("blank", ["", "  "])
def test_an_empty_text_option_is_refused_naming_it(option: str, blank: str) -> None:
    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.studies import RunOptions, check_options

    scenario = "stones" if option in ("profile", "stones") else "circle"
    with pytest.raises(InvalidInputError, match=f"--{option} = '{blank}': expected a non-empty value"):
        check_options(RunOptions(scenario=scenario, **{option: blank}))


def test_follow_path_needs_a_path(tmp_path, capsys) -> None:
    with pytest.raises(InvalidInputError, match="--path") as e:
        check_options(RunOptions("follow-path"))
    assert "my_waypoints.csv" in str(e.value)
    out = tmp_path / "o"
    assert main(["run", "follow-path", "--out", str(out)]) == EXIT_USAGE
    err = capsys.readouterr().err
    assert err.startswith("lipmpcc: error: --path") and len(err.strip().splitlines()) == 1 and not out.exists()
    assert "--path (required)" in options_help().split("  follow-path ")[1].split("  stones ")[0]


@pytest.mark.parametrize(
    "kw, words",
    [
        (dict(scenario="circle", set={"q_x": 1.0}), ["--set", "'q_x'", "--planner mpcc", "q_c", "rho", "delta_max"]),
        (dict(scenario="stones", set={"q_c": 1.0}), ["--set", "'q_c'", "--planner alip-mpc", "alpha_z_x", "horizon"]),
        (dict(scenario="push", planner="alip-qp", set={"horizon": 3}), ["'horizon'", "--planner alip-qp", "tau", "slack"]),
        (dict(scenario="overtake", set={"rho": -1.0}), ["--set rho", "-1", "[0, 10000]"]),
        (dict(scenario="circle", set={"gamma": 1.0}), ["--set gamma", "(0, 1)"]),
        (dict(scenario="circle", set={"delta_min": 0.5}), ["--set", "delta_min", "delta_max"]),
        (dict(scenario="stones", set={"T_min": 0.6}), ["--set", "T_min"]),
        (dict(scenario="circle", preset="paper-b"), ["--preset", "'paper-b'", "circle, overtake, cartesian"]),
        (dict(scenario="stones", preset="circle"), ["--preset", "'circle'", "paper-b"]),
        (dict(scenario="push", planner="alip-qp", preset="paper-b"), ["--preset", "paper-b-qp"]),
    ],
)
def test_presets_and_settings_are_checked_against_the_planner(kw, words) -> None:
    with pytest.raises(InvalidInputError) as e:
        check_options(RunOptions(**kw))
    assert all(w in str(e.value) for w in words), str(e.value)


@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "x", ""])
def test_a_non_finite_set_value_is_refused_naming_its_key(value) -> None:
    with pytest.raises(InvalidInputError, match="--set rho"):
        RunOptions("circle", set=[f"rho={value}"])


def test_an_unknown_preset_is_refused_listing_the_names(tmp_path, capsys) -> None:
    out = tmp_path / "o"
    assert main(["run", "circle", "--preset", "fast", "--out", str(out)]) == EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert err.startswith("lipmpcc: error: --preset = 'fast'") and len(err.splitlines()) == 1
    assert all(n in err for n in ("circle", "overtake", "cartesian", "paper-b", "paper-b-qp")) and not out.exists()


@pytest.mark.parametrize(
    "args, key",
    [
        (["circle", "--set", "foo=1"], "--set = 'foo'"),
        (["circle", "--set", "rho=nan"], "--set rho = 'nan'"),
        (["circle", "--set", "rho"], "--set = 'rho'"),
        (["stones", "--set", "horizon=2.5"], "--set horizon = 2.5"),
        (["walk", "--set", "rho=1"], "--set does not apply to scenario 'walk'"),
    ],
)
def test_cli_set_errors_exit_2_with_one_line(tmp_path, capsys, args, key) -> None:
    out = tmp_path / "o"
    assert main(["run", *args, "--out", str(out)]) == EXIT_USAGE
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lipmpcc: error: {key}") and len(err.splitlines()) == 1 and not out.exists()


def test_hints_point_overtake_path_to_follow_path() -> None:
    from lipmpcc.studies import hints

    (hint,) = hints(RunOptions("overtake", path="p.csv"))
    assert "follow-path" in hint and "--preset" in hint and "cut" in hint
    assert hints(RunOptions("circle", path="p.csv")) == []  # the path-following weights already
    assert hints(RunOptions("overtake")) == [] and hints(RunOptions("follow-path", path="p.csv")) == []
    assert hints(RunOptions("overtake", path="p.csv", preset="circle")) == []  # the user chose the weights
    assert hints(RunOptions("overtake", path="p.csv", planner="cartesian")) == []


def test_an_option_a_robot_kind_does_not_read_yet_says_so(monkeypatch) -> None:
    """NOT_YET: the refusal names what is missing or why (``replan_hz``: a full body always re-plans at 25 Hz)."""
    from lipmpcc.studies import applicability as ap

    kinds = dict(ap.APPLICABILITY["video"])
    monkeypatch.setitem(ap.APPLICABILITY, "video", {**kinds, "circle": frozenset({ap.REDUCED})})
    monkeypatch.setitem(ap.NOT_YET, "video", (ap.FULL, "not yet supported on a full body"))
    with pytest.raises(OptionNotApplicableError, match=r"with --robot digit_like \(not yet supported on a full body\)"):
        check_options(RunOptions("circle", robot="digit_like", video=True))
    check_options(RunOptions("circle", robot="digit_like", step_duration_range=(0.3, 0.5)))  # read now
