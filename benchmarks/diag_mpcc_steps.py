"""Diagnosis: paper A's MPCC on a full body, step by step (issue 26: why T1's MPCC runs fall).

Runs one full-body ``circle`` / ``overtake`` / ``follow-path`` (``lipmpcc.studies.path_following.simulate_full_body``,
the CLI's parameters) and prints, per touch-down k:

- ``yaw``: the foot's yaw at touch-down [rad] against its planned yaw, and ``spin``: how far the stance
  foot's yaw has moved when the MPCC is last asked in the next step (the heading it plans from) [rad];
- ``v pred / meas``: the exchange COM velocity (x, y) [m/s] the step's first plan predicted (the LIP from the
  measured state at the previous touch-down) against the one measured at touch-down k;
- ``fwd, lat``: the executed plan's foothold offset from the predicted COM, in its heading frame [m]; ``turn``:
  its heading change [rad]; ``dtheta``: its planned path progress per step of the horizon [m];
- ``QP``: the whole-body QP's failed ticks in the step; whether the foot was in contact at touch-down (``contact``)
  or landed by the clock in the air (``clock``), and its sole's height ``z`` [m];
- ``serr``: the swing foot's position error on the tick before touch-down [m]; ``sat``: the fraction of the
  step's ticks with some joint at 95 % of its torque limit or more, and the joint most often there;
- ``stance``: the stance foot in the step, sampled at 60 Hz (:class:`StanceProbe`): its fewest MuJoCo contact
  points, its least normal force over the robot's weight and its largest yaw rate [rad/s] (a foot that unloads
  onto one point and spins).

    PYTHONPATH=python python3 benchmarks/diag_mpcc_steps.py MODEL.xml [--layout FILE] [--scenario circle]
        [--duration 10] [--set KEY=VALUE ...] [--last 15] [--freeze-phase 0.85]

``--set`` takes the CLI's MPCC keys (``lipmpcc run --set``, e.g. ``r_theta=50``). The model needs its layout beside
it (``lipmpcc robot init MODEL.xml``) or ``--layout FILE``; a robot name (``digit_like``) works too.
``--freeze-phase`` sets the swing's :attr:`~lipmpcc.control.references.SwingParams.freeze_phase` (the phase after
which re-plans no longer move the foothold; 0.85 by default).
"""

from __future__ import annotations

import argparse
import functools
import math

import numpy as np

from lipmpcc.control.references import SwingParams
from lipmpcc.loops.fullbody import gait
from lipmpcc.planners.presets import PlannerSettings
from lipmpcc.robots import load_robot
from lipmpcc.robots.layouts import use_layout
from lipmpcc.studies.path_following import simulate_full_body


def _frame(h: float, vec: np.ndarray) -> tuple[float, float]:
    """``vec`` (x, y) in the frame of heading ``h`` [rad]: (forward, lateral)."""
    c, s = math.cos(h), math.sin(h)
    return c * vec[0] + s * vec[1], -s * vec[0] + c * vec[1]


class StanceProbe:
    """A loop hook (``simulate_full_body(viewer=...)``) that samples the stance foot at 60 Hz: (t [s], contact
    points, normal force / weight, |yaw rate| [rad/s]) in :attr:`rows`."""

    def __init__(self, robot: object) -> None:
        self.robot = robot
        self.rows: list[tuple[float, int, float, float]] = []
        self._ids: tuple[int, int] | None = None

    def set_scene(self, *args: object, **kwargs: object) -> None:
        """The viewer's scene call: nothing to draw."""

    def __call__(self, t: float, sim: object, gait_: object) -> None:
        import mujoco

        m, d = sim.model, sim.data  # type: ignore[attr-defined]
        k = int(getattr(gait_, "stance_index", -1))
        if k not in (0, 1):
            return
        if self._ids is None:
            self._ids = tuple(mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n)  # type: ignore[assignment]
                              for n in (self.robot.left_foot_body, self.robot.right_foot_body))  # type: ignore[attr-defined]
        b = self._ids[k]
        n, fz, f6 = 0, 0.0, np.zeros(6)
        for i in range(d.ncon):
            c = d.contact[i]
            if b in (m.geom_bodyid[c.geom1], m.geom_bodyid[c.geom2]):
                n += 1
                mujoco.mj_contactForce(m, d, i, f6)
                fz += float(f6[0])
        v = np.zeros(6)
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, b, v, 0)
        self.rows.append((t, n, fz / (9.81 * self.robot.total_mass), abs(float(v[2]))))  # type: ignore[attr-defined]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("robot", help="MODEL.xml (with its layout) or a robot name")
    ap.add_argument("--scenario", default="circle", choices=("circle", "overtake", "follow-path"))
    ap.add_argument("--duration", type=float, default=10.0, help="simulated time [s]")
    ap.add_argument("--obstacle-speed", type=float, default=0.3, help="overtake's obstacle speed [m/s]")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="an MPCC parameter (as the CLI's)")
    ap.add_argument("--last", type=int, default=15, help="print the last LAST steps")
    ap.add_argument("--layout", default=None, help="the layout file (lipmpcc robot init MODEL.xml --out FILE)")
    ap.add_argument("--freeze-phase", type=float, default=None, help="the swing's freeze phase (default 0.85)")
    args = ap.parse_args()
    if args.layout is not None:
        use_layout(args.robot, args.layout)
    if args.freeze_phase is not None:  # the loop builds its swing parameters from gait.SwingParams()
        gait.SwingParams = functools.partial(SwingParams, freeze_phase=args.freeze_phase)  # type: ignore[misc]
    values = {k: float(v) for k, v in (kv.split("=", 1) for kv in args.set)}
    robot = load_robot(args.robot)
    probe = StanceProbe(robot)
    run = simulate_full_body(robot, args.scenario, duration=args.duration, viewer=probe,  # type: ignore[arg-type]
                             obstacle_speed=args.obstacle_speed if args.scenario == "overtake" else None,
                             settings=PlannerSettings(values=values) if values else None)
    s, res, src = run.summary, run.result, run.source
    print({k: s.get(k) for k in ("fell", "fall_time_s", "fall_reason", "steps", "contouring_error_rms_m", "progress_m",
                                 "qp_failures", "real_time_factor")})
    first: dict[int, object] = {}
    last: dict[int, object] = {}
    for r in src.records:
        first.setdefault(r.step_index, r)
        last[r.step_index] = r
    log, tds = res.log, res.touchdowns
    sat = np.abs(log.tau) / np.asarray(robot.torque_limits) >= 0.95
    joints = list(robot.motor_joints)
    print(" k  side  t [s]  yaw/planned  spin   v pred (x,y)    v meas (x,y)   fwd    lat    turn  dtheta              QP"
          "            serr  sat  stance (pts fz/W wz)")
    probe_t = np.array([r[0] for r in probe.rows])
    i_prev = 0
    for k, td in list(enumerate(tds))[-args.last:]:
        i = min(int(np.searchsorted(log.t, td.t)), len(log.t) - 1)
        v = log.com_vel[i, :2]
        r0, rl, nxt = first.get(k), last.get(k), last.get(k + 1)
        pv = r0.x0[[1, 3]] if r0 is not None else np.full(2, np.nan)
        spin = math.remainder(float(nxt.x0[4]) - td.yaw, 2 * math.pi) if nxt is not None else math.nan
        fwd = lat = turn = math.nan
        dth = ""
        if rl is not None and rl.result is not None:
            fwd, lat = _frame(float(rl.x0[4] + rl.result.u0[2]), rl.result.u0[:2])
            turn = float(rl.result.u0[2])
            dth = " ".join(f"{d:.2f}" for d in np.diff(rl.result.theta))
        i0 = int(np.searchsorted(log.t, tds[k - 1].t)) if k else i_prev
        s_k = sat[i0:i]
        busy = f"{np.mean(s_k.any(axis=1)):.2f} {joints[int(np.argmax(s_k.sum(axis=0)))]}" if len(s_k) else "-"
        t_prev = tds[k - 1].t if k else 0.0
        st = [probe.rows[j] for j in np.flatnonzero((probe_t > t_prev) & (probe_t < td.t))]
        stance = (f"{min(r[1] for r in st)} {min(r[2] for r in st):.2f} {max(r[3] for r in st):.1f}" if st else "-")
        print(f"{k:2d} {td.side.sign:+d} {td.t:6.2f} {td.yaw:+.2f}/{td.planned_yaw:+.2f} {spin:+.2f} "
              f"({pv[0]:+.2f},{pv[1]:+.2f})  ({v[0]:+.2f},{v[1]:+.2f})  {fwd:+.3f} {lat:+.3f} {turn:+.2f}  {dth:18s} "
              f"{int(np.count_nonzero(log.fallback[i0:i]))} {'contact' if td.by_contact else 'clock'} z={td.pos[2]:+.3f}  "
              f"{log.swing_err[max(i - 1, 0)]:.3f} {busy}  {stance}")


if __name__ == "__main__":
    main()
