"""Grade a student's notebook with points: ``lipmpcc course grade NOTEBOOK.ipynb`` (or a folder of them).

The grader runs the notebook headless (a Jupyter kernel through ``nbclient``, fast mode, matplotlib's Agg
backend, the solutions *off*) and reads each exercise's check from the record the checks keep
(``LIPMPCC_GRADE_LOG``, :mod:`lipmpcc.course.exercises`):

- **The checks are the reference's.** Before running, every cell of the student's notebook that holds
  ``@ex.check(NAME ...)`` is replaced by the reference notebook's check cell of that exercise (the
  repository's ``notebooks/``, or ``reference=``): a student cannot edit a check, its points or its tags,
  and an exercise whose check cell was deleted is added back after the student's stub.
- **Points.** Each exercise is worth its check's ``points`` (default its stars, 1–3); it scores
  ``points × fraction``: 1 when solved, the share of the weighted expectations that held when partly
  right (:meth:`Exercises.expect`), 0 when unsolved, wrong, timed out, or when the function calls the library
  it was asked to write (``own_code``).
- **Time limits.** A check cell gets ``exercise_timeout_s`` (default 60 s), any other cell
  ``cell_timeout_s`` (900 s, as the site's build); a cell that runs out is interrupted, scores its exercise 0
  ("timed out") and the notebook goes on.

:func:`gradescope_results` turns a :class:`NotebookGrade` into Gradescope's ``results.json``
(:data:`GRADESCOPE_SCHEMA`; https://gradescope-autograders.readthedocs.io/en/latest/specs/).
"""

from __future__ import annotations

import ast
import json
import os
import re
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..exceptions import InvalidInputError
from .exercises import GRADE_LOG_ENV, SOLUTIONS_ENV, STAR_LABELS

__all__ = [
    "ExerciseSpec",
    "ExerciseGrade",
    "NotebookGrade",
    "GRADESCOPE_SCHEMA",
    "reference_notebooks",
    "exercise_specs",
    "grade_notebook",
    "grade_folder",
    "gradescope_results",
    "validate_gradescope",
    "format_grade",
    "grade_path",
    "write_gradescope",
]

#: the check cells' time limit [s]; other cells get :data:`CELL_TIMEOUT_S`
EXERCISE_TIMEOUT_S = 60.0
CELL_TIMEOUT_S = 900.0
_CHECK = re.compile(r"@ex\.check\(\s*(\w+)")
_STUB = re.compile(r"@ex\.stub\s*\n\s*def\s+(\w+)")

#: Gradescope's results.json, the part this grader writes (a JSON schema; extra keys are allowed by Gradescope)
GRADESCOPE_SCHEMA: dict[str, Any] = {
    "type": "object",
    "required": ["score", "max_score", "tests"],
    "properties": {
        "score": {"type": "number", "minimum": 0},
        "max_score": {"type": "number", "minimum": 0},
        "execution_time": {"type": "number", "minimum": 0},
        "output": {"type": "string"},
        "visibility": {"enum": ["hidden", "after_due_date", "after_published", "visible"]},
        "tests": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["name", "score", "max_score", "output"],
                "properties": {
                    "name": {"type": "string", "minLength": 1},
                    "score": {"type": "number", "minimum": 0},
                    "max_score": {"type": "number", "minimum": 0},
                    "output": {"type": "string"},
                    "status": {"enum": ["passed", "failed"]},
                    "visibility": {"enum": ["hidden", "after_due_date", "after_published", "visible"]},
                },
            },
        },
    },
}


@dataclass(frozen=True)
class ExerciseSpec:
    """One exercise of a reference notebook: its name, check cell source, stars, minutes and points."""

    name: str
    check_source: str
    stars: int
    minutes: int
    points: float


@dataclass(frozen=True)
class ExerciseGrade:
    """One exercise graded: ``score`` of ``max_score`` points, ``status`` (``solved``, ``wrong``,
    ``unsolved``, ``timed out``, ``not run``) and the check's message."""

    name: str
    score: float
    max_score: float
    status: str
    message: str = ""
    stars: int = 2
    minutes: int = 15


@dataclass
class NotebookGrade:
    """A notebook graded: its exercises, the total [points] and the run's time [s] and errors."""

    notebook: Path
    reference: str
    exercises: list[ExerciseGrade] = field(default_factory=list)
    seconds: float = 0.0
    errors: list[str] = field(default_factory=list)

    @property
    def score(self) -> float:
        return sum(e.score for e in self.exercises)

    @property
    def max_score(self) -> float:
        return sum(e.max_score for e in self.exercises)


def reference_notebooks() -> Path | None:
    """The repository's ``notebooks/`` folder (a source checkout), or ``None`` in an installed wheel."""
    here = Path(__file__).resolve()
    for parent in here.parents:
        cand = parent / "notebooks"
        if (cand / "solutions").is_dir() and any(cand.glob("00_*.ipynb")):
            return cand
    return None


def _keywords(source: str, name: str) -> dict[str, Any]:
    """The literal keyword arguments of ``@ex.check(name, ...)`` in ``source``."""
    for node in ast.walk(ast.parse(source)):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "check"
                and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == name):
            return {k.arg: ast.literal_eval(k.value) for k in node.keywords if k.arg}
    return {}


def exercise_specs(notebook: Path) -> dict[str, ExerciseSpec]:
    """The exercises of ``notebook`` (its ``@ex.check`` cells), in order, with their tags and points."""
    import nbformat

    nb = nbformat.read(str(notebook), as_version=4)
    specs: dict[str, ExerciseSpec] = {}
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        for name in _CHECK.findall(cell.source):
            kw = _keywords(cell.source, name)
            stars = int(kw.get("stars", 2))
            specs[name] = ExerciseSpec(name, cell.source, stars, int(kw.get("minutes", 15)),
                                       float(kw.get("points", stars)))
    return specs


def _with_reference_checks(nb, specs: dict[str, ExerciseSpec]) -> None:  # noqa: ANN001 - an nbformat notebook
    """Replace the student's check cells by the reference's; add back a missing one after its stub."""
    import nbformat

    placed: set[str] = set()
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        names = [n for n in _CHECK.findall(cell.source) if n in specs]
        if names:
            cell.source = "\n\n".join(specs[n].check_source for n in names)
            cell.outputs = []
            placed.update(names)
    for name, spec in specs.items():
        if name in placed:
            continue
        at = next((i for i, c in enumerate(nb.cells) if c.cell_type == "code" and name in _STUB.findall(c.source)), None)
        if at is not None:
            nb.cells.insert(at + 1, nbformat.v4.new_code_cell(spec.check_source))


def _run(nb, cwd: Path, env: dict[str, str], exercise_timeout_s: float, cell_timeout_s: float) -> list[str]:  # noqa: ANN001
    """Execute ``nb`` in a kernel started in ``cwd`` with ``env``; the cells' errors (a timeout, a crash)."""
    from nbclient import NotebookClient

    def timeout(cell) -> int:  # noqa: ANN001
        return int(exercise_timeout_s if _CHECK.search(cell.source) else cell_timeout_s)

    client = NotebookClient(nb, timeout=int(cell_timeout_s), timeout_func=timeout, allow_errors=True,
                            interrupt_on_timeout=True, kernel_name="python3",
                            resources={"metadata": {"path": str(cwd)}})
    try:
        client.execute(env=env)  # the kernel's whole environment (jupyter_client's start_kernel)
        errors = []
    except Exception as exc:  # noqa: BLE001 - a dead kernel: grade what ran, and say so
        errors = [f"the kernel stopped: {type(exc).__name__}: {str(exc)[:500]}"]
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out.get("output_type") == "error" and _CHECK.search(cell.source) and out.get("ename") in (
                    "KeyboardInterrupt", "CellTimeoutError"):
                errors.append("timed out: " + ", ".join(_CHECK.findall(cell.source)))
    return errors


def grade_notebook(notebook: str | Path, reference: str | Path | None = None, *, fast: bool = True,
                   exercise_timeout_s: float = EXERCISE_TIMEOUT_S, cell_timeout_s: float = CELL_TIMEOUT_S,
                   solutions: str | Path | None = None, cwd: str | Path | None = None) -> NotebookGrade:
    """Run ``notebook`` headless and grade its exercises against the reference notebook of the same name
    (``reference``: a notebook or a folder; default the repository's ``notebooks/``). ``solutions`` names a
    solutions folder to run instead of the student's code (to check the reference itself); ``cwd`` the
    kernel's folder (default the reference notebook's, where its relative paths resolve)."""
    import nbformat

    path = Path(notebook)
    if path.suffix != ".ipynb" or not path.is_file():
        raise InvalidInputError("notebook", str(notebook), "an existing .ipynb file")
    ref = _reference_for(path, reference)
    specs = exercise_specs(ref)
    if not specs:
        raise InvalidInputError("reference", str(ref), "a notebook with exercises (@ex.check cells)")
    try:
        nb = nbformat.read(str(path), as_version=4)
    except Exception as exc:  # noqa: BLE001 - not a notebook
        raise InvalidInputError("notebook", str(notebook), "a Jupyter notebook (nbformat 4)", str(exc)[:200]) from exc
    _with_reference_checks(nb, specs)
    with tempfile.TemporaryDirectory(prefix="lipmpcc-grade-") as tmp:
        log = Path(tmp) / "checks.jsonl"
        env = {k: v for k, v in os.environ.items() if k not in (SOLUTIONS_ENV, GRADE_LOG_ENV)}
        env.update({GRADE_LOG_ENV: str(log), "MPLBACKEND": "Agg", "PYDEVD_DISABLE_FILE_VALIDATION": "1"})
        env["LIPMPCC_FAST"] = "1" if fast else env.get("LIPMPCC_FAST", "")
        if solutions is not None:
            env[SOLUTIONS_ENV] = str(Path(solutions).resolve())
        t0 = time.perf_counter()
        errors = _run(nb, Path(cwd) if cwd else ref.parent, env, exercise_timeout_s, cell_timeout_s)
        rows = [json.loads(ln) for ln in log.read_text(encoding="utf-8").splitlines()] if log.is_file() else []
    grade = NotebookGrade(path, str(ref), seconds=time.perf_counter() - t0, errors=errors)
    last = {r["exercise"]: r for r in rows}
    timed_out = {n for e in errors if e.startswith("timed out: ") for n in e[11:].split(", ")}
    for name, spec in specs.items():
        row = last.get(name)
        if row is None:
            status = "timed out" if name in timed_out else "not run"
            why = (f"the check ran over {exercise_timeout_s:g} s" if status == "timed out"
                   else "the check did not run (a cell before it failed, or the stub is missing)")
            grade.exercises.append(ExerciseGrade(name, 0.0, spec.points, status, why, spec.stars, spec.minutes))
            continue
        fraction = float(row["fraction"]) if row["status"] != "unsolved" else 0.0
        grade.exercises.append(ExerciseGrade(name, round(spec.points * fraction, 4), spec.points, row["status"],
                                             row.get("message", ""), spec.stars, spec.minutes))
    return grade


def _reference_for(path: Path, reference: str | Path | None) -> Path:
    ref = Path(reference) if reference is not None else reference_notebooks()
    if ref is None:
        raise InvalidInputError("reference", None, "the course's notebooks/ folder (pass --reference DIR)")
    if ref.is_dir():
        ref = ref / path.name
    if not ref.is_file():
        raise InvalidInputError("notebook", path.name, "the name of a course notebook (NN_name.ipynb)",
                                f"no reference {ref}")
    return ref


def grade_folder(folder: str | Path, reference: str | Path | None = None, **kw: Any) -> list[NotebookGrade]:
    """Grade every ``.ipynb`` under ``folder`` (a class: one subfolder per student, or the notebooks side by
    side) whose name is a course notebook; the others are skipped."""
    root = Path(folder)
    if not root.is_dir():
        raise InvalidInputError("folder", str(folder), "an existing folder of notebooks")
    ref_dir = Path(reference) if reference is not None else reference_notebooks()
    found = sorted(p for p in root.rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts
                   and (ref_dir is None or (ref_dir / p.name).is_file()))
    if not found:
        raise InvalidInputError("folder", str(folder), "a folder holding course notebooks (NN_name.ipynb)")
    return [grade_notebook(p, reference, **kw) for p in found]


def gradescope_results(grade: NotebookGrade) -> dict[str, Any]:
    """Gradescope's ``results.json`` of ``grade``: one test per exercise (name with its stars and minutes)."""
    tests = [{"name": f"{e.name} [{STAR_LABELS.get(e.stars, '?')}, ~{e.minutes} min]", "score": e.score,
              "max_score": e.max_score, "status": "passed" if e.score >= e.max_score else "failed",
              "output": e.status + (f": {e.message}" if e.message else "")} for e in grade.exercises]
    out = f"{grade.notebook.name}: {grade.score:g} / {grade.max_score:g} points"
    if grade.errors:
        out += "\n" + "\n".join(grade.errors)
    return {"score": round(grade.score, 4), "max_score": grade.max_score,
            "execution_time": round(grade.seconds, 1), "output": out, "tests": tests}


def validate_gradescope(results: dict[str, Any]) -> None:
    """Raise :class:`InvalidInputError` naming the first field of ``results`` that breaks
    :data:`GRADESCOPE_SCHEMA` (types, required keys, non-negative scores, enums)."""

    def check(value: Any, schema: dict[str, Any], where: str) -> None:
        kind = schema.get("type")
        types_ = {"object": dict, "array": list, "string": str, "number": (int, float)}
        if kind and (not isinstance(value, types_[kind]) or (kind == "number" and isinstance(value, bool))):
            raise InvalidInputError(where, value, f"a {kind}")
        if "enum" in schema and value not in schema["enum"]:
            raise InvalidInputError(where, value, f"one of {schema['enum']}")
        if kind == "number" and value < schema.get("minimum", float("-inf")):
            raise InvalidInputError(where, value, f"a number ≥ {schema['minimum']}")
        if kind == "string" and len(value) < schema.get("minLength", 0):
            raise InvalidInputError(where, value, "a non-empty string")
        if kind == "object":
            for key in schema.get("required", []):
                if key not in value:
                    raise InvalidInputError(f"{where}.{key}", None, "a required field")
            for key, sub in schema.get("properties", {}).items():
                if key in value:
                    check(value[key], sub, f"{where}.{key}")
        if kind == "array":
            for i, item in enumerate(value):
                check(item, schema["items"], f"{where}[{i}]")

    check(results, GRADESCOPE_SCHEMA, "results")


def format_grade(grade: NotebookGrade) -> str:
    """The grade as printed by ``lipmpcc course grade``: a line per exercise, then the total."""
    lines = [f"{grade.notebook}  (checks of {grade.reference}; {grade.seconds:.0f} s)"]
    for e in grade.exercises:
        mark = "✓" if e.score >= e.max_score else ("◐" if e.score > 0 else "✗")
        msg = f"  {e.message}" if e.message and e.status != "solved" else ""
        lines.append(f"  {mark} {e.name:<28} {e.score:>5g} / {e.max_score:<3g} {STAR_LABELS.get(e.stars, '?'):<4}"
                     f" {e.status}{msg}")
    lines += [f"  ! {err}" for err in grade.errors if not err.startswith("timed out: ")]
    pct = 100.0 * grade.score / grade.max_score if grade.max_score else 0.0
    lines.append(f"  total: {grade.score:g} / {grade.max_score:g} points ({pct:.0f} %)")
    return "\n".join(lines)


def grade_path(path: str | Path, reference: str | Path | None = None, **kw: Any) -> list[NotebookGrade]:
    """Grade one notebook (a ``.ipynb``) or a class (a folder): :func:`grade_notebook` or :func:`grade_folder`."""
    p = Path(path)
    if p.is_dir():
        return grade_folder(p, reference, **kw)
    return [grade_notebook(p, reference, **kw)]


def write_gradescope(grades: list[NotebookGrade], target: str | Path, root: str | Path | None = None) -> list[Path]:
    """Write Gradescope's ``results.json`` (validated): for one notebook to the file ``target``; for a class
    (``root`` the graded folder) one file per notebook into the folder ``target``, named by the notebook's
    path under ``root`` (``alice__03_lip_mpcc.json``). Returns the files written."""
    out = Path(target)
    if out.exists() and out.is_dir() != (root is not None):
        raise InvalidInputError("--gradescope", str(target), "a file for one notebook, a folder for a class")
    written = []
    for g in grades:
        results = gradescope_results(g)
        validate_gradescope(results)
        if root is None:
            dest = out
        else:
            rel = g.notebook.resolve().relative_to(Path(root).resolve())
            dest = out / ("__".join(rel.with_suffix("").parts) + ".json")
        dest.parent.mkdir(parents=True, exist_ok=True)
        dest.write_text(json.dumps(results, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        written.append(dest)
    return written
