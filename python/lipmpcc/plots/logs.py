"""What the figures read: one record per kind of run, whichever model produced it.

- :class:`PathFollowingLog` (paper A's figures): a frozen dataclass. The path-following study builds it
  from a LIP run (:func:`lipmpcc.studies.path_metrics.lip_path_log`) or from a full-body run.
- :class:`SteppingStonesLog` (paper B's figures): a protocol. The ALIP loop's log
  (:class:`~lipmpcc.loops.alip.AlipLoopLog`) has these fields, and the stepping-stone study records a
  full-body run in that same log.
- :class:`FullBodyRunResult` (the walking figures): a protocol the full-body loop's result has.

The figures never import the loops: they read these fields only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, Sequence, runtime_checkable

import numpy as np

from ..push import Push

if TYPE_CHECKING:  # pragma: no cover
    from ..models.alip import DcmBounds
    from ..terrain import StoneSequence

__all__ = [
    "PathFollowingLog",
    "SteppingStonesLog",
    "TouchDownRecord",
    "FullBodyTickLog",
    "FullBodyRunResult",
]


@dataclass(frozen=True)
class PathFollowingLog:
    """A path-following run (paper A) as its figures and metrics read it, on the LIP or a full body.

    At the step instants (support exchanges):
        t: (n,) times [s]; e_contouring, e_lag, e_cartesian: (n,) errors of the COM at ``t`` [m]
        (NaN where undefined).
    Per step k:
        footholds: (k, 3) landed feet [x, y, yaw] [m, rad]; sides: (k,) +1 left / −1 right;
        step_offsets: (k, 2) paper A's u = [uˣ, uʸ], foot − COM [m] (planned on the LIP, realised at
        touch-down on the full body).
    Per planner solve:
        v_avg_t: (p,) times [s]; v_avg: (p,) (1/N) Σ v [m]; v_max [m].
    Continuous samples:
        tc: (m,) [s]; com: (m, 4) [x, ẋ, y, ẏ]; obstacles: (n_obs, m, 2) centres [m]; clearance: (m,)
        robot footprint to the obstacles [m]; theta_c: (m,) closest path parameter [m] and
        e_contouring_c: (m,) contouring error [m] (None on the LIP, whose errors are per step).

    pushes: the run's pushes; progress: the path parameter reached at the end [m].
    path_end_t: on a full body, the time [s] of the support exchange at which the MPCC's committed path
    parameter reached the path's end (where the LIP loop stops, ``"end of path"``); None when it did not
    (and on the LIP, whose loop stops there).
    """

    t: np.ndarray
    e_contouring: np.ndarray
    e_lag: np.ndarray
    e_cartesian: np.ndarray
    footholds: np.ndarray
    sides: np.ndarray
    step_offsets: np.ndarray
    v_avg_t: np.ndarray
    v_avg: np.ndarray
    v_max: float
    tc: np.ndarray
    com: np.ndarray
    obstacles: np.ndarray
    clearance: np.ndarray
    pushes: tuple[Push, ...] = ()
    progress: float = 0.0
    theta_c: np.ndarray | None = None
    e_contouring_c: np.ndarray | None = None
    path_end_t: float | None = None

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        return len(self.footholds)


@runtime_checkable
class SteppingStonesLog(Protocol):
    """A stepping-stone run (paper B) as its figures read it.

    Samples: t (k,) [s], com, com_vel, dcm (k, 2) [m, m/s, m]. Per footstep: footholds (n, 2) [m],
    step_index (n,) index in ``sequence``, step_sides (n,) +1/−1, in_stone, kin_ok (n,) bool, durations
    (n,) [s], td_times (n,) touch-down times [s], z_initial (n+1, 2) initial DCM of each step [m]. Per
    planner call: plan_t, plan_T (q,) [s]. push_windows: (t_start, t_end, (F_x, F_y)) [s, N].
    """

    @property
    def sequence(self) -> StoneSequence: ...
    @property
    def t(self) -> np.ndarray: ...
    @property
    def com(self) -> np.ndarray: ...
    @property
    def com_vel(self) -> np.ndarray: ...
    @property
    def dcm(self) -> np.ndarray: ...
    @property
    def footholds(self) -> np.ndarray: ...
    @property
    def step_index(self) -> np.ndarray: ...
    @property
    def step_sides(self) -> np.ndarray: ...
    @property
    def in_stone(self) -> np.ndarray: ...
    @property
    def kin_ok(self) -> np.ndarray: ...
    @property
    def durations(self) -> np.ndarray: ...
    @property
    def td_times(self) -> np.ndarray: ...
    @property
    def z_initial(self) -> np.ndarray: ...
    @property
    def plan_t(self) -> np.ndarray: ...
    @property
    def plan_T(self) -> np.ndarray: ...
    @property
    def start_stance(self) -> np.ndarray: ...
    @property
    def start_swing(self) -> np.ndarray | None: ...
    @property
    def fell(self) -> bool: ...
    @property
    def fall_index(self) -> int | None: ...
    @property
    def fall_time(self) -> float | None: ...
    @property
    def push_windows(self) -> list[tuple[float, float, tuple[float, float]]]: ...
    @property
    def dcm_bounds(self) -> DcmBounds: ...


class TouchDownRecord(Protocol):
    """A touch-down of a full-body run: time [s], foot side (``"left"``/``"right"``), landed and
    planned position [m]."""

    @property
    def t(self) -> float: ...
    @property
    def side(self) -> str: ...
    @property
    def pos(self) -> np.ndarray: ...
    @property
    def planned(self) -> np.ndarray: ...


class FullBodyTickLog(Protocol):
    """The full-body loop's per-tick arrays (k ticks; world frame, [s], [m], [m/s], [rad])."""

    @property
    def t(self) -> np.ndarray: ...
    @property
    def com(self) -> np.ndarray: ...
    @property
    def com_ref(self) -> np.ndarray: ...
    @property
    def com_vel(self) -> np.ndarray: ...
    @property
    def dcm(self) -> np.ndarray: ...
    @property
    def base_height(self) -> np.ndarray: ...
    @property
    def torso_tilt(self) -> np.ndarray: ...
    @property
    def swing_err(self) -> np.ndarray: ...
    @property
    def wbc_time(self) -> np.ndarray: ...
    @property
    def left_foot(self) -> np.ndarray: ...
    @property
    def right_foot(self) -> np.ndarray: ...


class FullBodyRunResult(Protocol):
    """A full-body run as the walking figures read it."""

    @property
    def log(self) -> FullBodyTickLog: ...
    @property
    def touchdowns(self) -> Sequence[TouchDownRecord]: ...
    @property
    def wbc_rate_hz(self) -> float: ...
    @property
    def wbc_ms(self) -> dict[str, float]: ...
    @property
    def real_time_factor(self) -> float: ...
