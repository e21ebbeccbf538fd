"""Issue 31's benchmark: success on seeded random scenes, per obstacle kind, with Wilson intervals.

Runs every scene seed × planner (fixed T, timed) × weights (follow-path, overtake) × robot (lip, digit_like)
asked for through the code path of ``lipmpcc run`` (:func:`lipmpcc.course.scenes.run_scene`), appends one
JSON line per run to ``OUT/runs.jsonl`` (a run already there is not run again: stop and resume freely),
saves each failing run (its figure and summary) under ``OUT/``, and writes ``OUT/report.md``
(:func:`lipmpcc.course.scenes.benchmark_report`: the table, the failures and their reasons, the solve-time
and clearance distributions). Success: the end reached, or a slower obstacle trailed, without contact.

    python benchmarks/scene_benchmark.py --seeds 0 200 --out bench/scenes_lip              # the LIP: 800 runs
    nice python benchmarks/scene_benchmark.py --seeds 0 50 --robots digit_like --out bench/scenes_digit
    python benchmarks/scene_benchmark.py --seeds 0 60 --planners "fixed T" timed --weights follow-path --out ...
    python benchmarks/scene_benchmark.py --seeds 0 50 --kinds ahead --robots digit_like --out ...  # those scenes first

``--kinds`` runs only the scenes that hold at least one obstacle of those kinds (the report covers every run
stored in ``OUT``: run again without it to add the others).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from lipmpcc.course.scenes import OBSTACLE_KINDS, PLANNERS, WEIGHTS, SceneRun, benchmark_report, judge, make_scene, run_scene


def _key(seed: int, robot: str, planner: str, weights: str) -> str:
    return f"{seed}|{robot}|{planner}|{weights}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs=2, default=(0, 20), metavar=("FIRST", "STOP"))
    ap.add_argument("--robots", nargs="+", default=["lip"])
    ap.add_argument("--planners", nargs="+", default=list(PLANNERS), choices=list(PLANNERS))
    ap.add_argument("--weights", nargs="+", default=list(WEIGHTS), choices=list(WEIGHTS))
    ap.add_argument("--kinds", nargs="+", default=list(OBSTACLE_KINDS), choices=list(OBSTACLE_KINDS),
                    help="run only the scenes holding an obstacle of one of these kinds (default: every scene)")
    ap.add_argument("--out", required=True, help="output folder (runs.jsonl, report.md, the failures)")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    store = out / "runs.jsonl"
    runs: dict[str, SceneRun] = {}
    if store.exists():
        for line in store.read_text().splitlines():
            d = json.loads(line)
            d["success"], d["reason"] = judge(d["summary"], make_scene(d["seed"]))  # today's judge, today's words
            runs[_key(d["seed"], d["robot"], d["planner"], d["weights"])] = SceneRun(**d)
    for seed in range(*args.seeds):
        scene = make_scene(seed)
        if not set(scene.kinds) & set(args.kinds):
            continue
        for robot in args.robots:
            for planner in args.planners:
                for weights in args.weights:
                    key = _key(seed, robot, planner, weights)
                    if key in runs:
                        continue
                    r = run_scene(scene, robot, planner, weights, folder=out / "scenes", save_failures=True)
                    runs[key] = r
                    with store.open("a") as f:
                        f.write(json.dumps(r.__dict__) + "\n")
                    print(f"seed {seed} {robot} {planner} {weights}: {r.reason}", flush=True)
    report = benchmark_report(list(runs.values()))
    (out / "report.md").write_text(report)
    print(report)


if __name__ == "__main__":
    main()
