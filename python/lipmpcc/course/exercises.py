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

``ex.check`` also takes the exercise's tags and grading: ``stars`` (1 a formula, 2 a small derivation or
algorithm, 3 real code), ``minutes`` (a time estimate), ``points`` (default: ``stars``) and ``own_code``,
the library names that compute the answer: an exercise that asks the student to *write* a function the
library has is wrong, whatever its numbers, when the student's function calls one of those names (checked
on its bytecode, :func:`library_calls`). Numbers alone cannot tell an exact reimplementation from a call
to the library, so the check on the code is what makes the exercise ask for code.

Inside a check, :meth:`Exercises.expect` is a soft assertion with a weight: the check continues, and the
exercise scores the share of the weights that held (partial credit, with the first failure's message).

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

import dis
import importlib.util
import json
import os
import sys
import types
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any, Callable, TypeVar

from ..exceptions import LipmpccError

__all__ = ["Exercises", "ExerciseError", "CheckResult", "SOLUTIONS_ENV", "GRADE_LOG_ENV", "solutions_dir",
           "library_calls", "STAR_LABELS"]

#: names the folder of the solution modules; set, solutions replace stubs and checks must pass
SOLUTIONS_ENV = "LIPMPCC_SOLUTIONS"
#: names a file to which every check appends its result as one JSON line (the grader's record)
GRADE_LOG_ENV = "LIPMPCC_GRADE_LOG"
#: the difficulty tags: ★ a formula given in the text, ★★ a small derivation or algorithm, ★★★ real code
STAR_LABELS = {1: "★", 2: "★★", 3: "★★★"}

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
    """What a check found: ``status`` is ``"solved"``, ``"unsolved"`` or ``"wrong"``; ``fraction`` [0, 1]
    the share of the check's weighted expectations that held (1 solved, 0 unsolved)."""

    exercise: str
    status: str
    message: str = ""
    with_solution: bool = False  # the function checked was the solution of notebooks/solutions/
    fraction: float = 0.0

    @property
    def solved(self) -> bool:
        return self.status == "solved"

    def line(self) -> str:
        """The one line printed under the check."""
        if self.status == "wrong" and 0.0 < self.fraction < 1.0:
            return f"✗ {self.exercise}: {self.message or 'a check failed'} (partly right: {self.fraction:.0%})"
        if self.status == "solved":
            return f"✓ {self.exercise}: solved" + (" (by the solution in notebooks/solutions/)" if self.with_solution else "")
        if self.status == "unsolved":
            return (f"◻ {self.exercise}: not yet solved (fill in the cell above, run it, then run this "
                    "check again; the rest of the notebook runs without it)")
        return f"✗ {self.exercise}: {self.message or 'a check failed'}"


_GLOBAL_OPS = {"LOAD_GLOBAL", "LOAD_NAME"}
_ATTR_OPS = {"LOAD_ATTR", "LOAD_METHOD", "IMPORT_FROM", "STORE_ATTR"}


def library_calls(fn: Callable[..., Any], names: tuple[str, ...] | list[str]) -> list[str]:
    """The names of ``names`` (``"Lip3dModel"``, or dotted: ``"lipmpcc.models.lip.dcm"``, matched on its last
    part) that ``fn`` refers to: as a global (also under another name: the object itself is compared), as
    an attribute (``m.Lip3dModel``, ``lip.dcm``), in an import inside the function, or through a helper
    function or a lambda it calls that is defined beside it (followed, also through closures). Empty when
    ``fn`` uses none of them."""
    wanted = {n.rsplit(".", 1)[-1] for n in names}
    objects = {}
    for n in names:
        mod, _, attr = n.rpartition(".")
        if mod:
            try:
                objects[id(getattr(importlib.import_module(mod), attr))] = attr
            except (ImportError, AttributeError):
                pass
    found: list[str] = []
    seen: set[int] = set()

    def visit_object(obj: Any, name: str) -> None:
        if id(obj) in objects:
            found.append(objects[id(obj)])
        elif isinstance(obj, types.FunctionType) and obj.__module__ == getattr(fn, "__module__", None):
            visit_function(obj)  # a helper written beside the function (the notebook's): followed
        elif name in wanted:
            found.append(name)

    def visit_code(code: types.CodeType, scope: dict, closure: dict) -> None:
        if id(code) in seen:
            return
        seen.add(id(code))
        for ins in dis.get_instructions(code):
            name = ins.argval if isinstance(ins.argval, str) else None
            if name is None:
                continue
            if ins.opname in _ATTR_OPS or ins.opname == "IMPORT_NAME":
                hits = {part for part in name.split(".") if part in wanted}
                found.extend(sorted(hits))
            elif ins.opname in _GLOBAL_OPS:
                if name in scope:
                    visit_object(scope[name], name)
                elif name in wanted:
                    found.append(name)
            elif ins.opname in ("LOAD_DEREF", "LOAD_CLOSURE") and name in closure:
                visit_object(closure[name], name)
        for const in code.co_consts:
            if isinstance(const, types.CodeType):
                visit_code(const, scope, closure)

    def visit_function(f: types.FunctionType) -> None:
        cells = {}
        for var, cell in zip(f.__code__.co_freevars, f.__closure__ or ()):
            try:
                cells[var] = cell.cell_contents
            except ValueError:  # an empty cell
                pass
        visit_code(f.__code__, f.__globals__, cells)

    target = _plain_function(fn)
    if target is not None:
        visit_function(target)
    return sorted(set(found))


def _plain_function(fn: Any) -> types.FunctionType | None:
    """The plain function behind ``fn`` (a bound method's or a ``functools.wraps`` wrapper's), or ``None``."""
    fn = getattr(fn, "__func__", fn)
    while hasattr(fn, "__wrapped__"):
        fn = fn.__wrapped__
    return fn if isinstance(fn, types.FunctionType) else None


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
    _expects: list[tuple[bool, float, str]] | None = field(default=None, repr=False)

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

    def check(self, fn: Callable[..., Any], *, stars: int = 2, minutes: int = 15, points: float | None = None,
              own_code: tuple[str, ...] = ()) -> Callable[[Callable[[Callable[..., Any]], Any]], CheckResult]:
        """Decorate a test body ``body(f)`` that asserts what ``fn`` must do; it runs at once, prints
        one line and returns the :class:`CheckResult` in place of the body. ``stars`` (1–3) and ``minutes``
        tag the exercise, ``points`` (default ``stars``) is what it is worth when graded, ``own_code`` the
        library names the student's function must not call (the exercise asks to write them)."""
        if stars not in STAR_LABELS or not (isinstance(minutes, int) and minutes > 0):
            raise ValueError(f"check({getattr(fn, '__name__', fn)!r}): stars {stars!r} (expected 1, 2 or 3), "
                             f"minutes {minutes!r} (expected a positive integer)")
        worth = float(stars if points is None else points)

        def run(body: Callable[[Callable[..., Any]], Any]) -> CheckResult:
            called = library_calls(fn, own_code) if own_code else []
            if called:
                result = CheckResult(getattr(fn, "__name__", "exercise"), "wrong",
                                     f"your function calls the library's {', '.join(called)}: this exercise "
                                     "asks you to write it yourself")
            else:
                result = self._evaluate_weighted(fn, body)
            if self.using_solutions:
                result = CheckResult(result.exercise, result.status, result.message, True, result.fraction)
            self.results.append(result)
            self._record(result, stars, minutes, worth)
            print(result.line() + f"  [{STAR_LABELS[stars]}, ~{minutes} min, {worth:g} points]")
            if self.using_solutions and not result.solved:
                raise ExerciseError(self.notebook, result.exercise, result.status, result.line())
            return result

        return run

    def expect(self, condition: Any, message: str, weight: float = 1.0) -> bool:
        """A soft assertion inside a check body: recorded with its ``weight`` and the check goes on; the
        exercise then scores the share of the weights that held. Outside a check it is a plain assertion."""
        ok = bool(condition)
        if self._expects is None:
            assert ok, message
        else:
            self._expects.append((ok, float(weight), message))
        return ok

    def _evaluate_weighted(self, fn: Callable[..., Any], body: Callable[[Callable[..., Any]], Any]) -> CheckResult:
        self._expects = []
        try:
            result = self.evaluate(fn, body)
            expects = self._expects
        finally:
            self._expects = None
        if result.status == "unsolved":
            return result
        weight = sum(w for _, w, _ in expects)
        held = sum(w for ok, w, _ in expects if ok)
        failed = [m for ok, _, m in expects if not ok]
        if result.status == "wrong":  # an assertion or an error stopped the body: it counts as one failed unit
            return CheckResult(result.exercise, "wrong", "; ".join([*failed, result.message]), fraction=held / (weight + 1.0))
        if failed:
            return CheckResult(result.exercise, "wrong", "; ".join(failed), fraction=held / weight)
        return CheckResult(result.exercise, "solved", fraction=1.0)

    def _record(self, result: CheckResult, stars: int, minutes: int, points: float) -> None:
        """Append the result to the grader's record (``LIPMPCC_GRADE_LOG``), when one is kept."""
        path = os.environ.get(GRADE_LOG_ENV, "").strip()
        if not path:
            return
        row = {"notebook": self.notebook, "exercise": result.exercise, "status": result.status,
               "message": result.message, "fraction": result.fraction, "stars": stars, "minutes": minutes,
               "points": points}
        with open(path, "a", encoding="utf-8") as fh:
            fh.write(json.dumps(row, ensure_ascii=False) + "\n")

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
        return CheckResult(name, "solved", fraction=1.0)

    def summary(self) -> str:
        """One line: how many of this notebook's checks are solved."""
        n = len(self.results)
        k = sum(r.solved for r in self.results)
        return f"{self.notebook}: {k} of {n} exercises solved"
