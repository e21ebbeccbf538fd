"""Global run-time switches.

Fast mode
---------
Set the environment variable ``LIPMPCC_FAST=1`` (or call :func:`set_fast_mode`)
to shorten every scenario's *horizon* — the number of steps or seconds simulated —
so that notebooks and tests run quickly. Fast mode never changes a planner, a
solver, or a code path: it only scales run lengths through :func:`horizon`.

Threads
-------
The full-body loop and the whole-body controller use helper threads when the process may run on
two CPUs or more (:func:`threads_enabled`); ``LIPMPCC_LOOP_THREAD=0`` and ``LIPMPCC_WBC_THREAD=0``
turn each off. Results do not depend on them.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from typing import Iterator

__all__ = [
    "fast_mode",
    "set_fast_mode",
    "horizon",
    "threads_enabled",
    "fast_mode_as",
    "scoped_env",
]

_FAST_OVERRIDE: bool | None = None


def fast_mode() -> bool:
    """True when run lengths are shortened (``LIPMPCC_FAST=1``)."""
    if _FAST_OVERRIDE is not None:
        return _FAST_OVERRIDE
    return os.environ.get("LIPMPCC_FAST", "0").strip().lower() in ("1", "true", "yes", "on")


def set_fast_mode(enabled: bool | None) -> None:
    """Force fast mode on/off for this process; ``None`` goes back to the environment."""
    global _FAST_OVERRIDE
    _FAST_OVERRIDE = enabled


@contextmanager
def fast_mode_as(enabled: bool) -> Iterator[None]:
    """Fast mode on or off within a ``with`` block, then back to what it was (an override or the environment)."""
    global _FAST_OVERRIDE
    previous = _FAST_OVERRIDE
    _FAST_OVERRIDE = bool(enabled)
    try:
        yield
    finally:
        _FAST_OVERRIDE = previous


def horizon(full: int | float, fast: int | float) -> int | float:
    """Pick a run length: ``full`` normally, ``fast`` in fast mode."""
    return fast if fast_mode() else full


def threads_enabled(env_var: str) -> bool:
    """True when the process may use two CPUs or more and ``env_var`` is not ``0``."""
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cpus = os.cpu_count() or 1
    return cpus >= 2 and os.environ.get(env_var, "1") != "0"


@contextmanager
def scoped_env(env: dict[str, str]) -> Iterator[None]:
    """``os.environ`` updated with ``env`` within a ``with`` block, then each of its variables back to what
    it was (removed when it was not set)."""
    old = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
