"""``lipmpcc reproduce``: run every study and write a report beside the papers' numbers.

Writes, under ``--out``:

- ``<study>/summary.json`` and figures for every run;
- ``results.json``: each study's key results beside the paper's number
  (from ``data/reference/paper_results.json``);
- ``report.md``: the same as tables, with the figures.

``--fast`` shortens every run's horizon (the ``LIPMPCC_FAST`` switch); ``--only`` picks
studies by name prefix. Studies whose robot is the full body are included when the
whole-body controller is built (``lipmpcc._wbc``).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from . import config
from .resources import data_path
from .scenarios import RunOptions, run


@dataclass
class Study:
    """One run of the report: a scenario with options, and what to compare with the paper."""

    name: str
    title: str
    options: dict[str, Any]
    paper: Callable[[dict], Any]  # reference numbers -> the paper's claim for this study
    keys: list[str]  # summary fields to report
    check: Callable[[dict], bool] | None = None  # the acceptance criterion
    criterion: str = ""
    tags: list[str] = field(default_factory=list)


#: paper B Table II: the stone courses (profile I cases, and profiles II–IV with seed 0)
TABLE_II_CASES: dict[str, dict[str, Any]] = {
    "I_L0.2_W+0.15": {"profile": "I", "L": 0.2, "W": 0.15},
    "I_L0.4_W+0.15": {"profile": "I", "L": 0.4, "W": 0.15},
    "I_L0.55_W+0.15": {"profile": "I", "L": 0.55, "W": 0.15},
    "I_L0.2_W-0.15": {"profile": "I", "L": 0.2, "W": -0.15},
    "I_L0.4_W-0.15": {"profile": "I", "L": 0.4, "W": -0.15},
    "I_L0.55_W-0.15": {"profile": "I", "L": 0.55, "W": -0.15},
    "II": {"profile": "II", "seed": 0},
    "III": {"profile": "III", "seed": 0},
    "IV": {"profile": "IV", "seed": 0},
}


def _ref() -> dict:
    with open(data_path("reference", "paper_results.json")) as f:
        return json.load(f)


def studies() -> list[Study]:
    """All studies of the report, reduced models first."""
    out = [
        Study(
            "lip-circle", "Paper A Fig. 5(a,b): circle r = 2 m, LIP", {"scenario": "circle", "planner": "mpcc", "robot": "lip"},
            lambda r: r["paper_a"]["circle"]["claim"],
            ["contouring_error_max_m", "contouring_error_rms_m", "solver_failures", "solve_ms"],
            lambda s: s["contouring_error_max_m"] <= 0.05 and s["solver_failures"] == 0,
            "max abs contouring error after 2 s <= 0.05 m",
        ),
        Study(
            "lip-circle-push", "Paper A Fig. 5(c,d): circle with random pushes, LIP",
            {"scenario": "circle-push", "planner": "mpcc", "robot": "lip", "seed": 0},
            lambda r: r["paper_a"]["circle"]["claim"],
            ["contouring_error_max_m", "push_recovery_s", "solver_failures", "solve_ms"],
            lambda s: s["solver_failures"] == 0 and all(x is not None and x <= 2.0 for x in s["push_recovery_s"]),
            "no planner failure; error back below 0.05 m within 2 s of each push",
        ),
        Study(
            "lip-overtake-cartesian", "Paper A Fig. 6(a-d): Cartesian MPC, obstacle 0.1 m/s, LIP",
            {"scenario": "overtake", "planner": "cartesian", "robot": "lip"},
            lambda r: {"cartesian_error_max_m": r["paper_a"]["overtake_cartesian"]["cartesian_error_max_m"], "overtook": False},
            ["overtook", "cartesian_error_max_m", "min_clearance_m", "v_avg_mean", "solve_ms"],
            lambda s: (not s["overtook"]) and s["cartesian_error_max_m"] <= 0.06 and s["min_clearance_m"] >= 0,
            "trails; Cartesian error <= 0.06 m; min clearance >= 0",
        ),
        Study(
            "lip-overtake-mpcc", "Paper A Fig. 6(e-h): MPCC, obstacle 0.6 m/s, LIP",
            {"scenario": "overtake", "planner": "mpcc", "robot": "lip"},
            lambda r: {"overtook": True, "lag_error": "near zero", "v_avg": "near v_max"},
            ["overtook", "min_clearance_m", "lag_error_rms_m", "contouring_error_max_m", "v_avg_mean", "solve_ms"],
            lambda s: s["overtook"] and s["min_clearance_m"] >= 0 and s["v_avg_mean"] >= 0.9 * 0.3,
            "overtakes; min clearance >= 0; mean v_avg >= 0.9 v_max",
        ),
    ]
    for case, opts in TABLE_II_CASES.items():
        for planner in ("alip-mpc", "alip-qp"):
            out.append(
                Study(
                    f"alip-stones-{case}-{planner}", f"Paper B Table II, profile {case}, {planner}, ALIP",
                    {"scenario": "stones", "planner": planner, "robot": "alip", **opts},
                    lambda r, c=case, p=planner: r["paper_b"]["table_ii_step_rmse_m"][c][p.replace("-", "_")],
                    ["fell", "fall_step", "steps_completed", "step_rmse_m", "stones_violated", "step_duration_min_s",
                     "step_duration_max_s", "solver_failures", "solve_ms"],
                    (lambda s: (not s["fell"]) and s["step_rmse_m"] <= 0.04 and s["solver_failures"] == 0) if planner == "alip-mpc" else None,
                    "no fall, step RMSE <= 0.04 m, no solver failure" if planner == "alip-mpc" else "reported",
                )
            )
    for planner in ("alip-mpc", "alip-qp"):
        out.append(
            Study(
                f"alip-push-{planner}", f"Paper B Fig. 7: push test, {planner}, ALIP",
                {"scenario": "push", "planner": planner, "robot": "alip"},
                lambda r, p=planner: r["paper_b"]["push_test"][p.replace("-", "_")],
                ["fell", "fall_step", "steps_completed", "step_rmse_m", "step_duration_min_s", "step_duration_max_s", "solve_ms"],
                (lambda s: not s["fell"]) if planner == "alip-mpc" else None,
                "survives" if planner == "alip-mpc" else "reported",
            )
        )
    out.append(
        Study(
            "alip-push-alip-mpc-foot", "Paper B Fig. 7: push test, alip-mpc with a foot (CoP within 0.12 x 0.05 m), ALIP",
            {"scenario": "push", "planner": "alip-mpc", "robot": "alip", "cop_range": (0.06, 0.025)},
            lambda r: r["paper_b"]["push_test"]["alip_mpc"],
            ["fell", "fall_step", "steps_completed", "step_rmse_m", "step_duration_min_s", "step_duration_max_s",
             "solver_failures", "solve_ms"],
            lambda s: not s["fell"] and s["solver_failures"] == 0,
            "survives, no solver failure",
        )
    )
    out += fullbody_studies()
    return out


def _wbc_available() -> bool:
    try:
        from . import _wbc  # noqa: F401
    except ImportError:
        return False
    return True


def fullbody_studies() -> list[Study]:
    """The same studies on the full-body ``digit_like`` robot in MuJoCo (the C++ WBC is needed)."""
    fb = {"robot": "digit_like"}
    out = [
        Study(
            "digit-walk", "Walking 10 m+ under the whole-body QP (capture-point footsteps)", {"scenario": "walk", **fb},
            lambda r: "(not in the papers: the low-level loop alone)",
            ["fell", "distance_walked_m", "real_time_factor", "wbc_ms", "qp_failures", "min_base_height_m"],
            lambda s: not s["fell"], "no fall",
        ),
        Study(
            "digit-stand-push", "Standing with four 50 N pushes", {"scenario": "stand", **fb},
            lambda r: "(not in the papers)",
            ["fell", "real_time_factor", "wbc_ms", "qp_failures"], lambda s: not s["fell"], "no fall",
        ),
        Study(
            "digit-circle", "Paper A Fig. 5(a,b): circle r = 2 m, digit_like", {"scenario": "circle", "planner": "mpcc", **fb},
            lambda r: r["paper_a"]["circle"]["claim"],
            ["fell", "contouring_error_max_m", "contouring_error_continuous_max_m", "solver_failures", "real_time_factor", "solve_ms", "wbc_ms"],
            lambda s: (not s["fell"]) and s["contouring_error_max_m"] <= 0.10,
            "no fall; max abs contouring error after 3 s <= 0.10 m",
        ),
        Study(
            "digit-circle-push", "Paper A Fig. 5(c,d): circle with random pushes, digit_like",
            {"scenario": "circle-push", "planner": "mpcc", "seed": 0, **fb},
            lambda r: r["paper_a"]["circle"]["claim"],
            ["fell", "pushes", "contouring_error_max_m", "solver_failures", "real_time_factor"],
            lambda s: not s["fell"], "no fall",
        ),
        Study(
            "digit-overtake-cartesian", "Paper A Fig. 6(a-d): Cartesian MPC, obstacle 0.1 m/s, digit_like",
            {"scenario": "overtake", "planner": "cartesian", **fb},
            lambda r: {"cartesian_error_max_m": r["paper_a"]["overtake_cartesian"]["cartesian_error_max_m"], "overtook": False},
            ["fell", "overtook", "cartesian_error_max_m", "min_clearance_m", "real_time_factor"],
            lambda s: (not s["fell"]) and (not s["overtook"]) and s["cartesian_error_max_m"] <= 0.06 and s["min_clearance_m"] >= 0,
            "no fall; trails; Cartesian error <= 0.06 m; clearance >= 0",
        ),
        Study(
            "digit-overtake-mpcc", "Paper A Fig. 6(e-h): MPCC, obstacle 0.6 m/s, digit_like",
            {"scenario": "overtake", "planner": "mpcc", **fb},
            lambda r: {"overtook": True, "lag_error": "near zero", "v_avg": "near v_max"},
            ["fell", "overtook", "min_clearance_m", "lag_error_rms_m", "v_avg_mean", "real_time_factor"],
            lambda s: (not s["fell"]) and s["overtook"] and s["min_clearance_m"] >= 0,
            "no fall; overtakes; clearance >= 0",
        ),
    ]
    for case, opts in TABLE_II_CASES.items():
        for planner in ("alip-mpc", "alip-qp"):
            out.append(
                Study(
                    f"digit-stones-{case}-{planner}", f"Paper B Table II, profile {case}, {planner}, digit_like",
                    {"scenario": "stones", "planner": planner, **opts, **fb},
                    lambda r, c=case, p=planner: r["paper_b"]["table_ii_step_rmse_m"][c][p.replace("-", "_")],
                    ["fell", "fall_step", "steps_completed", "step_rmse_m", "stones_violated", "step_duration_min_s",
                     "step_duration_max_s", "solver_failures", "real_time_factor"],
                    (lambda s: (not s["fell"]) and s["step_rmse_m"] <= 0.05) if planner == "alip-mpc" else None,
                    "no fall, step RMSE <= 0.05 m" if planner == "alip-mpc" else "reported",
                    tags=["fullbody"],
                )
            )
    for planner in ("alip-mpc", "alip-qp"):
        out.append(
            Study(
                f"digit-push-{planner}", f"Paper B Fig. 7: push test, {planner}, digit_like",
                {"scenario": "push", "planner": planner, **fb},
                lambda r, p=planner: r["paper_b"]["push_test"][p.replace("-", "_")],
                ["fell", "fall_step", "steps_completed", "step_rmse_m", "step_duration_min_s", "step_duration_max_s", "real_time_factor"],
                (lambda s: not s["fell"]) if planner == "alip-mpc" else None,
                "survives" if planner == "alip-mpc" else "reported",
            )
        )
    for st in out:
        st.tags.append("fullbody")
    return out


def _check(st: Study, summary: dict) -> bool | None:
    if st.check is None:
        return None
    try:
        return bool(st.check(summary))
    except (KeyError, TypeError):  # a field the run did not produce: criterion not met
        return False


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return "nan" if math.isnan(v) else f"{v:.4g}"
    if isinstance(v, dict) and "median" in v:
        return f"median {v['median']:.3g} ms, p90 {v['p90']:.3g} ms"
    if isinstance(v, list) and v and isinstance(v[0], float):
        return "[" + ", ".join(f"{x:.2f}" for x in v) + "]"
    return str(v)


def reproduce(out: Path, fast: bool = False, only: str | None = None) -> dict:
    """Run the studies and write the report; returns the results dictionary."""
    if fast:
        config.set_fast_mode(True)
    ref = _ref()
    out.mkdir(parents=True, exist_ok=True)
    results: dict[str, Any] = {"fast": config.fast_mode(), "studies": {}}
    t_all = time.perf_counter()
    from .cli import write_outputs

    wbc = _wbc_available()
    for st in studies():
        if only and not st.name.startswith(only):
            continue
        if "fullbody" in st.tags and not wbc:
            results["studies"][st.name] = {"title": st.title, "error": "skipped: the C++ whole-body controller lipmpcc._wbc is not built"}
            continue
        t0 = time.perf_counter()
        opts = RunOptions(out=str(out / st.name), **st.options)
        try:
            res = run(opts)
        except Exception as exc:  # a study that cannot run is reported, not fatal
            results["studies"][st.name] = {"title": st.title, "error": f"{type(exc).__name__}: {exc}"}
            print(f"[reproduce] {st.name}: ERROR {exc}")
            continue
        write_outputs(res, out / st.name)
        s = res.summary
        entry = {
            "title": st.title,
            "ours": {k: s.get(k) for k in st.keys},
            "paper": st.paper(ref),
            "criterion": st.criterion,
            "meets_criterion": _check(st, s),
            "figures": [f"{st.name}/{n}.png" for n in res.figures],
            "wall_s": time.perf_counter() - t0,
        }
        results["studies"][st.name] = entry
        flag = {True: "ok", False: "MISSED", None: "-"}[entry["meets_criterion"]]
        print(f"[reproduce] {st.name}: {flag} ({entry['wall_s']:.1f} s)")
    results["wall_s"] = time.perf_counter() - t_all
    with open(out / "results.json", "w") as f:
        json.dump(results, f, indent=2, default=str)
    (out / "report.md").write_text(_report(results))
    return results


def _report(results: dict) -> str:
    lines = [
        "# lipmpcc reproduction report",
        "",
        f"Fast mode: {results['fast']}. Total time: {results['wall_s']:.0f} s.",
        "",
        "| study | criterion | met | ours | paper |",
        "|---|---|---|---|---|",
    ]
    for name, e in results["studies"].items():
        if "error" in e:
            lines.append(f"| {name} | | error | {e['error']} | |")
            continue
        ours = "; ".join(f"{k}={_fmt(v)}" for k, v in e["ours"].items())
        met = {True: "yes", False: "**no**", None: "-"}[e["meets_criterion"]]
        lines.append(f"| {name} | {e['criterion']} | {met} | {ours} | {_fmt(e['paper'])} |")
    lines.append("")
    for name, e in results["studies"].items():
        for fig in e.get("figures", []):
            lines += [f"### {e['title']}", "", f"![{name}]({fig})", ""]
    return "\n".join(lines)


def main(ns: argparse.Namespace) -> int:
    """Entry point of ``lipmpcc reproduce``."""
    res = reproduce(Path(ns.out), fast=ns.fast, only=ns.only)
    missed = [n for n, e in res["studies"].items() if e.get("meets_criterion") is False or "error" in e]
    print(f"report: {Path(ns.out) / 'report.md'}; {len(res['studies'])} studies, {len(missed)} missed or failed"
          + (f": {', '.join(missed)}" if missed else ""))
    return 0
