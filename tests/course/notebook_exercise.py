"""The course tests' one way to reach a notebook's exercise: its shipped solution (``notebooks/solutions/``) and
its own stub and check cells, run on a student's function as the grader runs them."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any, Callable

import nbformat

from lipmpcc.course import CheckResult, Exercises

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"


def solution(notebook: str, name: str) -> Callable:
    """The function ``name`` of notebook ``notebook``'s (e.g. ``"06_alip_stepping_stones"``) shipped solutions."""
    spec = importlib.util.spec_from_file_location(f"solutions_{notebook}", NOTEBOOKS / "solutions" / f"{notebook}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return getattr(module, name)


def grade(notebook: str, name: str, student: Callable, namespace: dict[str, Any]) -> CheckResult:
    """Notebook ``notebook``'s exercise ``name`` (its stub cell ``def name`` and its check cell
    ``@ex.check(name``, with the globals ``namespace`` gives them and the notebook's ``ex``) on ``student``."""
    cells = [c.source for c in nbformat.read(str(NOTEBOOKS / f"{notebook}.ipynb"), as_version=4).cells
             if c.cell_type == "code"]
    ns = {**namespace, "ex": Exercises(notebook)}
    exec(next(s for s in cells if f"def {name}" in s), ns)  # noqa: S102 - the notebook's own cells
    ns[name] = student
    exec(next(s for s in cells if f"@ex.check({name}" in s), ns)  # noqa: S102
    return ns["ex"].results[-1]
