"""What the whole-body clearance costs the MPCC: its solve time with the default 0.2 m body disk against the
swept-body disk of a robot (:func:`lipmpcc.studies.clearance.swept_body`, ``digit_like``: 0.432 m), fixed T and
timed, on the same closed-loop overtaking runs on the 3D-LIP with the full body's parameters
(:func:`lipmpcc.studies.path_following.fullbody_params`, the robot's T and COM height), in one process and
interleaved (the machine's load hits both alike). The problem has the same rows either way (only the obstacles'
inflation changes), so what differs is the active set and the SQP's iterations.

Prints the median / p90 solve time and the mean SQP iterations per disk, their ratios, failures and the outcome side by side; the first (cold)
solve of each run is left out.

    python benchmarks/bench_body_clearance.py [--robot digit_like] [--steps 70] [--repeats 2]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense problems: one BLAS thread

import argparse

import numpy as np

from lipmpcc.loops import lip as lip_loop
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.planners.mpcc import MpccPlanner
from lipmpcc.robots import load_robot
from lipmpcc.studies.path_params import body_clearance_params, fullbody_params, timed_fullbody_params, timed_lip_planner


def _run(planner, obstacles, steps: int, timed: bool) -> tuple[np.ndarray, np.ndarray, dict]:
    """One closed-loop run: the solve times [s] and SQP iterations of every solve but the first, and the summary."""
    x0 = np.zeros(5)
    iters: list[int] = []
    solve = planner.solve

    def counted(*a, **kw):
        res = solve(*a, **kw)
        iters.append(int(res.iterations))
        return res

    planner.solve = counted  # type: ignore[method-assign]
    if timed:
        prm = planner.params.mpcc
        log = lip_loop.run_lip_loop(planner, x0, steps, planner.path, obstacles, [], 1, prm.model.H, prm.model.g,
                                    robot_radius=prm.robot_radius, foot_radius=prm.foot_radius, replan_hz=25.0)
    else:
        log = lip_loop.simulate(planner, x0, steps, obstacles, [])
    s = lip_loop.summarize(log, obstacles, settle_time=2.0)
    return np.asarray(log.solve_time[1:], dtype=float), np.asarray(iters[1:], dtype=float), s


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robot", default="digit_like", help="robot whose geometry gives the swept body")
    ap.add_argument("--steps", type=int, default=70, help="steps per run")
    ap.add_argument("--repeats", type=int, default=2, help="interleaved repeats per configuration")
    args = ap.parse_args()
    robot = load_robot(args.robot)
    base = fullbody_params("overtake", "mpcc", robot.standing.com_height, min_lateral_step=robot.min_lateral_step,
                           step_duration=robot.step_duration)
    body = body_clearance_params(base, robot)
    line = LinePath((0, 0), (40, 0))
    cases = [("fixed T, 0.6 m/s", False, 0.6), ("timed, 0.8 m/s", True, 0.8)]
    print(f"{args.robot}: the default disk {base.robot_radius:.3f} m, swept body {body.robot_radius:.3f} m")
    print(f"{'case':18s} {'disk':>6s} {'median ms':>9s} {'p90 ms':>8s} {'iters':>5s} {'fail':>4s} {'clear':>7s} {'overtook':>8s}")
    for name, timed, speed in cases:
        obstacles = [Obstacle.circle(0.25, path=line, s0=1.0, speed=speed)]
        times: dict[float, list[np.ndarray]] = {}
        its: dict[float, list[np.ndarray]] = {}
        for _ in range(args.repeats):
            for prm in (base, body):
                if timed:
                    planner = timed_lip_planner(line, timed_fullbody_params(prm, robot), (0.3, 0.5), within_step=True)
                else:
                    planner = MpccPlanner(line, prm)
                t, n, s = _run(planner, obstacles, args.steps, timed)
                times.setdefault(prm.robot_radius, []).append(t)
                its.setdefault(prm.robot_radius, []).append(n)
                clear = s["min_clearance_m"]
                print(f"{name:18s} {prm.robot_radius:6.3f} {1e3 * np.median(t):9.3f} {1e3 * np.percentile(t, 90):8.3f} "
                      f"{np.mean(n):5.2f} {s['solver_failures']:4d} {(clear if clear is not None else float('nan')):7.3f} {str(s['overtook']):>8s}")
        a, b = (np.concatenate(times[r]) for r in (base.robot_radius, body.robot_radius))
        ia, ib = (np.concatenate(its[r]) for r in (base.robot_radius, body.robot_radius))
        print(f"{name:18s} swept/paper A: median {np.median(b) / np.median(a):.2f}x, p90 "
              f"{np.percentile(b, 90) / np.percentile(a, 90):.2f}x, mean SQP iterations {np.mean(ib) / np.mean(ia):.2f}x "
              "(the iterations do not depend on the machine's load)")


if __name__ == "__main__":
    main()
