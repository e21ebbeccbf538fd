"""Diagnose a full-body ``stones`` run step by step: for each touch-down, the stone it was meant for, the
last plan's foothold, the measured sole, and each one's distance to the stone's edges (negative: off it).

    PYTHONPATH=python python3 benchmarks/diag_stones_steps.py MODEL.xml [--layout FILE] [--profile I] [--stones N]
        [--L L] [--W W] [--param KEY=VALUE ...] [--robot-param KEY=VALUE ...]

Columns: ``plan-in`` / ``land-in``: the last plan's foothold and the measured sole, each one's distance inside the
stone's foot-centre rectangle (x, y) [m] (negative: outside); ``land-plan``: landing minus plan [m]; ``T``: the
step's duration [s]; ``z0x``: the measured initial DCM of the step in the stance frame [m] against ``z_nomx``, the
one a steady ALIP gait of this step's length would have (length / (exp(lam T_nom) - 1)); ``status``: the last
planner call's (``relaxed``: the stones after the next were grown; ``fallback``: the previous plan).

The stone boxes of the scene are the foot-centre rectangles grown by the sole (``StonesSceneParams.foot_margin``),
so a foothold at the rectangle's edge still has its sole on the box.
"""

from __future__ import annotations

import argparse
import ast
import math
from pathlib import Path

import numpy as np

from lipmpcc.robots import load_robot
from lipmpcc.studies.stepping_stones import simulate_full_body
from lipmpcc.studies.stone_params import FullBodyStonesParams
from lipmpcc.studies.stone_course import CourseScale, scaled_profile
from lipmpcc.terrain import make_profile


def _inside(p: np.ndarray, c: np.ndarray, s: np.ndarray) -> tuple[float, float]:
    """Signed distances [m] of ``p`` to the stone's x and y edges (positive: inside)."""
    d = 0.5 * s - np.abs(p - c)
    return float(d[0]), float(d[1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model")
    ap.add_argument("--layout", default=None)
    ap.add_argument("--profile", default="I")
    ap.add_argument("--stones", type=int, default=12)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--L", type=float, default=None, help="profile I step length [m] (default: paper B's, scaled)")
    ap.add_argument("--W", type=float, default=None, help="profile I lateral offset [m] (default: paper B's, scaled)")
    ap.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                    help="a FullBodyStonesParams field (a Python literal), e.g. touchdown_timing='planner'")
    ap.add_argument("--robot-param", action="append", default=[], metavar="KEY=VALUE",
                    help="a layout field over the layout's (a Python literal), e.g. alip_com_gains=(16,8)")
    args = ap.parse_args()
    over = {k: ast.literal_eval(v) for k, v in (a.split("=", 1) for a in args.robot_param)}
    fields = {k: ast.literal_eval(v) for k, v in (a.split("=", 1) for a in args.param)}
    robot = load_robot(args.model if args.model == "digit_like" else Path(args.model), layout=args.layout, **over)
    scale = CourseScale.for_robot(robot)
    seq = make_profile(args.profile, args.seed, args.L, args.W) if scale is None else scaled_profile(args.profile, scale, args.seed, args.L, args.W)
    run = simulate_full_body(robot, "alip-mpc", seq.head(args.stones), params=FullBodyStonesParams(**fields))
    log, course = run.log, run.course
    print(f"{robot.name}: sole {robot.foot_length:.3f} x {robot.foot_width:.3f} m; fell={log.fell} "
          f"reason={log.fall_reason!r} t={log.fall_time}; metrics rmse={run.metrics['step_rmse_m']:.3f} "
          f"completed={run.metrics['steps_completed']} failures={run.metrics['solver_failures']}")
    lam = float(log.lam)
    T_nom = float(run.source.planner.params.T_nom)
    sig = math.exp(lam * T_nom)
    zi = log.z_initial
    print(f"lam {lam:.3f} 1/s, T_nom {T_nom:.3f} s; z0x: the measured initial DCM of the step (stance frame) against "
          "z_nom = the step's own length / (exp(lam T_nom) - 1)")
    print(" k  stone  stone c (x, y)     plan-in (x, y)    land-in (x, y)   land-plan (x, y)  T [s]   z0x  z_nomx status")
    pf, ps, pst = log.plan_foothold, log.plan_step, log.plan_status
    for j, (k, fh, T) in enumerate(zip(log.step_index, log.footholds, log.durations)):
        c, s = course.centers[k], np.asarray(course.sizes[k], float)
        rows = np.flatnonzero(ps == j)
        plan = pf[rows[-1]] if rows.size else np.full(2, np.nan)
        status = pst[rows[-1]] if rows.size else "-"
        stone = bool(course.is_stone[k])
        pin = _inside(plan, c, s) if stone else (np.nan, np.nan)
        lin = _inside(fh, c, s) if stone else (np.nan, np.nan)
        dl = fh - plan
        prev = log.footholds[j - 1] if j > 0 else log.start_stance
        z0x = zi[j, 0] if j < len(zi) else float("nan")
        znx = (c[0] - prev[0]) / (sig - 1.0)
        print(f"{j:2d} {k:3d}{'S' if stone else ' '}  ({c[0]:+.3f}, {c[1]:+.3f})  ({pin[0]:+.3f}, {pin[1]:+.3f})  "
              f"({lin[0]:+.3f}, {lin[1]:+.3f})  ({dl[0]:+.3f}, {dl[1]:+.3f})  {T:.3f}  {z0x:+.3f} {znx:+.3f} {status}")


if __name__ == "__main__":
    main()
