"""Running a sweep: the cases not yet in the store, on a local process pool, a Dask cluster or any
:class:`concurrent.futures.Executor`, each result appended to the store as it arrives.

- **Local pool** (default): ``workers`` processes (default: the CPUs this process may use), started with
  the ``forkserver`` (else ``spawn``) context under :func:`lipmpcc.sweep.worker.worker_env` (one
  BLAS/OpenMP thread; the package's helper threads off when the workers fill the CPUs).
- **Any executor** (``executor=``, e.g. ``distributed.Client(...).get_executor()``): the same cases, the
  same function (:func:`lipmpcc.sweep.worker.run_case`); at most ``max_in_flight`` at a time.
- **Resuming**: recorded cases (``done`` and ``error``) are skipped. A case whose worker died
  (:class:`~concurrent.futures.process.BrokenProcessPool`, a Dask ``KilledWorker``) is recorded ``died``;
  every case running when a pool broke is retried once at the end, alone in a fresh pool, so that a second
  death is that case's own.
- **Ctrl-C**: the pool is stopped, the running cases are dropped (never half-written: each row is one
  transaction) and :class:`SweepInterrupted` is raised; running the sweep again resumes it.
- **One sweep per folder**: ``OUT.lock`` beside ``--out`` (:class:`lipmpcc.studies.outputs.OutputLock`, as
  ``lipmpcc run``) is held while the sweep runs: a second sweep on the folder is refused at once
  (:class:`~lipmpcc.exceptions.OutputBusyError`, naming the holder).
- **No process left behind**: the pool's processes die with the sweep, even under ``kill -9``, and a
  sweep stops (and reports) those of an earlier run that did not (:mod:`lipmpcc.sweep.processes`).
"""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import time
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from ..config import scoped_env
from ..exceptions import InvalidInputError, LipmpccError, OutputFolderError
from ..studies import outputs
from . import processes
from .spec import SweepSpec
from .store import STORE_NAME, ResultStore, remove_store
from .worker import prepare_process, run_case, worker_env

__all__ = ["MAX_ATTEMPTS", "PRELOAD", "DaskExecutor", "SweepInterrupted", "SweepStats", "available_cpus", "local_pool", "dask_executor",
           "run_sweep"]

MAX_ATTEMPTS = 2  # a case whose worker died is run at most twice
#: modules the forkserver imports once (its workers fork from it with them loaded; nothing is compiled yet)
PRELOAD = ("lipmpcc.sweep.processes", "numpy", "lipmpcc.sweep.worker", "lipmpcc.studies.path_following", "lipmpcc.studies.stepping_stones")


class SweepInterrupted(LipmpccError):
    """The sweep was interrupted (Ctrl-C); the store holds every case finished before."""


@dataclass
class SweepStats:
    """What a call of :func:`run_sweep` did.

    Attributes:
        total: cases in the specification.
        skipped: cases already in the store (not run again).
        ran: cases run by this call (each attempt counts).
        done, errors, timeouts, died: cases recorded by this call, by status.
        fell: recorded cases that fell.
        wall_s: the call's wall time [s].
        store: the store's path.
        orphans: processes of an earlier run of this sweep found alive and stopped, as (role, pid).
    """

    total: int = 0
    skipped: int = 0
    ran: int = 0
    done: int = 0
    errors: int = 0
    timeouts: int = 0
    died: int = 0
    fell: int = 0
    wall_s: float = 0.0
    store: Path = field(default_factory=Path)
    orphans: list[tuple[str, int]] = field(default_factory=list)

    @property
    def cases_per_minute(self) -> float:
        """Cases run per minute of wall time."""
        return 60.0 * self.ran / self.wall_s if self.wall_s > 0 else 0.0


def available_cpus() -> int:
    """The CPUs this process may run on (``os.sched_getaffinity``; ``os.cpu_count`` elsewhere)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1



def local_pool(workers: int, env: dict[str, str] | None = None) -> ProcessPoolExecutor:
    """A started pool of ``workers`` processes (forkserver, else spawn), every one started under ``env``
    (default :func:`~lipmpcc.sweep.worker.worker_env`), so that libraries read it when they load."""
    env = worker_env(helper_threads=workers < available_cpus()) if env is None else env
    methods = mp.get_all_start_methods()
    ctx = mp.get_context("forkserver" if "forkserver" in methods else "spawn")
    if ctx.get_start_method() == "forkserver":
        ctx.set_forkserver_preload(list(PRELOAD))  # imported once, under env, when the server starts
    with scoped_env({**env, processes.PARENT_ENV: str(os.getpid())}):  # the forkserver watches this process
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_local_worker, initargs=(env,))
        for f in [pool.submit(prepare_process, env) for _ in range(workers)]:
            f.result()
    return pool


def _init_local_worker(env: dict[str, str]) -> None:
    """A local worker ignores Ctrl-C (the main process stops the pool), dies with its parent (the
    forkserver, which dies with the sweep: :mod:`lipmpcc.sweep.processes`) and takes ``env``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    processes.die_with_parent()
    processes.watch_parent()
    processes.no_process_locks()
    prepare_process(env)


class DaskExecutor(Executor):
    """The executor of a Dask cluster (``Client(address).get_executor()``); :meth:`shutdown` also closes
    the client."""

    def __init__(self, address: str) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise LipmpccError("--dask needs dask.distributed: pip install 'lipmpcc[dask]'") from None
        self.client = Client(address)
        self.executor = self.client.get_executor()

    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> Future:  # type: ignore[override]
        """Submit ``fn(*args, **kwargs)`` to the cluster."""
        return self.executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Cancel what is pending (unless ``wait``) and close the client."""
        self.executor.shutdown(wait=wait)
        self.client.close()


def dask_executor(address: str) -> DaskExecutor:
    """A :class:`DaskExecutor` on the scheduler at ``address`` (needs ``pip install "lipmpcc[dask]"``)."""
    return DaskExecutor(address)


def _kill(pool: ProcessPoolExecutor) -> None:
    """Stop a local pool now: terminate its processes (their running cases are dropped)."""
    procs = list(getattr(pool, "_processes", {}).values())
    for p in procs:
        p.terminate()
    pool.shutdown(wait=True, cancel_futures=True)


def _close(pool: ProcessPoolExecutor, ok: bool) -> None:
    """End a local pool after its cases: at once when a worker died (``ok`` false), else let its idle
    workers exit (terminating them leaves their queue's semaphore behind: Python warns of a leak at exit)."""
    if ok:
        pool.shutdown(wait=True)
    else:
        _kill(pool)


class _Run:
    """One call of :func:`run_sweep`: the queue, the futures in flight, the store, the counts."""

    def __init__(self, store: ResultStore, stats: SweepStats, bar: Any, on_result: Callable | None) -> None:
        self.store, self.stats, self.bar, self.on_result = store, stats, bar, on_result
        self.pending: list[dict[str, Any]] = []  # cases not yet submitted when a pool broke

    def record(self, case: dict[str, Any], result: dict[str, Any] | None, died: str | None = None) -> None:
        self.store.record(case, result, died)
        st = self.stats
        st.ran += 1
        if died is not None:
            st.died += 1
        elif result is not None and result["status"] == "error":
            st.errors += 1
        elif result is not None and result["status"] == "timeout":
            st.timeouts += 1
        else:
            st.done += 1
            st.fell += int(bool(((result or {}).get("summary") or {}).get("fell")))
        self.bar.update(0 if died is not None else 1)
        self.bar.set_postfix(fell=st.fell, errors=st.errors, timeouts=st.timeouts, died=st.died, refresh=False)
        if self.on_result is not None:
            self.on_result(case, result)

    def pump(self, cases: list[dict[str, Any]], submit: Callable[[dict[str, Any]], Future], window: int) -> bool:
        """Run ``cases`` with at most ``window`` in flight; returns False when a local pool broke (the cases
        in flight are then recorded ``died``, the unsubmitted ones are in :attr:`pending`)."""
        queue = list(reversed(cases))
        flying: dict[Future, dict[str, Any]] = {}
        while queue or flying:
            while queue and len(flying) < window:
                case = queue.pop()
                try:
                    flying[submit(case)] = case
                except BrokenProcessPool:
                    queue.append(case)
                    return self._broken(flying, queue)
            done, _ = wait(list(flying), return_when=FIRST_COMPLETED)
            for fut in done:
                case = flying.pop(fut)
                exc = fut.exception()
                if isinstance(exc, BrokenProcessPool):
                    flying[fut] = case
                    return self._broken(flying, queue)
                if exc is not None:  # a worker died under another executor (Dask: KilledWorker)
                    self.record(case, None, died=f"{type(exc).__name__}: {exc}"[:500])
                else:
                    self.record(case, _checked_result(case, fut.result()))
        return True

    def _broken(self, flying: dict[Future, dict[str, Any]], queue: list[dict[str, Any]]) -> bool:
        for fut, case in flying.items():
            if fut.done() and fut.exception() is None:
                self.record(case, fut.result())
            else:
                self.record(case, None, died="worker process died (BrokenProcessPool)")
        self.pending = list(reversed(queue))
        return False


def _checked_result(case: dict[str, Any], result: Any) -> dict[str, Any]:
    """``result`` when it is :func:`~lipmpcc.sweep.worker.run_case`'s record of ``case``; else the executor
    is not running run_case: :class:`~lipmpcc.exceptions.InvalidInputError` naming what came back."""
    if not (isinstance(result, dict) and result.get("id") == case["id"] and result.get("status") in ("done", "error", "timeout")):
        shown = repr(result)
        raise InvalidInputError("executor", result if len(shown) <= 80 else shown[:77] + "...",
                                f"futures that return run_case's record of the case submitted (a dict with id "
                                f"{case['id']!r} and status done, error or timeout)")
    return result


def _count(name: str, value: Any, low: int, what: str) -> int:
    """``value`` as an integer >= ``low`` (bool, float and anything else refused, naming ``name``)."""
    import numbers

    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < low:
        raise InvalidInputError(name, value, f"{what}: an integer >= {low}")
    return int(value)


def _todo(cases: list[dict[str, Any]], status: dict[str, tuple[str, int]]) -> tuple[list[dict], list[dict]]:
    """(cases never run, cases whose worker died and that may be retried)."""
    new = [c for c in cases if c["id"] not in status]
    retry = [c for c in cases if c["id"] in status and status[c["id"]][0] == "died" and status[c["id"]][1] < MAX_ATTEMPTS]
    return new, retry


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    workers: int | None = None,
    executor: Executor | None = None,
    max_in_flight: int = 64,
    progress: bool = True,
    on_result: Callable[[dict[str, Any], dict[str, Any] | None], None] | None = None,
    replace: bool = False,
) -> SweepStats:
    """Run every case of ``spec`` not yet in ``OUT/results.sqlite``.

    Args:
        spec: the campaign (:func:`lipmpcc.sweep.spec.load_spec`).
        out: the output folder (the store, the report).
        workers: local processes (default: :func:`available_cpus`); ignored with ``executor``.
        executor: run the cases there instead (any :class:`~concurrent.futures.Executor`; not shut down here).
        max_in_flight: cases submitted at once to ``executor``.
        progress: show a progress bar (cases done, failures so far, ETA).
        on_result: called as ``on_result(case, result)`` after each case is recorded (``result`` None: died).
        replace: delete the store first (a damaged one, or another campaign's) and start the sweep over.

    Raises:
        InvalidInputError: a bad argument (``spec``, ``workers``, ``max_in_flight``, ``executor``), an
            unusable ``out`` (:class:`~lipmpcc.exceptions.OutputFolderError`).
        OutputBusyError: another sweep (or run) holds ``out``.
        SweepSpecChangedError: the store holds another campaign.
        SweepStoreError: the store is damaged or cannot be written (the message says what to do).
        SweepInterrupted: Ctrl-C (the store keeps every case finished before).
    """
    if not isinstance(spec, SweepSpec):
        raise InvalidInputError("spec", spec, "a SweepSpec (lipmpcc.sweep.load_spec or parse_spec)")
    n_workers = available_cpus() if workers is None else _count("workers", workers, 1, "local worker processes")
    window = _count("max_in_flight", max_in_flight, 1, "cases in flight at once")
    if executor is not None and not isinstance(executor, Executor):
        raise InvalidInputError("executor", executor, "a concurrent.futures.Executor (or None: the local pool)")
    folder = Path(os.path.abspath(outputs.check_folder_path(out)))  # "--out ." has a name: its lock is ../NAME.lock
    if folder.exists() and not os.access(folder, os.W_OK | os.X_OK):
        raise OutputFolderError("--out", str(out), "a folder that can be written", "it is read-only")
    with outputs.OutputLock(folder):
        orphans = processes.stop_orphans(folder) if folder.is_dir() else []
        if replace:
            remove_store(folder / STORE_NAME)
        stats = _run_locked(spec, folder, n_workers, executor, window, progress, on_result)
    stats.orphans = orphans
    return stats


def _run_locked(spec: SweepSpec, out: Path, n_workers: int, executor: Executor | None, window: int, progress: bool,
                on_result: Callable | None) -> SweepStats:
    """:func:`run_sweep` under the folder's lock."""
    from tqdm import tqdm

    t0 = time.perf_counter()
    store = ResultStore(out / STORE_NAME, spec)
    cases = spec.cases()
    new, retry = _todo(cases, store.status())
    stats = SweepStats(total=len(cases), skipped=len(cases) - len(new) - len(retry), store=store.path)
    bar = tqdm(total=len(cases), initial=stats.skipped, disable=not progress, unit="case", desc=spec.name[:24], smoothing=0.1)
    run = _Run(store, stats, bar, on_result)
    pool: ProcessPoolExecutor | None = None
    try:
        if executor is not None:
            run.pump(new + retry, lambda c: executor.submit(run_case, c), window)
        else:
            queue = new + retry
            while queue:
                pool = local_pool(n_workers)
                processes.record_pool(out, pool)
                env = worker_env(helper_threads=n_workers < available_cpus())
                ok = run.pump(queue, lambda c, p=pool, e=env: p.submit(run_case, c, e), n_workers)
                _close(pool, ok)
                pool = None
                queue = [] if ok else run.pending
        queue = _todo(cases, store.status())[1]  # once more, one at a time: a second death is the case's own
        while queue:
            if executor is not None:
                run.pump(queue, lambda c: executor.submit(run_case, c), 1)
                break
            pool = local_pool(1)
            processes.record_pool(out, pool)
            ok = run.pump(queue, lambda c, p=pool: p.submit(run_case, c, worker_env(True)), 1)
            _close(pool, ok)
            pool = None
            queue = [] if ok else run.pending
    except BaseException as exc:
        if pool is not None:
            _kill(pool)
            pool = None
        if not isinstance(exc, KeyboardInterrupt):
            raise
        raise SweepInterrupted(f"interrupted: {stats.done + stats.errors + stats.timeouts} cases recorded in {store.path}; "
                               "run the same command again to resume") from None
    finally:
        bar.close()
        store.close()
        processes.forget_pool(out)
        stats.wall_s = time.perf_counter() - t0
    return stats
