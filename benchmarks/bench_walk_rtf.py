"""One full-body walk's real-time factor, for A/B runs of two checkouts or switches in one session.

Runs a capture-point walk (0.6 m/s) of ``--duration`` simulated seconds after a 0.5 s warm-up run, and prints
one JSON line: the package used, the real-time factor (simulated s per wall s), the same per CPU second of the
process (``time.process_time``: both of the loop's helper threads count), µs per WBC tick and whether it fell.
Alternate it between commits (``PYTHONPATH=OTHER/python``) or switches (``LIPMPCC_TICK_REFERENCES=0``,
``LIPMPCC_LOOP_THREAD=0``, ``LIPMPCC_WBC_THREAD=0``) and compare medians and paired ratios: on a shared machine
single runs vary by ×2.

Usage: ``python benchmarks/bench_walk_rtf.py [--robot digit_like|PATH.xml] [--duration S]``.
"""

from __future__ import annotations

import argparse
import json
import time

import lipmpcc
from lipmpcc.loops.fullbody import FullBodyLoop
from lipmpcc.planners.capture_point import CapturePointPlanner
from lipmpcc.robots import load_robot


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--robot", default="digit_like", help="robot name or MJCF path")
    ap.add_argument("--duration", type=float, default=5.0, help="simulated seconds of walking [s]")
    ns = ap.parse_args(argv)
    loop = FullBodyLoop(load_robot(ns.robot), planner=CapturePointPlanner(speed=0.6))
    loop.run(duration=0.5)
    c0 = time.process_time()
    r = loop.run(duration=ns.duration)
    cpu = time.process_time() - c0
    print(json.dumps({"package": lipmpcc.__file__, "rtf": r.real_time_factor, "rtf_cpu": r.sim_time / cpu,
                      "us_per_tick": r.wall_time / len(r.log.t) * 1e6, "fell": r.fell}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
