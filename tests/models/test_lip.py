"""lipmpcc.models.lip: ω, the closed-form LIP flow and the DCM."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lipmpcc.exceptions import InvalidInputError, ParameterError
from lipmpcc.models.lip import GRAVITY, dcm, lip_solution, omega


def test_omega() -> None:
    assert omega(0.9) == math.sqrt(9.81 / 0.9)
    assert omega(1.0, gravity=9.80665) == math.sqrt(9.80665)
    with pytest.raises(ParameterError, match="com_height"):
        omega(0.0)
    with pytest.raises(InvalidInputError, match="com_height"):
        omega(float("nan"))


def test_closed_form_matches_the_ode() -> None:
    w = omega(0.95)
    c0, v0, p = np.array([0.1, -0.05]), np.array([0.4, 0.2]), np.array([0.0, -0.14])
    sol = solve_ivp(lambda t, s: np.r_[s[2:], w**2 * (s[:2] - p)], (0.0, 0.4), np.r_[c0, v0],
                    rtol=1e-11, atol=1e-12, dense_output=True)
    for t in (0.0, 0.13, 0.4):
        c, v, a = lip_solution(c0, v0, p, w, t)
        np.testing.assert_allclose(c, sol.sol(t)[:2], atol=1e-9)
        np.testing.assert_allclose(v, sol.sol(t)[2:], atol=1e-9)
        np.testing.assert_allclose(a, w**2 * (c - p), atol=1e-12)
    cs, vs, _ = lip_solution(c0, v0, p, w, np.array([0.0, 0.2, 0.4]))
    assert cs.shape == (3, 2) and np.allclose(cs[0], c0) and np.allclose(vs[0], v0)


def test_dcm_diverges_at_omega() -> None:
    w = omega(0.9)
    c0, v0, p = np.array([0.05, 0.0]), np.array([0.3, -0.1]), np.zeros(2)
    xi0 = dcm(c0, v0, w)
    c, v, _ = lip_solution(c0, v0, p, w, 0.3)
    np.testing.assert_allclose(dcm(c, v, w) - p, (xi0 - p) * math.exp(w * 0.3), atol=1e-12)
    assert GRAVITY == 9.81


def test_omega_names_a_bad_gravity():
    import pytest

    from lipmpcc.exceptions import ParameterError
    from lipmpcc.models.lip import omega

    with pytest.raises(ParameterError, match=r"gravity = 'x'"):
        omega(0.9, "x")
    with pytest.raises(ParameterError, match=r"gravity = -9.81"):
        omega(0.9, -9.81)


def test_lip_solution_and_dcm_name_bad_arguments():
    import math

    import numpy as np
    import pytest

    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.models.lip import dcm, lip_solution

    with pytest.raises(InvalidInputError, match=r"c0 = 'x'"):
        lip_solution("x", [0, 0], [0, 0], 3.3, 0.1)
    with pytest.raises(InvalidInputError, match=r"t = nan"):
        lip_solution([0, 0], [0, 0], [0, 0], 3.3, math.nan)
    with pytest.raises(InvalidInputError, match=r"omega = None"):
        lip_solution([0, 0], [0, 0], [0, 0], None, 0.1)
    with pytest.raises(InvalidInputError, match=r"com_xy = 'x'"):
        dcm("x", [0, 0], 3.3)
    with pytest.raises(InvalidInputError, match=r"com_xy = nan: expected an array of shape \(n,\)"):
        dcm(math.nan, [0, 0], 3.3)
    with pytest.raises(InvalidInputError, match=r"com_xy/com_vel_xy"):
        dcm([1.0], [0, 0], 3.3)
    assert dcm(np.array([1.0, 2.0, 0.9]), [0.0, 3.3, 0.0], 3.3).tolist() == [1.0, 3.0]
