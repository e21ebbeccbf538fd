"""lipmpcc.contouring: P(φ), errors, weights; Q̄ = αI is the Cartesian MPC."""

import math

import casadi as ca
import numpy as np
import pytest

from lipmpcc import contouring as C
from lipmpcc.exceptions import ParameterError


@pytest.mark.parametrize("phi", np.linspace(-math.pi, math.pi, 13))
def test_projection_is_orthogonal_and_symmetric(phi):
    P = C.projection(phi)
    assert np.allclose(P @ P.T, np.eye(2))
    assert np.allclose(P, P.T)


@pytest.mark.parametrize("phi", np.linspace(-math.pi, math.pi, 25))
@pytest.mark.parametrize("alpha", [1.0, 200.0])
def test_equal_weights_give_cartesian_weights_for_every_phi(phi, alpha):
    assert np.allclose(C.weight_matrix((alpha, alpha), phi), alpha * np.eye(2), atol=1e-12)


def test_contouring_and_lag_signs():
    # path along +x: a robot to the right (y < 0) has positive contouring error,
    # a robot behind (x < x_d) has positive lag error
    assert np.allclose(C.errors([0.0, -0.1], [0.0, 0.0], 0.0), [0.1, 0.0])
    assert np.allclose(C.errors([-0.2, 0.0], [0.0, 0.0], 0.0), [0.0, 0.2])
    # rotated path: same geometry
    phi = 0.7
    t = np.array([math.cos(phi), math.sin(phi)])
    n_right = np.array([t[1], -t[0]])
    e = C.errors(0.3 * n_right - 0.1 * t, [0.0, 0.0], phi)
    assert np.allclose(e, [0.3, 0.1])


def test_weighted_error_matches_quadratic_form():
    rng = np.random.default_rng(1)
    for _ in range(20):
        p, r, phi = rng.normal(size=2), rng.normal(size=2), rng.uniform(-3, 3)
        eb = C.errors(p, r, phi)
        w = (300.0, 3.0)
        assert C.weighted_error(p, r, phi, w) == pytest.approx(w[0] * eb[0] ** 2 + w[1] * eb[1] ** 2)


def test_vectorised_and_casadi_agree():
    rng = np.random.default_rng(2)
    p, r, phi = rng.normal(size=(6, 2)), rng.normal(size=(6, 2)), rng.uniform(-3, 3, 6)
    e = C.errors(p, r, phi)
    for i in range(6):
        ec = np.asarray(ca.evalf(C.casadi_errors(ca.DM(p[i]), ca.DM(r[i]), phi[i]))).ravel()
        assert np.allclose(ec, e[i])
        assert np.allclose(np.asarray(ca.evalf(C.casadi_projection(phi[i]))), C.projection(phi[i]))


def test_bad_weights():
    with pytest.raises(ParameterError, match="non-negative"):
        C.weight_matrix((-1.0, 2.0), 0.0)
    with pytest.raises(ParameterError, match="diagonal"):
        C.weight_matrix([[1.0, 0.5], [0.5, 1.0]], 0.0)
    with pytest.raises(ParameterError, match="shape"):
        C.errors([0, 0, 0], [0, 0], 0.0)


# ---- issue 14: one validation layer -------------------------------------------------------------
@pytest.mark.parametrize(
    "args, match",
    [
        (([math.nan, 0.0], [0.0, 0.0], 0.0), r"position = .*NaN or inf"),
        (([0.0, 0.0], [math.inf, 0.0], 0.0), r"reference = .*NaN or inf"),
        (([0.0, 0.0], [0.0, 0.0], math.nan), r"phi = .*NaN or inf"),
        ((np.zeros((3, 2)), np.zeros((3, 2)), np.zeros(2)), r"phi = \(2,\): expected a scalar or one slope per position"),
        (("ab", [0.0, 0.0], 0.0), r"position = 'ab'"),
        (([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0), r"same \(…, 2\) shape"),
    ],
)
def test_bad_errors_arguments_are_named(args, match):
    with pytest.raises(ParameterError, match=match):
        C.errors(*args)


def test_errors_of_finite_input_are_unchanged():
    e = C.errors(np.array([[1.0, 2.0], [0.5, -1.0]]), np.zeros((2, 2)), np.array([0.3, -0.2]))
    assert e.shape == (2, 2) and np.all(np.isfinite(e))
    assert C.errors([1.0, 2.0], [0.0, 0.0], np.float64(0.0)).tolist() == [-2.0, -1.0]


def test_weighted_error_refuses_nan():
    with pytest.raises(ParameterError, match="position"):
        C.weighted_error([math.nan, 0.0], [0.0, 0.0], 0.0, (1.0, 1.0))


def test_projection_and_weights_name_bad_arguments():
    with pytest.raises(ParameterError, match=r"phi = 'x'"):
        C.projection("x")
    with pytest.raises(ParameterError, match=r"weights_bar = 'x'"):
        C.weight_matrix("x", 0.0)
