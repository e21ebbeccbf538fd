"""Old import paths that keep working for one release, with a :class:`DeprecationWarning`.

A module that moved leaves a two-line shim at its old path::

    from .._deprecated import forward
    __getattr__, __dir__ = forward(__name__, "lipmpcc.loops.lip")

Every attribute read through the old module warns once per call site and returns the object of the
new module (the same object: ``isinstance`` checks keep working). The moves are listed in
``CHANGELOG.md``.
"""

from __future__ import annotations

import importlib
import warnings
from typing import Callable

__all__ = ["forward", "REMOVED_IN"]

#: the release in which the old paths go away
REMOVED_IN = "0.3"


def forward(old: str, new: str, renames: dict[str, str] | None = None) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """Module-level ``__getattr__`` and ``__dir__`` that forward ``old``'s names to module ``new``.

    Args:
        old: the old module's ``__name__``.
        new: the new module's dotted name.
        renames: old name -> new name, for names that changed as they moved; a new name
            ``"package.module:name"`` moved to another module than ``new``.
    """
    renames = dict(renames or {})

    def __getattr__(name: str) -> object:
        if name.startswith("__"):
            raise AttributeError(name)
        module, _, new_name = renames.get(name, name).rpartition(":")
        module = module or new
        target = importlib.import_module(module)
        if not hasattr(target, new_name):
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        warnings.warn(
            f"{old}.{name} moved to {module}.{new_name}; the old path is removed in lipmpcc {REMOVED_IN}",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(target, new_name)

    def __dir__() -> list[str]:
        target = importlib.import_module(new)
        return sorted(set(dir(target)) | set(renames))

    return __getattr__, __dir__
