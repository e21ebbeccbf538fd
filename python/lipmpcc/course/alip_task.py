"""Paper B's ALIP-MPC whose dynamics rows come from a student's touch-down DCM prediction (notebook 06).

The ALIP-MPC (:mod:`lipmpcc.planners.alip_mpc`) is built on one prediction: where the DCM will be, relative to the
stance contact point, when the swing foot touches down. The student writes it::

    xi_td = touchdown_dcm(xi_now, t, sigma, d, lam)

with ``xi_now`` the DCM now relative to the stance contact point (2,) [m], ``t`` the time since touch-down [s],
``sigma`` = e^{λT} of this step [-] (T its duration [s]), ``d`` the centre-of-pressure offset from the contact point
held for the rest of the step (2,) [m] and ``lam`` = λ [1/s]; the result is the DCM at the end of the step (2,) [m]
(the right answer: ``d + sigma e^{-lam t} (xi_now - d)``). The function receives CasADi expressions (use ``ca.exp``).

:class:`StudentAlipMpc` is :class:`~lipmpcc.planners.alip_mpc.AlipMpc` (the same cost, bounds, warm start, solvers and
fallback) whose dynamics rows (8) are the student's: the first step's
``z^1 = touchdown_dcm(xi_now, t, sigma^1, d, lam) - u^1`` and every later one's
``z^k = touchdown_dcm(z^{k-1}, 0, sigma^k, 0, lam) - u^k`` (a step starts at its touch-down, on a point foot). A
wrong prediction plans footholds for a DCM that is not there: the ALIP loop misses stones or falls.
"""

from __future__ import annotations

import math
from typing import Callable

import casadi as ca
import numpy as np

from ..exceptions import InvalidInputError
from ..planners.alip_mpc import AlipMpc, AlipMpcParams, build_alip_nlp, pack_nlp

__all__ = ["StudentAlipMpc", "TouchdownDcm", "touchdown_function", "ALIP_MPC_LIBRARY"]

#: the student's function (see the module doc)
TouchdownDcm = Callable[..., ca.SX]

#: the library names a student's ``touchdown_dcm`` must not call (the exercise asks to write the prediction)
ALIP_MPC_LIBRARY = ("lipmpcc.models.alip.step_to_step", "lipmpcc.models.alip.alip_flow",
                    "lipmpcc.planners.alip_mpc.build_alip_nlp", "lipmpcc.planners.alip_mpc.AlipMpc")


def _student_td(touchdown_dcm: TouchdownDcm, xi_now: ca.SX, t: ca.SX | float, sigma: ca.SX, d: ca.SX,
                lam: float) -> ca.SX:
    """The student's prediction as a CasADi 2-vector; anything else is an :class:`InvalidInputError`."""
    try:
        out = touchdown_dcm(xi_now, t, sigma, d, lam)
    except NotImplementedError:  # the stub: the exercise is not yet solved
        raise
    except (TypeError, ValueError, RuntimeError) as exc:
        raise InvalidInputError("touchdown_dcm(...)", type(exc).__name__,
                                f"a CasADi 2-vector (use ca.exp, not math.exp) ({exc})") from None
    if isinstance(out, np.ndarray) and out.dtype == object:  # np.array([expr_x, expr_y])
        out = out.ravel().tolist()
    if isinstance(out, (list, tuple)):
        out = ca.vertcat(*out)
    if not (isinstance(out, (ca.SX, ca.DM)) and out.numel() == 2):
        raise InvalidInputError("touchdown_dcm(...)", type(out).__name__, "a CasADi 2-vector (the DCM at touch-down)")
    return ca.reshape(ca.SX(out), 2, 1)


def touchdown_function(touchdown_dcm: TouchdownDcm, lam: float) -> ca.Function:
    """The student's prediction as a CasADi Function ``(xi_now (2), t, sigma, d (2)) -> xi_td (2)`` at ``lam`` [1/s]
    (what the planner evaluates; the notebook's check evaluates the same)."""
    xi, t, s, d = ca.SX.sym("xi", 2), ca.SX.sym("t"), ca.SX.sym("sigma"), ca.SX.sym("d", 2)
    fun = ca.Function("touchdown_dcm", [xi, t, s, d], [_student_td(touchdown_dcm, xi, t, s, d, float(lam))])
    probe = np.asarray(fun([0.05, -0.02], 0.1, 4.0, [0.01, 0.0]), dtype=float)
    if not np.all(np.isfinite(probe)):  # math.exp or float() of a CasADi symbol is NaN, silently
        raise InvalidInputError("touchdown_dcm(...)", probe.ravel().tolist(),
                                "finite numbers (use ca.exp, not math.exp or float(), on CasADi arguments)")
    return fun


class StudentAlipMpc(AlipMpc):
    """Paper B's ALIP-MPC on the student's ``touchdown_dcm`` (see the module doc); ``params`` as for
    :class:`~lipmpcc.planners.alip_mpc.AlipMpc` (``cop_range`` > 0: the first step's CoP offset d is a variable).

    The NLP's parameters are the library's followed by ``xi_now`` (2) and ``t``; a solution is accepted when the
    student's rows hold to 1e-6 (the library checks its own rows)."""

    name = "alip-mpc-student"

    def __init__(self, touchdown_dcm: TouchdownDcm, params: AlipMpcParams | None = None,
                 solver: str | None = None) -> None:
        if not callable(touchdown_dcm):
            raise InvalidInputError("touchdown_dcm", touchdown_dcm, "a function (xi_now, t, sigma, d, lam) -> xi_td")
        super().__init__(params, solver)
        touchdown_function(touchdown_dcm, self.params.lam)  # a function of the wrong kind fails here, in one line
        self.touchdown_dcm = touchdown_dcm
        nlp, self._rows = self._student_nlp()
        self._solver = pack_nlp(nlp, self.params, self.params.solver)

    def _student_nlp(self) -> tuple[dict, ca.Function]:
        """The library's NLP with the dynamics block (its first 2N rows) replaced by the student's rows."""
        prm = self.params
        N, lam = prm.horizon, prm.lam
        nlp = build_alip_nlp(prm)
        x = nlp["x"]
        xi_now, t = ca.SX.sym("xi_now", 2), ca.SX.sym("t")
        d = x[5 * N:5 * N + 2] if prm.uses_cop else ca.SX.zeros(2)
        rows, z_prev = [], xi_now
        for k in range(N):
            sigma, u, z = x[5 * k], x[5 * k + 1:5 * k + 3], x[5 * k + 3:5 * k + 5]
            if k == 0:
                td = _student_td(self.touchdown_dcm, z_prev, t, sigma, d, lam)
            else:
                td = _student_td(self.touchdown_dcm, z_prev, 0.0, sigma, ca.SX.zeros(2), lam)
            rows.append(z - (td - u))
            z_prev = z
        dyn = ca.vertcat(*rows)
        g = ca.vertcat(dyn, nlp["g"][2 * N:])
        p = ca.vertcat(nlp["p"], xi_now, t)
        return {**nlp, "g": g, "p": p}, ca.Function("student_rows", [x, xi_now, t], [dyn])

    def problem_data(self, dcm_world, stance_world, stance_side, t_since_touchdown, stones) -> dict:  # noqa: ANN001
        """The library's data with ``xi_now`` [m] and ``t`` [s] appended to the parameter vector."""
        data = super().problem_data(dcm_world, stance_world, stance_side, t_since_touchdown, stones)
        t = float(t_since_touchdown)
        xi_now = np.asarray(data["z0"], dtype=float) / data["e_t"]
        return {**data, "p": np.concatenate([data["p"], xi_now, [t]]), "t": t}

    def dynamics_residual(self, x: np.ndarray, z0: np.ndarray, e_t: float = 1.0) -> float:
        """max |row| of the student's dynamics rows at the stacked solution ``x`` [m] (``z0``, ``e_t`` as the
        library's: the DCM now is ``z0 / e_t``, the time since touch-down ``-ln(e_t) / λ``)."""
        t = -math.log(e_t) / self.params.lam
        r = self._rows(np.asarray(x, dtype=float), np.asarray(z0, dtype=float) / e_t, t)
        return float(np.max(np.abs(np.asarray(r, dtype=float))))
