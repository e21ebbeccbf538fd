"""Solve time of the MPCC with step durations as variables: the condensed SQP against IPOPT on the same problem.

Both solvers run the same closed-loop scenarios on the 3D-LIP (N = 5, T ∈ [T_min, T_max]), in the same
process: once planning at each support exchange (the LIP loop), once re-planning at 25 Hz within each step
(a small loop here: the point foot lands at the latest planned time). Prints
the median / p90 solve time per solver, their ratio and the closed-loop outcomes side by side; the first
(cold) solve of each run is left out of both.

    python benchmarks/bench_mpcc_timed.py [--steps N] [--range TMIN TMAX]
"""

from __future__ import annotations

import os

# small dense problems: one BLAS thread (multi-threaded LAPACK on a loaded machine stalls for milliseconds)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import time

import numpy as np

from lipmpcc.loops import lip as lip_loop
from lipmpcc.models.lip import lip_solution
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.mpcc import MpccParams
from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner


def scenarios(steps: int):
    circle = ArcPath.circle(2.0, turns=1.25)
    line = LinePath((0, 0), (40, 0))
    rng = np.random.default_rng(0)
    yield "circle", circle, MpccParams.circle(), [], [], steps
    yield "circle-push", circle, MpccParams.circle(), [], lip_loop.random_pushes(steps * 0.4, rng), steps
    yield "overtake-0.8", line, MpccParams.overtake_mpcc(), [Obstacle.circle(0.25, path=line, s0=1.0, speed=0.8)], [], 45


def within_step_run(path, prm: TimedMpccParams, obstacles, solver: str, t_end: float, rate_hz: float = 25.0):
    """Walk the LIP re-planning at ``rate_hz`` within each step (paper B's loop): the stance foot stays until
    the latest planned touch-down, where the planned foothold and heading take over.

    Returns (solve times [s], executed step durations [s], planner failures, least clearance of the body
    disk to the obstacles at the re-planning ticks [m], ϑ_now at the end [m]).
    """
    pl = TimedMpccPlanner(path, prm.with_(mpcc=prm.mpcc.with_(solver=solver)), within_step=True)
    w, dt = prm.omega, 1.0 / rate_hz
    x, foot, side = np.zeros(5), np.zeros(2), 1  # the first foot placed is the left one
    t, t_td, shift, times, steps, clear = 0.0, 0.0, True, [], [], np.inf
    while t < t_end:
        r = pl.solve(x, side, obstacles, t_now=t, time_since_touchdown=t - t_td, stance_foot=foot, shift=shift)
        times.append(r.solve_time)
        for ob in obstacles:
            clear = min(clear, float(ob.clearance(x[[0, 2]], t, prm.mpcc.robot_radius)[0]))
        h = min(dt, r.remaining)
        c, v, _ = lip_solution(x[[0, 2]], x[[1, 3]], foot, w, h)
        x = np.array([c[0], v[0], c[1], v[1], x[4]])
        t += h
        shift = h >= r.remaining - 1e-12
        if shift:  # touch-down: the planned foot becomes the stance foot
            steps.append(t - t_td)
            foot, x[4], t_td, side = r.footsteps[0, :2].copy(), float(r.footsteps[0, 2]), t, -side
    return times[1:], np.array(steps), pl.failures, clear, r.theta_now


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=60, help="steps of the circle runs")
    ap.add_argument("--range", type=float, nargs=2, default=(0.3, 0.5), metavar=("TMIN", "TMAX"), help="step durations [s]")
    args = ap.parse_args()
    lo, hi = args.range
    print(f"N = 5, T in [{lo}, {hi}] s")
    print(f"{'scenario':14s} {'solver':6s} {'median ms':>9s} {'p90 ms':>8s} {'fail':>4s} {'ec_max':>7s} {'clear':>7s} "
          f"{'overtook':>8s} {'T mean':>6s}")
    fast_all, ref_all = [], []
    for name, path, mprm, obstacles, pushes, steps in scenarios(args.steps):
        prm = TimedMpccParams(mpcc=mprm, T_min=lo, T_max=hi)
        times = {}
        for solver in ("sqp", "ipopt"):
            pl = TimedMpccPlanner(path, prm.with_(mpcc=mprm.with_(solver=solver)))
            t0 = time.perf_counter()
            log = lip_loop.run_lip_loop(pl, np.zeros(5), steps, path, obstacles, pushes,
                                        robot_radius=mprm.robot_radius, foot_radius=mprm.foot_radius)
            wall = time.perf_counter() - t0
            s = lip_loop.summarize(log, obstacles, settle_time=2.0)
            wt, wsteps, wfail, wclear, wtheta = within_step_run(path, prm, obstacles, solver, float(log.t[-1]))
            times[solver] = list(log.solve_time[1:]) + list(wt)
            clear = s["min_clearance_m"]
            ts = np.array(times[solver])
            print(f"{name:14s} {solver:6s} {1e3 * np.median(ts):9.3f} {1e3 * np.percentile(ts, 90):8.3f} "
                  f"{s['solver_failures']:4d} {s['contouring_error_max_m']:7.4f} "
                  f"{(clear if clear is not None else float('nan')):7.3f} {str(s['overtook']):>8s} "
                  f"{np.mean(np.diff(log.t)):6.3f}   (run {wall:.1f} s; within-step run: {len(wt)} solves, "
                  f"median {1e3 * np.median(wt):.3f} ms, steps {np.mean(wsteps):.3f} s, {wfail} failures, clearance "
                  f"{wclear:.3f} m, progress {wtheta:.2f} m)")
        tf, ti = np.array(times["sqp"]), np.array(times["ipopt"])
        fast_all.append(tf)
        ref_all.append(ti)
        print(f"{'':14s} ratio IPOPT/SQP: median {np.median(ti) / np.median(tf):.1f}x")
    tf, ti = np.concatenate(fast_all), np.concatenate(ref_all)
    print(f"\nall scenarios ({len(tf)} solves each, at exchanges and mid-step): SQP median {1e3 * np.median(tf):.3f} ms "
          f"(p90 {1e3 * np.percentile(tf, 90):.3f}), IPOPT median {1e3 * np.median(ti):.3f} ms "
          f"(p90 {1e3 * np.percentile(ti, 90):.3f}), ratio {np.median(ti) / np.median(tf):.1f}x")


if __name__ == "__main__":
    main()
