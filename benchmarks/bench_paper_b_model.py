"""Paper B on a full-body model: the nine Table II courses and the push test, each with the ALIP-MPC (and
the push test with the ALIP-QP), as ``lipmpcc reproduce --robot MODEL.xml`` runs them (the same studies:
:func:`lipmpcc.reproduce.full_body_studies`), printed as one table beside the paper's numbers:

    course | planner | completed | step RMSE | paper | failed solves | relaxed solves | wall [s]

Default model: Digit v3 (``$LIPMPCC_DIGIT_V3``, else ``../shared/models/digit-v3/digit-v3.xml`` beside the
repository); ``digit_like`` with ``--model digit_like``. The runs are full length (32 stones, 24 steps for the
push test) and slow on a full body (about 1–3 min each on a loaded 2-core machine); ``--only`` picks studies by
the end of their name (``--only stones-IV-alip-mpc push-alip-mpc``).

    PYTHONPATH=python python3 benchmarks/bench_paper_b_model.py [--model PATH.xml] [--only SUFFIX ...]
        [--qp] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path
from typing import Any

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


def run_study(st: Study) -> dict[str, Any]:
    """One study: its row of the table (and the summary's counts)."""
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        s = run(RunOptions(out=tmp, **st.options)).summary
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
    parser.add_argument("--json", type=Path, help="also write the rows to this JSON file")
    args = parser.parse_args()
    if args.model != "digit_like" and not Path(args.model).is_file():
        raise SystemExit(f"model not found: {args.model} (pass --model PATH.xml or set {ROBOT_ENV})")
    print(f"paper B on {args.model}")
    print("| course | planner | completed | step RMSE | paper | failed solves | relaxed solves | wall [s] |")
    print("|---|---|---|---|---|---|---|---|")
    rows = []
    for st in paper_b_studies(args.model, args.qp, args.only):
        rows.append(run_study(st))
        print(_row(rows[-1]), flush=True)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=str))


if __name__ == "__main__":
    main()
