"""lipmpcc.models.lip3d: A, B against an ODE integration; rectangle; python-control view."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lipmpcc.exceptions import ParameterError, StateError
from lipmpcc.models.lip3d import Lip3dModel, ReachabilityRectangle


def _ode_step(model, x, u):
    foot = np.array([x[0] + u[0], x[2] + u[1]])
    w2 = model.g / model.H

    def f(t, s):
        return [s[1], w2 * (s[0] - foot[0]), s[3], w2 * (s[2] - foot[1])]

    sol = solve_ivp(f, (0, model.T), x[:4], rtol=1e-12, atol=1e-13, method="DOP853")
    return np.r_[sol.y[:, -1], x[4] + u[2]]


@pytest.mark.parametrize("T, H", [(0.4, 0.9), (0.35, 1.0), (0.5, 0.8)])
def test_step_map_matches_ode(T, H):
    m = Lip3dModel(T=T, H=H)
    rng = np.random.default_rng(0)
    for _ in range(10):
        x = rng.normal(scale=[1, 0.5, 1, 0.5, 1])
        u = rng.normal(scale=[0.2, 0.2, 0.2])
        assert np.allclose(m.step(x, u), _ode_step(m, x, u), atol=1e-9)


def test_continuous_trajectory_matches_step_map_and_ode():
    m = Lip3dModel()
    x = np.array([0.1, 0.4, -0.05, 0.2, 0.3])
    u = np.array([0.12, 0.1, 0.05])
    traj = m.com_trajectory(x, u, np.array([0.0, m.T]))
    assert np.allclose(traj[0], x[:4])
    assert np.allclose(traj[-1], m.step(x, u)[:4], atol=1e-12)


def test_periodic_gait_velocity():
    m = Lip3dModel()
    d = 0.25
    v0 = m.periodic_velocity(d)
    x = np.array([0.0, v0, 0, 0, 0])
    xn = m.step(x, np.array([d / 2, 0, 0]))
    assert xn[0] == pytest.approx(d)
    assert xn[1] == pytest.approx(v0)


def test_control_state_space():
    m = Lip3dModel()
    sys = m.ss()
    assert sys.dt == pytest.approx(m.T)
    poles = np.sort(np.abs(sys.poles()))
    w = m.omega
    # eigenvalues: 1 (x3 incl. heading) and e^{±ωT} ... the block [[1, sh/w],[0, ch]] has 1 and cosh
    assert poles[-1] == pytest.approx(math.cosh(w * m.T))
    assert np.allclose(sys.C, m.C)


def test_rectangle_alternates_sides():
    r = ReachabilityRectangle(forward=(-0.3, 0.4), lateral=(0.05, 0.35), heading=(-0.2, 0.2))
    lb, ub = r.bounds(1)
    assert np.allclose(lb, [-0.3, 0.05, -0.2]) and np.allclose(ub, [0.4, 0.35, 0.2])
    lb, ub = r.bounds(-1)
    assert np.allclose(lb, [-0.3, -0.35, -0.2]) and np.allclose(ub, [0.4, -0.05, 0.2])
    # rotated frame: a left step of 0.2 m when heading +90° points to world -x
    assert r.contains(np.array([-0.2, 0.0, 0.0]), math.pi / 2, side=1)
    assert not r.contains(np.array([0.2, 0.0, 0.0]), math.pi / 2, side=1)


@pytest.mark.parametrize("kw, match", [({"T": 0.0}, "T"), ({"H": -1.0}, "H"), ({"T": float("nan")}, "T")])
def test_bad_model(kw, match):
    with pytest.raises(ParameterError, match=match):
        Lip3dModel(**kw)


def test_bad_rectangle_and_state():
    with pytest.raises(ParameterError, match="min < max"):
        ReachabilityRectangle(forward=(0.3, -0.3))
    with pytest.raises(ParameterError, match="side"):
        ReachabilityRectangle().bounds(0)
    with pytest.raises(StateError, match="5-vector"):
        Lip3dModel().step(np.zeros(4), np.zeros(3))
    with pytest.raises(StateError, match="finite"):
        Lip3dModel().step(np.array([0, np.nan, 0, 0, 0]), np.zeros(3))


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Lip3dModel(T="long"), r"T = 'long': expected a finite number"),
        (lambda: Lip3dModel(H=None), r"H = None"),
        (lambda: ReachabilityRectangle(forward=None), r"forward = None: expected a list of two finite numbers"),
        (lambda: ReachabilityRectangle(lateral="x"), r"lateral = 'x'"),
        (lambda: ReachabilityRectangle(heading=(math.nan, 0.3)), r"heading = .*NaN or inf"),
        (lambda: ReachabilityRectangle(forward=(0.3, -0.3)), r"min < max"),
    ],
)
def test_bad_model_parameters_are_named(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


def test_numpy_numbers_are_parameters():
    assert Lip3dModel(T=np.float32(0.4), H=np.int64(1)).H == 1
    assert ReachabilityRectangle(forward=np.array([-0.3, 0.3])).forward[1] == pytest.approx(0.3)


def test_step_and_trajectory_name_bad_inputs():
    m = Lip3dModel()
    with pytest.raises(StateError, match=r"u = 'x'"):
        m.step(np.zeros(5), "x")
    with pytest.raises(StateError, match=r"x = .*5-vector.*NaN or inf"):
        m.step([0, 0, math.nan, 0, 0], np.zeros(3))
    with pytest.raises(StateError, match=r"u = \[0.0, 0.0\]"):
        m.com_trajectory(np.zeros(5), [0.0, 0.0], [0.1])
    with pytest.raises(StateError, match=r"t = 'x'"):
        m.com_trajectory(np.zeros(5), np.zeros(3), "x")
