"""Lazy re-exports for the package's ``__init__`` files: a name is imported from its module on first
use, so importing a package stays cheap (CasADi, MuJoCo and Pinocchio load only when needed)."""

from __future__ import annotations

import importlib
from typing import Callable

__all__ = ["lazy_exports"]


def lazy_exports(package: str, homes: dict[str, str], namespace: dict[str, object]
                 ) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """Module-level ``__getattr__`` and ``__dir__`` for ``package``: ``homes`` maps each public name to
    the submodule (relative to ``package``) that defines it; a loaded name is cached in ``namespace``
    (the package's ``globals()``)."""

    def __getattr__(name: str) -> object:
        home = homes.get(name)
        if home is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{home}"), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(homes))

    return __getattr__, __dir__
