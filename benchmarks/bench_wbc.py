"""Benchmark of the whole-body QP on digit_like (prints a table; ``--json PATH`` also saves it).

Measured in one run:

1. **WBC tick** (C++: Pinocchio terms + QP assembly + proxsuite solve + efforts), median and p90, in
   a closed-loop MuJoCo run that exercises the QP: a COM shift onto the right foot in double
   support, unloading of the left foot, a 5 cm swing of the left foot in single support, touch-down
   and the shift back. Also the wall time of the Python call ``WholeBodyController.solve`` (input
   checks and conversions included) and the same figures for static standing.
2. **Python reference**: the same QPs (states and references recorded in run 1) built with numpy
   from pinocchio-python and solved by qpsolvers/proxqp (``lipmpcc.control.reference_qp``), and the
   ratio of its median to the C++ tick median on those QPs.
3. **Real-time factor** of simulation + WBC (``RobotSim`` at 2 kHz, standing on the ``stand``
   keyframe) with the controller at 400 Hz and at 1 kHz.
4. **Time per mj_step** of the digit_like scene (standing, constant commands).

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

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from lipmpcc.config import horizon  # noqa: E402
from lipmpcc.control.wbc import WholeBodyController  # noqa: E402
from lipmpcc.control.wbc_types import WbcReference  # noqa: E402
from lipmpcc.metrics import timing_stats_ms  # noqa: E402
from lipmpcc.sim.robot_sim import RobotSim  # noqa: E402
from lipmpcc.control.reference_qp import ReferenceWbcQp  # noqa: E402


def _quintic(s: float) -> tuple[float, float, float]:
    s = min(max(s, 0.0), 1.0)
    return 10 * s**3 - 15 * s**4 + 6 * s**5, 30 * s**2 - 60 * s**3 + 30 * s**4, 60 * s - 180 * s**2 + 120 * s**3


def shift_and_lift(wbc: WholeBodyController, record_every: int) -> dict:
    """Closed loop at 2 kHz / 400 Hz: COM shift, foot lift (single support), touch-down, shift back."""
    wbc.reset()
    sim = RobotSim(wbc.description)
    sim.reset("stand")
    q, _ = sim.pinocchio_state()
    ref = wbc.hold_reference(q)
    com_c = ref.com_pos.copy()
    com_r = com_c.copy()
    com_r[1] = ref.foot_pos[1][1]
    p_left = ref.foot_pos[0].copy()
    shift, t_unload, t_lift, t_swing, height = 1.5, 1.5, 1.7, 1.2, 0.05
    ticks, walls, modes, recorded = [], [], [], []
    for k in range(int(4.7 * 400)):
        t = sim.time
        a, b = (com_c, com_r) if t < 3.0 else (com_r, com_c)
        s, ds, dds = _quintic((t if t < 3.0 else t - 3.0) / shift)
        ref.com_pos, ref.com_vel, ref.com_acc = a + s * (b - a), ds / shift * (b - a), dds / shift**2 * (b - a)
        swing = t_lift <= t < t_lift + t_swing
        ref.contact = (not swing, True)
        ramp = (t - t_unload) / (t_lift - t_unload)
        ref.max_normal_force = (400.0 * (1.0 - ramp) + 1.0 if 0.0 <= ramp < 1.0 else np.inf, np.inf)
        z = dz = ddz = 0.0
        if swing:
            w = 2 * np.pi / t_swing
            ph = (t - t_lift) * w
            z, dz, ddz = height * np.sin(ph / 2) ** 2, height * w / 2 * np.sin(ph), height * w**2 / 2 * np.cos(ph)
        ref.foot_pos = np.stack([p_left + [0.0, 0.0, z], ref.foot_pos[1]])
        ref.foot_vel = np.array([[0.0, 0.0, dz], [0.0, 0.0, 0.0]])
        ref.foot_acc = np.array([[0.0, 0.0, ddz], [0.0, 0.0, 0.0]])
        q, v = sim.pinocchio_state()
        w0 = time.perf_counter()
        out = wbc.solve(q, v, ref)
        walls.append(time.perf_counter() - w0)
        ticks.append(out.tick_time_us * 1e-6)
        modes.append("single" if swing else "double")
        if k % record_every == 0:
            fields = {f: np.array(getattr(ref, f), dtype=float) for f in ref.__dataclass_fields__ if f != "contact"}
            snapshot = WbcReference(contact=tuple(ref.contact), **fields)
            recorded.append((q, v, snapshot))
        sim.step(out.tau, 5)
    if sim.fallen():
        raise RuntimeError(f"the robot fell during the benchmark run: {sim.fall_reason()}")
    return dict(ticks=np.array(ticks), walls=np.array(walls), modes=np.array(modes), recorded=recorded,
                failures=wbc.qp_failures)


def standing_loop(wbc: WholeBodyController, duration: float, steps_per_tick: int) -> dict:
    """RobotSim + WBC holding the stand keyframe; returns the real-time factor and tick times."""
    wbc.reset()
    sim = RobotSim(wbc.description)
    sim.reset("stand")
    q, _ = sim.pinocchio_state()
    ref = wbc.hold_reference(q)
    n_ticks = int(round(duration / (steps_per_tick * sim.timestep)))
    ticks, walls = [], []
    t0 = time.perf_counter()
    for _ in range(n_ticks):
        q, v = sim.pinocchio_state()
        w0 = time.perf_counter()
        out = wbc.solve(q, v, ref)
        walls.append(time.perf_counter() - w0)
        ticks.append(out.tick_time_us * 1e-6)
        sim.step(out.tau, steps_per_tick)
    wall = time.perf_counter() - t0
    if sim.fallen():
        raise RuntimeError(f"the robot fell while standing: {sim.fall_reason()}")
    return dict(rtf=sim.time / wall, ticks=np.array(ticks), walls=np.array(walls), sim_time=sim.time,
                failures=wbc.qp_failures)


def mj_step_time(wbc: WholeBodyController, n: int) -> dict:
    """Raw mujoco.mj_step on the digit_like scene, standing with the WBC's standing efforts held."""
    sim = RobotSim(wbc.description)
    sim.reset("stand")
    q, v = sim.pinocchio_state()
    wbc.reset()
    sim.data.ctrl[:] = wbc.solve(q, v, wbc.hold_reference(q)).tau
    m, d = sim.model, sim.data
    batch = 100
    times = []
    for _ in range(max(1, n // batch)):
        t0 = time.perf_counter()
        for _ in range(batch):
            mujoco.mj_step(m, d)
        times.append((time.perf_counter() - t0) / batch)
    return timing_stats_ms(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", type=Path, default=None, help="also write the figures to this JSON file")
    args = parser.parse_args()

    wbc = WholeBodyController("digit_like")
    results: dict = {
        "machine": f"{platform.machine()}, {os.cpu_count()} cores, {platform.python_implementation()} "
        f"{platform.python_version()}, load average {os.getloadavg()[0]:.1f} at start",
    }

    # 1. WBC tick in a closed loop that uses the QP
    run = shift_and_lift(wbc, record_every=int(horizon(4, 20)))
    tick = timing_stats_ms(run["ticks"])
    results["wbc_tick_ms"] = tick
    results["wbc_tick_ms_double_support"] = timing_stats_ms(run["ticks"][run["modes"] == "double"])
    results["wbc_tick_ms_single_support"] = timing_stats_ms(run["ticks"][run["modes"] == "single"])
    results["wbc_python_call_ms"] = timing_stats_ms(run["walls"])
    results["qp_failures"] = run["failures"]
    results["qp_size_double_support"] = "38 variables, 18 equalities, 42 inequalities"
    results["qp_size_single_support"] = "32 variables, 12 equalities, 31 inequalities"

    # 2. the same QPs through the numpy/qpsolvers reference, and through C++ again (fresh warm start)
    reference = ReferenceWbcQp(wbc.model.spec, wbc.params)
    wbc.reset()
    cpp_times, ref_times, max_dev = [], [], 0.0
    for q, v, ref in run["recorded"]:
        out = wbc.solve(q, v, ref)
        cpp_times.append(out.tick_time_us * 1e-6)
        t0 = time.perf_counter()
        reference.solve(q, v, ref, eps=wbc.params.qp_eps_abs)  # same tolerance as the C++ solve
        ref_times.append(time.perf_counter() - t0)
        exact = reference.solve(q, v, ref, eps=1e-10)  # not timed: accuracy of the C++ efforts
        if exact.found and out.status == "solved":
            max_dev = max(max_dev, float(np.max(np.abs(out.tau - exact.tau))))
    cpp_same = timing_stats_ms(cpp_times)
    ref_stats = timing_stats_ms(ref_times)
    results["python_reference_ms"] = ref_stats
    results["cpp_tick_on_same_qps_ms"] = cpp_same
    results["python_reference_over_cpp_median"] = ref_stats["median"] / cpp_same["median"]
    results["max_abs_tau_difference_nm"] = max_dev

    # 3. real-time factors (standing)
    duration = float(horizon(5.0, 1.0))
    for hz, sub in (("400", 5), ("1000", 2)):
        r = standing_loop(wbc, duration, sub)
        results[f"rtf_2khz_{hz}hz"] = r["rtf"]
        results[f"standing_tick_ms_{hz}hz"] = timing_stats_ms(r["ticks"])
        results[f"standing_python_call_ms_{hz}hz"] = timing_stats_ms(r["walls"])

    # 4. mj_step
    results["mj_step_ms"] = mj_step_time(wbc, int(horizon(20000, 2000)))

    def fmt(s: dict) -> str:
        return f"median {s['median'] * 1e3:7.1f} us   p90 {s['p90'] * 1e3:7.1f} us   (n = {s['n']})"

    print("Whole-body QP benchmark, digit_like (nv = 26, nu = 20)")
    print(f"  machine: {results['machine']}")
    print(f"  QP: double support {results['qp_size_double_support']}; single {results['qp_size_single_support']}")
    print("  1. WBC tick, C++ (Pinocchio terms + QP), shift/lift/touch-down run:")
    print(f"       all ticks           {fmt(tick)}")
    print(f"       double support      {fmt(results['wbc_tick_ms_double_support'])}")
    print(f"       single support      {fmt(results['wbc_tick_ms_single_support'])}")
    print(f"       Python call         {fmt(results['wbc_python_call_ms'])}")
    print(f"       QP failures         {results['qp_failures']}")
    print("  2. the same QPs:")
    print(f"       numpy + qpsolvers   {fmt(ref_stats)}")
    print(f"       C++                 {fmt(cpp_same)}")
    print(f"       ratio (median)      {results['python_reference_over_cpp_median']:.0f}x slower in Python"
          f"   (max |tau_cpp - tau_exact| = {max_dev:.1e} N m)")
    print("  3. real-time factor, RobotSim 2 kHz + WBC, standing:")
    for hz in ("400", "1000"):
        print(f"       WBC at {hz:>4} Hz: {results[f'rtf_2khz_{hz}hz']:5.1f}x real time   "
              f"tick {fmt(results[f'standing_tick_ms_{hz}hz'])}")
    print(f"  4. mj_step               {fmt(results['mj_step_ms'])}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=2))
        print(f"  written to {args.json}")


if __name__ == "__main__":
    main()
