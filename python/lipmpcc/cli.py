"""Command-line interface: ``lipmpcc run SCENARIO [options]``, ``lipmpcc reproduce``, ``lipmpcc sweep``,
``lipmpcc replay RUN_DIR`` and ``lipmpcc course grade NOTEBOOK|FOLDER``.

``lipmpcc run`` writes ``summary.json``, the PNG figures (and a video with ``--video``) to ``--out``:
by default a new folder per run, ``results/SCENARIO-ROBOT-YYYYmmdd-HHMMSS``. The run writes into a
hidden staging folder beside it, moved into place only when everything is written
(:mod:`lipmpcc.studies.outputs`). An ``--out`` that holds anything is refused, unless ``--replace``
(then an earlier run's folder is replaced whole). A run that fails leaves ``failed.json`` (the error,
the options, the time) and no ``summary.json``; ``OUT.lock`` keeps a second command out of the folder
while one writes. A run estimated over an hour of wall time is refused up front unless
``--allow-long`` (:mod:`lipmpcc.studies.run_size`).

Exit codes (:data:`EXIT_OK` ... :data:`EXIT_INTERRUPTED`), read from the summary's ``outcome``
(:func:`lipmpcc.studies.run_outcome`):

====  ======================  =========================================================================
code  constant                meaning
====  ======================  =========================================================================
0     ``EXIT_OK``             the run completed (outcome ``completed``), trailed a slower obstacle along
                              the path as its preset chooses (``trailing``), or failed as its study expects
                              (``expected_outcome``: a baseline known to fail); ``reproduce``: every study
                              ran and met its expectation
1     ``EXIT_ERROR``          the run could not be done (``failed.json``); ``reproduce``: a study
                              errored or missed its criterion (a baseline expected to fail does not count)
2     ``EXIT_USAGE``          a bad or meaningless option, an unusable ``--out``, a run too long
3     ``EXIT_FELL``           the robot fell (outcome ``fell``)
4     ``EXIT_COLLIDED``       the robot collided with an obstacle (outcome ``collided``)
5     ``EXIT_STOPPED_EARLY``  the run stopped early (outcome ``stopped_early``)
6     ``EXIT_STALLED``        no progress along the path for the last 10 s of the run, the end not reached
                              (outcome ``stalled``; the summary's ``stall`` says where and what bound it)
7     ``EXIT_INCOMPLETE``     ``follow-path`` did not reach the end of the path in its set length while
                              still progressing (outcome ``incomplete``)
130   ``EXIT_INTERRUPTED``    Ctrl-C: nothing left of a run; ``reproduce`` leaves a report marked PARTIAL
====  ======================  =========================================================================

An outcome this version does not know (a newer lipmpcc's summary) exits ``EXIT_ERROR``: scripts must
treat an unknown ``outcome`` as not a success (:func:`lipmpcc.studies.outcome.is_success`).

Errors reach the user as one line on stderr, ``lipmpcc: error: ...``, never as a traceback (set
``LIPMPCC_DEBUG=1`` to see the traceback); an interrupt is the line ``lipmpcc: interrupted``.

This module only parses arguments and maps outcomes to exit codes: the studies are in
:mod:`lipmpcc.studies`, the report in :mod:`lipmpcc.reproduce`.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import signal
import sys
import threading
import warnings
from pathlib import Path
from typing import Any, Callable, NoReturn, Sequence

from . import __version__, studies
from ._deprecated import REMOVED_IN
from .exceptions import InvalidInputError, LipmpccError, OutputBusyError
from .loops.progress import progress_lines
from .planners.presets import presets_help
from .studies import outputs
from .studies.run_size import NOTICE_WALL_S
from .sweep.spec import MAX_CASES as MAX_SWEEP_CASES

__all__ = [
    "interrupt_answered",
    "EXIT_OK",
    "EXIT_ERROR",
    "EXIT_USAGE",
    "EXIT_FELL",
    "EXIT_COLLIDED",
    "EXIT_STOPPED_EARLY",
    "EXIT_STALLED",
    "EXIT_INCOMPLETE",
    "EXIT_INTERRUPTED",
    "OUTCOME_EXIT",
    "build_parser",
    "exit_code",
    "main",
]

EXIT_OK = 0
EXIT_ERROR = 1
EXIT_USAGE = 2
EXIT_FELL = 3
EXIT_COLLIDED = 4
EXIT_STOPPED_EARLY = 5
EXIT_STALLED = 6
EXIT_INCOMPLETE = 7
EXIT_INTERRUPTED = 130
#: summary outcome -> exit code of ``lipmpcc run`` (an outcome not in it: :data:`EXIT_ERROR`)
OUTCOME_EXIT = {"completed": EXIT_OK, "fell": EXIT_FELL, "collided": EXIT_COLLIDED, "stopped_early": EXIT_STOPPED_EARLY,
                "stalled": EXIT_STALLED, "incomplete": EXIT_INCOMPLETE, "trailing": EXIT_OK}


def _finite_float(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return v


def _positive_float(text: str) -> float:
    v = _finite_float(text)
    if v <= 0:
        raise argparse.ArgumentTypeError(f"{v} must be a positive number")
    return v


def _positive_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        try:  # 1e6: an integer written as a float
            f = float(text)
        except ValueError:
            f = math.nan
        if not (math.isfinite(f) and f.is_integer()):
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        v = int(f)
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


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line, ``lipmpcc: error: ...`` with a pointer to
    ``--help``, and exit :data:`EXIT_USAGE`."""

    def error(self, message: str) -> NoReturn:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"lipmpcc: error: {' '.join(message.split())} (see: {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    """The ``lipmpcc`` argument parser (commands ``run`` and ``reproduce``)."""
    p = _Parser(prog="lipmpcc", description="Bipedal footstep planning, reproduced: lipmpcc run SCENARIO, lipmpcc "
                "reproduce, lipmpcc sweep SPEC, lipmpcc replay RUN_DIR and lipmpcc course grade NOTEBOOK; each "
                "command's --help lists its options, docs/formats.md every file format and frame.")
    p.add_argument("--version", action="version", version=f"lipmpcc {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    r = sub.add_parser("run", help="run one scenario and write summary.json + figures",
                       epilog=studies.options_help() + "\n\n" + presets_help(),
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("scenario", choices=studies.names())
    r.add_argument("--planner", help="mpcc | cartesian | alip-mpc | alip-qp | capture-point; stone-field: "
                   "stone-field (default) | greedy-stone | path-agnostic-alip-mpc | stone-field-milp")
    r.add_argument("--robot", help="lip | alip | digit_like | PATH.xml (your MJCF MODEL.xml, with its layout "
                   "MODEL.lipmpcc.toml beside it: docs/formats.md; sample: data/examples/my_layout.toml)")
    r.add_argument("--layout", help="with --robot PATH.xml: its layout file, when it is not MODEL.lipmpcc.toml beside "
                   "the model (a read-only model folder: lipmpcc robot init MODEL.xml --out FILE)")
    r.add_argument("--obstacle-speed", type=_finite_float, help="obstacle speed along the path [m/s]")
    r.add_argument("--path", help="CSV of waypoints x,y [m], world frame, optional header, # comments "
                   "(docs/formats.md; sample: data/examples/my_waypoints.csv)")
    r.add_argument("--obstacles", help="JSON list of obstacles: circles/ellipses, static or moving, world frame "
                   "[m, m/s], # comment lines (docs/formats.md; sample: data/examples/my_obstacles.json)")
    r.add_argument("--steps", type=_positive_int, help="number of steps")
    r.add_argument("--seed", type=_nonneg_int, help="random seed of circle-push's pushes and of stones profiles II-IV "
                   "(default 0)")
    r.add_argument("--out", help="output folder, new or empty (default: a new folder per run, "
                   "results/SCENARIO-ROBOT-YYYYmmdd-HHMMSS)")
    r.add_argument("--replace", action="store_true", help="replace --out whole when it holds an earlier run")
    r.add_argument("--allow-long", action="store_true", help="run even when the estimated wall time is over an hour")
    r.add_argument("--profile", help="stepping-stone profile I | II | III | IV")
    r.add_argument("--L", type=_finite_float, help="profile I step length [m] (default paper B's 0.4, scaled to a robot whose layout states "
                   "max_step_length; given: used as given)")
    r.add_argument("--W", type=_finite_float, help="profile I lateral offset [m] (default paper B's 0.15, scaled likewise)")
    r.add_argument("--stones", help="CSV of stones x,y[,size_x,size_y] [m], world frame (robot at the origin, "
                   "first stone for the right foot; docs/formats.md; sample: data/examples/my_stones.csv)")
    r.add_argument("--duration", type=_finite_float, help="simulated time [s]")
    r.add_argument("--speed", type=_finite_float, help="commanded walking speed [m/s]")
    r.add_argument("--yaw-rate", type=_finite_float, help="commanded yaw rate [rad/s]")
    r.add_argument("--video", action="store_true", help="also write a video of the run, OUT/SCENARIO.mp4 (H.264, "
                   "640x480 at 30 fps) or with --video-format gif OUT/SCENARIO.gif (400x300 at 15 fps): the camera "
                   "follows the torso; the path, obstacles, footholds and push are drawn, the time and push written on "
                   "each frame (full-body runs)")
    r.add_argument("--video-format", choices=("mp4", "gif"), help="the --video file's format (default mp4)")
    r.add_argument("--viewer", nargs="?", const="realtime", choices=("realtime", "fast"),
                   help="show the run live in MuJoCo's viewer (full-body runs; needs a display): in real time "
                   "(--viewer, --viewer realtime) or as fast as it simulates (--viewer fast)")
    r.add_argument("--cop-range", type=_finite_float, nargs=2, metavar=("DX", "DY"),
                   help="stones/push with alip-mpc: half-extents of the centre-of-pressure box the planner may use "
                        "in the stance sole [m] (a foot; 0 0 = paper B's point foot; default: the robot's, "
                        "0 0 on the ALIP model)")
    r.add_argument("--step-duration-range", type=_finite_float, nargs=2, metavar=("TMIN", "TMAX"),
                   help="circle/circle-push/overtake/follow-path with mpcc or cartesian: the MPCC chooses each "
                        "step's duration in [TMIN, TMAX] [s] (within [0.2, 1] s and containing the nominal T, 0.4 s "
                        "on the LIP and digit_like; on the LIP once per step, or at --replan-hz; on a full body "
                        "re-planned at 25 Hz; default: the fixed T)")
    r.add_argument("--replan-hz", type=_finite_float, metavar="HZ",
                   help="with --step-duration-range on the LIP: re-plan the timed MPCC within each step at HZ "
                        "(in [1, 1000] Hz; paper B: 25; default: once per step, at the support exchange; a full "
                        "body always re-plans it at 25 Hz)")
    r.add_argument("--preset", metavar="NAME", help="the planner's parameters by name: circle | overtake | cartesian "
                   "(mpcc) | paper-b (alip-mpc) | paper-b-qp (alip-qp); listed below (default: the study's own)")
    r.add_argument("--push-set", choices=("paper-a", "paper-b"), help="circle-push's pushes: paper A's random "
                   "series (paper-a, the default; --seed) or paper B's four, +150 N forward, -150 N backward, +75 N "
                   "left, -75 N right in the walking frame, 0.1-0.2 s into four swings of the inner foot (paper-b; the "
                   "pushed run follows four shorter runs that place them; summary paper_b_pushes); stone-field: paper-b only, "
                   "the four on the swings towards field footholds 2, 4, 6 and 8 (world frame)")
    r.add_argument("--set", action="append", metavar="KEY=VALUE", help="set one planner weight or bound, after the "
                   "preset (repeat it: --set q_c=50 --set rho=10); the keys of each planner are listed below")

    rp = sub.add_parser("reproduce", help="run every study and write a report beside the papers' numbers")
    rp.add_argument("--fast", action="store_true", help="shorter runs (the LIPMPCC_FAST switch)")
    rp.add_argument("--out", default="results", help="output folder: report.md, results.json and a folder per study "
                    "(each replaced whole; default: results)")
    rp.add_argument("--only", help="run only the studies whose name starts with this")
    rp.add_argument("--robot", metavar="MODEL.xml", help="also run every full-body study on this MuJoCo model (its "
                    "layout MODEL.lipmpcc.toml beside it, or a shipped one: docs/formats.md), named with the file's "
                    "stem (digit-v3-stones-II-alip-mpc) and reported as its own column beside digit_like and the "
                    "papers (default: $LIPMPCC_DIGIT_V3 when set, else digit_like only)")
    _add_sweep_parser(sub)
    _add_course_parser(sub)
    _add_robot_parser(sub)
    rr = sub.add_parser("replay", help="replay a full-body run's folder in MuJoCo's viewer, or render it to a video",
                        description="Replay RUN_DIR/replay.npz (written by every full-body run) in MuJoCo's viewer "
                        "in real time, or with --video FILE render it (headless) to an MP4 (640x480, 30 fps) or a "
                        "GIF (400x300, 15 fps). Exit 0 done, 2 a bad RUN_DIR or no display for the viewer. Headless, "
                        "MuJoCo renders offscreen with MUJOCO_GL=egl (or osmesa); on macOS run the viewer under "
                        "mjpython.")
    rr.add_argument("run_dir", metavar="RUN_DIR", help="the folder of a full-body run (lipmpcc run ... --robot digit_like)")
    rr.add_argument("--speed", type=_finite_float, default=1.0, help="playback speed (1 = real time), in the viewer or "
                    "of the --video (2: the video shows the run twice as fast)")
    rr.add_argument("--video", metavar="FILE", help="render to FILE (.mp4 or .gif) instead of showing the viewer")
    return p


def _add_course_parser(sub: argparse._SubParsersAction) -> None:
    """``lipmpcc course grade NOTEBOOK.ipynb|FOLDER`` (:mod:`lipmpcc.course.grader`)."""
    c = sub.add_parser("course", help="the course's tools: grade a student's notebook (or a class) with points",
                       description="Course tools. `lipmpcc course grade` runs a notebook headless (fast mode) with "
                       "the reference checks and prints a score per exercise and a total.")
    csub = c.add_subparsers(dest="course_command", required=True)
    g = csub.add_parser("grade", help="run a student's notebook, or every notebook of a folder, and score its exercises",
                        description="Exit 0 graded (whatever the score), 2 a bad path or option.")
    g.add_argument("path", help="a student's notebook (NN_name.ipynb), or a folder of them (a class)")
    g.add_argument("--reference", metavar="DIR", help="the course notebooks whose checks grade (default: notebooks/)")
    g.add_argument("--gradescope", metavar="PATH", help="write Gradescope's results.json (a folder for a class)")
    g.add_argument("--timeout", type=_positive_float, default=60.0, help="time limit of an exercise's check [s]")
    g.add_argument("--full", action="store_true", help="run the notebook in full mode (default: LIPMPCC_FAST=1)")
    g.add_argument("--solutions", metavar="DIR", help="run this solutions folder instead of the student's code")


def _course(ns: argparse.Namespace) -> int:
    """``lipmpcc course grade``: exit 0 graded, 2 a bad path or option."""
    from .course import grader

    try:
        grades = grader.grade_path(ns.path, ns.reference, fast=not ns.full, exercise_timeout_s=ns.timeout,
                                   solutions=ns.solutions)
        for g in grades:
            print(grader.format_grade(g))
        if ns.gradescope:
            root = ns.path if Path(ns.path).is_dir() else None
            for dest in grader.write_gradescope(grades, ns.gradescope, root):
                print(f"gradescope: {dest}")
    except InvalidInputError as exc:
        return _usage_error(exc)
    return EXIT_OK


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
    s.add_argument("--robot", metavar="ROBOT", help="run the specification's cases on this robot instead of its own "
                   "(digit_like, or a PATH.xml such as Digit v3's: data/sweeps/table_ii_digit.toml --robot "
                   "digit-v3.xml); its own store (default --out: sweeps/SPEC_NAME-MODEL)")
    s.add_argument("--allow-long", action="store_true", help=f"run a sweep over {MAX_SWEEP_CASES} cases or a week of "
                   "estimated CPU time (refused otherwise)")
    s.add_argument("--replace", action="store_true", help="delete OUT/results.sqlite first (a damaged store, or one of "
                   "another specification) and start the sweep over")


def _add_robot_parser(sub: argparse._SubParsersAction) -> None:
    """``lipmpcc robot init MODEL.xml`` and ``lipmpcc robot check MODEL.xml`` (:mod:`lipmpcc.studies.robot_check`)."""
    rb = sub.add_parser("robot", help="write a new robot's layout (init) and check it stands and steps (check)",
                        description="init: guess MODEL.lipmpcc.toml (beside the model, or --out) from the MJCF "
                        "alone and say what was guessed and how sure; check: stand the robot, step in place and "
                        "print a verdict. Exit 0 done / the check passed, 1 the check failed, 2 a bad model or --out. "
                        "docs/add_a_robot.md walks through both.")
    rb.add_argument("action", choices=("init", "check"))
    rb.add_argument("model", metavar="MODEL.xml", help="the robot's MJCF (a scene file that includes it works too)")
    rb.add_argument("--out", help="init: the layout file to write (default: MODEL.lipmpcc.toml beside the model)")
    rb.add_argument("--force", action="store_true", help="init: replace an existing layout file")
    rb.add_argument("--crouch", type=_finite_float, metavar="RATIO", help="init: the standing pose's hip-to-sole height "
                    "as a fraction of the straight leg's, 0.6-0.99 (default 0.9; lower bends the knees more)")
    rb.add_argument("--layout", help="check: the layout file, when it is not MODEL.lipmpcc.toml beside the model "
                    "(the one `robot init --out` wrote)")


def _robot_command(ns: argparse.Namespace) -> int:
    """``lipmpcc robot init|check``: exit 0 done / passed, 1 the check failed, 2 a bad model, layout or --out."""
    from .exceptions import ModelFileError, RobotDescriptionError
    from .robots.mjcf import robot_in_scene
    from .studies import robot_check

    model = Path(ns.model)
    try:
        if ns.action == "init":
            if ns.layout is not None:
                return _usage_error(InvalidInputError("--layout", ns.layout, "only with `robot check` (init: --out)"))
            model = (robot_in_scene(model) or model) if model.is_file() else model
            crouch = {} if ns.crouch is None else {"crouch": ns.crouch}
            print(robot_check.init_robot(model, ns.out, overwrite=bool(ns.force), **crouch))
            return EXIT_OK
        if ns.out is not None or ns.force:
            return _usage_error(InvalidInputError("--out/--force", ns.out, "only with `robot init`"))
        if ns.crouch is not None:
            return _usage_error(InvalidInputError("--crouch", ns.crouch, "only with `robot init`"))
        result = robot_check.check_robot(model, layout=ns.layout)
    except (InvalidInputError, ModelFileError, RobotDescriptionError) as exc:
        return _usage_error(exc)
    print(result.report())
    return EXIT_OK if result.passed else EXIT_ERROR


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
        spec = sweep.load_spec(ns.spec, allow_long=ns.allow_long, robot=ns.robot)
        default = Path(ns.spec).stem + (f"-{Path(ns.robot).stem}" if ns.robot else "")
        out = Path(ns.out or Path("sweeps") / default)
        size = sweep.sweep_size(spec)
        if size.cpu_s > NOTICE_WALL_S:
            print(f"lipmpcc: this sweep: {size.describe(ns.workers or sweep.available_cpus())}", file=sys.stderr)
        executor = sweep.dask_executor(ns.dask) if ns.dask is not None else None
        try:
            stats = sweep.run_sweep(spec, out, workers=ns.workers, executor=executor, progress=not ns.no_progress,
                                    replace=ns.replace)
        finally:
            if executor is not None:
                executor.shutdown(wait=False)
    except sweep.SweepInterrupted as exc:
        _CTRL_C.settle()  # answered here: main prints nothing more
        print(f"lipmpcc: {exc}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except sweep.SweepStoreError as exc:
        print(f"lipmpcc: error: {_one_line(exc)}", file=sys.stderr)
        return EXIT_ERROR
    except InvalidInputError as exc:
        return _usage_error(exc)
    if stats.orphans:
        print(f"lipmpcc: stopped {len(stats.orphans)} processes left behind by an earlier run of this sweep (killed?): "
              + ", ".join(f"{role} {pid}" for role, pid in stats.orphans), file=sys.stderr)
    print(f"{stats.total} cases: {stats.skipped} already done, ran {stats.ran} ({stats.done} done, {stats.errors} errors, {stats.timeouts} timeouts, "
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
        out=ns.out if ns.out is not None else str(outputs.default_out(ns.scenario, ns.robot)),
        profile=ns.profile,
        L=ns.L,
        W=ns.W,
        stones=ns.stones,
        video=ns.video,
        duration=ns.duration,
        speed=ns.speed,
        yaw_rate=ns.yaw_rate,
        cop_range=None if ns.cop_range is None else (float(ns.cop_range[0]), float(ns.cop_range[1])),
        allow_long=bool(getattr(ns, "allow_long", False)),
        viewer=getattr(ns, "viewer", None),
        video_format=getattr(ns, "video_format", None),
        push_set=getattr(ns, "push_set", None),
        layout=getattr(ns, "layout", None),
        step_duration_range=None if ns.step_duration_range is None else (float(ns.step_duration_range[0]),
                                                                         float(ns.step_duration_range[1])),
        replan_hz=getattr(ns, "replan_hz", None),
        preset=getattr(ns, "preset", None),
        set=getattr(ns, "set", None),
    )


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text or type(exc).__name__


def _error_line(exc: BaseException) -> str:
    """``lipmpcc: error: ...``: the message of a lipmpcc, value or file error; the type and a hint for
    anything else (a bug)."""
    if isinstance(exc, (LipmpccError, ValueError, OSError)):
        return f"lipmpcc: error: {_one_line(exc)}"
    return f"lipmpcc: error: unexpected {type(exc).__name__}: {_one_line(exc)} (set LIPMPCC_DEBUG=1 to see the traceback)"


def _usage_error(exc: Exception) -> int:
    print(f"lipmpcc: error: {_one_line(exc)}", file=sys.stderr)
    return EXIT_USAGE


def exit_code(summary: dict) -> int:
    """The exit code of ``lipmpcc run`` for a written ``summary``: :data:`OUTCOME_EXIT` of
    :func:`lipmpcc.studies.run_outcome`, or :data:`EXIT_OK` for a baseline that failed the way its study
    expects (:func:`lipmpcc.studies.is_expected`: e.g. paper B's push test with a point foot falls); an outcome
    it does not know: :data:`EXIT_ERROR`."""
    return EXIT_OK if studies.is_expected(summary) else OUTCOME_EXIT.get(studies.run_outcome(summary), EXIT_ERROR)


class _CtrlC:
    """Ctrl-C that no library can swallow, while a command runs (``with _CTRL_C:`` in :func:`main`).

    SIGINT raises ``KeyboardInterrupt`` as usual, and also arms a timer that raises it again every
    :attr:`REPEAT_S` seconds of CPU time until some code handles it (SIGVTALRM: the wall-clock SIGALRM is
    left to the caller, e.g. a test's time limit): a solver that catches the interrupt in
    its own callback (CasADi's IPOPT interface turns it into a warning and a failed solve) cannot make
    the run go on. :meth:`check` raises it for a run that ended while an interrupt was swallowed. Only
    in the main thread, where ``signal.setitimer`` exists; elsewhere, Python's own handling.

    The timer can fire inside a finalizer (a ``__del__``, a weakref callback), where Python cannot raise:
    it prints the interrupt as "Exception ignored in ..." with a traceback and goes on. While a command
    runs, the timer does not raise inside a ``__del__`` (it fires again :attr:`RETRY_S` later), and
    ``sys.unraisablehook`` drops such an interrupt from any other finalizer without a word (it is raised
    again :attr:`RETRY_S` later); any other unraisable exception is handed to the previous hook.
    """

    REPEAT_S = 0.2  # [s]
    RETRY_S = 0.002  # [s] after a timer's interrupt landed in a finalizer

    def __init__(self) -> None:
        self.count = 0
        self.settled = False
        self._previous: list[tuple[int, object]] = []
        self._previous_hook: Callable[[Any], object] = sys.unraisablehook

    def __enter__(self) -> _CtrlC:
        self.count, self.settled = 0, False
        if threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer"):
            self._previous = [(signal.SIGINT, signal.signal(signal.SIGINT, self._on_sigint)),
                              (signal.SIGVTALRM, signal.signal(signal.SIGVTALRM, self._on_alarm))]
            self._previous_hook = sys.unraisablehook
            sys.unraisablehook = self._on_unraisable
        return self

    def __exit__(self, *exc: object) -> None:
        if self._previous:
            signal.setitimer(signal.ITIMER_VIRTUAL, 0.0)
            for signum, handler in self._previous:
                signal.signal(signum, handler)  # type: ignore[arg-type]
            self._previous = []
            sys.unraisablehook = self._previous_hook

    def _on_unraisable(self, unraisable: Any) -> None:
        if self.count and not self.settled and isinstance(unraisable.exc_value, KeyboardInterrupt):
            signal.setitimer(signal.ITIMER_VIRTUAL, self.RETRY_S)  # the interrupt, raised in a finalizer: soon again
            return
        self._previous_hook(unraisable)

    def _in_finalizer(self, frame: Any) -> bool:
        """True when ``frame`` or a caller is a ``__del__`` or this hook (where a raise is only printed)."""
        hook = self._on_unraisable.__func__.__code__
        f = frame
        while f is not None:
            if f.f_code is hook:
                return True
            f = f.f_back
        return outputs.in_finalizer(frame)

    def _on_sigint(self, signum: int, frame: object) -> None:
        self.count += 1
        if self.count > 1 or self.settled:  # already interrupted: a second Ctrl-C must not break the clean-up
            return
        signal.setitimer(signal.ITIMER_VIRTUAL, self.REPEAT_S)
        raise KeyboardInterrupt

    def _on_alarm(self, signum: int, frame: object) -> None:
        if not self.count or self.settled or outputs.is_interrupt(sys.exc_info()[1]):  # none, or being handled
            return
        if self._in_finalizer(frame):
            signal.setitimer(signal.ITIMER_VIRTUAL, self.RETRY_S)
            return
        signal.setitimer(signal.ITIMER_VIRTUAL, self.REPEAT_S)
        raise KeyboardInterrupt

    def settle(self) -> None:
        """The interrupt reached the top and is answered: stop raising it again; later Ctrl-Cs only count
        until the command returns."""
        self.settled = True
        if self._previous:
            signal.setitimer(signal.ITIMER_VIRTUAL, 0.0)

    def check(self) -> None:
        """Raise ``KeyboardInterrupt`` when Ctrl-C was pressed (and swallowed) since entering."""
        if self.count:
            raise KeyboardInterrupt


_CTRL_C = _CtrlC()


def _checked_run(ns: argparse.Namespace) -> tuple[studies.RunOptions, Path, studies.RunSize]:
    """The run's options, its output folder and its size, checked (usage errors raise InvalidInputError)."""
    opts = _options(ns)
    studies.check_options(opts)
    size = studies.check_run_size(opts)
    out = outputs.check_out(opts.out, replace=ns.replace)
    return opts, out, size


def _locked(ns: argparse.Namespace, opts: studies.RunOptions) -> tuple[outputs.OutputLock, studies.RunOptions]:
    """The lock of the run's folder, held, and the options (a default folder taken meanwhile by a run
    started in the same second: the next free name)."""
    for _ in range(5):
        lock = outputs.OutputLock(opts.out)
        try:
            lock.acquire()
            return lock, opts
        except OutputBusyError:
            if ns.out is not None:
                raise
            opts = dataclasses.replace(opts, out=str(outputs.default_out(opts.scenario, opts.robot)))
    lock.acquire()
    return lock, opts


def _run(ns: argparse.Namespace) -> int:
    try:
        opts, out, size = _checked_run(ns)
        lock, opts = _locked(ns, opts)  # OutputFolderError: the parent cannot be created or written
    except InvalidInputError as exc:
        return _usage_error(exc)
    if size.wall_s > NOTICE_WALL_S:
        print(f"lipmpcc: this run takes {size.describe()}", file=sys.stderr)
    for hint in studies.hints(opts):
        print(f"lipmpcc: hint: {hint}", file=sys.stderr)
    record = {k: v for k, v in dataclasses.asdict(opts).items() if k != "extra"}
    try:
        out = outputs.check_out(opts.out, replace=ns.replace)  # again, under the lock
        stage = outputs.StagedFolder(out, record)
        try:
            with stage:
                with progress_lines():  # off a terminal: a progress line now and then (loops.progress)
                    result = studies.run(dataclasses.replace(opts, out=str(stage.tmp)))
                result.save(stage.tmp)
                _CTRL_C.check()  # an interrupt swallowed on the way: nothing is kept
        except Exception as exc:
            if _debug() or stage.failed is None or outputs.is_interrupt(exc):
                raise
            print(f"{_error_line(exc)} [{stage.failed}]", file=sys.stderr)
            return EXIT_ERROR
    finally:
        lock.release()
    s = result.summary
    outcome = studies.run_outcome(s)
    keys = [k for k in ("scenario", "planner", "robot", "steps", "fell", "solver_failures") if k in s]
    shown = f"{outcome} (expected: a baseline known to fail)" if studies.is_expected(s) else outcome
    print(" ".join(f"{k}={s[k]}" for k in keys) + f" outcome={shown} -> {out / outputs.SUMMARY_FILE}")
    why = _path_outcome_line(s)
    if why:
        print(why)
    return exit_code(s)


def _path_outcome_line(s: dict) -> str:
    """A path-following run that did not reach its goal, or trailed: how far it came, and why (stall, trailing)."""
    if "path_length_m" not in s or s.get("reached_end", True) or s.get("outcome") == "completed":
        return ""
    line = f"  progress {float(s.get('progress_m') or 0.0):.2f} of {float(s['path_length_m']):.2f} m"
    stall = s.get("stall")
    if isinstance(stall, dict):
        line += (f"; no progress since t = {stall['t_s']:.1f} s at {stall['progress_m']:.2f} m "
                 f"({stall['duration_s']:.1f} s): {stall['binding']['text']}")
    if s.get("trailing_obstacle") is not None:
        line += f"; trailing obstacle {s['trailing_obstacle']} by {float(s['trailing_gap_m']):.2f} m"
    return line


def _reproduce(ns: argparse.Namespace) -> int:
    from .reproduce import expected_failures, extra_robot, missed, reproduce, select_studies

    try:
        robot = extra_robot(getattr(ns, "robot", None))
        select_studies(ns.only, robot)
        outputs.check_folder_path(ns.out)
    except InvalidInputError as exc:
        return _usage_error(exc)
    if robot is not None:
        print(f"[reproduce] the full-body studies also on {robot}")
    res = reproduce(Path(ns.out), fast=ns.fast, only=ns.only, robot=robot)
    bad = missed(res)
    expected = expected_failures(res)
    print(f"report: {Path(ns.out) / 'report.md'} (and report.html); {len(res['studies'])} studies, {len(bad)} missed or failed"
          + (f": {', '.join(bad)}" if bad else "")
          + (f"; {len(expected)} expected failure{'s' if len(expected) > 1 else ''}: {', '.join(expected)}" if expected else ""))
    return EXIT_ERROR if bad else EXIT_OK


def _command(ns: argparse.Namespace) -> int:
    if ns.command == "run":
        return _run(ns)
    if ns.command == "sweep":
        return _sweep(ns)
    if ns.command == "replay":
        return _replay(ns)
    if ns.command == "course":
        return _course(ns)
    if ns.command == "robot":
        return _robot_command(ns)
    return _reproduce(ns)


def _replay(ns: argparse.Namespace) -> int:
    """``lipmpcc replay RUN_DIR``: exit 0 done, 2 a bad RUN_DIR, speed or file, or no display."""
    from .studies.replay import replay_run

    try:
        print(replay_run(ns.run_dir, ns.speed, ns.video))
    except InvalidInputError as exc:
        return _usage_error(exc)
    return EXIT_OK


def _debug() -> bool:
    return bool(os.environ.get("LIPMPCC_DEBUG"))


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``lipmpcc`` and ``python -m lipmpcc``: the exit code (see the module doc)."""
    os.environ.setdefault("MPLBACKEND", "Agg")
    with _CTRL_C:  # Ctrl-C raises KeyboardInterrupt until it is answered, then only counts until main returns
        code = _main(argv)
        if _CTRL_C.count and not _CTRL_C.settled:  # pressed, but swallowed on the way and the command ended
            _CTRL_C.settle()
            print("lipmpcc: interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED
        return code


def _main(argv: Sequence[str] | None) -> int:
    try:
        parser = build_parser()
        ns = parser.parse_args(argv)
        return _command(ns)
    except KeyboardInterrupt:
        if _debug():
            raise
        _CTRL_C.settle()
        print("lipmpcc: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:  # a lipmpcc error, or a bug: one line all the same
        if _debug():
            raise
        if outputs.is_interrupt(exc):  # a Ctrl-C that a library turned into another error
            _CTRL_C.settle()
            print("lipmpcc: interrupted", file=sys.stderr)
            return EXIT_INTERRUPTED
        print(_error_line(exc), file=sys.stderr)
        return EXIT_ERROR


def interrupt_answered() -> bool:
    """True when the last :func:`main` answered a Ctrl-C (printed ``lipmpcc: interrupted``)."""
    return _CTRL_C.settled
