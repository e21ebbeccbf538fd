"""Deprecated: moved to :mod:`lipmpcc.studies.stepping_stones` in lipmpcc 0.2, its markdown tables to
:mod:`lipmpcc.report` (see CHANGELOG.md); removed in 0.3."""

import importlib
import warnings

from .._deprecated import REMOVED_IN

_NEW = "lipmpcc.studies.stepping_stones"
_TO_REPORT = ("table_markdown", "sweep_markdown")


def _paper_constants() -> dict[str, object]:
    """The 0.1 module's constants of paper B, now read from ``data/reference/paper_results.json``."""
    from ..studies import paper

    test = paper.push_test()
    table = paper._table_ii()
    return {
        "PUSH_STEPS": test.n_stones,
        "PUSH_LW": (test.L, test.W),
        "PAPER_PUSHES": tuple((p.stone, p.force) for p in test.pushes),
        "PUSH_WINDOW": test.window,
        "PAPER_TABLE_II": {case: {k: (v if isinstance(v, (int, float)) else None) for k, v in row.items()}
                           for case, row in table.items()},
    }


_CONSTANTS = ("PUSH_STEPS", "PUSH_LW", "PAPER_PUSHES", "PUSH_WINDOW", "PAPER_TABLE_II")


def __getattr__(name: str) -> object:
    if name.startswith("__"):
        raise AttributeError(name)
    if name in _CONSTANTS:
        warnings.warn(f"{__name__}.{name} is read from data/reference/paper_results.json by lipmpcc.studies.paper "
                      f"(paper.push_test(), paper.table_ii_claim()); the old name is removed in lipmpcc {REMOVED_IN}",
                      DeprecationWarning, stacklevel=2)
        return _paper_constants()[name]
    new = "lipmpcc.report" if name in _TO_REPORT else _NEW
    target = importlib.import_module(new)
    if not hasattr(target, name):
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"{__name__}.{name} moved to {new}.{name}; the old path is removed in lipmpcc {REMOVED_IN}",
                  DeprecationWarning, stacklevel=2)
    return getattr(target, name)


def __dir__() -> list[str]:
    return sorted(set(dir(importlib.import_module(_NEW))) | set(_TO_REPORT) | set(_CONSTANTS))
