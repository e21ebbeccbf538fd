"""Paper B's studies on the full-body robot: ``stones`` and ``push`` with ``--robot digit_like`` (or ``PATH.xml``).

ALIP-MPC or ALIP-QP (:mod:`lipmpcc.planners.alip_source`) drives the full-body loop
(:mod:`lipmpcc.loops.fullbody.loop`: MuJoCo at 2 kHz, the C++ whole-body QP at 400 Hz), re-planning at
25 Hz within each swing, on a MuJoCo course of stepping stones (:mod:`lipmpcc.sim.stones_scene`: stone
boxes with their tops at z = 0 over a pit 0.6 m deep, solid approach and exit platforms).
:mod:`lipmpcc.scenarios.stepping_stones` dispatches here when ``--robot`` is not ``alip``.

**Set-up** (as the reduced runs, :mod:`lipmpcc.scenarios.stepping_stones`):

- The course is the reduced one translated so that its standing feet (0, ±0.14 m) are centred on the
  robot's standing feet (digit_like: (0, ±0.131 m), so a shift of 0): the 6 approach footholds of
  :func:`lipmpcc.terrain.approach_footholds` (free, on the platform), then the stones, then two free
  footholds on the exit platform (so that a fall right after the last stone is seen).
- The robot starts standing, shifts its weight onto the left foot (0.6 s), walks the approach driven by
  ALIP-MPC for every planner under test (consistent conditions when the planner under test takes over,
  paper B) and enters the stones with a right swing.
- ``stones``: 32 stones (12 in fast mode), ``--steps`` to walk fewer; ``push``: 24 stones of
  (L, W) = (0.4, 0) (22 in fast mode) with paper B's four pushes on the torso, 0.1–0.2 s into the swings
  towards stones 5 (F_x = +150 N), 10 (−150 N), 15 (F_y = +75 N) and 20 (−75 N). The pushes are
  registered at the touch-down that starts those swings (the step timing is not known in advance).

**Model choices** (in the summary's ``model``):

- ALIP constants: the robot's mass and z_c = the loop's COM height = the standing COM height (0.953 m
  for digit_like, λ = 3.21 1/s), so that the ALIP-MPC, the loop's LIP COM reference and the DCM share one
  λ. The planners' other parameters are paper B's (:meth:`AlipMpcParams.paper`, :meth:`AlipQpParams.paper`).
- DCM (paper B eq. 2) from the angular momentum about the stance contact point of the lumped mass,
  L = m (c − p) × ċ (see :mod:`lipmpcc.planners.alip_source`).
- Landing: the swing foot aims ``LANDING_DEPTH`` = 15 mm below the stone top so that it meets the stone
  with a downward speed and the contact instant is sharp (contact at τ ≈ 0.84 of the swing phase, within
  ±0.01 for a given swing length). Aiming at the top, the foot creeps down over the last ~5 % of the swing
  and contact comes anywhere in τ = 0.93–0.98, which scatters the step durations by ±15 ms; 10 ms moves
  the next initial DCM by ~1.5 cm. The footstep source learns τ_c and stretches the requested duration so
  that contact happens at the planned time (measured: |measured − planned| ≈ 1–3 ms).
- The loop's LIP COM reference restarts at each touch-down from the measured state (the loop's default):
  within a step the COM follows the LIP exactly (< 1 mm) until the end of long swings.
- The horizontal COM task of the whole-body QP takes the robot description's ``alip_com_gains``
  (:func:`stones_wbc_params`): for digit_like k_p = 16 1/s², k_d = 8 1/s (critically damped at 4 1/s),
  against 100 and 20 in the QP's defaults and in paper A's runs. Paper B's low level tracks base height,
  torso orientation and the swing foot only, and leaves the horizontal COM to the ALIP the planner
  assumes. With the stiff task the QP pulled the COM back onto the LIP reference of the step's start
  whenever the planner had re-timed or moved the step, and the two disagreed step after step. Measured
  on digit_like (seed 0; soft / stiff): Profile I L = 0.55 m, W = +0.15 no fall, no stone missed / fall
  at stone 10; W = −0.15 no fall, one sole 1.3 mm beyond its stone's side / fall at stone 19; Profiles
  II–IV seeds 0–4 no fall, 14 of 15 with no stone missed (III seed 0: one sole 1.2 mm beyond) / 13 of 15.
  Digit v3 keeps the stiff task (``alip_com_gains`` None): with 16/8 it falls on Profile I (0.4, +0.15)
  and II, which it crosses with 100/20.

- **Ankle** (our extension of paper B, the robot description's ``alip_cop_range``; digit_like ±6 cm
  along, ±2.5 cm across the sole): the ALIP-MPC also plans the centre of pressure in the stance sole for
  the rest of each step (:attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`) and the loop's LIP
  reference turns about it. Paper B's point foot cannot survive its own push test (the backward push
  leaves a DCM no step sequence recovers on the stones, :func:`lipmpcc.models.alip.min_forward_dcm_on_stones`);
  with the ankle digit_like survives all four pushes. Measured on digit_like (seed 0; ankle / point foot):
  Profile I RMSE 3.5–11 mm / 7–29 mm, II–IV 8–10 mm / 15–23 mm, no fall and no sole off its stone on
  any course; push test: survives / falls at stone 9. Digit v3 (±4 cm × ±1.5 cm, inside its controller's
  CoP box) now also completes Profile I (0.4, −0.15) and III. ``FullBodyStonesParams(cop_range=(0, 0))``
  runs paper B's point foot.

**Metrics** (:func:`stone_metrics`, the reduced runs' :func:`lipmpcc.loops.alip.loop_metrics` on the
full-body log): the step positions are the *measured* sole centres at touch-down (detected from contact);
``step_rmse_m`` is their RMSE to the stone centres, ``stones_violated`` counts soles outside the stone's
0.2 × 0.1 m bounds, ``fell``/``fall_step`` come from the simulator (torso height or tilt, or a foot in the
pit); ``fall_step`` is the stone being stepped to when the fall is detected.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..exceptions import InvalidInputError, ParameterError
from ..models.alip import AlipParams, KinematicLimits
from ..loops.alip import AlipLoopLog, Push, loop_metrics
from ..terrain import L_APPROACH, N_APPROACH, StoneSequence, approach_footholds, initial_feet
from . import RunOptions, RunResult

__all__ = [
    "LANDING_DEPTH",
    "FullBodyStonesParams",
    "FullBodyStonesRun",
    "StepPushes",
    "make_course",
    "paper_cases_fullbody",
    "simulate",
    "stone_metrics",
    "robot_cop_range",
    "stones_wbc_params",
    "study_table",
    "to_alip_log",
    "run_stones",
    "run_push",
]

LANDING_DEPTH = 0.015  # [m]
N_EXIT = 2


def robot_cop_range(robot: Any) -> tuple[float, float]:
    """The ALIP-MPC's centre-of-pressure box (x, y) [m] on ``robot``: its description's
    ``alip_cop_range``, or (0, 0) (paper B's point foot) when it has none."""
    r = getattr(robot, "alip_cop_range", None)
    return (0.0, 0.0) if r is None else (float(r[0]), float(r[1]))


def stones_wbc_params(robot: Any) -> Any:
    """The whole-body QP's parameters for paper B's runs on ``robot``: the robot's own
    (:meth:`~lipmpcc.wbc.WbcParams.for_robot`), with the horizontal COM task's k_p, k_d replaced by the
    description's ``alip_com_gains`` when it has them (height gains and every weight unchanged)."""
    from dataclasses import replace

    from ..wbc import TaskGains, WbcParams

    base = WbcParams.for_robot(robot)
    gains = getattr(robot, "alip_com_gains", None)
    if gains is None:
        return base
    kp, kd = gains
    c = base.com
    return replace(base, com=TaskGains(weight=c.weight, kp=(kp, kp, c.kp[2]), kd=(kd, kd, c.kd[2])))


@dataclass(frozen=True)
class FullBodyStonesParams:
    """Settings of a full-body stepping-stone run.

    Attributes:
        landing_depth: the swing foot aims this far below the stone top [m].
        n_exit: free footsteps on the exit platform after the last stone.
        centroidal_momentum: include the centroidal angular momentum in the contact L (see module doc).
        rate_hz: planner rate [Hz] (paper B: 25 Hz).
        stone_tolerance: a measured sole counts inside its stone's bounds within this tolerance [m].
        com_resync: re-start the loop's LIP COM reference from the measured COM state at every planner
            update (``LoopParams.com_resync_on_plan``) rather than at touch-down only. Off by default:
            re-started every 40 ms the reference inherits the COM's tracking lag, and the measured initial
            DCM then decays by ~5 % over each step (the planner's model does not have that).
        wbc: :class:`~lipmpcc.wbc.WbcParams` of the whole-body QP (None: :func:`stones_wbc_params`).
        com_height: the loop's constant COM height and the ALIP's z_c [m] (None: the standing COM height).
        approach_length: length of the last approach step [m] (see :func:`make_course`).
        scene: the course's geometry (None: :class:`~lipmpcc.sim.stones_scene.StonesSceneParams` defaults).
        cop_range: the ALIP-MPC's centre-of-pressure box (x, y) [m] (its ankle strategy,
            :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`; (0, 0): paper B's point foot);
            None: the robot description's ``alip_cop_range`` (a point foot when it has none).
    """

    landing_depth: float = LANDING_DEPTH
    n_exit: int = N_EXIT
    centroidal_momentum: bool = False
    rate_hz: float = 25.0
    stone_tolerance: float = 0.0
    com_resync: bool = False
    wbc: Any = None
    com_height: float | None = None
    approach_length: float = L_APPROACH
    scene: Any = None
    cop_range: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.landing_depth) and 0.0 <= self.landing_depth <= 0.05):
            raise ParameterError("landing_depth", self.landing_depth, "a depth in [0, 0.05] m")
        if not (isinstance(self.n_exit, (int, np.integer)) and 0 <= self.n_exit <= 10):
            raise ParameterError("n_exit", self.n_exit, "an integer in [0, 10]")
        if not (math.isfinite(self.rate_hz) and self.rate_hz > 0):
            raise ParameterError("rate_hz", self.rate_hz, "a positive rate [Hz]")
        if not (math.isfinite(self.stone_tolerance) and self.stone_tolerance >= 0):
            raise ParameterError("stone_tolerance", self.stone_tolerance, "a non-negative length [m]")
        if self.com_height is not None and not (math.isfinite(self.com_height) and 0.3 < self.com_height < 2.0):
            raise ParameterError("com_height", self.com_height, "None or a COM height in (0.3, 2) m")
        if not (math.isfinite(self.approach_length) and 0.0 < self.approach_length <= 0.6):
            raise ParameterError("approach_length", self.approach_length, "a step length in (0, 0.6] m")


# --------------------------------------------------------------------------------------------
# Course
# --------------------------------------------------------------------------------------------
def make_course(
    stones: StoneSequence, standing_feet: np.ndarray | None = None, approach_length: float = L_APPROACH
) -> tuple[StoneSequence, np.ndarray]:
    """Approach footholds + ``stones``, translated onto the robot's standing feet.

    Args:
        stones: the stones (world frame of the reduced runs: standing feet at (0, ±0.14) m).
        standing_feet: (2, 2) the robot's standing sole positions (left, right) [m]; None: no shift.
        approach_length: length of the last approach step [m] (the approach ramps up to it); the stones
            keep their positions relative to the last approach foothold.

    Returns:
        The course (approach + stones) in the simulator's world frame, and the shift applied (2,) [m].
    """
    if not isinstance(stones, StoneSequence) or len(stones) == 0:
        raise InvalidInputError("stones", stones, "a non-empty StoneSequence")
    app = approach_footholds(L_app=approach_length)
    moved = app.centers[-1] - approach_footholds().centers[-1]
    if np.any(moved != 0.0):
        stones = StoneSequence(stones.centers + moved, stones.sizes, stones.sides, stones.is_stone, stones.name, dict(stones.meta))
    seq = app + stones
    shift = np.zeros(2)
    if standing_feet is not None:
        feet = np.asarray(standing_feet, dtype=float).reshape(2, 2)
        ref = np.mean(np.vstack(initial_feet()), axis=0)
        shift = np.mean(feet, axis=0) - ref
    if np.any(shift != 0.0):
        seq = StoneSequence(seq.centers + shift, seq.sizes, seq.sides, seq.is_stone, seq.name, dict(seq.meta))
    return seq, shift


# --------------------------------------------------------------------------------------------
# Pushes at the start of given footsteps
# --------------------------------------------------------------------------------------------
class StepPushes:
    """A footstep source wrapper that pushes the torso during given footsteps.

    The step timing of paper B's runs is not known in advance, so each :class:`~lipmpcc.loops.alip.Push`
    (``force`` (F_x, F_y) [N], window ``t_start``–``t_end`` relative to the touch-down that starts footstep
    ``step``) is registered on the simulator at the first planner call of that footstep (its lift-off).

    Attributes:
        windows: registered pushes as (t_start, t_end, (F_x, F_y)) in simulation time [s].
    """

    def __init__(self, source: Any, sim: Any, pushes: Sequence[Push]) -> None:
        for p in pushes:
            if not isinstance(p, Push) or p.step is None:
                raise InvalidInputError("pushes", p, "lipmpcc.loops.alip.Push objects with a footstep index")
        self.source = source
        self.sim = sim
        self.pushes = tuple(pushes)
        self.name = source.name
        self.rate_hz = source.rate_hz
        self.windows: list[tuple[float, float, tuple[float, float]]] = []
        self._last = -1

    def reset(self) -> None:
        self.source.reset()
        self.windows = []
        self._last = -1

    def plan(self, inp: Any) -> Any:
        k = int(inp.step_index)
        if k != self._last:
            self._last = k
            t_td = float(inp.t) - float(inp.time_since_touchdown)
            for p in self.pushes:
                if p.step == k:
                    a, b = t_td + p.t_start, t_td + p.t_end
                    self.sim.add_push(np.array([p.force[0], p.force[1], 0.0]), a, b - a)
                    self.windows.append((a, b, p.force))
        return self.source.plan(inp)


# --------------------------------------------------------------------------------------------
# Logs and metrics
# --------------------------------------------------------------------------------------------
def to_alip_log(
    result: Any,
    source: Any,
    course: StoneSequence,
    push_windows: Sequence[tuple[float, float, tuple[float, float]]] = (),
    pushes: Sequence[Push] = (),
    fall_reason: str = "",
    stone_tolerance: float = 0.0,
    limits: KinematicLimits | None = None,
) -> AlipLoopLog:
    """The full-body run in the reduced runs' log format (:class:`~lipmpcc.loops.alip.AlipLoopLog`),
    so that :func:`~lipmpcc.loops.alip.loop_metrics` and :mod:`lipmpcc.plots.stepping_stones` apply.

    Times start at the first lift-off (the end of the weight shift). Footholds are the measured soles at
    touch-down; ``z_initial`` is the measured initial DCM of each step (eq. 10 at the planner's first call
    of the step, at its touch-down); ``com``/``com_vel``/``dcm`` are the loop's 400 Hz samples (DCM c + ċ/ω); the plan arrays are the
    source's records (planned duration and foothold at each 25 Hz call).
    """
    lim = limits or getattr(getattr(source.planner, "params", None), "limits", None) or KinematicLimits()
    recs = source.records
    t0 = float(recs[0].t) if recs else 0.0
    log = result.log
    tds = result.touchdowns[: len(course)]
    n = len(tds)
    feet = np.array([td.pos[:2] for td in tds], dtype=float).reshape(n, 2)
    sides = np.array([1 if td.side == "left" else -1 for td in tds], dtype=int)
    in_stone = np.array(
        [(not course.is_stone[k]) or course[k].contains(feet[k], stone_tolerance) for k in range(n)], dtype=bool
    )
    prev = [recs[0].stance if recs else np.zeros(2)] + [feet[k] for k in range(n - 1)]
    kin_ok = np.array([lim.contains(feet[k] - prev[k], int(sides[k]), 1e-3) for k in range(n)], dtype=bool)
    first = {}
    for r in recs:
        first.setdefault(r.step_index, r)
    lam = float(source.alip.lam)
    z_init = [(first[k].dcm - first[k].stance) * math.exp(-lam * first[k].time_since_touchdown)
              for k in sorted(first) if k <= n]
    bounds = source.planner.params.dcm_bounds
    fell = bool(result.fell)
    fall_index = None
    if fell:
        fall_index = int(len(result.touchdowns))
        if n and not in_stone[-1] and fall_index == n:
            fall_index = n - 1
    completed = (not fell) and n >= len(course)
    plan_status = [r.status for r in recs]
    return AlipLoopLog(
        sequence=course,
        t=np.asarray(log.t, dtype=float) - t0,
        com=np.asarray(log.com, dtype=float)[:, :2],
        com_vel=np.asarray(log.com_vel, dtype=float)[:, :2],
        dcm=np.asarray(log.dcm, dtype=float),
        sample_step=np.searchsorted(np.array([td.t for td in result.touchdowns]), np.asarray(log.t), side="right"),
        footholds=feet,
        step_index=np.arange(n, dtype=int),
        step_sides=sides,
        durations=np.array([td.duration for td in tds], dtype=float),
        td_times=np.array([td.t for td in tds], dtype=float) - t0,
        z_initial=np.array(z_init, dtype=float).reshape(-1, 2),
        in_stone=in_stone,
        kin_ok=kin_ok,
        plan_t=np.array([r.t for r in recs], dtype=float) - t0,
        plan_step=np.array([r.step_index for r in recs], dtype=int),
        plan_t_step=np.array([r.time_since_touchdown for r in recs], dtype=float),
        plan_T=np.array([r.planned_duration for r in recs], dtype=float),
        plan_foothold=np.array(
            [r.result.next_foothold if r.result is not None else np.full(2, np.nan) for r in recs], dtype=float
        ).reshape(-1, 2),
        solve_time=np.array([r.result.solve_time if r.result is not None else np.nan for r in recs], dtype=float),
        plan_time=np.array([r.result.plan_time if r.result is not None else np.nan for r in recs], dtype=float),
        plan_fallback=np.array([r.result is None or bool(r.result.fallback) for r in recs], dtype=bool),
        plan_status=plan_status,
        start_stance=np.asarray(recs[0].stance if recs else np.zeros(2), dtype=float),
        start_swing=None,
        fell=fell,
        fall_index=fall_index,
        fall_reason=fall_reason,
        fall_time=(float(result.fall_time) - t0) if fell else None,
        completed=completed,
        solver_failures=int(source.solver_failures),
        pushes=tuple(pushes),
        push_windows=[(a - t0, b - t0, f) for a, b, f in push_windows],
        dcm_bounds=bounds,
        lam=lam,
    )


def stone_metrics(alip_log: AlipLoopLog, source: Any) -> dict[str, Any]:
    """:func:`~lipmpcc.loops.alip.loop_metrics` of the full-body run; ``solve_ms`` and ``plan_ms`` count the
    planner under test only (the approach is planned by ALIP-MPC for every planner)."""
    from ..metrics import timing_stats_ms

    m = loop_metrics(alip_log)
    recs = [r for r in source.course_records() if r.result is not None]
    m["solve_ms"] = timing_stats_ms([r.result.solve_time for r in recs])
    m["plan_ms"] = timing_stats_ms([r.result.plan_time for r in recs])
    m["fallback_ticks"] = int(sum(r.result is None or r.result.fallback for r in source.course_records()))
    return m


# --------------------------------------------------------------------------------------------
# A run
# --------------------------------------------------------------------------------------------
@dataclass
class FullBodyStonesRun:
    """Everything a full-body stepping-stone run produces.

    Attributes:
        result: the loop's :class:`~lipmpcc.loops.fullbody.loop.LoopResult`.
        log: the run as an :class:`~lipmpcc.loops.alip.AlipLoopLog` (:func:`to_alip_log`).
        metrics: :func:`stone_metrics`.
        source: the :class:`~lipmpcc.planners.alip_source.AlipFootstepSource` (its records hold every call).
        loop: the :class:`~lipmpcc.loops.fullbody.loop.FullBodyLoop` (``loop.sim.model`` renders the video).
        course: approach + stones in the simulator's frame; stones: the stones alone.
        push_windows: the pushes as applied (t_start, t_end, (F_x, F_y)) [s, N], simulation time.
        alip: the ALIP constants; planner: "alip-mpc" or "alip-qp".
    """

    result: Any
    log: AlipLoopLog
    metrics: dict[str, Any]
    source: Any
    loop: Any
    course: StoneSequence
    stones: StoneSequence
    push_windows: list[tuple[float, float, tuple[float, float]]]
    alip: AlipParams
    planner: str
    params: FullBodyStonesParams = field(default_factory=FullBodyStonesParams)

    def full_body_summary(self) -> dict[str, Any]:
        """The loop's full-body summary fields (wbc_ms, qp_failures, real_time_factor, ...)."""
        s = self.result.summary()
        for k in ("fell", "steps"):
            s.pop(k, None)
        return s


def _standing(robot: Any) -> tuple[np.ndarray, float]:
    """Standing sole positions (2, 2) and COM height [m] of ``robot`` (a plain simulator)."""
    from ..sim.robot_sim import RobotSim

    sim = RobotSim(robot)
    (pl, _), (pr, _) = sim.foot_poses()
    return np.array([pl[:2], pr[:2]], dtype=float), float(sim.com()[2])


def simulate(
    robot: Any,
    planner: str,
    stones: StoneSequence,
    pushes: Sequence[Push] = (),
    params: FullBodyStonesParams | None = None,
    record_video: bool = False,
    progress: bool = False,
) -> FullBodyStonesRun:
    """One stepping-stone course on a full-body robot.

    Args:
        robot: a :class:`~lipmpcc.robot.RobotDescription` (``load_robot("digit_like")``).
        planner: ``"alip-mpc"`` or ``"alip-qp"`` (the approach is ALIP-MPC's for both).
        stones: the stones (reduced runs' frame, e.g. :func:`lipmpcc.terrain.make_profile`).
        pushes: torso pushes (:class:`~lipmpcc.loops.alip.Push` with footstep indices that count the
            approach, e.g. :func:`lipmpcc.scenarios.stepping_stones.paper_pushes`).
        params: :class:`FullBodyStonesParams`.
        record_video: record configurations for a video.
        progress: progress bar.
    """
    from ..planners.alip_source import AlipFootstepSource, AlipSourceParams
    from ..loops.fullbody.loop import FullBodyLoop, LoopParams
    from ..sim.stones_scene import StonesRobotSim
    from ..trajectory import SwingParams
    from .stepping_stones import PLANNERS, make_planner

    if planner not in PLANNERS:
        raise InvalidInputError("--planner", planner, "'alip-mpc' or 'alip-qp' for this scenario")
    prm = params or FullBodyStonesParams()
    feet, H = _standing(robot)
    if prm.com_height is not None:
        H = float(prm.com_height)
    course, _ = make_course(stones, feet, prm.approach_length)
    sim = StonesRobotSim(robot, course, prm.scene, standing_feet=feet)
    alip = AlipParams(mass=float(robot.total_mass), z_c=H)
    swing = SwingParams()
    sp = AlipSourceParams(rate_hz=prm.rate_hz, swing_min_remaining=swing.min_remaining,
                          centroidal_momentum=prm.centroidal_momentum)
    cop = robot_cop_range(robot) if prm.cop_range is None else tuple(float(x) for x in prm.cop_range)
    source = AlipFootstepSource(make_planner(planner, alip, cop_range=cop), course,
                                approach_planner=make_planner("alip-mpc", alip, cop_range=cop),
                                approach_steps=N_APPROACH, params=sp, name=planner)
    source.warm_up()
    wrapped: Any = StepPushes(source, sim, pushes) if pushes else source
    loop_params = LoopParams(com_height=H, first_stance="left", landing_depth=prm.landing_depth, swing=swing,
                             com_resync_on_plan=prm.com_resync)
    wbc = prm.wbc if prm.wbc is not None else stones_wbc_params(robot)
    loop = FullBodyLoop(robot, planner=wrapped, params=loop_params, wbc_params=wbc, sim=sim)
    result = loop.run(n_steps=len(course) + prm.n_exit, progress=progress, record_video=record_video)
    reason = (sim.fall_reason() or "") if result.fell else ""
    windows = list(wrapped.windows) if pushes else []
    alog = to_alip_log(result, source, course, windows, pushes, reason, prm.stone_tolerance)
    metrics = stone_metrics(alog, source)
    return FullBodyStonesRun(result, alog, metrics, source, loop, course, stones, windows, alip, planner, prm)


def paper_cases_fullbody() -> list[dict]:
    """The full-body study's cases: the 6 of profile I and seed 0 of profiles II, III and IV."""
    from ..terrain import paper_cases

    return [c for c in paper_cases() if c["profile"] == "I" or c["seed"] == 0]


def study_table(
    robot: Any,
    n_stones: int = 32,
    planners: Sequence[str] = ("alip-mpc", "alip-qp"),
    cases: Sequence[dict] | None = None,
    params: FullBodyStonesParams | None = None,
) -> tuple[list[dict[str, Any]], dict[tuple[str, str], FullBodyStonesRun]]:
    """Table II on the full-body robot: one row per case and planner with the run metrics, the paper's
    RMSE for that case, the real-time factor and the WBC's QP failures; also the runs by (case, planner)."""
    from ..terrain import make_profile
    from .stepping_stones import PAPER_TABLE_II, case_label

    rows: list[dict[str, Any]] = []
    runs: dict[tuple[str, str], FullBodyStonesRun] = {}
    for case in paper_cases_fullbody() if cases is None else cases:
        stones = make_profile(case["profile"], case["seed"], case["L"], case["W"]).head(n_stones)
        label = case_label(case["profile"], case["L"], case["W"], case["seed"])
        key = label if case["profile"] == "I" else case["profile"]
        for name in planners:
            run = simulate(robot, name, stones, params=params)
            runs[(label, name)] = run
            rows.append(
                {
                    "case": label,
                    "planner": name,
                    "paper_rmse_m": PAPER_TABLE_II[key][name],
                    **run.metrics,
                    "real_time_factor": run.result.real_time_factor,
                    "qp_failures": run.result.qp_failures,
                }
            )
    return rows, runs


# --------------------------------------------------------------------------------------------
# CLI entry points (called by lipmpcc.scenarios.stepping_stones when --robot is not "alip")
# --------------------------------------------------------------------------------------------
def _video(run: FullBodyStonesRun, opts: RunOptions) -> list[Path]:
    """Render the recorded configurations to ``OUT/SCENARIO.mp4`` (``.gif`` without imageio-ffmpeg)."""
    frames = run.result.frames
    if not opts.video or frames is None or len(frames) == 0:
        return []
    from ..sim import render

    suffix = ".mp4" if ".mp4" in render.video_formats() else ".gif"
    settings = render.VideoSettings(fps=run.loop.params.video_fps, track_body=run.loop.robot.torso_body)
    out = render.write_video(run.loop.sim.model, frames, Path(opts.out) / f"{opts.scenario}{suffix}", settings)
    return [Path(out)]


def summarize(run: FullBodyStonesRun, scenario: str, robot_name: str, extra: dict[str, Any]) -> dict[str, Any]:
    """The reduced runs' summary fields for a full-body run, plus the loop's full-body fields."""
    from .stepping_stones import _summary

    s = _summary(scenario, run.planner, robot_name, run.log, run.metrics, run.alip, extra)
    s["approach"] = f"{N_APPROACH} steps driven by alip-mpc on the full-body robot"
    s["fall_reason"] = run.log.fall_reason
    s.update(run.full_body_summary())
    s["model"].update(
        {
            "lambda_1ps": run.alip.lam,
            "dcm": "eq. 2 with L = k + m (c - p) x c_dot" if run.params.centroidal_momentum
            else "eq. 2 with the lumped-mass L = m (c - p) x c_dot",
            "landing_depth_m": run.params.landing_depth,
            "contact_phase": run.source.contact_phase,
            "planner_rate_hz": run.params.rate_hz,
            "wbc_com_kp_kd": [list(run.loop.wbc.params.com.kp), list(run.loop.wbc.params.com.kd)],
            "cop_range_m": list(getattr(run.source.planner.params, "cop_range", (0.0, 0.0))),
            "stone_box_m": next(
                ([2 * b.half_size[0], 2 * b.half_size[1], 2 * b.half_size[2]] for b in run.loop.sim.scene_boxes if b.kind == "stone"), None
            ),
        }
    )
    s["solver_failures_approach"] = int(run.source.approach_failures)
    cops = [np.asarray(r.result.cop_offset) for r in run.source.course_records() if r.result is not None]
    s["cop_offset_max_m"] = np.max(np.abs(cops), axis=0).tolist() if cops else [0.0, 0.0]
    return s


def _params(opts: RunOptions, planner: str) -> FullBodyStonesParams:
    """Run settings from the CLI options (``--cop-range``; None: the robot's ``alip_cop_range``)."""
    from .stepping_stones import _cop_range

    return FullBodyStonesParams(cop_range=_cop_range(opts, planner))


def run_stones(opts: RunOptions) -> RunResult:
    """``lipmpcc run stones --robot digit_like``: one course on the full-body robot."""
    from ..plots import stepping_stones as plots
    from ..robot import load_robot
    from .stepping_stones import PAPER_TABLE_II, _n_stones, _planner_name, _stones_from_options, case_label

    planner = _planner_name(opts)
    seq, info = _stones_from_options(opts)
    n = _n_stones(opts, len(seq), 32, 12)
    stones = seq.head(n)
    robot = load_robot(opts.robot)
    run = simulate(robot, planner, stones, params=_params(opts, planner), record_video=opts.video, progress=True)
    key = None
    if info["profile"] == "I":
        key = case_label("I", info["L"], info["W"])
    elif info["profile"] is not None:
        key = info["profile"]
    paper = PAPER_TABLE_II.get(key, {}).get(planner) if key else None
    summary = summarize(run, "stones", getattr(robot, "name", str(opts.robot)), {**info, "paper_rmse_m": paper, "paper_case": key})
    title = f"{planner} on {getattr(robot, 'name', 'full body')}, {stones.name}"
    figures = {
        "footprints": plots.plot_footprints(run.log, title=title),
        "durations_dcm": plots.plot_durations_and_dcm(run.log, title=title),
    }
    return RunResult(summary=summary, figures=figures, log=run, files=_video(run, opts))


def run_push(opts: RunOptions) -> RunResult:
    """``lipmpcc run push --robot digit_like``: paper B's perturbation test on the full-body robot."""
    from ..plots import stepping_stones as plots
    from ..robot import load_robot
    from .stepping_stones import PAPER_PUSHES, PUSH_LW, PUSH_STEPS, PUSH_WINDOW, _n_stones, _planner_name, paper_pushes, push_stones

    planner = _planner_name(opts)
    if opts.stones is not None or opts.profile is not None or opts.L is not None or opts.W is not None:
        raise InvalidInputError("--stones/--profile/--L/--W", opts.profile or opts.stones, "none: the push test uses (L, W) = (0.4, 0) stones")
    n = _n_stones(opts, PUSH_STEPS, PUSH_STEPS, 22)
    robot = load_robot(opts.robot)
    stones = push_stones(n)
    pushes = [p for p in paper_pushes() if p.step is not None and p.step < N_APPROACH + n]
    run = simulate(robot, planner, stones, pushes=pushes, params=_params(opts, planner), record_video=opts.video,
                   progress=True)
    extra = {
        "profile": None,
        "L": PUSH_LW[0],
        "W": PUSH_LW[1],
        "pushes": [{"stone": j, "force_N": list(f), "window_s": list(PUSH_WINDOW)} for j, f in PAPER_PUSHES],
        "pushes_applied": len(run.push_windows),
    }
    summary = summarize(run, "push", getattr(robot, "name", str(opts.robot)), extra)
    title = f"{planner} on {getattr(robot, 'name', 'full body')}, push test"
    figures = {
        "push_response": plots.plot_push_response(run.log, title=title),
        "footprints": plots.plot_footprints(run.log, title=title),
    }
    if max(summary["model"]["cop_range_m"]) > 0.0:
        figures["cop_offsets"] = plots.plot_cop_offsets(run.source, run.push_windows, title=title + ": planned CoP offset")
    return RunResult(summary=summary, figures=figures, log=run, files=_video(run, opts))
