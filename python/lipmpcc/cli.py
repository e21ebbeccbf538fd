"""Command-line interface: ``lipmpcc run SCENARIO [options]``.

Every run writes ``summary.json`` and PNG figures to ``--out``. Errors reach the
user as one readable line on stderr and a non-zero exit code, never as a
traceback (set ``LIPMPCC_DEBUG=1`` to see the traceback).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from pathlib import Path
from typing import Any, Sequence

from .exceptions import LipmpccError

EXIT_OK = 0
EXIT_USAGE = 2
EXIT_ERROR = 1


def _finite_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return v


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if v <= 0:
        raise argparse.ArgumentTypeError(f"{v} must be a positive integer")
    return v


def _nonneg_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if v < 0:
        raise argparse.ArgumentTypeError(f"{v} must be >= 0")
    return v


def build_parser() -> argparse.ArgumentParser:
    from . import scenarios

    p = argparse.ArgumentParser(prog="lipmpcc", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)

    r = sub.add_parser("run", help="run one scenario and write summary.json + figures")
    r.add_argument("scenario", choices=scenarios.names())
    r.add_argument("--planner", help="mpcc | cartesian | alip-mpc | alip-qp | capture-point")
    r.add_argument("--robot", help="lip | alip | digit_like | PATH.xml")
    r.add_argument("--obstacle-speed", type=_finite_float, help="obstacle speed along the path [m/s]")
    r.add_argument("--path", help="CSV file of waypoints with columns x,y [m]")
    r.add_argument("--obstacles", help="JSON file: list of obstacles")
    r.add_argument("--steps", type=_positive_int, help="number of steps")
    r.add_argument("--seed", type=_nonneg_int, default=0, help="random seed")
    r.add_argument("--out", default="results", help="output folder")
    r.add_argument("--profile", help="stepping-stone profile I | II | III | IV")
    r.add_argument("--L", type=_finite_float, help="profile I step length [m]")
    r.add_argument("--W", type=_finite_float, help="profile I lateral offset [m]")
    r.add_argument("--stones", help="CSV of stones x,y[,size_x,size_y] [m], world frame")
    r.add_argument("--duration", type=_finite_float, help="simulated time [s]")
    r.add_argument("--speed", type=_finite_float, help="commanded walking speed [m/s]")
    r.add_argument("--yaw-rate", type=_finite_float, help="commanded yaw rate [rad/s]")
    r.add_argument("--video", action="store_true", help="also write a video of the run")
    r.add_argument("--cop-range", type=_finite_float, nargs=2, metavar=("DX", "DY"),
                   help="stones/push with alip-mpc: half-extents of the centre-of-pressure box the planner may use "
                        "in the stance sole [m] (a foot; 0 0 = paper B's point foot; default: the robot's, "
                        "0 0 on the ALIP model)")

    rp = sub.add_parser("reproduce", help="run every study and write a report beside the papers' numbers")
    rp.add_argument("--fast", action="store_true", help="shorter runs (the LIPMPCC_FAST switch)")
    rp.add_argument("--out", default="results", help="output folder")
    rp.add_argument("--only", help="run only the studies whose name starts with this")
    return p


def _jsonable(obj: Any) -> Any:
    import numpy as np

    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (np.bool_,)):
        return bool(obj)
    return obj


def write_outputs(result: Any, out: str | Path) -> Path:
    """Write ``summary.json`` and every figure of a :class:`RunResult` to ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "summary.json", "w") as f:
        json.dump(_jsonable(result.summary), f, indent=2, sort_keys=False)
    for name, fig in result.figures.items():
        fig.savefig(out / f"{name}.png", dpi=110, bbox_inches="tight")
    try:
        import matplotlib.pyplot as plt

        for fig in result.figures.values():
            plt.close(fig)
    except Exception:  # pragma: no cover - matplotlib missing is impossible here
        pass
    return out / "summary.json"


def _run(ns: argparse.Namespace) -> int:
    from . import scenarios

    opts = scenarios.RunOptions(
        scenario=ns.scenario,
        planner=ns.planner,
        robot=ns.robot,
        obstacle_speed=ns.obstacle_speed,
        path=ns.path,
        obstacles=ns.obstacles,
        steps=ns.steps,
        seed=ns.seed,
        out=ns.out,
        profile=ns.profile,
        L=ns.L,
        W=ns.W,
        stones=ns.stones,
        video=ns.video,
        duration=ns.duration,
        speed=ns.speed,
        yaw_rate=ns.yaw_rate,
        cop_range=None if ns.cop_range is None else (float(ns.cop_range[0]), float(ns.cop_range[1])),
    )
    result = scenarios.run(opts)
    path = write_outputs(result, ns.out)
    s = result.summary
    keys = [k for k in ("scenario", "planner", "robot", "steps", "fell", "solver_failures") if k in s]
    print(" ".join(f"{k}={s[k]}" for k in keys) + f" -> {path}")
    return EXIT_OK


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``lipmpcc`` and ``python -m lipmpcc``."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    parser = build_parser()
    ns = parser.parse_args(argv)
    try:
        if ns.command == "run":
            return _run(ns)
        if ns.command == "reproduce":  # added by the reproduction report
            from .reproduce import main as reproduce_main

            return reproduce_main(ns)
    except (LipmpccError, ValueError, FileNotFoundError, OSError) as exc:
        if os.environ.get("LIPMPCC_DEBUG"):
            raise
        print(f"lipmpcc: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    parser.error(f"unknown command {ns.command!r}")
    return EXIT_USAGE
