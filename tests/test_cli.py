"""lipmpcc.cli: the argument parser (commands, scenarios, option types) and the exit codes."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from lipmpcc import studies
from lipmpcc.cli import EXIT_ERROR, EXIT_OK, EXIT_USAGE, build_parser, main

REPO = Path(__file__).resolve().parents[1]


def test_run_help_lists_every_scenario(capsys) -> None:
    with pytest.raises(SystemExit) as done:
        main(["run", "--help"])
    assert done.value.code == EXIT_OK
    out = capsys.readouterr().out
    assert "{" + ",".join(studies.names()) + "}" in out
    for option in ("--planner", "--robot", "--steps", "--cop-range", "--yaw-rate", "--video"):
        assert option in out


@pytest.mark.parametrize(
    "argv, word",
    [
        (["run", "marathon"], "invalid choice"),
        (["run", "circle", "--steps", "0"], "must be a positive integer"),
        (["run", "circle", "--steps", "two"], "is not an integer"),
        (["run", "circle", "--seed", "-1"], "must be >= 0"),
        (["run", "circle", "--speed", "nan"], "is not a finite number"),
        (["run", "circle", "--L", "long"], "is not a number"),
        (["run", "circle", "--no-such-option"], "unrecognized arguments"),
        (["run", "stones", "--cop-range", "0.05"], "expected 2 arguments"),
        ([], "required"),
    ],
)
def test_a_bad_option_exits_2_with_a_usage_message(argv: list[str], word: str, capsys) -> None:
    with pytest.raises(SystemExit) as done:
        main(argv)
    assert done.value.code == EXIT_USAGE
    assert word in capsys.readouterr().err


def test_options_are_parsed_into_the_studies_options() -> None:
    from lipmpcc.cli import _options

    ns = build_parser().parse_args(["run", "push", "--planner", "alip-mpc", "--robot", "alip", "--cop-range", "0.06", "0.025",
                                    "--seed", "3", "--out", "x", "--yaw-rate", "0.25", "--L", "0.4"])
    opts = _options(ns)
    assert isinstance(opts, studies.RunOptions)
    assert (opts.scenario, opts.planner, opts.robot, opts.seed, opts.out) == ("push", "alip-mpc", "alip", 3, "x")
    assert opts.cop_range == (0.06, 0.025) and opts.yaw_rate == 0.25 and opts.L == 0.4 and opts.video is False
    rp = build_parser().parse_args(["reproduce", "--fast", "--only", "lip-"])
    assert (rp.command, rp.fast, rp.only, rp.out) == ("reproduce", True, "lip-", "results")


def test_a_study_error_is_one_line_and_exit_code_1(tmp_path: Path, capsys) -> None:
    assert main(["run", "walk", "--robot", "lip", "--out", str(tmp_path)]) == EXIT_ERROR
    err = capsys.readouterr().err
    assert err.startswith("lipmpcc: error: --robot = 'lip'") and err.count("\n") == 1
    assert not (tmp_path / "summary.json").exists()


def test_a_short_run_writes_its_summary(tmp_path: Path, capsys) -> None:
    assert main(["run", "circle", "--robot", "lip", "--steps", "3", "--out", str(tmp_path)]) == EXIT_OK
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["scenario"] == "circle" and s["steps"] == 3
    assert capsys.readouterr().out.startswith("scenario=circle planner=mpcc")


def test_python_dash_m_lipmpcc_is_the_cli() -> None:
    env = {**os.environ, "PYTHONPATH": str(REPO / "python")}
    out = subprocess.run([sys.executable, "-m", "lipmpcc", "run", "marathon"], capture_output=True, text=True, env=env,
                         timeout=120)
    assert out.returncode == EXIT_USAGE and "usage: lipmpcc run" in out.stderr and "'circle'" in out.stderr
