"""Old import paths that keep working for one release, with a :class:`DeprecationWarning`.

A module that moved leaves a two-line shim at its old path::

    from .._deprecated import forward
    __getattr__, __dir__ = forward(__name__, "lipmpcc.loops.lip")

Every attribute read through the old module warns once per call site and returns the object of the
new module (the same object: ``isinstance`` checks keep working). The moves are listed in
``CHANGELOG.md``.

A module that keeps using names it gave to a new module (a study split into modules named for their
concepts) imports them as before and declares them moved::

    from .._deprecated import moved_names
    moved_names(__name__, {"fullbody_params": "lipmpcc.studies.path_params"})

Its own code reads them as globals, without a warning; a read from outside (``module.name``,
``from module import name``) warns.
"""

from __future__ import annotations

import importlib
import sys
import warnings
from typing import Callable

__all__ = ["forward", "moved_names", "REMOVED_IN"]

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


def moved_names(old: str, moved: dict[str, str]) -> None:
    """Make module ``old`` warn (a :class:`DeprecationWarning` naming the new place) when one of ``moved``'s
    names (name -> the new module's dotted name) is read from it as an attribute; its own code, which reads
    its globals, does not warn.

    Args:
        old: the module's ``__name__`` (already in ``sys.modules``).
        moved: each moved name and the module it moved to.
    """
    module = sys.modules[old]
    table = dict(moved)
    base = type(module)

    class _Module(base):  # type: ignore[misc, valid-type]
        def __getattribute__(self, name: str) -> object:
            new = table.get(name)
            if new is not None:
                warnings.warn(f"{old}.{name} moved to {new}.{name}; the old path is removed in lipmpcc {REMOVED_IN}",
                              DeprecationWarning, stacklevel=2)
            return base.__getattribute__(self, name)

    module.__class__ = _Module
