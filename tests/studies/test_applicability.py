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
    "cop_range": (0.0, 0.0),
    "duration": 2.0,
    "video": True,
    "video_format": "gif",
    "viewer": "fast",
    "speed": 0.4,
    "yaw_rate": 0.1,
    "allow_long": True,
    "step_duration_range": (0.3, 0.5),
}
PLANNER = {"circle": "mpcc", "circle-push": "mpcc", "overtake": "cartesian", "stones": "alip-mpc", "push": "alip-qp",
           "walk": "capture-point", "stand": "capture-point"}
ROBOT = {REDUCED: {"circle": "lip", "circle-push": "lip", "overtake": "lip", "stones": "alip", "push": "alip"},
         FULL: "digit_like"}

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
    (dict(scenario="circle", robot="digit_like", step_duration_range=(0.3, 0.5)), "--step-duration-range",
     "with --robot digit_like (not yet supported on a full body)"),
    (dict(scenario="overtake", robot="x.xml", step_duration_range=(0.3, 0.5)), "--step-duration-range",
     "with --robot x.xml (not yet supported on a full body)"),
    (dict(scenario="stones", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="push", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="walk", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
    (dict(scenario="stand", step_duration_range=(0.3, 0.5)), "--step-duration-range", ""),
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
    with pytest.raises(OptionNotApplicableError, match=r"\(it applies to: overtake without --obstacles\)$"):
        check_options(RunOptions("circle", obstacle_speed=0.3))
    with pytest.raises(OptionNotApplicableError, match=r"\(it applies to: circle-push, stones with profile II-IV\)$"):
        check_options(RunOptions("walk", seed=3))
    with pytest.raises(OptionNotApplicableError, match=r"circle, circle-push, overtake, walk, stand on a full-body robot\)$"):
        check_options(RunOptions("circle", robot="lip", duration=2.0))
    with pytest.raises(OptionNotApplicableError, match=r"\(it applies to: circle, circle-push, overtake on the reduced model\)$"):
        check_options(RunOptions("stones", step_duration_range=(0.3, 0.5)))


def _applicable_cases() -> list[tuple[str, str, str]]:
    return [(option, scenario, kind) for option, where in APPLICABILITY.items()
            for scenario, kinds in where.items() for kind in sorted(kinds)]


@pytest.mark.parametrize("option, scenario, kind", _applicable_cases())
def test_every_option_is_accepted_where_the_table_says_it_applies(option, scenario, kind, monkeypatch) -> None:
    robot = ROBOT[kind] if kind == FULL else ROBOT[kind][scenario]
    value = PLANNER[scenario] if option == "planner" else robot if option == "robot" else SAMPLE[option]
    kw = {"scenario": scenario, "robot": robot, option: value}
    if option == "video_format":
        kw["video"] = True
    if option == "viewer":  # the display is checked after the table (tests/studies/test_viewer.py)
        monkeypatch.setattr("lipmpcc.studies.viewer.check_display", lambda what="--viewer": None)
    if scenario == "stones" and option in ("L", "W"):
        kw["profile"] = "I"
    if scenario == "stones" and option in ("profile", "seed"):
        kw["profile"] = "IV"
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
    for scenario in studies.names():
        check_options(RunOptions(scenario))  # the defaults


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
    assert "--step-duration-range (--robot lip only)" in out


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
