"""lipmpcc.solvers.convexify: the modified Cholesky factorisation keeps a Hessian that is positive definite
enough, makes any other one positive definite with a bounded factor, and the SQP's two backends agree on it."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.solvers import convexify
from lipmpcc.solvers.convexify import (PARTIAL_EIGEN_ENV, eigen_clip, modified_cholesky, requested_convexification,
                                      requested_partial_eigen)


def _sym(rng: np.random.Generator, eigs: np.ndarray) -> np.ndarray:
    Q, _ = np.linalg.qr(rng.standard_normal((eigs.size, eigs.size)))
    return (Q * eigs) @ Q.T


@pytest.mark.parametrize("seed", range(5))
def test_positive_definite_enough_is_unchanged(seed):
    """λ_min(H) ≥ floor: E = 0 and RᵀR = H (as the eigenvalue clip leaves H), for scales from 1 to 1e6."""
    rng = np.random.default_rng(seed)
    n = 20
    H = _sym(rng, np.geomspace(1.0, 10.0 ** rng.uniform(1, 6), n))  # smallest eigenvalue exactly the floor
    R, e = modified_cholesky(H, 1.0)
    assert np.all(e == 0.0)
    assert np.allclose(R.T @ R, H, rtol=0, atol=1e-9 * np.abs(H).max())
    assert np.allclose(eigen_clip(H, 1.0), H, rtol=0, atol=1e-9 * np.abs(H).max())
    assert np.array_equal(R, np.triu(R))


@pytest.mark.parametrize("seed", range(5))
def test_indefinite_becomes_positive_definite(seed):
    """An indefinite H (eigenvalues from −1e6 to 1e6, as the MPCC's): H + diag(e) = RᵀR with e ≥ 0 diagonal, every
    pivot at least the floor, the factor bounded (|l_ij|·√d_j ≤ β), and only the lower triangle read."""
    rng = np.random.default_rng(10 + seed)
    n = 20
    H = _sym(rng, rng.choice([-1, 1], n) * 10.0 ** rng.uniform(-1, 6, n))
    assert np.linalg.eigvalsh(H)[0] < 0
    upper_garbage = H + np.triu(rng.standard_normal((n, n)), 1)
    R, e = modified_cholesky(upper_garbage, 1.0)
    assert np.all(e >= 0) and np.any(e > 0)
    assert np.allclose(R.T @ R, H + np.diag(e), rtol=0, atol=1e-9 * (np.abs(H).max() + e.max()))
    assert np.all(np.diag(R) >= 1.0)
    off = np.abs(H - np.diag(np.diag(H))).max()
    beta = np.sqrt(max(np.abs(np.diag(H)).max(), off / np.sqrt(n * n - 1)))
    assert np.abs(np.triu(R, 1)).max() <= beta * (1 + 1e-12)
    assert np.linalg.eigvalsh(R.T @ R)[0] > 0


def test_requested_convexification(monkeypatch):
    monkeypatch.delenv(convexify.CONVEXIFICATION_ENV, raising=False)
    assert requested_convexification(None) == "eigen_clip"
    monkeypatch.setenv(convexify.CONVEXIFICATION_ENV, "Modified_Cholesky")
    assert requested_convexification(None) == "modified_cholesky"
    assert requested_convexification("eigen_clip") == "eigen_clip"  # explicit beats the environment
    monkeypatch.setenv(convexify.CONVEXIFICATION_ENV, "ldl")
    with pytest.raises(InvalidInputError, match=convexify.CONVEXIFICATION_ENV):
        requested_convexification(None)
    with pytest.raises(InvalidInputError, match="convexification"):
        requested_convexification("cholesky")


def test_the_partial_eigen_clip_is_opt_in(monkeypatch) -> None:
    """The C++ SQP's partial eigenvalue clip moves chaotic closed loops by its rounding (Digit v3's Cartesian MPC
    overtook the 0.1 m/s obstacle with it): off unless ``$LIPMPCC_SQP_PARTIAL_EIGEN`` is 1 or it is asked for."""
    from lipmpcc.exceptions import InvalidInputError

    monkeypatch.delenv(PARTIAL_EIGEN_ENV, raising=False)
    assert requested_partial_eigen(None) is False
    monkeypatch.setenv(PARTIAL_EIGEN_ENV, "1")
    assert requested_partial_eigen(None) is True and requested_partial_eigen(False) is False
    monkeypatch.setenv(PARTIAL_EIGEN_ENV, "yes")
    with pytest.raises(InvalidInputError, match="LIPMPCC_SQP_PARTIAL_EIGEN"):
        requested_partial_eigen(None)
