"""Deprecated: moved to :mod:`lipmpcc.loops.fullbody` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

The loop's names forward to :mod:`lipmpcc.loops.fullbody.loop`; the planner contract
(``PlannerInput``, ``StepPlan``, ``FootstepSource``) to :mod:`lipmpcc.planners.base`; ``LEFT``,
``RIGHT`` and ``other_side`` to :mod:`lipmpcc.conventions`; ``Push(t_start, force, duration)`` makes
a :class:`lipmpcc.push.Push`. Each use warns with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

import warnings

from .._deprecated import REMOVED_IN, forward
from ..push import Push as _Push

__getattr__, __dir__ = forward(__name__, "lipmpcc.loops.fullbody.loop", {
    "PlannerInput": "lipmpcc.planners.base:PlannerInput",
    "StepPlan": "lipmpcc.planners.base:StepPlan",
    "FootstepSource": "lipmpcc.planners.base:FootstepSource",
    "LEFT": "lipmpcc.conventions:LEFT",
    "RIGHT": "lipmpcc.conventions:RIGHT",
    "other_side": "lipmpcc.conventions:other_side",
})


def Push(t_start: float, force: tuple[float, ...], duration: float = 0.1) -> _Push:  # noqa: N802 - the old class name
    """Deprecated: the old ``Push(t_start, force, duration=0.1)`` (positional order ``t_start``,
    ``force``); returns the one :class:`lipmpcc.push.Push` (force [N], times [s])."""
    warnings.warn(
        f"{__name__}.Push(t_start, force, duration) is replaced by lipmpcc.push.Push(force, t_start, duration) "
        f"(note the order); the old path is removed in lipmpcc {REMOVED_IN}",
        DeprecationWarning,
        stacklevel=2,
    )
    return _Push(force=force, t_start=t_start, duration=duration)
