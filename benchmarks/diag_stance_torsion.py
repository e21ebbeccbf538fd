"""Diagnosis: the stance foot's yaw moment, per whole-body tick (issue 26: why T1's stance foot spins).

Runs one full-body path-following run (``circle`` / ``overtake``, the CLI's parameters) or a capture-point ``walk``
and records, at every whole-body tick with one foot in contact (single support):

- the wrench the QP commands at the stance sole (sole frame): its normal force ``fz`` [N], its CoP ``cop``
  (x, y) [m] from the sole rectangle's centre, as a fraction of the QP's CoP rectangle (``cop_frac``: the larger
  of |x|/sL, |y|/sW), its yaw moment about the CoP centre ``tz`` [N m];
- the torsion bound the QP applies (``mu min(sL, sW) fz``) and the yaw moment a rectangle of the QP's size can carry
  at that CoP and tangential force (the contact wrench cone of Caron et al. 2015, the corners' friction cones);
- what MuJoCo's contact does: its contact points on the foot, the measured normal force, CoP and yaw moment, and
  the foot's yaw rate [rad/s].

It prints shares over the single-support ticks, split by MuJoCo's contact points (<= 1 point: the foot on a corner),
and the ticks around each spin (|yaw rate| > ``--spin`` rad/s).

    PYTHONPATH=python python3 benchmarks/diag_stance_torsion.py MODEL.xml --layout FILE [--scenario circle]
        [--duration 6] [--speed 0.5] [--obstacle-speed 0.3] [--spin 2.0]

``--scenario stones``: paper B's profile I scaled to the robot (ALIP-MPC, as ``lipmpcc run stones``).
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from lipmpcc.control.wbc import WholeBodyController
from lipmpcc.robots import load_robot
from lipmpcc.robots.layouts import use_layout


#: a yaw moment above a bound by more than this counts as beyond it (the QP's tolerance) [N m]
TOL = 0.01


@dataclass
class TickRow:
    """One single-support tick's stance-foot quantities (see the module doc)."""

    t: float
    side: int
    fallback: bool
    fz: float
    cop: np.ndarray
    cop_frac: float
    tz: float
    bound_qp: float
    bound_cwc: float
    n_points: int
    fz_meas: float
    cop_meas: np.ndarray
    tz_meas: float
    yaw_rate: float


def cwc_torsion_bound(f: np.ndarray, tau: np.ndarray, mu: float, X: float, Y: float) -> float:
    """The largest yaw moment [N m] on ``tau[2]``'s side that a rectangle of half-sizes X, Y [m] with friction
    ``mu`` (a pyramid at each corner) carries under the sole-frame force ``f`` and moments ``tau`` (about the
    rectangle's centre), by Caron et al. (2015): negative when no yaw moment of that sign is possible."""
    fx, fy, fz = f
    tx, ty = tau[0], tau[1]
    if tau[2] >= 0.0:
        return mu * (X + Y) * fz - abs(Y * fx + mu * tx) - abs(X * fy + mu * ty)
    return mu * (X + Y) * fz - abs(Y * fx - mu * tx) - abs(X * fy - mu * ty)


class Recorder:
    """Wraps the controller's tick: records the QP's stance wrench and MuJoCo's contact at each tick."""

    def __init__(self, robot: object) -> None:
        self.robot = robot
        self.rows: list[TickRow] = []
        self.sim: object | None = None
        self._orig = WholeBodyController.solve_tick
        rec = self

        def solve_tick(wbc: WholeBodyController, q, v, ref):  # type: ignore[no-untyped-def]
            out = wbc.solve(q, v, ref)
            rec.record(wbc, ref, out)
            return out.tau, out.status_code, bool(out.used_fallback), out.errors.angular_momentum

        WholeBodyController.solve_tick = solve_tick  # type: ignore[method-assign]

    # the loop's on_tick hook: only to get the simulator
    def set_scene(self, *args: object, **kwargs: object) -> None:
        """The viewer's scene call: nothing to draw."""

    def __call__(self, t: float, sim: object, gait: object) -> None:
        if self.sim is None:
            m = sim.model  # type: ignore[attr-defined]
            self.body_ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n)
                             for n in (self.robot.left_foot_body, self.robot.right_foot_body)]  # type: ignore[attr-defined]
        self.sim = sim

    def record(self, wbc: WholeBodyController, ref: object, out: object) -> None:
        sim = self.sim
        contact = tuple(bool(c) for c in ref.contact)  # type: ignore[attr-defined]
        if sim is None or sum(contact) != 1:
            return
        k = 0 if contact[0] else 1
        terms = wbc.last_terms()
        R = np.asarray(terms["R_sole"][k])
        p = np.asarray(terms["p_sole"][k])
        r = self.robot
        mu = wbc.friction
        s = wbc.params.cop_safety_factor
        X, Y = s * 0.5 * r.foot_length, s * 0.5 * r.foot_width  # type: ignore[attr-defined]
        c = np.asarray(self.centers[k])
        w = np.asarray(out.wrenches[k])  # type: ignore[attr-defined]
        f, tau = R.T @ w[:3], R.T @ w[3:]
        # moments about the CoP rectangle's centre c (sole frame, z = 0)
        tau_c = tau - np.cross(np.array([c[0], c[1], 0.0]), f)
        fz = float(f[2])
        cop = np.array([-tau_c[1], tau_c[0]]) / fz if fz > 1e-6 else np.full(2, np.nan)
        frac = float(max(abs(cop[0]) / X, abs(cop[1]) / Y)) if fz > 1e-6 else math.nan
        n, fm, tm = self._measured(sim, k, R, p + R @ np.array([c[0], c[1], 0.0]))
        cop_m = np.array([-tm[1], tm[0]]) / fm[2] if fm[2] > 1e-6 else np.full(2, np.nan)
        m, d = sim.model, sim.data  # type: ignore[attr-defined]
        vel = np.zeros(6)
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_BODY, self.body_ids[k], vel, 0)
        self.rows.append(TickRow(float(d.time), k, bool(out.used_fallback), fz, cop, frac, float(tau_c[2]),  # type: ignore[attr-defined]
                                 mu * min(X, Y) * fz, cwc_torsion_bound(f, tau_c, mu, X, Y), n,
                                 float(fm[2]), cop_m, float(tm[2]), float(vel[2])))

    def _measured(self, sim: object, k: int, R: np.ndarray, origin: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
        """MuJoCo's contact on foot ``k``: (points, force, moment about ``origin``), both in the sole frame."""
        m, d = sim.model, sim.data  # type: ignore[attr-defined]
        b = self.body_ids[k]
        n, F, T = 0, np.zeros(3), np.zeros(3)
        f6 = np.zeros(6)
        for i in range(d.ncon):
            con = d.contact[i]
            b1, b2 = m.geom_bodyid[con.geom1], m.geom_bodyid[con.geom2]
            if b not in (b1, b2):
                continue
            n += 1
            mujoco.mj_contactForce(m, d, i, f6)
            frame = con.frame.reshape(3, 3)
            fw = frame.T @ f6[:3]
            if b == b1:
                fw = -fw
            F += fw
            T += np.cross(con.pos - origin, fw)
        return n, R.T @ F, R.T @ T


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("robot", help="MODEL.xml (with its layout) or a robot name")
    ap.add_argument("--scenario", default="circle", choices=("circle", "overtake", "walk", "stones"))
    ap.add_argument("--duration", type=float, default=6.0, help="simulated time [s]")
    ap.add_argument("--speed", type=float, default=0.5, help="walk's speed [m/s]")
    ap.add_argument("--yaw-rate", type=float, default=0.0, help="walk's yaw rate [rad/s]")
    ap.add_argument("--obstacle-speed", type=float, default=0.3, help="overtake's obstacle speed [m/s]")
    ap.add_argument("--layout", default=None, help="the layout file")
    ap.add_argument("--spin", type=float, default=2.0, help="a spin: |yaw rate| above this [rad/s]")
    ap.add_argument("--wbc", action="append", default=[], metavar="KEY=VALUE", help="a WbcParams override")
    args = ap.parse_args()
    if args.layout is not None:
        use_layout(args.robot, args.layout)
    robot = load_robot(args.robot)
    rec = Recorder(robot)
    from lipmpcc.robots.wbc_model import sole_cop_centers

    rec.centers = sole_cop_centers(robot, mujoco.MjModel.from_xml_path(str(robot.mjcf_path)))  # type: ignore[attr-defined]
    summary = _run(robot, rec, args)
    print(summary)
    _report(rec.rows, args.spin)


def _run(robot: object, rec: Recorder, args: argparse.Namespace) -> dict:
    """One run with ``rec`` hooked in; its summary's main fields."""
    if args.scenario == "walk":  # the CLI's run walk: the capture-point walker, the layout's sizes
        from lipmpcc.loops.fullbody.loop import FullBodyLoop
        from lipmpcc.planners.capture_point import CapturePointPlanner
        from lipmpcc.studies.walking import capture_point_params

        planner = CapturePointPlanner(capture_point_params(robot), speed=args.speed, yaw_rate=args.yaw_rate)  # type: ignore[arg-type]
        res = FullBodyLoop(robot, planner=planner).run(duration=args.duration, on_tick=rec)  # type: ignore[arg-type]
        return {"fell": res.fell, "steps": res.n_steps, "qp_failures": res.summary().get("qp_failures")}
    if args.scenario == "stones":  # paper B's profile I scaled to the robot, ALIP-MPC (the CLI's run stones)
        from lipmpcc.studies import stepping_stones
        from lipmpcc.studies.stone_course import CourseScale, scaled_profile

        run_s = stepping_stones.simulate_full_body(robot, "alip-mpc", scaled_profile("I", CourseScale.for_robot(robot)),  # type: ignore[arg-type]
                                                   viewer=rec)  # type: ignore[arg-type]
        return {k: run_s.metrics.get(k) for k in ("fall_reason", "stones_reached", "step_rmse_m", "solver_failures")}
    from lipmpcc.studies.path_following import simulate_full_body

    run = simulate_full_body(robot, args.scenario, duration=args.duration, viewer=rec,  # type: ignore[arg-type]
                             obstacle_speed=args.obstacle_speed if args.scenario == "overtake" else None)
    s = run.summary
    return {k: s.get(k) for k in ("fell", "fall_time_s", "fall_reason", "steps", "contouring_error_rms_m",
                                  "qp_failures")}


def _report(rows: list[TickRow], spin: float) -> None:
    """Shares over the single-support ticks and the ticks around each spin."""
    ok = [r for r in rows if not r.fallback and r.fz > 1.0]
    if not ok:
        print("no single-support ticks")
        return
    tz = np.array([abs(r.tz) for r in ok])
    bq = np.array([r.bound_qp for r in ok])
    bc = np.array([r.bound_cwc for r in ok])
    frac = np.array([r.cop_frac for r in ok])
    npts = np.array([r.n_points for r in ok])
    wz = np.array([abs(r.yaw_rate) for r in ok])
    print(f"single-support ticks (QP solved): {len(ok)}")
    print(f"  |tz| at the QP's torsion bound (>= 0.98 of it): {np.mean(tz >= 0.98 * bq):.1%}")
    print(f"  |tz| above what the rectangle carries at the commanded CoP (CWC): {np.mean(tz > np.maximum(bc, 0) + TOL):.1%}"
          f" (CWC bound < 0: {np.mean(bc < 0):.1%})")
    print(f"  commanded CoP at >= 0.98 of the QP rectangle: {np.mean(frac >= 0.98):.1%}")
    for lab, sel in (("<= 1 MuJoCo point", npts <= 1), ("2 points", npts == 2), (">= 3 points", npts >= 3)):
        if sel.any():
            print(f"  {lab}: {np.mean(sel):.1%} of ticks; there |tz|/bound_qp median {np.median(tz[sel] / bq[sel]):.2f},"
                  f" CoP frac median {np.median(frac[sel]):.2f}, |yaw rate| median {np.median(wz[sel]):.2f} rad/s,"
                  f" tz > CWC {np.mean(tz[sel] > np.maximum(bc[sel], 0) + TOL):.1%}")
    print("  t      side pts  fz_qp  cop_qp(x,y)      frac  tz_qp  bnd_qp bnd_cwc | fz_mj  cop_mj(x,y)     tz_mj  wz")
    last = -1.0
    for r in rows:
        if abs(r.yaw_rate) > spin and r.t - last > 0.05:
            for q in rows:
                if r.t - 0.03 <= q.t <= r.t + 0.01:
                    print(f"  {q.t:6.3f} {q.side:d} {q.n_points:3d} {q.fz:6.1f} ({q.cop[0]:+.3f},{q.cop[1]:+.3f}) "
                          f"{q.cop_frac:5.2f} {q.tz:+6.2f} {q.bound_qp:6.2f} {q.bound_cwc:+6.2f} | {q.fz_meas:6.1f} "
                          f"({q.cop_meas[0]:+.3f},{q.cop_meas[1]:+.3f}) {q.tz_meas:+6.2f} {q.yaw_rate:+5.1f}"
                          f"{' FB' if q.fallback else ''}")
            print("  --")
            last = r.t


if __name__ == "__main__":
    main()
