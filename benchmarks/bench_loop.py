"""Benchmark of the full-body loop (MuJoCo + C++ whole-body QP + footstep planner) on digit_like.

Prints, for standing (four 50 N pushes) and walking (capture-point planner, 0.6 m/s), at
2 kHz simulation with the WBC at 400 Hz and at 1 kHz:

1. **Real-time factor** (simulated seconds per wall second) of ``FullBodyLoop.run``, best of
   ``--repeat`` runs, and the same per CPU second of the process (``time.process_time``), which is
   less sensitive to other processes sharing the cores.
2. **Tick breakdown** [µs per WBC tick] from a separate, instrumented run (each part wrapped with a
   timer, exclusive of the parts it calls):

   - ``mj_step``: MuJoCo stepping (all sub-steps of the tick: ``mj_step``, ``mj_step2``); with the compiled tick
     (``lipmpcc._mjtick``, the default when it is built) its ``Tick.step``, which also applies the pushes;
   - ``mj_forward``: the one forward pass that makes a tick's measurements current (``mj_forward``, or
     ``mj_step1`` + the acceleration stages, and ``mj_subtreeVel``); with the compiled
     tick its ``Tick.measure``, which also maps the state and sums the contacts (C++);
   - ``sim.step (py)``: ``RobotSim.step`` minus ``mj_step`` (command checks, pushes);
   - ``reads (py)``: ``FullBodyLoop._measure`` minus ``mj_forward`` (state mapping, contacts, poses);
   - ``wbc C++``: the ``_wbc`` solve call; ``wbc.py``: the rest of ``WholeBodyController.solve_tick`` (the loop's call);
   - ``planner``: ``FootstepSource.plan``; ``fall checks``: ``RobotSim.fallen`` outside the reads;
   - ``loop + trajectory``: everything else (gait logic, references, logs).

3. **Time per mj_step** of the digit_like scene (from the standing keyframe, zero commands), per
   step with ``mj_step(nstep=5)``, and per ``mj_forward``.

Usage: ``python benchmarks/bench_loop.py [--repeat N] [--walk-time S] [--stand-time S] [--json PATH]``.
``LIPMPCC_FAST=1`` shortens the runs. Timings depend on the machine's load (this machine's two
cores are shared): compare figures measured in one session, e.g. this checkout against another
(``PYTHONPATH=OTHER/python python benchmarks/bench_loop.py``; the script only uses public APIs, plus
``FullBodyLoop._measure`` and the controller's ``_solver`` for the breakdown).
"""

from __future__ import annotations

import argparse
import functools
import json
import platform
import sys
import time
from pathlib import Path
from typing import Any, Callable

import mujoco

from lipmpcc.config import horizon
from lipmpcc.planners.capture_point import CapturePointPlanner
from lipmpcc.robots import load_robot
from lipmpcc.studies.walking import stand_pushes
from lipmpcc.loops.fullbody import FullBodyLoop, LoopParams

PARTS = (
    "mj_step",
    "mj_forward",
    "sim.step (py)",
    "reads (py)",
    "wbc C++",
    "wbc.py",
    "planner",
    "fall checks",
    "loop + trajectory",
)


# ------------------------------------------------------------------------------------------------
# Exclusive-time instrumentation
# ------------------------------------------------------------------------------------------------
class _Profiler:
    """Wall time per part, exclusive of nested instrumented calls."""

    def __init__(self) -> None:
        self.total: dict[str, float] = {}
        self._stack: list[list[float]] = []  # [start, time of nested parts]

    def wrap(self, part: str, fn: Callable[..., Any]) -> Callable[..., Any]:
        perf = time.perf_counter
        stack = self._stack
        total = self.total
        total.setdefault(part, 0.0)

        @functools.wraps(fn)
        def timed(*args: Any, **kwargs: Any) -> Any:
            frame = [perf(), 0.0]
            stack.append(frame)
            try:
                return fn(*args, **kwargs)
            finally:
                stack.pop()
                elapsed = perf() - frame[0]
                total[part] += elapsed - frame[1]
                if stack:
                    stack[-1][1] += elapsed

        return timed


class _TickProxy:
    """Forwards to the compiled tick (``lipmpcc._mjtick.Tick``), timing ``step`` (MuJoCo's steps and the
    pushes, in C++) as ``mj_step`` and ``measure`` (``mj_forward``, the state map and the contact sums, in
    C++) as ``mj_forward``: with the compiled tick, MuJoCo is called from C++, never through
    ``mujoco.mj_step``."""

    def __init__(self, tick: Any, prof: _Profiler) -> None:
        self._tick = tick
        self.step = prof.wrap("mj_step", tick.step)
        self.measure = prof.wrap("mj_forward", tick.measure)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._tick, name)


class _SolverProxy:
    """Forwards to the C++ solver, timing ``solve_packed``."""

    def __init__(self, solver: Any, prof: _Profiler) -> None:
        self._solver = solver
        self.solve_packed = prof.wrap("wbc C++", solver.solve_packed)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._solver, name)


# ------------------------------------------------------------------------------------------------
# Runs
# ------------------------------------------------------------------------------------------------
def _make_loop(robot: Any, case: str, n_sub: int) -> FullBodyLoop:
    params = LoopParams(sim_steps_per_wbc=n_sub)
    planner = None if case == "stand" else CapturePointPlanner(speed=0.6)
    return FullBodyLoop(robot, planner=planner, params=params)


def _run_kwargs(case: str, duration: float) -> dict:
    if case == "stand":
        spacing = duration / 5.0
        return {"duration": duration, "pushes": stand_pushes(t_first=spacing, spacing=spacing)}
    return {"duration": duration}


def real_time_factor(robot: Any, case: str, n_sub: int, duration: float, repeat: int) -> dict:
    """Best wall and CPU real-time factors over ``repeat`` runs (one loop, warm)."""
    loop = _make_loop(robot, case, n_sub)
    loop.run(**_run_kwargs(case, min(duration, 1.0)))  # warm-up (imports, caches)
    best_wall, best_cpu, final = 0.0, 0.0, None
    for _ in range(repeat):
        c0, w0 = time.process_time(), time.perf_counter()
        res = loop.run(**_run_kwargs(case, duration))
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        if res.fell:
            raise RuntimeError(f"{case} at {n_sub} sub-steps fell at t = {res.fall_time:.2f} s")
        best_wall = max(best_wall, res.sim_time / wall)
        best_cpu = max(best_cpu, res.sim_time / cpu)
        final = res
    return {
        "rtf_wall": best_wall,
        "rtf_cpu": best_cpu,
        "loop_rtf": final.real_time_factor,
        "sim_time": final.sim_time,
        "final_com": final.log.com[-1].tolist(),
        "steps": final.n_steps,
    }


def breakdown(robot: Any, case: str, n_sub: int, duration: float) -> dict:
    """Exclusive time per part per WBC tick [µs] from one instrumented run."""
    loop = _make_loop(robot, case, n_sub)
    loop.run(**_run_kwargs(case, min(duration, 1.0)))  # warm-up
    prof = _Profiler()
    sim, wbc = loop.sim, loop.wbc
    # the Python tick splits a step into mj_step1 + the acceleration stages (the forward pass that makes the
    # measurements current) and mj_step2 (the rest of the step)
    mj_parts = {"mj_step": "mj_step", "mj_step2": "mj_step", "mj_forward": "mj_forward", "mj_step1": "mj_forward",
                "mj_fwdActuation": "mj_forward", "mj_fwdAcceleration": "mj_forward",
                "mj_fwdConstraint": "mj_forward", "mj_sensorAcc": "mj_forward", "mj_subtreeVel": "mj_forward"}
    saved = {name: getattr(mujoco, name) for name in mj_parts}
    try:
        for name, part in mj_parts.items():
            setattr(mujoco, name, prof.wrap(part, saved[name]))
        sim.step = prof.wrap("sim.step (py)", sim.step)
        sim.fallen = prof.wrap("fall checks", sim.fallen)
        loop._measure = prof.wrap("reads (py)", loop._measure)
        wbc.solve_tick = prof.wrap("wbc.py", wbc.solve_tick)  # the loop's call
        tick = getattr(sim, "_tick", None)
        if tick is not None:
            sim._tick = _TickProxy(tick, prof)
        solver = getattr(wbc, "_solver", None)
        if solver is not None:
            wbc._solver = _SolverProxy(solver, prof)
        if loop.planner is not None:
            loop.planner.plan = prof.wrap("planner", loop.planner.plan)
        w0 = time.perf_counter()
        res = loop.run(**_run_kwargs(case, duration))
        wall = time.perf_counter() - w0
    finally:
        for name, fn in saved.items():
            setattr(mujoco, name, fn)
        for name in ("step", "fallen"):
            sim.__dict__.pop(name, None)
        loop.__dict__.pop("_measure", None)
        wbc.__dict__.pop("solve", None)
        if solver is not None:
            wbc._solver = solver
        if tick is not None:
            sim._tick = tick
        if loop.planner is not None:
            loop.planner.__dict__.pop("plan", None)
    ticks = len(res.log.t)
    parts = {k: 1e6 * prof.total.get(k, 0.0) / ticks for k in PARTS if k != "loop + trajectory"}
    parts["loop + trajectory"] = 1e6 * wall / ticks - sum(parts.values())
    parts["tick"] = 1e6 * wall / ticks
    parts["compiled_tick"] = tick is not None
    return parts


def mj_step_time(robot: Any, n: int = 500, repeat: int = 10) -> dict:
    """Time per mj_step and per mj_forward [µs] over the first ``n`` steps from the standing keyframe
    (zero commands: the robot starts to sink, feet in contact), best of ``repeat``."""
    from lipmpcc.sim.robot_sim import RobotSim

    sim = RobotSim(robot)
    m, d = sim.model, sim.data
    out = {"mj_step": float("inf"), "mj_step(nstep=5)": float("inf"), "mj_forward": float("inf")}
    for _ in range(repeat):
        for label, nstep in (("mj_step", 1), ("mj_step(nstep=5)", 5)):
            sim.reset(robot.standing_keyframe)
            t0 = time.perf_counter()
            for _ in range(n // nstep):
                mujoco.mj_step(m, d, nstep)
            out[label] = min(out[label], 1e6 * (time.perf_counter() - t0) / (nstep * (n // nstep)))
        sim.reset(robot.standing_keyframe)
        t0 = time.perf_counter()
        for _ in range(n // 5):
            mujoco.mj_forward(m, d)
        out["mj_forward"] = min(out["mj_forward"], 1e6 * (time.perf_counter() - t0) / (n // 5))
    return out


# ------------------------------------------------------------------------------------------------
def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3, help="runs per real-time factor (best is kept)")
    ap.add_argument("--walk-time", type=float, default=None, help="simulated seconds of walking")
    ap.add_argument("--stand-time", type=float, default=None, help="simulated seconds of standing")
    ap.add_argument("--json", type=Path, default=None, help="also write the figures to this file")
    args = ap.parse_args(argv)
    walk_t = args.walk_time or float(horizon(10.0, 3.0))
    stand_t = args.stand_time or float(horizon(5.0, 2.0))
    robot = load_robot("digit_like")
    results: dict[str, Any] = {"machine": platform.processor() or platform.machine(), "rtf": {}, "breakdown": {}}

    print(f"full-body loop on digit_like, sim 2 kHz; walk {walk_t:g} s, stand {stand_t:g} s (best of {args.repeat})")
    print(f"{'case':14s} {'RTF wall':>9s} {'RTF cpu':>9s}  final COM [m]")
    for case, dur in (("stand", stand_t), ("walk", walk_t)):
        for n_sub, label in ((5, "400 Hz"), (2, "1 kHz")):
            r = real_time_factor(robot, case, n_sub, dur, args.repeat)
            key = f"{case} {label}"
            results["rtf"][key] = r
            com = ", ".join(f"{x:.6f}" for x in r["final_com"])
            print(f"{key:14s} {r['rtf_wall']:9.2f} {r['rtf_cpu']:9.2f}  ({com})", flush=True)

    cases = [("stand", 5, stand_t), ("walk", 5, walk_t), ("walk", 2, walk_t)]
    cols = {}
    for case, n_sub, dur in cases:
        label = f"{case} {'400 Hz' if n_sub == 5 else '1 kHz'}"
        cols[label] = breakdown(robot, case, n_sub, dur)
    results["breakdown"] = cols
    compiled = any(c["compiled_tick"] for c in cols.values())
    print("\ntick breakdown [µs per WBC tick] (instrumented run; wrappers add ~1 µs per call)")
    if compiled:
        print("compiled tick (lipmpcc._mjtick): mj_step = Tick.step (the sub-steps and pushes, C++), mj_forward = "
              "Tick.measure (mj_forward, state map, contact sums, C++); LIPMPCC_PYTHON_TICK=1 for the Python tick")
    print(f"{'part':20s}" + "".join(f"{c:>13s}" for c in cols))
    for part in PARTS + ("tick",):
        print(f"{part:20s}" + "".join(f"{cols[c][part]:13.1f}" for c in cols))

    mj = mj_step_time(robot)
    results["mj_step_us"] = mj
    print("\nMuJoCo alone [µs]: " + ", ".join(f"{k} {v:.1f}" for k, v in mj.items()))
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
