"""One thread at a time: a guard for objects that hold one native workspace.

A planner's CasADi buffers, a simulator's ``MjData`` or the whole-body controller's C++ workspace are
written by every call; two threads inside one such object at once corrupt it (the process can die with
a segmentation fault). :func:`exclusive` wraps such a method so that a second thread entering any
guarded method of the same object raises :class:`~lipmpcc.exceptions.ConcurrentUseError` at once,
naming the object and the method, instead of crashing. The same thread may re-enter (a guarded method
calling another). The guard costs well under a microsecond per call. Use one object per thread.
"""

from __future__ import annotations

import functools
import threading
from typing import Any, Callable, TypeVar

from .exceptions import ConcurrentUseError

__all__ = ["exclusive"]

F = TypeVar("F", bound=Callable[..., Any])
_ATTR = "_lipmpcc_exclusive_lock"
_CREATE = threading.Lock()


def _lock_of(obj: object) -> threading.RLock:
    lock = obj.__dict__.get(_ATTR)
    if lock is None:
        with _CREATE:  # two threads' first calls must not create two locks
            lock = obj.__dict__.get(_ATTR)
            if lock is None:
                lock = threading.RLock()
                object.__setattr__(obj, _ATTR, lock)
    return lock


def exclusive(kind: str) -> Callable[[F], F]:
    """Decorator of a method that must not run in two threads at once on one object.

    Args:
        kind: what the object is, for the advice of the error (``"planner"``: "use one planner per thread").
    """

    def wrap(method: F) -> F:
        name = method.__name__

        @functools.wraps(method)
        def guarded(self: Any, *args: Any, **kwargs: Any) -> Any:
            lock = _lock_of(self)
            if not lock.acquire(False):
                raise ConcurrentUseError(f"{type(self).__name__}(id={id(self):#x})", name, kind)
            try:
                return method(self, *args, **kwargs)
            finally:
                lock.release()

        return guarded  # type: ignore[return-value]

    return wrap
