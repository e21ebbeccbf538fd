"""The fuzz of issue 14: bad inputs and faults across every entry point of lipmpcc.

:func:`all_cases` lists the cases (each states the clean behaviour it expects); ``tests/test_fuzz.py``
runs them under pytest, one test per case, and ``tools/fuzz.py`` prints the tally for humans. The
harness and its outcome classes are in :mod:`tests.fuzz.harness`.
"""

from __future__ import annotations

from .harness import CLASSES, Case, Outcome, run_case

__all__ = ["CLASSES", "Case", "Outcome", "all_cases", "run_case"]


def all_cases() -> list["Case"]:
    """Every case, CLI first, then files, API and faults; ids are unique."""
    from . import cases_api, cases_cli, cases_faults, cases_files, cases_harden

    cases = cases_cli.CASES + cases_files.CASES + cases_api.CASES + cases_faults.CASES + cases_harden.CASES
    ids = [c.id for c in cases]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise ValueError(f"duplicate fuzz case ids: {dup}")
    return cases
