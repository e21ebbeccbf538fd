"""What a full-body run records: the per-tick log (:class:`LoopLog`, written by :class:`TickLogger`),
the support exchanges (:class:`TouchDown`), the video frames (:class:`FrameRecorder`) and the
run's outcome (:class:`LoopResult`, whose :meth:`~LoopResult.summary` gives the summary.json fields)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...conventions import Side
from ...planners.base import StepPlan
from ...push import Push
from ...sim.robot_sim import RobotSim
from ...sim.types import Measurement
from ..base import RunRecord
from .angles import tilt_of, yaw_of

__all__ = ["LoopLog", "TouchDown", "LoopResult", "TickLogger", "FrameRecorder"]


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
    side: Side
    pos: np.ndarray
    planned: np.ndarray
    yaw: float
    planned_yaw: float
    by_contact: bool
    duration: float


@dataclass
class LoopResult:
    """Outcome of :meth:`~lipmpcc.loops.fullbody.FullBodyLoop.run`.

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
        plans: every planner answer with its time [s], in order.
        fall_reason: why the run counts as a fall (the simulator's fall criterion, or
            ``"simulation diverged"`` when MuJoCo's state blew up), or None.
        warnings: one line per problem the run met without an error: MuJoCo's divergence (the run
            stopped there, as a fall) and other warnings, motors without a torque limit.
        relaxed_solves: distinct planner answers that came from a relaxed re-solve after a failed solve
            (their status starts with ``"relaxed"``, e.g. the ALIP footstep source's), 0 when none.
        fall_body, fall_contact: the robot body of the fall (the torso for height and tilt, the body
            that touched for a contact) and what it touched (``""`` otherwise), or None without a fall.
        pushes: the pushes as applied, absolute times (the footstep-timed ones as they were armed).
        record: the run's :class:`~lipmpcc.loops.base.RunRecord` (planned vs landed footholds and durations).
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
    fall_reason: str | None = None
    warnings: list[str] = field(default_factory=list)
    relaxed_solves: int = 0
    fall_body: str | None = None
    fall_contact: str | None = None
    pushes: tuple[Push, ...] = ()
    record: RunRecord | None = None

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
        if len(self.log.t) < 2:  # no tick or one: no path (an empty log's arrays are 1-D)
            return 0.0
        c = self.log.com[:, :2]
        return float(np.sum(np.linalg.norm(np.diff(c, axis=0), axis=1)))

    @property
    def displacement(self) -> float:
        """Straight-line horizontal COM displacement from start to end [m]."""
        if len(self.log.t) < 2:
            return 0.0
        c = self.log.com[:, :2]
        return float(np.linalg.norm(c[-1] - c[0]))

    def summary(self) -> dict[str, object]:
        """The full-body fields of a scenario's summary.json."""
        return {
            "fell": self.fell,
            "fall_time_s": self.fall_time if self.fell else None,
            "fall_reason": self.fall_reason if self.fell else None,
            "fall_body": self.fall_body if self.fell else None,
            "fall_contact": self.fall_contact if self.fell else None,
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


class TickLogger:
    """Collects one row of :class:`LoopLog` per WBC tick; :meth:`to_log` makes the arrays.

    A tick appends one tuple of what it was handed (the arrays are stored, not copied); the derived
    columns (DCM, torso heading and tilt) are computed by :meth:`to_log`, with the same arithmetic per
    row (``tests/loops/fullbody/test_log.py`` checks them against the per-tick formulas to the bit).

    Args:
        omega: the LIP ω [1/s] of the logged DCM.
    """

    def __init__(self, omega: float) -> None:
        self.omega = omega
        self._rows: list[tuple] = []

    def log(self, t: float, m: Measurement, yaw_ref: float, com_ref: np.ndarray, swing_ref: np.ndarray,
            phase: float, stance: int, tau: np.ndarray, wbc_time: float, status: int, fallback: bool) -> None:
        """One tick: its time [s], measurement, references (torso heading [rad], COM [m], swing foot
        [m], phase), stance code (:attr:`LoopLog.stance`) and the WBC's answer (efforts, wall time
        [s], QP status code, fallback used). The arrays are stored, not copied."""
        feet = m.feet
        self._rows.append((t, m.com, com_ref, m.com_vel, m.q[2], m.torso.rotation, yaw_ref, m.contact, stance, phase,
                           feet[0].position, feet[1].position, swing_ref, tau, wbc_time, status, fallback))

    def to_log(self) -> LoopLog:
        """The rows so far as a :class:`LoopLog` (with the DCM, the torso's heading and tilt, the swing-foot error)."""
        rows = self._rows
        if not rows:  # an empty log's arrays are 1-D
            return LoopLog(**{k: np.asarray([]) for k in LoopLog.__dataclass_fields__})
        (t, com, com_ref, com_vel, base_height, rotation, yaw_ref, contact, stance, phase, left_foot, right_foot,
         swing_ref, tau, wbc_time, status, fallback) = (list(col) for col in zip(*rows))
        com_a, com_vel_a = np.asarray(com), np.asarray(com_vel)
        dcm = com_a[:, :2] + com_vel_a[:, :2] / self.omega  # the same IEEE operations as per row
        arrays = dict(
            t=np.asarray(t), com=com_a, com_ref=np.asarray(com_ref), com_vel=com_vel_a, dcm=dcm,
            base_height=np.asarray([float(h) for h in base_height]),
            torso_yaw=np.asarray([yaw_of(r) for r in rotation]), torso_yaw_ref=np.asarray(yaw_ref),
            torso_tilt=np.asarray([tilt_of(r) for r in rotation]), contact=np.asarray(contact),
            stance=np.asarray(stance), phase=np.asarray(phase), left_foot=np.asarray(left_foot),
            right_foot=np.asarray(right_foot), swing_ref=np.asarray(swing_ref), tau=np.asarray(tau),
            wbc_time=np.asarray(wbc_time), wbc_status=np.asarray(status), fallback=np.asarray(fallback),
        )
        swing_foot = np.where((arrays["stance"] == 1)[:, None], arrays["left_foot"], arrays["right_foot"])
        arrays["swing_err"] = np.linalg.norm(arrays["swing_ref"] - swing_foot, axis=1)  # NaN in double support
        return LoopLog(**arrays)


class FrameRecorder:
    """MuJoCo configurations for a video, at ``fps`` frames per simulated second from ``t0`` [s]."""

    def __init__(self, t0: float, fps: float) -> None:
        self.fps = fps
        self.next_t = t0
        self.qpos: list[np.ndarray] = []
        self.times: list[float] = []

    def record(self, t: float, sim: RobotSim) -> None:
        """Keep the simulator's configuration at ``t`` [s] when a frame is due."""
        if t >= self.next_t - 1e-9:
            self.qpos.append(np.array(sim.qpos, dtype=float))
            self.times.append(t)
            self.next_t += 1.0 / self.fps
