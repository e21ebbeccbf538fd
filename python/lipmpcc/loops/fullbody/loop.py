"""Full-body walking loop: MuJoCo at 2 kHz, the whole-body QP at 400 Hz, a footstep planner at its own rate.

The loop owns the gait's phase and timing; a planner (:class:`FootstepSource`) only says where and
when the swing foot should land (:class:`StepPlan`) from the measured state (:class:`PlannerInput`).
This is the interface paper A's MPCC (15 Hz) and paper B's ALIP-MPC (25 Hz) plug into; here the
capture-point source (:mod:`lipmpcc.planners.capture_point`) drives it.

One run:

1. **Start** in double support at the standing keyframe. When walking, the COM shifts (quintic) towards
   the first stance foot (the right one) for ``initial_shift`` seconds.
2. **Single support.** The swing foot follows a :class:`~lipmpcc.trajectory.StepTrajectory` from its
   lift-off pose to the planned foothold; the torso stays upright and yaws to the planned heading; the
   horizontal COM follows the LIP about the stance foot (:class:`~lipmpcc.trajectory.LipComReference`,
   re-initialised from the measured COM state at each touch-down) at constant height. Each planner update
   moves the foothold and re-times the phase (SPEC §2); changes are blended smoothly.
3. **Touch-down** when the swing foot's contact is detected after ``touchdown_min_phase``, or when the
   phase reaches 1 (clock) — whichever first. An optional double support of ``double_support`` seconds
   follows, with the new stance foot's load ramped in; then the other foot lifts off.

Rates: MuJoCo at the model's time step (2 kHz), the whole-body QP every ``sim_steps_per_wbc`` simulation
steps (default 5: 400 Hz; 1 gives 2 kHz), the planner at its own ``rate_hz`` (rounded to WBC ticks).
Torques are held between WBC ticks. The run stops early when the robot falls (``RobotSim.fallen()``).

Everything is logged at the WBC rate as NumPy arrays (:class:`LoopLog`); :class:`LoopResult` adds the
touch-down events, timing statistics and the real-time factor (simulated seconds per wall second).

Threads (each optional, none changes a result by a bit): the whole-body controller computes its
dynamics terms on its own worker while the loop builds the reference
(``WholeBodyController.prepare``, started from ``RobotSim.measure(on_state=...)``), and, while MuJoCo
steps (C++, without the GIL), a helper thread logs the tick and evaluates the next tick's references
(``LoopParams.helper_thread``); the next tick takes them unless its gait logic changed the gait state.
"""

from __future__ import annotations

import math
import sys
import threading
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from ...config import threads_enabled
from ...exceptions import InvalidInputError, ParameterError, StateError
from ...conventions import LEFT, RIGHT, other_side
from ...planners.base import FootstepSource, PlannerInput, StepPlan
from ...trajectory import LipComReference, Quintic, StepReference, StepTrajectory, SwingParams, yaw_rotation



class _Overlap:
    """One helper thread that runs a job while the caller's thread is inside C++ without the GIL
    (the MuJoCo step): ``start(job, args)``, then ``result()`` waits for the job and returns its value
    (or raises its exception). ``close()`` ends the thread."""

    def __init__(self) -> None:
        self._go = threading.Lock()
        self._go.acquire()
        self._done = threading.Lock()
        self._done.acquire()
        self._job: Callable[..., Any] | None = None
        self._args: tuple = ()
        self._value: Any = None
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="lipmpcc-loop-helper", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while True:
            self._go.acquire()
            job = self._job
            if job is None:
                return
            try:
                self._value = job(*self._args)
            except BaseException as err:  # noqa: BLE001 - handed to the caller's thread
                self._error = err
            self._done.release()

    def start(self, job: Callable[..., Any], args: tuple = ()) -> None:
        self._job = job
        self._args = args
        self._error = None
        self._go.release()

    def result(self) -> Any:
        self._done.acquire()
        if self._error is not None:
            err, self._error = self._error, None
            raise err
        return self._value

    def close(self) -> None:
        self._job = None
        self._go.release()
        self._thread.join()


# --------------------------------------------------------------------------------------------
# Loop parameters, pushes, logs
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LoopParams:
    """Parameters of :class:`FullBodyLoop` (times [s], lengths [m]).

    Attributes:
        sim_steps_per_wbc: simulation steps per WBC tick (5 → 400 Hz at 2 kHz; 1 → 2 kHz).
        com_height: constant COM height of the references [m]; None: the standing keyframe's.
        initial_shift: duration of the initial COM shift onto the first stance foot [s].
        initial_shift_fraction: where the COM goes in that shift, as a fraction of the way from the
            feet's midpoint to the first stance foot [-].
        first_stance: ``"left"`` or ``"right"``: the first stance foot.
        double_support: double-support time after each touch-down [s] (0: none).
        load_ramp: time over which a touching-down foot's normal-force bound ramps up [s].
        touchdown_min_phase: a swing-foot contact counts as touch-down after this phase [-].
        landing_depth: the swing foot aims this far below the ground height [m] (firm landing).
        swing: :class:`~lipmpcc.trajectory.SwingParams` (apex height, freeze phase, ...).
        com_resync_on_plan: re-initialise the LIP COM reference from the measured COM state at every
            planner update (True) or only at touch-down (False).
        video_fps: frames per second of the recorded video (``video=True``).
        helper_thread: while MuJoCo steps, log the tick and evaluate the next tick's references on a
            helper thread (None: when the process may use two CPUs or more and the environment
            variable ``LIPMPCC_LOOP_THREAD`` is not ``0``). Results do not depend on it.
    """

    sim_steps_per_wbc: int = 5
    com_height: float | None = None
    initial_shift: float = 0.6
    initial_shift_fraction: float = 0.6
    first_stance: str = RIGHT
    double_support: float = 0.0
    load_ramp: float = 0.0
    touchdown_min_phase: float = 0.6
    landing_depth: float = 0.0
    swing: SwingParams | None = None
    com_resync_on_plan: bool = False
    video_fps: float = 30.0
    helper_thread: bool | None = None

    def resolved_helper_thread(self) -> bool:
        """Whether :meth:`FullBodyLoop.run` uses its helper thread (see ``helper_thread``)."""
        if self.helper_thread is not None:
            return bool(self.helper_thread)
        return threads_enabled("LIPMPCC_LOOP_THREAD")

    def __post_init__(self) -> None:
        if not (isinstance(self.sim_steps_per_wbc, (int, np.integer)) and 1 <= self.sim_steps_per_wbc <= 100):
            raise ParameterError("sim_steps_per_wbc", self.sim_steps_per_wbc, "an integer in [1, 100]")
        if self.com_height is not None and not (math.isfinite(self.com_height) and self.com_height > 0.0):
            raise ParameterError("com_height", self.com_height, "a positive height [m] or None")
        for name in ("initial_shift", "double_support", "load_ramp", "landing_depth"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ParameterError(name, v, "a non-negative finite number")
        if not 0.0 <= self.initial_shift_fraction <= 1.0:
            raise ParameterError("initial_shift_fraction", self.initial_shift_fraction, "a fraction in [0, 1]")
        if not 0.0 < self.touchdown_min_phase <= 1.0:
            raise ParameterError("touchdown_min_phase", self.touchdown_min_phase, "a phase in (0, 1]")
        if self.first_stance not in (LEFT, RIGHT):
            raise ParameterError("first_stance", self.first_stance, "'left' or 'right'")
        if not (math.isfinite(self.video_fps) and self.video_fps > 0.0):
            raise ParameterError("video_fps", self.video_fps, "a positive frame rate [Hz]")
        if self.helper_thread is not None and not isinstance(self.helper_thread, (bool, np.bool_)):
            raise ParameterError("helper_thread", self.helper_thread, "True, False or None")


@dataclass(frozen=True)
class Push:
    """An external force on the torso: ``force`` (3,) [N] from ``t_start`` [s] for ``duration`` [s]."""

    t_start: float
    force: tuple[float, float, float]
    duration: float = 0.1


@dataclass
class LoopLog:
    """Per-WBC-tick log as arrays (n ticks); world frame.

    Attributes:
        t: time [s] (n,).
        com, com_ref, com_vel: COM position, its reference, COM velocity (n, 3).
        dcm: ξ = c + ċ/ω (n, 2).
        base_height: torso (floating base) height [m] (n,).
        torso_yaw, torso_yaw_ref: torso heading and its reference [rad] (n,).
        torso_tilt: angle between the torso z axis and the vertical [rad] (n,).
        contact: measured foot contacts (left, right) (n, 2) bool.
        stance: 0 = left stance, 1 = right stance, 2 = double support (n,).
        phase: step phase τ (n,) (NaN in double support).
        left_foot, right_foot: sole positions (n, 3).
        swing_ref: swing-foot reference position (n, 3) (NaN in double support).
        swing_err: swing-foot position error norm [m] (n,) (NaN in double support).
        tau: motor torques (n, nu).
        wbc_time: WBC wall time per tick [s] (n,).
        wbc_status: QP status code (n,) (0 = solved).
        fallback: the WBC used its fallback (n,) bool.
    """

    t: np.ndarray
    com: np.ndarray
    com_ref: np.ndarray
    com_vel: np.ndarray
    dcm: np.ndarray
    base_height: np.ndarray
    torso_yaw: np.ndarray
    torso_yaw_ref: np.ndarray
    torso_tilt: np.ndarray
    contact: np.ndarray
    stance: np.ndarray
    phase: np.ndarray
    left_foot: np.ndarray
    right_foot: np.ndarray
    swing_ref: np.ndarray
    swing_err: np.ndarray
    tau: np.ndarray
    wbc_time: np.ndarray
    wbc_status: np.ndarray
    fallback: np.ndarray


@dataclass(frozen=True)
class TouchDown:
    """One support exchange.

    Attributes:
        t: time [s]; side: the foot that touched down; pos: its sole position (3,) [m];
        planned: the last planned foothold (2,) [m]; yaw: foot yaw [rad]; planned_yaw [rad];
        by_contact: True when detected from contact (False: by the clock);
        duration: time since the previous touch-down [s].
    """

    t: float
    side: str
    pos: np.ndarray
    planned: np.ndarray
    yaw: float
    planned_yaw: float
    by_contact: bool
    duration: float


@dataclass
class LoopResult:
    """Outcome of :meth:`FullBodyLoop.run`.

    Attributes:
        log: :class:`LoopLog`.
        touchdowns: the support exchanges, in order.
        fell: the robot fell; fall_time: when [s] (NaN if not).
        sim_time: simulated time [s]; wall_time: wall time of the loop [s].
        real_time_factor: simulated seconds per wall second.
        wbc_ms: WBC tick time statistics {median, p90, max, n} [ms].
        planner_ms: planner time statistics [ms].
        qp_failures: WBC ticks whose QP did not solve (fallback used).
        wbc_rate_hz, sim_rate_hz, planner_rate_hz: the rates actually used [Hz].
        omega: LIP ω [1/s]; com_height: constant COM height [m].
        frames: recorded MuJoCo qpos for the video (k, nq), or None.
        frame_times: their times [s].
    """

    log: LoopLog
    touchdowns: list[TouchDown]
    fell: bool
    fall_time: float
    sim_time: float
    wall_time: float
    real_time_factor: float
    wbc_ms: dict[str, float]
    planner_ms: dict[str, float]
    qp_failures: int
    wbc_rate_hz: float
    sim_rate_hz: float
    planner_rate_hz: float
    omega: float
    com_height: float
    frames: np.ndarray | None = None
    frame_times: np.ndarray | None = None
    plans: list[tuple[float, StepPlan]] = field(default_factory=list)

    @property
    def n_steps(self) -> int:
        """Number of touch-downs."""
        return len(self.touchdowns)

    @property
    def min_base_height(self) -> float:
        """Lowest torso height over the run [m]."""
        return float(np.min(self.log.base_height)) if self.log.t.size else float("nan")

    @property
    def distance_walked(self) -> float:
        """Length of the horizontal COM path [m]."""
        c = self.log.com[:, :2]
        return float(np.sum(np.linalg.norm(np.diff(c, axis=0), axis=1))) if len(c) > 1 else 0.0

    @property
    def displacement(self) -> float:
        """Straight-line horizontal COM displacement from start to end [m]."""
        c = self.log.com[:, :2]
        return float(np.linalg.norm(c[-1] - c[0])) if len(c) > 1 else 0.0

    def summary(self) -> dict[str, object]:
        """The full-body fields of a scenario's summary.json."""
        return {
            "fell": self.fell,
            "fall_time_s": self.fall_time if self.fell else None,
            "sim_time_s": self.sim_time,
            "wall_time_s": self.wall_time,
            "real_time_factor": self.real_time_factor,
            "wbc_ms": {k: self.wbc_ms[k] for k in ("median", "p90", "max")},
            "planner_ms": {k: self.planner_ms[k] for k in ("median", "p90", "max")},
            "qp_failures": self.qp_failures,
            "min_base_height_m": self.min_base_height,
            "distance_walked_m": self.distance_walked,
            "displacement_m": self.displacement,
            "steps": self.n_steps,
            "touchdowns_by_contact": int(sum(td.by_contact for td in self.touchdowns)),
            "rates_hz": {"sim": self.sim_rate_hz, "wbc": self.wbc_rate_hz, "planner": self.planner_rate_hz},
            "com_height_m": self.com_height,
        }


# --------------------------------------------------------------------------------------------
# The loop
# --------------------------------------------------------------------------------------------
_NAN3 = np.full(3, np.nan)


def _yaw_of_rotation(R: np.ndarray) -> float:
    return math.atan2(R[1, 0], R[0, 0])


class FullBodyLoop:
    """Simulation + whole-body QP + footstep planner, at their own rates.

    Args:
        robot: a :class:`~lipmpcc.robot.RobotDescription` (e.g. ``load_robot("digit_like")``).
        planner: a :class:`FootstepSource`; None to stand in double support.
        params: :class:`LoopParams`.
        wbc_params: parameters of the whole-body controller (None: its defaults).
        sim: an existing :class:`~lipmpcc.sim.robot_sim.RobotSim` (None: a new one).
        wbc: an existing :class:`~lipmpcc.wbc.WholeBodyController` (None: a new one).
    """

    def __init__(
        self,
        robot: object,
        planner: FootstepSource | None = None,
        params: LoopParams | None = None,
        wbc_params: object | None = None,
        sim: object | None = None,
        wbc: object | None = None,
    ) -> None:
        if planner is not None and not isinstance(planner, FootstepSource):
            raise InvalidInputError("planner", planner, "an object with name, rate_hz, reset() and plan(inp)")
        if planner is not None and not (math.isfinite(planner.rate_hz) and planner.rate_hz > 0.0):
            raise ParameterError("planner.rate_hz", planner.rate_hz, "a positive rate [Hz]")
        self.robot = robot
        self.planner = planner
        self.params = params or LoopParams()
        if sim is None:
            from ...sim.robot_sim import RobotSim

            sim = RobotSim(robot)
        if wbc is None:
            from ...wbc import WholeBodyController

            wbc = WholeBodyController(robot, wbc_params)
        self.sim = sim
        self.wbc = wbc
        from ...sim.robot_sim import RobotSim

        # WholeBodyController.prepare, for a RobotSim's measure(on_state=...)
        self._prepare = getattr(wbc, "prepare", None) if isinstance(sim, RobotSim) else None

    # ---- state access (one place that knows the simulator's API) -------------------------
    def _read(self) -> dict[str, object]:
        sim = self.sim
        measure = getattr(sim, "measure", None)
        if measure is not None:  # RobotSim: everything from one forward pass
            # the WBC's dynamics stage starts on the state (on its worker thread) while the forward
            # pass runs and the reference is made
            prepare = self._prepare
            m = measure(on_state=prepare) if prepare is not None else measure()
            (pl, Rl), (pr, Rr) = m.feet
            cl, cr = m.contact
            return {
                "q": m.q,
                "v": m.v,
                "com": m.com,
                "com_vel": m.com_vel,
                "feet_pos": {LEFT: pl, RIGHT: pr},
                "feet_rot": {LEFT: Rl, RIGHT: Rr},
                "contact": {LEFT: cl, RIGHT: cr},
                "torso_rot": m.torso.rotation,
                "base_height": float(m.q[2]),
            }
        q, v = sim.pinocchio_state()
        (pl, Rl), (pr, Rr) = sim.foot_poses()
        cl, cr = sim.contact_state()
        return {
            "q": q,
            "v": v,
            "com": np.asarray(sim.com(), dtype=float),
            "com_vel": np.asarray(sim.com_velocity(), dtype=float),
            "feet_pos": {LEFT: np.asarray(pl, dtype=float), RIGHT: np.asarray(pr, dtype=float)},
            "feet_rot": {LEFT: np.asarray(Rl, dtype=float), RIGHT: np.asarray(Rr, dtype=float)},
            "contact": {LEFT: bool(cl), RIGHT: bool(cr)},
            "torso_rot": np.asarray(sim.torso_pose().rotation, dtype=float),
            "base_height": float(q[2]),
        }

    def _arm_posture(self) -> np.ndarray:
        """Arm joint angles of the standing configuration [rad] (held constant)."""
        import mujoco

        m = self.sim.model
        qpos = self.sim.qpos
        out = []
        for name in self.robot.arm_joints:
            j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)
            out.append(float(qpos[m.jnt_qposadr[j]]))
        return np.asarray(out)

    @staticmethod
    def _fill_swing_reference(ref: object, i: int, r: StepReference) -> None:
        """Write the swing foot's references ``r`` into row ``i`` (0 left, 1 right) of the per-foot
        fields of the (reused, loop-owned) whole-body reference ``ref`` (world frame).

        The foot turns about the vertical only: the angular velocity and acceleration rows get their
        z component [rad/s, rad/s²]; their x and y components are never written (they stay 0).
        """
        ref.foot_pos[i] = r.swing_pos
        ref.foot_vel[i] = r.swing_vel
        ref.foot_acc[i] = r.swing_acc
        ref.foot_rot[i] = yaw_rotation(r.swing_yaw)
        ref.foot_angvel[i, 2] = r.swing_yaw_rate
        ref.foot_angacc[i, 2] = r.swing_yaw_acc

    # ---- the run ---------------------------------------------------------------------------
    def run(
        self,
        duration: float | None = None,
        n_steps: int | None = None,
        pushes: tuple[Push, ...] | list[Push] = (),
        progress: bool = False,
        record_video: bool = False,
        stop_on_fall: bool = True,
    ) -> LoopResult:
        """Simulate until ``duration`` [s] or ``n_steps`` touch-downs, whichever first.

        Args:
            duration: simulated time [s]; required when standing (no planner).
            n_steps: stop after this many touch-downs (walking only).
            pushes: external forces on the torso.
            progress: show a progress bar (tqdm, on stderr).
            record_video: record MuJoCo configurations at ``video_fps`` for a video.
            stop_on_fall: stop at the first fall.
        """
        import time as _time

        from ...metrics import timing_stats_ms

        p = self.params
        if duration is None and n_steps is None:
            raise InvalidInputError("duration", duration, "a simulated time [s] or a number of steps")
        if duration is not None and not (math.isfinite(duration) and duration > 0.0):
            raise InvalidInputError("duration", duration, "a positive simulated time [s]")
        if n_steps is not None:
            if self.planner is None:
                raise InvalidInputError("n_steps", n_steps, "None when standing (no planner)")
            if int(n_steps) != n_steps or n_steps <= 0:
                raise InvalidInputError("n_steps", n_steps, "a positive integer")
        t_max = float(duration) if duration is not None else 5.0 + 1.0 * float(n_steps)
        swing_params = p.swing or SwingParams()
        walking = self.planner is not None

        sim, wbc = self.sim, self.wbc
        sim.reset(self.robot.standing_reset)  # keyframe or standing qpos (Digit v3 has no keyframe)
        if hasattr(wbc, "reset"):
            wbc.reset()
        for push in pushes:
            sim.add_push(np.asarray(push.force, dtype=float), float(push.t_start), float(push.duration))
        if walking:
            self.planner.reset()

        dt_sim = float(sim.timestep)
        n_sub = int(p.sim_steps_per_wbc)
        dt_wbc = dt_sim * n_sub
        plan_period = 1.0 / float(self.planner.rate_hz) if walking else math.inf

        s = self._read()
        com_height = float(p.com_height) if p.com_height is not None else float(s["com"][2])
        lip = LipComReference(com_height)
        omega = lip.omega
        mass = float(getattr(wbc, "mass", getattr(self.robot, "total_mass", float("nan"))))
        mass_g = mass * 9.81
        from ...wbc import WbcReference

        ref = WbcReference(arm_posture=self._arm_posture())  # reused every tick

        # ---- gait state ----
        t0 = float(sim.time)
        feet0 = s["feet_pos"]
        torso_yaw_ref = _yaw_of_rotation(s["torso_rot"])
        stance = p.first_stance
        mode = "stand"
        com_quintic = None
        t_td = t0
        t_lift = t0
        if walking and p.initial_shift > 0.0:
            mid = 0.5 * (feet0[LEFT][:2] + feet0[RIGHT][:2])
            target = mid + p.initial_shift_fraction * (feet0[stance][:2] - mid)
            com_quintic = Quintic(t0, t0 + p.initial_shift, s["com"][:2], x1=target)
            mode = "shift"
        elif walking:  # no shift: lift the first swing foot at once
            lip.reset(t0, s["com"][:2], s["com_vel"][:2], feet0[stance][:2])
            mode = "double"
        stand_com = s["com"][:2].copy()
        step: StepTrajectory | None = None
        last_plan: StepPlan | None = None
        next_plan_t = math.inf
        touchdowns: list[TouchDown] = []
        plans: list[tuple[float, StepPlan]] = []
        plan_times: list[float] = []
        k_last = np.zeros(3)
        ground_z = float(min(feet0[LEFT][2], feet0[RIGHT][2]))

        step_contact = np.zeros(2)  # the LIP pivot at the step's start (the stance contact point)

        def apply_cop(t: float, plan: StepPlan) -> None:
            """Turn the LIP COM reference about the plan's centre of pressure, if it has one."""
            if plan.cop_offset is not None:
                pivot = step_contact + plan.cop_offset
                if np.any(pivot != lip.pivot):
                    lip.move_pivot(t, pivot)

        def start_swing(t: float, st: dict) -> None:
            nonlocal mode, step, next_plan_t, last_plan, step_contact
            swing = other_side(stance)
            step_contact = lip.pivot
            last_plan = call_planner(t, st)
            apply_cop(t, last_plan)
            t_end = max(t_td + last_plan.duration, t + swing_params.min_remaining)
            target = np.array([last_plan.foothold[0], last_plan.foothold[1], ground_z - p.landing_depth])
            step = StepTrajectory(
                t_start=t,
                t_end=t_end,
                start_pos=st["feet_pos"][swing],
                start_yaw=_yaw_of_rotation(st["feet_rot"][swing]),
                target_pos=target,
                target_yaw=last_plan.yaw,
                torso_start_yaw=torso_yaw_ref,
                torso_target_yaw=last_plan.yaw,
                params=swing_params,
            )
            mode = "single"
            next_plan_t = t + plan_period

        def call_planner(t: float, st: dict) -> StepPlan:
            swing = other_side(stance)
            inp = PlannerInput(
                t=t,
                com_pos=st["com"],
                com_vel=st["com_vel"],
                dcm=st["com"][:2] + st["com_vel"][:2] / omega,
                omega=omega,
                stance_side=stance,
                stance_pos=st["feet_pos"][stance],
                stance_yaw=_yaw_of_rotation(st["feet_rot"][stance]),
                swing_pos=st["feet_pos"][swing],
                swing_yaw=_yaw_of_rotation(st["feet_rot"][swing]),
                time_since_touchdown=t - t_td,
                step_index=len(touchdowns),
                torso_yaw=_yaw_of_rotation(st["torso_rot"]),
                angular_momentum=k_last.copy(),
                mass=mass,
            )
            w0 = _time.perf_counter()
            plan = self.planner.plan(inp)
            plan_times.append(_time.perf_counter() - w0)
            if not isinstance(plan, StepPlan):
                raise StateError("planner output", plan, "a StepPlan")
            plans.append((t, plan))
            return plan

        # ---- logs ----
        L: dict[str, list] = {k: [] for k in LoopLog.__dataclass_fields__}
        frames: list[np.ndarray] = []
        frame_times: list[float] = []
        next_frame_t = t0
        wbc_times: list[float] = []
        qp_failures = 0
        fell = False
        fall_time = float("nan")
        (log_t, log_com, log_com_ref, log_com_vel, log_dcm, log_base_height, log_torso_yaw, log_torso_yaw_ref,
         log_torso_tilt, log_contact, log_stance, log_phase, log_left_foot, log_right_foot, log_swing_ref,
         log_tau, log_wbc_time, log_wbc_status, log_fallback) = (
            L[k].append for k in (
                "t", "com", "com_ref", "com_vel", "dcm", "base_height", "torso_yaw", "torso_yaw_ref",
                "torso_tilt", "contact", "stance", "phase", "left_foot", "right_foot", "swing_ref",
                "tau", "wbc_time", "wbc_status", "fallback",
            )
        )

        # ---- per-tick constants (read-only arrays shared between ticks) ----
        zero3 = np.zeros(3)
        # torso yaw rate and acceleration as (0, 0, ψ̇) [rad/s] and (0, 0, ψ̈) [rad/s²]: z rewritten each swing tick
        yaw_rates = (np.zeros(3), np.zeros(3))
        no_load_bound = (math.inf, math.inf)
        stand_com_ref = np.array([stand_com[0], stand_com[1], com_height])
        rot_yaw: float | None = None  # torso_yaw_ref of the cached rotation (compared by identity)
        rot_ref = np.eye(3)
        crit = getattr(sim, "fall_criterion", None)
        if crit is not None:
            height_alarm = crit.min_height + 0.05
            tilt_alarm = math.cos(crit.max_tilt) + 0.05
        perf = _time.perf_counter
        solve = wbc.solve
        sim_step = sim.step

        bar = None
        if progress:
            from tqdm import tqdm

            # disable=None: no bar when stderr is not a terminal (logs, CI, `reproduce > log`)
            bar = tqdm(total=round(t_max, 3), unit="sim s", leave=False, desc="full-body", disable=None)

        def references(t: float, yaw_ref: float) -> tuple:
            """The whole-body references at time ``t`` from the gait state, written into ``ref``.

            Reads the gait state but does not change it: the torso heading reference it yields is
            returned (the caller commits it). Returns (torso heading reference, COM reference,
            swing-foot reference, phase) for the log.
            """
            nonlocal rot_yaw, rot_ref
            contacts = (True, True)
            swing_pos_ref = _NAN3
            phase = math.nan
            if mode == "stand":
                com_ref, com_vel_ref, com_acc_ref = stand_com_ref, zero3, zero3
            elif mode == "shift":
                x, dx, ddx = com_quintic.evaluate(t)
                com_ref = np.array([x[0], x[1], com_height])
                com_vel_ref = np.array([dx[0], dx[1], 0.0])
                com_acc_ref = np.array([ddx[0], ddx[1], 0.0])
            else:
                com_ref, com_vel_ref, com_acc_ref = lip.evaluate(t)
            if mode == "single":
                r = step.evaluate(t)
                swing = other_side(stance)
                contacts = (swing != LEFT, swing != RIGHT)
                phase = r.tau
                swing_pos_ref = r.swing_pos
                self._fill_swing_reference(ref, 0 if swing == LEFT else 1, r)
                yaw_ref = r.torso_yaw
                torso_angvel, torso_angacc = yaw_rates
                torso_angvel[2] = r.torso_yaw_rate
                torso_angacc[2] = r.torso_yaw_acc
            else:
                torso_angvel = torso_angacc = zero3
            max_fz = no_load_bound
            if p.load_ramp > 0.0 and mode != "stand" and touchdowns:
                ramp = (t - t_td) / p.load_ramp
                if ramp < 1.0:
                    bound = max(0.05, ramp) * 1.5 * mass_g
                    max_fz = (bound, math.inf) if stance == LEFT else (math.inf, bound)
            if yaw_ref is not rot_yaw:
                rot_ref = yaw_rotation(yaw_ref)
                rot_yaw = yaw_ref
            ref.contact = contacts
            ref.com_pos, ref.com_vel, ref.com_acc = com_ref, com_vel_ref, com_acc_ref
            ref.torso_rot, ref.torso_angvel, ref.torso_angacc = rot_ref, torso_angvel, torso_angacc
            ref.max_normal_force = max_fz
            return yaw_ref, com_ref, swing_pos_ref, phase

        def log_tick(t: float, s: dict, yaw_ref: float, com_ref: np.ndarray, swing_pos_ref: np.ndarray,
                     phase: float, tau_cmd: np.ndarray, wbc_time: float, status: int, fallback: bool) -> None:
            com, com_vel, feet_pos, contact = s["com"], s["com_vel"], s["feet_pos"], s["contact"]
            Rt = s["torso_rot"]
            cx, cy, _ = com.tolist()
            vx, vy, _ = com_vel.tolist()
            log_t(t)
            log_com(com)
            log_com_ref(com_ref)
            log_com_vel(com_vel)
            log_dcm((cx + vx / omega, cy + vy / omega))
            log_base_height(s["base_height"])
            log_torso_yaw(_yaw_of_rotation(Rt))
            log_torso_yaw_ref(yaw_ref)
            log_torso_tilt(math.acos(max(-1.0, min(1.0, float(Rt[2, 2])))))
            log_contact((contact[LEFT], contact[RIGHT]))
            log_stance(2 if mode != "single" else (0 if stance == LEFT else 1))
            log_phase(phase)
            log_left_foot(feet_pos[LEFT])
            log_right_foot(feet_pos[RIGHT])
            log_swing_ref(swing_pos_ref)
            log_tau(tau_cmd)
            log_wbc_time(wbc_time)
            log_wbc_status(status)
            log_fallback(fallback)

        def side_work(logged: tuple, t_next: float) -> tuple:
            """The helper's job: log the tick, then the next tick's references at ``t_next``."""
            log_tick(*logged)
            return (t_next, references(t_next, logged[2]))

        # While MuJoCo steps (C++, without the GIL) a helper thread logs the tick and evaluates the
        # next tick's references from the gait state, for the time the step will end at. The next
        # tick uses them when its gait logic changes nothing (no touch-down, lift-off or planner
        # call) and the time is that one; otherwise it evaluates them again. Same results either way.
        helper = _Overlap() if p.resolved_helper_thread() else None
        old_switch = sys.getswitchinterval()
        if helper is not None:  # the loop's thread gets the GIL back soon after its step if the helper still runs
            sys.setswitchinterval(min(old_switch, 2e-4))
        spec: tuple | None = None  # (time, references(...) result) of the next tick
        try:
            wall0 = perf()
            t = t0
            tick = 0
            fall_check_every = max(1, int(round(0.02 / dt_wbc)))
            while t - t0 < t_max - 1e-9:
                s = self._read() if t > t0 else s
                contact = s["contact"]
                com, com_vel = s["com"], s["com_vel"]
                feet_pos = s["feet_pos"]
                changed = False  # the gait logic changed the gait state

                # ---- gait logic ----
                if mode == "shift" and t >= com_quintic.t1 - 1e-9:
                    changed = True
                    t_td = t
                    lip.reset(t, com[:2], com_vel[:2], feet_pos[stance][:2])
                    start_swing(t, s)
                elif mode == "single":
                    swing = other_side(stance)
                    tau = step.phase.tau(t)
                    by_contact = contact[swing] and tau >= p.touchdown_min_phase
                    if by_contact or tau >= 1.0:
                        changed = True
                        prev_t_td = t_td
                        touchdowns.append(
                            TouchDown(
                                t=t,
                                side=swing,
                                pos=feet_pos[swing].copy(),
                                planned=step.target_pos[:2].copy(),
                                yaw=_yaw_of_rotation(s["feet_rot"][swing]),
                                planned_yaw=step.target_yaw,
                                by_contact=bool(by_contact),
                                duration=t - prev_t_td,
                            )
                        )
                        ref_now = step.evaluate(t)
                        torso_yaw_ref = ref_now.torso_yaw
                        stance = swing
                        t_td = t
                        lip.reset(t, com[:2], com_vel[:2], feet_pos[stance][:2])
                        step = None
                        if n_steps is not None and len(touchdowns) >= n_steps:
                            break
                        if p.double_support > 0.0:
                            mode = "double"
                            t_lift = t + p.double_support
                        else:
                            start_swing(t, s)
                elif mode == "double" and t >= t_lift - 1e-9:
                    changed = True
                    start_swing(t, s)

                if mode == "single" and t >= next_plan_t - 1e-9:
                    changed = True
                    last_plan = call_planner(t, s)
                    while next_plan_t <= t + 1e-9:
                        next_plan_t += plan_period
                    if p.com_resync_on_plan:
                        lip.reset(t, com[:2], com_vel[:2], feet_pos[stance][:2])
                    apply_cop(t, last_plan)
                    step.update(
                        t,
                        target_pos=np.array([last_plan.foothold[0], last_plan.foothold[1], ground_z - p.landing_depth]),
                        target_yaw=last_plan.yaw,
                        t_end=t_td + last_plan.duration,
                        torso_target_yaw=last_plan.yaw,
                    )

                # ---- references (the helper's, when still valid) ----
                if spec is not None and not changed and spec[0] == t:
                    refs = spec[1]
                else:
                    refs = references(t, torso_yaw_ref)
                spec = None
                torso_yaw_ref = refs[0]

                # ---- whole-body QP ----
                w0 = perf()
                out = solve(s["q"], s["v"], ref)
                wbc_time = perf() - w0
                wbc_times.append(wbc_time)
                fallback = bool(getattr(out, "used_fallback", False))
                if fallback:
                    qp_failures += 1
                k = getattr(getattr(out, "errors", None), "angular_momentum", None)
                if k is not None:
                    k_last = np.asarray(k, dtype=float)
                tau_cmd = np.asarray(out.tau, dtype=float)
                status = int(out.status_code)

                if record_video and t >= next_frame_t - 1e-9:
                    frames.append(np.array(sim.qpos, dtype=float))
                    frame_times.append(t)
                    next_frame_t += 1.0 / p.video_fps

                # ---- simulate (on the helper, log this tick and prepare the next one's references meanwhile) ----
                logged = (t, s, refs[0], refs[1], refs[2], refs[3], tau_cmd, wbc_time, status, fallback)
                if helper is None:
                    log_tick(*logged)
                    sim_step(tau_cmd, n_sub)
                else:
                    t_next = t
                    for _ in range(n_sub):  # the simulator's own sum: time += timestep per step
                        t_next += dt_sim
                    helper.start(side_work, (logged, t_next))
                    try:
                        sim_step(tau_cmd, n_sub)
                    finally:
                        spec = helper.result()
                t = float(sim.time)
                if bar is not None:
                    bar.update(dt_wbc)
                # fall check: the simulator's full criterion (incl. non-foot contacts) at ~50 Hz, and
                # whenever the cheap height/tilt test on this tick's state fails
                tick += 1
                suspicious = crit is None or (
                    s["base_height"] - min(feet_pos[LEFT][2], feet_pos[RIGHT][2]) < height_alarm
                    or s["torso_rot"][2, 2] < tilt_alarm
                )
                if (suspicious or tick % fall_check_every == 0) and sim.fallen():
                    fell = True
                    fall_time = t
                    if stop_on_fall:
                        break
        finally:
            if helper is not None:
                helper.close()
                sys.setswitchinterval(old_switch)
        wall = _time.perf_counter() - wall0
        if bar is not None:
            bar.close()

        arrays = {k: np.asarray(v) for k, v in L.items() if k != "swing_err"}
        n = len(arrays["t"])
        swing_foot = np.where((arrays["stance"] == 1)[:, None], arrays["left_foot"], arrays["right_foot"])
        arrays["swing_err"] = (
            np.linalg.norm(arrays["swing_ref"] - swing_foot, axis=1) if n else np.zeros(0)
        )  # NaN in double support (the reference is NaN there)
        log = LoopLog(**arrays)
        sim_time = t - t0
        return LoopResult(
            log=log,
            touchdowns=touchdowns,
            fell=fell,
            fall_time=fall_time,
            sim_time=sim_time,
            wall_time=wall,
            real_time_factor=sim_time / wall if wall > 0 else float("inf"),
            wbc_ms=timing_stats_ms(wbc_times),
            planner_ms=timing_stats_ms(plan_times),
            qp_failures=qp_failures,
            wbc_rate_hz=1.0 / dt_wbc,
            sim_rate_hz=1.0 / dt_sim,
            planner_rate_hz=(1.0 / plan_period) if walking else 0.0,
            omega=omega,
            com_height=com_height,
            frames=np.asarray(frames) if record_video else None,
            frame_times=np.asarray(frame_times) if record_video else None,
            plans=plans,
        )
