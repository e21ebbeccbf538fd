"""Benchmark: ``lipmpcc sweep`` throughput (cases per minute) with 1 and with 2 local workers, and the
sweep's overhead per case against running the same cases one after the other in this process through
``lipmpcc.studies.run`` (what ``lipmpcc run`` does, without writing figures).

The default campaign: paper A's pushes on the circle on the LIP (``circle-push``, ``--steps`` steps),
``push_scale`` x ``seed``, MPCC and Cartesian. ``--study push`` uses paper B's push test on the ALIP;
``--study digit-overtake`` paper A's overtaking on ``digit_like`` in MuJoCo (``--duration`` s simulated per
case, over obstacle speeds). The pool's start (the forkserver importing the studies) is
timed apart; the machine's load average is printed beside the numbers: on a shared machine they move with it.

Two references: the same cases one after the other in this process, after a warm-up case (the strictest:
no process start, solvers already built), and ``--cli N``: N of the cases each run as its own ``lipmpcc run``
process, as a user without ``sweep`` would (process start, imports and solver set-up paid per case).

    PYTHONPATH=python python3 benchmarks/bench_sweep.py [--cases 16] [--steps 40] [--study circle-push|push|digit-overtake]
                                                        [--duration 4] [--cli 4] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time

from lipmpcc import studies
from lipmpcc.sweep import parse_spec, run_sweep
from lipmpcc.sweep.runner import _kill, local_pool
from lipmpcc.sweep.worker import case_options, push_extra


def spec_for(study: str, n_cases: int, steps: int, duration: float = 4.0) -> dict:
    """A campaign of about ``n_cases`` cases: two planners x scales x seeds."""
    per = max(1, n_cases // 4)
    if study == "digit-overtake":
        return {"name": "bench digit overtake", "study": "overtake", "robot": "digit_like", "planners": ["mpcc", "cartesian"],
                "options": {"duration": duration}, "axes": {"obstacle_speed": {"range": [0.0, 0.5], "n": 2 * per}}}
    if study == "push":
        planners, robot = ["alip-mpc", "alip-qp"], "alip"
    else:
        planners, robot = ["mpcc", "cartesian"], "lip"
    return {"name": f"bench {study}", "study": study, "robot": robot, "planners": planners,
            "options": {"steps": steps},
            "axes": {"push_scale": {"values": [0.5, 1.0]}} if study == "push" else
            {"push_scale": {"values": [0.5, 1.0]}, "seed": {"range": [0, per - 1], "n": per}}}


def in_process(spec) -> float:
    """Seconds to run every case in this process, one after the other (after one warm-up case)."""
    import matplotlib.pyplot as plt

    from dataclasses import replace

    cases = spec.cases()
    studies.run(replace(case_options(cases[0], False), extra=push_extra(cases[0], None)))
    plt.close("all")
    t0 = time.perf_counter()
    for c in cases:
        studies.run(replace(case_options(c, False), extra=push_extra(c, None)))
        plt.close("all")
    return time.perf_counter() - t0


def via_cli(spec, n: int) -> float:
    """Seconds per case when each of the first ``n`` cases runs as its own ``lipmpcc run`` process."""
    import subprocess
    import sys

    from lipmpcc.studies.options import option_flag

    cases = [c for c in spec.cases() if "push_scale" not in c["params"]][:n]  # push_scale has no CLI form
    if not cases:
        raise SystemExit("--cli: these cases scale the study's pushes (push_scale), which `lipmpcc run` cannot")
    t0 = time.perf_counter()
    for c in cases:
        opts = case_options(c, False)
        cmd = [sys.executable, "-m", "lipmpcc", "run", opts.scenario, "--robot", opts.robot, "--planner", opts.planner]
        for k, v in c["options"].items():
            if k != "seed" or v:
                cmd += [option_flag(k), str(v)]
        with tempfile.TemporaryDirectory() as out:
            subprocess.run(cmd + ["--out", f"{out}/run"], check=True, stdout=subprocess.DEVNULL)
    return (time.perf_counter() - t0) / len(cases)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=16)
    ap.add_argument("--steps", type=int, default=40)
    ap.add_argument("--study", default="circle-push", choices=("circle-push", "push", "digit-overtake"))
    ap.add_argument("--duration", type=float, default=4.0, help="digit-overtake: seconds simulated per case")
    ap.add_argument("--cli", type=int, default=0, help="also time N cases as separate `lipmpcc run` processes")
    ap.add_argument("--json", help="also save the figures to this JSON file")
    args = ap.parse_args()
    record: dict = {"study": args.study, "steps": args.steps}
    spec = parse_spec(spec_for(args.study, args.cases, args.steps, args.duration))
    n = len(spec.cases())
    t0 = time.perf_counter()
    _kill(local_pool(2))
    print(f"{n} cases of {args.study}, {args.steps} steps; load average {os.getloadavg()[0]:.1f}; "
          f"pool start (forkserver importing the studies) {time.perf_counter() - t0:.1f} s")
    record.update(cases=n, pool_start_s=time.perf_counter() - t0)
    alone = in_process(spec)
    record["in_process_cases_per_min"] = 60 * n / alone
    print(f"in this process, one after the other: {alone:.1f} s = {60 * n / alone:.1f} cases/min")
    if args.cli:
        per_case = via_cli(spec, args.cli)
        record["cli_cases_per_min"] = 60 / per_case
        print(f"each case as its own `lipmpcc run` ({args.cli} cases): {per_case:.1f} s/case = {60 / per_case:.1f} cases/min")
    for w in (1, 2):
        with tempfile.TemporaryDirectory() as out:
            st = run_sweep(spec, out, workers=w, progress=False)
        over = (st.wall_s - alone) / n if w == 1 else float("nan")
        print(f"sweep, {w} worker(s): {st.wall_s:.1f} s = {st.cases_per_minute:.1f} cases/min"
              + (f" (overhead {over:+.2f} s/case = {100 * (st.wall_s / alone - 1):+.0f} %)" if w == 1 else
                 f" (x{alone / st.wall_s:.2f} the single process)")
              + f"; load average {os.getloadavg()[0]:.1f}")
        record[f"workers_{w}_cases_per_min"] = st.cases_per_minute
        record[f"workers_{w}_load_average"] = os.getloadavg()[0]
    if args.json:
        with open(args.json, "w") as f:
            json.dump(record, f, indent=2)


if __name__ == "__main__":
    main()
