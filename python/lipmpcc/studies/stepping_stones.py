"""Paper B's studies: ``stones`` (profiles I–IV or a stone file) and the push test ``push``, on the ALIP or
on a full-body robot.

ALIP-MPC (``--planner alip-mpc``, default) or ALIP-QP (``--planner alip-qp``) plans the footsteps:

- ``--robot alip`` (default): the ALIP (:mod:`lipmpcc.loops.alip`, re-planning every 40 ms), with that
  loop's failure criterion (:func:`run_case`).
- ``--robot digit_like`` or ``--robot PATH.xml``: the full-body loop (:mod:`lipmpcc.loops.fullbody.loop`)
  through :class:`~lipmpcc.planners.sources.alip.AlipFootstepSource`, re-planning at 25 Hz, on a MuJoCo course
  of stone boxes over a pit (:mod:`lipmpcc.sim.stones_scene`); a run fails when the simulator sees a fall
  or a foot in the pit (:func:`simulate_full_body`).

One set-up for both:

- The course (:func:`make_course`): the 6 approach footholds of :func:`lipmpcc.terrain.approach_footholds`,
  then the stones. The robot starts standing with the left foot in stance and enters the stones with a
  right swing; the approach is driven by ALIP-MPC for every planner under test, so that the planners take
  over in the same state (paper B: consistent initial conditions). On a full body the course is moved onto
  the robot's standing feet, the robot first shifts its weight onto the left foot, and
  :attr:`FullBodyStonesParams.n_exit` free footholds follow the last stone (a fall right after it is seen).
- ``stones``: ``--profile I|II|III|IV`` (default I), ``--L/--W`` for profile I (default 0.4 / +0.15),
  ``--seed`` for II–IV, or ``--stones FILE.csv``; 32 stones of a profile (in fast mode 16 on the ALIP, 12
  on a full body), every stone of a file, ``--steps`` to walk fewer. The summary says how many stones
  were reached of how many (``stones_reached`` / ``stones_total``).
- ``push``: paper B's push test (:func:`lipmpcc.studies.paper.push_test`): 24 stones of (L, W) = (0.4, 0)
  (22 in fast mode), pushes from 0.1 to 0.2 s into the swings towards stones 5 (F_x = +150 N), 10 (−150 N),
  15 (F_y = +75 N) and 20 (−75 N): on the COM of the ALIP, on the torso of a full body (each loop arms them
  at the touch-down that starts the pushed swing: :class:`~lipmpcc.loops.base.PushSchedule`).
- ``--preset NAME`` / ``--set KEY=VALUE`` (:mod:`lipmpcc.planners.presets`): the planner under test's
  parameters (the shared approach keeps paper B's); the summary records ``preset``, ``planner_set`` and
  ``planner_params``.
- ``--cop-range DX DY``: the ALIP-MPC's centre-of-pressure box in the stance sole (a foot; ``0 0``: paper
  B's point foot; default ``0 0`` on the ALIP, the robot's ``alip_cop_range`` on a full body).

The outcome (:mod:`lipmpcc.studies.outcome`): ``fell``, ``stopped_early`` (a run that ends before its
last stone without a fall), ``outcome``; paper B's push test with the ALIP-QP or a point foot is a baseline
expected to fall (``expected_outcome: "fell"``, :func:`expected_outcome`).

Metrics (:func:`lipmpcc.loops.alip.loop_metrics`, the same on both logs): the step positions (on a full
body the measured sole centres at touch-down) against the stone centres (``step_rmse_m``), the soles
outside their stone's bounds (``stones_violated``), the step durations on the stones, and ``fall_step``,
the stone being stepped to when the run fails.

The study's parts live in modules named for them: the courses, pushes and planners
(:mod:`lipmpcc.studies.stone_course`), the full-body settings (:mod:`lipmpcc.studies.stone_params`) and paper B's
metrics, once for both robots (:mod:`lipmpcc.studies.stone_metrics`). Their names, read from this module, still
work with a DeprecationWarning until lipmpcc 0.3.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from .. import config
from .._deprecated import REMOVED_IN, moved_names
from ..exceptions import InvalidInputError
from ..loops.alip import AlipLoopConfig, AlipLoopLog, loop_metrics, run_alip_loop
from ..models.alip import AlipParams
from ..planners.presets import PlannerSettings, params_dict
from ..push import Push
from ..terrain import N_APPROACH, N_STONES, STEP_WIDTH, StoneSequence, load_stones, make_profile, paper_cases
from . import paper, replay, stone_course, stone_params
from . import stone_metrics as _metrics_module
from .viewer import LiveViewer, live_viewer
from .options import RunOptions, RunResult
from .outcome import add_outcome
from .paper import table_ii_cases
from .stone_course import (
    PLANNERS, LANDING_DEPTH, N_EXIT, FAST_STONES, FAST_PUSH_STONES, case_label, planner_params, make_planner,
    make_course, push_stones, paper_pushes, _push_test_summary, CourseScale, scaled_profile,
)
from .stone_params import robot_cop_range, stones_wbc_params, stones_timing, FullBodyStonesParams, _StepPushes
from .stone_metrics import full_body_stones_log, stone_metrics, stones_reached

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from ..loops.fullbody.loop import FullBodyLoop, LoopResult
    from ..planners.sources.alip import AlipFootstepSource
    from ..robots import RobotDescription
    from ..sim.stones_scene import StonesRobotSim

__all__ = [
    "PLANNERS", "planner_fields", "run_case", "study_table", "push_sweep", "FullBodyStonesRun", "simulate_full_body",
    "study_table_full_body", "expected_outcome", "run_stones", "run_push",
]

# the names that moved to their own modules: read from here, they warn (removed in lipmpcc 0.3)
moved_names(__name__, {n: m.__name__ for m in (stone_course, stone_params, _metrics_module) for n in m.__all__
                        if n != "PLANNERS"})  # every study module names its planners (lipmpcc sweep reads them)


# --------------------------------------------------------------------------------------------
# The ALIP
# --------------------------------------------------------------------------------------------
def run_case(
    planner: str,
    stones: StoneSequence,
    pushes: Sequence[Push] = (),
    alip: AlipParams | None = None,
    shared_approach: bool = True,
    solver: str | None = None,
    cop_range: tuple[float, float] = (0.0, 0.0),
    settings: PlannerSettings | None = None,
) -> tuple[AlipLoopLog, dict[str, Any]]:
    """Approach + ``stones`` on the ALIP with one planner; returns the log and its
    :func:`~lipmpcc.loops.alip.loop_metrics`.

    Args:
        planner: "alip-mpc" or "alip-qp".
        stones: the stones (without the approach).
        pushes: COM pushes (:func:`paper_pushes`; footstep indices count the approach).
        alip: ALIP constants.
        shared_approach: drive the approach with ALIP-MPC whatever ``planner`` is
            (False: ``planner`` walks its own approach).
        solver: ALIP-MPC solver ("sqp" or "ipopt").
        cop_range: the ALIP-MPC's centre-of-pressure box (x, y) [m] (a foot; (0, 0): paper B's point
            foot), for the planner under test and the approach; the loop then turns the ALIP about
            the planned centre of pressure.
        settings: ``--preset`` / ``--set`` for the planner under test (the shared approach keeps paper B's).
    """
    if not isinstance(stones, StoneSequence):
        raise InvalidInputError("stones", stones, "a StoneSequence")
    a = AlipParams() if alip is None else alip
    seq, _ = make_course(stones)
    pl = make_planner(planner, a, solver, cop_range=cop_range, settings=settings)
    app = make_planner("alip-mpc", a, cop_range=cop_range) if shared_approach else None
    log = run_alip_loop(
        pl,
        seq,
        config=AlipLoopConfig(alip=a, pushes=tuple(pushes)),
        approach_planner=app,
        approach_steps=N_APPROACH if shared_approach else 0,
    )
    return log, loop_metrics(log)


def study_table(
    n_stones: int = N_STONES,
    planners: Sequence[str] = PLANNERS,
    cases: Sequence[dict] | None = None,
    alip: AlipParams | None = None,
) -> list[dict[str, Any]]:
    """Table II on the ALIP: one row per course and planner with the run metrics and the paper's RMSE
    for that course (``cases``: dicts as :func:`lipmpcc.terrain.paper_cases`, its 21 courses by default)."""
    rows: list[dict[str, Any]] = []
    for case in paper_cases() if cases is None else cases:
        stones = make_profile(case["profile"], case["seed"], case["L"], case["W"]).head(n_stones)
        label = case_label(case["profile"], case["L"], case["W"], case["seed"])
        key = paper.case_key(case["profile"], case["L"], case["W"])
        for name in planners:
            _, m = run_case(name, stones, alip=alip)
            rows.append({"case": label, "planner": name, "paper_rmse_m": paper.table_ii_rmse(key, name), **m})
    return rows


def push_sweep(
    scales: Sequence[float] = (1.0, 0.75, 0.5),
    planners: Sequence[str] = PLANNERS,
    n_stones: int | None = None,
    alip: AlipParams | None = None,
) -> list[dict[str, Any]]:
    """Each of paper B's pushes alone, its force scaled, on the ALIP: one row per (push, scale, planner)
    with ``fell`` and ``fall_step`` (``n_stones``: None, the paper's 24)."""
    rows = []
    stones = push_stones(n_stones)
    for i, p in enumerate(paper.push_test().pushes):
        if p.stone > len(stones):
            continue
        for sc in scales:
            push = paper_pushes(sc)[i]
            for name in planners:
                _, m = run_case(name, stones, pushes=(push,), alip=alip)
                rows.append({"push": f"stone {p.stone}: F = {tuple(p.force)} N", "scale": sc, "planner": name,
                             "fell": m["fell"], "fall_step": m["fall_step"]})
    return rows


# --------------------------------------------------------------------------------------------
# A full body
# --------------------------------------------------------------------------------------------


def __getattr__(name: str) -> object:
    if name == "StepPushes":  # the full-body loop arms footstep-timed pushes itself now
        warnings.warn(
            "lipmpcc.studies.stepping_stones.StepPushes is deprecated: FullBodyLoop.run(schedule=lipmpcc.loops.base."
            f"PushSchedule(pushes)) arms pushes timed from footsteps; removed in lipmpcc {REMOVED_IN}",
            DeprecationWarning,
            stacklevel=2,
        )
        return _StepPushes
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@dataclass
class FullBodyStonesRun:
    """Everything a full-body stepping-stone run produces.

    Attributes:
        result: the loop's :class:`~lipmpcc.loops.fullbody.loop.LoopResult`.
        log: the run in the ALIP loop's log (:func:`full_body_stones_log`).
        metrics: :func:`stone_metrics`.
        source: the footstep source (its records hold every call).
        loop: the full-body loop (``loop.sim.model`` renders the video).
        course: approach + stones in the simulator's frame; stones: the stones alone.
        push_windows: the pushes as applied (t_start, t_end, (F_x, F_y)) [s, N], simulation time.
        alip: the ALIP constants; planner: "alip-mpc" or "alip-qp"; params: the run's settings.
    """

    result: LoopResult
    log: AlipLoopLog
    metrics: dict[str, Any]
    source: AlipFootstepSource
    loop: FullBodyLoop
    course: StoneSequence
    stones: StoneSequence
    push_windows: list[tuple[float, float, tuple[float, float]]]
    alip: AlipParams
    planner: str
    params: FullBodyStonesParams = field(default_factory=FullBodyStonesParams)

    def full_body_summary(self) -> dict[str, Any]:
        """The loop's full-body summary fields (wbc_ms, qp_failures, real_time_factor, ...)."""
        s = self.result.summary()
        for k in ("fell", "steps", "fall_reason"):  # the study's own (a missed stone, the pit, the simulator's)
            s.pop(k, None)
        return s


def simulate_full_body(
    robot: RobotDescription,
    planner: str,
    stones: StoneSequence,
    pushes: Sequence[Push] = (),
    params: FullBodyStonesParams | None = None,
    record_video: bool = False,
    progress: bool = False,
    settings: PlannerSettings | None = None,
    viewer: LiveViewer | None = None,
) -> FullBodyStonesRun:
    """One stepping-stone course on a full-body robot.

    Args:
        robot: a :class:`~lipmpcc.robots.RobotDescription` (``load_robot("digit_like")``).
        planner: ``"alip-mpc"`` or ``"alip-qp"`` (the approach is ALIP-MPC's for both).
        stones: the stones (the ALIP's frame, e.g. :func:`lipmpcc.terrain.make_profile`).
        pushes: torso pushes with footstep indices that count the approach (:func:`paper_pushes`).
        params: :class:`FullBodyStonesParams`.
        record_video: record configurations for a video.
        progress: progress bar.
        settings: ``--preset`` / ``--set`` for the planner under test (the approach keeps paper B's).
        viewer: a :class:`~lipmpcc.studies.viewer.LiveViewer` that shows the run live (None: none; the
            stones are in the model, the pushes are drawn as they act).
    """
    from ..loops.base import Course, PushSchedule
    from ..loops.fullbody.loop import FullBodyLoop, LoopParams
    from ..planners.sources.alip import AlipFootstepSource
    from ..sim.stones_scene import StonesRobotSim
    from ..control.references import SwingParams

    if planner not in PLANNERS:
        raise InvalidInputError("--planner", planner, "'alip-mpc' or 'alip-qp' for this scenario")
    prm = params or FullBodyStonesParams()
    feet, H = robot.standing.feet_xy, robot.standing.com_height
    if prm.com_height is not None:
        H = float(prm.com_height)
    scale = CourseScale.for_robot(robot) if prm.scale_to_robot else None
    w, app_len = (STEP_WIDTH, prm.approach_length) if scale is None else (scale.w, prm.approach_length * scale.length)
    course, _ = make_course(stones, feet, app_len, w)
    sim = StonesRobotSim(robot, course, prm.scene, standing_feet=feet)
    alip = AlipParams(mass=float(robot.total_mass), z_c=H)
    swing = SwingParams()
    timing, resync, sp = stones_timing(robot, prm, swing.min_remaining)
    cop = robot_cop_range(robot) if prm.cop_range is None else (float(prm.cop_range[0]), float(prm.cop_range[1]))
    mpc = {"step_reference": robot.alip_step_reference, "stone_bounds": robot.alip_stone_bounds,
           "max_speed": robot.alip_max_speed}
    source = AlipFootstepSource(make_planner(planner, alip, cop_range=cop, settings=settings, scale=scale, **mpc), course,
                                approach_planner=make_planner("alip-mpc", alip, cop_range=cop, scale=scale, **mpc),
                                approach_steps=N_APPROACH, params=sp, name=planner)
    source.warm_up()
    loop_params = LoopParams(com_height=H, first_stance="left", landing_depth=prm.landing_depth, swing=swing,
                             com_resync_on_plan=resync, touchdown_timing=timing, touchdown_contact=prm.touchdown_contact)
    wbc = prm.wbc if prm.wbc is not None else stones_wbc_params(robot)
    loop = FullBodyLoop(robot, planner=source, params=loop_params, wbc_params=wbc, sim=sim)
    if viewer is not None and pushes:
        viewer.set_scene(pushes=lambda: _windows(loop.armed_pushes))  # armed as the steps come
    result = loop.run(n_steps=len(course) + prm.n_exit, progress=progress, record_video=record_video, on_tick=viewer,
                      course=Course(stones=course), schedule=PushSchedule(tuple(pushes)))
    reason = (result.fall_reason or sim.fall_reason() or "") if result.fell else ""  # the loop's: right after a divergence too
    windows = _windows(result.pushes)
    alog = full_body_stones_log(result, source, course, windows, pushes, reason, prm.stone_tolerance)
    return FullBodyStonesRun(result, alog, stone_metrics(alog, source), source, loop, course, stones, windows, alip, planner, prm)


def _windows(pushes: Sequence[Push]) -> list[tuple[float, float, tuple[float, ...]]]:
    """(start, end [s], force [N]) of pushes with absolute times."""
    return [(p.t_start, p.t_end, p.force) for p in pushes]


def study_table_full_body(
    robot: RobotDescription,
    n_stones: int = N_STONES,
    planners: Sequence[str] = PLANNERS,
    cases: Sequence[dict] | None = None,
    params: FullBodyStonesParams | None = None,
) -> tuple[list[dict[str, Any]], dict[tuple[str, str], FullBodyStonesRun]]:
    """Table II on a full-body robot (``cases``: Table II's, :func:`lipmpcc.studies.paper.table_ii_cases`):
    one row per course and planner with the run metrics, the paper's RMSE for that course, the real-time
    factor and the WBC's QP failures; also the runs by (row label, planner)."""
    rows: list[dict[str, Any]] = []
    runs: dict[tuple[str, str], FullBodyStonesRun] = {}
    for case in table_ii_cases() if cases is None else cases:
        stones = make_profile(case["profile"], case["seed"], case["L"], case["W"]).head(n_stones)
        label = case_label(case["profile"], case["L"], case["W"], case["seed"])
        key = paper.case_key(case["profile"], case["L"], case["W"])
        for name in planners:
            run = simulate_full_body(robot, name, stones, params=params)
            runs[(label, name)] = run
            rows.append({"case": label, "planner": name, "paper_rmse_m": paper.table_ii_rmse(key, name), **run.metrics,
                         "real_time_factor": run.result.real_time_factor, "qp_failures": run.result.qp_failures})
    return rows, runs


# --------------------------------------------------------------------------------------------
# The studies from the CLI options: one set-up, one summary, one figure choice
# --------------------------------------------------------------------------------------------
def _planner_name(opts: RunOptions) -> str:
    name = opts.planner or "alip-mpc"
    if name not in PLANNERS:
        raise InvalidInputError("--planner", name, "'alip-mpc' or 'alip-qp' for this scenario")
    return name


def _robot_name(opts: RunOptions) -> str:
    """``"alip"`` (the reduced model, default) or the full-body robot's name or MJCF path."""
    robot = opts.robot or "alip"
    if robot in ("lip", ""):
        raise InvalidInputError("--robot", robot, "'alip' (the reduced model), 'digit_like' or a PATH.xml (full body)")
    return robot


def _cop_range(opts: RunOptions, planner: str) -> tuple[float, float] | None:
    """``--cop-range`` checked: None (not given) or two numbers in [0, 0.2) m, with alip-mpc only."""
    from ..robots import MAX_ALIP_COP_RANGE

    c = opts.cop_range
    if c is None:
        return None
    expected = f"two half-extents DX DY in [0, {MAX_ALIP_COP_RANGE:g}) m"
    try:
        d = tuple(float(x) for x in c)
    except (TypeError, ValueError):
        raise InvalidInputError("--cop-range", c, expected) from None
    if len(d) != 2 or not all(math.isfinite(x) and 0.0 <= x < MAX_ALIP_COP_RANGE for x in d):
        raise InvalidInputError("--cop-range", c, expected)
    if planner != "alip-mpc" and max(d) > 0.0:
        raise InvalidInputError("--cop-range", c, "0 0 with --planner alip-qp (only the ALIP-MPC plans the centre of pressure)")
    return (d[0], d[1])


def _n_stones(opts: RunOptions, available: int, full: int | None, fast: int | None) -> int:
    """The number of stones to walk: ``--steps``, else the study's (None: every available stone)."""
    n = available if full is None else int(config.horizon(full, fast))
    if opts.steps is not None:
        if not isinstance(opts.steps, int) or opts.steps < 1:
            raise InvalidInputError("--steps", opts.steps, "a positive integer")
        if opts.steps > available:
            raise InvalidInputError("--steps", opts.steps, f"at most {available} (the number of stones)")
        n = opts.steps
    return min(n, available)


def _stones_from_options(opts: RunOptions, scale: CourseScale | None = None) -> tuple[StoneSequence, dict[str, Any]]:
    """The ``stones`` study's stones and their description (profile, file, L, W, seed) for the summary; with a
    ``scale`` (a robot whose layout states its sizes) the profile's steps are scaled to it (:func:`scaled_profile`;
    ``--L`` / ``--W`` given are used as given) and ``L_used_m`` / ``W_used_m`` say what the stones use."""
    if opts.stones is not None:
        if opts.profile is not None or opts.L is not None or opts.W is not None:
            raise InvalidInputError("--stones", opts.stones, "either --stones FILE or --profile/--L/--W, not both")
        seq = load_stones(opts.stones)
        return seq, {"profile": None, "stones_file": str(opts.stones), "L": None, "W": None, "seed": None}
    profile = (opts.profile or "I").strip().upper()
    if profile not in ("I", "II", "III", "IV"):
        raise InvalidInputError("--profile", opts.profile, "one of I, II, III, IV")
    if profile != "I" and (opts.L is not None or opts.W is not None):
        raise InvalidInputError("--L/--W", (opts.L, opts.W), "only with --profile I")
    L = W = None
    if profile == "I":
        L = 0.4 if opts.L is None else float(opts.L)
        W = 0.15 if opts.W is None else float(opts.W)
        if not 0.0 < L <= 0.6:
            raise InvalidInputError("--L", L, "a step length in (0, 0.6] [m]")
        if not -0.2 <= W <= 0.2:
            raise InvalidInputError("--W", W, "a lateral offset in [-0.2, 0.2] [m]")
    info = {"profile": profile, "stones_file": None, "L": L, "W": W, "seed": opts.rng_seed if profile != "I" else None}
    if scale is None:
        return make_profile(profile, opts.rng_seed, L, W), info
    Lg, Wg = (opts.L, opts.W) if profile == "I" else (None, None)
    seq = scaled_profile(profile, scale, opts.rng_seed, None if Lg is None else L, None if Wg is None else W)
    if profile == "I":
        info.update({"L_used_m": float(seq.meta["L"][0]), "W_used_m": float(seq.meta["W"][0])})
    return seq, info


@dataclass(frozen=True)
class _Course:
    """One run's set-up from the CLI options."""

    planner: str
    robot: str  # "alip" or the full body's name or MJCF path
    stones: StoneSequence
    pushes: tuple[Push, ...]
    cop_range: tuple[float, float] | None
    extra: dict[str, Any]  # the summary's description of the course
    settings: PlannerSettings = field(default_factory=PlannerSettings)  # --preset / --set
    description: RobotDescription | None = None  # the full body, loaded (None: the reduced model or not yet)


def _stones_course(opts: RunOptions) -> _Course:
    robot = _robot_name(opts)
    planner = _planner_name(opts)
    desc, scale = None, None
    if robot != "alip" and opts.stones is None:  # a robot with its own sizes walks a course scaled to it
        from ..robots import load_robot

        desc = load_robot(robot)
        scale = CourseScale.for_robot(desc)
    seq, info = _stones_from_options(opts, scale)
    if scale is not None:  # (Digit's layouts state no sizes: their summaries are unchanged)
        info["course_scale"] = scale.summary()
    if opts.stones is not None:  # a stone file is walked to its end (--steps: its first stones)
        n = _n_stones(opts, len(seq), None, None)
    else:
        n = _n_stones(opts, len(seq), N_STONES, FAST_STONES["alip" if robot == "alip" else "full body"])
    info = {**info, "stones_available": len(seq)}
    key = paper.case_key(info["profile"], info["L"], info["W"]) if info["profile"] is not None else None
    extra = {**info, "paper_rmse_m": paper.table_ii_rmse(key, planner), "paper_case": key}
    return _Course(planner, robot, seq.head(n), (), _cop_range(opts, planner), extra, opts.planner_settings, desc)


def _push_course(opts: RunOptions) -> _Course:
    robot = _robot_name(opts)
    planner = _planner_name(opts)
    if opts.stones is not None or opts.profile is not None or opts.L is not None or opts.W is not None:
        raise InvalidInputError("--stones/--profile/--L/--W", opts.profile or opts.stones,
                                "none: the push test uses (L, W) = (0.4, 0) stones")
    test = paper.push_test()
    n = _n_stones(opts, test.n_stones, test.n_stones, FAST_PUSH_STONES)
    given = opts.extra.get("pushes")  # lipmpcc sweep's hook: these pushes instead of the paper's (scaled)
    pool = paper_pushes(float(opts.extra.get("push_scale", 1.0))) if given is None else tuple(given)
    pushes = tuple(p for p in pool if p.step is None or p.step < N_APPROACH + n)
    described = _push_test_summary() if given is None and "push_scale" not in opts.extra else [
        {"step": p.step, "force_N": list(p.force), "window_s": [p.t_start, p.t_end]} for p in pushes]
    extra = {"profile": None, "L": test.L, "W": test.W, "pushes": described}
    return _Course(planner, robot, push_stones(n), pushes, _cop_range(opts, planner), extra, opts.planner_settings)


def _summary(scenario: str, course: _Course, robot: str, m: dict[str, Any], alip: AlipParams,
             run: FullBodyStonesRun | None) -> dict[str, Any]:
    """summary.json: the course, the stone metrics, the model; a full-body run adds the loop's fields."""
    s: dict[str, Any] = {"scenario": scenario, "planner": course.planner, "robot": robot}
    s.update(course.extra)
    if run is not None and scenario == "push":
        s["pushes_applied"] = len(run.push_windows)
    s.update({k: m[k] for k in ("n_stones", "fell", "fall_step", "fall_reason", "steps_completed", "step_rmse_m",
                                "step_error_max_m", "stones_violated", "step_duration_min_s", "step_duration_max_s")})
    s["solve_ms"] = {k: m["solve_ms"][k] for k in ("median", "p90", "max", "n")}
    s["plan_ms"] = {k: m["plan_ms"][k] for k in ("median", "p90", "max", "n")}
    s["solver_failures"] = m["solver_failures"]
    s["fallback_ticks"] = m["fallback_ticks"]
    s["solver"] = "sqpmethod+qrqp" if course.planner == "alip-mpc" else "proxqp"
    s["approach"] = f"{N_APPROACH} steps driven by alip-mpc" + ("" if run is None else " on the full-body robot")
    s["model"] = {"mass_kg": alip.mass, "z_c_m": alip.z_c, "g": alip.g}
    s["fast_mode"] = config.fast_mode()
    if run is None:
        s["model"]["cop_range_m"] = list(course.cop_range or (0.0, 0.0))
        s.update(planner_fields(course, alip, None))
        return s
    s.update(run.full_body_summary())
    s["model"].update(_full_body_model(run))
    s["solver_failures_approach"] = int(run.source.approach_failures)
    cops = [np.asarray(r.result.cop_offset) for r in run.source.course_records() if r.result is not None]
    s["cop_offset_max_m"] = np.max(np.abs(cops), axis=0).tolist() if cops else [0.0, 0.0]
    s.update(planner_fields(course, alip, run))
    return s


def planner_fields(course: _Course, alip: AlipParams, run: FullBodyStonesRun | None) -> dict[str, Any]:
    """The summary's ``preset`` (``--preset``, else the planner's paper preset), ``planner_set`` (the ``--set``
    values) and ``planner_params`` (every field of the effective parameters of the planner under test)."""
    settings = course.settings
    if run is not None:
        prm = run.source.planner.params
    else:
        prm = planner_params(course.planner, alip, course.cop_range or (0.0, 0.0), settings)
    default = "paper-b" if course.planner == "alip-mpc" else "paper-b-qp"
    return {"preset": settings.preset or default, "planner_set": dict(settings.values), "planner_params": params_dict(prm)}


def _full_body_model(run: FullBodyStonesRun) -> dict[str, Any]:
    """The full-body run's model choices in the summary."""
    boxes = run.loop.sim.scene_boxes
    return {
        "lambda_1ps": run.alip.lam,
        "dcm": "eq. 2 with L = k + m (c - p) x c_dot" if run.params.centroidal_momentum
        else "eq. 2 with the lumped-mass L = m (c - p) x c_dot",
        "landing_depth_m": run.params.landing_depth,
        "contact_phase": run.source.contact_phase,
        "planner_rate_hz": run.params.rate_hz,
        "wbc_com_kp_kd": [list(run.loop.wbc.params.com.kp), list(run.loop.wbc.params.com.kd)],
        "cop_range_m": list(getattr(run.source.planner.params, "cop_range", (0.0, 0.0))),
        "stone_box_m": next(
            ([2 * b.half_size[0], 2 * b.half_size[1], 2 * b.half_size[2]] for b in boxes if b.kind == "stone"), None
        ),
    }


def _figures(scenario: str, log: AlipLoopLog, title: str, run: FullBodyStonesRun | None) -> dict[str, Figure]:
    from ..plots import stepping_stones as plots

    if scenario == "stones":
        return {"footprints": plots.plot_footprints(log, title=title),
                "durations_dcm": plots.plot_durations_and_dcm(log, title=title)}
    figures = {"push_response": plots.plot_push_response(log, title=title),
               "footprints": plots.plot_footprints(log, title=title)}
    if run is not None and max(getattr(run.source.planner.params, "cop_range", (0.0, 0.0))) > 0.0:
        figures["cop_offsets"] = plots.plot_cop_offsets(run.source, run.push_windows, title=title + ": planned CoP offset")
    return figures


def expected_outcome(scenario: str, planner: str, cop_range: tuple[float, float]) -> str | None:
    """The outcome a known baseline has: ``"fell"`` for paper B's push test with the ALIP-QP (paper B: it
    fails on the lateral pushes) or with a point foot (``cop_range`` (0, 0): the ALIP-MPC cannot survive
    the backward push, :mod:`lipmpcc.planners.alip_mpc`); None otherwise."""
    if scenario == "push" and (planner == "alip-qp" or max(cop_range) <= 0.0):
        return "fell"
    return None


def _add_outcome(summary: dict[str, Any], scenario: str, course: _Course, log: AlipLoopLog,
                 result: LoopResult | None) -> None:
    """The outcome fields (:mod:`lipmpcc.studies.outcome`) with ``stones_reached`` / ``stones_total``; a run
    that ends without a fall before its last stone stopped early."""
    total = int(np.sum(course.stones.is_stone))
    reached = min(stones_reached(log), total)
    summary["stones_reached"], summary["stones_total"] = reached, total
    early = None
    if not summary["fell"] and reached < total:
        early = f"ended after {reached} of {total} stones without a fall (the run's step or time bound)"
    cop = summary["model"].get("cop_range_m") or (0.0, 0.0)
    add_outcome(summary, stopped_early=early, result=result,
                expected_outcome=expected_outcome(scenario, course.planner, (float(cop[0]), float(cop[1]))))


def _run(opts: RunOptions, scenario: str, course: _Course) -> RunResult:
    what = course.stones.name if scenario == "stones" else "push test"
    if course.robot == "alip":
        alip = AlipParams()
        cop = course.cop_range or (0.0, 0.0)
        log, m = run_case(course.planner, course.stones, pushes=course.pushes, alip=alip, cop_range=cop,
                          settings=course.settings)
        foot = f" with a foot ({cop[0]:g} x {cop[1]:g} m)" if scenario == "push" and max(cop) > 0 else ""
        summary = _summary(scenario, course, "alip", m, alip, None)
        _add_outcome(summary, scenario, course, log, None)
        return RunResult(summary=summary, figures=_figures(scenario, log, f"{course.planner}, {what}{foot}", None), log=log)
    from ..robots import load_robot

    robot = course.description if course.description is not None else load_robot(course.robot)
    live = live_viewer(opts)
    try:  # the frames are always recorded: the run's replay (studies.replay)
        run = simulate_full_body(robot, course.planner, course.stones, pushes=course.pushes,
                                 params=FullBodyStonesParams(cop_range=course.cop_range), record_video=True,
                                 progress=True, settings=course.settings, viewer=live)
    finally:
        if live is not None:
            live.close()
    summary = _summary(scenario, course, robot.name, run.metrics, run.alip, run)
    _add_outcome(summary, scenario, course, run.log, run.result)
    rep, files = replay.run_outputs(opts, robot, run.loop.sim.model, run.result, pushes=run.push_windows,
                                    fps=run.loop.params.video_fps)
    figures = _figures(scenario, run.log, f"{course.planner} on {robot.name}, {what}", run)
    return RunResult(summary=summary, figures=figures, log=run, files=list(files), replay=rep)


def run_stones(opts: RunOptions) -> RunResult:
    """``lipmpcc run stones``: one stepping-stone course with one planner."""
    return _run(opts, "stones", _stones_course(opts))


def run_push(opts: RunOptions) -> RunResult:
    """``lipmpcc run push``: paper B's perturbation test on (L, W) = (0.4, 0) stones."""
    return _run(opts, "push", _push_course(opts))
