"""``lipmpcc sweep`` on the command line: exit codes, the report, Ctrl-C (the sweep's part of lipmpcc.cli)."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from ..conftest import default_sigint, package_env

from lipmpcc.cli import main

SPEC = """
name = "cli tiny"
study = "circle-push"
robot = "lip"
planners = ["mpcc"]
[options]
steps = 10
[axes]
impulse = { unit = "N*s", values = [3.0, 40.0] }
push_step = 4
"""


def write(tmp_path: Path, text: str = SPEC) -> str:
    p = tmp_path / "spec.toml"
    p.write_text(text)
    return str(p)


def test_a_sweep_runs_writes_its_report_and_resumes(tmp_path, capsys) -> None:
    spec, out = write(tmp_path), str(tmp_path / "out")
    assert main(["sweep", spec, "--out", out, "--workers", "1", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "2 cases: 0 already done, ran 2" in text and "report:" in text
    assert "Survival against push impulse" in (tmp_path / "out" / "report.md").read_text()
    assert main(["sweep", spec, "--out", out, "--no-progress", "--no-report"]) == 0
    assert "2 already done, ran 0" in capsys.readouterr().out
    assert main(["sweep", "--report", out]) == 0


def test_a_bad_or_changed_spec_is_a_usage_error_in_one_line(tmp_path, capsys) -> None:
    assert main(["sweep", write(tmp_path, SPEC.replace("N*s", "furlong")), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lipmpcc: error: axes.impulse.unit") and "\n" not in err
    out = str(tmp_path / "o2")
    small = SPEC.replace("[3.0, 40.0]", "[3.0]")
    assert main(["sweep", write(tmp_path, small), "--out", out, "--workers", "1", "--no-progress", "--no-report"]) == 0
    assert main(["sweep", write(tmp_path, small.replace("steps = 10", "steps = 9")), "--out", out, "--no-progress"]) == 2
    assert "changed" in capsys.readouterr().err
    assert main(["sweep", "--report", str(tmp_path / "nowhere")]) == 2
    assert main(["sweep"]) == 2


@pytest.mark.slow
def test_a_finished_sweep_prints_no_warning_at_exit(tmp_path) -> None:
    """The local pool's workers are let go, not terminated, when the cases are done: a terminated worker
    left its queue's semaphore behind, and Python warned of a "leaked semaphore" after every sweep."""
    cmd = [sys.executable, "-m", "lipmpcc", "sweep", write(tmp_path), "--out", str(tmp_path / "out"), "--workers", "1",
           "--no-progress", "--no-report"]
    p = subprocess.run(cmd, env=package_env(), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert p.stderr == "", p.stderr


def test_ctrl_c_exits_130_with_a_consistent_store_and_the_rerun_finishes(tmp_path) -> None:
    spec = write(tmp_path, SPEC.replace("[3.0, 40.0]", "[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]"))
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "lipmpcc", "sweep", spec, "--out", str(out), "--workers", "1", "--no-progress"]
    proc = subprocess.Popen(cmd, env=package_env(), preexec_fn=default_sigint, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    db = out / "results.sqlite"
    deadline = time.time() + 120
    while time.time() < deadline:
        try:
            if sqlite3.connect(db).execute("select count(*) from cases").fetchone()[0] >= 1:
                break
        except sqlite3.OperationalError:
            pass
        time.sleep(0.2)
    os.killpg(proc.pid, signal.SIGINT)  # the terminal's Ctrl-C: the whole process group
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "resume" in err
    assert err.count("interrupted") == 1 and "leaked" not in err and "Traceback" not in err, err  # one clean message
    done = sqlite3.connect(db).execute("select count(*) from cases where status = 'done'").fetchone()[0]
    assert 1 <= done < 6
    assert main(["sweep", spec, "--out", str(out), "--workers", "1", "--no-progress", "--no-report"]) == 0
    assert sqlite3.connect(db).execute("select count(*) from cases where status = 'done'").fetchone()[0] == 6


def test_a_second_sweep_on_a_held_folder_is_refused_at_once_naming_the_holder(tmp_path, capsys) -> None:
    from lipmpcc.studies.outputs import OutputLock

    out = tmp_path / "out"
    with OutputLock(out):
        t0 = time.monotonic()
        assert main(["sweep", write(tmp_path), "--out", str(out), "--workers", "1", "--no-progress"]) == 1
        assert time.monotonic() - t0 < 30.0
    err = capsys.readouterr().err.strip()
    assert f"pid {os.getpid()}" in err and str(out) in err and "\n" not in err
    assert not (out / "results.sqlite").exists()


def test_a_damaged_store_is_named_with_what_to_do(tmp_path, capsys) -> None:
    spec, out = write(tmp_path, SPEC.replace("[3.0, 40.0]", "[3.0]")), tmp_path / "out"
    out.mkdir()
    (out / "results.sqlite").write_bytes(b"this is not a database" * 100)
    assert main(["sweep", spec, "--out", str(out), "--workers", "1", "--no-progress", "--no-report"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("lipmpcc: error: store") and str(out / "results.sqlite") in err and "--replace" in err
    assert "\n" not in err  # --replace: test_runner.py (run_sweep(replace=True)), the option passes it on


def test_an_oversized_grid_is_refused_at_once_with_its_count_and_estimate(tmp_path, capsys) -> None:
    big = SPEC.replace('impulse = { unit = "N*s", values = [3.0, 40.0] }',
                       'impulse = { unit = "N*s", range = [0.0, 40.0], n = 100000 }\n'
                       'direction = { unit = "deg", range = [0.0, 360.0], n = 10000 }')
    t0 = time.monotonic()
    assert main(["sweep", write(tmp_path, big), "--out", str(tmp_path / "o")]) == 2
    assert time.monotonic() - t0 < 30.0
    err = capsys.readouterr().err
    assert "1000000000 cases" in err and "CPU time" in err and "--allow-long" in err
    assert not (tmp_path / "o").exists()


def test_a_missing_file_named_by_the_spec_is_refused_up_front(tmp_path, capsys) -> None:
    spec = write(tmp_path, SPEC.replace("steps = 10", "steps = 10\npath = 'nowhere.csv'").replace("circle-push", "follow-path")
                 .replace('impulse = { unit = "N*s", values = [3.0, 40.0] }\npush_step = 4', "seed = { values = [1, 2] }"))
    assert main(["sweep", spec, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "options.path" in err and "nowhere.csv" in err and "no such file" in err
