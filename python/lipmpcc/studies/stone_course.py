"""Paper B's courses (:mod:`lipmpcc.studies.stepping_stones`): the planners under test (ALIP-MPC, ALIP-QP) and
their parameters, the approach + stones moved onto the robot's standing feet, the push test's stones and pushes
(timed from footsteps), and the row labels of Table II.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..exceptions import InvalidInputError
from ..models.alip import AlipParams
from ..planners.alip_mpc import AlipMpc, AlipMpcParams
from ..planners.alip_qp import AlipQp, AlipQpParams
from ..planners.presets import PlannerSettings
from ..push import Push
from ..terrain import L_APPROACH, N_APPROACH, StoneSequence, approach_footholds, initial_feet, stones_from_steps
from . import paper

__all__ = [
    "PLANNERS", "LANDING_DEPTH", "N_EXIT", "FAST_STONES", "FAST_PUSH_STONES", "case_label", "planner_params",
    "make_planner", "make_course", "push_stones", "paper_pushes",
]


PLANNERS = ("alip-mpc", "alip-qp")
LANDING_DEPTH = 0.015  # [m] the swing foot aims this far below the stone top (a sharp contact instant)
N_EXIT = 2  # free footholds after the last stone on a full body
FAST_STONES = {"alip": 16, "full body": 12}  # stones of the ``stones`` study in fast mode
FAST_PUSH_STONES = 22  # stones of the push test in fast mode


def case_label(profile: str, L: float | None = None, W: float | None = None, seed: int | None = None) -> str:
    """Row label of a course: ``"I L=0.4 W=+0.15"`` or ``"II seed 3"``."""
    if profile == "I":
        return f"I L={L:g} W={W:+.2f}"
    return f"{profile} seed {seed}"


def planner_params(
    name: str, alip: AlipParams | None = None, cop_range: tuple[float, float] = (0.0, 0.0),
    settings: PlannerSettings | None = None,
) -> AlipMpcParams | AlipQpParams:
    """The parameters of ``"alip-mpc"`` (paper B's preset; with a foot, ``cop_range`` [m], see
    :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`) or ``"alip-qp"`` (Khadiv's QP on stones),
    with ``settings`` (``--preset`` / ``--set``) applied over them."""
    a = AlipParams() if alip is None else alip
    if name == "alip-mpc":
        prm: AlipMpcParams | AlipQpParams = AlipMpcParams.paper(alip=a, cop_range=tuple(cop_range))
    elif name == "alip-qp":
        prm = AlipQpParams.paper(alip=a)
    else:
        raise InvalidInputError("--planner", name, "'alip-mpc' or 'alip-qp'")
    return prm if settings is None else settings.apply(prm, name)


def make_planner(
    name: str, alip: AlipParams | None = None, solver: str | None = None, cop_range: tuple[float, float] = (0.0, 0.0),
    settings: PlannerSettings | None = None,
) -> AlipMpc | AlipQp:
    """The planner ``"alip-mpc"`` or ``"alip-qp"`` of :func:`planner_params`."""
    prm = planner_params(name, alip, cop_range, settings)
    if isinstance(prm, AlipMpcParams):
        return AlipMpc(prm, solver=solver)
    if solver not in (None, "proxqp"):
        raise InvalidInputError("solver", solver, "None or 'proxqp' for alip-qp")
    return AlipQp(prm)


def make_course(
    stones: StoneSequence, standing_feet: np.ndarray | None = None, approach_length: float = L_APPROACH
) -> tuple[StoneSequence, np.ndarray]:
    """Approach footholds + ``stones``, moved onto the robot's standing feet.

    Args:
        stones: the stones (the ALIP's frame: standing feet at (0, ±0.14) m).
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
