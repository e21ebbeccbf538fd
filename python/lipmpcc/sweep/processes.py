"""The local pool's processes die with the sweep, and a resumed sweep finds those of a run that did not.

A ``kill -9`` of the sweep's main process gives it no chance to stop its pool. So that its forkserver,
its workers and the resource tracker do not stay behind, idle and re-parented to PID 1:

- the **forkserver** (it imports :mod:`lipmpcc.sweep.worker` when it starts, see
  :data:`lipmpcc.sweep.runner.PRELOAD`) runs :func:`watch_parent`: a daemon thread that ends the process
  (``os._exit``) as soon as its parent, the sweep (:data:`PARENT_ENV`), is gone;
- every **worker** asks the kernel for ``SIGKILL`` when its parent (the forkserver) dies
  (:func:`die_with_parent`: ``prctl(PR_SET_PDEATHSIG)`` on Linux) and also runs :func:`watch_parent`
  (other systems, and the spawn start method);
- the **resource tracker** ends by itself when the last of them has gone (its pipe is closed).

The main process also writes the pool's processes (pid and start time) to :data:`POOL_FILE` in ``--out``
while the pool runs (:func:`record_pool`). A sweep that starts on that folder (under its lock, so no
live sweep owns them) looks for them (:func:`stop_orphans`): any still alive, with the same start time,
is an orphan of a run that was killed; it is stopped and reported. A case is never lost or run twice
by this: the store records a case only when its result arrives.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any

__all__ = ["PARENT_ENV", "POOL_FILE", "POLL_S", "die_with_parent", "watch_parent", "watch_if_started_by_sweep", "no_process_locks", "start_time", "pool_pids",
           "record_pool", "forget_pool", "stop_orphans"]

#: the environment variable that names the sweep's main process (set while its forkserver starts)
PARENT_ENV = "LIPMPCC_SWEEP_PARENT"
#: the file in ``--out`` that lists the pool's processes while it runs
POOL_FILE = ".pool.json"
#: how often a watching thread looks at its parent [s]
POLL_S = 0.2
_PR_SET_PDEATHSIG = 1


def die_with_parent() -> bool:
    """Ask the kernel to ``SIGKILL`` this process when its parent dies (Linux ``prctl``); False elsewhere."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):  # pragma: no cover - no libc prctl
        return False


_WATCHER: list[threading.Thread] = []  # this process's watching thread, once started


def watch_parent(period: float = POLL_S) -> threading.Thread:
    """A daemon thread that ends this process (``os._exit(1)``) when its parent process changes (it died:
    the process was re-parented); one per process (a second call returns the first thread)."""
    if _WATCHER and _WATCHER[0].is_alive():
        return _WATCHER[0]
    parent = os.getppid()
    if parent <= 1:  # pragma: no cover - already an orphan
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(period)
        os._exit(1)

    thread = threading.Thread(target=watch, name="lipmpcc-parent-watch", daemon=True)
    thread.start()
    _WATCHER[:] = [thread]
    return thread


def watch_if_started_by_sweep() -> None:
    """In a process started by a sweep (its parent is :data:`PARENT_ENV`: the forkserver, or a spawned
    worker), watch the parent; nothing elsewhere (the sweep itself, a forked worker)."""
    if os.environ.get(PARENT_ENV) == str(os.getppid()):
        watch_parent()


def no_process_locks() -> None:
    """Let tqdm (the loops' progress bars) use a thread lock only in this worker: its default
    inter-process lock is a named semaphore that a worker stopped by the sweep (Ctrl-C) cannot release,
    which the resource tracker then reports as "leaked"."""
    try:
        from tqdm.std import TqdmDefaultWriteLock
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return
    if getattr(TqdmDefaultWriteLock, "mp_lock", None) is None:
        TqdmDefaultWriteLock.mp_lock = None


def start_time(pid: int) -> int | None:
    """The start time of process ``pid`` (clock ticks since boot, ``/proc/PID/stat``), None when it does
    not run (or is a zombie) or is unknown (no ``/proc``)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = stat[stat.rindex(")") + 2:].split()
    if fields[0] in ("Z", "X"):
        return None
    return int(fields[19])


def pool_pids(pool: Any) -> dict[str, list[int]]:
    """The processes of a local pool: its workers, the forkserver and the resource tracker (each
    ``[]`` when there is none)."""
    from multiprocessing import forkserver, resource_tracker

    workers = sorted(int(p) for p in getattr(pool, "_processes", {}) or {})
    server = getattr(getattr(forkserver, "_forkserver", None), "_forkserver_pid", None)
    tracker = getattr(getattr(resource_tracker, "_resource_tracker", None), "_pid", None)
    return {"workers": workers, "forkserver": [server] if server else [], "resource_tracker": [tracker] if tracker else []}


def record_pool(out: str | Path, pool: Any) -> None:
    """Write :data:`POOL_FILE` in ``out``: the sweep's pid and every pool process with its start time."""
    procs = [(role, pid, start_time(pid)) for role, pids in pool_pids(pool).items() for pid in pids]
    data = {"parent": os.getpid(), "parent_start": start_time(os.getpid()),
            "processes": [{"role": r, "pid": p, "start": s} for r, p, s in procs if s is not None]}
    path = Path(out) / POOL_FILE
    tmp = path.with_name(path.name + ".tmp")
    with contextlib.suppress(OSError):  # a folder that cannot take it: no orphan check on resume, nothing else
        tmp.write_text(json.dumps(data))
        os.replace(tmp, path)


def forget_pool(out: str | Path) -> None:
    """Remove :data:`POOL_FILE` (the pool ended cleanly)."""
    with contextlib.suppress(OSError):
        (Path(out) / POOL_FILE).unlink()


def stop_orphans(out: str | Path, grace: float = 2.0) -> list[tuple[str, int]]:
    """Find the processes of an earlier sweep on ``out`` that are still alive (same pid and start time as
    :data:`POOL_FILE` recorded, its sweep gone), stop them (SIGTERM, then SIGKILL after ``grace`` [s]) and
    return them as (role, pid). Call it under the folder's lock."""
    path = Path(out) / POOL_FILE
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return []
    parent = data.get("parent")
    if isinstance(parent, int) and parent != os.getpid() and start_time(parent) == data.get("parent_start") is not None:
        return []  # its sweep still runs (it cannot hold the lock: not ours to stop)
    alive = [(str(p.get("role")), int(p["pid"])) for p in data.get("processes", [])
             if isinstance(p, dict) and isinstance(p.get("pid"), int) and p.get("start") is not None
             and p["pid"] != os.getpid() and start_time(p["pid"]) == p["start"]]
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for _, pid in alive:
            with contextlib.suppress(OSError):
                os.kill(pid, sig)
        t_end = time.monotonic() + grace
        while time.monotonic() < t_end and any(start_time(pid) is not None for _, pid in alive):
            time.sleep(0.05)
    forget_pool(out)
    return alive


watch_if_started_by_sweep()  # the forkserver imports this module first (lipmpcc.sweep.runner.PRELOAD)
