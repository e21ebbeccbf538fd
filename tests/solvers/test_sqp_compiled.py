"""lipmpcc._sqp: the C++ condensed SQP takes the Python reference's iterations on recorded MPCC problems.

The problems are recorded in-test from short closed-loop runs (the fixed-T MPCC overtaking an obstacle and
pushed on a circle, the timed MPCC pushed on a line: with its second-order correction and rate stop) and from the small problems
of test_condensed_sqp; each is solved by both backends from the same guess, parameters and multipliers.
Both evaluate the same compiled CasADi functions; they differ only in rounding (the C++ eigenvalue clip through
the tridiagonal form, or Eigen's eigensolver, against LAPACK's; summation orders), so the solutions agree to 1e-9
where the problem itself is that well conditioned: where a 1e-14 or 1e-13 relative nudge of the guess already
moves the Python iterates (a QP with a
Hessian condition of 1e7 near an active-set change; a non-convex problem where rounding picks one of two
local solutions), the C++ answer must be one of the nudged Python answers.
Skipped when the compiled module is absent (everything then runs on Python).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.solvers import sqp_compiled
from lipmpcc.solvers.condensed_sqp import CondensedSqp

pytestmark = pytest.mark.skipif(not sqp_compiled.compiled_available(), reason="lipmpcc._sqp is not built")


def _same_daqp() -> bool:
    """Whether the daqp wheel is the vendored release (cpp/third_party/daqp): then the cold QPs take its iterations."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("daqp") == "0.11.0"
    except PackageNotFoundError:
        return False


def _record(run) -> list[tuple[CondensedSqp, np.ndarray, list[np.ndarray], np.ndarray]]:
    """(solver, u0, params, lam) of every CondensedSqp.solve call made by ``run()``."""
    rec = []
    original = CondensedSqp.solve

    def spy(self, u0, params):
        rec.append((self, np.array(u0, dtype=float), [np.array(p, dtype=float) for p in params], self.lam.copy()))
        return original(self, u0, params)

    CondensedSqp.solve = spy
    try:
        run()
    finally:
        CondensedSqp.solve = original
    return rec


def _mpcc_problems():
    """Problems of the fixed-T MPCC overtaking a moving obstacle and pushed on a circle, and of the timed MPCC
    pushed on a line."""
    from lipmpcc.loops import lip as lip_loop
    from lipmpcc.obstacles import Obstacle
    from lipmpcc.paths import ArcPath, LinePath
    from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
    from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner

    line = LinePath((0, 0), (40, 0))
    obs = [Obstacle.circle(0.25, path=line, s0=1.5, speed=0.6)]
    fixed = _record(lambda: lip_loop.simulate(MpccPlanner(line, MpccParams.overtake_mpcc()), np.zeros(5), 16, obs))
    # a circle of another radius, pushed (its second solve: rounding picks one of two local solutions)
    circle = ArcPath.circle(3.0, turns=1.0)
    pushes = lip_loop.random_pushes(10.0, np.random.default_rng(7))
    fixed += _record(lambda: lip_loop.simulate(MpccPlanner(circle, MpccParams.circle()), np.zeros(5), 10, [], pushes))
    # the timed MPCC on a line, pushed (no obstacle: compiled before its first evaluation)
    path = LinePath((0, 0), (30, 0))
    prm = TimedMpccParams(mpcc=MpccParams.overtake_mpcc(), T_min=0.3, T_max=0.5)
    pushes = lip_loop.random_pushes(6.0, np.random.default_rng(3))
    timed = _record(lambda: lip_loop.run_lip_loop(TimedMpccPlanner(path, prm), np.zeros(5), 16, path, [], pushes,
                                                  robot_radius=prm.mpcc.robot_radius, foot_radius=prm.mpcc.foot_radius))
    return fixed, timed


@pytest.fixture(scope="module")
def mpcc_problems():
    return _mpcc_problems()


def _cold(sqp: CondensedSqp) -> sqp_compiled.CompiledSqp:
    """The C++ solver of ``sqp`` with cold DAQP solves (as daqp.solve: the reference's QP iterations)."""
    return sqp_compiled.CompiledSqp(sqp.f_all, sqp.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu, max_iter=sqp.max_iter,
                                    tol=sqp.tol, eig_floor=sqp.eig_floor, warm_start=False,
                                    second_order_correction=sqp.second_order_correction, rate_stop=sqp.rate_stop)


def _both(sqp: CondensedSqp, u0: np.ndarray, params: list[np.ndarray], lam: np.ndarray, cold: bool) -> dict:
    """{backend: (solution, lam after, trace)} from the same start; C++ with warm (the default) or cold QPs."""
    sqp.lam, sqp.trace = lam.copy(), []
    out = {"python": (sqp._solve(u0, params), sqp.lam.copy(), sqp.trace)}
    if cold:
        res = _cold(sqp).solve(u0, params, lam, record_trace=True)
        out["cpp"] = (res, np.asarray(res.lam), res.trace)
    else:
        sqp.lam, sqp.trace = lam.copy(), []
        out["cpp"] = (sqp._solve_compiled(u0, params), sqp.lam.copy(), sqp.trace)
    sqp.trace = None
    return out


def _nudged(sqp: CondensedSqp, u0: np.ndarray, params: list[np.ndarray], lam: np.ndarray) -> list[tuple]:
    """The Python solutions (solution, trace) from the guess nudged by ±1e-14 and ±1e-13 relative: the problem's
    own sensitivity to rounding."""
    out = []
    for nudge in (1e-14, -1e-14, 1e-13, -1e-13):
        sqp.lam, sqp.trace = lam.copy(), []
        out.append((sqp._solve(u0 * (1 + nudge), params), sqp.trace))
    sqp.trace = None
    return out


def _check(sqp, u0, params, lam, cold: bool = False) -> bool:
    """Asserts parity; returns whether it held to 1e-9. Else the problem must be one whose Python iterates
    move under a 1e-14 nudge of the guess (a Hessian condition of 1e7 near an active-set change, or a
    non-convex problem where rounding picks the local solution), and the C++ answer one of the nudged
    Python answers: the same status, the same point up to the last steps (the stopping rule's accuracy).
    With ``cold`` the DAQP iterations are the reference's."""
    r = _both(sqp, u0, params, lam, cold)
    (sp, lp, tp), (sc, lc, tc) = r["python"], r["cpp"]
    du = float(np.max(np.abs(sp.u - sc.u)))
    diff = max(du, float(np.max(np.abs(lp - lc), initial=0.0)))
    steps = max((abs(a[2] - b[2]) for a, b in zip(tp, tc)), default=0.0)
    # the cost as far as the points' difference explains (|∇f|₁ reaches 1e4 at the timed MPCC's solutions)
    grad = np.asarray(sqp.f_all.evaluate(sp.u)[1], dtype=float)  # the parameters _solve bound
    cost_ok = abs(sp.cost - sc.cost) <= 1e-9 + float(np.abs(grad).sum()) * du
    if diff <= 1e-9 and steps <= 1e-9 and cost_ok:
        assert (sc.status, sc.iterations, sc.found) == (sp.status, sp.iterations, sp.found)
        assert [t[0] for t in tc] == [t[0] for t in tp] and [t[1] for t in tc] == [t[1] for t in tp]  # same α
        if cold and _same_daqp():
            assert [t[3] for t in tc] == [t[3] for t in tp]  # the same DAQP iterations
        return True
    nudged = _nudged(sqp, u0, params, lam)
    spread = max(max((abs(a[2] - b[2]) for a, b in zip(tn, tp)), default=0.0) for _, tn in nudged)
    assert spread > 1e-10, f"a well-conditioned problem differs by {diff:.2e} (status {sp.status} / {sc.status})"
    assert any(sn.status == sc.status and sn.found == sc.found
               and float(np.max(np.abs(sn.u - sc.u))) <= 10 * (tn[-1][2] + tc[-1][2]) + 1e-9
               for sn, tn in [(sp, tp), *nudged]), f"C++ ends {sc.status} at {diff:.2e} from every nudged Python answer"
    return False


@pytest.mark.parametrize("cold", [False, True], ids=["warm-qp", "cold-qp"])
def test_mpcc_problems_same_iterates(mpcc_problems, cold):
    fixed, timed = mpcc_problems
    for rec, label in ((fixed, "fixed T"), (timed, "timed")):
        assert len(rec) >= 15 and all(s.backend == "cpp" for s, *_ in rec), label
        exact = [_check(*p, cold=cold) for p in rec]
        # almost all to 1e-9; the rest only as sensitive as the problem itself
        assert sum(exact) >= 0.8 * len(rec), f"{label}: {sum(exact)} of {len(rec)} to 1e-9"


def test_counters_and_lam_are_kept(mpcc_problems):
    sqp, u0, params, lam = mpcc_problems[1][3]
    sqp.lam, sqp.qp_time, sqp.qp_iters, sqp.trace = lam.copy(), 0.0, 0, []
    sol = sqp.solve(u0, params)
    assert sol.found and len(sqp.trace) == sol.iterations and sqp.qp_iters >= sol.iterations
    assert 0.0 < sqp.qp_time < 1.0
    assert np.any(sqp.lam != 0) and sqp.lam.shape == lam.shape


def _small(name: str, soc: float = 0.0, rate: float = 0.0, backend: str = "auto") -> CondensedSqp:
    """The Maratos-like problem of test_condensed_sqp (a circle constraint), JIT-compiled."""
    u = ca.SX.sym("u", 2)
    p = ca.SX.sym("p", 1)
    circle = u[0] ** 2 + u[1] ** 2 - 1
    return CondensedSqp(name, u, [p], 2 * circle - u[0] + 0 * p[0], circle, [0.0], [0.0], [-3.0, -3.0], [3.0, 3.0],
                        max_iter=30, jit=True, second_order_correction=soc, rate_stop=rate, backend=backend)


@pytest.mark.parametrize("soc, rate", [(0.0, 0.0), (1.0, 0.0), (1.0, 0.5)])
def test_small_problem_with_soc_and_rate_stop(soc, rate):
    sqp = _small("test_sqp_compiled_maratos", soc, rate)
    if sqp.backend != "cpp":
        pytest.skip("no C compiler for the JIT")
    for start in ([0.0, 1.0], [2.0, -0.5], [-1.0, 0.2]):
        for cold in (False, True):
            assert _check(sqp, np.array(start), [np.zeros(1)], np.zeros(1), cold)


def test_backend_choice_and_bad_input(monkeypatch):
    monkeypatch.setenv("LIPMPCC_SQP_BACKEND", "python")
    assert _small("test_sqp_compiled_env").backend == "python"
    assert _small("test_sqp_compiled_env", backend="cpp").backend in ("cpp",)  # explicit beats the environment
    monkeypatch.setenv("LIPMPCC_SQP_BACKEND", "fortran")
    with pytest.raises(InvalidInputError, match="LIPMPCC_SQP_BACKEND"):
        _small("test_sqp_compiled_env")
    monkeypatch.delenv("LIPMPCC_SQP_BACKEND")
    with pytest.raises(InvalidInputError, match="backend"):
        _small("test_sqp_compiled_env", backend="gpu")
    u = ca.SX.sym("u", 2)
    with pytest.raises(InvalidInputError, match="JIT-compiled"):  # interpreted functions: no C++ backend
        CondensedSqp("test_sqp_interp", u, [], ca.sumsqr(u), u[0], [0.0], [1.0], [-1, -1], [1, 1], backend="cpp")
    sqp = _small("test_sqp_compiled_env")
    with pytest.raises(InvalidInputError, match="u0"):
        sqp.solve(np.zeros(3), [np.zeros(1)])
    with pytest.raises(InvalidInputError, match="params"):
        sqp.solve(np.zeros(2), [np.array([np.nan])])
    if sqp.backend == "cpp":  # checked in C++, named by the wrapper
        with pytest.raises(InvalidInputError, match="u0"):
            sqp._compiled.solve(np.array([0.0, np.inf]), [np.zeros(1)], np.zeros(1))
        with pytest.raises(InvalidInputError, match="lam"):
            sqp._compiled.solve(np.zeros(2), [np.zeros(1)], np.array([np.nan]))
        with pytest.raises(InvalidInputError, match="params"):
            sqp._compiled.solve(np.zeros(2), [np.zeros(1), np.zeros(1)], np.zeros(1))


def test_auto_falls_back_to_python(monkeypatch):
    """Without the module, or when it cannot load the compiled library, "auto" runs the Python loop (the same
    answer); "cpp" says why it cannot."""
    from lipmpcc.solvers import condensed_sqp

    ref = _small("test_sqp_compiled_fallback", backend="python").solve(np.array([2.0, -0.5]), [np.zeros(1)])
    monkeypatch.setattr(condensed_sqp, "compiled_available", lambda: False)
    assert _small("test_sqp_compiled_fallback").backend == "python"
    monkeypatch.undo()

    def broken(*args, **kwargs):
        raise RuntimeError("CasadiFunction: cannot load the library")

    monkeypatch.setattr(condensed_sqp, "CompiledSqp", broken)
    sqp = _small("test_sqp_compiled_fallback")
    assert sqp.backend == "python"
    sol = sqp.solve(np.array([2.0, -0.5]), [np.zeros(1)])
    assert sol.found and np.array_equal(sol.u, ref.u)
    with pytest.raises(RuntimeError, match="cannot load"):
        _small("test_sqp_compiled_fallback", backend="cpp")


def test_partial_eigen_clip_same_iterates(mpcc_problems):
    """``partial_eigen=True`` (the tridiagonal form's eigenvalues, only the eigenvectors below the floor; opt-in by
    ``$LIPMPCC_SQP_PARTIAL_EIGEN``, the default being Eigen's full eigendecomposition) takes the Python reference's
    iterates too."""
    fixed, timed = mpcc_problems
    exact = []
    for sqp, u0, params, lam in fixed + timed:
        original = sqp._compiled
        sqp._compiled = sqp_compiled.CompiledSqp(
            sqp.f_all, sqp.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu, max_iter=sqp.max_iter, tol=sqp.tol,
            eig_floor=sqp.eig_floor, second_order_correction=sqp.second_order_correction, rate_stop=sqp.rate_stop,
            partial_eigen=True)
        try:
            exact.append(_check(sqp, u0, params, lam))
        finally:
            sqp._compiled = original
    assert sum(exact) >= 0.8 * len(exact), f"{sum(exact)} of {len(exact)} to 1e-9"


def test_modified_cholesky_same_iterates(mpcc_problems):
    """With ``convexification="modified_cholesky"`` (the factor handed to DAQP as its LDP's R) both backends take
    the same iterates on the recorded fixed-T problems (within each problem's own rounding spread, as above);
    the eigenvalue clip stays the default."""
    fixed = mpcc_problems[0]
    assert all(s.convexification == "eigen_clip" for s, *_ in fixed)
    solvers: dict[int, sqp_compiled.CompiledSqp] = {}
    exact = []
    for sqp, u0, params, lam in fixed[:12]:
        if id(sqp) not in solvers:
            solvers[id(sqp)] = sqp_compiled.CompiledSqp(
                sqp.f_all, sqp.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu, max_iter=sqp.max_iter, tol=sqp.tol,
                eig_floor=sqp.eig_floor, second_order_correction=sqp.second_order_correction, rate_stop=sqp.rate_stop,
                convexification="modified_cholesky")
        original = sqp._compiled
        sqp.convexification, sqp._compiled = "modified_cholesky", solvers[id(sqp)]
        try:
            exact.append(_check(sqp, u0, params, lam))
        finally:
            sqp.convexification, sqp._compiled = "eigen_clip", original
    assert sum(exact) >= 0.8 * len(exact), f"{sum(exact)} of {len(exact)} to 1e-9"
    with pytest.raises(InvalidInputError, match="convexification"):
        sqp_compiled.CompiledSqp(sqp.f_all, sqp.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu, max_iter=10, tol=1e-4,
                                 eig_floor=1.0, second_order_correction=0.0, rate_stop=0.0, convexification="qr")


def _timed_planner(jit: bool = True):
    """A timed MPCC on a 30 m line (T in [0.3, 0.5] s) and the recording of its solves."""
    from lipmpcc.paths import LinePath
    from lipmpcc.planners.mpcc import MpccParams
    from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner

    prm = TimedMpccParams(mpcc=MpccParams.overtake_mpcc(jit=jit), T_min=0.3, T_max=0.5)
    return TimedMpccPlanner(LinePath((0, 0), (30, 0)), prm)


def test_a_function_not_compiled_yet_is_called_back_with_the_same_bits(mpcc_problems):
    """A function built for the JIT but not compiled (yet) is evaluated interpreted through a callback from C++: the
    same iterates, multipliers and costs to the bit as the compiled library's (the timed MPCC on a line, the
    recorded problems), and the library is taken over by ``refresh`` once there; an error in the callback reaches
    the caller."""
    timed = mpcc_problems[1]
    sqp = timed[0][0]
    assert sqp.backend == "cpp" and sqp.f_all.so is not None and not sqp._compiled.callbacks
    interp = _timed_planner(jit=False)
    ref = interp.formulation.build(interp.problem_path, 0, "sqp")["sqp"]
    assert ref.f_all.so is None and ref.m == sqp.m and ref.nu == sqp.nu
    for f in (ref.f_all, ref.f_merit):
        f.jit = True  # as a function whose background compile has not ended
    opts = dict(max_iter=sqp.max_iter, tol=sqp.tol, eig_floor=sqp.eig_floor,
                second_order_correction=sqp.second_order_correction, rate_stop=sqp.rate_stop)
    called = sqp_compiled.CompiledSqp(ref.f_all, ref.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu, **opts)
    library = sqp_compiled.CompiledSqp(sqp.f_all, sqp.f_merit, sqp.lbg, sqp.ubg, sqp.lbu, sqp.ubu, **opts)
    assert called.callbacks and not library.callbacks
    rows = [p for p in timed if p[0] is sqp]
    assert len(rows) >= 10
    for _, u0, params, lam in rows:
        a, b = called.solve(u0, params, lam), library.solve(u0, params, lam)
        assert (a.status, a.iterations, a.cost, a.qp_iters) == (b.status, b.iterations, b.cost, b.qp_iters)
        assert np.array_equal(np.asarray(a.u), np.asarray(b.u)) and np.array_equal(np.asarray(a.lam), np.asarray(b.lam))
    # the library arrives: refresh hands it to C++ (here the compiled sqp's own, the same function)
    ref.f_all.so, ref.f_all.symbol = sqp.f_all.so, sqp.f_all.symbol
    called.refresh()
    assert called._impl.uses_callback(1) and not called._impl.uses_callback(0) and called.callbacks
    _, u0, params, lam = rows[-1]
    a, b = called.solve(u0, params, lam), library.solve(u0, params, lam)
    assert np.array_equal(np.asarray(a.u), np.asarray(b.u))
    ref.f_merit._args = None  # a broken callback: its Python error reaches the caller through C++
    with pytest.raises(TypeError):
        called.solve(u0, params, lam)


def test_the_timed_mpcc_with_an_obstacle_slot_runs_on_cpp_when_asked(monkeypatch):
    """The timed MPCC with an obstacle slot (about 14 600 instructions: above MAX_JIT_INSTRUCTIONS, compiled in the
    background or not at all) stays on Python with "auto" (whatever the cache holds), and with
    ``LIPMPCC_SQP_BACKEND=cpp`` runs on the C++ SQP from its first solve, with the Python reference's iterates to
    1e-9 with cold QPs (within each problem's own rounding spread, as above), its answers within 1e-8 warm."""
    from lipmpcc.loops import lip as lip_loop
    from lipmpcc.obstacles import Obstacle

    auto = _timed_planner()
    built = auto.formulation.build(auto.problem_path, 1, "sqp")["sqp"]
    assert built.backend == "python" and not built.f_all.eager and built.f_merit.eager
    monkeypatch.setenv("LIPMPCC_SQP_BACKEND", "cpp")
    pl = _timed_planner()
    obs = [Obstacle.circle(0.25, path=pl.path, s0=1.0, speed=0.8)]
    prm = pl.params.mpcc
    rec = _record(lambda: lip_loop.run_lip_loop(pl, np.zeros(5), 20, pl.path, obs, [], robot_radius=prm.robot_radius,
                                                foot_radius=prm.foot_radius))
    slot = [r for r in rec if r[0].m > 21]  # the rows of one obstacle slot
    assert len(slot) >= 15 and all(s.backend == "cpp" for s, *_ in slot)
    exact = [_check(*r, cold=True) for r in slot]  # DAQP cold, as the reference
    assert sum(exact) >= 0.8 * len(exact), f"{sum(exact)} of {len(exact)} to 1e-9"
    close = 0  # warm-started DAQP (the default): a degenerate QP may end at another of its solutions (4.7e-7 in
    for r in slot:  # one step of one recorded solve here), the end point within about 1e-8
        both = _both(*r, cold=False)
        (sp, *_), (sc, *_) = both["python"], both["cpp"]
        assert (sp.found, sp.status) == (sc.found, sc.status)
        close += float(np.max(np.abs(sp.u - sc.u))) <= 1e-8
    assert close >= 0.8 * len(slot), f"{close} of {len(slot)} within 1e-8"
