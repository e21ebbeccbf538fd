"""Benchmark: the Menagerie humanoids (Unitree G1, Booster T1) with the layouts ``lipmpcc robot init``
writes, unedited, through the issue-26 runs: ``stand``, ``walk`` (20 s at 0.5 m/s), ``circle``,
``overtake`` (0.3 m/s obstacle) and ``stones --profile I``. Prints one row per run: outcome, fall
time and reason, steps, distance, contouring error, step RMSE, RTF and WBC tick.

The models are read from ``../shared/models`` (or ``--models DIR``); each is linked into a scratch
folder beside its generated layout (the shared folder stays untouched).

    PYTHONPATH=python python3 benchmarks/bench_humanoids.py [--robots g1 t1] [--scenarios walk stand]
        [--duration 20] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from lipmpcc.studies.robot_check import init_robot

REPO = Path(__file__).resolve().parents[1]
MODELS = {"g1": ("unitree-g1", "g1.xml"), "t1": ("booster-t1", "t1.xml")}
RUNS = {
    "stand": ["stand"],
    "walk": ["walk", "--speed", "0.5"],
    "circle": ["circle"],
    "overtake": ["overtake", "--obstacle-speed", "0.3"],
    "stones": ["stones", "--profile", "I"],
}
FIELDS = ("outcome", "fell", "fall_time_s", "fall_reason", "steps", "steps_completed", "distance_walked_m",
          "contouring_error_rms_m", "step_rmse_m", "real_time_factor", "qp_failures")


def _row(summary: dict) -> dict:
    row = {k: summary.get(k) for k in FIELDS if k in summary}
    row["wbc_ms_median"] = (summary.get("wbc_ms") or {}).get("median")
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--models", default=str(REPO.parent / "shared" / "models"))
    ap.add_argument("--robots", nargs="+", default=list(MODELS))
    ap.add_argument("--scenarios", nargs="+", default=list(RUNS))
    ap.add_argument("--duration", type=float, default=20.0, help="walk's simulated time [s]")
    ap.add_argument("--json", help="write the rows to this file")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for robot in args.robots:
            folder, name = MODELS[robot]
            src = Path(args.models) / folder
            work = Path(tmp) / robot
            work.mkdir()
            for item in src.iterdir():
                (work / item.name).symlink_to(item)
            print(init_robot(work / name).splitlines()[0], flush=True)
            for scenario in args.scenarios:
                out = Path(tmp) / f"{robot}-{scenario}"
                argv = RUNS[scenario] + ["--robot", str(work / name), "--out", str(out)]
                if scenario == "walk":
                    argv += ["--duration", str(args.duration)]
                proc = subprocess.run([sys.executable, "-m", "lipmpcc", "run", *argv], capture_output=True, text=True)
                summary_file = out / "summary.json"
                row = {"robot": robot, "scenario": scenario, "exit": proc.returncode}
                if summary_file.is_file():
                    row.update(_row(json.loads(summary_file.read_text())))
                else:
                    row["error"] = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else "no summary"
                rows.append(row)
                print(json.dumps(row), flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
