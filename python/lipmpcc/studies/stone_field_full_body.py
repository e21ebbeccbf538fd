"""The stone field on a full body (issue 29): ``lipmpcc run stone-field --robot digit_like``.

The planner is the ALIP study's, unchanged (:class:`~lipmpcc.planners.stone_field.StoneFieldPlanner`: the stone
choice, then paper B's ALIP-MPC), with the robot's ALIP constants (its mass, its standing COM height) and its
centre-of-pressure box. On the full body it runs inside paper B's footstep source
(:class:`~lipmpcc.planners.sources.alip.AlipFootstepSource`: the contact DCM, the learned contact phase and
landing bias), as paper B's ALIP-MPC does in ``lipmpcc run stones``; the approach is paper B's, driven by an
ALIP-MPC. The scene is :class:`~lipmpcc.sim.stones_scene.StonesRobotSim` with every stone of the field as a box
(the foot-centre rectangle grown by the foot) over a pit, the approach platform, and the exit platform as the goal.
The field is moved onto the robot's standing feet (as :func:`~lipmpcc.studies.stepping_stones.make_course` moves
paper B's courses); the pedestrians keep the simulation's clock.

The run is judged as on the ALIP (:mod:`lipmpcc.studies.stone_field`): every field foothold (the measured sole
at touch-down) on a stone up to the goal, no contact with a pedestrian, no fall (the pit, the simulator's fall).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, replace
from types import SimpleNamespace
from typing import Any, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..planners.alip_mpc import AlipMpc, AlipMpcParams
from ..planners.base import PlannerInput, StepPlan
from ..planners.sources.alip import AlipFootstepSource, AlipSourceParams
from ..planners.stone_field import StoneFieldParams, StoneFieldPlanner
from ..push import Push
from ..robots.description import RobotDescription
from ..stone_field import StoneField
from ..terrain import N_APPROACH, StoneSequence
from .stone_course import LANDING_DEPTH, make_course
from .stone_metrics import full_body_stones_log
from .stone_params import robot_cop_range, stones_wbc_params

__all__ = ["FieldSolver", "FullBodyFieldRun", "field_on_robot", "run_field_full_body"]


class FieldSolver:
    """The stone-field planner behind paper B's full-body footstep source: the source calls
    ``solve(dcm, stance, side, t, stones)`` as it calls an ALIP-MPC (the ``stones`` it passes, its course's, are not
    read: the planner chooses its own); ``now`` [s] is the simulation time of the call (set by
    :class:`_ClockedSource`), the pedestrians' clock."""

    def __init__(self, planner: StoneFieldPlanner) -> None:
        self.planner = planner
        self.params: AlipMpcParams = planner.params.mpc
        self.horizon = int(self.params.horizon)
        self.name = planner.name
        self.now = 0.0
        self._step = 0
        self._stance: np.ndarray | None = None

    @property
    def has_foot(self) -> bool:
        return self.planner.mpc.has_foot

    def reset(self) -> None:
        self.planner.reset()
        self._step, self._stance = 0, None

    def solve(self, xi: np.ndarray, stance: np.ndarray, side: int, t: float, stones: Sequence[Any]) -> Any:
        p = np.asarray(stance, float)[:2]
        if self._stance is not None and float(np.max(np.abs(p - self._stance))) > 1e-9:
            self._step += 1
        self._stance = p.copy()
        inp = SimpleNamespace(stance_pos=p, stance_side=int(side), dcm=np.asarray(xi, float), t=float(self.now),
                              time_since_touchdown=float(t), step_index=N_APPROACH + self._step)
        return self.planner.solve_step(inp)  # type: ignore[arg-type]


class _ClockedSource(AlipFootstepSource):
    """Paper B's source that hands the simulation time of each call to its :class:`FieldSolver`."""

    def plan(self, inp: PlannerInput) -> StepPlan:
        if isinstance(self.planner, FieldSolver):
            self.planner.now = float(inp.t)
        return super().plan(inp)


def field_on_robot(stone_field: StoneField, offset: np.ndarray) -> StoneField:
    """``stone_field`` moved by ``offset`` (2,) [m] (stones, path, goal, the pedestrians' start)."""
    off = np.asarray(offset, float).reshape(2)
    peds = tuple(dataclasses.replace(p, position=tuple(np.asarray(p.position, float) + off)) for p in stone_field.pedestrians)
    return StoneField(stone_field.centers + off, stone_field.sizes, stone_field.path + off, stone_field.corridor_width,
                      tuple(np.asarray(stone_field.goal_center) + off), stone_field.goal_size, peds, stone_field.seed,
                      stone_field.name, dict(stone_field.meta))


def _free(n: int, start: np.ndarray) -> StoneSequence:
    """``n`` free footholds after the approach (a straight preview; the field planner chooses its own)."""
    sides = np.array([-1 if k % 2 == 0 else 1 for k in range(n)])
    centers = np.column_stack([start[0] + 0.3 * np.arange(1, n + 1), start[1] - 0.14 + 0.14 * sides])
    return StoneSequence(centers, np.full((n, 2), np.inf), sides, np.zeros(n, bool), "stone field (free)")


def _scene(app: StoneSequence, fld: StoneField) -> StoneSequence:
    """The scene's sequence: the approach, then every stone of the field by x (the last one's far edge starts the
    exit platform, the goal's solid ground)."""
    order = np.argsort(fld.centers[:, 0], kind="stable")
    n = len(order)
    stones = StoneSequence(fld.centers[order], fld.sizes[order], np.array([1 if k % 2 else -1 for k in range(n)]),
                           np.ones(n, bool), fld.name)
    return app + stones


@dataclass
class FullBodyFieldRun:
    """A full-body run across a field, to be judged (:func:`lipmpcc.studies.stone_field.judge_log`).

    Attributes:
        log: the run in the ALIP loop's log, on the simulation's clock (the pedestrians' clock).
        result: the loop's :class:`~lipmpcc.loops.fullbody.log.LoopResult`.
        field: the field as placed in the scene (moved onto the robot's feet).
        planner: the stone-field planner; plan_times: its calls' wall times on the field [s].
        loop: the full-body loop (``loop.sim.model`` renders the replay and the video).
    """

    log: Any
    result: Any
    field: StoneField
    planner: StoneFieldPlanner
    plan_times: np.ndarray
    loop: Any = None


def run_field_full_body(robot: RobotDescription, stone_field: StoneField, cop_range: tuple[float, float] | None = None,
                        pushes: Sequence[Push] = (), budget: int | None = None, progress: bool = False,
                        chooser: str = "cost-to-go", record_video: bool = False) -> FullBodyFieldRun:
    """Cross ``stone_field`` (the ALIP study's frame) on ``robot`` with the planner's ``chooser``. ``cop_range``
    None: the robot's ``alip_cop_range``; ``budget``: the most footsteps after the approach; ``record_video``: keep the
    configurations for a replay or a video."""
    from ..control.references import SwingParams
    from ..loops.base import Course, PushSchedule
    from ..loops.fullbody.loop import FullBodyLoop, LoopParams
    from ..models.alip import AlipParams
    from ..sim.stones_scene import StonesRobotSim

    if not isinstance(stone_field, StoneField):
        raise InvalidInputError("stone_field", stone_field, "a lipmpcc.stone_field.StoneField")
    n = int(math.ceil(stone_field.path_length / 0.2)) + 8 if budget is None else int(budget)
    feet, H = robot.standing.feet_xy, float(robot.standing.com_height)
    probe = _free(1, np.array([1.05, 0.14]))
    course, _ = make_course(probe, feet)
    offset = course.centers[N_APPROACH] - probe.centers[0]
    fld = field_on_robot(stone_field, offset)
    app = StoneSequence(course.centers[:N_APPROACH], course.sizes[:N_APPROACH], course.sides[:N_APPROACH],
                        course.is_stone[:N_APPROACH], "approach")
    course = app + _free(n, app.centers[-1])
    alip = AlipParams(mass=float(robot.total_mass), z_c=H)
    cop = robot_cop_range(robot) if cop_range is None else (float(cop_range[0]), float(cop_range[1]))
    mpc = AlipMpcParams.paper(alip=alip, cop_range=cop, step_reference=robot.alip_step_reference,
                              stone_bounds=robot.alip_stone_bounds)
    planner = StoneFieldPlanner(fld, StoneFieldParams(chooser=chooser, mpc=mpc))
    swing = SwingParams()
    timing = robot.alip_touchdown_timing or "planner"
    sp = AlipSourceParams(rate_hz=25.0, swing_min_remaining=swing.min_remaining, relax_on_failure=False,
                          dcm_settle_time=float(robot.alip_dcm_settle_time))
    if timing == "loop":
        sp = replace(sp, contact_phase=1.0, contact_window=0)
    source = _ClockedSource(FieldSolver(planner), course, approach_planner=AlipMpc(mpc), approach_steps=N_APPROACH,
                            params=sp, name=planner.name)
    sim = StonesRobotSim(robot, _scene(app, fld), standing_feet=feet)
    loop_params = LoopParams(com_height=H, first_stance="left", landing_depth=LANDING_DEPTH, swing=swing,
                             com_resync_on_plan=bool(robot.alip_com_resync), touchdown_timing=timing)
    loop = FullBodyLoop(robot, planner=source, params=loop_params, wbc_params=stones_wbc_params(robot), sim=sim)
    result = loop.run(n_steps=len(course), progress=progress, record_video=record_video, course=Course(stones=course),
                      schedule=PushSchedule(tuple(pushes)))
    reason = (result.fall_reason or sim.fall_reason() or "") if result.fell else ""
    log = full_body_stones_log(result, source, course, (), pushes, reason)
    t0 = float(source.records[0].t) if source.records else 0.0  # the log's clock starts at the first lift-off
    log = replace(log, t=log.t + t0, td_times=log.td_times + t0,
                  fall_time=None if log.fall_time is None else log.fall_time + t0)
    times = np.array([r.result.plan_time for r in source.course_records() if r.result is not None], float)
    return FullBodyFieldRun(log, result, fld, planner, times, loop)
