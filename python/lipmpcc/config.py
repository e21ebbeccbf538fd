"""Global run-time switches.

Fast mode
---------
Set the environment variable ``LIPMPCC_FAST=1`` (or call :func:`set_fast_mode`)
to shorten every scenario's *horizon* — the number of steps or seconds simulated —
so that notebooks and tests run quickly. Fast mode never changes a planner, a
solver, or a code path: it only scales run lengths through :func:`horizon`.
"""

from __future__ import annotations

import os

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


def horizon(full: int | float, fast: int | float) -> int | float:
    """Pick a run length: ``full`` normally, ``fast`` in fast mode."""
    return fast if fast_mode() else full
