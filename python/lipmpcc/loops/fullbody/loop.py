"""The full-body walking loop: MuJoCo at 2 kHz, the whole-body QP at 400 Hz, a footstep planner at its own rate.

One run of :meth:`FullBodyLoop.run`: check the arguments, reset the simulator, the controller and the
planner, set up the run's parts (the :class:`~lipmpcc.loops.fullbody.gait.Gait`, the
:class:`~lipmpcc.loops.fullbody.references.WholeBodyReferences`, the
:class:`~lipmpcc.loops.fullbody.log.TickLogger`), then tick until the time or the number of steps is
reached or the robot falls. Each tick: measure (:meth:`RobotSim.measure <lipmpcc.sim.robot_sim.RobotSim.measure>`),
advance the gait, evaluate the references, solve the whole-body QP, log, step MuJoCo, check for a fall.

Rates: MuJoCo at the model's time step (2 kHz), the whole-body QP every ``sim_steps_per_wbc`` simulation
steps (default 5: 400 Hz; 1 gives 2 kHz), the planner at its own ``rate_hz`` (rounded to WBC ticks).
Torques are held between WBC ticks. The run stops early when the robot falls (``RobotSim.fallen()``).

A per-tick hook (``run(on_tick=...)``, :data:`TickHook`) is called after a tick at most ``on_tick_hz``
times per simulated second, with the time, the simulator and the gait: the live viewer
(:mod:`lipmpcc.studies.viewer`) is one. Without a hook the loop does one ``is None`` test per tick.

The run contract (:mod:`lipmpcc.loops.base`): :meth:`FullBodyLoop.run` takes a
:class:`~lipmpcc.loops.base.Course` (handed to the planner at every call: its obstacles, and the stones
ahead or the path) and a :class:`~lipmpcc.loops.base.PushSchedule` (or the older ``pushes``). A push timed
from footstep ``k`` is armed when footstep ``k``'s swing starts, from the touch-down that starts it
(:attr:`FullBodyLoop.armed_pushes`). The result carries a :class:`~lipmpcc.loops.base.RunRecord`
(``LoopResult.record``) and the pushes as applied (``LoopResult.pushes``).

Threads (each optional, none changes a result by a bit): the whole-body controller computes its
dynamics terms on its own worker while the loop builds the reference
(``WholeBodyController.prepare``, started from ``RobotSim.measure(on_state=...)``), and, while MuJoCo
steps (C++, without the GIL), a helper thread (:mod:`~lipmpcc.loops.fullbody.overlap`) logs the tick
and evaluates the next tick's references (``LoopParams.helper_thread``); the next tick takes them unless
its gait logic changed the gait state.
"""

from __future__ import annotations

import logging
import math
import time
from contextlib import contextmanager
from dataclasses import replace
from typing import Callable, Iterable, Iterator

import numpy as np

from ...conventions import GRAVITY
from ...exceptions import InvalidInputError, StateError
from ...metrics import timing_stats_ms
from ...planners.base import FootstepSource, check_rate_hz
from ..progress import line_progress
from ...push import Push
from ...validation import count, number_in
from ...robots import RobotDescription
from ...sim.robot_sim import RobotSim
from ...sim.types import Measurement
from ...control.wbc import WholeBodyController
from ...control.wbc_types import WbcParams
from ..base import Course, PushSchedule, RunRecord, resolve_course, resolve_schedule
from .gait import Gait, GaitMode
from .log import FrameRecorder, LoopLog, LoopResult, TickLogger, TouchDown
from .overlap import helper_thread
from .params import MAX_RUN_DURATION, MAX_RUN_STEPS, LoopParams
from .references import TickReferences, WholeBodyReferences

__all__ = ["FullBodyLoop", "LoopParams", "LoopLog", "LoopResult", "TouchDown", "TickHook"]

#: a per-tick callback of :meth:`FullBodyLoop.run`: ``hook(t, sim, gait)`` with the time [s] after the tick,
#: the simulator (read it, never step or change it) and the :class:`~lipmpcc.loops.fullbody.gait.Gait`
#: (its ``plans`` and ``touchdowns`` so far)
TickHook = Callable[[float, RobotSim, Gait], None]

_log = logging.getLogger(__name__)


class _Run:
    """The parts and tallies of one run of :meth:`FullBodyLoop.run`, set up from its first measurement ``m0``."""

    def __init__(self, loop: "FullBodyLoop", m0: Measurement, n_steps: int | None, record_video: bool,
                 course: Course, schedule: PushSchedule) -> None:
        p, sim, wbc = loop.params, loop.sim, loop.wbc
        if p.com_height is not None:
            com_height = float(p.com_height)
        else:  # the layout's LIP height (over the soles' ground), else the standing COM's
            lip = loop.robot.lip_height
            com_height = float(m0.com[2]) if lip is None else float(lip) + min(float(f.position[2]) for f in m0.feet)
        mass = float(wbc.mass)
        self.t0 = float(sim.time)
        self.gait = Gait(loop.planner, p, com_height, mass, max_steps=n_steps, course=course)
        self.schedule = schedule
        self.next_armed = 0 if schedule.step_timed else MAX_RUN_STEPS + 1  # the next footstep to arm
        self.gait.start(self.t0, m0)
        self.references = WholeBodyReferences(self.gait, loop._arm_posture(), m0.com[:2].copy(), com_height,
                                              weight=mass * GRAVITY, load_ramp=p.load_ramp)
        self.logger = TickLogger(self.gait.omega)
        self.frames = FrameRecorder(self.t0, p.video_fps) if record_video else None
        self.dt_sim = float(sim.timestep)
        self.n_sub = int(p.sim_steps_per_wbc)
        self.dt_wbc = self.dt_sim * self.n_sub
        self.com_height = com_height
        self._solve = wbc.solve_tick
        self.t = self.t0
        self.fell = False
        self.fall_time = float("nan")
        self.fall_reason: str | None = None
        self.fall_body: str | None = None
        self.fall_contact: str | None = None
        self.warnings: list[str] = []
        self.wall_time = 0.0
        self.on_tick: TickHook | None = None
        self.on_tick_period = 0.0  # [s]
        self.on_tick_next = self.t0  # [s]

    def call_hook(self, t: float, sim: RobotSim) -> None:
        """Call ``on_tick`` when one is due at ``t`` [s] (at most once per ``on_tick_period``)."""
        if t >= self.on_tick_next - 1e-9 and self.on_tick is not None:
            self.on_tick(t, sim, self.gait)
            self.on_tick_next = max(self.on_tick_next + self.on_tick_period, t - 1e-9)

    def diverged(self, kind: str, t: float) -> None:
        """The simulation diverged (``kind``: see :meth:`RobotSim.divergence`) in the tick that ended at ``t`` [s]:
        the run ends as a fall there."""
        self.fell, self.fall_time, self.fall_reason = True, t, "simulation diverged"
        self.warnings.append(f"MuJoCo: simulation diverged ({kind}) at t={t:.3f} s; the run stopped there")

    def solve(self, m: Measurement) -> tuple[np.ndarray, float, int, bool]:
        """The whole-body QP at measurement ``m``: (efforts, wall time [s], QP status code, fallback
        used); the angular momentum it measured goes to the gait (for the planner)."""
        perf = time.perf_counter
        w0 = perf()
        tau, status, fallback, angular_momentum = self._solve(m.q, m.v, self.references.ref)
        wbc_time = perf() - w0
        self.gait.angular_momentum = angular_momentum
        return np.asarray(tau, dtype=float), wbc_time, int(status), bool(fallback)

    def arm_pushes(self, sim: RobotSim, armed: list[Push]) -> None:
        """When the gait has just started footstep ``next_armed``'s swing: its pushes, timed from the touch-down
        that starts it, registered on ``sim`` and added to ``armed``."""
        gait = self.gait
        if gait.mode is GaitMode.SINGLE and len(gait.touchdowns) == self.next_armed:
            for push in self.schedule.arm(self.next_armed, gait.t_td):
                sim.add_push(np.asarray(push.force_xyz, dtype=float), push.t_start, push.duration, body=push.body)
                armed.append(push)
            self.next_armed += 1

    def time_after_step(self, t: float) -> float:
        """The time [s] MuJoCo reaches after the tick's steps from ``t`` (its own sum: ``time += timestep``)."""
        for _ in range(self.n_sub):
            t += self.dt_sim
        return t

    def side_work(self, logged: tuple, t_next: float) -> tuple[float, TickReferences]:
        """The helper thread's job while MuJoCo steps: log the tick, then the next tick's references at ``t_next``."""
        self.logger.log(*logged)
        return t_next, self.references.evaluate(t_next, logged[2])


class _FallCheck:
    """The simulator's full fall criterion (incl. non-foot contacts) at ~50 Hz, and whenever a cheap
    height/tilt test on the tick's measurement fails."""

    def __init__(self, sim: RobotSim, dt_wbc: float) -> None:
        crit = sim.fall_criterion
        self.height_alarm = crit.min_height + 0.05  # [m] torso above the lower sole
        self.tilt_alarm = math.cos(crit.max_tilt) + 0.05  # [-] z component of the torso's z axis
        self.every = max(1, int(round(0.02 / dt_wbc)))  # [ticks]
        self._sim = sim

    def diverged(self, tick: int, t_before: float, t_after: float) -> str | None:
        """How the simulation diverged in tick number ``tick`` (from ``t_before`` to ``t_after`` [s]), or None.

        MuJoCo resets the time to 0 when it diverges: a time that did not advance is checked at once,
        MuJoCo's warning counters and the state at ~50 Hz (a divergence in the first ticks).
        """
        if t_after > t_before and tick % self.every:
            return None
        kind = self._sim.divergence()
        if kind is None and t_after <= t_before:
            kind = "the time went back"
        return kind

    def fallen(self, tick: int, m: Measurement) -> bool:
        """Whether the robot has fallen after tick number ``tick`` (measured before its step: ``m``)."""
        if tick % self.every == 0:  # the full criterion at ~50 Hz
            return self._sim.fallen()
        feet = m.feet
        lz, rz = feet[0].position[2], feet[1].position[2]
        suspicious = m.q[2] - (rz if rz < lz else lz) < self.height_alarm or m.torso.rotation[2, 2] < self.tilt_alarm
        return suspicious and self._sim.fallen()


class _Progress:
    """The run's progress bar (tqdm, on stderr): simulated seconds, rounded, or touch-downs when the run
    is bounded by a number of steps; full when the run completes, marked when it stops early."""

    def __init__(self, t_max: float, n_steps: int | None) -> None:
        from tqdm import tqdm

        self.by_steps = n_steps is not None
        if self.by_steps:
            total: float = int(n_steps)  # type: ignore[arg-type]
            fmt = "{desc}: {percentage:3.0f}%|{bar}| {n:.0f}/{total:.0f} steps [{elapsed}<{remaining}{postfix}]"
        else:
            total = round(t_max, 3)
            fmt = "{desc}: {percentage:3.0f}%|{bar}| {n:.2f}/{total:.2f} sim s [{elapsed}<{remaining}{postfix}]"
        # disable=None: no bar when stderr is not a terminal (logs, CI, `reproduce > log`); lines instead under lipmpcc run
        self.lines = line_progress(total, "full-body", "steps" if self.by_steps else "simulated s")
        self.bar = tqdm(total=total, leave=False, desc="full-body", disable=None, bar_format=fmt)
        self._shown = 0.0

    def tick(self, elapsed: float, steps: int) -> None:
        """After a tick: ``elapsed`` simulated seconds since the start, ``steps`` touch-downs so far."""
        value = min(float(steps) if self.by_steps else elapsed, self.bar.total)  # the last tick may pass the end
        if value != self._shown:
            self.bar.update(value - self._shown)
            self._shown = value
            if self.lines is not None:
                self.lines.update_to(value)

    def finish(self, completed: bool, note: str) -> None:
        """The bar at the run's end: full when ``completed``, else where it stopped, with ``note``."""
        if completed:
            self.bar.update(self.bar.total - self._shown)
        else:
            self.bar.set_postfix_str(note, refresh=False)
        self.bar.refresh()

    def close(self) -> None:
        self.bar.close()


@contextmanager
def _progress_bar(show: bool, t_max: float, n_steps: int | None) -> Iterator[_Progress | None]:
    """A :class:`_Progress` (None when not ``show``), closed on the way out."""
    if not show:
        yield None
        return
    bar = _Progress(t_max, n_steps)
    try:
        yield bar
    finally:
        bar.close()


def _checked_pushes(pushes: Iterable[Push]) -> tuple[Push, ...]:
    """``pushes`` as a tuple of :class:`~lipmpcc.push.Push` (absolute times, or timed from a footstep).

    Raises:
        InvalidInputError: not an iterable of pushes.
    """
    try:
        items = tuple(pushes)
    except TypeError:
        raise InvalidInputError("pushes", pushes, "a sequence of lipmpcc.push.Push") from None
    for push in items:
        if not isinstance(push, Push):
            raise InvalidInputError("pushes", push, "a lipmpcc.push.Push(force [N], t_start [s], duration [s])")
    return items


class FullBodyLoop:
    """Simulation + whole-body QP + footstep planner, at their own rates.

    Args:
        robot: a :class:`~lipmpcc.robots.RobotDescription` (e.g. ``load_robot("digit_like")``).
        planner: a :class:`~lipmpcc.planners.base.FootstepSource`; None to stand in double support.
        params: :class:`LoopParams`.
        wbc_params: parameters of the whole-body controller (None: its defaults); used when ``wbc`` is None.
        sim: an existing :class:`~lipmpcc.sim.robot_sim.RobotSim` (None: a new one).
        wbc: an existing :class:`~lipmpcc.control.wbc.WholeBodyController` (None: a new one).

    Attributes:
        model_warnings: one line per problem of the robot model that does not stop a run (a motor
            without a torque limit); logged once here and repeated in every result's ``warnings``.
        armed_pushes: the footstep-timed pushes of the current (or last) run, made absolute as their
            footsteps started (:meth:`~lipmpcc.loops.base.PushSchedule.arm`).

    Raises:
        InvalidInputError: ``planner``, ``sim`` or ``wbc`` of the wrong kind.
        ParameterError: the planner's ``rate_hz`` is not a number in (0, the WBC rate] Hz.
    """

    def __init__(
        self,
        robot: RobotDescription,
        planner: FootstepSource | None = None,
        params: LoopParams | None = None,
        wbc_params: WbcParams | None = None,
        sim: RobotSim | None = None,
        wbc: WholeBodyController | None = None,
    ) -> None:
        if planner is not None and not isinstance(planner, FootstepSource):
            raise InvalidInputError("planner", planner, "an object with name, rate_hz, reset() and plan(inp)")
        if not isinstance(robot, RobotDescription):
            raise InvalidInputError("robot", robot, "a lipmpcc.robots.RobotDescription (lipmpcc.robots.load_robot(...))")
        if params is not None and not isinstance(params, LoopParams):
            raise InvalidInputError("params", params, "a lipmpcc.loops.fullbody.params.LoopParams or None")
        if sim is not None and not isinstance(sim, RobotSim):
            raise InvalidInputError("sim", sim, "a lipmpcc.sim.robot_sim.RobotSim or None")
        if wbc is not None and not isinstance(wbc, WholeBodyController):
            raise InvalidInputError("wbc", wbc, "a lipmpcc.control.wbc.WholeBodyController or None")
        self.robot = robot
        self.planner = planner
        self.params = params or LoopParams()
        if self.params.touchdown_timing == "auto" and robot.touchdown_timing is not None:  # the robot's layout says
            self.params = replace(self.params, touchdown_timing=robot.touchdown_timing)
        self.sim = sim if sim is not None else RobotSim(robot)
        if planner is not None and not (isinstance(planner.name, str) and planner.name.strip()):
            raise InvalidInputError("planner.name", planner.name, "a non-empty string (the planner's name in the summary)")
        if planner is not None:  # at most once per WBC tick: a faster clock would only spin
            check_rate_hz(planner, 1.0 / (float(self.sim.timestep) * int(self.params.sim_steps_per_wbc)))
        self.wbc = wbc if wbc is not None else WholeBodyController(robot, wbc_params)
        self.model_warnings = [
            f"motor {name} has no torque limit (ctrlrange \"0 0\" or ctrllimited false, and no forcerange): "
            "MuJoCo applies any torque the controller commands"
            for name in self.sim.description.unlimited_motors()
        ]
        for text in self.model_warnings:
            _log.warning("%s", text)
        self.armed_pushes: list[Push] = []

    def _measure(self) -> Measurement:
        """The tick's measurement; the WBC's dynamics stage starts on its state (on the WBC's worker
        thread) while the forward pass runs and the reference is made. Without the worker the solve
        computes that stage itself (the same numbers: :meth:`WholeBodyController.prepare`), one call less."""
        wbc = self.wbc
        if wbc.threaded or type(wbc).prepare is not WholeBodyController.prepare:
            return self.sim.measure(on_state=wbc.prepare)
        return self.sim.measure()

    def _arm_posture(self) -> np.ndarray:
        """Angles of the posture joints (arms, waist, head, the rest but the legs:
        :attr:`~lipmpcc.robots.RobotDescription.posture_joints`) in the simulator's current
        configuration [rad] (held constant in a run)."""
        import mujoco

        m = self.sim.model
        qpos = self.sim.qpos
        out = []
        for name in self.robot.posture_joints:
            j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)
            out.append(float(qpos[m.jnt_qposadr[j]]))
        return np.asarray(out)

    # ---- the run ---------------------------------------------------------------------------
    def run(
        self,
        duration: float | None = None,
        n_steps: int | None = None,
        pushes: Iterable[Push] = (),
        progress: bool = False,
        record_video: bool = False,
        stop_on_fall: bool = True,
        on_tick: TickHook | None = None,
        on_tick_hz: float = 60.0,
        course: Course | None = None,
        schedule: PushSchedule | None = None,
    ) -> LoopResult:
        """Simulate until ``duration`` [s] or ``n_steps`` touch-downs, whichever first.

        Args:
            duration: simulated time [s]; required when standing (no planner).
            n_steps: stop after this many touch-downs (walking only).
            pushes: external forces (:class:`lipmpcc.push.Push`, absolute times or timed from a footstep's
                touch-down; default body: the torso).
            progress: show a progress bar (tqdm, on stderr).
            record_video: record MuJoCo configurations at ``video_fps`` for a video.
            stop_on_fall: stop at the first fall.
            on_tick: a :data:`TickHook` called after a tick at most ``on_tick_hz`` times per simulated
                second (and after the first tick), e.g. a live viewer; None: no call, and no cost. It only
                reads: the run's results are the same with it or without.
            on_tick_hz: the most calls of ``on_tick`` per simulated second [Hz].
            course: the run's :class:`~lipmpcc.loops.base.Course`, given to the planner at every call (None:
                an empty course).
            schedule: the run's :class:`~lipmpcc.loops.base.PushSchedule`, instead of ``pushes``.

        Raises:
            InvalidInputError: a bad ``duration``, ``n_steps``, push, ``on_tick``, ``course`` or ``schedule``;
                both ``schedule`` and ``pushes``.
        """
        t_max = self._run_length(duration, n_steps)
        if on_tick is not None and not callable(on_tick):
            raise InvalidInputError("on_tick", on_tick, "a callable hook(t, sim, gait) or None")
        if on_tick is not None:
            number_in("on_tick_hz", on_tick_hz, 0.0, 1e4, "Hz", lo_open=True, what="a call rate")
        run_schedule = resolve_schedule(schedule, _checked_pushes(pushes))
        run_course = resolve_course(course)
        m0 = self._reset(run_schedule.absolute)
        self.armed_pushes = []
        run = _Run(self, m0, n_steps, record_video, run_course, run_schedule)
        if on_tick is not None:
            run.on_tick, run.on_tick_period = on_tick, 1.0 / float(on_tick_hz)
        with _progress_bar(progress, t_max, n_steps) as bar:
            self._tick_loop(run, m0, t_max, stop_on_fall, bar)
            if bar is not None:
                bar.finish(*self._ending(run, n_steps))
        return self._result(run)

    @staticmethod
    def _ending(run: _Run, n_steps: int | None) -> tuple[bool, str]:
        """(whether the run did all it was asked, a note on where it stopped otherwise) for the progress bar."""
        if run.fell:
            return False, f"{run.fall_reason or 'fell'} at t={run.fall_time:.2f} s"
        if n_steps is not None and not run.gait.finished:
            return False, f"time limit after {len(run.gait.touchdowns)} steps"
        return True, ""

    def _run_length(self, duration: float | None, n_steps: int | None) -> float:
        """The longest simulated time of the run [s], after checking ``duration`` and ``n_steps``."""
        if duration is None and n_steps is None:
            raise InvalidInputError("duration", duration, "a simulated time [s] or a number of steps")
        if duration is not None:
            number_in("duration", duration, 0.0, MAX_RUN_DURATION, "s", lo_open=True, what="a simulated time")
        if n_steps is not None:
            if self.planner is None:
                raise InvalidInputError("n_steps", n_steps, "None when standing (no planner)")
            count("n_steps", n_steps, 1, MAX_RUN_STEPS, what="a number of steps")
        return float(duration) if duration is not None else 5.0 + 1.0 * float(n_steps)

    def _reset(self, pushes: tuple[Push, ...]) -> Measurement:
        """Standing pose, fresh controller, the pushes registered, the planner reset; the first measurement."""
        sim = self.sim
        sim.reset(self.robot.standing_reset)  # keyframe or standing qpos (Digit v3 has no keyframe)
        self.wbc.reset()
        for push in pushes:
            sim.add_push(np.asarray(push.force_xyz, dtype=float), push.t_start, push.duration, body=push.body)
        if self.planner is not None:
            self.planner.reset()
        return self._measure()

    def _tick_loop(self, run: _Run, m: Measurement, t_max: float, stop_on_fall: bool, bar: _Progress | None) -> None:
        """The ticks from the first measurement ``m`` until ``t_max`` [s] of simulated time, the last
        step or a fall (see the module doc); their outcome goes to ``run``."""
        sim, gait, logger, frames = self.sim, run.gait, run.logger, run.frames
        measure, references, solve, sim_step = self._measure, run.references.evaluate, run.solve, sim.step
        n_sub, dt_wbc = run.n_sub, run.dt_wbc
        hook = run.call_hook if run.on_tick is not None else None
        arm = run.arm_pushes if run.schedule.step_timed else None
        armed = self.armed_pushes
        falls = _FallCheck(sim, dt_wbc)
        data = sim.data
        perf = time.perf_counter
        spec: tuple[float, TickReferences] | None = None  # the helper's references for the next tick
        with helper_thread(self.params.resolved_helper_thread()) as helper:
            wall0 = perf()
            t = t0 = run.t0
            t_last = t_max - 1e-9
            tick = 0
            while t - t0 < t_last:
                if t > t0:
                    try:
                        m = measure()
                    except StateError:  # a non-finite state (MuJoCo's automatic reset disabled)
                        run.diverged(sim.divergence() or "non-finite state", t)
                        break
                changed = gait.update(t, m)
                if gait.finished:
                    break
                if changed and arm is not None:
                    arm(sim, armed)
                if spec is not None and not changed and spec[0] == t:
                    refs = spec[1]  # the helper's: the gait logic changed nothing and the time is theirs
                else:
                    refs = references(t, gait.torso_yaw_ref)
                spec = None
                gait.torso_yaw_ref = refs.torso_yaw
                tau, wbc_time, status, fallback = solve(m)
                if frames is not None:
                    frames.record(t, sim)
                logged = (t, m, refs.torso_yaw, refs.com, refs.swing_pos, refs.phase, gait.stance_code, tau,
                          wbc_time, status, fallback)
                if helper is None:
                    logger.log(*logged)
                    sim_step(tau, n_sub)
                else:  # the helper logs and evaluates the next references while MuJoCo steps
                    helper.start(run.side_work, (logged, run.time_after_step(t)))
                    try:
                        sim_step(tau, n_sub)
                    finally:
                        spec = helper.result()
                t_before, t = t, float(data.time)
                if bar is not None:
                    bar.tick(t - t0, len(gait.touchdowns))
                if hook is not None:
                    hook(t, sim)
                tick += 1
                diverged = falls.diverged(tick, t_before, t)
                if diverged is not None:
                    t = run.time_after_step(t_before)  # MuJoCo reset its time: the tick's end
                    run.diverged(diverged, t)
                    break
                if falls.fallen(tick, m):
                    run.fell, run.fall_time = True, t
                    if run.fall_reason is None:
                        detail = sim.fall_detail() or {}
                        run.fall_reason = detail.get("reason")
                        run.fall_body, run.fall_contact = detail.get("body"), detail.get("contact")
                    if stop_on_fall:
                        break
        run.wall_time = perf() - wall0
        run.t = t

    def _result(self, run: _Run) -> LoopResult:
        """The :class:`LoopResult` of a finished run."""
        log = run.logger.to_log()
        gait, frames = run.gait, run.frames
        sim_time = run.t - run.t0
        wall = run.wall_time
        return LoopResult(
            log=log,
            touchdowns=gait.touchdowns,
            fell=run.fell,
            fall_time=run.fall_time,
            sim_time=sim_time,
            wall_time=wall,
            real_time_factor=sim_time / wall if wall > 0 else float("inf"),
            wbc_ms=timing_stats_ms(log.wbc_time),
            planner_ms=timing_stats_ms(gait.plan_times),
            qp_failures=int(np.count_nonzero(log.fallback)),
            wbc_rate_hz=1.0 / run.dt_wbc,
            sim_rate_hz=1.0 / run.dt_sim,
            planner_rate_hz=(1.0 / gait.plan_period) if self.planner is not None else 0.0,
            omega=gait.omega,
            com_height=run.com_height,
            frames=np.asarray(frames.qpos) if frames is not None else None,
            frame_times=np.asarray(frames.times) if frames is not None else None,
            plans=gait.plans,
            fall_reason=run.fall_reason,
            fall_body=run.fall_body,
            fall_contact=run.fall_contact,
            warnings=[*self.model_warnings, *run.warnings, *self.sim.warning_messages()],
            # distinct answers: a planner may hand the same answer again (the ALIP source while landing)
            relaxed_solves=len({id(plan) for _, plan in gait.plans if str(plan.status).startswith("relaxed")}),
            pushes=(*run.schedule.absolute, *self.armed_pushes),
            record=_run_record(run, (*run.schedule.absolute, *self.armed_pushes)),
        )


def _run_record(run: _Run, pushes: tuple[Push, ...]) -> RunRecord:
    """The :class:`~lipmpcc.loops.base.RunRecord` of a finished run: per touch-down the planned and the landed
    foothold and the duration the last plan asked for and the one executed."""
    gait, tds = run.gait, run.gait.touchdowns
    n = len(tds)
    return RunRecord(
        touchdown_times=[td.t for td in tds],
        sides=[td.side.sign for td in tds],
        planned_footholds=np.array([td.planned[:2] for td in tds], dtype=float).reshape(n, 2),
        footholds=np.array([td.pos[:2] for td in tds], dtype=float).reshape(n, 2),
        planned_durations=gait.planned_durations[:n],
        durations=[td.duration for td in tds],
        pushes=pushes,
        plans=[(t, k, plan) for (t, plan), k in zip(gait.plans, gait.plan_steps)],
        fell=run.fell,
        yaws=[td.yaw for td in tds],
    )
