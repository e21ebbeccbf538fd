"""ALIP model: exact flow vs ODE integration, DCM, step-to-step map, nominal gait,
viability bounds (paper B's Proposition), frames, bad inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lipmpcc.exceptions import InvalidInputError, ParameterError, StateError
from lipmpcc.models.alip import (
    LEFT,
    RIGHT,
    AlipParams,
    KinematicLimits,
    alip_flow,
    alip_from_com,
    alip_rhs,
    com_velocity_from_alip,
    contact_to_world,
    dcm_from_alip,
    dcm_from_com,
    duration_from_sigma,
    nominal_initial_dcm,
    parse_side,
    sigma_from_duration,
    signed_width,
    step_to_step,
    viability_bounds,
    world_to_contact,
)

P = AlipParams()
LAM = P.lam


@pytest.mark.parametrize("force", [(0.0, 0.0), (120.0, -60.0)])
def test_flow_matches_ode_integration(force):
    s0 = alip_from_com([0.05, -0.08], [0.4, 0.15], P)
    T = 0.47
    sol = solve_ivp(lambda t, s: alip_rhs(s, P, force), (0, T), s0, rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(alip_flow(s0, T, P, force), sol.y[:, -1], rtol=1e-8, atol=1e-8)


def test_dcm_grows_exponentially_without_force():
    s0 = alip_from_com([0.02, 0.1], [0.3, -0.2], P)
    xi0 = dcm_from_alip(s0, P)
    for t in (0.1, 0.35, 0.6):
        np.testing.assert_allclose(dcm_from_alip(alip_flow(s0, t, P), P), xi0 * math.exp(P.lam * t), atol=1e-12)
    # the LIP form c + c'/lambda gives the same DCM
    np.testing.assert_allclose(dcm_from_com([0.02, 0.1], [0.3, -0.2], P.lam), xi0, atol=1e-14)
    np.testing.assert_allclose(com_velocity_from_alip(s0, P), [0.3, -0.2], atol=1e-14)


def test_step_to_step_map_matches_integration_and_reset():
    """z^k = sigma z^{k-1} - u: integrate a step, move the contact point, compare."""
    s0 = alip_from_com([-0.03, 0.12], [0.5, -0.1], P)
    z0 = dcm_from_alip(s0, P)
    T, u = 0.42, np.array([0.35, -0.3])
    sT = alip_flow(s0, T, P)
    sT[0:2] -= u  # the new contact frame
    np.testing.assert_allclose(dcm_from_alip(sT, P), step_to_step(z0, sigma_from_duration(T, P.lam), u), atol=1e-12)


@pytest.mark.parametrize("L,W,T", [(0.4, 0.0, 0.5), (0.3, 0.15, 0.4), (0.2, -0.1, 0.62)])
def test_nominal_initial_dcm_is_periodic(L, W, T):
    """Eq. (5): two steps (left then right) bring the initial DCM back to itself."""
    w = 0.28
    sig = sigma_from_duration(T, P.lam)
    z_left = nominal_initial_dcm(L, W, T, LEFT, P.lam, w)  # step whose swing foot is left
    z_right = step_to_step(z_left, sig, [L, signed_width(LEFT, w) + W])
    np.testing.assert_allclose(z_right, nominal_initial_dcm(L, W, T, RIGHT, P.lam, w), atol=1e-12)
    z_back = step_to_step(z_right, sig, [L, signed_width(RIGHT, w) + W])
    np.testing.assert_allclose(z_back, z_left, atol=1e-12)


def _can_stay(z, lo, hi, sigmas, steps_u, mirror=False):
    """Is there (sigma, u) on the grid mapping z into [lo, hi] (or its mirror)?"""
    tlo, thi = (-hi, -lo) if mirror else (lo, hi)
    for s in sigmas:
        for u in steps_u:
            n = s * z - u
            if tlo - 1e-12 <= n <= thi + 1e-12:
                return True
    return False


def test_sagittal_bounds_are_invariant_and_maximal():
    """Paper B Proposition: [L_min, L_max]/(e^{lam T_min} - 1) is invariant; beyond it
    every admissible step lets the DCM diverge."""
    lim = KinematicLimits()
    b = viability_bounds(P.lam, 0.35, lim)
    sigmas = np.exp(P.lam * np.linspace(0.35, 0.65, 31))
    us = np.linspace(-lim.x_max, lim.x_max, 121)
    for z in np.linspace(b.x[0], b.x[1], 41):
        assert _can_stay(z, *b.x, sigmas, us)
    for z in (b.x[1] + 1e-3, b.x[0] - 1e-3):
        nxt = [s * z - u for s in sigmas for u in us]
        # every successor is further out than z itself: divergence
        assert min(abs(n) for n in nxt) > abs(z)


def test_lateral_bounds_are_invariant_over_two_steps():
    lim = KinematicLimits()
    b = viability_bounds(P.lam, 0.35, lim)
    sigmas = np.exp(P.lam * np.linspace(0.35, 0.65, 31))
    u_left = np.linspace(lim.y_min, lim.y_max, 81)
    lo, hi = b.y_left
    assert b.y_right == (-hi, -lo)
    assert lo < 0.0 < hi
    for z in np.linspace(lo, hi, 41):
        assert _can_stay(z, lo, hi, sigmas, u_left, mirror=True)
    # just outside: no admissible step lands in the mirrored interval
    assert not _can_stay(lo - 2e-3, lo, hi, sigmas, u_left, mirror=True)
    assert not _can_stay(hi + 2e-3, lo, hi, sigmas, u_left, mirror=True)
    assert b.contains([0.0, 0.05], LEFT) and not b.contains([0.0, 0.05], RIGHT)
    assert b.margin([0.0, hi + 0.01], LEFT) == pytest.approx(-0.01)


@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.1])
def test_world_contact_round_trip(yaw):
    stance = np.array([1.2, -0.3])
    pts = np.array([[1.5, 0.2], [0.0, 0.0], [2.0, -1.0]])
    c = world_to_contact(pts, stance, yaw)
    np.testing.assert_allclose(contact_to_world(c, stance, yaw), pts, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(c, axis=1), np.linalg.norm(pts - stance, axis=1), atol=1e-12)
    if yaw == 0.0:
        np.testing.assert_allclose(c, pts - stance)


def test_sides_widths_and_sigma():
    assert parse_side("left") == LEFT == parse_side(1) == parse_side("L")
    assert parse_side("Right") == RIGHT == parse_side(-1)
    assert signed_width("left", 0.28) == 0.28 and signed_width(RIGHT, 0.28) == -0.28
    assert duration_from_sigma(sigma_from_duration(0.5, P.lam), P.lam) == pytest.approx(0.5)
    lo, hi = KinematicLimits().box("right")
    np.testing.assert_allclose(lo, [-0.6, -0.5])
    np.testing.assert_allclose(hi, [0.6, -0.1])
    assert KinematicLimits().contains([0.3, 0.2], LEFT) and not KinematicLimits().contains([0.3, 0.05], LEFT)


@pytest.mark.parametrize(
    "call, err, word",
    [
        (lambda: parse_side("up"), InvalidInputError, "side"),
        (lambda: parse_side(True), InvalidInputError, "side"),
        (lambda: parse_side(0), InvalidInputError, "side"),
        (lambda: AlipParams(mass=-1.0), ParameterError, "mass"),
        (lambda: AlipParams(z_c=float("nan")), ParameterError, "z_c"),
        (lambda: KinematicLimits(y_min=0.6, y_max=0.5), ParameterError, "y_min"),
        (lambda: KinematicLimits(x_max=0.0), ParameterError, "x_max"),
        (lambda: alip_flow([0, 0, float("nan"), 0], 0.1, P), StateError, "state"),
        (lambda: alip_flow([0, 0, 0], 0.1, P), StateError, "state"),
        (lambda: alip_flow([0, 0, 0, 0], -0.1, P), InvalidInputError, "t"),
        (lambda: alip_rhs([0, 0, 0, 0], P, force=(1.0,)), InvalidInputError, "force"),
        (lambda: sigma_from_duration(-0.2, P.lam), ParameterError, "T"),
        (lambda: duration_from_sigma(0.5, P.lam), ParameterError, "sigma"),
        (lambda: step_to_step([0.1, 0.0], 0.5, [0.2, 0.1]), InvalidInputError, "sigma"),
        (lambda: step_to_step([0.1, "a"], 2.0, [0.2, 0.1]), StateError, "z_prev"),
        (lambda: nominal_initial_dcm(0.4, 0.0, 0.0, LEFT, P.lam, 0.28), ParameterError, "T"),
        (lambda: viability_bounds(P.lam, -0.35), ParameterError, "T_min"),
        (lambda: world_to_contact([[1.0, 2.0, 3.0]], [0, 0]), InvalidInputError, "p_world"),
        (lambda: contact_to_world([1.0, 2.0], [0, 0], yaw=float("inf")), InvalidInputError, "yaw"),
        (lambda: dcm_from_com([0, 0], [0, 0], 0.0), ParameterError, "lam"),
    ],
)
def test_bad_inputs_are_named(call, err, word):
    with pytest.raises(err) as e:
        call()
    assert word in str(e.value)


def test_least_viable_forward_dcm_on_stones():
    from lipmpcc.models.alip import min_forward_dcm_on_stones

    sig = math.exp(LAM * 0.65)
    # one stone: the step onto its near edge at the longest duration lands the DCM exactly on it
    assert min_forward_dcm_on_stones(0.0, [0.3], LAM, 0.65) == pytest.approx(0.3 / sig)
    # many evenly spaced stones: tends to the periodic gait's L / (sigma - 1)
    edges = 0.3 + 0.4 * np.arange(60)
    z = min_forward_dcm_on_stones(0.0, edges, LAM, 0.65)
    assert z == pytest.approx((0.3 + 0.4 / (sig - 1.0)) / sig, rel=1e-9)
    # from that DCM the best-case sequence ends exactly on the last stone with z = 0; a bit less
    # falls short (8 stones: sigma^8 ~ 3e7 keeps the forward round-off small)
    few = edges[:8]
    z8 = min_forward_dcm_on_stones(0.0, few, LAM, 0.65)
    for z0, ok in ((z8 * (1 + 1e-9), True), (0.99 * z8, False)):
        zk, x = z0, 0.0
        for e in few:
            zk = sig * zk - (e - x)
            x = e
            if not ok:
                continue
            assert zk >= 0.0
        assert (zk >= 0.0) == ok
    for bad, word in (([], "near_edges"), ([0.3, 0.2], "near_edges"), ([float("nan")], "near_edges")):
        with pytest.raises(InvalidInputError, match=word):
            min_forward_dcm_on_stones(0.0, bad, LAM, 0.65)
    with pytest.raises(InvalidInputError, match="stance_x"):
        min_forward_dcm_on_stones(float("inf"), [0.3], LAM, 0.65)


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
@pytest.mark.parametrize("field, value", [("z_c", None), ("z_c", "tall"), ("mass", math.nan), ("g", True)])
def test_bad_alip_params_are_named(field, value):
    from lipmpcc.models.alip import AlipParams

    with pytest.raises(ParameterError, match=rf"{field} = "):
        AlipParams(**{field: value})


@pytest.mark.parametrize("field, value", [("x_max", None), ("y_min", "x"), ("y_max", math.inf)])
def test_bad_kinematic_limits_are_named(field, value):
    from lipmpcc.models.alip import KinematicLimits

    with pytest.raises(ParameterError, match=rf"{field} = "):
        KinematicLimits(**{field: value})


def test_model_functions_name_bad_arguments():
    from lipmpcc.models import alip as A

    P = A.AlipParams()
    cases = (
        (lambda: A.sigma_from_duration("x", 3.0), ParameterError, r"T = 'x'"),
        (lambda: A.duration_from_sigma(None, 3.0), ParameterError, r"sigma = None"),
        (lambda: A.step_to_step([0, 0], "x", [0, 0]), InvalidInputError, r"sigma = 'x'"),
        (lambda: A.nominal_initial_dcm("x", 0.0, 0.5, "left", 3.3, 0.28), ParameterError, r"L = 'x'"),
        (lambda: A.world_to_contact([0, 0], [0, 0], "x"), InvalidInputError, r"yaw = 'x'"),
        (lambda: A.contact_to_world([0, 0], [0, 0], None), InvalidInputError, r"yaw = None"),
        (lambda: A.signed_width("left", "x"), ParameterError, r"w = 'x'"),
        (lambda: A.alip_flow([0, 0, 0, 0], "x", P), InvalidInputError, r"t = 'x'"),
        (lambda: A.alip_flow([0, 0, 0, 0], 0.1, "params"), InvalidInputError, r"params = 'params'"),
        (lambda: A.alip_rhs([0, 0, 0, 0], None), InvalidInputError, r"params = None"),
    )
    for call, err, match in cases:
        with pytest.raises(err, match=match):
            call()
