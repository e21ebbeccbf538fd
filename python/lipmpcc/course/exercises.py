"""Exercises with checked solutions, for the notebooks (the course in ``notebooks/``).

An exercise is a function the student fills in, followed by a check that asserts what it must do::

    from lipmpcc.course import Exercises
    ex = Exercises("01_path_parametrisation")

    @ex.stub
    def closest_parameter(path, p, theta0):
        \"\"\"θ* [m] of the point of ``path`` closest to ``p`` [m], by Newton's method from ``theta0``.\"\"\"
        raise NotImplementedError  # your code here

    @ex.check(closest_parameter)
    def _(f):
        assert abs(f(circle, [2.5, 0.3], 0.1) - 0.1194) < 1e-6, "not the closest point"

The check runs at once and prints one line:

- ``✓ closest_parameter: solved`` when every assertion holds;
- ``◻ closest_parameter: not yet solved`` while the stub still raises :class:`NotImplementedError`
  (the rest of the notebook keeps running);
- ``✗ closest_parameter: <the failed assertion's message>`` for a wrong answer.

**Solutions.** ``notebooks/solutions/<notebook>.py`` defines each exercise's function under the same
name. When the environment variable ``LIPMPCC_SOLUTIONS`` names that folder, :meth:`Exercises.stub`
returns the solution instead of the stub, and a failed or unsolved check raises
:class:`ExerciseError` instead of printing: the notebook tests (``notebooks/conftest.py`` sets the
variable) so fail when a solution no longer matches the library. A student can set it too, to read the
solutions running.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any, Callable, TypeVar

from ..exceptions import LipmpccError

__all__ = ["Exercises", "ExerciseError", "CheckResult", "SOLUTIONS_ENV", "solutions_dir"]

#: names the folder of the solution modules; set, solutions replace stubs and checks must pass
SOLUTIONS_ENV = "LIPMPCC_SOLUTIONS"

F = TypeVar("F", bound=Callable[..., Any])


class ExerciseError(LipmpccError, AssertionError):
    """An exercise's check failed (or its solution is missing) while solutions are in use.

    Attributes: ``notebook`` and ``exercise`` name it, ``status`` is ``"wrong"``, ``"unsolved"`` or
    ``"missing"``.
    """

    def __init__(self, notebook: str, exercise: str, status: str, message: str) -> None:
        super().__init__(f"exercise {exercise!r} of {notebook}: {message}")
        self.notebook, self.exercise, self.status = notebook, exercise, status


@dataclass(frozen=True)
class CheckResult:
    """What a check found: ``status`` is ``"solved"``, ``"unsolved"`` or ``"wrong"``."""

    exercise: str
    status: str
    message: str = ""
    with_solution: bool = False  # the function checked was the solution of notebooks/solutions/

    @property
    def solved(self) -> bool:
        return self.status == "solved"

    def line(self) -> str:
        """The one line printed under the check."""
        if self.status == "solved":
            return f"✓ {self.exercise}: solved" + (" (by the solution in notebooks/solutions/)" if self.with_solution else "")
        if self.status == "unsolved":
            return (f"◻ {self.exercise}: not yet solved (fill in the cell above, run it, then run this "
                    "check again; the rest of the notebook runs without it)")
        return f"✗ {self.exercise}: {self.message or 'a check failed'}"


def solutions_dir() -> Path | None:
    """The folder named by ``LIPMPCC_SOLUTIONS``, or ``None`` when the variable is unset or empty."""
    value = os.environ.get(SOLUTIONS_ENV, "").strip()
    return Path(value).expanduser() if value else None


@dataclass
class Exercises:
    """The exercises of one notebook; ``notebook`` is its file name without ``.ipynb``
    (also the name of its solutions module)."""

    notebook: str
    results: list[CheckResult] = field(default_factory=list)
    _module: ModuleType | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.notebook, str) or not self.notebook.strip():
            raise ValueError(f"Exercises(notebook={self.notebook!r}): expected the notebook's file name")

    @property
    def using_solutions(self) -> bool:
        return solutions_dir() is not None

    def _solutions(self) -> ModuleType:
        if self._module is None:
            folder = solutions_dir()
            assert folder is not None
            path = folder / f"{self.notebook}.py"
            if not path.is_file():
                raise ExerciseError(self.notebook, "*", "missing",
                                    f"no solutions module {path} ({SOLUTIONS_ENV}={folder})")
            spec = importlib.util.spec_from_file_location(f"lipmpcc_solutions_{self.notebook}", path)
            assert spec is not None and spec.loader is not None
            module = importlib.util.module_from_spec(spec)
            sys.modules[spec.name] = module
            spec.loader.exec_module(module)
            self._module = module
        return self._module

    def stub(self, fn: F) -> F:
        """Mark ``fn`` as an exercise: returned unchanged, or replaced by the solution of the same name
        when ``LIPMPCC_SOLUTIONS`` is set."""
        if not self.using_solutions:
            return fn
        solution = getattr(self._solutions(), fn.__name__, None)
        if not callable(solution):
            raise ExerciseError(self.notebook, fn.__name__, "missing",
                                f"the solutions module defines no function {fn.__name__!r}")
        return solution  # type: ignore[no-any-return]

    def check(self, fn: Callable[..., Any]) -> Callable[[Callable[[Callable[..., Any]], Any]], CheckResult]:
        """Decorate a test body ``body(f)`` that asserts what ``fn`` must do; it runs at once, prints
        one line and returns the :class:`CheckResult` in place of the body."""

        def run(body: Callable[[Callable[..., Any]], Any]) -> CheckResult:
            result = self.evaluate(fn, body)
            if self.using_solutions:
                result = CheckResult(result.exercise, result.status, result.message, with_solution=True)
            self.results.append(result)
            print(result.line())
            if self.using_solutions and not result.solved:
                raise ExerciseError(self.notebook, result.exercise, result.status, result.line())
            return result

        return run

    @staticmethod
    def evaluate(fn: Callable[..., Any], body: Callable[[Callable[..., Any]], Any]) -> CheckResult:
        """Run ``body(fn)``: solved if it returns, unsolved if ``fn`` raised NotImplementedError,
        wrong (with the assertion's message) if an assertion failed or ``fn`` raised anything else."""
        name = getattr(fn, "__name__", "exercise")
        try:
            body(fn)
        except NotImplementedError:
            return CheckResult(name, "unsolved")
        except AssertionError as exc:
            return CheckResult(name, "wrong", str(exc) or "an assertion failed")
        except Exception as exc:  # noqa: BLE001 - a student's bug is reported, not raised
            return CheckResult(name, "wrong", f"raised {type(exc).__name__}: {exc}")
        return CheckResult(name, "solved")

    def summary(self) -> str:
        """One line: how many of this notebook's checks are solved."""
        n = len(self.results)
        k = sum(r.solved for r in self.results)
        return f"{self.notebook}: {k} of {n} exercises solved"
