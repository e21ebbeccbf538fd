"""The MPCC's condensed SQP per solve: the Python loop, its C++ port (lipmpcc._sqp) and IPOPT, in one run.

Each scenario of ``bench_mpcc.py`` (fixed T) and ``bench_mpcc_timed.py`` (timed, planning at each support
exchange) walks the 3D-LIP closed loop three times: with the SQP on its Python backend, on its C++ backend
(``LIPMPCC_SQP_BACKEND``) and with IPOPT. Prints per solve the median / p90 of the SQP call alone
(``CondensedSqp.solve``) and of the planner's whole ``solve_time`` (closest point, barrier parameters,
guess, roll-out around the SQP), the IPOPT planner's, and which backend ran (a problem whose CasADi
function is too large for the JIT stays on Python, e.g. the timed MPCC with an obstacle slot; raise
``LIPMPCC_JIT_MAX_INSTRUCTIONS`` to compile it). The first (cold) solve of each run is left out.

    python benchmarks/bench_sqp.py [--steps N] [--only fixed|timed] [--no-ipopt]

``--against DIR`` compares two commits instead: DIR is another commit's ``python/`` folder (e.g. ``git archive
HEAD~1 python | tar -x -C /tmp/prev``, its compiled modules copied beside); each scenario's closed loop runs
``--repeat`` times on the C++ backend with this commit's package and with DIR's, interleaved, each run in a
fresh process (this script as the worker, ``PYTHONPATH`` selecting the package), and once with IPOPT (this
commit's package); per solve the planner's ``solve_time`` and the SQP call (wall), medians / p90 over all runs.

``--convexification eigen_clip,modified_cholesky`` runs each scenario's closed loop on the C++ backend once per
convexification of the SQP's Hessian (``LIPMPCC_SQP_CONVEXIFICATION``), in this process, ``--repeat`` rounds
interleaved; per solve the SQP call (wall and CPU) and the planner's ``solve_time``, and the loop's solver failures.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense problems: one BLAS thread

import argparse
import json
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

from lipmpcc.loops import lip as lip_loop
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import ArcPath, LinePath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner
from lipmpcc.solvers.condensed_sqp import CondensedSqp
from lipmpcc.solvers.convexify import CONVEXIFICATION_ENV, CONVEXIFICATIONS


def scenarios(steps: int, only: str | None):
    """(label, path, planner factory for a solver name, obstacles, pushes, steps)."""
    circle = ArcPath.circle(2.0, turns=1.25)
    line = LinePath((0, 0), (40, 0))
    pushes = lip_loop.random_pushes(steps * 0.4, np.random.default_rng(0))
    fixed = lambda prm: lambda path, solver: MpccPlanner(path, prm.with_(solver=solver))  # noqa: E731
    timed = lambda prm: lambda path, solver: TimedMpccPlanner(  # noqa: E731
        path, TimedMpccParams(mpcc=prm.with_(solver=solver), T_min=0.3, T_max=0.5))
    if only in (None, "fixed"):
        yield "fixed circle", circle, fixed(MpccParams.circle()), [], [], steps
        yield "fixed circle-push", circle, fixed(MpccParams.circle()), [], pushes, steps
        yield "fixed overtake-cart", line, fixed(MpccParams.overtake_cartesian()), [Obstacle.circle(0.25, path=line, s0=1.5, speed=0.1)], [], 70
        yield "fixed overtake-mpcc", line, fixed(MpccParams.overtake_mpcc()), [Obstacle.circle(0.25, path=line, s0=1.5, speed=0.6)], [], 70
    if only in (None, "timed"):
        yield "timed circle", circle, timed(MpccParams.circle()), [], [], steps
        yield "timed circle-push", circle, timed(MpccParams.circle()), [], pushes, steps
        yield "timed overtake-0.8", line, timed(MpccParams.overtake_mpcc()), [Obstacle.circle(0.25, path=line, s0=1.0, speed=0.8)], [], 45
        yield "timed line-push", line, timed(MpccParams.overtake_mpcc()), [], pushes, steps


def run(make, path, solver: str, obstacles, pushes, steps: int, log_out: list | None = None,
        ) -> tuple[np.ndarray, np.ndarray, Counter, np.ndarray]:
    """One closed loop: (SQP call wall times [s], planner solve times [s], backends used, SQP call CPU times of
    the calling thread [s]: less sensitive to other jobs on the machine), the first solve dropped."""
    calls: list[float] = []
    cpu: list[float] = []
    used: Counter = Counter()
    original = CondensedSqp.solve

    def timed_solve(self, u0, params):
        c0, t0 = time.thread_time(), time.perf_counter()
        sol = original(self, u0, params)
        calls.append(time.perf_counter() - t0)
        cpu.append(time.thread_time() - c0)
        used[self.backend] += 1
        return sol

    CondensedSqp.solve = timed_solve
    try:
        pl = make(path, solver)
        prm = pl.params.mpcc if hasattr(pl.params, "mpcc") else pl.params
        log = lip_loop.run_lip_loop(pl, np.zeros(5), steps, path, obstacles, pushes,
                                    robot_radius=prm.robot_radius, foot_radius=prm.foot_radius)
    finally:
        CondensedSqp.solve = original
    if log_out is not None:
        log_out.append(log)
    return np.array(calls[1:]), np.asarray(log.solve_time[1:]), used, np.array(cpu[1:])


def _ms(a: np.ndarray) -> str:
    return f"{1e3 * np.median(a):7.3f} {1e3 * np.percentile(a, 90):7.3f}" if len(a) else f"{'-':>7s} {'-':>7s}"


def _worker(label: str, steps: int, solver: str) -> None:
    """One closed loop of scenario ``label`` (the package on ``PYTHONPATH``): JSON on stdout."""
    for lab, path, make, obstacles, pushes, n in scenarios(steps, None):
        if lab == label:
            calls, planner, used, _ = run(make, path, solver, obstacles, pushes, n)
            print(json.dumps({"sqp": calls.tolist(), "planner": planner.tolist(), "backends": dict(used)}))
            return
    raise SystemExit(f"bench_sqp: no scenario {label!r}")


def _spawn(python_dir: str, label: str, steps: int, solver: str) -> dict:
    """:func:`_worker` in a fresh process with ``python_dir`` first on ``PYTHONPATH``."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([python_dir, *filter(None, [os.environ.get("PYTHONPATH")])]))
    env.pop("LIPMPCC_SQP_BACKEND", None)
    out = subprocess.run([sys.executable, __file__, "--worker", label, "--steps", str(steps), "--solver", solver],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def compare(against: str, steps: int, only: str | None, repeat: int, ipopt: bool) -> None:
    """This commit's C++ planner against the one of the package in ``against``, and IPOPT (see the docstring)."""
    here = str(Path(__file__).resolve().parents[1] / "python")
    print(f"per solve, median / p90 [ms] over {repeat} interleaved runs each; this: {here}; previous: {against}")
    print(f"{'scenario':20s} {'prev planner':>15s} {'this planner':>15s} {'prev sqp':>15s} {'this sqp':>15s} "
          f"{'IPOPT planner':>15s} {'IPOPT/this':>10s} {'this/prev':>9s}  backends (this)")
    total: dict[str, list[np.ndarray]] = {k: [] for k in ("pp", "tp", "ps", "ts", "ip")}
    for label, *_ in scenarios(steps, only):
        runs: dict[str, list[dict]] = {"prev": [], "this": []}
        for _ in range(repeat):
            runs["prev"].append(_spawn(against, label, steps, "sqp"))
            runs["this"].append(_spawn(here, label, steps, "sqp"))
        cat = {k: {f: np.concatenate([r[f] for r in v]) for f in ("sqp", "planner")} for k, v in runs.items()}
        ip = np.array(_spawn(here, label, steps, "ipopt")["planner"]) if ipopt else np.array([])
        row = {"pp": cat["prev"]["planner"], "tp": cat["this"]["planner"], "ps": cat["prev"]["sqp"],
               "ts": cat["this"]["sqp"], "ip": ip}
        for k, v in row.items():
            total[k].append(v)
        _compare_row(label, row, runs["this"][0]["backends"])
    _compare_row("all", {k: np.concatenate(v) for k, v in total.items()}, None)


def compare_convexifications(convs: list[str], steps: int, only: str | None, repeat: int) -> None:
    """Each scenario's closed loop on the C++ backend per convexification, ``repeat`` rounds interleaved."""
    print(f"per solve, median / p90 [ms] over {repeat} closed loops each (interleaved); sqp: CondensedSqp.solve (wall, cpu);"
          " planner: solve_time; failures: the loops' solver failures")
    print(f"{'scenario':20s} {'convexification':18s} {'sqp':>15s} {'sqp cpu':>15s} {'planner':>15s} {'failures':>8s}")
    previous = os.environ.get(CONVEXIFICATION_ENV)
    try:
        for label, path, make, obstacles, pushes, n in scenarios(steps, only):
            rows: dict[str, list] = {c: [[], [], [], 0] for c in convs}
            for _ in range(repeat):
                for c in convs:
                    os.environ[CONVEXIFICATION_ENV] = c
                    logs: list = []
                    sqp, planner, _, cpu = run(make, path, "sqp", obstacles, pushes, n, logs)
                    for acc, v in zip(rows[c], (sqp, cpu, planner)):
                        acc.append(v)
                    rows[c][3] += int(np.sum(logs[0].fallback))
            for c in convs:
                sqp, cpu, planner = (np.concatenate(v) for v in rows[c][:3])
                print(f"{label:20s} {c:18s} {_ms(sqp)} {_ms(cpu)} {_ms(planner)} {rows[c][3]:8d}", flush=True)
    finally:
        os.environ.pop(CONVEXIFICATION_ENV, None)
        if previous is not None:
            os.environ[CONVEXIFICATION_ENV] = previous


def _compare_row(label: str, row: dict[str, np.ndarray], backends: dict | None) -> None:
    r_ip = f"{np.median(row['ip']) / np.median(row['tp']):9.1f}x" if len(row["ip"]) else f"{'-':>10s}"
    r_tp = f"{np.median(row['tp']) / np.median(row['pp']):8.2f}x"
    print(f"{label:20s} {' '.join(_ms(row[k]) for k in ('pp', 'tp', 'ps', 'ts', 'ip'))} {r_ip} {r_tp}"
          f"  {backends if backends is not None else ''}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=60, help="steps of the circle and push runs")
    ap.add_argument("--only", choices=("fixed", "timed"), default=None)
    ap.add_argument("--no-ipopt", action="store_true", help="skip the IPOPT runs")
    ap.add_argument("--against", metavar="DIR", help="compare with the lipmpcc package in DIR (another commit's python/)")
    ap.add_argument("--repeat", type=int, default=3, help="with --against: runs per commit and scenario")
    ap.add_argument("--convexification", default=None,
                    help=f"comma-separated, of {', '.join(CONVEXIFICATIONS)}: the C++ closed loops per convexification")
    ap.add_argument("--worker", metavar="SCENARIO", help=argparse.SUPPRESS)
    ap.add_argument("--solver", default="sqp", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        return _worker(args.worker, args.steps, args.solver)
    if args.convexification:
        convs = args.convexification.split(",")
        bad = [c for c in convs if c not in CONVEXIFICATIONS]
        if bad:
            raise SystemExit(f"bench_sqp: --convexification {bad[0]!r}: expected one of {', '.join(CONVEXIFICATIONS)}")
        return compare_convexifications(convs, args.steps, args.only, args.repeat)
    if args.against:
        return compare(args.against, args.steps, args.only, args.repeat, not args.no_ipopt)
    print("per solve, median and p90 [ms]; sqp: CondensedSqp.solve alone (wall; cpu: the thread's CPU time);"
          " planner: the planner's solve_time (wall)")
    print(f"{'scenario':20s} {'py sqp':>15s} {'C++ sqp':>15s} {'py sqp cpu':>15s} {'C++ sqp cpu':>15s} "
          f"{'py planner':>15s} {'C++ planner':>15s} {'IPOPT planner':>15s} {'IPOPT/C++':>9s}  backends")
    keys = ("py", "cpp", "py_cpu", "cpp_cpu", "py_pl", "cpp_pl", "ipopt")
    total: dict[str, list[np.ndarray]] = {k: [] for k in keys}
    for label, path, make, obstacles, pushes, steps in scenarios(args.steps, args.only):
        out = {}
        for backend in ("python", "cpp"):
            os.environ["LIPMPCC_SQP_BACKEND"] = "python" if backend == "python" else "auto"
            out[backend] = run(make, path, "sqp", obstacles, pushes, steps)
        os.environ.pop("LIPMPCC_SQP_BACKEND", None)
        ipopt = np.array([]) if args.no_ipopt else run(make, path, "ipopt", obstacles, pushes, steps)[1]
        (py, py_pl, _, py_cpu), (cc, cc_pl, used, cc_cpu) = out["python"], out["cpp"]
        row = dict(zip(keys, (py, cc, py_cpu, cc_cpu, py_pl, cc_pl, ipopt)))
        ratio = f"{np.median(ipopt) / np.median(cc_pl):8.1f}x" if len(ipopt) else f"{'-':>9s}"
        print(f"{label:20s} {' '.join(_ms(row[k]) for k in keys)} {ratio}  {dict(used)} ({len(cc)} solves)")
        for k in keys:
            total[k].append(row[k])
    all_ = {k: np.concatenate(v) for k, v in total.items()}
    ratio = f"{np.median(all_['ipopt']) / np.median(all_['cpp_pl']):8.1f}x" if len(all_["ipopt"]) else ""
    print(f"{'all':20s} {' '.join(_ms(all_[k]) for k in keys)} {ratio}")


if __name__ == "__main__":
    main()
