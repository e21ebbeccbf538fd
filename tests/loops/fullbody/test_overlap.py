"""lipmpcc.loops.fullbody.overlap: the loop's helper thread (a job's result or error reaches the caller;
the thread ends and the switch interval is restored)."""

from __future__ import annotations

import sys
import threading

import pytest

from lipmpcc.loops.fullbody.overlap import SWITCH_INTERVAL, THREAD_NAME, Overlap, helper_thread


def _helpers() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name == THREAD_NAME]


def test_jobs_run_on_the_helper_thread_one_at_a_time() -> None:
    o = Overlap()
    try:
        o.start(lambda a, b: (a + b, threading.current_thread().name), (2, 3))
        assert o.result() == (5, THREAD_NAME)
        o.start(lambda: threading.get_ident())
        assert o.result() != threading.get_ident()  # not the caller's thread
    finally:
        o.close()
    assert not _helpers()


def test_a_jobs_exception_is_raised_by_result_and_the_thread_goes_on() -> None:
    class Boom(RuntimeError):
        pass

    def fail() -> None:
        raise Boom("on the helper")

    o = Overlap()
    try:
        o.start(fail)
        with pytest.raises(Boom, match="on the helper"):
            o.result()
        o.start(lambda: 7)
        assert o.result() == 7  # the error was handed over once
    finally:
        o.close()


def test_helper_thread_context_closes_and_restores_the_switch_interval() -> None:
    old = sys.getswitchinterval()
    with helper_thread(False) as none:
        assert none is None and sys.getswitchinterval() == old
    with pytest.raises(ValueError):
        with helper_thread(True) as h:
            assert isinstance(h, Overlap) and len(_helpers()) == 1
            assert sys.getswitchinterval() == pytest.approx(min(old, SWITCH_INTERVAL))
            raise ValueError("the run failed")
    assert not _helpers() and sys.getswitchinterval() == old


def test_close_right_after_start_ends_the_thread() -> None:
    """An interrupt between ``start`` and ``result`` (Ctrl-C while the job runs or before the thread took
    it) leaves ``close`` to end the thread: no "release unlocked lock", no thread left."""
    import time

    for i in range(300):
        o = Overlap()
        o.start(time.sleep, (0.0005 * (i % 3),))
        if i % 4 == 0:
            time.sleep(0.0003)  # sometimes the job has begun
        o.close()
        assert not o._thread.is_alive()
    assert not _helpers()


def test_close_after_a_result_and_with_no_job() -> None:
    o = Overlap()
    o.close()
    o = Overlap()
    o.start(int, ("5",))
    assert o.result() == 5
    o.close()
    assert not _helpers()
