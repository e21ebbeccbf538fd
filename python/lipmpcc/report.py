"""Markdown reports: the reproduction report of ``lipmpcc reproduce`` (``results.json`` and ``report.md``)
and the stepping-stone tables (Table II beside the paper's numbers, the push sweep), all built on one
markdown-table function, :func:`md_table`."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Sequence

from .studies.outputs import write_text_atomic

__all__ = ["REPORT_FILE", "RESULTS_FILE", "md_table", "fmt", "report_markdown", "write_report", "table_markdown",
           "sweep_markdown"]

REPORT_FILE = "report.md"
RESULTS_FILE = "results.json"


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


def _met(e: dict[str, Any]) -> str:
    if e.get("expected_failure"):
        return "no (expected failure)"
    return {True: "yes", False: "**no**", None: "-"}[e["meets_criterion"]]


def _outcome(e: dict[str, Any]) -> str:
    """How a study's run ended (``completed``, ``fell``, ``collided``, ``stopped_early``; ``(expected)`` for a
    baseline known to fail), with its solver failures and relaxed re-solves when there were any."""
    if "outcome" not in e:  # results.json of an older lipmpcc
        return "-"
    text = e["outcome"] + (" (expected)" if e["outcome"] != "completed" and e.get("expected_outcome") == e["outcome"] else "")
    counts = [f"{e[k]} {label}" for k, label in (("solver_failures", "solver failures"), ("relaxed_solves", "relaxed"))
              if e.get(k)]
    return text + (f"; {', '.join(counts)}" if counts else "")


def _partial_banner(results: dict[str, Any]) -> list[str]:
    """The lines that mark a report PARTIAL (``status`` ``"running"`` or ``"interrupted"``), naming the
    studies not run; none for a complete report (or one without ``status``, as before 0.2)."""
    status = results.get("status", "complete")
    if status == "complete":
        return []
    done, rest = list(results["studies"]), list(results.get("not_run", []))
    why = "interrupted" if status == "interrupted" else "still running or stopped"
    lines = [f"**PARTIAL REPORT ({why})**: {len(done)} of {len(done) + len(rest)} studies ran."]
    if rest:
        lines.append("Not run: " + ", ".join(rest) + ".")
    return lines + [""]


def report_markdown(results: dict[str, Any]) -> str:
    """``report.md``: one row per study (its criterion, whether it is met, how the run ended with its solver
    failures and relaxed re-solves, our numbers and the paper's), the runs' warnings,
    then every study's figures; a report of a run that did not end is marked PARTIAL at the top, with
    the studies not run."""
    rows = []
    for name, e in results["studies"].items():
        if "error" in e:
            rows.append([name, "", "error", "", e["error"], ""])
            continue
        ours = "; ".join(f"{k}={fmt(v)}" for k, v in e["ours"].items())
        rows.append([name, e["criterion"], _met(e), _outcome(e), ours, fmt(e["paper"])])
    lines = ["# lipmpcc reproduction report", "", *_partial_banner(results),
             f"Fast mode: {results['fast']}. Total time: {results['wall_s']:.0f} s.", ""]
    expected = [(n, e["expected_failure"]) for n, e in results["studies"].items() if e.get("expected_failure")]
    lines += [md_table(["study", "criterion", "met", "outcome", "ours", "paper"], rows), ""]
    warned = [(n, w) for n, e in results["studies"].items() for w in e.get("warnings") or []]
    if warned:
        lines += ["Warnings of the runs:", ""] + [f"- {n}: {w}" for n, w in warned] + [""]
    if expected:
        lines += ["Expected failures (the reproduction misses these criteria on purpose):", ""]
        lines += [f"- {n}: {why}" for n, why in expected] + [""]
    for name, e in results["studies"].items():
        for fig in e.get("figures", []):
            lines += [f"### {e['title']}", "", f"![{name}]({fig})", ""]
    return "\n".join(lines)


def write_report(results: dict[str, Any], out: str | Path) -> Path:
    """Write ``results.json`` and ``report.md`` (:func:`report_markdown`) to the folder ``out``, each
    through a file renamed over it; returns the path of ``report.md``."""
    out = Path(out)
    write_text_atomic(out / RESULTS_FILE, json.dumps(results, indent=2, default=str))
    write_text_atomic(out / REPORT_FILE, report_markdown(results))
    return out / REPORT_FILE


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
