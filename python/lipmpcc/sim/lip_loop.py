"""Deprecated: moved to :mod:`lipmpcc.loops.lip` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

``Push(t_start, duration, force)`` of this module keeps its old argument order and returns the one
:class:`lipmpcc.push.Push` (``Push(force, t_start, duration)``).
"""

from __future__ import annotations

import warnings

from .._deprecated import REMOVED_IN, forward
from ..push import Push as _Push

__all__ = ["Push"]

__getattr__, __dir__ = forward(__name__, "lipmpcc.loops.lip")


def Push(t_start: float, duration: float, force: tuple[float, float]) -> _Push:  # noqa: N802 (the old class name)
    """Deprecated: the LIP loop's old push, ``lipmpcc.push.Push(force, t_start, duration)`` now."""
    warnings.warn(
        f"lipmpcc.sim.lip_loop.Push(t_start, duration, force) is removed in lipmpcc {REMOVED_IN}: "
        "use lipmpcc.push.Push(force, t_start, duration)",
        DeprecationWarning,
        stacklevel=2,
    )
    return _Push(force, t_start, duration)
