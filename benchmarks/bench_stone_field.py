"""Benchmark (issue 29): crossing seeded stone fields on the ALIP, with and without a pedestrian.

The stone-field planner (cost-to-go stone choice + paper B's ALIP-MPC) beside the two baselines in the
same runs: the greedy nearest stone ahead with a fixed step duration, and the path-agnostic ALIP-MPC
(the stone nearest a nominal step). Even seeds have no pedestrian, odd seeds one crossing at
0.3-0.6 m/s (:func:`lipmpcc.studies.stone_field.field_cases`). Prints the success rates with Wilson 95 %
intervals, the outcomes, and the plan time per planner call on the field (median, p90; the stone
choice included) — wall times on a shared machine are noisy.

    PYTHONPATH=python python3 benchmarks/bench_stone_field.py [--seeds 0-99] [--json out.json] [--cop-range 0.06 0.025]
    PYTHONPATH=python python3 benchmarks/bench_stone_field.py --robot digit_like --seeds 0-19 --choosers cost-to-go greedy
    PYTHONPATH=python python3 benchmarks/bench_stone_field.py --push-scale 1.0      # paper B's four pushes on the field
"""

from __future__ import annotations

import argparse
import json
import time

from lipmpcc.planners.alip_mpc import AlipMpcParams
from lipmpcc.planners.stone_field import CHOOSERS
from lipmpcc.studies.stone_field import field_table


def _seeds(text: str) -> list[int]:
    a, _, b = text.partition("-")
    return list(range(int(a), int(b) + 1)) if b else [int(a)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="0-99", help="a seed range a-b (inclusive) [default 0-99]")
    ap.add_argument("--choosers", nargs="+", default=list(CHOOSERS), choices=CHOOSERS)
    ap.add_argument("--json", default=None, help="write the table to this JSON file")
    ap.add_argument("--cop-range", nargs=2, type=float, default=None, metavar=("X", "Y"),
                    help="give every planner's ALIP-MPC a foot: the centre-of-pressure box half-extents [m] "
                         "(default: paper B's point foot)")
    ap.add_argument("--robot", default="alip", help="alip (default), digit_like or a PATH.xml (a full body: its own "
                    "ALIP constants and CoP box; about 8 s of wall time per field)")
    ap.add_argument("--push-scale", type=float, default=None, help="paper B's four pushes on field footholds 2, 4, 6, 8, "
                    "forces times this (default: no push)")
    args = ap.parse_args()
    if args.robot != "alip" and args.cop_range is not None:
        ap.error("--cop-range is the ALIP's: a full body uses its own CoP box (its layout's alip_cop_range)")
    seeds = _seeds(args.seeds)
    t0 = time.perf_counter()
    mpc = None if args.cop_range is None else AlipMpcParams.paper(cop_range=tuple(args.cop_range))
    table = field_table(seeds, tuple(args.choosers), mpc, robot=args.robot, push_scale=args.push_scale)
    wall = time.perf_counter() - t0
    foot = "point foot" if args.cop_range is None else f"a foot, CoP box +-{args.cop_range[0]:g} x +-{args.cop_range[1]:g} m"
    if args.robot != "alip":
        foot = "the robot's CoP box"
    pushed = "" if args.push_scale is None else f", paper B's pushes x{args.push_scale:g}"
    print(f"{len(seeds)} fields (seeds {args.seeds}) on {args.robot}, ALIP-MPC with {foot}{pushed}, {wall:.0f} s")
    print(f"{'planner':26s} {'all':>22s} {'no pedestrian':>22s} {'pedestrian':>22s}  plan ms median / p90")
    for name, row in table.items():
        cells = []
        for key in ("all", "no_pedestrian", "pedestrian"):
            r = row[key]
            lo, hi = r["wilson95"]
            cells.append(f"{r['success']:3d}/{r['n']:3d} [{100 * lo:3.0f},{100 * hi:3.0f}] %")
        ms = row["plan_ms"]
        print(f"{name:26s} {cells[0]:>22s} {cells[1]:>22s} {cells[2]:>22s}  {ms['median']:.2f} / {ms['p90']:.2f}")
        print(f"{'':26s} outcomes {row['outcomes']}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"seeds": args.seeds, "wall_s": wall, "table": table}, f, indent=1)


if __name__ == "__main__":
    main()
