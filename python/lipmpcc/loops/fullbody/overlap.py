"""The full-body loop's helper thread: one job at a time, run while the loop's thread is in MuJoCo.

MuJoCo's step runs in C++ without the GIL, so a Python job on another thread runs meanwhile.
:class:`Overlap` is that thread (``start(job, args)``, then ``result()``); :func:`helper_thread`
opens one for a run, shortens the interpreter's switch interval while it lives (so that the loop's
thread gets the GIL back soon after its step if the job still runs) and closes it afterwards.
"""

from __future__ import annotations

import sys
import threading
from contextlib import contextmanager
from typing import Any, Callable, Iterator

__all__ = ["Overlap", "helper_thread", "THREAD_NAME", "SWITCH_INTERVAL"]

#: name of the helper thread (tests check that it ends with the run)
THREAD_NAME = "lipmpcc-loop-helper"
#: the interpreter's switch interval while a helper thread lives (at most) [s]
SWITCH_INTERVAL = 2e-4


class Overlap:
    """One helper thread that runs a job while the caller's thread is inside C++ without the GIL
    (the MuJoCo step): ``start(job, args)``, then ``result()`` waits for the job and returns its value
    (or raises its exception). ``close()`` ends the thread, also between a start and its result
    (an interrupt)."""

    def __init__(self) -> None:
        self._go = threading.Lock()
        self._go.acquire()
        self._done = threading.Lock()
        self._done.acquire()
        self._job: Callable[..., Any] | None = None
        self._args: tuple = ()
        self._value: Any = None
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name=THREAD_NAME, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while True:
            self._go.acquire()
            job = self._job
            if job is None:
                return
            try:
                self._value = job(*self._args)
            except BaseException as err:  # noqa: BLE001 - handed to the caller's thread
                self._error = err
            self._done.release()

    def start(self, job: Callable[..., Any], args: tuple = ()) -> None:
        """Run ``job(*args)`` on the helper thread; call :meth:`result` before the next start."""
        self._job = job
        self._args = args
        self._error = None
        self._go.release()

    def result(self) -> Any:
        """Wait for the job; its return value, or raise its exception."""
        self._done.acquire()
        if self._error is not None:
            err, self._error = self._error, None
            raise err
        return self._value

    def close(self) -> None:
        """End the thread: at once when it waits for a job or when a started job has not begun, else
        after the job that runs (its result is dropped). Safe at any point of the start/result cycle,
        e.g. when a KeyboardInterrupt lands between :meth:`start` and :meth:`result`."""
        self._job = None
        try:
            self._go.release()  # wakes the thread waiting for a job, or gives it one more start after its job
        except RuntimeError:
            # "release unlocked lock": the token of the last start() is still there (the thread has not
            # taken it): the thread takes it, finds no job and returns.
            pass
        self._thread.join()


@contextmanager
def helper_thread(enabled: bool) -> Iterator[Overlap | None]:
    """An :class:`Overlap` for the duration of a run (None when not ``enabled``).

    While it lives the switch interval is at most :data:`SWITCH_INTERVAL`; it is restored, and the
    thread ended, on the way out (also when the run raises).
    """
    if not enabled:
        yield None
        return
    helper = Overlap()
    old_switch = sys.getswitchinterval()
    sys.setswitchinterval(min(old_switch, SWITCH_INTERVAL))
    try:
        yield helper
    finally:
        helper.close()
        sys.setswitchinterval(old_switch)
