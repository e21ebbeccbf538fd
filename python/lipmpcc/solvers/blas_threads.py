"""One BLAS thread for the planners' small dense algebra.

The planners factor matrices of 20–30 rows (``numpy.linalg.eigh`` of the SQP's Hessian). OpenBLAS
splits such calls over its threads, and on a loaded machine a call then waits for a descheduled
thread: measured on 2 shared cores (load average 10–15), 400 ``eigh`` calls on a 28 × 28 matrix took
51–57 µs median on 2 threads and 54 µs on one, but 40 ms at the 90th percentile on 2 threads in two of
three runs, against 56 µs on one (20 × 20: no difference). In closed-loop LIP runs of the MPCC and the
timed MPCC (60 steps, circle) the solve times were the same either way on that machine that day. :func:`one_blas_thread`
sets OpenBLAS (numpy's bundled ``scipy_openblas`` or a system one) to one thread for the duration of a
``with`` block and restores the previous count after it; with another BLAS (MKL, Accelerate) it does
nothing. Environment variables such as ``OPENBLAS_NUM_THREADS`` only act before numpy is imported,
which a library cannot rely on.
"""

from __future__ import annotations

import ctypes
import re
import threading
from contextlib import contextmanager
from typing import Callable, Iterator

__all__ = ["one_blas_thread", "blas_threads"]

_SET = ("scipy_openblas_set_num_threads64_", "scipy_openblas_set_num_threads", "openblas_set_num_threads64_",
        "openblas_set_num_threads")
_GET = ("scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads", "openblas_get_num_threads64_",
        "openblas_get_num_threads")
_lock = threading.Lock()
_depth = 0
_saved = 0
_api: tuple[Callable[[int], None], Callable[[], int]] | None | bool = False  # False: not looked up yet


def _openblas() -> tuple[Callable[[int], None], Callable[[], int]] | None:
    """(set, get) of the OpenBLAS numpy uses, found among the loaded libraries; None if there is none."""
    global _api
    if _api is False:
        import numpy  # noqa: F401  (loads numpy's BLAS)

        _api = None
        try:
            with open("/proc/self/maps", encoding="utf-8", errors="replace") as f:
                paths = sorted(set(re.findall(r"(/\S*openblas\S*\.so\S*)", f.read())))
        except OSError:  # not Linux: no /proc
            paths = []
        for path in paths:
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            set_ = next((getattr(lib, n) for n in _SET if hasattr(lib, n)), None)
            get_ = next((getattr(lib, n) for n in _GET if hasattr(lib, n)), None)
            if set_ is not None and get_ is not None:
                set_.argtypes, set_.restype = [ctypes.c_int], None
                get_.argtypes, get_.restype = [], ctypes.c_int
                _api = (set_, get_)
                break
    return _api or None


def blas_threads() -> int | None:
    """OpenBLAS's current thread count, or None when numpy does not use OpenBLAS."""
    api = _openblas()
    return None if api is None else int(api[1]())


@contextmanager
def one_blas_thread() -> Iterator[None]:
    """OpenBLAS on one thread inside the block (nested and concurrent blocks share one setting: the
    count is restored when the last of them ends)."""
    global _depth, _saved
    api = _openblas()
    if api is None:
        yield
        return
    with _lock:
        if _depth == 0:
            _saved = int(api[1]())
            if _saved != 1:
                api[0](1)
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0 and _saved != 1:
                api[0](_saved)
