"""Paper B on a full body: per footstep, how close the legs come to their joint stops and what leads the fall.

One stepping-stone course (or paper B's push test) with the ALIP-MPC on a full-body model, read at every WBC tick
(the run is the same with the hook as without it), printed one line per footstep:

    step side T[s] | COM lead at lift-off [m] | DCM lead [m] | stance ankle-stop margin [deg] (joint) |
    nearest stop of any leg joint [deg] (joint) | saturated actuator ticks

"COM lead" and "DCM lead" are the COM's and the DCM's forward distance (x) from the stance sole at the
step's last tick; the margins are the distance of a limited hinge joint to the nearer end of its range (< 0: at
or past the stop). Then the per-step log of :func:`bench_paper_b_model.step_log` (touch-down time error, DCM
miss, foothold − stone centre, relaxed and fallback calls). It is how Digit v3's ankle stop at L = 0.55 m was
found (docs/design.md, "Digit v3's ankle stop at 1.1 m/s").

    PYTHONPATH=python python3 benchmarks/bench_paper_b_joints.py [--model PATH.xml] [--profile I --L 0.55 --W 0.15]
        [--profile IV --seed 0] [--push] [--ankle NAME]

``--ankle``: the ankle joint's name without the side prefix (default ``toe-pitch``, Digit v3's; the joints of a
side are those whose body name starts with ``left``/``right``).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from lipmpcc.robots import load_robot
from lipmpcc.studies.stepping_stones import simulate_full_body
from lipmpcc.studies.stone_course import paper_pushes, push_stones
from lipmpcc.terrain import make_profile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_paper_b_model import DEFAULT_MODEL, step_log  # noqa: E402

G = 9.81  # [m/s²] for the DCM of the printout only


@dataclass
class _Step:
    """What one footstep's ticks left: the last state and the extremes."""

    side: str = ""
    t0: float = math.nan
    t1: float = math.nan
    com_lead: float = math.nan
    dcm_lead: float = math.nan
    ankle: tuple[float, str] = (math.inf, "")
    nearest: tuple[float, str] = (math.inf, "")
    saturated: dict[str, int] = field(default_factory=dict)


class JointRecorder:
    """A tick hook (``simulate_full_body(viewer=...)``): per footstep, the stance leg's ankle margin, the nearest
    stop of any leg joint, the saturated actuators and the COM/DCM lead over the stance foot at its last tick."""

    def __init__(self, ankle: str, com_height: float) -> None:
        self.ankle = ankle
        self.lam = math.sqrt(G / com_height)
        self.steps: dict[int, _Step] = {}
        self._joints: list[tuple[int, str, int]] | None = None
        self._last: tuple[float, np.ndarray] | None = None

    def set_scene(self, **_: Any) -> None:
        """(The live viewer's method; nothing to draw.)"""

    def _index(self, m: mujoco.MjModel) -> list[tuple[int, str, int]]:
        out = []
        for j in range(m.njnt):
            if m.jnt_limited[j] and m.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE:
                body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, m.jnt_bodyid[j]) or ""
                side = 0 if body.startswith("left") else 1 if body.startswith("right") else -1
                if side >= 0:
                    out.append((j, mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or str(j), side))
        return out

    def __call__(self, t: float, sim: Any, gait: Any) -> None:
        m, d = sim.model, sim.data
        if self._joints is None:
            self._joints = self._index(m)
        k, st = len(gait.touchdowns), int(gait.stance_index)
        s = self.steps.setdefault(k, _Step(side=("left", "right")[st], t0=t))
        s.t1 = t
        for j, name, side in self._joints:
            q, (lo, hi) = d.qpos[m.jnt_qposadr[j]], m.jnt_range[j]
            margin = math.degrees(min(q - lo, hi - q))
            if margin < s.nearest[0]:
                s.nearest = (margin, name)
            if side == st and name.endswith(self.ankle) and margin < s.ankle[0]:
                s.ankle = (margin, name)
        hi = m.actuator_ctrlrange[:, 1]
        for i in np.flatnonzero(np.abs(d.ctrl) >= 0.98 * hi):
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, int(i)) or str(i)
            s.saturated[name] = s.saturated.get(name, 0) + 1
        com = d.subtree_com[1].copy()
        foot = sim.foot_poses()[st].position
        if self._last is not None and t > self._last[0]:
            v = (com[0] - self._last[1][0]) / (t - self._last[0])
            s.com_lead = float(com[0] - foot[0])
            s.dcm_lead = float(com[0] + v / self.lam - foot[0])
        self._last = (t, com)


def _course(args: argparse.Namespace) -> tuple[Any, tuple, str]:
    if args.push:
        return push_stones(), paper_pushes(), "push test"
    if args.profile == "I":
        return make_profile("I", L=args.L, W=args.W), (), f"I L={args.L:g} W={args.W:+.2f}"
    return make_profile(args.profile, seed=args.seed), (), f"{args.profile} seed {args.seed}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    env = os.environ.get("LIPMPCC_DIGIT_V3", "").strip()
    ap.add_argument("--model", default=env or str(DEFAULT_MODEL), help="a MODEL.xml, or digit_like")
    ap.add_argument("--profile", default="I", choices=("I", "II", "III", "IV"))
    ap.add_argument("--L", type=float, default=0.55)
    ap.add_argument("--W", type=float, default=0.15)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--push", action="store_true", help="paper B's push test instead of a profile")
    ap.add_argument("--ankle", default="toe-pitch", help="the ankle joint's name after the side prefix")
    args = ap.parse_args()
    if args.model != "digit_like" and not Path(args.model).is_file():
        raise SystemExit(f"model not found: {args.model} (pass --model PATH.xml or set LIPMPCC_DIGIT_V3)")
    robot = load_robot(args.model)
    stones, pushes, name = _course(args)
    rec = JointRecorder(args.ankle, float(robot.standing.com_height))
    run = simulate_full_body(robot, "alip-mpc", stones, pushes=pushes, viewer=rec)  # type: ignore[arg-type]
    res = run.result
    print(f"{name} on {args.model}: " + (f"fell ({res.fall_reason})" if res.fell else "completed")
          + f", {run.metrics.get('solver_failures')} failed solves, step RMSE {run.metrics.get('step_rmse_m')}")
    print("step side   T[s] COM-lead DCM-lead | stance ankle margin [deg]     | nearest stop [deg]            | saturated")
    for k, s in sorted(rec.steps.items()):
        sat = ", ".join(f"{a} {n}" for a, n in sorted(s.saturated.items())) or "-"
        print(f"{k:4d} {s.side:5s} {s.t1 - s.t0:6.3f} {s.com_lead:+8.3f} {s.dcm_lead:+8.3f} | "
              f"{s.ankle[0]:+6.1f} {s.ankle[1]:22s} | {s.nearest[0]:+6.1f} {s.nearest[1]:22s} | {sat}")
    print("\n".join(step_log(run)))


if __name__ == "__main__":
    main()
