"""Why a full body lags the ALIP on the stones: per single-support tick, the whole-body QP's stance centre of
pressure against its box, the centroidal angular momentum rate and the COM's lag behind the loop's reference.

    PYTHONPATH=python python3 benchmarks/diag_stones_com.py MODEL.xml [--layout FILE] [--stones N]
        [--robot-param KEY=VALUE ...]

Prints one line: the CoP box (``cop_safety_factor`` of the sole's half-length and half-width), the share of
single-support ticks with the stance CoP within 3 % of the box's edge (x, y), the box's COM-acceleration authority
ω²·box [m/s²] against the 90th percentile of |L̇|/(m h) (the COM acceleration the centroidal angular momentum
takes away when the CoP stays put) and of the COM's lag |c_ref − c| [mm]; then the run's outcome. Measured in
docs/design.md, "Paper B on smaller humanoids" (session 40). The tick hook re-solves through
:meth:`~lipmpcc.control.wbc.WholeBodyController.solve`, which gives the same efforts as the loop's ``solve_tick``.
"""

from __future__ import annotations

import argparse
import ast
from pathlib import Path

import numpy as np

from lipmpcc.control import wbc as wbcmod
from lipmpcc.robots import load_robot
from lipmpcc.studies.stepping_stones import simulate_full_body
from lipmpcc.studies.stone_course import CourseScale, scaled_profile
from lipmpcc.studies.stone_params import stones_wbc_params
from lipmpcc.terrain import make_profile


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model")
    ap.add_argument("--layout", default=None)
    ap.add_argument("--stones", type=int, default=12)
    ap.add_argument("--robot-param", action="append", default=[], metavar="KEY=VALUE",
                    help="a layout field over the layout's (a Python literal), e.g. alip_wbc_overrides=()")
    args = ap.parse_args()
    over = {k: ast.literal_eval(v) for k, v in (a.split("=", 1) for a in args.robot_param)}
    robot = load_robot(args.model if args.model == "digit_like" else Path(args.model), layout=args.layout, **over)
    rows: list[np.ndarray] = []
    solve_tick = wbcmod.WholeBodyController.solve_tick

    def recording(self, q, v, ref):  # type: ignore[no-untyped-def]
        out = self.solve(q, v, ref)
        terms, f = self.last_terms(), out.wrenches
        cops = []
        for i in range(2):
            fz = f[i, 2]
            cop = np.array([-f[i, 4] / fz, f[i, 3] / fz]) if fz > 1e-3 else np.full(2, np.nan)
            cops.append(np.asarray(terms["R_sole"][i])[:2, :2].T @ cop)
        rows.append(np.concatenate([np.asarray(terms["com"]), np.array(ref.com_pos), *cops, out.errors.angular_momentum]))
        return out.tau, out.status_code, bool(out.used_fallback), out.errors.angular_momentum

    wbcmod.WholeBodyController.solve_tick = recording
    try:
        scale = CourseScale.for_robot(robot)
        seq = make_profile("I") if scale is None else scaled_profile("I", scale)
        run = simulate_full_body(robot, "alip-mpc", seq.head(args.stones))
    finally:
        wbcmod.WholeBodyController.solve_tick = solve_tick
    log = run.result.log
    r = np.array(rows)[: len(log.t)]
    t, st = log.t[: len(r)], log.stance[: len(r)]
    com, ref, cop_l, cop_r, L = r[:, 0:3], r[:, 3:6], r[:, 6:8], r[:, 8:10], r[:, 10:13]
    wp = stones_wbc_params(robot)
    box = 0.5 * wp.cop_safety_factor * np.array([robot.foot_length, robot.foot_width])
    h = float(np.median(ref[:, 2]))
    w2, m = 9.81 / h, float(robot.total_mass)
    ss = (st < 2) & (t > t[0] + 1.0) & (t < t[-1] - 0.3)
    cop = np.where((st == 0)[:, None], cop_l, cop_r)[ss]
    sat = np.mean(np.abs(cop) > 0.97 * box, axis=0)
    ldot = np.abs(np.gradient(L, t, axis=0)[ss]) / (m * h)
    lag = np.abs(ref - com)[ss]
    p90 = lambda a: np.percentile(a, 90)  # noqa: E731
    print(f"{robot.name}: CoP box ±{box[0]:.3f} x ±{box[1]:.3f} m; CoP at the edge x {sat[0]:.0%}, y {sat[1]:.0%} of "
          f"single-support ticks; authority w²·box x {w2 * box[0]:.2f}, y {w2 * box[1]:.2f} m/s²; |dL/dt|/(m h) p90 "
          f"sagittal {p90(ldot[:, 1]):.2f}, lateral {p90(ldot[:, 0]):.2f} m/s²; COM lag p90 x {1e3 * p90(lag[:, 0]):.0f}, "
          f"y {1e3 * p90(lag[:, 1]):.0f} mm")
    print(f"fell={run.result.fell} ({run.result.fall_reason or ''}); stones completed {run.metrics['steps_completed']} "
          f"of {args.stones}, step RMSE {run.metrics['step_rmse_m']:.3f} m")


if __name__ == "__main__":
    main()
