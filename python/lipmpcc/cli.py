"""Command-line interface: ``lipmpcc run SCENARIO [options]``, ``lipmpcc reproduce`` and ``lipmpcc sweep``.

Every run writes ``summary.json`` and PNG figures to ``--out``. Errors reach the
user as one readable line on stderr and a non-zero exit code, never as a
traceback (set ``LIPMPCC_DEBUG=1`` to see the traceback): exit 2 for a usage error
(a bad or meaningless option: an option the scenario does not read, ``reproduce --only``
matching no study), 1 for a run that cannot be done.

This module only parses arguments: the studies are in :mod:`lipmpcc.studies`, the
report in :mod:`lipmpcc.reproduce`.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import warnings
from pathlib import Path
from typing import Sequence

from . import __version__, studies
from ._deprecated import REMOVED_IN
from .exceptions import InvalidInputError, LipmpccError

__all__ = ["EXIT_OK", "EXIT_USAGE", "EXIT_ERROR", "build_parser", "main"]

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
    """The ``lipmpcc`` argument parser (commands ``run`` and ``reproduce``)."""
    p = argparse.ArgumentParser(prog="lipmpcc", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"lipmpcc {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    r = sub.add_parser("run", help="run one scenario and write summary.json + figures",
                       epilog=studies.options_help(), formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("scenario", choices=studies.names())
    r.add_argument("--planner", help="mpcc | cartesian | alip-mpc | alip-qp | capture-point")
    r.add_argument("--robot", help="lip | alip | digit_like | PATH.xml")
    r.add_argument("--obstacle-speed", type=_finite_float, help="obstacle speed along the path [m/s]")
    r.add_argument("--path", help="CSV of waypoints x,y [m], world frame, optional header, # comments "
                   "(docs/formats.md; sample: data/examples/my_waypoints.csv)")
    r.add_argument("--obstacles", help="JSON list of obstacles: circles/ellipses, static or moving "
                   "(docs/formats.md; sample: data/examples/my_obstacles.json)")
    r.add_argument("--steps", type=_positive_int, help="number of steps")
    r.add_argument("--seed", type=_nonneg_int, help="random seed of circle-push's pushes and of stones profiles II-IV "
                   "(default 0)")
    r.add_argument("--out", default="results", help="output folder")
    r.add_argument("--profile", help="stepping-stone profile I | II | III | IV")
    r.add_argument("--L", type=_finite_float, help="profile I step length [m]")
    r.add_argument("--W", type=_finite_float, help="profile I lateral offset [m]")
    r.add_argument("--stones", help="CSV of stones x,y[,size_x,size_y] [m], world frame (robot at the origin, "
                   "first stone for the right foot; docs/formats.md; sample: data/examples/my_stones.csv)")
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
    _add_sweep_parser(sub)
    return p


def _add_sweep_parser(sub: argparse._SubParsersAction) -> None:
    """``lipmpcc sweep SPEC.toml --out DIR`` and ``lipmpcc sweep --report DIR`` (:mod:`lipmpcc.sweep`)."""
    s = sub.add_parser("sweep", help="run a campaign of cases (grids / random draws) and write survival statistics",
                       description="Run every case of a sweep specification (TOML; docs/sweeps.md, data/sweeps/) "
                       "not yet in OUT/results.sqlite, then write OUT/report.md. Exit 0 done, 1 error, "
                       "2 bad specification or a store of another specification, 130 interrupted (run again to resume).")
    s.add_argument("spec", nargs="?", help="the sweep specification (TOML), or the name of one in data/sweeps")
    s.add_argument("--out", help="output folder: results.sqlite, report.md, figures (default: sweeps/SPEC_NAME)")
    s.add_argument("--workers", type=_positive_int, help="local worker processes (default: the CPUs this process may use)")
    s.add_argument("--dask", metavar="ADDRESS", help="run the cases on this Dask scheduler (tcp://HOST:8786)")
    s.add_argument("--report", metavar="DIR", help="only write DIR/report.md and figures from DIR/results.sqlite")
    s.add_argument("--no-report", action="store_true", help="do not write the report at the end of the run")
    s.add_argument("--no-progress", action="store_true", help="no progress bar")


def _sweep(ns: argparse.Namespace) -> int:
    """``lipmpcc sweep``: exit 0 done, 1 a case could not be stored / the cluster failed, 2 a bad spec, 130 Ctrl-C."""
    from . import sweep

    if ns.report is not None:
        if ns.spec is not None:
            return _usage_error(InvalidInputError("--report", ns.report, "either SPEC or --report DIR, not both"))
        try:
            print(f"report: {sweep.write_report(ns.report)}")
        except InvalidInputError as exc:
            return _usage_error(exc)
        return EXIT_OK
    if ns.spec is None:
        return _usage_error(InvalidInputError("spec", None, "a sweep specification (TOML), or --report DIR"))
    if ns.dask is not None and ns.workers is not None:
        return _usage_error(InvalidInputError("--workers", ns.workers, "no --workers with --dask (the cluster has its own)"))
    try:
        spec = sweep.load_spec(ns.spec)
        out = Path(ns.out or Path("sweeps") / Path(ns.spec).stem)
        executor = sweep.dask_executor(ns.dask) if ns.dask is not None else None
        try:
            stats = sweep.run_sweep(spec, out, workers=ns.workers, executor=executor, progress=not ns.no_progress)
        finally:
            if executor is not None:
                executor.shutdown(wait=False)
    except sweep.SweepInterrupted as exc:
        print(f"lipmpcc: {exc}", file=sys.stderr)
        return 130
    except InvalidInputError as exc:
        return _usage_error(exc)
    print(f"{stats.total} cases: {stats.skipped} already done, ran {stats.ran} ({stats.done} done, {stats.errors} errors, "
          f"{stats.died} worker deaths, {stats.fell} fell) in {stats.wall_s:.1f} s -> {stats.store}")
    if not ns.no_report:
        print(f"report: {sweep.write_report(out)}")
    return EXIT_OK


def write_outputs(result: studies.RunResult, out: str | Path) -> Path:
    """Deprecated: :meth:`lipmpcc.studies.RunResult.save`."""
    warnings.warn(
        f"lipmpcc.cli.write_outputs moved to lipmpcc.studies.RunResult.save; the old path is removed in lipmpcc {REMOVED_IN}",
        DeprecationWarning,
        stacklevel=2,
    )
    return result.save(out)


def _options(ns: argparse.Namespace) -> studies.RunOptions:
    return studies.RunOptions(
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


def _usage_error(exc: Exception) -> int:
    print(f"lipmpcc: error: {exc}", file=sys.stderr)
    return EXIT_USAGE


def _run(ns: argparse.Namespace) -> int:
    opts = _options(ns)
    try:
        studies.check_options(opts)
    except InvalidInputError as exc:
        return _usage_error(exc)
    result = studies.run(opts)
    path = result.save(ns.out)
    s = result.summary
    keys = [k for k in ("scenario", "planner", "robot", "steps", "fell", "solver_failures") if k in s]
    print(" ".join(f"{k}={s[k]}" for k in keys) + f" -> {path}")
    return EXIT_OK


def _reproduce(ns: argparse.Namespace) -> int:
    from .reproduce import missed, reproduce, select_studies

    try:
        select_studies(ns.only)
    except InvalidInputError as exc:
        return _usage_error(exc)
    res = reproduce(Path(ns.out), fast=ns.fast, only=ns.only)
    bad = missed(res)
    print(f"report: {Path(ns.out) / 'report.md'}; {len(res['studies'])} studies, {len(bad)} missed or failed"
          + (f": {', '.join(bad)}" if bad else ""))
    return EXIT_OK


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``lipmpcc`` and ``python -m lipmpcc``."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    parser = build_parser()
    ns = parser.parse_args(argv)
    try:
        if ns.command == "run":
            return _run(ns)
        if ns.command == "reproduce":
            return _reproduce(ns)
        if ns.command == "sweep":
            return _sweep(ns)
    except (LipmpccError, ValueError, FileNotFoundError, OSError) as exc:
        if os.environ.get("LIPMPCC_DEBUG"):
            raise
        print(f"lipmpcc: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    parser.error(f"unknown command {ns.command!r}")
    return EXIT_USAGE
