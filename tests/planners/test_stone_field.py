"""The stone-field planner (issue 29): it chooses the stones across a field and places each foot with
paper B's ALIP-MPC; a field with no way across is reported, never a hang."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.obstacles import Obstacle
from lipmpcc.planners.stone_field import StoneFieldParams, StoneFieldPlanner, cost_to_go
from lipmpcc.stone_field import StoneField
from lipmpcc.studies.stone_field import run_field


def _easy_field(gap_at: float | None = None, pedestrians: tuple = ()) -> StoneField:
    """A straight backbone (0.3 m steps, feet 0.28 m apart) with distractors off to the sides; ``gap_at``
    removes every stone beyond that x but for one far away (no way across)."""
    xs = 1.05 + 0.3 * np.arange(1, 9)
    back = np.column_stack([xs, np.where(np.arange(8) % 2 == 0, -0.14, 0.14)])
    extra = np.array([[1.5, 0.55], [2.0, -0.6], [2.6, 0.6], [3.1, -0.55]])
    c = np.vstack([back, extra])
    goal_x = xs[-1] + 0.45
    if gap_at is not None:
        c = np.vstack([c[c[:, 0] < gap_at], [[goal_x - 0.3, 0.0]]])
    return StoneField(c, np.tile((0.2, 0.1), (len(c), 1)), [[1.05, 0.0], [goal_x, 0.0]], 1.5, (goal_x + 0.3, 0.0),
                      (0.6, 1.5), pedestrians)


def test_crosses_an_easy_field_on_the_alip_every_foot_on_a_stone() -> None:
    fld = _easy_field()
    run = run_field(fld)
    assert run.outcome == "completed" and run.reached_end, run.reason
    field_feet = run.log.footholds[6 : 6 + run.field_steps]
    assert all(fld.stone_at(f) is not None for f in field_feet[:-1]) and fld.in_goal(field_feet[-1])
    assert run.field_steps <= 10  # 8 stones and the goal: no detour on an easy field
    assert np.median(run.plan_times) < 0.05


def test_a_field_with_no_way_across_is_stalled_naming_the_step() -> None:
    run = run_field(_easy_field(gap_at=1.8), budget=12)
    assert run.outcome == "stalled" and not run.reached_end
    assert "no way to the goal" in run.reason and "step 6" in run.reason


def test_waits_for_a_pedestrian_crossing_ahead_instead_of_walking_into_it() -> None:
    # a pedestrian crossing the path at x = 2.3 m, 0.4 m/s, at the path when the robot would get there
    ped = Obstacle.circle(0.25, position=(2.3, -0.4 * 5.0 - 0.0), velocity=(0.0, 0.4))
    fld = _easy_field(pedestrians=(ped,))
    run = run_field(fld)
    assert run.outcome == "completed", run.reason
    assert run.min_clearance_m is not None and run.min_clearance_m > 0.0
    assert run.waits >= 1  # it marched in place while the pedestrian passed
    blind = run_field(fld, "nominal")  # the path-agnostic baseline ignores the pedestrian
    assert blind.outcome == "collided"


def test_cost_to_go_counts_steps_to_the_goal() -> None:
    # nodes 0 -> 1 -> 2(goal), a right swing onto 0 and 2's edges, a left swing onto 1
    adj = {1: np.zeros((3, 3), bool), -1: np.zeros((3, 3), bool)}
    adj[1][0, 1] = True
    adj[-1][1, 2] = True
    adj[1][2, 2] = adj[-1][2, 2] = True
    ctg = cost_to_go(adj, np.zeros(3))
    assert ctg[-1][0] == 2.0 and ctg[1][1] == 1.0 and ctg[1][0] == np.inf


def test_bad_parameters_and_inputs_are_named() -> None:
    with pytest.raises(ParameterError, match="chooser"):
        StoneFieldParams(chooser="random")
    with pytest.raises(ParameterError, match="horizon_choice"):
        StoneFieldParams(horizon_choice=2)
    with pytest.raises(InvalidInputError, match="stone_field"):
        StoneFieldPlanner("field.json")  # type: ignore[arg-type]
    pl = StoneFieldPlanner(_easy_field())
    assert pl.name == "stone-field" and pl.rate_hz == pytest.approx(25.0)
    with pytest.raises(InvalidInputError, match="inp"):
        pl.plan(None)  # type: ignore[arg-type]


def test_with_a_foot_the_stones_shrink_by_the_centre_of_pressure_box() -> None:
    from lipmpcc.planners.alip_mpc import AlipMpcParams

    fld = _easy_field()
    point = StoneFieldPlanner(fld)._regions_of(np.array([1.05, 0.14]), 1, [0, 1])
    foot = StoneFieldPlanner(fld, StoneFieldParams(mpc=AlipMpcParams.paper(cop_range=(0.06, 0.025))))
    shrunk = foot._regions_of(np.array([1.05, 0.14]), 1, [0, 1])
    assert point[0].size == pytest.approx((0.2, 0.1)) and shrunk[0].size == pytest.approx((0.08, 0.05))
    assert shrunk[0].center == point[0].center
