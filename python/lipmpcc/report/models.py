"""The full-body studies on each model side by side: one row per study (its ``variant``: the ``digit_like``
study it repeats), the paper's claim, then one column per full-body model (``digit_like`` first, then the
model of ``lipmpcc reproduce --robot MODEL.xml``), each cell the result in a few words with its mark and
its solver counts.

:func:`full_body_robots` lists the models of a ``results.json``; :func:`models_table` builds the table from
the entries and their marks (:class:`~lipmpcc.report.marks.Judgement`), so that it can be tested with fake
summaries.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from .document import Table
from .marks import Judgement
from .values import length, model_name, paper_text, run_text

__all__ = ["REDUCED_MODELS", "full_body_robots", "model_cell", "models_table"]

#: the papers' planning models (the reduced loops): not full-body columns
REDUCED_MODELS = ("lip", "alip")


def _robot(entry: Mapping[str, Any]) -> str | None:
    r = entry.get("robot")
    return None if r is None or r in REDUCED_MODELS else str(r)


def full_body_robots(studies: Mapping[str, Mapping[str, Any]]) -> list[str]:
    """The full-body models of the entries ``studies`` (name -> entry of ``results.json``), in the order they
    first appear (``digit_like`` first in a reproduction)."""
    return list(dict.fromkeys(r for e in studies.values() if (r := _robot(e)) is not None))


def model_cell(entry: Mapping[str, Any], judgement: Judgement) -> str:
    """One model's result of a study in a few words: the step RMSE (or how the run ended when it did not
    complete), the mark, and the solver failures and relaxed solves when there were any."""
    if "error" in entry:
        return f"{judgement.label}: {entry['error']}"
    ours = entry.get("ours") or {}
    outcome = entry.get("outcome")
    if outcome not in (None, "completed", "-"):
        head = run_text(entry)
    elif "step_rmse_m" in ours:
        head = f"RMSE {length(ours.get('step_rmse_m'))}"
    else:
        head = run_text(entry)
    counts = [f"{entry[k]} {w}" for k, w in (("solver_failures", "failed"), ("relaxed_solves", "relaxed"))
              if isinstance(entry.get(k), int) and entry[k] > 0]
    return f"{head} ({judgement.label}" + (f"; {', '.join(counts)})" if counts else ")")


def models_table(studies: Mapping[str, Mapping[str, Any]], marks: Mapping[str, Judgement],
                 robots: Sequence[str] | None = None) -> Table | None:
    """The full-body studies of ``studies`` with one column per model (``robots``: by default
    :func:`full_body_robots`), a row per ``variant`` in the order of the entries; ``–`` where a model did
    not run the study. None when fewer than two models ran a full-body study (nothing to set side by side)."""
    robots = list(robots) if robots is not None else full_body_robots(studies)
    if len(robots) < 2:
        return None
    rows: dict[str, dict[str, str]] = {}
    claims: dict[str, str] = {}
    for name, e in studies.items():
        robot = _robot(e)
        if robot not in robots:
            continue
        key = str(e.get("variant") or name)
        rows.setdefault(key, {})[robot] = model_cell(e, marks[name])
        claims.setdefault(key, paper_text(e.get("paper")) if e.get("paper_id") else "(not in the papers)")
    header = ("study", "paper", *(model_name(r) for r in robots))
    body = tuple((f"`{k}`", claims[k], *(cells.get(r, "–") for r in robots)) for k, cells in rows.items())
    return Table(header, body)
