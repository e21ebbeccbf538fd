"""The MPCC planner's solves replayed K times: per solve the best of K (a loaded machine's noise left out).

Each scenario of ``bench_sqp.py`` walks the 3D-LIP closed loop once, recording the planner's ``solve`` calls
(state, side, obstacles, time); then a fresh planner answers the same calls K times over (``reset`` between the
replays: the same solves as the closed loop's). Per solve the minimum over the K replays of the planner's
``solve_time``, of its ``CondensedSqp.solve`` calls and of the whole ``solve()`` call (the input checks and the
result included); medians / p90 over the solves [µs], the first (cold) solve left out. The package on
``PYTHONPATH`` is the one measured (run it once per commit to compare).

    python benchmarks/bench_mpcc_replay.py [--only fixed|timed] [--scenario LABEL,...] [--repeat K]

``--convexification eigen_clip,modified_cholesky`` replays the same recorded calls (recorded with the default)
on one fresh planner per convexification of the SQP's Hessian (``LIPMPCC_SQP_CONVEXIFICATION`` while it is
built), the replays interleaved in this process, one row each. ``--full-eigen`` runs the planners on the partial eigenvalue
clip (``$LIPMPCC_SQP_PARTIAL_EIGEN=1``, opt-in) and adds one whose C++ SQPs use Eigen's full eigendecomposition
(``partial_eigen=False``, the default).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small dense problems: one BLAS thread

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_sqp  # noqa: E402  (the scenarios)

from lipmpcc.loops import lip as lip_loop  # noqa: E402
from lipmpcc.solvers.condensed_sqp import CondensedSqp  # noqa: E402
from lipmpcc.solvers.convexify import CONVEXIFICATION_ENV, CONVEXIFICATIONS, PARTIAL_EIGEN_ENV  # noqa: E402
from lipmpcc.solvers.sqp_compiled import CompiledSqp  # noqa: E402


def _full_eigen(pl) -> None:
    """Every C++ SQP the planner has built, again with ``partial_eigen=False``."""
    for built in pl._built.values():
        sqp = built.get("sqp")
        if sqp is not None and sqp._compiled is not None:
            sqp._compiled = CompiledSqp(sqp.f_all, sqp.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu,
                                        max_iter=sqp.max_iter, tol=sqp.tol, eig_floor=sqp.eig_floor,
                                        second_order_correction=sqp.second_order_correction, rate_stop=sqp.rate_stop,
                                        convexification=sqp.convexification, partial_eigen=False)


def _record(make, path, obstacles, pushes, steps: int) -> tuple[object, list[tuple[tuple, dict]]]:
    """The planner and its ``solve`` calls in one closed loop."""
    pl = make(path, "sqp")
    cls = type(pl)
    calls: list[tuple[tuple, dict]] = []
    original = cls.solve

    def recording(self, *a, **k):
        calls.append((a, k))
        return original(self, *a, **k)

    cls.solve = recording
    prm = pl.params.mpcc if hasattr(pl.params, "mpcc") else pl.params
    try:
        lip_loop.run_lip_loop(pl, np.zeros(5), steps, path, obstacles, pushes, robot_radius=prm.robot_radius,
                              foot_radius=prm.foot_radius)
    finally:
        cls.solve = original
    return pl, calls


def replay(pl, calls: list[tuple[tuple, dict]], repeat: int, convexification: str | None = None) -> np.ndarray:
    """(repeat, solves, 3): solve_time, the SQP calls' wall time and the solve() call's [s] of each replay; with
    ``convexification``, ``LIPMPCC_SQP_CONVEXIFICATION`` is set to it meanwhile (the SQPs the planner builds)."""
    previous_env = os.environ.get(CONVEXIFICATION_ENV)
    if convexification is not None:
        os.environ[CONVEXIFICATION_ENV] = convexification
    sqp_t: list[float] = []
    original = CondensedSqp.solve

    def timed(self, u0, params):
        t0 = time.perf_counter()
        out = original(self, u0, params)
        sqp_t[-1] += time.perf_counter() - t0
        return out

    CondensedSqp.solve = timed
    res = np.full((repeat, len(calls), 3), np.inf)
    try:
        for r in range(repeat):
            pl.reset()
            for i, (a, k) in enumerate(calls):
                sqp_t.append(0.0)
                t0 = time.perf_counter()
                out = pl.solve(*a, **k)
                res[r, i] = (out.solve_time, sqp_t[-1], time.perf_counter() - t0)
    finally:
        CondensedSqp.solve = original
        if convexification is not None:
            os.environ.pop(CONVEXIFICATION_ENV, None)
            if previous_env is not None:
                os.environ[CONVEXIFICATION_ENV] = previous_env
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=60, help="steps of the circle and push runs")
    ap.add_argument("--only", choices=("fixed", "timed"), default=None)
    ap.add_argument("--scenario", default=None, help="comma-separated scenario labels (default: all)")
    ap.add_argument("--repeat", type=int, default=5, help="replays per scenario (the best of them per solve)")
    ap.add_argument("--full-eigen", action="store_true",
                    help="the partial eigenvalue clip ($LIPMPCC_SQP_PARTIAL_EIGEN=1) beside Eigen's full eigendecomposition "
                         "(C++ partial_eigen=False, the default)")
    ap.add_argument("--convexification", default=None,
                    help=f"comma-separated, of {', '.join(CONVEXIFICATIONS)}: one interleaved replay each")
    args = ap.parse_args()
    convs: list = [None] if args.convexification is None else args.convexification.split(",")
    for c in convs:
        if c is not None and c not in CONVEXIFICATIONS:
            raise SystemExit(f"bench_mpcc_replay: --convexification {c!r}: expected one of {', '.join(CONVEXIFICATIONS)}")
    if args.full_eigen:  # the partial clip (opt-in: $LIPMPCC_SQP_PARTIAL_EIGEN) for the planners compared with it
        os.environ[PARTIAL_EIGEN_ENV] = "1"
        convs.append("full")
    pick = None if args.scenario is None else set(args.scenario.split(","))
    fmt = lambda a: f"{1e6 * np.median(a):7.1f} {1e6 * np.percentile(a, 90):7.1f}"  # noqa: E731
    print(f"per solve, the best of {args.repeat} replays, median / p90 over the solves [µs]")
    print(f"{'scenario':20s} {'solve_time':>15s} {'SQP calls':>15s} {'solve()':>15s}  backends")
    total: dict[str | None, list[np.ndarray]] = {c: [] for c in convs}
    for label, path, make, obstacles, pushes, steps in bench_sqp.scenarios(args.steps, args.only):
        if pick is not None and label not in pick:
            continue
        pl, calls = _record(make, path, obstacles, pushes, steps)
        planners = {c: pl if c is None else make(path, "sqp") for c in convs if c != "full"}
        if "full" in convs:  # built by one untimed replay, then its C++ SQPs swapped
            planners["full"] = make(path, "sqp")
            replay(planners["full"], calls, 1, "eigen_clip")
            _full_eigen(planners["full"])
        runs: dict[str | None, list[np.ndarray]] = {c: [] for c in convs}
        for _ in range(args.repeat):  # interleaved: the convexifications see the same load
            for c in convs:
                runs[c].append(replay(planners[c], calls, 1, "eigen_clip" if c == "full" else c)[0])
        for c in convs:
            best = np.min(runs[c], axis=0)[1:]
            total[c].append(best)
            sqps = [b["sqp"] for b in planners[c]._built.values() if "sqp" in b]
            tag = "" if c is None else " eigen_clip (full eigendecomposition)" if c == "full" else f" {c}"
            print(f"{label:20s} {' '.join(fmt(best[:, j]) for j in range(3))}  "
                  f"{sorted({q.backend for q in sqps})}{tag} ({len(best)} solves)", flush=True)
    for c in convs:
        if total[c]:
            allb = np.concatenate(total[c])
            print(f"{'all':20s} {' '.join(fmt(allb[:, j]) for j in range(3))}{'' if c is None else ' ' + c}")


if __name__ == "__main__":
    main()
