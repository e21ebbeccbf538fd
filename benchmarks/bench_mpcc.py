"""MPCC solve time: the fast condensed SQP against the paper's formulation (CasADi Opti + IPOPT).

Both planners run the same closed-loop scenarios on the 3D-LIP (the reduced model), in the
same process. Prints median / p90 solve time per planner, their ratio, and both closed-loop
outcomes side by side.

    python benchmarks/bench_mpcc.py [--steps N]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.loops import lip as lip_loop


def scenarios(steps: int):
    circle = ArcPath.circle(2.0, turns=1.25)
    line = LinePath((0, 0), (40, 0))
    rng = np.random.default_rng(0)
    yield "circle", circle, MpccParams.circle(), [], [], steps
    yield "circle-push", circle, MpccParams.circle(), [], lip_loop.random_pushes(steps * 0.4, rng), steps
    yield "overtake-cartesian", line, MpccParams.overtake_cartesian(), [Obstacle.circle(0.25, path=line, s0=1.5, speed=0.1)], [], 70
    yield "overtake-mpcc", line, MpccParams.overtake_mpcc(), [Obstacle.circle(0.25, path=line, s0=1.5, speed=0.6)], [], 70


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=110, help="steps of the circle runs")
    args = ap.parse_args()
    print(f"{'scenario':20s} {'solver':6s} {'median ms':>9s} {'p90 ms':>8s} {'max ms':>8s} {'fail':>4s} "
          f"{'ec_max':>7s} {'el_rms':>7s} {'ecart':>7s} {'clear':>7s} {'overtook':>8s} {'progress':>8s} {'v_avg':>6s}")
    all_fast, all_ref = [], []
    for name, path, prm, obstacles, pushes, steps in scenarios(args.steps):
        rows = {}
        for solver in ("sqp", "ipopt"):
            planner = MpccPlanner(path, prm.with_(solver=solver))
            t0 = time.perf_counter()
            log = lip_loop.simulate(planner, np.zeros(5), steps, obstacles, pushes)
            wall = time.perf_counter() - t0
            s = lip_loop.summarize(log, obstacles, settle_time=2.0)
            rows[solver] = (log, s)
            st = s["solve_ms"]
            clear = s["min_clearance_m"]
            print(f"{name:20s} {solver:6s} {st['median']:9.3f} {st['p90']:8.3f} {st['max']:8.2f} {s['solver_failures']:4d} "
                  f"{s['contouring_error_max_m']:7.4f} {s['lag_error_rms_m']:7.4f} {s['cartesian_error_max_m']:7.4f} "
                  f"{(clear if clear is not None else float('nan')):7.3f} {str(s['overtook']):>8s} {s['progress_m']:8.2f} "
                  f"{s['v_avg_mean']:6.3f}   (run {wall:.2f} s)")
        tf = rows["sqp"][0].solve_time[1:]  # the first (cold) solve is excluded from both
        ti = rows["ipopt"][0].solve_time[1:]
        all_fast.append(tf)
        all_ref.append(ti)
        print(f"{'':20s} ratio IPOPT/SQP: median {np.median(ti) / np.median(tf):.1f}x, p90 {np.percentile(ti, 90) / np.percentile(tf, 90):.1f}x")
    tf, ti = np.concatenate(all_fast), np.concatenate(all_ref)
    print(f"\nall scenarios: SQP median {1e3 * np.median(tf):.3f} ms (p90 {1e3 * np.percentile(tf, 90):.3f}), "
          f"IPOPT median {1e3 * np.median(ti):.3f} ms (p90 {1e3 * np.percentile(ti, 90):.3f}), "
          f"ratio {np.median(ti) / np.median(tf):.1f}x")


if __name__ == "__main__":
    main()
