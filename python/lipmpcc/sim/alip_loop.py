"""Deprecated: moved to :mod:`lipmpcc.loops.alip` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

``Push(force, t_start, t_end, step=None)`` of this module keeps its old arguments and returns the one
:class:`lipmpcc.push.Push` (``Push.between(force, t_start, t_end, step)``); ``FootPlanner`` is
:class:`lipmpcc.planners.base.FootstepSource`.
"""

from __future__ import annotations

import warnings

from .._deprecated import REMOVED_IN, forward
from ..push import Push as _Push

__all__ = ["Push"]

__getattr__, __dir__ = forward(__name__, "lipmpcc.loops.alip", renames={"FootPlanner": "FootstepSource"})


def Push(force: tuple[float, float], t_start: float, t_end: float, step: int | None = None) -> _Push:  # noqa: N802
    """Deprecated: the ALIP loop's old push, ``lipmpcc.push.Push.between(force, t_start, t_end, step)`` now."""
    warnings.warn(
        f"lipmpcc.sim.alip_loop.Push(force, t_start, t_end, step) is removed in lipmpcc {REMOVED_IN}: "
        "use lipmpcc.push.Push.between(force, t_start, t_end, step)",
        DeprecationWarning,
        stacklevel=2,
    )
    return _Push.between(force, t_start, t_end, step)
