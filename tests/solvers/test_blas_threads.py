"""lipmpcc.solvers.blas_threads: OpenBLAS on one thread inside the block, the previous count after it,
nested blocks, and the SQP's solve running under it (its eigh sees one thread)."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from lipmpcc.solvers import blas_threads
from lipmpcc.solvers.blas_threads import blas_threads as current, one_blas_thread

from .test_condensed_sqp import _problem

needs_openblas = pytest.mark.skipif(current() is None, reason="numpy does not use OpenBLAS here")


@needs_openblas
def test_one_thread_inside_and_the_previous_count_after(monkeypatch) -> None:
    set_, get_ = blas_threads._openblas()
    before = current()
    set_(2)
    try:
        with one_blas_thread():
            assert current() == 1
            with one_blas_thread():  # nested: still one, and the outer block's end restores
                assert current() == 1
            assert current() == 1
        assert current() == 2
        with pytest.raises(RuntimeError):  # restored on an exception too
            with one_blas_thread():
                raise RuntimeError("boom")
        assert current() == 2
    finally:
        set_(before)


@needs_openblas
def test_concurrent_blocks_restore_once_the_last_ends() -> None:
    set_, _ = blas_threads._openblas()
    before = current()
    set_(2)
    inside, release = threading.Event(), threading.Event()

    def other() -> None:
        with one_blas_thread():
            inside.set()
            release.wait(5.0)

    t = threading.Thread(target=other)
    try:
        t.start()
        assert inside.wait(5.0)
        with one_blas_thread():
            assert current() == 1
        assert current() == 1  # the other thread's block is still open
        release.set()
        t.join(5.0)
        assert current() == 2
    finally:
        release.set()
        set_(before)


@needs_openblas
def test_the_sqp_factors_its_hessian_on_one_thread(monkeypatch) -> None:
    set_, _ = blas_threads._openblas()
    before = current()
    set_(2)
    seen: list[int | None] = []
    eigh = np.linalg.eigh

    def spy(a):
        seen.append(current())
        return eigh(a)

    monkeypatch.setattr(np.linalg, "eigh", spy)
    try:
        sol = _problem().solve(np.zeros(2), [np.array([1.0])])
        assert sol.found and seen and set(seen) == {1}
        assert current() == 2
    finally:
        set_(before)
