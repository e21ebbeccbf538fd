"""Benchmark: the whole-body QP with proxsuite and with DAQP, side by side (``WbcParams.qp_solver``).

For digit_like and — when present — the reference Digit v3 (``../shared/models/digit-v3/digit-v3.xml``):

1. A capture-point walk at 0.6 m/s (MuJoCo 2 kHz, WBC 400 Hz) is run once with each solver in the
   closed loop: fall or not, QP failures.
2. The states and references of the proxsuite walk are recorded, and every recorded tick is solved again
   by one fresh controller per solver, in order (so that each warm-starts as in the loop), the two
   solvers interleaved tick by tick (the same machine load for both). Reported per solver: the wall time
   of the Python call ``WholeBodyController.solve`` (checks and conversions included), the C++ tick
   (``WbcOutput.tick_time_us``: dynamics terms, QP assembly, QP solve, efforts) and the QP solve alone
   (``solve_time_us``), median and p90 [µs]; the iterations; the largest difference of the motor
   efforts between the two solvers [N m], and of each solver's efforts from those of a tight cold solve
   (proxsuite, ``qp_eps_abs = 1e-10``, reset before every tick; untimed) [N m].

Usage: ``python benchmarks/bench_wbc_solvers.py [--walk-time S] [--rounds N] [--json PATH] [--digit-v3 PATH]``;
``LIPMPCC_FAST=1`` shortens the walk. Timings depend on the machine's load (run it on an idle machine
for the figures of docs/benchmarks.md; under load, compare the two columns of the same run only).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

from lipmpcc.config import horizon
from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.control.wbc_types import QP_SOLVERS, WbcParams, WbcReference
from lipmpcc.loops.fullbody.loop import FullBodyLoop, LoopParams
from lipmpcc.planners.capture_point import CapturePointPlanner
from lipmpcc.robots import load_robot

SHARED_DIGIT = Path(__file__).resolve().parents[2] / "shared" / "models" / "digit-v3" / "digit-v3.xml"


def _snapshot(ref) -> WbcReference:
    """A copy of the tick's reference (a ``WbcReference``, or the loop's ``PackedWbcReference``) as a ``WbcReference``."""
    fields = {f: np.array(getattr(ref, f), dtype=float) for f in WbcReference.__dataclass_fields__ if f != "contact"}
    return WbcReference(contact=tuple(ref.contact), **fields)


def walk(robot, solver: str, duration: float, record: bool) -> dict:
    """The closed-loop walk with ``solver``; with ``record``, every tick's (q, v, reference)."""
    params = dataclasses.replace(WbcParams.for_robot(robot), qp_solver=solver)
    wbc = WholeBodyController(robot, params, threaded=False)
    recorded: list = []
    if record:
        solve = wbc.solve_tick  # the loop's call

        def recording(q, v, ref):
            recorded.append((np.array(q), np.array(v), _snapshot(ref)))
            return solve(q, v, ref)

        wbc.solve_tick = recording
    loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.6), wbc=wbc, params=LoopParams(helper_thread=False))
    res = loop.run(duration=duration)
    return dict(fell=bool(res.fell), fall_time=res.fall_time, qp_failures=int(res.qp_failures),
                touchdowns=len(res.touchdowns), recorded=recorded)


def replay(robot, recorded: list, rounds: int) -> dict:
    """Every recorded tick through one controller per solver, interleaved; ``rounds`` passes (best median)."""
    base = WbcParams.for_robot(robot)
    stats: dict = {}
    for r in range(rounds):
        wbcs = {s: WholeBodyController(robot, dataclasses.replace(base, qp_solver=s), threaded=False) for s in QP_SOLVERS}
        tick = {s: [] for s in QP_SOLVERS}
        qp = {s: [] for s in QP_SOLVERS}
        its = {s: [] for s in QP_SOLVERS}
        call = {s: [] for s in QP_SOLVERS}
        exact = WholeBodyController(robot, dataclasses.replace(base, qp_eps_abs=1e-10), threaded=False)
        dtau = 0.0
        dexact = {s: 0.0 for s in QP_SOLVERS}
        for q, v, ref in recorded:
            outs = {}
            for s in (QP_SOLVERS if r % 2 == 0 else QP_SOLVERS[::-1]):
                t0 = time.perf_counter()
                out = wbcs[s].solve(q, v, ref)
                call[s].append((time.perf_counter() - t0) * 1e6)
                outs[s] = out
                tick[s].append(out.tick_time_us)
                qp[s].append(out.solve_time_us)
                its[s].append(out.iterations)
            if all(o.status == "solved" for o in outs.values()):
                dtau = max(dtau, float(np.max(np.abs(outs["daqp"].tau - outs["proxsuite"].tau))))
            if r == 0:  # accuracy: once
                exact.reset()
                e = exact.solve(q, v, ref)
                if e.status == "solved":
                    for s in QP_SOLVERS:
                        if outs[s].status == "solved":
                            dexact[s] = max(dexact[s], float(np.max(np.abs(outs[s].tau - e.tau))))
        for s in QP_SOLVERS:
            row = dict(tick_median_us=float(np.median(tick[s])), tick_p90_us=float(np.percentile(tick[s], 90)),
                       qp_median_us=float(np.median(qp[s])), qp_p90_us=float(np.percentile(qp[s], 90)),
                       call_median_us=float(np.median(call[s])), call_p90_us=float(np.percentile(call[s], 90)),
                       iterations_median=float(np.median(its[s])), iterations_max=int(np.max(its[s])),
                       qp_failures=int(wbcs[s].qp_failures), n=len(tick[s]))
            row["max_abs_tau_error_nm"] = dexact[s] if r == 0 else stats[s]["max_abs_tau_error_nm"]
            if s not in stats or row["tick_median_us"] < stats[s]["tick_median_us"]:
                stats[s] = row
        stats["max_abs_tau_difference_nm"] = max(stats.get("max_abs_tau_difference_nm", 0.0), dtau)
    return stats


def bench_robot(robot, walk_time: float, rounds: int) -> dict:
    out: dict = {"walks": {}}
    recorded = None
    for s in ("proxsuite", "daqp"):
        w = walk(robot, s, walk_time, record=(s == "proxsuite"))
        if s == "proxsuite":
            recorded = w["recorded"]
        out["walks"][s] = {k: v for k, v in w.items() if k != "recorded"}
    out["replay"] = replay(robot, recorded, rounds)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--walk-time", type=float, default=float(horizon(4.0, 1.5)), help="[s] of each walk")
    parser.add_argument("--rounds", type=int, default=int(horizon(3, 1)), help="replay passes (best median)")
    parser.add_argument("--json", type=Path, default=None, help="also write the figures to this JSON file")
    parser.add_argument("--digit-v3", type=Path, default=SHARED_DIGIT, help="the Digit v3 MJCF (skipped if absent)")
    args = parser.parse_args()

    robots = {"digit_like": load_robot("digit_like")}
    if args.digit_v3.exists():
        robots["digit_v3"] = load_robot(args.digit_v3)
    results: dict = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, {platform.python_implementation()} "
        f"{platform.python_version()}, load average {os.getloadavg()[0]:.1f} at start",
    }
    for name, robot in robots.items():
        results[name] = bench_robot(robot, args.walk_time, args.rounds)

    print("Whole-body QP: proxsuite vs DAQP (same recorded walking ticks, interleaved)")
    print(f"  machine: {results['machine']}")
    for name in robots:
        r = results[name]
        print(f"  {name}: walk {args.walk_time:.1f} s at 0.6 m/s")
        for s in ("proxsuite", "daqp"):
            w = r["walks"][s]
            state = f"FELL at {w['fall_time']:.2f} s" if w["fell"] else "no fall"
            print(f"    closed loop, {s:9s}: {state}, {w['qp_failures']} QP failures, {w['touchdowns']} touch-downs")
        print(f"    {'replayed ticks':24s} {'proxsuite':>22s} {'daqp':>22s}")
        rp = r["replay"]
        for key, label in (("call", "Python solve() [us]"), ("tick", "C++ tick [us]"), ("qp", "QP solve [us]")):
            cells = [f"{rp[s][key + '_median_us']:8.1f} (p90 {rp[s][key + '_p90_us']:6.1f})" for s in ("proxsuite", "daqp")]
            print(f"    {label:24s} {cells[0]:>22s} {cells[1]:>22s}")
        cells = [f"{rp[s]['iterations_median']:.0f} (max {rp[s]['iterations_max']})" for s in ("proxsuite", "daqp")]
        print(f"    {'iterations, median':24s} {cells[0]:>22s} {cells[1]:>22s}")
        print(f"    {'QP failures':24s} {rp['proxsuite']['qp_failures']:>22d} {rp['daqp']['qp_failures']:>22d}")
        cells = [f"{rp[s]['max_abs_tau_error_nm']:.2e}" for s in ("proxsuite", "daqp")]
        print(f"    {'max |u - u_tight| [N m]':24s} {cells[0]:>22s} {cells[1]:>22s}")
        print(f"    ticks: {rp['proxsuite']['n']}; largest |u_daqp - u_proxsuite|: {rp['max_abs_tau_difference_nm']:.2e} N m")
    if args.json:
        args.json.write_text(json.dumps(results, indent=2))


if __name__ == "__main__":
    main()
