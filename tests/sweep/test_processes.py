"""lipmpcc.sweep.processes: ``kill -9`` of a sweep leaves no process behind, its resume loses and repeats no
case, and a resume stops (and reports) the orphans of an earlier run; a second sweep on the same --out is
refused at once, naming the holder."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

from ..conftest import package_env

from lipmpcc.cli import main
from lipmpcc.sweep import load_spec, processes

SPEC = """
name = "kill tiny"
study = "circle-push"
robot = "lip"
planners = ["mpcc", "cartesian"]
[axes]
impulse = { unit = "N*s", value = 2.0 }
push_step = 4
steps = { values = [6, 60] }
"""
DEADLINE_S = 120.0  # [s] generous: a loaded 2-core machine


def _descendants(pid: int) -> set[int]:
    """Every process below ``pid`` (from /proc)."""
    children: dict[int, list[int]] = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            ppid = int(stat[stat.rindex(")") + 2:].split()[1])
            children.setdefault(ppid, []).append(int(d.name))
    out, todo = set(), [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            if c not in out:
                out.add(c)
                todo.append(c)
    return out


def _rows(db: Path) -> dict[str, tuple]:
    if not db.is_file():
        return {}
    try:
        con = sqlite3.connect(f"file:{db}?mode=ro", uri=True)
    except sqlite3.OperationalError:
        return {}
    try:
        return {r[0]: r[1:] for r in con.execute("select case_id, status, attempts, finished_at, worker from cases")}
    except sqlite3.OperationalError:
        return {}
    finally:
        con.close()


def _sleeper() -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])


def test_kill_9_leaves_no_process_and_the_resume_loses_and_repeats_no_case(tmp_path, capsys) -> None:
    if not Path("/proc/self/stat").exists():  # pragma: no cover - Linux only
        import pytest

        pytest.skip("needs /proc")
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    out = tmp_path / "out"
    load_spec(spec)  # the imports of the second sweep below, done now: it must come while the first runs
    cmd = [sys.executable, "-m", "lipmpcc", "sweep", str(spec), "--out", str(out), "--workers", "2", "--no-progress",
           "--no-report"]
    proc = subprocess.Popen(cmd, env=package_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        t_end = time.monotonic() + DEADLINE_S
        # the two short cases end first; the two long ones then run for seconds
        while time.monotonic() < t_end and not (len(_rows(out / "results.sqlite")) >= 1 and (out / processes.POOL_FILE).is_file()):
            assert proc.poll() is None, proc.stderr.read()
            time.sleep(0.1)
        # a second sweep on the same folder is refused at once, naming the holder
        t0 = time.monotonic()
        assert main(["sweep", str(spec), "--out", str(out), "--workers", "1", "--no-progress"]) == 1
        err = capsys.readouterr().err
        assert f"pid {proc.pid}" in err and "is writing to this folder" in err and time.monotonic() - t0 < 10.0
        family = _descendants(proc.pid)
        assert len(family) >= 3  # the forkserver, the resource tracker, the workers
        before = _rows(out / "results.sqlite")
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.stderr.close()
    t0 = time.monotonic()
    while time.monotonic() - t0 < 30.0 and any(processes.start_time(p) is not None for p in family):
        time.sleep(0.05)
    left = [p for p in family if processes.start_time(p) is not None]
    assert not left, f"still alive {time.monotonic() - t0:.1f} s after kill -9: {left}"
    sys.__stderr__.write(f"the pool was gone {time.monotonic() - t0:.2f} s after kill -9\n")
    # a process that outlived its sweep (planted: the kill left none) is found by the resume
    sleeper = _sleeper()
    try:
        data = json.loads((out / processes.POOL_FILE).read_text())
        data["processes"].append({"role": "workers", "pid": sleeper.pid, "start": processes.start_time(sleeper.pid)})
        (out / processes.POOL_FILE).write_text(json.dumps(data))
        assert main(["sweep", str(spec), "--out", str(out), "--workers", "2", "--no-progress", "--no-report"]) == 0
        assert sleeper.wait(timeout=10) is not None
    finally:
        if sleeper.poll() is None:
            sleeper.kill()
    captured = capsys.readouterr()
    assert f"stopped 1 processes left behind by an earlier run of this sweep (killed?): workers {sleeper.pid}" in captured.err
    after = _rows(out / "results.sqlite")
    assert len(after) == 4 and {r[0] for r in after.values()} == {"done"}
    assert all(r[1] == 1 for r in after.values())  # no case ran twice (nor was taken for a dead worker)
    assert all(after[cid] == row for cid, row in before.items())  # the rows recorded before the kill: untouched
    assert not (out / processes.POOL_FILE).exists()


def test_stop_orphans_stops_only_the_recorded_processes_still_alive(tmp_path) -> None:
    a, b = _sleeper(), _sleeper()
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    try:
        procs = [{"role": "workers", "pid": a.pid, "start": processes.start_time(a.pid)},
                 {"role": "forkserver", "pid": b.pid, "start": (processes.start_time(b.pid) or 0) + 1},  # pid reused
                 {"role": "workers", "pid": gone.pid, "start": 12}]
        (tmp_path / processes.POOL_FILE).write_text(json.dumps({"parent": gone.pid, "parent_start": 1, "processes": procs}))
        assert processes.stop_orphans(tmp_path) == [("workers", a.pid)]
        assert a.wait(timeout=10) is not None and b.poll() is None
        assert not (tmp_path / processes.POOL_FILE).exists()
        assert processes.stop_orphans(tmp_path) == []  # nothing recorded: nothing to do
    finally:
        for p in (a, b):
            if p.poll() is None:
                p.kill()
                p.wait()


def test_the_processes_of_a_live_sweep_are_not_orphans(tmp_path) -> None:
    a = _sleeper()
    try:
        procs = [{"role": "workers", "pid": a.pid, "start": processes.start_time(a.pid)}]
        data = {"parent": a.pid, "parent_start": processes.start_time(a.pid), "processes": procs}
        (tmp_path / processes.POOL_FILE).write_text(json.dumps(data))
        assert processes.stop_orphans(tmp_path) == [] and a.poll() is None
    finally:
        a.kill()
        a.wait()


def test_a_watched_process_ends_when_its_parent_dies(tmp_path) -> None:
    """watch_parent: the grandchild (its parent killed with SIGKILL) ends by itself."""
    script = ("import os, subprocess, sys, time\n"
              "child = subprocess.Popen([sys.executable, '-c', 'from lipmpcc.sweep import processes; import time; "
              "processes.watch_parent(0.05); print(\\'watching\\', flush=True); time.sleep(60)'])\n"
              "print(child.pid, flush=True); time.sleep(60)\n")
    parent = subprocess.Popen([sys.executable, "-c", script], env=package_env(), stdout=subprocess.PIPE, text=True)
    try:
        child = int(parent.stdout.readline())
        assert parent.stdout.readline().strip() == "watching"
        parent.kill()
        parent.wait()
        t_end = time.monotonic() + 30.0
        while time.monotonic() < t_end and processes.start_time(child) is not None:
            time.sleep(0.05)
        assert processes.start_time(child) is None
    finally:
        if parent.poll() is None:
            parent.kill()
        parent.stdout.close()


def test_die_with_parent_is_set_on_linux() -> None:
    assert processes.die_with_parent() is sys.platform.startswith("linux")
    if sys.platform.startswith("linux"):  # undo it for this (test) process: PR_SET_PDEATHSIG 0
        import ctypes

        ctypes.CDLL(None).prctl(1, 0, 0, 0, 0)
