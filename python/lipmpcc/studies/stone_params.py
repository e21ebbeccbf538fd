"""Paper B on a full body (:mod:`lipmpcc.studies.stepping_stones`): the ALIP-MPC's centre-of-pressure box and the
whole-body QP's gains from the robot's description, and the settings of a full-body stepping-stone run
(:class:`FullBodyStonesParams`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..exceptions import InvalidInputError, ParameterError
from ..push import Push
from ..terrain import L_APPROACH

from .stone_course import LANDING_DEPTH, N_EXIT

if TYPE_CHECKING:  # pragma: no cover
    from ..planners.sources.alip import AlipFootstepSource, AlipSourceParams
    from ..planners.base import PlannerInput, StepPlan
    from ..robots import RobotDescription
    from ..sim.stones_scene import StonesRobotSim, StonesSceneParams
    from ..control.wbc_types import WbcParams

__all__ = ["robot_cop_range", "stones_wbc_params", "FullBodyStonesParams", "stones_timing"]


def robot_cop_range(robot: RobotDescription) -> tuple[float, float]:
    """The ALIP-MPC's centre-of-pressure box (x, y) [m] on ``robot``: its description's
    ``alip_cop_range``, or (0, 0) (paper B's point foot) when it has none."""
    r = robot.alip_cop_range
    return (0.0, 0.0) if r is None else (float(r[0]), float(r[1]))


def stones_wbc_params(robot: RobotDescription) -> WbcParams:
    """The whole-body QP's parameters for paper B's runs on ``robot``: the robot's own
    (:meth:`~lipmpcc.control.wbc_types.WbcParams.for_robot`), with the horizontal COM task's k_p, k_d replaced by the
    description's ``alip_com_gains`` when it has them (height gains and every weight unchanged): paper B's
    low level leaves the horizontal COM to the ALIP the planner assumes; with the description's
    ``alip_wbc_overrides`` over its ``wbc_overrides``; and with the description's
    ``alip_cop_safety_factor`` as the CoP safety factor when it has one (Digit v3: the controller's lateral CoP
    room beyond the ALIP-MPC's box, docs/design.md)."""
    from ..control.wbc_types import TaskGains, WbcParams

    extra = tuple(robot.alip_wbc_overrides or ())
    base = WbcParams.for_robot(replace(robot, wbc_overrides=tuple(robot.wbc_overrides or ()) + extra) if extra else robot)
    csf = robot.alip_cop_safety_factor
    if csf is not None:
        base = replace(base, cop_safety_factor=float(csf))
    gains = robot.alip_com_gains
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
        centroidal_momentum: include the centroidal angular momentum in the contact L
            (:func:`lipmpcc.planners.sources.alip.contact_dcm`).
        rate_hz: planner rate [Hz] (paper B: 25 Hz).
        stone_tolerance: a measured sole counts inside its stone's bounds within this tolerance [m].
        com_resync: re-start the loop's LIP COM reference from the measured COM state at every planner
            update (``LoopParams.com_resync_on_plan``) rather than at touch-down only; None: the robot
            description's ``alip_com_resync``.
        wbc: the whole-body QP's parameters (None: :func:`stones_wbc_params`).
        com_height: the loop's constant COM height and the ALIP's z_c [m] (None: the standing COM height).
        approach_length: length of the last approach step [m] (see :func:`make_course`).
        scene: the course's geometry (None: :class:`~lipmpcc.sim.stones_scene.StonesSceneParams` defaults).
        cop_range: the ALIP-MPC's centre-of-pressure box (x, y) [m] ((0, 0): paper B's point foot);
            None: the robot description's ``alip_cop_range`` (a point foot when it has none).
        touchdown_timing: who times the touch-down (:attr:`~lipmpcc.loops.fullbody.LoopParams.touchdown_timing`):
            ``"planner"`` (the swing ends at the detected contact; the footstep source learns the contact phase)
            or ``"loop"`` (the loop keeps the planned time; the source asks for the plan's duration as is);
            None: the robot description's ``alip_touchdown_timing``.
        touchdown_contact: which swing-foot contact ends a step
            (:attr:`~lipmpcc.loops.fullbody.LoopParams.touchdown_contact`): ``"tick"`` (default, the state
            measured at the WBC tick) or ``"substep"`` (any 2 kHz substep since the last tick: a toe-first landing
            counts when the toe touches; measured on Digit v3 in docs/design.md, not the default).
        scale_to_robot: scale the planners' reach, step width and step durations and the approach to the robot
            when its layout states its sizes (:meth:`~lipmpcc.studies.stone_course.CourseScale.for_robot`; the
            approach's last step becomes ``approach_length`` times the length ratio); False: paper B's (Digit's).
    """

    landing_depth: float = LANDING_DEPTH
    n_exit: int = N_EXIT
    centroidal_momentum: bool = False
    rate_hz: float = 25.0
    stone_tolerance: float = 0.0
    com_resync: bool | None = None
    wbc: WbcParams | None = None
    com_height: float | None = None
    approach_length: float = L_APPROACH
    scene: StonesSceneParams | None = None
    cop_range: tuple[float, float] | None = None
    touchdown_timing: str | None = None
    scale_to_robot: bool = True
    touchdown_contact: str = "tick"

    def __post_init__(self) -> None:
        if self.touchdown_timing not in (None, "planner", "loop"):
            raise ParameterError("touchdown_timing", self.touchdown_timing, "None, 'planner' or 'loop'")
        if self.touchdown_contact not in ("tick", "substep"):
            raise ParameterError("touchdown_contact", self.touchdown_contact, "'tick' or 'substep'")
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


class _StepPushes:
    """A footstep source wrapper that pushes the torso during given footsteps (deprecated: the loop's
    :class:`~lipmpcc.loops.base.PushSchedule` does it).

    The step timing of paper B's runs is not known in advance, so each push (``force`` (F_x, F_y) [N],
    window ``t_start``–``t_end`` after the touch-down that starts footstep ``step``) is registered on the
    simulator at the first planner call of that footstep (its lift-off).

    Attributes:
        windows: registered pushes as (t_start, t_end, (F_x, F_y)) in simulation time [s].
    """

    def __init__(self, source: AlipFootstepSource, sim: StonesRobotSim, pushes: Sequence[Push]) -> None:
        for p in pushes:
            if not isinstance(p, Push) or p.step is None:
                raise InvalidInputError("pushes", p, "lipmpcc.push.Push objects with a footstep index")
        self.source = source
        self.sim = sim
        self.pushes = tuple(pushes)
        self.name = source.name
        self.rate_hz = source.rate_hz
        self.compensates_touchdown = getattr(source, "compensates_touchdown", False)
        self.windows: list[tuple[float, float, tuple[float, float]]] = []
        self._last = -1

    def reset(self) -> None:
        self.source.reset()
        self.windows = []
        self._last = -1

    def plan(self, inp: PlannerInput) -> StepPlan:
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


def stones_timing(
    robot: RobotDescription, prm: FullBodyStonesParams, swing_min_remaining: float
) -> tuple[str, bool, "AlipSourceParams"]:
    """Paper B's full-body timing on ``robot``: who times the touch-down (``prm.touchdown_timing``, else the
    robot's ``alip_touchdown_timing``), whether the loop's LIP COM reference restarts at every planner update
    (``prm.com_resync``, else the robot's ``alip_com_resync``), and the ALIP footstep source's parameters (with
    the loop timing the touch-down it learns no contact phase: the loop lands at the requested end)."""
    from ..planners.sources.alip import AlipSourceParams

    timing = robot.alip_touchdown_timing if prm.touchdown_timing is None else prm.touchdown_timing
    resync = bool(robot.alip_com_resync if prm.com_resync is None else prm.com_resync)
    sp = AlipSourceParams(rate_hz=prm.rate_hz, swing_min_remaining=swing_min_remaining,
                          centroidal_momentum=prm.centroidal_momentum, dcm_settle_time=float(robot.alip_dcm_settle_time))
    return timing, resync, (replace(sp, contact_phase=1.0, contact_window=0) if timing == "loop" else sp)
