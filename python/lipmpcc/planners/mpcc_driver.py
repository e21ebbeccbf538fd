"""The one solve driver of the MPCC planners (issue 24): warm start, θ_init search, the retry and fallback
chain, the liveness rules and the hold, over a formulation that says what differs.

Paper A's MPCC at a fixed step duration (:class:`~lipmpcc.planners.mpcc.FixedStepFormulation`) and the MPCC
with the step durations as decision variables (:class:`~lipmpcc.planners.mpcc_timed.TimedFormulation`) share
everything but the problem: the driver (:class:`MpccDriver`, the base of
:class:`~lipmpcc.planners.mpcc.MpccPlanner` and :class:`~lipmpcc.planners.mpcc_timed.TimedMpccPlanner`)
builds the solvers on first use (one per obstacle count, solver and end mode), times the solve (the θ_init
search included, as paper A), warm-starts from the shifted previous plan, tries more starts when the first
is not good enough (cold starts, other progress rates, the IPOPT solution of the lifted problem), switches
to the detour weights when stalled (:mod:`lipmpcc.planners.liveness`), and on failure replays the previous
plan — or holds in place when that replay walks into an obstacle. An :class:`MpccFormulation` gives the
problem: its solvers, the call's data, the guesses, the parameter vector, one solve, the result and the
replay of the previous plan.
"""

from __future__ import annotations

import math
import time
from typing import Any, Protocol, Sequence

import numpy as np

from ..exceptions import NoFallbackPlanError, ParameterError, StateError
from ..obstacles import Obstacle
from ..validation import finite_array
from .liveness import (RETURN_STEPS, ProgressMonitor, approach_mode, detour_fields, end_mode, passing, return_fields,
                       return_level, stall_progress, stall_window, trailed)

__all__ = ["MpccFormulation", "MpccDriver", "Attempt"]

#: one solve attempt: (converged, status, iterations, cost, X (N+1, 6), U (the formulation's variables))
Attempt = tuple[bool, str, int, float, np.ndarray, np.ndarray]


class MpccFormulation(Protocol):
    """What an MPCC formulation gives the driver (``call`` is the formulation's record of one solve's
    inputs, with at least ``theta`` [m], ``t_now`` [s], ``side`` and ``shift``; U its decision variables)."""

    label: str  #: the planner's name in errors ("mpcc", "mpcc-timed")
    mpcc: Any  #: the MpccParams (solver, horizon, v_max, liveness switches)
    restart_standing: bool  #: a stand-still plan is tried again from the cold starts (MpccDriver._standing)
    trail_moving_on: bool  #: behind an obstacle moving on along the path no stall detour starts (liveness.trailed)

    def build(self, path: Any, n_obs: int, solver: str, at_end: bool = False, arrive: bool = False) -> dict:
        """The solver of ``solver`` ("sqp"/"ipopt") for ``n_obs`` obstacles on ``path`` (``at_end``: the end
        mode's, whose steps may leave the COM where it is: ``delta_min`` = 0; ``arrive``: the approach's, with
        ``delta_min`` = 0 and the arrival row at the path's end: :meth:`MpccDriver._end_mode`)."""

    def select(self, x0: np.ndarray, obstacles: list[Obstacle], t_now: float) -> list[Obstacle]:
        """The obstacles the solve plans around."""

    def reach(self) -> float:
        """How far from the COM a plan's barriers reach [m] (the detour rule)."""

    def guess(self, call: Any, last: Any, cold: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """The initial guess (X, U): from ``last`` (the previous result) unless ``cold``."""

    def parameters(self, call: Any, obstacles: Sequence[Obstacle], U: np.ndarray) -> np.ndarray:
        """The parameter vector of the solve (``U``: the guess, for formulations that need its times)."""

    def solve_sqp(self, built: dict, call: Any, p: np.ndarray, X: np.ndarray, U: np.ndarray) -> Attempt:
        """One SQP solve from a guess."""

    def solve_ipopt(self, built: dict, call: Any, p: np.ndarray, X: np.ndarray, U: np.ndarray) -> Attempt:
        """One IPOPT solve from a guess."""

    def with_progress(self, U: np.ndarray, v: float) -> np.ndarray:
        """A copy of ``U`` with every step's path progress ``v`` [m]."""

    def mean_progress(self, U: np.ndarray) -> float:
        """The mean path progress per step of ``U`` [m]."""

    def progress_start(self, call: Any, best: np.ndarray, Ug: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A start that makes progress (v = v_max / 2), from the best solution or the warm-start guess."""

    def result(self, call: Any, X: np.ndarray, U: np.ndarray, found: bool, status: str, iters: int, elapsed: float,
               cost: float, side: int) -> Any:
        """The result of a solve (or of a replay)."""

    def replay(self, call: Any, last: Any, obstacles: Sequence[Obstacle]) -> tuple[np.ndarray, np.ndarray, int, list[int]]:
        """The previous plan replayed from the call's state (X, U, side, held_by): held in place when it would
        walk into one of ``obstacles``."""


class MpccDriver:
    """The solve driver of the MPCC planners over :attr:`formulation` (set by the subclass before
    :meth:`_init_driver`).

    Attributes:
        failures, solves: failed solves (the fallback was used) and all solves.
        last: the last result (warm start and fallback).
        progress: the :class:`~lipmpcc.planners.liveness.ProgressMonitor` of the liveness rules.
        detour_solves: solves made in the detour mode (:mod:`lipmpcc.planners.liveness`).
        return_solves: solves made on the way back from the detour (:func:`~lipmpcc.planners.liveness.return_level`).
    """

    formulation: MpccFormulation
    path: Any

    def _init_driver(self, formulation: MpccFormulation) -> None:
        self.formulation = formulation
        m = formulation.mpcc
        self.failures = 0
        self.solves = 0
        self.last: Any = None
        self._fallback_shift = 0
        self._last_status: tuple[str, int] = ("not solved", 0)
        self._built: dict[tuple[int, str, bool], dict] = {}
        self._at_end = False  # the end mode (_end_mode)
        self._arriving = False  # the approach to the end (_end_mode)
        self._build_s = 0.0  # seconds spent building solvers [s]
        self._step_plan: Any = None
        self.progress = ProgressMonitor(stall_window(m.N, m.model.T), stall_progress(m.N, m.v_max))
        self._detour = detour_fields(m)  # the detour mode's weights (None: these are they)
        self._detour_planners: dict[float, Any] = {}  # by the return's fraction s (0: the detour itself)
        self._return: int | None = None  # the return's step after a detour (-1: in the detour)
        self.detour_solves = 0
        self.return_solves = 0

    def reset(self) -> None:
        """Forget the previous plan (warm start and fallback) and the counts."""
        self.last = None
        self.failures = 0
        self.solves = 0
        self._fallback_shift = 0
        self._last_status = ("not solved", 0)
        self._step_plan = None
        self.progress.reset()
        self.detour_solves = 0
        self.return_solves = 0
        self._return = None
        self._at_end = False
        self._arriving = False

    # ---- solvers -----------------------------------------------------------------------------------
    def _get(self, n_obs: int, solver: str | None = None) -> dict:
        """The solver for ``n_obs`` obstacles, built on first use and cached (on the path itself in the end
        mode, with the arrival row in the approach to it, :meth:`_end_mode`; its build time is added to
        ``_build_s``)."""
        end = self._at_end
        arrive = self._arriving and not end
        key = (n_obs, solver or self.formulation.mpcc.solver, end, arrive)
        if key not in self._built:
            tb = time.perf_counter()
            path = self.path if end else self.problem_path
            self._built[key] = self.formulation.build(path, n_obs, key[1], at_end=end, arrive=arrive)
            self._build_s += time.perf_counter() - tb
        return self._built[key]

    def _end_mode(self, theta: float) -> None:
        """Enter or leave the end mode for a solve from the measured ``theta`` [m]: with ``past_end``, once
        the measured ϑ is the path's end (the robot there or past it), the problem is built on the path itself
        (ϑ ≤ ϑ_T): the goal is reached, and the plans stop there rather than lead the robot on along the end
        tangent (a full body keeps planning after the end; the LIP loop stops before). It is left only when ϑ
        falls more than v_max short of the end (:func:`~lipmpcc.planners.liveness.end_mode`).

        The end mode's problem has no least COM distance per step (``delta_min`` = 0; paper A's eq. 16 keeps
        the robot walking, and at the end that is what it must not do): with ``delta_min`` the plans moved the
        COM by exactly ``delta_min`` every step, and on ``digit_like`` with the timed MPCC the robot drifted
        back 3 cm a step from the end of issue 31's crossing-pedestrian path, fell more than v_max short of
        it, left the end mode, and the extended path's plan then led it on by a long step: it fell 4 s after
        reaching the end (sideways by 0.32 m in 10 steps on an 8 m path). In the end mode there is no progress to
        find, so neither the stall restarts (:meth:`_retry`) nor the detour and the pass act there: they had tried
        3-4 more starts (IPOPT's among them) at every re-plan while a full body stood at the end, and after two
        stall windows switched it to the detour's weights, whose plans moved it on again. A return to the path
        under way when the end is reached goes on (its weights graded back to these).

        **The approach.** Once the plan's reach (how far the extended path runs past the end) takes ϑ to the
        end, the problem gets the arrival row (:func:`~lipmpcc.planners.mpcc._arrival_rows`: the capture point
        ξ = c + ċ/ω of the next planned exchange state stays behind the end + ``delta_min``) and ``delta_min`` =
        0, still on the extended path (its progress reward pulls the COM all the way): the plans brake when
        they must and the COM comes to rest at the end. Without it the plans led a full body on at full speed
        until it was past the end, and the end mode then asked it to stop and come back: ``digit_like``, timed,
        0.8 m/s obstacle, a 40 m line, fell 2 s after the end (14 failed solves). The end mode on the path
        itself (ϑ ≤ ϑ_T) from a horizon before the end instead stopped ``digit_like`` 0.33-0.62 m short
        (issue 31's scenes 0 and 1, ``stalled``): only the weak lag weight pulls the COM to a ϑ resting at the
        end."""
        m = self.formulation.mpcc
        self._at_end = end_mode(self._at_end, theta, self.path.length, m.past_end, m.v_max)
        reach = float(self.problem_path.length) - float(self.path.length)
        self._arriving = approach_mode(self._arriving, theta, self.path.length, reach, m.past_end, m.v_max)

    @staticmethod
    def _check_inputs(x0: np.ndarray, stance_side: int, obstacles: Sequence[Obstacle]) -> tuple[np.ndarray, list[Obstacle]]:
        """``x0`` as a finite 5-vector, ``stance_side`` ±1 and ``obstacles`` as a list of Obstacle (else the
        error naming the value)."""
        x0 = finite_array("x0", x0, (5,), error=StateError, what="a 5-vector [x, xdot, y, ydot, heading]")
        if isinstance(stance_side, (bool, np.bool_)) or not isinstance(stance_side, (int, np.integer)) \
                or stance_side not in (1, -1):
            raise ParameterError("stance_side", stance_side, "+1 (left) or -1 (right)")
        if isinstance(obstacles, (str, bytes, Obstacle)) or not hasattr(obstacles, "__iter__"):
            raise ParameterError("obstacles", obstacles, "a list of lipmpcc.obstacles.Obstacle")
        obstacles = list(obstacles)
        for i, ob in enumerate(obstacles):
            if not isinstance(ob, Obstacle):
                raise ParameterError(f"obstacles[{i}]", ob, "a lipmpcc.obstacles.Obstacle")
        return x0, obstacles

    # ---- the driver --------------------------------------------------------------------------------
    def _drive(self, x0: np.ndarray, given: list[Obstacle], t_now: float, make_call: Any) -> Any:
        """One solve: the solvers, ``make_call()`` (the θ_init search, timed), the guess, the attempts, and
        the result or the fallback (``given``: every obstacle; the formulation selects those planned around)."""
        form = self.formulation
        obstacles = form.select(x0, given, t_now)
        # building (and JIT-compiling) the solvers happens once, outside the timed solve
        built = self._get(len(obstacles))
        if self.last is None and form.mpcc.solver == "sqp":
            self._get(len(obstacles), "ipopt")
        t0 = time.perf_counter()  # the solve time includes the θ_init search, as in paper A
        build_before = self._build_s
        call = make_call()
        self._end_mode(call.theta)
        built = self._get(len(obstacles))  # the end mode's solver (built once: not timed)
        t0 += self._build_s - build_before
        Xg, Ug = form.guess(call, self.last)
        p = form.parameters(call, obstacles, Ug)
        self.solves += 1
        self.progress.record(call.t_now, call.theta)
        if self._detour is not None and form.mpcc.restart_when_stalled:
            p_path = self.path._frame(np.array([min(max(call.theta, 0.0), self.path.length)]))[0][0]
            err = math.hypot(float(x0[0]) - float(p_path[0]), float(x0[2]) - float(p_path[1]))
            # the robot and its last plan's end both off the path (a robot that drifts off and whose plan leads back
            # is not going around anything: Digit v3's Cartesian run, 0.10 m off, then passed the obstacle it trails)
            off = min(err, abs(float(self.last.e_contouring[-1]))) if self.last is not None else 0.0
            # the detour and the pass start short of the end only: in the end mode standing still is the goal, not
            # a stall. A return under way goes on there (the own weights at once pulled digit_like, 0.34 m off the
            # path at the end, by a 0.7 m side step: it fell, scene 11)
            if not self._at_end:
                if passing(call.theta, off, given, call.t_now, form.mpcc.obstacle_inflation, form.reach()) is not None:
                    self.progress.start_detour(call.theta + form.reach())  # pass it: liveness.passing
                # behind an obstacle that moves on along the path the robot trails; the stall's detour is for those
                # that will not clear the way (liveness.trailed)
                mon = self.progress
                held = form.trail_moving_on and trailed(call.theta, (float(x0[0]), float(x0[2])), given, call.t_now,
                                                        mon.min_progress / mon.window, form.reach()) is not None
                if mon.detour(call.theta, form.reach(), trailing=held):
                    self._return = -1
                    return self._detour_solve(call, given, 0.0)
            if self._return is not None:  # back from the detour, by steps (liveness.return_level)
                self._return = return_level(max(self._return, 0), err, form.mpcc)
                if self._return is not None:
                    return self._detour_solve(call, given, RETURN_STEPS[self._return])
        best = self._attempt(built, call, p, Xg, Ug)
        best = self._retry(best, built, len(obstacles), call, p, Xg, Ug)
        elapsed = time.perf_counter() - t0
        if best is None:
            self.failures += 1
            status, iters = self._last_status
            if self.last is None:
                raise NoFallbackPlanError(f"{form.label}/{form.mpcc.solver}", status, iters,
                                          "first solve failed, no previous plan")
            return self._fallback(call, status, iters, elapsed, given)
        _, status, iters, cost, X, U = best
        self._fallback_shift = 0
        self.last = form.result(call, X, U, True, status, iters, elapsed, cost, call.side)
        return self.last

    def _detour_solve(self, call: Any, obstacles: list[Obstacle], s: float = 0.0) -> Any:
        """The detour mode's solve of ``call`` (the planner's ``_solve_detour``), or with ``s`` > 0 the return's
        (the weights that fraction of the way back to this planner's own)."""
        raise NotImplementedError

    def _detour_fields(self, s: float) -> dict[str, object]:
        """The fields of the detour planner of fraction ``s`` (0: the detour's, :data:`~lipmpcc.planners.liveness.
        DETOUR_FIELDS`; else :func:`~lipmpcc.planners.liveness.return_fields`)."""
        assert self._detour is not None
        return dict(self._detour) if s == 0.0 else return_fields(self.formulation.mpcc, s)

    def _via_detour(self, sub: "MpccDriver", solve: Any, s: float = 0.0) -> Any:
        """``solve()`` by the detour (or return, ``s`` > 0) planner ``sub`` warm-started from this one's plan; its
        plan and failures become this one's. ``sub`` has no detour of its own."""
        sub._detour = None
        sub.last, sub._fallback_shift, failures = self.last, self._fallback_shift, sub.failures
        res = solve()
        self.last, self._fallback_shift = sub.last, sub._fallback_shift
        self.failures += sub.failures - failures
        if s == 0.0:
            self.detour_solves += 1
        else:
            self.return_solves += 1
        return res

    def _retry(self, best: Attempt | None, built: dict, n_obs: int, call: Any, p: np.ndarray, Xg: np.ndarray,
               Ug: np.ndarray) -> Attempt | None:
        """More starts when the first attempt is not good enough; the cheapest converged attempt."""
        form = self.formulation
        m = form.mpcc
        cold = self.last is None
        # liveness (issue 31): stalled, or a plan that stands still where nothing holds it (_standing); not in the
        # end mode, where ϑ ≤ ϑ_T leaves no progress to find: there the restarts (IPOPT's lifted start among them)
        # ran at every re-plan while a full body stood at the end
        restart = m.restart_when_stalled and not self._at_end
        stuck = restart and (self.progress.stalled() or self._standing(best, n_obs))
        if cold or best is None or stuck:
            # cold start, or the warm start failed: the problem is non-convex, so try other
            # starts — other progress rates and, for the SQP, the interior-point (IPOPT)
            # solution of the lifted problem, which finds good basins from poor guesses — and
            # keep the cheapest converged solution before giving up
            Xc, Uc = (Xg, Ug) if cold else form.guess(call, self.last, cold=True)
            starts = [(Xc, Uc)] if not cold else []
            for frac in (0.0, 1.0):
                starts.append((Xc, form.with_progress(Uc, frac * m.v_max)))
            if m.solver == "sqp":
                lifted = self._attempt(self._get(n_obs, "ipopt"), call, p, Xc, Uc, ipopt=True)
                if lifted is not None:
                    starts.append((Xc, lifted[5]))
            for Xs, Us in starts:
                best = self._better(best, self._attempt(built, call, p, Xs, Us))
        elif restart and form.mean_progress(best[5]) < 0.1 * m.v_max:
            # −ρv² has zero slope at v = 0, so "stand still" is a local minimum the warm start
            # can get stuck in (e.g. behind an obstacle that has since moved on): try once more
            # from a guess that makes progress, and keep the better of the two
            Xr, Ur = form.progress_start(call, best[5], Ug)
            best = self._better(best, self._attempt(built, call, p, Xr, Ur))
        return best

    def _standing(self, best: Attempt | None, n_obs: int) -> bool:
        """Whether the warm-started ``best`` is a stand-still plan the formulation asks to be tried again from the
        cold starts (``restart_standing``, the timed MPCC's): at most v_max [m] of progress over its N steps,
        obstacles in the problem, a previous plan, and not in the end mode (where the plans stop by design).

        Why (the timed MPCC, issue 31): its plans speed up towards their end (COM steps 0.13, 0.17, 0.26, 0.40 m;
        the shifted warm start's appended step 0.67 m), and the CBF (17), b_{k+1} ≥ (1 − γ) b_k with b ≈ d²/r²,
        lets a step close at most ≈ 1 − √(1 − γ) of the distance d to an obstacle (0.4 m from 3.8 m at γ = 0.2).
        So the tail's barrier rows bind when the robot, a metre behind its plan's last step, is about 4.5 m
        from an obstacle on the path, and the warm start violates them (measured on a straight line with one
        static obstacle: by 6.0 units of b). From there the SQP ended in v = (0, 0, 0.3, 0.3, 0.3), then
        (0, 0, 0, 0, v_max): the stand-still of −ρv² (zero slope at v = 0), no barrier row active, the robot
        walking 3 cm back per step; a plan that walks on and only slows its tail was feasible and cheaper
        (cost −1.25 against +1.65: the same warm start with v = v_max finds it). The restarts keep the cheapest
        converged plan, so a robot held by a barrier keeps waiting. The fixed-T MPCC's plans walk on from the
        same states (its benchmark is 200/200); it does not ask for this, and paper A's studies are unchanged."""
        form = self.formulation
        if best is None or self.last is None or n_obs == 0 or self._at_end or not form.restart_standing:
            return False
        m = form.mpcc
        return form.mean_progress(best[5]) * m.N <= m.v_max * (1.0 + 1e-9)

    def _attempt(self, built: dict, call: Any, p: np.ndarray, Xg: np.ndarray, Ug: np.ndarray,
                 ipopt: bool | None = None) -> Attempt | None:
        """One solve from a guess; returns (ok, status, iters, cost, X, U) or None on failure (the status
        is kept for the report)."""
        use_ipopt = self.formulation.mpcc.solver == "ipopt" if ipopt is None else ipopt
        try:
            out = (self._solve_ipopt if use_ipopt else self._solve_sqp)(built, call, p, Xg, Ug)
        except RuntimeError as exc:  # CasADi evaluation errors (NaN in functions, ...)
            self._last_status = (f"exception: {str(exc).splitlines()[0][:120]}", -1)
            return None
        ok, status, iters = out[0], out[1], out[2]
        if ok and not (np.isfinite(out[4]).all() and np.isfinite(out[5]).all()):
            ok, status = False, "non-finite solution"
        if not ok:
            self._last_status = (status, iters)
            return None
        return out

    def _solve_sqp(self, built: dict, call: Any, p: np.ndarray, Xg: np.ndarray, Ug: np.ndarray) -> Attempt:
        return self.formulation.solve_sqp(built, call, p, Xg, Ug)

    def _solve_ipopt(self, built: dict, call: Any, p: np.ndarray, Xg: np.ndarray, Ug: np.ndarray) -> Attempt:
        return self.formulation.solve_ipopt(built, call, p, Xg, Ug)

    @staticmethod
    def _better(a: Attempt | None, b: Attempt | None) -> Attempt | None:
        """The cheaper of two attempts (None is worse than anything)."""
        if a is None:
            return b
        if b is None:
            return a
        return b if b[3] < a[3] - 1e-9 else a

    def _fallback(self, call: Any, status: str, iters: int, elapsed: float,
                  obstacles: Sequence[Obstacle] = ()) -> Any:
        """The previous plan (shifted by one step for a new step), replayed from the current state; when that
        replay walks into one of ``obstacles``, step in place instead (``held_by`` names them)."""
        assert self.last is not None
        X, U, side, held = self.formulation.replay(call, self.last, obstacles)
        res = self.formulation.result(call, X, U, False, status, iters, elapsed, math.nan, side)
        res.used_fallback = True
        res.held_by = held
        self.last = res
        return res
