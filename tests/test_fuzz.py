"""The issue-14 fuzz under pytest: every bad input or fault of :mod:`tests.fuzz` must end cleanly
(no traceback, crash, hang, silent acceptance, vague error or refused legitimate input).

One test per case, named by its id; ``tools/fuzz.py`` runs the same cases and prints the tally.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from .fuzz import all_cases, run_case
from .fuzz.harness import CLASSES

CASES = all_cases()


def test_the_fuzz_has_at_least_150_cases_over_every_entry_point() -> None:
    assert len(CASES) >= 150
    kinds = {c.category for c in CASES}
    for category in ("cli", "outputs", "outcomes", "path-csv", "obstacles-json", "stones-csv", "layout", "mjcf",
                     "api-params", "api-geometry", "api-planners", "api-wbc", "api-loops", "cache", "threads",
                     "interrupts"):
        assert category in kinds, category
    assert {"cli", "api", "proc"} == {c.kind for c in CASES}
    assert set(CLASSES) >= {"ok", "traceback", "crash", "hang", "silent"}


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_fuzz_case(case, tmp_path: Path) -> None:
    out = run_case(case, tmp_path)
    if out.cls != "ok":
        pytest.fail(f"[{case.category}] {case.id}: {out.cls}: {out.detail}", pytrace=False)
