"""Paper B's courses (:mod:`lipmpcc.studies.stepping_stones`): the planners under test (ALIP-MPC, ALIP-QP) and
their parameters, the approach + stones moved onto the robot's standing feet, the push test's stones and pushes
(timed from footsteps), and the row labels of Table II.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..exceptions import InvalidInputError
from ..models.alip import AlipParams
from ..planners.alip_mpc import AlipMpc, AlipMpcParams
from ..planners.alip_qp import AlipQp, AlipQpParams
from ..planners.presets import PlannerSettings
from ..push import Push
from ..terrain import (
    L_APPROACH, N_APPROACH, N_STONES, STEP_WIDTH, StoneSequence, approach_footholds, check_reachable, entry_foothold,
    initial_feet, profile_steps, stones_from_steps,
)
from . import paper

if TYPE_CHECKING:  # pragma: no cover
    from ..robots import RobotDescription

__all__ = [
    "PLANNERS", "LANDING_DEPTH", "N_EXIT", "FAST_STONES", "FAST_PUSH_STONES", "case_label", "planner_params",
    "make_planner", "make_course", "push_stones", "paper_pushes", "CourseScale", "scaled_profile",
    "DIGIT_REACH", "DIGIT_STEP_WIDTH", "DIGIT_STEP_DURATION",
]


PLANNERS = ("alip-mpc", "alip-qp")
LANDING_DEPTH = 0.015  # [m] the swing foot aims this far below the stone top (a sharp contact instant)
N_EXIT = 2  # free footholds after the last stone on a full body
FAST_STONES = {"alip": 16, "full body": 12}  # stones of the ``stones`` study in fast mode
FAST_PUSH_STONES = 22  # stones of the push test in fast mode
# Paper B's sizes are Digit's; a robot whose layout states its own sizes gets them scaled by its ratio to these
# (the same references as the MPCC's reach rectangle, lipmpcc.studies.path_params.robot_rectangle).
DIGIT_REACH = 0.55  # [m] Digit's forward reach per step (a layout's ``max_step_length``)
DIGIT_STEP_WIDTH = 0.26  # [m] Digit's standing feet spacing (a layout's ``step_width``)
DIGIT_STEP_DURATION = 0.4  # [s] Digit's step duration (a layout's ``step_duration``; the description's default)


@dataclass(frozen=True)
class CourseScale:
    """Paper B's sizes on a robot of another size, as ratios to Digit's (1: Digit's).

    Attributes:
        length: the legs' sizes (the ALIP-MPC's forward and lateral reach, the profile's L and W, the approach):
            the layout's ``max_step_length`` / :data:`DIGIT_REACH`.
        width: the nominal step width w and the smallest lateral distance between the feet:
            ``step_width`` / :data:`DIGIT_STEP_WIDTH` (the lateral reach beyond w and the profile's W scale with
            ``length``, :meth:`~lipmpcc.planners.alip_common.AlipStepParams.scaled`).
        time: step durations (T_nom, T_min, T_max): ``step_duration`` / :data:`DIGIT_STEP_DURATION`.
    """

    length: float = 1.0
    width: float = 1.0
    time: float = 1.0

    def __post_init__(self) -> None:
        for name in ("length", "width", "time"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or not 0.1 <= v <= 3.0:
                raise InvalidInputError(f"scale {name}", v, "a ratio in [0.1, 3]")

    @classmethod
    def for_robot(cls, robot: RobotDescription) -> "CourseScale | None":
        """``robot``'s ratios from its layout's ``max_step_length``, ``step_width`` and ``step_duration``, or
        None when the layout states no ``max_step_length`` or ``step_width`` (Digit's layouts: paper B as is)."""
        if robot.max_step_length is None or robot.step_width is None:
            return None
        return cls(length=float(robot.max_step_length) / DIGIT_REACH, width=float(robot.step_width) / DIGIT_STEP_WIDTH,
                   time=float(robot.step_duration) / DIGIT_STEP_DURATION)

    @property
    def w(self) -> float:
        """The nominal step width of the course and the planners [m] (paper B's w scaled)."""
        return STEP_WIDTH * self.width

    @property
    def approach_length(self) -> float:
        """The last approach step's length [m] (:data:`~lipmpcc.terrain.L_APPROACH` scaled)."""
        return L_APPROACH * self.length

    def summary(self) -> dict[str, float]:
        """The ratios and the sizes they give, for summary.json."""
        return {"length": self.length, "width": self.width, "time": self.time, "step_width_m": self.w,
                "approach_length_m": self.approach_length}


def case_label(profile: str, L: float | None = None, W: float | None = None, seed: int | None = None) -> str:
    """Row label of a course: ``"I L=0.4 W=+0.15"`` or ``"II seed 3"``."""
    if profile == "I":
        return f"I L={L:g} W={W:+.2f}"
    return f"{profile} seed {seed}"


def planner_params(
    name: str, alip: AlipParams | None = None, cop_range: tuple[float, float] = (0.0, 0.0),
    settings: PlannerSettings | None = None, scale: CourseScale | None = None,
    step_reference: str = "plan", stone_bounds: str = "relative", max_speed: float = 0.0,
) -> AlipMpcParams | AlipQpParams:
    """The parameters of ``"alip-mpc"`` (paper B's preset; with a foot, ``cop_range`` [m], see
    :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`; its ``step_reference`` and ``stone_bounds``,
    paper B's by default; its ``max_speed`` [m/s], 0: paper B's T_nom for every step) or ``"alip-qp"`` (Khadiv's
    QP on stones),
    with their reach, step width and durations scaled by ``scale`` (None: paper B's) and ``settings``
    (``--preset`` / ``--set``) applied over them."""
    a = AlipParams() if alip is None else alip
    if name == "alip-mpc":
        prm: AlipMpcParams | AlipQpParams = AlipMpcParams.paper(alip=a, cop_range=tuple(cop_range),
                                                                step_reference=step_reference, stone_bounds=stone_bounds,
                                                                max_speed=float(max_speed))
    elif name == "alip-qp":
        prm = AlipQpParams.paper(alip=a)
    else:
        raise InvalidInputError("--planner", name, "'alip-mpc' or 'alip-qp'")
    if scale is not None:
        prm = prm.scaled(scale.length, scale.width, scale.time)  # type: ignore[assignment]
    return prm if settings is None else settings.apply(prm, name)


def make_planner(
    name: str, alip: AlipParams | None = None, solver: str | None = None, cop_range: tuple[float, float] = (0.0, 0.0),
    settings: PlannerSettings | None = None, scale: CourseScale | None = None,
    step_reference: str = "plan", stone_bounds: str = "relative", max_speed: float = 0.0,
) -> AlipMpc | AlipQp:
    """The planner ``"alip-mpc"`` or ``"alip-qp"`` of :func:`planner_params`."""
    prm = planner_params(name, alip, cop_range, settings, scale, step_reference, stone_bounds, max_speed)
    if isinstance(prm, AlipMpcParams):
        return AlipMpc(prm, solver=solver)
    if solver not in (None, "proxqp"):
        raise InvalidInputError("solver", solver, "None or 'proxqp' for alip-qp")
    return AlipQp(prm)


def make_course(
    stones: StoneSequence, standing_feet: np.ndarray | None = None, approach_length: float = L_APPROACH,
    w: float = STEP_WIDTH,
) -> tuple[StoneSequence, np.ndarray]:
    """Approach footholds + ``stones``, moved onto the robot's standing feet.

    Args:
        stones: the stones (the ALIP's frame: standing feet at (0, ±0.14) m).
        standing_feet: (2, 2) the robot's standing sole positions (left, right) [m]; None: no shift.
        approach_length: length of the last approach step [m] (the approach ramps up to it); the stones
            keep their positions relative to the last approach foothold.
        w: the approach's step width [m] (the stones' frame: standing feet at (0, ±w/2); paper B's 0.28 m).

    Returns:
        The course (approach + stones) in the simulator's world frame, and the shift applied (2,) [m].
    """
    if not isinstance(stones, StoneSequence) or len(stones) == 0:
        raise InvalidInputError("stones", stones, "a non-empty StoneSequence")
    app = approach_footholds(L_app=approach_length, w=w)
    moved = app.centers[-1] - approach_footholds(w=w).centers[-1]
    if np.any(moved != 0.0):
        stones = StoneSequence(stones.centers + moved, stones.sizes, stones.sides, stones.is_stone, stones.name, dict(stones.meta))
    seq = app + stones
    shift = np.zeros(2)
    if standing_feet is not None:
        feet = np.asarray(standing_feet, dtype=float).reshape(2, 2)
        ref = np.mean(np.vstack(initial_feet(w)), axis=0)
        shift = np.mean(feet, axis=0) - ref
    if np.any(shift != 0.0):
        seq = StoneSequence(seq.centers + shift, seq.sizes, seq.sides, seq.is_stone, seq.name, dict(seq.meta))
    return seq, shift


def scaled_profile(
    profile: str, scale: CourseScale, seed: int | None = 0, L: float | None = None, W: float | None = None,
    n: int = N_STONES,
) -> StoneSequence:
    """Stones of profile I–IV (:func:`lipmpcc.terrain.make_profile`) with the steps' L^j and W^j (offsets beyond the
    nominal width, a reach) scaled by ``scale``'s length and the step width w by its width, checked against the scaled reach; a profile I ``L`` / ``W`` given
    [m] is used as given."""
    p = str(profile).strip().upper()
    Ls, Ws = profile_steps(p, seed, L, W, n)
    if p != "I" or L is None:
        Ls = Ls * scale.length
    if p != "I" or W is None:  # the stones' lateral offsets from the nominal width: the legs' reach
        Ws = Ws * scale.length
    label = f"profile {p}" + (f" L={Ls[0]:.3g} W={Ws[0]:+.3g}" if p == "I" else f" seed {seed}") + " (scaled)"
    seq = stones_from_steps(Ls, Ws, w=scale.w, name=label)
    seq.meta.update({"profile": p, "seed": seed, "L": Ls.tolist(), "W": Ws.tolist()})
    limits = AlipMpcParams.paper().scaled(scale.length, scale.width, scale.time).limits
    check_reachable(seq, entry_foothold(scale.w), limits)
    return seq


def push_stones(n: int | None = None) -> StoneSequence:
    """The push test's stones: ``n`` stones (None: the paper's 24) of its (L, W) = (0.4, 0)."""
    test = paper.push_test()
    n = test.n_stones if n is None else n
    return stones_from_steps(np.full(n, test.L), np.full(n, test.W), name=f"push (L, W) = ({test.L:g}, {test.W:g})")


def paper_pushes(scale: float = 1.0, n_approach: int = N_APPROACH) -> tuple[Push, ...]:
    """Paper B's pushes, forces multiplied by ``scale``, each with the index of the footstep it pushes
    (the approach counts: the swing towards stone j is footstep ``n_approach + j − 1``)."""
    if not isinstance(scale, (int, float)) or not math.isfinite(scale) or scale < 0:
        raise InvalidInputError("scale", scale, "a finite number >= 0")
    test = paper.push_test()
    a, b = test.window
    return tuple(
        Push.between((scale * p.force[0], scale * p.force[1]), a, b, step=n_approach + p.stone - 1) for p in test.pushes
    )


def _push_test_summary() -> list[dict[str, Any]]:
    test = paper.push_test()
    return [{"stone": p.stone, "force_N": list(p.force), "window_s": list(test.window)} for p in test.pushes]
