"""MPCC solve time with many obstacles within reach: compiled against interpreted CasADi functions, and IPOPT.

The MPCC has a slot per obstacle within reach (1, 2, then 4, 8, … slots). Its derivative functions grow
with the slots: the fixed-T MPCC's with 8 slots (19 000 instructions) and the timed MPCC's with 2 or more
(17 600 – 53 000) are above ``MAX_JIT_INSTRUCTIONS``; before the background compile they ran
interpreted for the whole run. Now they are compiled in a background thread and swapped in when ready
(``lipmpcc.solvers.casadi_buffer``). This benchmark runs the same closed loop on the 3D-LIP (a straight
path, k static obstacles standing 0.9–1.6 m beside it along the first metres, all within reach) three
ways in one process:

- ``interp``: ``LIPMPCC_BACKGROUND_JIT=0`` and an empty compiled-code cache (what every run did before:
  interpreted above the limit);
- ``jit``: the compiled functions (the same run once before, and its background compiles waited for);
- ``ipopt``: paper A's formulation with IPOPT.

Prints median / p90 solve time per run (the first, cold solve left out) and the closed-loop outcome,
which must be the same for ``interp`` and ``jit`` (the compiled code gives the same numbers to the bit).

    python benchmarks/bench_mpcc_obstacles.py [--steps N] [--counts 0 1 5 20] [--no-ipopt]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import tempfile

import numpy as np

from lipmpcc.loops import lip as lip_loop
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner
from lipmpcc.solvers import casadi_buffer


def obstacles(k: int) -> list[Obstacle]:
    """k static circles (radius 0.15 m) beside the path, alternating sides, 0.9–1.6 m from it."""
    out = []
    for i in range(k):
        side = 1.0 if i % 2 == 0 else -1.0
        out.append(Obstacle.circle(0.15, position=(0.6 + 0.35 * i, side * (0.9 + 0.07 * (i % 10)))))
    return out


def run(kind: str, k: int, solver: str, steps: int) -> tuple[np.ndarray, dict]:
    """The closed loop on the LIP with the fixed-T or the timed MPCC: (solve times [s], summary)."""
    path = LinePath((0, 0), (40, 0))
    obs = obstacles(k)
    prm = MpccParams.overtake_mpcc().with_(solver=solver)
    if kind == "timed":
        pl = TimedMpccPlanner(path, TimedMpccParams(mpcc=prm, T_min=0.3, T_max=0.5))
        log = lip_loop.run_lip_loop(pl, np.zeros(5), steps, path, obs, [], robot_radius=prm.robot_radius,
                                    foot_radius=prm.foot_radius)
    else:
        log = lip_loop.simulate(MpccPlanner(path, prm), np.zeros(5), steps, obs, [])
    return np.asarray(log.solve_time[1:]), lip_loop.summarize(log, obs, settle_time=2.0)


def wait_for_compiles() -> None:
    """Wait for every background compile started so far."""
    for fut in list(casadi_buffer._PENDING.values()):
        fut.result()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=30)
    ap.add_argument("--counts", type=int, nargs="+", default=[0, 1, 5, 20])
    ap.add_argument("--no-ipopt", action="store_true")
    args = ap.parse_args()
    print(f"{'MPCC':6s} {'obst':>4s} {'mode':7s} {'median ms':>9s} {'p90 ms':>8s} {'fail':>4s} {'progress m':>10s} "
          f"{'clear m':>8s}")
    cache = os.environ.get("LIPMPCC_CACHE_DIR")
    empty = tempfile.mkdtemp(prefix="lipmpcc-bench-")
    for kind in ("fixed", "timed"):
        for k in args.counts:
            modes = ["interp", "jit"] + ([] if args.no_ipopt else ["ipopt"])
            for mode in modes:
                os.environ["LIPMPCC_BACKGROUND_JIT"] = "0" if mode == "interp" else "1"
                if mode == "interp":
                    os.environ["LIPMPCC_CACHE_DIR"] = empty
                    casadi_buffer._JIT_CACHE.clear()
                elif cache is None:
                    os.environ.pop("LIPMPCC_CACHE_DIR", None)
                else:
                    os.environ["LIPMPCC_CACHE_DIR"] = cache
                if mode == "jit":
                    run(kind, k, "sqp", args.steps)  # builds every solver the run needs: starts their compiles
                    wait_for_compiles()
                t, s = run(kind, k, "ipopt" if mode == "ipopt" else "sqp", args.steps)
                clear = s["min_clearance_m"]
                print(f"{kind:6s} {k:4d} {mode:7s} {1e3 * np.median(t):9.3f} {1e3 * np.percentile(t, 90):8.3f} "
                      f"{s['solver_failures']:4d} {s['progress_m']:10.4f} {(clear if clear is not None else float('nan')):8.3f}",
                      flush=True)


if __name__ == "__main__":
    main()
