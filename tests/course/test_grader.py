"""lipmpcc.course.grader: ``lipmpcc course grade`` scores a student's notebook with points.

Three kernel runs (about 6 s each): the course's notebook 00 with its stubs (0 %) and its solutions (100 %),
and a probe notebook whose student got one exercise partly right (a wrong sign: the message says which
error), called the library in another (0, the call named), looped forever in a third (0, timed out) and
rewrote a check (the reference's check grades all the same). The Gradescope file validates against its
schema (also with ``jsonschema`` when installed)."""

from __future__ import annotations

import json
from pathlib import Path

import nbformat
import pytest

from lipmpcc.cli import main
from lipmpcc.course import grader
from lipmpcc.exceptions import InvalidInputError

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks"

SETUP = "import numpy as np\nfrom lipmpcc.course import Exercises\nex = Exercises('99_probe')"
CHECK_CL = '''@ex.check(contouring_lag, stars=2, minutes=10, own_code=("lipmpcc.contouring.errors",))
def _(f):
    ex.expect(np.allclose(f([0.0, -1.0], [0.0, 0.0], 0.0), [1.0, 0.0]),
              "contouring error: a robot 1 m to the right of a path along +x has e_c = +1")
    ex.expect(np.allclose(f([-1.0, 0.0], [0.0, 0.0], 0.0), [0.0, 1.0]),
              "lag error: a robot 1 m behind on a path along +x has e_l = +1")'''
CHECK_DCM = '''@ex.check(dcm, stars=1, minutes=5, own_code=("lipmpcc.models.lip.dcm",))
def _(f):
    assert np.allclose(f(np.array([0.1, 0.2]), np.array([0.3, -0.6]), 3.0), [0.2, 0.0]), "not x + v / w"'''
CHECK_SLOW = '''@ex.check(answer, stars=3, minutes=30)
def _(f):
    assert f() == 42, "the answer is 42"'''
STUBS = {"contouring_lag": "def contouring_lag(p, yd, phi):\n    raise NotImplementedError",
         "dcm": "def dcm(x, v, w):\n    raise NotImplementedError",
         "answer": "def answer():\n    raise NotImplementedError"}
STUDENT = {
    "contouring_lag": "def contouring_lag(p, yd, phi):\n"
                      "    d = np.asarray(p, float) - np.asarray(yd, float)\n"
                      "    c, s = np.cos(phi), np.sin(phi)\n"
                      "    return np.array([s * d[0] - c * d[1], c * d[0] + s * d[1]])  # lag sign wrong",
    "dcm": "def dcm(x, v, w):\n    from lipmpcc.models.lip import dcm as library_dcm\n"
           "    return library_dcm(x, v, w)",
    "answer": "def answer():\n    while True:\n        pass",
}
SOLUTIONS = '''import numpy as np

def contouring_lag(p, yd, phi):
    d = np.asarray(p, float) - np.asarray(yd, float)
    c, s = np.cos(phi), np.sin(phi)
    return np.array([s * d[0] - c * d[1], -c * d[0] - s * d[1]])

def dcm(x, v, w):
    return np.asarray(x) + np.asarray(v) / w

def answer():
    return 42
'''


def _notebook(path: Path, bodies: dict[str, str], checks: dict[str, str]) -> Path:
    cells = [nbformat.v4.new_code_cell(SETUP)]
    for name, body in bodies.items():
        cells.append(nbformat.v4.new_code_cell("@ex.stub\n" + body))
        cells.append(nbformat.v4.new_code_cell(checks[name]))
    nb = nbformat.v4.new_notebook(cells=cells)
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, str(path))
    return path


@pytest.fixture(scope="module")
def probe(tmp_path_factory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("grading")
    checks = {"contouring_lag": CHECK_CL, "dcm": CHECK_DCM, "answer": CHECK_SLOW}
    ref = _notebook(root / "ref" / "99_probe.ipynb", STUBS, checks)
    tampered = dict(checks, contouring_lag="@ex.check(contouring_lag)\ndef _(f):\n    pass")
    student = _notebook(root / "class" / "alice" / "99_probe.ipynb", STUDENT, tampered)
    (root / "solutions").mkdir()
    (root / "solutions" / "99_probe.py").write_text(SOLUTIONS, encoding="utf-8")
    return {"root": root, "ref": ref, "student": student, "solutions": root / "solutions"}


def test_the_course_notebook_stubs_score_zero_and_its_solutions_full_marks(tmp_path: Path) -> None:
    nb = tmp_path / "00_roadmap.ipynb"
    nb.write_bytes((NOTEBOOKS / "00_roadmap.ipynb").read_bytes())
    stubs = grader.grade_notebook(nb, NOTEBOOKS)
    assert stubs.max_score > 0 and stubs.score == 0 and all(e.status == "unsolved" for e in stubs.exercises)
    solved = grader.grade_notebook(nb, NOTEBOOKS, solutions=NOTEBOOKS / "solutions")
    assert solved.score == solved.max_score == stubs.max_score, grader.format_grade(solved)
    assert [e.name for e in solved.exercises] == list(grader.exercise_specs(NOTEBOOKS / "00_roadmap.ipynb"))


def test_a_class_is_graded_with_partial_credit_a_library_call_and_a_timeout(probe, tmp_path: Path, capsys) -> None:
    out = tmp_path / "gradescope"
    code = main(["course", "grade", str(probe["root"] / "class"), "--reference", str(probe["ref"].parent),
                 "--timeout", "3", "--gradescope", str(out)])
    text = capsys.readouterr().out
    assert code == 0, text
    results = json.loads((out / "alice__99_probe.json").read_text(encoding="utf-8"))
    grader.validate_gradescope(results)
    by = {t["name"].split(" [")[0]: t for t in results["tests"]}
    cl, dcm, slow = by["contouring_lag"], by["dcm"], by["answer"]
    assert cl["max_score"] == 2 and cl["score"] == 1.0 and "lag error" in cl["output"], cl  # the tampered check is the reference's
    assert "contouring error" not in cl["output"]
    assert dcm["score"] == 0 and "calls the library's dcm" in dcm["output"], dcm
    assert slow["score"] == 0 and slow["output"].startswith("timed out"), slow
    assert results["score"] == 1.0 and results["max_score"] == 6.0
    assert "total: 1 / 6 points (17 %)" in text
    pytest.importorskip("jsonschema").validate(results, grader.GRADESCOPE_SCHEMA)


def test_the_reference_solutions_score_full_marks_on_the_probe(probe) -> None:
    g = grader.grade_notebook(probe["ref"], probe["ref"].parent, solutions=probe["solutions"])
    assert g.score == g.max_score == 6.0, grader.format_grade(g)


def test_gradescope_schema_rejects_what_gradescope_would() -> None:
    good = {"score": 1.0, "max_score": 2, "tests": [{"name": "a", "score": 1, "max_score": 2, "output": "ok"}]}
    grader.validate_gradescope(good)
    for bad, where in (({**good, "score": -1}, "results.score"), ({k: v for k, v in good.items() if k != "tests"}, "results.tests"),
                       ({**good, "tests": [{"name": "a", "score": 1, "max_score": 2}]}, "results.tests[0].output"),
                       ({**good, "tests": [{"name": "", "score": 1, "max_score": 2, "output": ""}]}, "results.tests[0].name")):
        with pytest.raises(InvalidInputError, match=where.replace("[", r"\[").replace("]", r"\]")):
            grader.validate_gradescope(bad)


def test_bad_paths_are_one_line_errors(tmp_path: Path, capsys) -> None:
    assert main(["course", "grade", str(tmp_path / "none.ipynb")]) == 2
    assert "expected an existing .ipynb file" in capsys.readouterr().err
    (tmp_path / "x.ipynb").write_text("{}", encoding="utf-8")
    with pytest.raises(InvalidInputError, match="name of a course notebook"):
        grader.grade_notebook(tmp_path / "x.ipynb", NOTEBOOKS)
    with pytest.raises(InvalidInputError, match="folder holding course notebooks"):
        grader.grade_folder(tmp_path, NOTEBOOKS)
