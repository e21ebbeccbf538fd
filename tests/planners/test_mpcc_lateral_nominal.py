"""lipmpcc.planners.mpcc: the lateral nominal (MpccParams.lateral_nominal) takes away the dead band of a lateral
bound that every step sits on (Digit v3's Cartesian trailing run, docs/design.md)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import ParameterError
from lipmpcc.models.lip3d import Lip3dModel, ReachabilityRectangle
from lipmpcc.paths import LinePath
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner

_MODEL = Lip3dModel(T=0.35, H=0.9)


def _params(lower: float, nominal: float) -> MpccParams:
    rect = ReachabilityRectangle(forward=(-0.35, 0.35), lateral=(lower, 0.40), heading=(-0.3, 0.3))
    return MpccParams.overtake_cartesian(model=_MODEL, rectangle=rect, heading_weight=20.0, lateral_nominal=nominal,
                                         jit=False)


def _plan(prm: MpccParams, y0: float, side: int):
    """A plan from 0.1 m/s along a straight line, ``y0`` [m] beside it, with the lateral velocity of stepping
    0.16 m beside the COM (the periodic gait's at the exchange, towards the foot placed now)."""
    w = _MODEL.omega
    vy = side * 0.16 * w * math.tanh(0.5 * w * _MODEL.T)
    return MpccPlanner(LinePath((0.0, 0.0), (40.0, 0.0)), prm).solve(np.array([0.0, 0.1, y0, vy, 0.0]), side, [], 0.0)


@pytest.mark.parametrize("side", [1, -1])
@pytest.mark.parametrize("y0", [-0.04, 0.04])
def test_a_lateral_error_is_corrected_at_once_about_the_nominal_and_put_off_on_the_bound(y0: float, side: int) -> None:
    on_bound = _plan(_params(0.16, 0.0), y0, side)  # paper A's cost, every step on the 0.16 m bound
    about = _plan(_params(0.10, 0.16), y0, side)  # the bound at 0.10 m, the cost about 0.16 m
    assert on_bound.found and about.found
    # on the bound a wider step costs first order: two steps on, most of the 4 cm is left
    assert abs(on_bound.e_contouring[2]) > 0.02
    # about the nominal both sides correct at once, and the steps stay about 0.16 m beside the COM
    assert abs(about.e_contouring[2]) < 0.01
    psi = about.states[:-1, 4] + about.inputs[:, 2]
    lat = -np.sin(psi) * about.inputs[:, 0] + np.cos(psi) * about.inputs[:, 1]
    sides = side * np.array([1, -1, 1, -1, 1])
    assert np.all(np.abs(sides * lat - 0.16) < 0.05)


def test_lateral_nominal_zero_keeps_paper_a_cost_and_bad_values_are_refused() -> None:
    a, b = _plan(_params(0.10, 0.0), 0.04, 1), _plan(MpccParams.overtake_cartesian(
        model=_MODEL, rectangle=_params(0.10, 0.0).rectangle, heading_weight=20.0, jit=False), 0.04, 1)
    np.testing.assert_array_equal(a.inputs, b.inputs)
    for bad in (-0.01, float("nan")):
        with pytest.raises(ParameterError, match="lateral_nominal"):
            MpccParams(lateral_nominal=bad)
