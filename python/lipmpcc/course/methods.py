"""Planners assembled from a student's functions, so that an exercise's closed loop runs on the student's code.

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

import numpy as np

from ..exceptions import InvalidInputError, ParameterError
from ..models.alip import nominal_initial_dcm, parse_side
from ..planners.alip_common import (AlipPlanner, AlipPlanResult, check_time_since_touchdown, check_xy, pad_stones,
                                    stone_arrays)
from ..planners.alip_qp import AlipQpParams

__all__ = ["StudentStonePlanner", "STUDENT_WEIGHTS"]

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
