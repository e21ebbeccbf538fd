"""Paper B on a full-body model: the nine Table II courses and the push test, each with the ALIP-MPC (and
the push test with the ALIP-QP), as ``lipmpcc reproduce --robot MODEL.xml`` runs them (the same studies:
:func:`lipmpcc.reproduce.full_body_studies`), printed as one table beside the paper's numbers:

    course | planner | completed | step RMSE | paper | failed solves | relaxed solves | wall [s]

Default model: Digit v3 (``$LIPMPCC_DIGIT_V3``, else ``../shared/models/digit-v3/digit-v3.xml`` beside the
repository); ``digit_like`` with ``--model digit_like``. The runs are full length (32 stones, 24 steps for the
push test) and slow on a full body (about 1–3 min each on a loaded 2-core machine); ``--only`` picks studies by
the end of their name (``--only stones-IV-alip-mpc push-alip-mpc``).

    PYTHONPATH=python python3 benchmarks/bench_paper_b_model.py [--model PATH.xml] [--only SUFFIX ...]
        [--qp] [--steps] [--calls K0 K1] [--json out.json]

``--steps`` also prints each run's per-step log (:func:`step_log`): the touch-down time error (actual −
planned duration), the error of the planner's predicted initial DCM of the next step against the one measured
at its touch-down, the foothold's offset from its stone's centre, and the planner calls of the step that
were relaxed or fell back. It is how Digit v3's falls were diagnosed (docs/design.md). ``--calls K0 K1`` also prints every planner call of
footsteps K0..K1 (:func:`call_log`): the initial DCM z⁰, the planned durations, the planned footholds against their
stones' centres, the planned centre-of-pressure offset and the status — how the push test's fall was traced
(docs/design.md, "Digit v3's push test").
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from lipmpcc.report.values import length, paper_text
from lipmpcc.reproduce import ROBOT_ENV, Study, full_body_studies
from lipmpcc.studies import RunOptions, run, run_outcome

DEFAULT_MODEL = Path(__file__).resolve().parents[2] / "shared" / "models" / "digit-v3" / "digit-v3.xml"


def paper_b_studies(model: str, qp: bool = False, only: list[str] | None = None) -> list[Study]:
    """Paper B's full-body studies on ``model``: Table II with the ALIP-MPC (and the ALIP-QP with ``qp``), the
    push test with both planners; ``only``: those whose name ends with one of these."""
    out = []
    for st in full_body_studies(model):
        if st.paper_id != "B":
            continue
        if st.item == "Table II" and st.options["planner"] == "alip-qp" and not qp:
            continue
        if only and not any(st.name.endswith(s) for s in only):
            continue
        out.append(st)
    return out


def step_log(fb: Any) -> list[str]:
    """Per footstep of a full-body stones run (a :class:`~lipmpcc.studies.stepping_stones.FullBodyStonesRun`):
    side, touch-down time error [ms], next initial DCM predicted − measured [mm], foothold − stone centre [mm],
    planner calls, relaxed and fallback calls."""
    src, course = fb.source, fb.course
    tds = fb.result.touchdowns[: len(course)]
    first: dict[int, Any] = {}
    last: dict[int, Any] = {}
    calls: dict[int, list[str]] = {}
    for r in src.records:
        first.setdefault(r.step_index, r)
        last[r.step_index] = r
        calls.setdefault(r.step_index, []).append(r.status)
    lam = float(src.alip.lam)
    lines = ["step side dt_td[ms] dz_next[mm] foot-stone[mm] calls relaxed fallback"]
    for k, td in enumerate(tds):
        r, r1 = last.get(k), first.get(k + 1)
        dt = 1000 * (td.duration - r.result.step_duration) if r is not None and r.result is not None else math.nan
        dz = np.full(2, math.nan)
        if r is not None and r.result is not None and r1 is not None:
            dz = 1000 * ((r1.dcm - r1.stance) * math.exp(-lam * r1.time_since_touchdown) - np.asarray(r.result.z[0]))
        off = 1000 * (np.asarray(td.pos[:2]) - np.asarray(course[k].center))
        st = calls.get(k, [])
        lines.append(f"{k:3d} {td.side[0]} {dt:+6.0f} ({dz[0]:+5.0f},{dz[1]:+5.0f}) ({off[0]:+5.0f},{off[1]:+5.0f}) "
                     f"{len(st):3d} {sum(x.startswith('relaxed') for x in st):3d} "
                     f"{sum(x.startswith(('fallback', 'failed')) for x in st):3d}")
    return lines


def call_log(fb: Any, k0: int, k1: int) -> list[str]:
    """Every planner call of footsteps ``k0``..``k1`` of a full-body stones run: time [s], time since the
    touch-down t̃ [s], the initial DCM z⁰ = (ξ − p) e^{−λt̃} [mm], the planned durations [s], each planned foothold
    − its stone's centre [mm], the planned CoP offset [mm] and the status."""
    course = fb.course
    lines = ["step t[s] t~[s] z0[mm] durations[s] | foothold-stone[mm] ... | cop[mm] status"]
    for r in fb.source.records:
        k = r.step_index
        if not k0 <= k <= k1:
            continue
        res = r.result
        if res is None:
            lines.append(f"{k:3d} {r.t:6.3f} {r.time_since_touchdown:5.3f} (no plan) {r.status}")
            continue
        z0 = 1000 * np.asarray(res.z0)
        offs = " ".join(f"({1000 * (f[0] - course[k + j].center[0]):+4.0f},{1000 * (f[1] - course[k + j].center[1]):+4.0f})"
                        for j, f in enumerate(res.footholds) if k + j < len(course))
        cop = 1000 * np.asarray(res.cop_offset)
        durs = " ".join(f"{d:.2f}" for d in res.durations)
        lines.append(f"{k:3d} {r.t:6.3f} {r.time_since_touchdown:5.3f} ({z0[0]:+4.0f},{z0[1]:+4.0f}) {durs} | {offs} | "
                     f"({cop[0]:+3.0f},{cop[1]:+3.0f}) {r.status[:24]}")
    return lines


def run_study(st: Study, steps: bool = False, calls: tuple[int, int] | None = None) -> dict[str, Any]:
    """One study: its row of the table (and the summary's counts); with ``steps`` its per-step log printed, with
    ``calls`` = (k0, k1) the planner calls of footsteps k0..k1 (:func:`call_log`)."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        res = run(RunOptions(out=tmp, **st.options))
    s = res.summary
    if steps and hasattr(res.log, "source"):
        print("\n".join(f"    {x}" for x in [st.name] + step_log(res.log)), flush=True)
    if calls is not None and hasattr(res.log, "source"):
        print("\n".join(f"    {x}" for x in call_log(res.log, *calls)), flush=True)
    course = st.placement()["course"] or "push test"
    return {"study": st.name, "course": course, "planner": st.options["planner"], "outcome": run_outcome(s),
            "fall_step": s.get("fall_step"), "step_rmse_m": s.get("step_rmse_m"), "paper": st.paper(),
            "solver_failures": s.get("solver_failures"), "relaxed_solves": s.get("relaxed_solves"),
            "stones_violated": s.get("stones_violated"), "wall_s": time.perf_counter() - t0}


def _row(r: dict[str, Any]) -> str:
    done = "yes" if r["outcome"] == "completed" else (f"fell at stone {r['fall_step']}" if r["outcome"] == "fell" else r["outcome"])
    return (f"| {r['course']} | {r['planner']} | {done} | {length(r['step_rmse_m'])} | {paper_text(r['paper'])} | "
            f"{r['solver_failures']} | {r['relaxed_solves']} | {r['wall_s']:.0f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    env = os.environ.get(ROBOT_ENV, "").strip()
    parser.add_argument("--model", default=env or str(DEFAULT_MODEL), help="a MODEL.xml, or digit_like")
    parser.add_argument("--only", nargs="*", help="studies whose name ends with one of these")
    parser.add_argument("--qp", action="store_true", help="also the ALIP-QP on the Table II courses")
    parser.add_argument("--steps", action="store_true", help="also print each run's per-step log")
    parser.add_argument("--calls", nargs=2, type=int, metavar=("K0", "K1"),
                        help="also print every planner call of footsteps K0..K1")
    parser.add_argument("--json", type=Path, help="also write the rows to this JSON file")
    args = parser.parse_args()
    if args.model != "digit_like" and not Path(args.model).is_file():
        raise SystemExit(f"model not found: {args.model} (pass --model PATH.xml or set {ROBOT_ENV})")
    print(f"paper B on {args.model}")
    print("| course | planner | completed | step RMSE | paper | failed solves | relaxed solves | wall [s] |")
    print("|---|---|---|---|---|---|---|---|")
    rows = []
    for st in paper_b_studies(args.model, args.qp, args.only):
        rows.append(run_study(st, args.steps, tuple(args.calls) if args.calls else None))
        print(_row(rows[-1]), flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=str))


if __name__ == "__main__":
    main()
