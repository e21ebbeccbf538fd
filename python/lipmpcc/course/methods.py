"""Planners assembled from a student's functions, so that an exercise's closed loop runs on the student's code.

:class:`StudentMpccPlanner` is paper A's MPCC whose contouring and lag cost terms and/or obstacle CBF rows are the
student's (CasADi functions, see the class); the LIP loop then follows the circle (notebook 03) or overtakes
(notebook 04) on them.

:class:`StudentStonePlanner` is a one-step stepping-stone planner (the ALIP-QP's problem, paper B's baseline)
whose three modelling pieces are the student's:

- ``step_map(z_prev, sigma, u)``: the initial DCM of the next step [m] (2,), paper B eq. (8);
- ``sigma_bounds(lam, T_lo, T_hi)``: the bounds of σ = e^{λT} for durations in [T_lo, T_hi] [s];
- ``stone_box(u_nom, size, kin_lo, kin_hi)``: the box (lo, hi) [m] of footholds u relative to the stance
  foot that land on the stone of centre ``u_nom`` and ``size`` (x, y) and respect the kinematic box.

At each call it measures z⁰ = (ξ − p) e^{−λt} (eq. 10), takes eq. (5)'s initial DCM of the following step
as the target z_des, and for σ on a grid over the student's bounds chooses the foothold in the student's
box that brings the student's ``step_map(z⁰, σ, u)`` closest to z_des (weighted as the ALIP-QP: z 1000,
u 10, σ 1; the map is read as affine in u, its offset and slope evaluated from the student's function).
The loop (:func:`lipmpcc.loops.alip.run_alip_loop`) then walks the ALIP on that plan: a wrong sign in the
map, the bounds or the box shows as missed stones or a fall.
"""

from __future__ import annotations

import math
import time
from typing import Callable

import casadi as ca
import numpy as np

from ..exceptions import InvalidInputError, ParameterError
from ..models.alip import nominal_initial_dcm, parse_side
from ..planners.alip_common import (AlipPlanner, AlipPlanResult, check_time_since_touchdown, check_xy, pad_stones,
                                    stone_arrays)
from ..planners import mpcc as mpcc_module
from ..planners.alip_qp import AlipQpParams
from ..planners.mpcc import MpccParams, MpccPlanner
from ..paths import Path

__all__ = ["StudentStonePlanner", "STUDENT_WEIGHTS", "StudentMpccPlanner", "student_terms", "student_row", "CONTOURING_LIBRARY"]

#: the weights of the one-step problem on (z − z_des, u − u_nom, σ − σ_nom), as the ALIP-QP's (Khadiv's)
STUDENT_WEIGHTS = (1000.0, 10.0, 1.0)


class StudentStonePlanner(AlipPlanner):
    """A one-step stepping-stone planner from the student's ``step_map``, ``sigma_bounds`` and ``stone_box``
    (see the module doc), with paper B's limits and durations (``params``: an
    :class:`~lipmpcc.planners.alip_qp.AlipQpParams`); ``n_sigma`` grid values of σ [-]."""

    name = "student"
    horizon = 1
    stones_needed = 2

    def __init__(self, step_map: Callable, sigma_bounds: Callable, stone_box: Callable,
                 params: AlipQpParams | None = None, n_sigma: int = 41) -> None:
        p = AlipQpParams.paper() if params is None else params
        if not isinstance(p, AlipQpParams):
            raise ParameterError("params", params, "an AlipQpParams")
        if not all(callable(f) for f in (step_map, sigma_bounds, stone_box)):
            raise InvalidInputError("step_map, sigma_bounds, stone_box", (step_map, sigma_bounds, stone_box),
                                    "three functions")
        self.params, self.n_sigma = p, int(n_sigma)
        self.step_map, self.sigma_bounds, self.stone_box = step_map, sigma_bounds, stone_box
        self.solves = 0

    def reset(self) -> None:
        """Nothing is carried from one run to the next but the count of solves."""
        self.solves = 0

    def _target(self, st: np.ndarray, swing: int, c: np.ndarray) -> np.ndarray:
        """z_des: eq. (5)'s initial DCM of the following step (its swing foot ``-swing``), from the step
        stone 1 → stone 2, as the ALIP-QP's ``dcm_target="next"``."""
        prm = self.params
        u_tgt = c[1] - c[0]
        return nominal_initial_dcm(u_tgt[0], u_tgt[1] + swing * prm.w, prm.T_nom, -swing, prm.lam, prm.w)

    def _best(self, z0: np.ndarray, z_des: np.ndarray, u_nom: np.ndarray, lo: np.ndarray, hi: np.ndarray,
              sigmas: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, float]:
        """(σ, u, z, cost) of the grid's best plan: per σ the foothold in [lo, hi] closest, in the weighted
        sense, to bringing the student's map to z_des."""
        wz, wu, ws = STUDENT_WEIGHTS
        sig_nom = math.exp(self.params.lam * self.params.T_nom)
        best = (float("nan"), u_nom, z_des, float("inf"))
        for s in sigmas:
            off = np.asarray(self.step_map(z0, s, np.zeros(2)), dtype=float).reshape(2)
            slope = np.array([np.asarray(self.step_map(z0, s, e), dtype=float).reshape(2) - off for e in np.eye(2)]).T
            d = np.diag(slope)  # per axis: z_i = off_i + d_i u_i (a map of the right form is diagonal)
            u = np.clip((wz * d * (z_des - off) + wu * u_nom) / (wz * d * d + wu), lo, hi)
            z = np.asarray(self.step_map(z0, s, u), dtype=float).reshape(2)
            cost = wz * float(np.sum((z - z_des) ** 2)) + wu * float(np.sum((u - u_nom) ** 2)) + ws * (s - sig_nom) ** 2
            if cost < best[3]:
                best = (float(s), u, z, cost)
        return best

    def solve(self, dcm_world, stance_world, stance_side, t_since_touchdown, stones) -> AlipPlanResult:  # noqa: ANN001
        """The next foothold [m] and this step's duration [s] (same arguments and result as
        :meth:`lipmpcc.planners.alip_qp.AlipQp.solve`)."""
        t0 = time.perf_counter()
        prm = self.params
        xi, st = check_xy("dcm_world", dcm_world), check_xy("stance_world", stance_world, InvalidInputError)
        swing = -parse_side(stance_side)
        t = check_time_since_touchdown(t_since_touchdown)
        c, s = stone_arrays(stones, prm.stone_size)
        c, s = pad_stones(c, s, 2, st)
        z0 = (xi - st) * math.exp(-prm.lam * t)
        u_nom = c[0] - st
        lo, hi = (np.asarray(v, dtype=float).reshape(2) for v in self.stone_box(u_nom, s[0], *prm.limits.box(swing)))
        t_lo = max(prm.T_min, t)
        s_lo, s_hi = (float(v) for v in self.sigma_bounds(prm.lam, t_lo, max(prm.T_max, t_lo)))
        if not (np.all(lo <= hi) and 0.0 < s_lo <= s_hi and math.isfinite(s_hi)):
            raise InvalidInputError("the student's bounds", (lo.tolist(), hi.tolist(), s_lo, s_hi),
                                    "lo <= hi for the box and 0 < sigma_lo <= sigma_hi")
        sigma, u, z, cost = self._best(z0, self._target(st, swing, c), u_nom, lo, hi,
                                       np.linspace(s_lo, s_hi, self.n_sigma))
        self.solves += 1
        T = math.log(sigma) / prm.lam
        f = (st + u).reshape(1, 2)
        dt = time.perf_counter() - t0
        return AlipPlanResult(next_foothold=f[0].copy(), step_duration=T, time_to_touchdown=T - t, footholds=f,
                              durations=np.array([T]), u=u.reshape(1, 2), z=z.reshape(1, 2), sigma=np.array([sigma]),
                              z0=z0, success=True, fallback=False, status="grid", cost=cost, iterations=self.n_sigma,
                              solve_time=dt, plan_time=dt, solver="grid")


# ---- paper A: the MPCC's contouring and lag cost terms, the student's -----------------------------------------
#: the library names a student's ``contouring_lag_cost`` must not call (the exercise asks to write them)
CONTOURING_LIBRARY = ("lipmpcc.contouring.casadi_errors", "lipmpcc.contouring.casadi_projection",
                      "lipmpcc.contouring.projection", "lipmpcc.contouring.weighted_error",
                      "lipmpcc.contouring.weight_matrix")


def student_terms(contouring_lag_cost: Callable, position: ca.SX | ca.MX, path_point: ca.SX | ca.MX,
                  phi: ca.SX | ca.MX, q_bar: tuple[float, float]) -> tuple[ca.SX | ca.MX, ca.SX | ca.MX, ca.SX | ca.MX]:
    """The student's ``contouring_lag_cost(position, path_point, phi, q_bar)`` as three CasADi scalars
    (cost [m²·weight], ē_c [m], ē_l [m]); any other result is an :class:`InvalidInputError`."""
    try:
        cost, e_c, e_l = contouring_lag_cost(position, path_point, phi, q_bar)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError("contouring_lag_cost(...)", type(exc).__name__,
                                f"three CasADi expressions (cost, e_c, e_l) ({exc})") from None
    out = (cost, e_c, e_l)
    if not all(isinstance(v, (ca.SX, ca.MX)) and v.numel() == 1 for v in out):
        raise InvalidInputError("contouring_lag_cost(...)", tuple(type(v).__name__ for v in out),
                                "three scalar CasADi expressions (cost, e_c, e_l)")
    return out


def _student_problem(library_problem: Callable, contouring_lag_cost: Callable | None,
                     cbf_row: Callable | None = None) -> Callable:
    """:func:`lipmpcc.planners.mpcc.build_problem` with the student's pieces in place of the library's.

    ``contouring_lag_cost``: the library's problem with zero contouring/lag weights (its constraints, its input,
    progress and heading terms) plus, per stage k, the student's cost of the COM against y_d(ϑ_k), φ_d(ϑ_k)
    with Q̄ (k < N) or W̄ (k = N). ``cbf_row``: the library's problem without obstacles plus, per stage k and
    obstacle j, the student's CBF row (17) ``cbf_row(p_k, p_{k+1}, ob_k, ob_{k+1}, γ) ≥ 0`` on the COM disk
    and, with ``foot_clearance``, the foothold rows b(foot) ≥ 0 as the student's row with γ = 1 (the
    obstacle's parameters ``ob = [c_x, c_y, M_11, M_12, M_22]`` from the parameter vector, see
    :func:`~lipmpcc.planners.mpcc.build_problem`)."""

    def build(path, prm, xs, us, p, *args, **kw):  # noqa: ANN001, ANN202 - build_problem's own signature
        lib_prm = prm if contouring_lag_cost is None else prm.with_(Q_bar=(0.0, 0.0), W_bar=(0.0, 0.0))
        lib_p = p if cbf_row is None else p[0:1]
        cost, g, lo, hi = library_problem(path, lib_prm, xs, us, lib_p, *args, **kw)
        if contouring_lag_cost is not None:
            for k, xk in enumerate(xs):
                yd, d = path.casadi_derivs(xk[5])
                q_bar = tuple(float(q) for q in (prm.W_bar if k == len(xs) - 1 else prm.Q_bar))
                cost = cost + student_terms(contouring_lag_cost, ca.vertcat(xk[0], xk[2]), yd, ca.atan2(d[1], d[0]),
                                            q_bar)[0]
        if cbf_row is not None:
            g, lo, hi = list(g), list(lo), list(hi)
            for row in _student_cbf_rows(cbf_row, prm, xs, us, p):
                g.append(row)
                lo.append(0.0)
                hi.append(ca.inf)
        return cost, g, lo, hi

    return build


def _student_cbf_rows(cbf_row: Callable, prm: MpccParams, xs: list, us: list, p: ca.SX | ca.MX) -> list:
    """The obstacle rows of the MPCC (each ≥ 0) from the student's ``cbf_row``: per stage and obstacle, (17) on
    the COM, then (with ``foot_clearance``) the new foothold outside the obstacle during its stance."""
    N, nb = prm.N, mpcc_module.NB
    nob = (p.shape[0] - 1) // ((N + 1) * nb)

    def ob(j: int, k: int, foot: bool = False) -> ca.SX | ca.MX:
        o = 1 + (j * (N + 1) + k) * nb
        return ca.vertcat(p[o], p[o + 1], *(p[o + i] for i in ((5, 6, 7) if foot else (2, 3, 4))))

    rows = []
    for k in range(N):
        pk, pn = ca.vertcat(xs[k][0], xs[k][2]), ca.vertcat(xs[k + 1][0], xs[k + 1][2])
        for j in range(nob):
            rows.append(student_row(cbf_row, pk, pn, ob(j, k), ob(j, k + 1), prm.gamma))
        if prm.foot_clearance:
            foot = ca.vertcat(xs[k][0] + us[k][0], xs[k][2] + us[k][1])
            rows += [student_row(cbf_row, foot, foot, ob(j, kk, True), ob(j, kk, True), 1.0)
                     for j in range(nob) for kk in (k, k + 1)]
    return rows


def student_row(cbf_row: Callable, p_now: ca.SX | ca.MX, p_next: ca.SX | ca.MX, ob_now: ca.SX | ca.MX,
                ob_next: ca.SX | ca.MX, gamma: float) -> ca.SX | ca.MX:
    """The student's ``cbf_row(p_now, p_next, ob_now, ob_next, gamma)`` as one CasADi scalar (the row, ≥ 0
    when the CBF (17) holds); any other result is an :class:`InvalidInputError`."""
    row = cbf_row(p_now, p_next, ob_now, ob_next, gamma)
    if not (isinstance(row, (ca.SX, ca.MX)) and row.numel() == 1):
        raise InvalidInputError("cbf_row(...)", type(row).__name__, "one scalar CasADi expression (the row, >= 0)")
    return row


class StudentMpccPlanner(MpccPlanner):
    """Paper A's MPCC (:class:`~lipmpcc.planners.mpcc.MpccPlanner`: the same solvers, constraints, warm start,
    fallback and liveness) whose contouring and lag cost is the student's
    ``contouring_lag_cost(position, path_point, phi, q_bar) -> (cost, e_c, e_l)``: CasADi expressions of
    the COM ``position`` (a 2-vector [m]), the path point y_d(ϑ) (a 2-vector [m]), the path's slope φ_d(ϑ)
    [rad] and the weights ``q_bar = (q̄_c, q̄_l)`` [1/m²] (``None``: the library's); optionally the obstacle rows
    are the student's ``cbf_row(p_now, p_next, ob_now, ob_next, gamma)``: the CBF (17) as one CasADi expression
    that must be ≥ 0, for the COM at two exchanges (2-vectors [m]) and the obstacle at those instants as
    ``ob = [c_x, c_y, M_11, M_12, M_22]`` (its barrier b(p) = (p − c)ᵀM(p − c) − 1, notebook 04).

    The MPCC's cost is the student's cost at every stage (Q̄ for k < N, W̄ at N) plus the library's other
    terms. The solvers are built (once per obstacle count, as the library's) by
    :func:`~lipmpcc.planners.mpcc.build_sqp` / ``build_ipopt`` on :func:`_student_problem`: while
    :meth:`_get` builds, ``lipmpcc.planners.mpcc.build_problem`` is that composition (a hook that lives in
    this module; the planner module is unchanged and its own planners are built as before)."""

    def __init__(self, path: Path, contouring_lag_cost: Callable | None, params: MpccParams | None = None,
                 name: str = "mpcc-student", cbf_row: Callable | None = None) -> None:
        if contouring_lag_cost is not None and not callable(contouring_lag_cost):
            raise InvalidInputError("contouring_lag_cost", contouring_lag_cost,
                                    "a function (position, path_point, phi, q_bar) -> (cost, e_c, e_l)")
        if cbf_row is not None and not callable(cbf_row):
            raise InvalidInputError("cbf_row", cbf_row, "a function (p_now, p_next, ob_now, ob_next, gamma) -> row")
        super().__init__(path, params, name)
        self.contouring_lag_cost, self.cbf_row = contouring_lag_cost, cbf_row

    def _get(self, n_obs: int, solver: str | None = None) -> dict:
        """The solver for ``n_obs`` obstacles, built with the student's cost on first use and cached."""
        key = (n_obs, solver or self.params.solver)
        if key in self._built:
            return self._built[key]
        library = mpcc_module.build_problem
        mpcc_module.build_problem = _student_problem(library, self.contouring_lag_cost, self.cbf_row)
        try:
            return super()._get(n_obs, solver)
        finally:
            mpcc_module.build_problem = library

    def _solve_detour(self, x0, stance_side, obstacles, t_now, theta_init, shift, s=0.0):  # noqa: ANN001, ANN202
        """The detour mode's solves and the return's (liveness) on the student's cost too."""
        if s not in self._detour_planners:
            self._detour_planners[s] = StudentMpccPlanner(self.path, self.contouring_lag_cost,
                                                          self.params.with_(**self._detour_fields(s)),
                                                          name=f"{self.name}-detour" if s == 0.0 else f"{self.name}-return",
                                                          cbf_row=self.cbf_row)
        return super()._solve_detour(x0, stance_side, obstacles, t_now, theta_init, shift, s)
