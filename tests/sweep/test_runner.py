"""lipmpcc.sweep.runner: the same results on 1 and 2 local workers and on Dask; resuming; a dead worker."""

from __future__ import annotations

import multiprocessing as mp
import os
import signal

import pytest

from lipmpcc.sweep.runner import SweepInterrupted, run_sweep

from ..conftest import package_env
from lipmpcc.sweep.spec import parse_spec
from lipmpcc.sweep.store import ResultStore, SweepSpecChangedError

# 4 LIP cases of 10 steps (about a second each)
RAW = {"name": "tiny", "study": "circle-push", "robot": "lip", "planners": ["mpcc", "cartesian"],
       "options": {"steps": 10}, "axes": {"impulse": {"unit": "N*s", "values": [3.0, 40.0]}, "push_step": {"value": 4}}}
TIMING = ("solve_ms", "plan_ms")


def results(out):
    """case id -> (status, the summary without its timings)."""
    store = ResultStore(out / "results.sqlite", parse_spec(RAW))
    try:
        import json

        return {r["case_id"]: (r["status"], {k: v for k, v in json.loads(r["summary"]).items() if k not in TIMING})
                for r in store.rows()}
    finally:
        store.close()


@pytest.fixture(scope="module")
def one_worker(tmp_path_factory):
    """The tiny sweep on one local worker: its results by case id."""
    out = tmp_path_factory.mktemp("w1")
    stats = run_sweep(parse_spec(RAW), out, workers=1, progress=False)
    assert (stats.done, stats.errors, stats.died) == (4, 0, 0)
    return results(out)


def test_one_and_two_workers_give_identical_results(tmp_path, one_worker) -> None:
    s2 = run_sweep(parse_spec(RAW), tmp_path / "w2", workers=2, progress=False)
    assert (s2.done, s2.errors, s2.died) == (4, 0, 0)
    assert results(tmp_path / "w2") == one_worker
    assert {st for st, _ in one_worker.values()} == {"done"} and sum(s["fell"] for _, s in one_worker.values()) >= 1


@pytest.mark.parametrize("processes", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_a_dask_local_cluster_gives_the_same_results(tmp_path, one_worker, processes) -> None:
    distributed = pytest.importorskip("distributed")
    spec = parse_spec(RAW)
    with distributed.LocalCluster(n_workers=1 if not processes else 2, threads_per_worker=1, processes=processes,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        sd = run_sweep(spec, tmp_path / "dask", executor=client.get_executor(), progress=False)
    assert sd.done == 4 and results(tmp_path / "dask") == one_worker


def test_an_interrupted_sweep_resumes_without_running_a_finished_case(tmp_path) -> None:
    spec = parse_spec(RAW)
    seen = []

    def stop_after_two(case, result):
        seen.append(case["id"])
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(SweepInterrupted, match="resume"):
        run_sweep(spec, tmp_path, workers=1, progress=False, on_result=stop_after_two)
    store = ResultStore(tmp_path / "results.sqlite", spec)
    first = {r["case_id"]: r["finished_at"] for r in store.rows()}
    store.close()
    assert set(first) == set(seen)
    again = []
    stats = run_sweep(spec, tmp_path, workers=1, progress=False, on_result=lambda c, r: again.append(c["id"]))
    assert stats.skipped == 2 and stats.ran == 2 and not set(again) & set(first)
    store = ResultStore(tmp_path / "results.sqlite", spec)
    rows = store.rows()
    store.close()
    assert len(rows) == 4 and all(first[r["case_id"]] == r["finished_at"] for r in rows if r["case_id"] in first)
    assert run_sweep(spec, tmp_path, workers=1, progress=False).ran == 0


def test_a_changed_spec_is_not_mixed_in(tmp_path) -> None:
    small = {**RAW, "axes": {"impulse": {"value": 3.0}, "push_step": {"value": 4}}, "planners": ["mpcc"]}
    run_sweep(parse_spec(small), tmp_path, workers=1, progress=False)
    with pytest.raises(SweepSpecChangedError):
        run_sweep(parse_spec({**small, "options": {"steps": 11}}), tmp_path, workers=1, progress=False)


def test_killing_a_worker_loses_no_case(tmp_path) -> None:
    spec = parse_spec(RAW)
    killed = []

    def kill_a_worker(case, result):
        if not killed:
            victims = [p for p in mp.active_children() if p.is_alive() and "Process" in type(p).__name__]
            os.kill(victims[-1].pid, signal.SIGKILL)
            killed.append(victims[-1].pid)

    stats = run_sweep(spec, tmp_path, workers=2, progress=False, on_result=kill_a_worker)
    store = ResultStore(tmp_path / "results.sqlite", spec)
    rows = store.rows()
    store.close()
    assert killed and stats.died >= 1
    assert len(rows) == 4 and {r["status"] for r in rows} == {"done"}
    assert any(r["attempts"] == 2 for r in rows)


@pytest.mark.slow
def test_a_dask_scheduler_and_worker_started_apart(tmp_path, one_worker) -> None:
    """``dask scheduler`` and ``dask worker`` as separate processes, as a user starts them; the sweep goes
    through ``lipmpcc sweep --dask ADDRESS``."""
    pytest.importorskip("distributed")
    import subprocess
    import sys
    import time

    from lipmpcc.cli import main

    sched_file = tmp_path / "scheduler.json"
    # the workers import the lipmpcc this test imports (the installed one in CI: the source tree lacks its compiled
    # modules, and a worker without `_sqp` solves on the Python SQP, equal to the C++ one only to rounding)
    env = {**package_env(), "OMP_NUM_THREADS": "1"}
    py = [sys.executable, "-m"]  # `dask scheduler` and `dask worker`, without relying on the console script
    procs = [subprocess.Popen([*py, "distributed.cli.dask_scheduler", "--scheduler-file", str(sched_file),
                               "--port", "0", "--dashboard-address", ":0"], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.time() + 60
        while not sched_file.exists() and time.time() < deadline:
            time.sleep(0.2)
        import json

        address = json.loads(sched_file.read_text())["address"]
        procs.append(subprocess.Popen([*py, "distributed.cli.dask_worker", address, "--nthreads", "1",
                                       "--nworkers", "2", "--no-dashboard"], env=env,
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        spec_file = tmp_path / "spec.toml"
        spec_file.write_text(_toml(RAW))
        assert main(["sweep", str(spec_file), "--out", str(tmp_path / "out"), "--dask", address, "--no-progress",
                     "--no-report"]) == 0
        assert results(tmp_path / "out") == one_worker
    finally:
        for p in reversed(procs):
            p.terminate()
            p.wait(timeout=30)


def _toml(raw: dict) -> str:
    """The tiny spec as TOML (only the shapes RAW uses)."""
    def val(v):
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + " }"
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return f'"{v}"' if isinstance(v, str) else repr(v)

    top = [f"{k} = {val(v)}" for k, v in raw.items() if not isinstance(v, dict)]
    tables = [f"[{k}]\n" + "\n".join(f"{kk} = {val(vv)}" for kk, vv in v.items()) for k, v in raw.items() if isinstance(v, dict)]
    return "\n".join(top) + "\n" + "\n".join(tables) + "\n"


def test_local_workers_run_with_one_blas_thread_and_without_helper_threads() -> None:
    from lipmpcc.sweep.runner import _kill, available_cpus, local_pool

    pool = local_pool(2)
    try:
        names = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MPLBACKEND", "LIPMPCC_LOOP_THREAD", "LIPMPCC_WBC_THREAD")
        env = {k: pool.submit(os.getenv, k).result() for k in names}
    finally:
        _kill(pool)
    assert env["OPENBLAS_NUM_THREADS"] == "1" and env["OMP_NUM_THREADS"] == "1" and env["MPLBACKEND"] == "Agg"
    if available_cpus() <= 2:
        assert env["LIPMPCC_LOOP_THREAD"] == "0" and env["LIPMPCC_WBC_THREAD"] == "0"


class _Canned:
    """An executor that answers each case at once with ``answer(case)`` (no study is run)."""

    def __init__(self, answer):
        self.answer = answer

    def submit(self, fn, case, *args):
        from concurrent.futures import Future

        f = Future()
        f.set_result(self.answer(case))
        return f


def _record(case):
    return {"id": case["id"], "status": "error", "summary": None, "push": {}, "error": "canned", "wall_s": 0.0,
            "worker": "test"}


def _executor(answer):
    from concurrent.futures import Executor

    class Canned(_Canned, Executor):
        pass

    return Canned(answer)


@pytest.mark.parametrize("kw, name", [({"workers": 0}, "workers"), ({"workers": -1}, "workers"),
                                      ({"workers": 1.5}, "workers"), ({"workers": True}, "workers"),
                                      ({"max_in_flight": 0}, "max_in_flight"), ({"max_in_flight": "8"}, "max_in_flight"),
                                      ({"executor": object()}, "executor")])
def test_workers_max_in_flight_and_executor_are_checked_before_anything_runs(tmp_path, kw, name) -> None:
    from lipmpcc.exceptions import InvalidInputError

    with pytest.raises(InvalidInputError, match=name):
        run_sweep(parse_spec(RAW), tmp_path / "o", progress=False, **kw)
    assert not (tmp_path / "o").exists()


def test_a_spec_that_is_not_a_sweep_spec_is_refused(tmp_path) -> None:
    from lipmpcc.exceptions import InvalidInputError

    with pytest.raises(InvalidInputError, match="SweepSpec"):
        run_sweep(RAW, tmp_path / "o")


def test_an_executor_whose_futures_return_something_else_is_named(tmp_path) -> None:
    from lipmpcc.exceptions import InvalidInputError

    with pytest.raises(InvalidInputError, match="executor = 'hello'.*run_case's record"):
        run_sweep(parse_spec(RAW), tmp_path / "o", executor=_executor(lambda case: "hello"), progress=False)
    stats = run_sweep(parse_spec(RAW), tmp_path / "o", executor=_executor(_record), progress=False, max_in_flight=1)
    assert (stats.errors, stats.ran) == (4, 4)  # the lock and the store were released by the refused run


def test_a_read_only_or_looping_out_is_refused_before_the_run(tmp_path, monkeypatch) -> None:
    from lipmpcc.exceptions import OutputFolderError
    from lipmpcc.sweep import runner

    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    with pytest.raises(OutputFolderError, match="symbolic link"):
        run_sweep(parse_spec(RAW), tmp_path / "loop", executor=_executor(_record), progress=False)
    (tmp_path / "ro").mkdir()
    monkeypatch.setattr(runner.os, "access", lambda path, mode: False)  # as root, chmod would not stop us
    with pytest.raises(OutputFolderError, match="ro"):
        run_sweep(parse_spec(RAW), tmp_path / "ro", executor=_executor(_record), progress=False)
    assert list((tmp_path / "ro").iterdir()) == []


def test_a_store_that_becomes_read_only_mid_run_is_named_and_keeps_its_rows(tmp_path, monkeypatch) -> None:
    from lipmpcc.sweep.store import SweepStoreError

    stores = []
    init = ResultStore.__init__

    def capture(self, *a, **k):
        init(self, *a, **k)
        stores.append(self)

    monkeypatch.setattr(ResultStore, "__init__", capture)

    def on_result(case, result):  # after the first row: the database is read-only from now on
        stores[-1].db.execute("PRAGMA query_only = ON")

    with pytest.raises(SweepStoreError, match=r"readonly.*1 rows.*run the same command again") as err:
        run_sweep(parse_spec(RAW), tmp_path / "o", executor=_executor(_record), progress=False, max_in_flight=1,
                  on_result=on_result)
    assert str(tmp_path / "o" / "results.sqlite") in str(err.value) and "\n" not in str(err.value)
    monkeypatch.undo()
    stats = run_sweep(parse_spec(RAW), tmp_path / "o", executor=_executor(_record), progress=False)
    assert (stats.skipped, stats.ran) == (1, 3)


def test_replace_deletes_a_damaged_store_and_starts_the_sweep_over(tmp_path) -> None:
    from lipmpcc.sweep.store import SweepStoreError

    out = tmp_path / "o"
    out.mkdir()
    (out / "results.sqlite").write_bytes(b"garbage" * 100)
    with pytest.raises(SweepStoreError, match="--replace"):
        run_sweep(parse_spec(RAW), out, executor=_executor(_record), progress=False)
    stats = run_sweep(parse_spec(RAW), out, executor=_executor(_record), progress=False, replace=True)
    assert (stats.skipped, stats.ran, stats.errors) == (0, 4, 4)
    assert len(ResultStore(out / "results.sqlite", parse_spec(RAW)).status()) == 4


def test_a_sweep_into_the_working_folder_takes_its_lock_beside_it(tmp_path, monkeypatch) -> None:
    work = tmp_path / "here"
    work.mkdir()
    monkeypatch.chdir(work)
    stats = run_sweep(parse_spec(RAW), ".", executor=_executor(_record), progress=False)
    assert stats.ran == 4 and (work / "results.sqlite").is_file() and not (tmp_path / "here.lock").exists()
