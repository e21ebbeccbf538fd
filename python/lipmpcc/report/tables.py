"""Markdown tables: the stepping-stone tables (Table II beside the paper's numbers, the push sweep), built
on one markdown-table function, :func:`md_table`, and :func:`fmt`, a value of a table."""

from __future__ import annotations

import math
from typing import Any, Sequence

__all__ = ["md_table", "fmt", "table_markdown", "sweep_markdown"]


def md_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A markdown table: the header row, the ``|---|`` rule and one line per row (an empty cell is
    written ``| |``, a ``|`` in a cell ``\\|``)."""

    def line(cells: Sequence[str]) -> str:
        return "|" + "|".join(" " + c.replace("|", r"\|") + " " if c else " " for c in cells) + "|"

    return "\n".join([line(header), "|" + "---|" * len(header)] + [line(r) for r in rows])


def fmt(v: Any) -> str:
    """A value of the report: floats to 4 significant digits, timing statistics as median and p90 [ms],
    lists of floats to 2 decimals."""
    if isinstance(v, float):
        return "nan" if math.isnan(v) else f"{v:.4g}"
    if isinstance(v, dict) and "median" in v:
        return f"median {v['median']:.3g} ms, p90 {v['p90']:.3g} ms"
    if isinstance(v, list) and v and isinstance(v[0], float):
        return "[" + ", ".join(f"{x:.2f}" for x in v) + "]"
    return str(v)


def table_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """Table II: ALIP-MPC and ALIP-QP side by side with the paper's numbers (rows of
    :func:`lipmpcc.studies.stepping_stones.study_table`)."""
    by_case: dict[str, dict[str, dict[str, Any]]] = {}
    for r in rows:
        by_case.setdefault(r["case"], {})[r["planner"]] = r

    def cell(r: dict[str, Any] | None) -> str:
        if r is None:
            return "–"
        if r["fell"]:
            return f"falls at stone {r['fall_step']}"
        return f"{r['step_rmse_m']:.3f}"

    def paper(r: dict[str, Any] | None) -> str:
        if r is None:
            return "–"
        v = r["paper_rmse_m"]
        return "fails" if v is None else f"{v:.3f}"

    lines = []
    for case, d in by_case.items():
        m, q = d.get("alip-mpc"), d.get("alip-qp")
        lines.append([case, cell(m), paper(m), cell(q), paper(q), "–" if m is None else str(m["solver_failures"])])
    header = ["case", "ALIP-MPC RMSE [m]", "paper", "ALIP-QP RMSE [m]", "paper", "MPC solver failures"]
    return md_table(header, lines)


def sweep_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """The push sweep (:func:`lipmpcc.studies.stepping_stones.push_sweep`): for each push and scale, each
    planner's outcome."""
    planners = list(dict.fromkeys(r["planner"] for r in rows))
    keys = list(dict.fromkeys((r["push"], r["scale"]) for r in rows))
    lines = []
    for push, sc in keys:
        cells = [push, f"{sc:g}"]
        for p in planners:
            r = next(r for r in rows if r["push"] == push and r["scale"] == sc and r["planner"] == p)
            cells.append(f"falls at stone {r['fall_step']}" if r["fell"] else "survives")
        lines.append(cells)
    return md_table(["push", "scale", *planners], lines)
