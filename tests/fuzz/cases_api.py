"""Fuzz cases of the Python API (in-process): the params dataclasses, paths, obstacles, pushes,
contouring errors, stones, planners' solve/plan, the whole-body controller and its reference, the
loops, and ``lipmpcc.run``."""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .harness import REPO, Case, Ran

NAN, INF = float("nan"), float("inf")


def api(cid: str, category: str, func: Callable[[Path], Any], names: tuple = (), expect: str = "error",
        **kw: Any) -> Case:
    return Case(cid, category, "api", expect, func=func, names=names, **kw)


def call(f: Callable[..., Any], *args: Any, **kwargs: Any) -> Callable[[Path], Any]:
    """``f(*args, **kwargs)``, ``f`` given as ``"module:attr"`` (imported when the case runs)."""
    def run(tmp: Path) -> Any:  # noqa: ARG001
        return _resolve(f)(*args, **kwargs)
    return run


def _resolve(f: Any) -> Any:
    if not isinstance(f, str):
        return f
    mod, _, attr = f.partition(":")
    import importlib

    obj: Any = importlib.import_module(mod)
    for part in attr.split("."):
        obj = getattr(obj, part)
    return obj


# ---- params dataclasses ---------------------------------------------------------------------------
MP = "lipmpcc.planners.mpcc:MpccParams"
PARAMS = [
    api("MpccParams-R-None", "api-params", call(MP, R=None), ("R",)),
    api("MpccParams-foot_radius-nan", "api-params", call(MP, foot_radius=NAN), ("foot_radius", "nan")),
    api("MpccParams-foot_radius-negative", "api-params", call(MP, foot_radius=-1.0), ("foot_radius", "-1")),
    api("MpccParams-N-zero", "api-params", call(MP, N=0), ("N",)),
    api("MpccParams-N-float", "api-params", call(MP, N=2.5), ("2.5",)),
    api("MpccParams-N-str", "api-params", call(MP, N="5"), ("'5'",)),
    api("MpccParams-Q_bar-one", "api-params", call(MP, Q_bar=(1.0,)), ("Q_bar",)),
    api("MpccParams-Q_bar-nan", "api-params", call(MP, Q_bar=(NAN, 1.0)), ("Q_bar",)),
    api("MpccParams-Q_bar-str", "api-params", call(MP, Q_bar="ab"), ("Q_bar",)),
    api("MpccParams-rho-negative", "api-params", call(MP, rho=-1.0), ("rho",)),
    api("MpccParams-v_max-zero", "api-params", call(MP, v_max=0.0), ("v_max",)),
    api("MpccParams-delta-inverted", "api-params", call(MP, delta_min=0.5, delta_max=0.4), ("delta_min",)),
    api("MpccParams-gamma-1.5", "api-params", call(MP, gamma=1.5), ("gamma",)),
    api("MpccParams-gamma-nan", "api-params", call(MP, gamma=NAN), ("gamma",)),
    api("MpccParams-gamma-str", "api-params", call(MP, gamma="0.2"), ("gamma",)),
    api("MpccParams-solver-foo", "api-params", call(MP, solver="foo"), ("foo",)),
    api("MpccParams-max_iter-negative", "api-params", call(MP, max_iter=-1), ("max_iter",)),
    api("MpccParams-robot_radius-inf", "api-params", call(MP, robot_radius=INF), ("robot_radius",)),
    api("MpccParams-obstacle_margin-negative", "api-params", call(MP, obstacle_margin=-0.1), ("obstacle_margin",)),
    api("MpccParams-heading_weight-nan", "api-params", call(MP, heading_weight=NAN), ("heading_weight",)),
    api("MpccParams-model-str", "api-params", call(MP, model="lip"), ("model",)),
    api("MpccParams-foot_clearance-str", "api-params", call(MP, foot_clearance="no"), ("foot_clearance",),
        question="a truthy string for a bool flag: expected refused (it would silently mean True)"),
    api("MpccParams-N-numpy", "api-params", call(MP, N=np.int64(5)), (), "ok"),
    api("MpccParams-v_max-float32", "api-params", call(MP, v_max=np.float32(0.3)), (), "ok"),
    api("Lip3dModel-T-zero", "api-params", call("lipmpcc.models.lip3d:Lip3dModel", T=0.0), ("T",)),
    api("Lip3dModel-H-str", "api-params", call("lipmpcc.models.lip3d:Lip3dModel", H="tall"), ("tall",)),
    api("AlipMpcParams-horizon-zero", "api-params", call("lipmpcc.planners.alip_mpc:AlipMpcParams", horizon=0),
        ("horizon",)),
    api("AlipMpcParams-T-inverted", "api-params",
        call("lipmpcc.planners.alip_mpc:AlipMpcParams", T_min=0.7, T_max=0.3), ("T_min",)),
    api("AlipMpcParams-cop-negative", "api-params",
        call("lipmpcc.planners.alip_mpc:AlipMpcParams", cop_range=(-0.1, 0.0)), ("cop_range",)),
    api("AlipMpcParams-solver-foo", "api-params", call("lipmpcc.planners.alip_mpc:AlipMpcParams", solver="foo"),
        ("foo",)),
    api("AlipParams-mass-nan", "api-params", call("lipmpcc.models.alip:AlipParams", mass=NAN), ("mass",)),
    api("KinematicLimits-inverted", "api-params", call("lipmpcc.models.alip:KinematicLimits", y_min=0.6, y_max=0.1),
        ("y_min",)),
    api("CapturePointParams-step_duration-negative", "api-params",
        call("lipmpcc.planners.capture_point:CapturePointParams", step_duration=-0.4), ("step_duration",)),
    api("WbcParams-qp_max_iter-zero", "api-params", call("lipmpcc.control.wbc_types:WbcParams", qp_max_iter=0),
        ("qp_max_iter",)),
    api("WbcParams-qp_solver-unknown", "api-params", call("lipmpcc.control.wbc_types:WbcParams", qp_solver="osqp"),
        ("qp_solver", "osqp", "daqp")),
    api("WbcParams-cop_safety-nan", "api-params", call("lipmpcc.control.wbc_types:WbcParams", cop_safety_factor=NAN),
        ("cop_safety_factor",)),
    api("TaskGains-kp-negative", "api-params", call("lipmpcc.control.wbc_types:TaskGains", kp=-1.0), ("kp",)),
    api("LoopParams-sim_steps-zero", "api-params", call("lipmpcc.loops.fullbody:LoopParams", sim_steps_per_wbc=0),
        ("sim_steps_per_wbc",)),
    api("LoopParams-first_stance-middle", "api-params",
        call("lipmpcc.loops.fullbody:LoopParams", first_stance="middle"), ("middle",)),
    api("LoopParams-com_height-str", "api-params", call("lipmpcc.loops.fullbody:LoopParams", com_height="high"),
        ("high",)),
]


# ---- geometry: paths, obstacles, pushes, contouring, stones -------------------------------------
ARC = "lipmpcc.paths:ArcPath"
OB = "lipmpcc.obstacles:Obstacle"
PUSH = "lipmpcc.push:Push"
ERR = "lipmpcc.contouring:errors"


def _position(theta: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.paths import ArcPath

        return ArcPath.circle(2.0).position(theta)
    return run


def _composite_gap(tmp: Path) -> Any:  # noqa: ARG001
    from lipmpcc.paths import CompositePath, LinePath

    return CompositePath([LinePath((0, 0), (1, 0)), LinePath((5, 5), (6, 5))])


GEOMETRY = [
    api("ArcPath-circle-int64", "api-geometry", call(ARC + ".circle", np.int64(2)), (), "ok"),
    api("ArcPath-circle-zero", "api-geometry", call(ARC + ".circle", 0.0), ("radius",)),
    api("ArcPath-circle-negative", "api-geometry", call(ARC + ".circle", -1.0), ("-1",)),
    api("ArcPath-circle-nan", "api-geometry", call(ARC + ".circle", NAN), ("nan",)),
    api("ArcPath-circle-str", "api-geometry", call(ARC + ".circle", "2"), ("'2'",)),
    api("ArcPath-center-1d", "api-geometry", call(ARC, (0.0,), 1.0), ("center",)),
    api("ArcPath-sweep-zero", "api-geometry", call(ARC, (0.0, 0.0), 1.0, 0.0, 0.0), ("sweep",)),
    api("ArcPath-circle-huge", "api-geometry", call(ARC + ".circle", 1e300), (("1e+300", "1e300"),),
        question="a circle of radius 1e300 m: expected refused as absurd"),
    api("LinePath-zero-length", "api-geometry", call("lipmpcc.paths:LinePath", (0, 0), (0, 0)), ("end",)),
    api("LinePath-nan", "api-geometry", call("lipmpcc.paths:LinePath", (NAN, 0), (1, 0)), ("nan",)),
    api("SplinePath-one-point", "api-geometry", call("lipmpcc.paths:SplinePath", [[0.0, 0.0]]), ("waypoints",)),
    api("SplinePath-same-point-4x", "api-geometry", call("lipmpcc.paths:SplinePath", [[1.0, 1.0]] * 4),
        ("waypoints", ("same", "duplicate", "distinct", "at least"))),
    api("SplinePath-nan", "api-geometry", call("lipmpcc.paths:SplinePath", [[0, 0], [1, NAN], [2, 0]]), ("nan",)),
    api("SplinePath-ds-zero", "api-geometry", call("lipmpcc.paths:SplinePath", [[0, 0], [1, 0], [2, 1]], ds=0.0),
        ("ds",)),
    api("SplinePath-str", "api-geometry", call("lipmpcc.paths:SplinePath", "abc"), ("abc",)),
    api("SplinePath-2e-9-apart", "api-geometry", call("lipmpcc.paths:path_from_waypoints", [[0, 0], [2e-9, 0]]),
        ("waypoints",), question="the issue: 2 waypoints 2e-9 m apart accepted; expected refused as degenerate"),
    api("CompositePath-empty", "api-geometry", call("lipmpcc.paths:CompositePath", []), ("pieces",)),
    api("CompositePath-gap", "api-geometry", _composite_gap, ("pieces",)),
    api("Path-position-str", "api-geometry", _position("abc"), ("abc",)),
    api("Path-position-nan", "api-geometry", _position(NAN), ("theta",),
        question="position(NaN) returns NaN today; expected refused naming theta"),
    api("Obstacle-axes-one", "api-geometry", call(OB, axes=(1.0,)), ("axes",)),
    api("Obstacle-axes-negative", "api-geometry", call(OB, axes=(1.0, -1.0)), ("axes",)),
    api("Obstacle-axes-nan", "api-geometry", call(OB, axes=(NAN, 1.0)), ("axes",)),
    api("Obstacle-axes-str", "api-geometry", call(OB, axes="ab"), ("axes",)),
    api("Obstacle-s0-nan", "api-geometry", call(OB, axes=(1.0, 1.0), s0=NAN), ("s0",)),
    api("Obstacle-position-one", "api-geometry", call(OB, axes=(1.0, 1.0), position=(1.0,)), ("position",)),
    api("Obstacle-position-None", "api-geometry", call(OB, axes=(1.0, 1.0), position=None), ("position",)),
    api("Obstacle-velocity-str", "api-geometry", call(OB, axes=(1.0, 1.0), velocity=("a", 0)), ("velocity",)),
    api("Obstacle-orientation-None", "api-geometry", call(OB, axes=(1.0, 1.0), orientation=None), ("orientation",)),
    api("Obstacle-path-str", "api-geometry", call(OB, axes=(1.0, 1.0), path="line"), ("path",)),
    api("Obstacle-circle-big", "api-geometry", call(OB + ".circle", radius="big"), ("big",)),
    api("Obstacle-circle-1e6", "api-geometry", call(OB + ".circle", 1e6), ("1000000",),
        question="the issue: an obstacle of radius 1e6 m is accepted; expected refused as absurd"),
    api("Obstacle-circle-int64", "api-geometry", call(OB + ".circle", np.int64(1)), (), "ok"),
    api("Push-force-one", "api-geometry", call(PUSH, (1.0,), 0.5), ("force",)),
    api("Push-force-nan", "api-geometry", call(PUSH, (NAN, 0.0), 0.5), ("force",)),
    api("Push-force-str", "api-geometry", call(PUSH, "ab", 0.5), ("force",)),
    api("Push-t_start-negative", "api-geometry", call(PUSH, (1.0, 0.0), -1.0), ("t_start",)),
    api("Push-duration-zero", "api-geometry", call(PUSH, (1.0, 0.0), 0.5, 0.0), ("duration",)),
    api("Push-step-negative", "api-geometry", call(PUSH, (1.0, 0.0), 0.5, 0.1, -1), ("step",)),
    api("Push-body-empty", "api-geometry", call(PUSH, (1.0, 0.0), 0.5, 0.1, None, ""), ("body",)),
    api("Push-between-inverted", "api-geometry", call(PUSH + ".between", (1.0, 0.0), 1.0, 0.5), ("t_start",)),
    api("Push-numpy-scalars", "api-geometry", call(PUSH, (np.int64(10), 0), np.float32(0.5)), (), "ok"),
    api("errors-position-nan", "api-geometry", call(ERR, [NAN, 0.0], [0.0, 0.0], 0.0), ("position",)),
    api("errors-reference-inf", "api-geometry", call(ERR, [0.0, 0.0], [INF, 0.0], 0.0), ("reference",)),
    api("errors-phi-nan", "api-geometry", call(ERR, [0.0, 0.0], [0.0, 0.0], NAN), ("phi",)),
    api("errors-position-3", "api-geometry", call(ERR, [1.0, 2.0, 3.0], [0.0, 0.0], 0.0), ("position",)),
    api("errors-position-str", "api-geometry", call(ERR, "ab", [0.0, 0.0], 0.0), ("position",)),
    api("weight_matrix-one", "api-geometry", call("lipmpcc.contouring:weight_matrix", (1.0,), 0.0), ("weights",)),
    api("make_profile-V", "api-geometry", call("lipmpcc.terrain:make_profile", "V"), ("V",)),
    api("make_profile-L-huge", "api-geometry", call("lipmpcc.terrain:make_profile", "I", L=5.0), ("5",)),
    api("make_profile-n-zero", "api-geometry", call("lipmpcc.terrain:make_profile", "I", n=0), ("n",)),
    api("StoneSequence-lengths", "api-geometry",
        call("lipmpcc.terrain:StoneSequence", np.zeros((3, 2)), np.ones((2, 2)), [1, -1, 1], [True] * 3), ("stones",)),
    api("Stone-center-nan", "api-geometry", call("lipmpcc.terrain:Stone", (NAN, 0.0)), ("center",),
        question="Stone has no validation today; expected refused naming center"),
]


# ---- planners -------------------------------------------------------------------------------------
@functools.cache
def _mpcc() -> Any:
    from lipmpcc.paths import ArcPath
    from lipmpcc.planners.mpcc import MpccParams, MpccPlanner

    return MpccPlanner(ArcPath.circle(2.0), MpccParams.circle())


X0 = np.array([0.0, 0.0, 0.0, 0.0, 0.0])


def _solve(*args: Any, **kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        p = _mpcc()
        p.reset()
        return p.solve(*args, **kw)
    return run


def _far_obstacle_solve(tmp: Path) -> Any:  # noqa: ARG001
    from lipmpcc.obstacles import Obstacle
    from lipmpcc.paths import LinePath
    from lipmpcc.planners.mpcc import MpccParams, MpccPlanner

    p = MpccPlanner(LinePath((0, 0), (40, 0)), MpccParams.overtake_mpcc())
    return p.solve(X0, 1, [Obstacle.circle(0.2, position=(20.0, 60.0))])


def _solve_ok(ran: Ran) -> str | None:
    st = getattr(ran.value, "status", None)
    ok = getattr(ran.value, "found", getattr(ran.value, "ok", None))  # MpccResult.found; StepPlan.ok
    return None if ok or st == "ok" else f"status {st!r} for a legitimate far obstacle"


@functools.cache
def _alip() -> Any:
    from lipmpcc.planners.alip_mpc import AlipMpc

    return AlipMpc()


def _alip_solve(dcm: Any, stance: Any, side: Any, t: Any, stones: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        p = _alip()
        p.reset()
        return p.solve(dcm, stance, side, t, stones)
    return run


def _stones() -> Any:
    from lipmpcc.terrain import make_profile

    return make_profile("I")


def _alip_stones_solve(*args: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        p = _alip()
        p.reset()
        a = list(args)
        return p.solve(*a[:4], _stones() if a[4] == "S" else a[4])
    return run


def _plan_bad(planner: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        p = _mpcc() if planner == "mpcc" else _alip()
        return p.plan("not an input")
    return run


PLANNERS = [
    api("MpccPlanner-solve-str", "api-planners", _solve("abc", 1), ("x0",)),
    api("MpccPlanner-solve-nan", "api-planners", _solve([0, NAN, 0, 0, 0], 1), ("x0",)),
    api("MpccPlanner-solve-shape", "api-planners", _solve([0, 0, 0, 0], 1), ("x0",)),
    api("MpccPlanner-solve-side-0", "api-planners", _solve(X0, 0), ("stance_side",)),
    api("MpccPlanner-solve-obstacles-int", "api-planners", _solve(X0, 1, [1]), ("obstacles",)),
    api("MpccPlanner-solve-t_now-nan", "api-planners", _solve(X0, 1, (), NAN), ("t_now",)),
    api("MpccPlanner-solve-theta-nan", "api-planners", _solve(X0, 1, (), 0.0, NAN), ("theta",)),
    api("MpccPlanner-solve-side-str", "api-planners", _solve(X0, "left"), ("stance_side",),
        question="'left' could be accepted like the ALIP planners' sides; expected refused or accepted, not a crash"),
    api("MpccPlanner-path-str", "api-planners", call("lipmpcc.planners.mpcc:MpccPlanner", "circle"), ("path",)),
    api("MpccPlanner-params-str", "api-planners", lambda t: _resolve("lipmpcc.planners.mpcc:MpccPlanner")(
        _resolve(ARC + ".circle")(2.0), "fast"), ("params",)),
    api("MpccPlanner-plan-str", "api-planners", _plan_bad("mpcc"), ("inp",)),
    api("MpccPlanner-far-obstacle", "api-planners", _far_obstacle_solve, (), "ok", check=_solve_ok, timeout=60),
    api("AlipMpc-solve-dcm-nan", "api-planners", _alip_stones_solve([NAN, 0.0], [1.05, 0.14], 1, 0.0, "S"),
        ("dcm",)),
    api("AlipMpc-solve-stance-shape", "api-planners", _alip_stones_solve([1.1, 0.0], [1.05], 1, 0.0, "S"),
        ("stance",)),
    api("AlipMpc-solve-side-middle", "api-planners", _alip_stones_solve([1.1, 0.0], [1.05, 0.14], "middle", 0.0, "S"),
        ("middle",)),
    api("AlipMpc-solve-t-negative", "api-planners", _alip_stones_solve([1.1, 0.0], [1.05, 0.14], 1, -1.0, "S"),
        ("t_since_touchdown",)),
    api("AlipMpc-solve-stones-empty", "api-planners", _alip_stones_solve([1.1, 0.0], [1.05, 0.14], 1, 0.0, []),
        ("stones",)),
    api("AlipMpc-solve-stones-str", "api-planners", _alip_stones_solve([1.1, 0.0], [1.05, 0.14], 1, 0.0, "abc"),
        ("stones",)),
    api("AlipMpc-solver-foo", "api-planners", call("lipmpcc.planners.alip_mpc:AlipMpc", None, "foo"), ("foo",)),
    api("AlipMpc-plan-str", "api-planners", _plan_bad("alip"), ("inp",)),
    api("AlipQp-params-str", "api-planners", call("lipmpcc.planners.alip_qp:AlipQp", "fast"), ("params",)),
    api("CapturePoint-plan-none", "api-planners",
        lambda t: _resolve("lipmpcc.planners.capture_point:CapturePointPlanner")().plan(None), ("inp",)),
]


# ---- the whole-body controller and its reference ---------------------------------------------------
@functools.cache
def robot() -> Any:
    from lipmpcc.robots import load_robot

    return load_robot("digit_like")


@functools.cache
def _wbc_and_state() -> tuple[Any, Any]:
    from lipmpcc.control.wbc import WholeBodyController
    from lipmpcc.sim.robot_sim import RobotSim

    w = WholeBodyController(robot(), threaded=False)
    m = RobotSim(robot()).measure()
    return w, m


def _ref(**kw: Any) -> Any:
    from lipmpcc.control.wbc_types import WbcReference

    w, m = _wbc_and_state()
    base = dict(com_pos=np.asarray(m.com), arm_posture=np.zeros(w.n_arm),
                foot_pos=np.array([m.feet[0].position, m.feet[1].position]))
    base.update(kw)
    return WbcReference(**base)


def _wbc_solve(q: Any = None, v: Any = None, after: Callable[[Any], None] | None = None, **ref: Any) -> Callable:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        w, m = _wbc_and_state()
        r = _ref(**ref)
        if after is not None:
            after(r)
        return w.solve(m.q if q is None else q, m.v if v is None else v, r)
    return run


def _set_contact_true(r: Any) -> None:
    r.contact = True


def _wbc_new(*args: Any, **kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.control.wbc import WholeBodyController

        return WholeBodyController(*(args or (robot(),)), **kw)
    return run


def _q_bad(kind: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        w, m = _wbc_and_state()
        q = np.array(m.q)
        if kind == "nan":
            q[7] = NAN
        elif kind == "shape":
            q = q[:-1]
        elif kind == "quat":
            q[3:7] = 0.0
        v = m.v.tolist() if kind == "vlist" else m.v
        return w.solve(q, v, _ref())
    return run


WBC = [
    api("WbcReference-contact-True", "api-wbc", _wbc_solve(after=_set_contact_true), ("contact",)),
    api("WbcReference-contact-str", "api-wbc", _wbc_solve(contact="both"), ("contact",)),
    api("WbcReference-com-2", "api-wbc", _wbc_solve(com_pos=np.zeros(2)), ("com_pos",)),
    api("WbcReference-com-nan", "api-wbc", _wbc_solve(com_pos=np.array([0.0, NAN, 0.9])), ("com_pos",)),
    api("WbcReference-foot-shape", "api-wbc", _wbc_solve(foot_pos=np.zeros(3)), ("foot_pos",)),
    api("WbcReference-max-force-negative", "api-wbc", _wbc_solve(max_normal_force=(-1.0, 100.0)),
        ("max_normal_force",)),
    api("WbcReference-torso-zeros", "api-wbc", _wbc_solve(torso_rot=np.zeros((3, 3))), ("torso_rot",),
        question="a zero matrix as a rotation: expected refused (not orthonormal); judgment call on the tolerance"),
    api("WbcReference-arm-str", "api-wbc", _wbc_solve(arm_posture="down"), ("arm_posture",)),
    api("Wbc-solve-q-nan", "api-wbc", _q_bad("nan"), ("q",)),
    api("Wbc-solve-q-shape", "api-wbc", _q_bad("shape"), ("q",)),
    api("Wbc-solve-q-quat-zero", "api-wbc", _q_bad("quat"), ("q",)),
    api("Wbc-solve-v-list", "api-wbc", _q_bad("vlist"), ("v",),
        question="a list v could be converted; the docstring asks for a float64 array: refused or accepted, no crash"),
    api("Wbc-robot-unknown", "api-wbc", _wbc_new("no_such_robot"), ("no_such_robot",)),
    api("Wbc-params-str", "api-wbc", _wbc_new(params="fast"), ("params",)),
    api("Wbc-loop-formulation", "api-wbc", _wbc_new(loop_formulation="x"), ("loop_formulation",)),
    api("Wbc-friction-negative", "api-wbc", _wbc_new(friction=-1.0), ("friction",)),
    api("Wbc-friction-nan", "api-wbc", _wbc_new(friction=NAN), ("friction",)),
    api("Wbc-threaded-str", "api-wbc", _wbc_new(threaded="yes"), ("threaded",)),
]


# ---- loops and lipmpcc.run -------------------------------------------------------------------------
def _lip_loop(planner: Any = "mpcc", x0: Any = None, n: Any = 3, **kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.loops.lip import run_lip_loop

        p = _mpcc() if planner == "mpcc" else planner
        return run_lip_loop(p, X0 if x0 is None else x0, n, path=_mpcc().path, **kw)
    return run


def _alip_loop(planner: Any = "alip", seq: Any = "S") -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.loops.alip import run_alip_loop

        return run_alip_loop(_alip() if planner == "alip" else planner, _stones() if seq == "S" else seq)
    return run


def _fb_run(planner: Any = None, **kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.loops.fullbody import FullBodyLoop, LoopParams

        args = {k: v for k, v in kw.items() if k != "helper"}
        return FullBodyLoop(robot(), planner, LoopParams(helper_thread=kw.get("helper"))).run(**args)
    return run


def _pushes(*pushes: tuple) -> list:
    from lipmpcc.push import Push

    return [Push(*p) for p in pushes]


def _fb_push(force: float, duration: float) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        return _fb_run(duration=duration, pushes=_pushes(((force, 0.0), 0.1, 0.05)))(tmp)
    return run


def _has_report_fields(ran: Ran) -> str | None:
    res = ran.value
    miss = [a for a in ("relaxed_solves", "warnings") if not hasattr(res, a)]
    return f"the loop result has no {miss}" if miss else None


def _diverged_reported(ran: Ran) -> str | None:
    res = ran.value
    warnings = getattr(res, "warnings", None)
    if not warnings or not any("mujoco" in str(w).lower() for w in warnings):
        return f"no MuJoCo warning after a 1e9 N push (warnings = {warnings!r})"
    if res.fell and not (math.isnan(res.fall_time) or res.fall_time >= 0.1):
        return f"a fall at {res.fall_time:.3f} s, before the push at 0.1 s"
    return None


def _ctrlrange_zero(tmp: Path) -> Any:
    from lipmpcc.loops.fullbody import FullBodyLoop
    from lipmpcc.robots import load_robot

    xml = (REPO / "data" / "models" / "digit_like" / "digit_like.xml").read_text()
    xml = xml.replace('ctrlrange="-113.0000 113.0000"', 'ctrlrange="0 0"', 1)
    (tmp / "zero.xml").write_text(xml)
    from lipmpcc.exceptions import LipmpccError

    try:
        desc = load_robot(tmp / "zero.xml", layout="digit_like")
        return FullBodyLoop(desc).run(duration=0.05)
    except LipmpccError as exc:  # a refusal naming the motor is as good as a warning
        if "left_hip_roll" in str(exc):
            return f"refused: {exc}"
        raise


def _ctrlrange_warned(ran: Ran) -> str | None:
    if isinstance(ran.value, str) and ran.value.startswith("refused:"):
        return None
    w = getattr(ran.value, "warnings", None) or []
    return None if any("left_hip_roll" in str(x) for x in w) else f"no warning naming left_hip_roll (warnings = {w!r})"


def _studies_run(**kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from lipmpcc.studies import RunOptions, run as run_study

        return run_study(RunOptions(out=str(tmp / "out"), **kw))
    return run


def _sim_step(ctrl: Any, n: Any = 1) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.sim.robot_sim import RobotSim

        sim = RobotSim(robot())
        c = np.zeros(sim.model.nu) if isinstance(ctrl, str) and ctrl == "zeros" else ctrl
        return sim.step(c, n)
    return run


LOOPS = [
    api("run_lip_loop-planner-None", "api-loops", _lip_loop(None), ("planner",)),
    api("run_lip_loop-x0-nan", "api-loops", _lip_loop(x0=np.array([0, NAN, 0, 0, 0])), ("x0",)),
    api("run_lip_loop-n-zero", "api-loops", _lip_loop(n=0), ("n_steps",)),
    api("run_lip_loop-n-float", "api-loops", _lip_loop(n=2.5), ("n_steps",)),
    api("run_lip_loop-n-absurd", "api-loops", _lip_loop(n=10 ** 11), ("n_steps",),
        question="absurd sizes in the API: expected refused up front (a warning would also satisfy the issue)"),
    api("run_lip_loop-side-middle", "api-loops", _lip_loop(first_side="middle"), ("middle",)),
    api("run_lip_loop-pushes-int", "api-loops", _lip_loop(pushes=[1]), ("pushes",)),
    api("run_lip_loop-height-negative", "api-loops", _lip_loop(com_height=-0.9), ("com_height",)),
    api("run_alip_loop-planner-None", "api-loops", _alip_loop(None), ("planner",)),
    api("run_alip_loop-seq-str", "api-loops", _alip_loop(seq="stones"), ("sequence",)),
    api("FullBodyLoop-planner-str", "api-loops",
        lambda t: _resolve("lipmpcc.loops.fullbody:FullBodyLoop")(robot(), "mpcc"), ("planner",)),
    api("FullBodyLoop-run-no-length", "api-loops", _fb_run(), ("duration",)),
    api("FullBodyLoop-run-negative", "api-loops", _fb_run(duration=-1.0), ("duration",)),
    api("FullBodyLoop-run-nan", "api-loops", _fb_run(duration=NAN), ("duration",)),
    api("FullBodyLoop-run-pushes-int", "api-loops", _fb_run(duration=0.1, pushes=[1]), ("pushes",)),
    api("FullBodyLoop-run-absurd", "api-loops", _fb_run(duration=1e9), (("1e+09", "1e9", "1000000000"),),
        question="absurd sizes in the API: expected refused up front"),
    api("FullBodyLoop-push", "api-loops", _fb_push(50.0, 0.3), (), "ok", check=_has_report_fields, timeout=60),
    api("FullBodyLoop-push-helper-thread", "api-loops",
        lambda t: _fb_run(duration=0.3, helper=True, pushes=_pushes(((80.0, 0.0), 0.1, 0.05)))(t), (), "ok",
        check=_has_report_fields, timeout=60),
    api("FullBodyLoop-push-1e9N", "api-loops", _fb_push(1e9, 0.2), (), "ok", check=_diverged_reported, timeout=20,
        question="a diverged simulation: the run ends (today one tick takes ~40 s: a hang at 20 s) with a MuJoCo "
                 "warning and a fall not before the push"),
    api("FullBodyLoop-ctrlrange-zero", "api-loops", _ctrlrange_zero, ("left_hip_roll",), "ok", check=_ctrlrange_warned,
        timeout=60, question="ctrlrange='0 0' (unlimited torque): a warning naming the motor, or a refusal naming it"),
    api("RobotSim-step-shape", "api-loops", _sim_step(np.zeros(3)), ("ctrl",)),
    api("RobotSim-step-nan", "api-loops", _sim_step(np.full(20, NAN)), ("ctrl",)),
    api("RobotSim-step-n-zero", "api-loops", _sim_step("zeros", 0), ("n",)),
    api("run-option-not-applying", "api-loops", _studies_run(scenario="circle", obstacle_speed=0.3),
        (("obstacle_speed", "obstacle-speed"),), question="lipmpcc.run in Python refuses what the CLI refuses (one validation layer)"),
    api("run-scenario-unknown", "api-loops", _studies_run(scenario="marathon"), ("marathon",)),
    api("run-steps-str", "api-loops", _studies_run(scenario="circle", steps="3"), ("steps",)),
]

CASES: list[Case] = PARAMS + GEOMETRY + PLANNERS + WBC + LOOPS
