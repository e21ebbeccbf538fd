"""Deprecated: moved to :mod:`lipmpcc.loops.fullbody` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

The loop's names forward to :mod:`lipmpcc.loops.fullbody.loop`; the planner contract
(``PlannerInput``, ``StepPlan``, ``FootstepSource``) to :mod:`lipmpcc.planners.base`; ``LEFT``,
``RIGHT`` and ``other_side`` to :mod:`lipmpcc.conventions`; ``Push(t_start, force, duration)`` makes
a :class:`lipmpcc.push.Push`. Each use warns with a :class:`DeprecationWarning`.
"""

from __future__ import annotations

import importlib
import warnings

from .._deprecated import REMOVED_IN
from ..push import Push as _Push

#: old names that moved elsewhere than the loop module -> their new module
_ELSEWHERE = {
    "PlannerInput": "lipmpcc.planners.base",
    "StepPlan": "lipmpcc.planners.base",
    "FootstepSource": "lipmpcc.planners.base",
    "LEFT": "lipmpcc.conventions",
    "RIGHT": "lipmpcc.conventions",
    "other_side": "lipmpcc.conventions",
}


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


_LOOP = "lipmpcc.loops.fullbody.loop"


def __getattr__(name: str) -> object:
    if name.startswith("__"):
        raise AttributeError(name)
    module = importlib.import_module(_ELSEWHERE.get(name, _LOOP))
    if not hasattr(module, name):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(
        f"{__name__}.{name} moved to {module.__name__}.{name}; the old path is removed in lipmpcc {REMOVED_IN}",
        DeprecationWarning,
        stacklevel=2,
    )
    return getattr(module, name)


def __dir__() -> list[str]:
    return sorted(set(dir(importlib.import_module(_LOOP))) | set(_ELSEWHERE) | {"Push"})
