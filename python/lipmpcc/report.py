"""Markdown reports: the reproduction report of ``lipmpcc reproduce`` (``results.json`` and ``report.md``)
and the stepping-stone tables (Table II beside the paper's numbers, the push sweep), all built on one
markdown-table function, :func:`md_table`."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Sequence

__all__ = ["md_table", "fmt", "report_markdown", "write_report", "table_markdown", "sweep_markdown"]


def md_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A markdown table: the header row, the ``|---|`` rule and one line per row (an empty cell is
    written ``| |``)."""

    def line(cells: Sequence[str]) -> str:
        return "|" + "|".join(f" {c} " if c else " " for c in cells) + "|"

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


def report_markdown(results: dict[str, Any]) -> str:
    """``report.md``: one row per study (its criterion, whether it is met, our numbers and the paper's),
    then every study's figures."""
    rows = []
    for name, e in results["studies"].items():
        if "error" in e:
            rows.append([name, "", "error", e["error"], ""])
            continue
        ours = "; ".join(f"{k}={fmt(v)}" for k, v in e["ours"].items())
        met = {True: "yes", False: "**no**", None: "-"}[e["meets_criterion"]]
        rows.append([name, e["criterion"], met, ours, fmt(e["paper"])])
    lines = [
        "# lipmpcc reproduction report",
        "",
        f"Fast mode: {results['fast']}. Total time: {results['wall_s']:.0f} s.",
        "",
        md_table(["study", "criterion", "met", "ours", "paper"], rows),
        "",
    ]
    for name, e in results["studies"].items():
        for fig in e.get("figures", []):
            lines += [f"### {e['title']}", "", f"![{name}]({fig})", ""]
    return "\n".join(lines)


def write_report(results: dict[str, Any], out: str | Path) -> Path:
    """Write ``results.json`` and ``report.md`` (:func:`report_markdown`) to the folder ``out``; returns the
    path of ``report.md``."""
    out = Path(out)
    with open(out / "results.json", "w") as f:
        json.dump(results, f, indent=2, default=str)
    (out / "report.md").write_text(report_markdown(results))
    return out / "report.md"


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
