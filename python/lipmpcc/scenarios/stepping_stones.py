"""Deprecated: moved to :mod:`lipmpcc.studies.stepping_stones` in lipmpcc 0.2, its markdown tables to
:mod:`lipmpcc.report` (see CHANGELOG.md); removed in 0.3."""

import importlib
import warnings

from .._deprecated import REMOVED_IN

_NEW = "lipmpcc.studies.stepping_stones"
_TO_REPORT = ("table_markdown", "sweep_markdown")


def __getattr__(name: str) -> object:
    if name.startswith("__"):
        raise AttributeError(name)
    new = "lipmpcc.report" if name in _TO_REPORT else _NEW
    target = importlib.import_module(new)
    if not hasattr(target, name):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"{__name__}.{name} moved to {new}.{name}; the old path is removed in lipmpcc {REMOVED_IN}",
                  DeprecationWarning, stacklevel=2)
    return getattr(target, name)


def __dir__() -> list[str]:
    return sorted(set(dir(importlib.import_module(_NEW))) | set(_TO_REPORT))
