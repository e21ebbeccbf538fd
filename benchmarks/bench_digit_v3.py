"""Benchmark: the whole stack on the reference Digit v3 MJCF beside digit_like.

For each robot (the Digit v3 file ``../shared/models/digit-v3/digit-v3.xml``, skipped when absent,
and the project's ``digit_like``):

1. **WBC tick** [ms]: the C++ tick (Pinocchio terms, loop elimination, QP assembly, proxsuite solve,
   efforts; ``WbcOutput.tick_time_us``) and the Python ``WholeBodyController.solve`` call, median and
   p90, over a capture-point walk at 0.6 m/s (MuJoCo 2 kHz, WBC 400 Hz); the QP sizes.
2. **Real-time factor** of ``FullBodyLoop.run`` (simulated seconds per wall second; best of
   ``--repeat``), standing under four 50 N pushes and walking at 0.6 m/s, and the same per CPU second
   of the process (all its threads: the loop's, the loop's helper that logs and evaluates the next
   references while MuJoCo steps, and the WBC's ``prepare`` worker; see ``cpp/wbc/README.md``). The
   walk again on one thread (``LoopParams(helper_thread=False)``, ``WholeBodyController(threaded=False)``),
   interleaved with the other walks, for a paired comparison on the same machine in the same run.
3. **mj_step** [µs] of each scene at its standing pose (zero commands, ``mj_step(nstep=5)``) and the
   real-time factor it alone would allow (``1 / (2000 · t_step)``).
4. **Closed loops** (Digit v3): the largest distance between the two anchors of any
   ``<equality connect>`` after every controller tick of a walking and a standing run (separate runs,
   not timed) [mm] (MuJoCo's loop constraints are soft).
5. Digit v3, loops as **multipliers** instead of eliminated: QP size and C++ tick on the same walk.

Usage: ``python benchmarks/bench_digit_v3.py [--repeat N] [--walk-time S] [--json PATH] [--digit-v3 PATH]``;
``LIPMPCC_FAST=1`` shortens the runs. Timings depend on the machine's load.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import mujoco
import numpy as np

from lipmpcc.config import horizon
from lipmpcc.metrics import timing_stats_ms
from lipmpcc.planners.capture_point import CapturePointPlanner
from lipmpcc.robots import load_robot, loop_closure_errors
from lipmpcc.studies.walking import stand_pushes
from lipmpcc.loops.fullbody.loop import FullBodyLoop

SHARED_DIGIT = Path(__file__).resolve().parents[2] / "shared" / "models" / "digit-v3" / "digit-v3.xml"


class Instrumented:
    """Records the C++ tick and the Python call time of every solve of a controller (the loop calls
    ``solve_tick``, whose checks and C++ call are ``_solve_raw``: its fifth item is the C++ tick [µs])."""

    def __init__(self, wbc) -> None:
        self.ticks: list[float] = []
        self.calls: list[float] = []
        solve_raw = wbc._solve_raw

        def timed(q, v, ref):
            t0 = time.perf_counter()
            res = solve_raw(q, v, ref)
            self.calls.append(time.perf_counter() - t0)
            if res is not None:
                self.ticks.append(res[4] * 1e-6)
            return res

        wbc._solve_raw = timed


class LoopWatch:
    """Largest anchor distance of the model's loops after every controller tick [m]."""

    def __init__(self, sim) -> None:
        self.max = 0.0
        step = sim.step

        def watched(ctrl, n=1, **kw):
            step(ctrl, n, **kw)
            if sim.model.neq:
                self.max = max(self.max, float(np.max(loop_closure_errors(sim.model, sim.data))))

        sim.step = watched


def run_loop(
    robot,
    speed: float | None,
    duration: float,
    loop_formulation: str = "eliminate",
    watch: bool = False,
    threaded: bool | None = None,
) -> dict:
    from lipmpcc.loops.fullbody.loop import LoopParams
    from lipmpcc.control.wbc import WholeBodyController

    planner = None if speed is None else CapturePointPlanner(speed=speed)
    wbc = WholeBodyController(robot, loop_formulation=loop_formulation, threaded=threaded)
    loop = FullBodyLoop(robot, planner=planner, wbc=wbc, params=LoopParams(helper_thread=threaded))
    inst = Instrumented(wbc)
    lw = LoopWatch(loop.sim) if watch else None
    pushes = stand_pushes(1.0, 1.0) if speed is None else ()
    c0 = time.process_time()
    res = loop.run(duration=duration, pushes=pushes)
    cpu = time.process_time() - c0
    if res.fell:
        raise RuntimeError(f"{robot.name} fell at {res.fall_time:.2f} s: {loop.sim.fall_reason()}")
    qp = wbc.last_qp()
    return dict(
        rtf=res.real_time_factor,
        rtf_cpu=res.sim_time / cpu,
        tick=timing_stats_ms(inst.ticks),
        call=timing_stats_ms(inst.calls),
        qp_failures=res.qp_failures,
        loop_max_m=lw.max if lw else None,
        qp_size=f"{qp['n_var']} variables, {qp['n_eq']} equalities, {qp['n_in']} inequalities",
    )


def mj_step_us(robot, n: int) -> float:
    from lipmpcc.sim.robot_sim import RobotSim

    sim = RobotSim(robot)
    m, d = sim.model, sim.data
    best = np.inf
    for _ in range(max(1, n // 500)):
        t0 = time.perf_counter()
        for _ in range(100):
            mujoco.mj_step(m, d, 5)
        best = min(best, (time.perf_counter() - t0) / 500)
        sim.reset("stand")
    return best * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=int(horizon(2, 1)))
    parser.add_argument("--walk-time", type=float, default=float(horizon(10.0, 3.0)))
    parser.add_argument("--stand-time", type=float, default=float(horizon(5.0, 2.0)))
    parser.add_argument("--json", type=Path, default=None)
    parser.add_argument("--digit-v3", type=Path, default=SHARED_DIGIT,
                        help="a Digit v3 MJCF (default: ../shared/models/digit-v3/digit-v3.xml beside the repository)")
    args = parser.parse_args()

    robots = []
    if args.digit_v3.exists():
        robots.append(load_robot(args.digit_v3))
    else:
        print(f"(Digit v3 skipped: {args.digit_v3} not found; pass --digit-v3 PATH)")
    robots.append(load_robot("digit_like"))
    results: dict = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"load average {os.getloadavg()[0]:.1f} at start",
    }
    for robot in robots:
        r: dict = {}
        step_before = mj_step_us(robot, int(horizon(5000, 1000)))
        walks, single = [], []
        for _ in range(args.repeat):  # interleaved: both see the same moments of the machine
            walks.append(run_loop(robot, 0.6, args.walk_time))
            single.append(run_loop(robot, 0.6, args.walk_time, threaded=False))
        stands = [run_loop(robot, None, args.stand_time) for _ in range(args.repeat)]
        best_walk = max(walks, key=lambda w: w["rtf"])
        r["qp_size_walking"] = best_walk["qp_size"]
        r["wbc_tick_ms"] = min((w["tick"] for w in walks), key=lambda s: s["median"])
        r["wbc_python_call_ms"] = min((w["call"] for w in walks), key=lambda s: s["median"])
        r["rtf_walk"] = best_walk["rtf"]
        r["rtf_walk_cpu"] = max(w["rtf_cpu"] for w in walks)
        r["rtf_walk_single_thread"] = max(w["rtf"] for w in single)
        r["threaded_over_single_walk_median"] = float(np.median([a["rtf"] / b["rtf"] for a, b in zip(walks, single)]))
        r["rtf_stand"] = max(s["rtf"] for s in stands)
        r["rtf_stand_cpu"] = max(s["rtf_cpu"] for s in stands)
        r["qp_failures"] = sum(w["qp_failures"] for w in walks + stands)
        step = mj_step_us(robot, int(horizon(5000, 1000)))
        r["mj_step_us"] = step
        r["mj_step_us_before_walks"] = step_before
        r["rtf_limit_mj_step_only"] = 1.0 / (2000 * step * 1e-6)
        if robot.closed_loops:  # separate runs: the check costs ~25 us per tick
            watched = [run_loop(robot, 0.6, args.walk_time, watch=True), run_loop(robot, None, args.stand_time, watch=True)]
            r["loop_closure_max_mm"] = 1e3 * max(x["loop_max_m"] for x in watched)
            mult = run_loop(robot, 0.6, args.walk_time, loop_formulation="multipliers")
            r["multipliers_qp_size_walking"] = mult["qp_size"]
            r["multipliers_wbc_tick_ms"] = mult["tick"]
        results[robot.name] = r

    def fmt(s: dict) -> str:
        return f"median {s['median'] * 1e3:6.0f} us   p90 {s['p90'] * 1e3:6.0f} us   (n = {s['n']})"

    print("Bring your own Digit: the stack on the Digit v3 MJCF beside digit_like")
    print(f"  machine: {results['machine']}")
    for robot in robots:
        r = results[robot.name]
        print(f"  {robot.name}:")
        print(f"    QP while walking        {r['qp_size_walking']}")
        print(f"    WBC tick (C++)          {fmt(r['wbc_tick_ms'])}")
        print(f"    WBC solve (Python call) {fmt(r['wbc_python_call_ms'])}")
        print(f"    real-time factor        walk {r['rtf_walk']:.2f}x (per CPU s {r['rtf_walk_cpu']:.2f}x)   "
              f"stand {r['rtf_stand']:.2f}x (per CPU s {r['rtf_stand_cpu']:.2f}x)")
        print(f"    on one thread           walk {r['rtf_walk_single_thread']:.2f}x   (threaded / single, paired: "
              f"x{r['threaded_over_single_walk_median']:.2f})")
        print(f"    mj_step                 {r['mj_step_us']:.0f} us  -> at most {r['rtf_limit_mj_step_only']:.1f}x real time"
              f"   ({r['mj_step_us_before_walks']:.0f} us before the walks)")
        print(f"    QP failures             {r['qp_failures']}")
        if "loop_closure_max_mm" in r:
            print(f"    loop closure (MuJoCo)   max {r['loop_closure_max_mm']:.3f} mm over the runs")
            print(f"    loops as multipliers    {r['multipliers_qp_size_walking']};  tick {fmt(r['multipliers_wbc_tick_ms'])}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=2, default=float))
        print(f"  written to {args.json}")


if __name__ == "__main__":
    sys.exit(main())
