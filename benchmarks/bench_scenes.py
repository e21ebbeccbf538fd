"""MPCC solve time on issue 31's random scenes: the fast condensed SQP beside IPOPT, in the same run.

Each seeded scene (:func:`lipmpcc.course.scenes.make_scene`: a ~19 m path, 1–3 obstacles ahead, oncoming,
crossing or static) is walked on the 3D-LIP twice, once per solver, with the same planner and weights
(the liveness rules of :mod:`lipmpcc.planners.liveness` included: their restarts count in the solve times).
Prints, per scene and solver, the solve time median / p90 / max [ms] and how the run ended, then the
median and p90 over all solves of each solver and their ratio.

    python benchmarks/bench_scenes.py [--seeds 0 5] [--planner fixed|timed] [--weights follow-path|overtake]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lipmpcc.course.scenes import judge, make_scene
from lipmpcc.loops import lip as lip_loop
from lipmpcc.obstacles import obstacle_from_dict
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.studies.path_params import timed_lip_planner
from lipmpcc.studies.path_scenarios import follow_path_steps


def _planner(path, solver: str, planner: str, weights: str):
    prm = (MpccParams.circle if weights == "follow-path" else MpccParams.overtake_mpcc)(solver=solver)
    if planner == "fixed":
        return MpccPlanner(path, prm)
    return timed_lip_planner(path, prm, (0.3, 0.5))


def _start(path) -> np.ndarray:
    """The LIP at rest on the path's start, facing along it: [x, ẋ, y, ẏ, heading]."""
    p0 = path.position(0.0)
    return np.array([p0[0], 0.0, p0[1], 0.0, float(path.slope(0.0))])


def _run(scene, solver: str, planner: str, weights: str) -> tuple[np.ndarray, dict, float]:
    obs = [obstacle_from_dict(it, scene.path) for it in scene.obstacles]
    pl = _planner(scene.path, solver, planner, weights)
    prm = pl.params if planner == "fixed" else pl.params.mpcc
    t0 = time.perf_counter()
    log = lip_loop.run_lip_loop(pl, _start(scene.path), follow_path_steps(scene.length), scene.path, obs,
                                [], 1, prm.model.H, prm.model.g, robot_radius=prm.robot_radius,
                                foot_radius=prm.foot_radius)
    wall = time.perf_counter() - t0
    return np.asarray(log.solve_time[1:]), lip_loop.summarize(log, obs), wall  # the first (cold) solve left out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs=2, default=(0, 3), metavar=("FIRST", "STOP"),
                    help="scene seeds FIRST..STOP-1 (default 0 3)")
    ap.add_argument("--planner", choices=("fixed", "timed"), default="fixed")
    ap.add_argument("--weights", choices=("follow-path", "overtake"), default="follow-path")
    args = ap.parse_args()
    print(f"{'seed':>4s} {'kinds':28s} {'solver':6s} {'median ms':>9s} {'p90 ms':>8s} {'max ms':>8s} "
          f"{'progress':>8s} {'clear':>6s}  outcome")
    times: dict[str, list[np.ndarray]] = {"sqp": [], "ipopt": []}
    for seed in range(*args.seeds):
        scene = make_scene(seed)
        for solver in ("sqp", "ipopt"):
            st, s, wall = _run(scene, solver, args.planner, args.weights)
            times[solver].append(st)
            ok, why = judge(s, scene)
            clear = s["min_clearance_m"]
            print(f"{seed:4d} {','.join(scene.kinds):28s} {solver:6s} {1e3 * np.median(st):9.2f} "
                  f"{1e3 * np.percentile(st, 90):8.2f} {1e3 * st.max():8.1f} {s['progress_m']:8.2f} "
                  f"{(clear if clear is not None else float('nan')):6.3f}  {why}  (run {wall:.0f} s)")
    tf, ti = np.concatenate(times["sqp"]), np.concatenate(times["ipopt"])
    print(f"\nall scenes ({args.planner}, {args.weights}): SQP median {1e3 * np.median(tf):.2f} ms "
          f"(p90 {1e3 * np.percentile(tf, 90):.2f}), IPOPT median {1e3 * np.median(ti):.2f} ms "
          f"(p90 {1e3 * np.percentile(ti, 90):.2f}); ratio median {np.median(ti) / np.median(tf):.1f}x, "
          f"p90 {np.percentile(ti, 90) / np.percentile(tf, 90):.1f}x")


if __name__ == "__main__":
    main()
