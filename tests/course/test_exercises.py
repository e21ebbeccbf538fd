"""lipmpcc.course.exercises: stubs, checks and solutions; and the notebooks' exercises all have
solutions (a stub without one would only be found by a student)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from lipmpcc.course import SOLUTIONS_ENV, ExerciseError, Exercises

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"


@pytest.fixture()
def no_solutions(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(SOLUTIONS_ENV, raising=False)


@pytest.fixture()
def solutions(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "nb.py").write_text("def square(x):\n    return x * x\n\ndef cube(x):\n    return x * x\n")
    monkeypatch.setenv(SOLUTIONS_ENV, str(tmp_path))
    return tmp_path


def _stubs(ex: Exercises):
    @ex.stub
    def square(x):
        raise NotImplementedError

    @ex.stub
    def cube(x):
        raise NotImplementedError

    return square, cube


def test_an_unsolved_exercise_says_so_and_does_not_raise(no_solutions, capsys) -> None:
    ex = Exercises("nb")
    square, _ = _stubs(ex)

    @ex.check(square)
    def res(f):
        assert f(3) == 9

    assert res.status == "unsolved" and not res.solved
    assert "◻ square: not yet solved" in capsys.readouterr().out


def test_a_solved_and_a_wrong_exercise(no_solutions, capsys) -> None:
    ex = Exercises("nb")

    @ex.stub
    def square(x):
        return x * x

    @ex.stub
    def cube(x):
        return x * x  # wrong

    @ex.check(square)
    def ok(f):
        assert f(3) == 9

    @ex.check(cube)
    def bad(f):
        assert f(2) == 8, f"cube(2) should be 8, got {f(2)}"

    out = capsys.readouterr().out
    assert ok.solved and "✓ square: solved" in out
    assert bad.status == "wrong" and "✗ cube: cube(2) should be 8, got 4" in out
    assert ex.summary() == "nb: 1 of 2 exercises solved"


def test_a_student_bug_is_reported_not_raised(no_solutions) -> None:
    ex = Exercises("nb")

    @ex.stub
    def square(x):
        return x.nope

    res = ex.evaluate(square, lambda f: f(2))
    assert res.status == "wrong" and "AttributeError" in res.message


def test_solutions_replace_stubs_and_a_failed_check_raises(solutions, capsys) -> None:
    ex = Exercises("nb")
    square, cube = _stubs(ex)
    assert square(4) == 16  # the solution, not the stub

    @ex.check(square)
    def ok(f):
        assert f(3) == 9

    assert ok.solved
    with pytest.raises(ExerciseError) as err:
        @ex.check(cube)
        def _(f):
            assert f(2) == 8, "cube(2) should be 8"
    assert err.value.status == "wrong" and err.value.exercise == "cube" and "nb" in str(err.value)


def test_a_missing_solution_is_named(solutions) -> None:
    ex = Exercises("nb")
    with pytest.raises(ExerciseError, match="no function 'quartic'"):
        @ex.stub
        def quartic(x):
            raise NotImplementedError
    with pytest.raises(ExerciseError, match="no solutions module"):
        Exercises("other").stub(lambda x: x)


def test_bad_notebook_name() -> None:
    with pytest.raises(ValueError, match="notebook=''"):
        Exercises("")


def _notebook_stubs(nb: Path) -> list[str]:
    cells = json.loads(nb.read_text())["cells"]
    src = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    return re.findall(r"@ex\.stub\s*\n\s*def\s+(\w+)", src)


@pytest.mark.skipif(not NOTEBOOKS.is_dir(), reason="needs the source tree's notebooks/")
def test_every_notebook_stub_has_a_solution_and_a_check() -> None:
    problems = []
    for nb in sorted(NOTEBOOKS.glob("*.ipynb")):
        names = _notebook_stubs(nb)
        if not names:
            continue
        sol = NOTEBOOKS / "solutions" / f"{nb.stem}.py"
        text = sol.read_text() if sol.is_file() else ""
        src = nb.read_text()
        for name in names:
            if not re.search(rf"^def {name}\(", text, re.M):
                problems.append(f"{nb.name}: no solution for {name} in {sol.name}")
            call = re.search(rf"@ex\.check\({name}\b([^)]*)\)", src)
            if call is None:
                problems.append(f"{nb.name}: no check for {name}")
            elif "stars=" not in call.group(1) or "minutes=" not in call.group(1):
                problems.append(f"{nb.name}: the check of {name} has no difficulty (stars=) or time (minutes=) tag")
    assert not problems, "\n".join(problems)
