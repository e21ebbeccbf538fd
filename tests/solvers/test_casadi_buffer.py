"""lipmpcc.solvers.casadi_buffer.BufferedFunction: a buffered CasADi function equals the direct call."""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from lipmpcc.solvers import casadi_buffer
from lipmpcc.solvers.casadi_buffer import BufferedFunction


def _tiny() -> tuple[list[ca.SX], list[ca.SX]]:
    x = ca.SX.sym("x", 3)
    y = ca.SX.sym("y", 2)
    vec = ca.vertcat(x[0] * y[0], ca.sin(x[1]) + y[1], x[2] ** 2)
    mat = ca.horzcat(x[:2], y, x[1:] * y[0])  # 2 x 3: comes back column-major, reshaped
    sparse = ca.diag(x)  # densified
    return [x, y], [vec, mat, sparse]


def test_buffered_evaluation_equals_the_direct_call() -> None:
    inputs, outputs = _tiny()
    f = BufferedFunction("tiny", inputs, outputs)
    direct = ca.Function("direct", inputs, outputs)
    x, y = np.array([0.3, -1.2, 2.0]), np.array([[4.0], [0.5]])  # any shape: raveled
    vec, mat, sparse = f(x, y)
    want = [np.asarray(ca.DM(w)) for w in direct(x, y.ravel())]
    assert vec.shape == (3,) and mat.shape == (2, 3) and sparse.shape == (3, 3)
    np.testing.assert_array_equal(vec, want[0].ravel())
    np.testing.assert_array_equal(mat, want[1])
    np.testing.assert_array_equal(sparse, np.diag(x))
    # the results are views into the buffers: the next call overwrites them
    first = vec.copy()
    again = f(2 * x, y)
    assert again[0] is vec and not np.array_equal(vec, first)


def test_jit_compiled_function_gives_the_same_values(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if not casadi_buffer.jit_available():
        pytest.skip("no C compiler on the PATH")
    monkeypatch.setenv("LIPMPCC_CACHE_DIR", str(tmp_path))
    assert casadi_buffer.cache_dir() == tmp_path
    inputs, outputs = _tiny()
    plain, fast = BufferedFunction("tiny", inputs, outputs), BufferedFunction("tiny", inputs, outputs, jit=True)
    x, y = np.array([0.3, -1.2, 2.0]), np.array([4.0, 0.5])
    for a, b in zip(plain(x, y), fast(x, y)):
        np.testing.assert_allclose(a, b, rtol=1e-15, atol=0.0)
    assert list(tmp_path.glob("lipmpcc_*.so")), "the compiled library is cached on disk"
