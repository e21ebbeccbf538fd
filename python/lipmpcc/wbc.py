"""Whole-body QP controller: the validating Python face of the C++ core ``lipmpcc._wbc``.

One control tick solves, for the current state (q, v) and a :class:`WbcReference`, a dense QP in

    x = [q̈ (nv); w_left (6, if in contact); w_right (6, if in contact)]

with ``w = [f; τ]`` the ground wrench at a sole frame in world axes (C++ ``cpp/wbc/``, Pinocchio for
the dynamics terms, proxsuite dense warm-started across ticks; ``cpp/wbc/include/lipmpcc/wbc/qp.hpp``
states every row). The cost is a weighted least-squares over the tasks

- COM position (3), torso orientation (3), swing-foot position (3) and orientation (3) for a foot
  not in contact: desired acceleration ``a* = a_ref + kp (x_ref - x) + kd (v_ref - v)``
  (orientation error ``log3(R_ref Rᵀ)``, world axes);
- a constant arm posture (per arm joint, ``q̈* = kp (q_ref - q) - kd q̇``);
- centroidal angular momentum damped toward zero (``k̇* = -kd k``);
- small regularisation on q̈ and on the wrenches,

subject to the unactuated (floating-base, passive-joint) rows of ``M q̈ + h = B u + J_cᵀ w``, no slip
of each stance foot (``J_c q̈ + J̇_c v = 0``), a friction pyramid, the CoP inside the (shrunk) sole
rectangle, a torsion bound, ``fz_min ≤ fz ≤ fz_max`` and the motor bounds ``u_min ≤ u ≤ u_max`` with
``u = B⁺(M q̈ + h - J_cᵀ w)``. The actuator efforts u follow from the solution.

Closed kinematic loops (a Digit v3-style file: rods at the knees and toes) come from the MJCF's
``<equality connect>`` constraints, which Pinocchio parses as point-anchor constraints. Each is a
holonomic equality on the accelerations, ``J_loop q̈ + J̇_loop v = 0``, with the loop forces
``J_loopᵀ λ`` in the dynamics: ``M q̈ + h = B u + J_cᵀ w + J_loopᵀ λ``. By default
(``loop_formulation="eliminate"``) the loop-dependent accelerations (passive joints and rods, chosen
once) are solved from the loop rows, ``q̈ = Z a + z0``, and the QP runs in the independent ones —
the same optimum as keeping λ as QP variables (``"multipliers"``), in a smaller QP. Passive joints
(a stiffness and no motor, e.g. Digit's shin and heel springs) carry zero motor torque and their
spring torque ``-k (q - q_spring)`` (in ``h``, with the joint damping). Motor efforts, not joint
torques, are bounded: each motor drives its joint through the gear of its MuJoCo transmission.
The floating base is a free joint or the 3 slides + ball joint of the Digit v3 file.

Conventions:

- State: Pinocchio's (q, v) for the model built from the same MJCF the simulator loads: quaternion
  (x, y, z, w) at ``q[3:7]``, free-flyer velocity in the base frame; for a slide+ball base, the
  slide velocities (world) then the ball's angular velocity (base frame)
  (``RobotSim.pinocchio_state()``).
- Actuation: actuator k applies the generalised force ``gear_k · gain_k · u_k`` on its joint (MuJoCo
  ``motor`` actuators); ``u`` is the MuJoCo ``ctrl`` vector, bounded by ``ctrlrange`` (and
  ``forcerange``). For ``digit_like`` (gear 1) u is the joint torque [N m].
- Friction: unless given, the pyramid coefficient is the smallest sliding friction of the foot geoms,
  halved for MuJoCo's pyramidal cone (whose section is a diamond) or divided by √2 for the elliptic
  cone, so that the pyramid lies inside MuJoCo's cone.

Robustness: a QP failure (any status other than solved, a non-finite solution, a solver exception)
never raises. The controller then returns ``u_last - fallback_damping · Bᵀ v`` clipped to the motor
bounds, where ``u_last`` is the last successful solution (zero before the first), sets
``used_fallback`` and counts it in :attr:`WholeBodyController.qp_failures`. Invalid *input* (wrong
shape or dtype, NaN, a reference rotation that is not a rotation) raises
:class:`~lipmpcc.exceptions.InvalidInputError` / :class:`~lipmpcc.exceptions.StateError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .config import threads_enabled
from .exceptions import (
    InvalidInputError,
    ModelFileError,
    ParameterError,
    RobotDescriptionError,
    StateError,
)
from .robot import RobotDescription, compile_mjcf, load_robot

try:
    from . import _wbc
except ImportError as _err:  # pragma: no cover - depends on the build
    raise ImportError(
        "lipmpcc._wbc (the C++ whole-body QP) is not built or cannot load its libraries: install the "
        f"package with `pip install .` ({_err})"
    ) from _err

__all__ = [
    "TaskGains",
    "PostureGains",
    "WbcParams",
    "WbcReference",
    "WbcTaskErrors",
    "WbcOutput",
    "WholeBodyController",
]

LEFT, RIGHT = 0, 1
_F64 = np.dtype(np.float64)  # the float64 descriptor (``a.dtype is _F64`` is a fast exact-type test)
_STATUS_NAMES = {int(s): _wbc.status_name(s) for s in _wbc.QpStatus.__members__.values()}


# ------------------------------------------------------------------------------------------------
# Parameters (immutable)
# ------------------------------------------------------------------------------------------------
def _triple(name: str, value: float | Sequence[float]) -> tuple[float, float, float]:
    arr = np.asarray(value, dtype=float)
    if arr.shape == ():
        arr = np.full(3, float(arr))
    if arr.shape != (3,) or not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise ParameterError(name, value, "a finite number >= 0 or three of them (x, y, z)")
    return (float(arr[0]), float(arr[1]), float(arr[2]))


@dataclass(frozen=True)
class TaskGains:
    """Weight and PD gains of a 3-D task (scalars apply to x, y and z alike).

    The task asks ``J q̈ + J̇ v`` to equal ``a* = a_ref + kp (x_ref - x) + kd (v_ref - v)``; its cost
    is ``0.5 Σ_i weight_i (J q̈ + J̇ v - a*)_i²``.

    Attributes:
        weight: cost weight (per axis).
        kp: stiffness [1/s²] (per axis).
        kd: damping [1/s] (per axis).
    """

    weight: float | tuple[float, float, float] = 1.0
    kp: float | tuple[float, float, float] = 0.0
    kd: float | tuple[float, float, float] = 0.0

    def __post_init__(self) -> None:
        for name in ("weight", "kp", "kd"):
            object.__setattr__(self, name, _triple(name, getattr(self, name)))

    def _to_cpp(self) -> Any:
        g = _wbc.TaskGains()
        g.weight = np.asarray(self.weight)
        g.kp = np.asarray(self.kp)
        g.kd = np.asarray(self.kd)
        return g


@dataclass(frozen=True)
class PostureGains:
    """Weight and PD gains of the arm-posture task (the same for every arm joint).

    Attributes:
        weight: cost weight.
        kp: stiffness [1/s²].
        kd: damping [1/s].
    """

    weight: float = 1.0
    kp: float = 100.0
    kd: float = 20.0

    def __post_init__(self) -> None:
        for name in ("weight", "kp", "kd"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ParameterError(f"arm_posture.{name}", v, "a finite number >= 0")


def _positive(name: str, v: Any, *, strict: bool = True, upper: float | None = None) -> None:
    ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
    ok = ok and (v > 0 if strict else v >= 0) and (upper is None or v <= upper)
    if not ok:
        bound = "> 0" if strict else ">= 0"
        if upper is not None:
            bound += f" and <= {upper:g}"
        raise ParameterError(name, v, f"a finite number {bound}")


@dataclass(frozen=True)
class WbcParams:
    """Weights, gains, regularisation and solver settings of the whole-body QP (immutable).

    The defaults hold ``digit_like`` standing and track walking references at 400 Hz.

    Attributes:
        com: COM position task; gains on the COM error [m].
        torso: torso orientation task; gains on ``log3(R_ref Rᵀ)`` [rad].
        swing_position: swing sole position task [m].
        swing_orientation: swing sole orientation task [rad].
        arm_posture: posture task of each arm joint [rad].
        angular_momentum_weight: weight of the centroidal angular momentum task.
        angular_momentum_kd: [1/s] the task asks ``k̇ = -kd k``.
        qdd_regularization: weight on ``|q̈|²`` (> 0: strict convexity).
        force_regularization: weight on ``|w|²`` of the contact wrenches (> 0).
        min_normal_force: [N] lower bound of the normal force of a foot in contact.
        cop_safety_factor: the CoP stays within this fraction of the sole half-length/width, in (0, 1].
        contact_velocity_gain: [1/s] no-slip rows ``J q̈ + J̇ v = -gain · J v`` (0: pure no-slip).
        spring_damping_gain: [1/s] rigid passive springs are held at ``q̈_s = -gain · q̇_s``: the
            controller damps the spring mode it does not model (0: ``q̈_s = 0``).
        friction_compensation_velocity: [rad/s] the joints' dry friction (MuJoCo ``frictionloss``)
            is compensated as ``f · tanh(v / this)`` in the bias forces (> 0).
        qp_eps_abs: proxsuite absolute tolerance.
        qp_max_iter: proxsuite limit on outer and on inner iterations per solve (bounds the time
            of a failing solve).
        fallback_damping: [N m s/rad] damping of the fallback efforts ``u_last - d · Bᵀ v``.
    """

    com: TaskGains = TaskGains(weight=(100.0, 100.0, 100.0), kp=(100.0, 100.0, 100.0), kd=(20.0, 20.0, 20.0))
    torso: TaskGains = TaskGains(weight=50.0, kp=100.0, kd=20.0)
    swing_position: TaskGains = TaskGains(weight=100.0, kp=400.0, kd=40.0)
    swing_orientation: TaskGains = TaskGains(weight=20.0, kp=200.0, kd=28.0)
    arm_posture: PostureGains = PostureGains(weight=1.0, kp=100.0, kd=20.0)
    angular_momentum_weight: float = 0.01
    angular_momentum_kd: float = 5.0
    qdd_regularization: float = 1e-3
    force_regularization: float = 1e-5
    min_normal_force: float = 0.0
    cop_safety_factor: float = 0.9
    contact_velocity_gain: float = 0.0
    spring_damping_gain: float = 60.0
    friction_compensation_velocity: float = 0.02
    qp_eps_abs: float = 1e-6
    qp_max_iter: int = 50
    fallback_damping: float = 1.0

    def __post_init__(self) -> None:
        for name in ("com", "torso", "swing_position", "swing_orientation"):
            if not isinstance(getattr(self, name), TaskGains):
                raise ParameterError(name, getattr(self, name), "a TaskGains")
        if not isinstance(self.arm_posture, PostureGains):
            raise ParameterError("arm_posture", self.arm_posture, "a PostureGains")
        _positive("angular_momentum_weight", self.angular_momentum_weight, strict=False)
        _positive("angular_momentum_kd", self.angular_momentum_kd, strict=False)
        _positive("qdd_regularization", self.qdd_regularization)
        _positive("force_regularization", self.force_regularization)
        _positive("min_normal_force", self.min_normal_force, strict=False)
        _positive("cop_safety_factor", self.cop_safety_factor, upper=1.0)
        _positive("contact_velocity_gain", self.contact_velocity_gain, strict=False)
        _positive("spring_damping_gain", self.spring_damping_gain, strict=False)
        _positive("friction_compensation_velocity", self.friction_compensation_velocity)
        _positive("qp_eps_abs", self.qp_eps_abs)
        if not (isinstance(self.qp_max_iter, (int, np.integer)) and self.qp_max_iter >= 1):
            raise ParameterError("qp_max_iter", self.qp_max_iter, "an integer >= 1")
        _positive("fallback_damping", self.fallback_damping, strict=False)

    @classmethod
    def for_robot(cls, robot: RobotDescription) -> "WbcParams":
        """The defaults with the robot description's ``wbc_overrides`` applied.

        Raises:
            ParameterError: an override that is not a field of :class:`WbcParams`, or a bad value.
        """
        items = robot.wbc_overrides.items() if isinstance(robot.wbc_overrides, dict) else robot.wbc_overrides
        kwargs = dict(items or ())
        unknown = sorted(set(kwargs) - set(cls.__dataclass_fields__))
        if unknown:
            fields = ", ".join(cls.__dataclass_fields__)
            raise ParameterError("wbc_overrides", unknown, f"fields of WbcParams ({fields})")
        for name in ("com", "torso", "swing_position", "swing_orientation"):
            if isinstance(kwargs.get(name), dict):
                kwargs[name] = TaskGains(**kwargs[name])
        if isinstance(kwargs.get("arm_posture"), dict):
            kwargs["arm_posture"] = PostureGains(**kwargs["arm_posture"])
        return cls(**kwargs)

    def _to_cpp(self) -> Any:
        p = _wbc.WbcParams()
        p.com = self.com._to_cpp()
        p.torso = self.torso._to_cpp()
        p.swing_position = self.swing_position._to_cpp()
        p.swing_orientation = self.swing_orientation._to_cpp()
        a = _wbc.ScalarTaskGains()
        a.weight, a.kp, a.kd = self.arm_posture.weight, self.arm_posture.kp, self.arm_posture.kd
        p.arm_posture = a
        p.angular_momentum_weight = float(self.angular_momentum_weight)
        p.angular_momentum_kd = float(self.angular_momentum_kd)
        p.qdd_regularization = float(self.qdd_regularization)
        p.force_regularization = float(self.force_regularization)
        p.min_normal_force = float(self.min_normal_force)
        p.cop_safety_factor = float(self.cop_safety_factor)
        p.contact_velocity_gain = float(self.contact_velocity_gain)
        p.spring_damping_gain = float(self.spring_damping_gain)
        p.friction_compensation_velocity = float(self.friction_compensation_velocity)
        p.qp_eps_abs = float(self.qp_eps_abs)
        p.qp_max_iter = int(self.qp_max_iter)
        p.fallback_damping = float(self.fallback_damping)
        return p


# ------------------------------------------------------------------------------------------------
# Reference (mutable, one per tick) and output
# ------------------------------------------------------------------------------------------------
def _eye2() -> np.ndarray:
    return np.stack([np.eye(3), np.eye(3)])


@dataclass
class WbcReference:
    """Desired motion for one tick, world frame. Per-foot fields: row 0 left, row 1 right.

    A foot with ``contact[i]`` True is a stance foot (no-slip, wrench variables): its swing fields are
    ignored. Array fields accept any array-like of the right shape (lists of per-foot vectors too).

    Attributes:
        contact: (left, right) support flags.
        com_pos, com_vel, com_acc: COM reference (3,) [m, m/s, m/s²].
        torso_rot: torso orientation (3, 3) (columns: torso axes in the world).
        torso_angvel, torso_angacc: (3,) [rad/s, rad/s²], world axes.
        foot_pos, foot_vel, foot_acc: sole references (2, 3) [m, m/s, m/s²].
        foot_rot: sole orientations (2, 3, 3).
        foot_angvel, foot_angacc: (2, 3) [rad/s, rad/s²], world axes.
        arm_posture: (n_arm,) [rad] arm joint angles, in the robot's ``arm_joints`` order.
        max_normal_force: (2,) [N] normal force bound per stance foot (load ramps); inf: none.
    """

    contact: Sequence[bool] = (True, True)
    com_pos: Any = field(default_factory=lambda: np.zeros(3))
    com_vel: Any = field(default_factory=lambda: np.zeros(3))
    com_acc: Any = field(default_factory=lambda: np.zeros(3))
    torso_rot: Any = field(default_factory=lambda: np.eye(3))
    torso_angvel: Any = field(default_factory=lambda: np.zeros(3))
    torso_angacc: Any = field(default_factory=lambda: np.zeros(3))
    foot_pos: Any = field(default_factory=lambda: np.zeros((2, 3)))
    foot_vel: Any = field(default_factory=lambda: np.zeros((2, 3)))
    foot_acc: Any = field(default_factory=lambda: np.zeros((2, 3)))
    foot_rot: Any = field(default_factory=_eye2)
    foot_angvel: Any = field(default_factory=lambda: np.zeros((2, 3)))
    foot_angacc: Any = field(default_factory=lambda: np.zeros((2, 3)))
    arm_posture: Any = field(default_factory=lambda: np.zeros(0))
    max_normal_force: Any = (math.inf, math.inf)


@dataclass(frozen=True)
class WbcTaskErrors:
    """Task errors of one tick (reference minus measured), world frame.

    Attributes:
        com_pos: [m] (3,).
        com_vel: [m/s] (3,).
        torso_rot: [rad] (3,) ``log3(R_ref Rᵀ)``.
        torso_angvel: [rad/s] (3,).
        foot_pos: [m] (2, 3); zero for a stance foot.
        foot_rot: [rad] (2, 3); zero for a stance foot.
        arm_posture: [rad] (n_arm,).
        angular_momentum: measured centroidal angular momentum [kg m²/s] (3,).
    """

    com_pos: np.ndarray
    com_vel: np.ndarray
    torso_rot: np.ndarray
    torso_angvel: np.ndarray
    foot_pos: np.ndarray
    foot_rot: np.ndarray
    arm_posture: np.ndarray
    angular_momentum: np.ndarray


@dataclass(frozen=True)
class WbcOutput:
    """Result of one tick.

    Attributes:
        tau: (nu,) actuator efforts u, in MuJoCo actuator order (= ``ctrl``; joint torques [N m] for
            ``digit_like``).
        tau_joint: (nv,) generalised actuation force ``B u``.
        qdd: (nv,) joint accelerations of the QP solution (zeros after a fallback).
        wrenches: (2, 6) ground wrench ``[f (N); τ (N m)]`` at each sole, world axes (zeros when
            the foot is not in contact or after a fallback).
        status: QP status name (``"solved"``, ``"max_iter_reached"``, ``"primal_infeasible"``, ...).
        status_code: its integer code (0 = solved).
        iterations: proxsuite iterations.
        solve_time_us: QP update + solve time [µs].
        tick_time_us: C++ time of the whole tick (dynamics, assembly, solve, efforts) [µs].
        used_fallback: True when ``tau`` is the fallback (the QP failed).
        errors: the :class:`WbcTaskErrors`.
        loop_forces: (3 per loop) [N] loop-closure forces λ, world axes; empty for a
            tree-structured model, zeros after a fallback.
        spring_torques: (one per spring joint, MuJoCo joint order) [N m] torque of each spring
            joint: ``-k (q - q_spring)``, plus the holding torque the QP plans for a rigid passive
            spring (``spring_model="rigid"``). With them, ``M q̈ + h₀ = B u + J_cᵀ w + J_loopᵀ λ +
            S_springᵀ spring_torques`` (h₀: the bias and damping forces).
    """

    tau: np.ndarray
    tau_joint: np.ndarray
    qdd: np.ndarray
    wrenches: np.ndarray
    status: str
    status_code: int
    iterations: int
    solve_time_us: float
    tick_time_us: float
    used_fallback: bool
    errors: WbcTaskErrors
    loop_forces: np.ndarray = field(default_factory=lambda: np.zeros(0))
    spring_torques: np.ndarray = field(default_factory=lambda: np.zeros(0))


# ------------------------------------------------------------------------------------------------
# Input checks
# ------------------------------------------------------------------------------------------------
def _array(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    """float64 array of ``shape`` from an array-like (no copy when already right); shape checked."""
    if type(value) is np.ndarray and value.dtype is _F64:
        arr = value
    else:
        try:
            arr = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise InvalidInputError(name, value, f"an array of shape {shape} of numbers") from None
    if arr.shape != shape:
        raise InvalidInputError(name, f"array of shape {arr.shape}", f"an array of shape {shape}")
    return arr


def _frozen(cls: type, **fields: Any) -> Any:
    """An instance of the frozen dataclass ``cls`` from all its fields, without the per-field
    ``object.__setattr__`` of the generated ``__init__`` (per-tick outputs built from trusted data)."""
    obj = object.__new__(cls)
    obj.__dict__.update(fields)
    return obj


def _state(name: str, value: Any, n: int) -> np.ndarray:
    if not isinstance(value, np.ndarray):
        raise StateError(name, type(value).__name__, f"a numpy float64 array of shape ({n},)")
    if value.dtype is not _F64 and value.dtype != np.float64:
        raise StateError(name, f"array of dtype {value.dtype}", f"a float64 array of shape ({n},)")
    if value.shape != (n,):
        raise StateError(name, f"array of shape {value.shape}", f"a float64 array of shape ({n},)")
    if not value.flags.c_contiguous:
        raise StateError(name, "a non-contiguous array", f"a C-contiguous float64 array of shape ({n},)")
    return value  # finiteness is checked in C++ (StateError from WholeBodyController.solve)


# ------------------------------------------------------------------------------------------------
# The controller
# ------------------------------------------------------------------------------------------------
class WholeBodyController:
    """The whole-body QP for one robot (wraps the C++ ``WbcModel`` + ``WbcSolver``).

    Args:
        robot: a :class:`~lipmpcc.robot.RobotDescription`, ``"digit_like"`` or an MJCF path
            (see :func:`~lipmpcc.robot.load_robot`). Pinocchio and the motor data are read from
            ``robot.mjcf_path``, the file the simulator's scene includes.
        params: :class:`WbcParams` (None: :meth:`WbcParams.for_robot`, the defaults with the
            robot description's ``wbc_overrides``).
        friction: friction-pyramid coefficient (None: from the foot geoms, see the module doc).
        loop_formulation: ``"eliminate"`` (default: the QP runs in the loop-independent
            accelerations) or ``"multipliers"`` (all accelerations, the loop rows as equalities and
            the loop forces as QP variables). Same optimum; only models with loops differ.
        spring_model: how passive springs (stiffness, no motor) enter the QP: ``"compliant"``
            (the joint moves under its known spring torque) or ``"rigid"`` (for the controller the
            spring joint is held, ``q̈_s = 0``, by a holding torque added to its known spring
            torque; the simulated spring deflects quasi-statically). None (default): ``"rigid"`` for
            a model with passive springs — the compliant QP cannot use the ground at a touch-down
            until the unloaded spring has deflected (see ``cpp/wbc/README.md``).
        threaded: whether :meth:`prepare` computes on a worker thread (None:
            :meth:`default_threaded`). Results do not depend on it.

    Raises:
        ModelFileError: the MJCF cannot be loaded (by MuJoCo or by Pinocchio).
        RobotDescriptionError: the model does not fit, with what is missing named (a non-motor
            actuator, a missing frame, a base that is neither a free joint nor 3 slides + a ball
            joint, an equality constraint other than ``connect``, loops that do not close, ...).
        ParameterError: bad ``params``, ``friction``, ``loop_formulation`` or ``threaded``.
    """

    @staticmethod
    def default_threaded() -> bool:
        """What ``threaded=None`` means: True when the process may use two CPUs or more and the
        environment variable ``LIPMPCC_WBC_THREAD`` is not ``0``."""
        return threads_enabled("LIPMPCC_WBC_THREAD")

    def __init__(
        self,
        robot: RobotDescription | str | Path = "digit_like",
        params: WbcParams | None = None,
        *,
        friction: float | None = None,
        loop_formulation: str = "eliminate",
        spring_model: str | None = None,
        threaded: bool | None = None,
    ) -> None:
        desc = robot if isinstance(robot, RobotDescription) else load_robot(robot)
        if params is None:
            params = WbcParams.for_robot(desc)
        if not isinstance(params, WbcParams):
            raise ParameterError("params", params, "a WbcParams or None")
        formulations = {"eliminate": _wbc.LoopFormulation.eliminate, "multipliers": _wbc.LoopFormulation.multipliers}
        if loop_formulation not in formulations:
            raise ParameterError("loop_formulation", loop_formulation, "'eliminate' or 'multipliers'")
        springs = {"compliant": _wbc.SpringModel.compliant, "rigid": _wbc.SpringModel.rigid}
        if spring_model is None:
            spring_model = "rigid"
        if spring_model not in springs:
            raise ParameterError("spring_model", spring_model, "'compliant', 'rigid' or None")
        self.description = desc
        self.params = params
        self.loop_formulation = loop_formulation
        self.spring_model = spring_model
        if threaded is None:
            threaded = self.default_threaded()
        if not isinstance(threaded, (bool, np.bool_)):
            raise ParameterError("threaded", threaded, "True, False or None")
        self.threaded = bool(threaded)
        mj = compile_mjcf(Path(desc.mjcf_path))
        _check_equalities(desc, mj)
        spec, self.actuator_names = _model_spec(desc, mj, friction)
        spec.loop_formulation = formulations[loop_formulation]
        spec.spring_model = springs[spring_model]
        q_ref = _loop_reference(desc, mj)
        spec.loop_reference_configuration = q_ref
        self.friction = float(spec.friction)
        try:
            self._model = _wbc.WbcModel(spec)
        except ValueError as err:
            raise RobotDescriptionError(str(desc.mjcf_path), [str(err)]) from None
        except RuntimeError as err:
            raise ModelFileError(str(desc.mjcf_path), str(err)) from None
        _check_consistency(desc, mj, self._model)
        self._solver = _wbc.WbcSolver(self._model, params._to_cpp())
        no_swing = np.zeros((2, 24))
        no_swing[:, 9:18] = np.eye(3).ravel()
        self._no_swing = no_swing.ravel()
        self._py_failures = 0
        self._u_last = np.zeros(self._model.nu)
        self.nq = int(self._model.nq)
        self.nv = int(self._model.nv)
        self.nu = int(self._model.nu)
        self.n_arm = int(self._model.n_arm)
        self.n_loop_rows = int(self._model.n_loop_rows)
        self.n_springs = len(self._model.spring_idx_v)
        self._arm_shape = (self.n_arm,)
        self._B = np.array(self._model.actuation)
        self._iq = int(self._model.base_quaternion_idx)
        if mj.neq > 0:
            _check_loops_close(desc, mj, self, q_ref)

    # ---- properties ----------------------------------------------------------------------
    @property
    def qp_failures(self) -> int:
        """Ticks that returned the fallback efforts since construction or :meth:`reset`."""
        return int(self._solver.qp_failures) + self._py_failures

    @property
    def mass(self) -> float:
        """Total mass of the Pinocchio model [kg]."""
        return float(self._model.mass)

    @property
    def actuation(self) -> np.ndarray:
        """Actuation matrix B (nv, nu): generalised force = B u."""
        return self._B.copy()

    @property
    def u_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """(u_min, u_max) actuator bounds (nu,) each."""
        return np.array(self._model.u_min), np.array(self._model.u_max)

    @property
    def joint_names(self) -> list[str]:
        """Pinocchio joint names (the free-flyer ``root``/base first), MJCF tree order."""
        return list(self._model.joint_names)

    @property
    def model(self) -> Any:
        """The C++ ``WbcModel`` (read-only properties: nq, nv, nu, sole_frames, loops, ...)."""
        return self._model

    @property
    def n_loops(self) -> int:
        """Number of closed kinematic loops (``<equality connect>`` constraints)."""
        return self.n_loop_rows // 3

    @property
    def base_quaternion_index(self) -> int:
        """Index of the base quaternion (x, y, z, w) in q."""
        return self._iq

    # ---- control -------------------------------------------------------------------------
    def reset(self) -> None:
        """Forget warm starts, the last efforts and the failure count."""
        self._solver.reset()
        self._py_failures = 0
        self._u_last = np.zeros(self.nu)

    def solve(self, q: np.ndarray, v: np.ndarray, ref: WbcReference) -> WbcOutput:
        """One control tick.

        Args:
            q: Pinocchio configuration, float64, C-contiguous, shape (nq,), base quaternion
                (x, y, z, w) at ``q[3:7]`` of unit norm (to 1e-3; it is normalised).
            v: Pinocchio velocity, float64, C-contiguous, shape (nv,).
            ref: the :class:`WbcReference`.

        Returns:
            The :class:`WbcOutput`. Never raises because the QP failed (see the module doc).

        Raises:
            StateError: bad q or v (type, dtype, shape, contiguity, NaN/inf, quaternion norm).
            InvalidInputError: a bad reference field (named in the message).
        """
        _state("q", q, self.nq)
        _state("v", v, self.nv)
        qx, qy, qz, qw = q[3:7].tolist()
        qn = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
        if not abs(qn - 1.0) <= 1e-3:  # also catches NaN
            raise StateError("q[3:7]", q[3:7], "a finite unit quaternion (x, y, z, w) (norm 1 +/- 1e-3)")
        if not isinstance(ref, WbcReference):
            raise InvalidInputError("ref", type(ref).__name__, "a WbcReference")
        contact = ref.contact
        if len(contact) != 2:
            raise InvalidInputError("ref.contact", contact, "two flags (left, right)")
        cl, cr = bool(contact[0]), bool(contact[1])
        packed = self._pack_reference(ref, cl and cr)
        try:
            res = self._solver.solve_packed(q, v, cl, cr, packed)
        except ValueError as err:  # C++ checks values: "<argument>: <what was expected>"
            name, _, expected = str(err).partition(": ")
            if name in ("q", "v"):
                raise StateError(name, q if name == "q" else v, expected) from None
            value = getattr(ref, name[4:], None) if name.startswith("ref.") else None
            raise InvalidInputError(name, value, expected) from None
        except Exception:  # noqa: BLE001 - the loop must go on: fallback
            return self._python_fallback(v)
        return self._unpack(*res)

    def prepare(self, q: np.ndarray, v: np.ndarray) -> None:
        """Start the first stage of the next :meth:`solve` at (q, v): the dynamics terms (one
        Pinocchio pass, spring and friction terms, loop elimination).

        With :attr:`threaded` the stage runs on a worker thread while the caller goes on (say,
        computing the reference); the next :meth:`solve` with equal ``q`` and ``v`` waits for it
        and skips the stage. Its results are identical to those of a :meth:`solve` without
        ``prepare``, which is also what a :meth:`solve` at another state gets. Invalid values are
        reported by that :meth:`solve`.

        Args:
            q, v: as for :meth:`solve`.

        Raises:
            StateError: q or v of the wrong type, dtype, shape or contiguity.
        """
        self._solver.prepare(_state("q", q, self.nq), _state("v", v, self.nv), self.threaded)

    def evaluate(self, q: np.ndarray, v: np.ndarray | None = None) -> dict[str, Any]:
        """Kinematic and dynamic terms at (q, v) without solving (``v`` None: zero).

        Returns a dict: ``com`` (3,), ``vcom``, ``p_sole`` [(3,), (3,)], ``R_sole``, ``R_torso``,
        ``M``, ``h``, ``J_sole``, ``J_com``, ... (see ``cpp/wbc/include/lipmpcc/wbc/dynamics.hpp``).
        """
        q = _state("q", q, self.nq)
        v = np.zeros(self.nv) if v is None else _state("v", v, self.nv)
        try:
            return self._solver.evaluate(q, v)
        except ValueError as err:
            raise StateError("q/v", "see message", str(err)) from None

    def last_qp(self) -> dict[str, Any]:
        """The QP of the last tick in proxsuite form (``0.5 xᵀHx + gᵀx``, ``Ax = b``,
        ``l <= Cx <= u``): keys H, g, A, b, C, l, u, n_var, n_eq, n_in, wrench_offset."""
        return self._solver.last_qp()

    def last_terms(self) -> dict[str, Any]:
        """The dynamics terms of the last tick (same keys as :meth:`evaluate`)."""
        return self._solver.last_terms()

    def last_reduced_terms(self) -> dict[str, Any]:
        """With eliminated loops: the terms in the independent accelerations the last QP was built
        from (M, h, Jacobians, drifts, ``qdd_metric``); see :meth:`last_terms`."""
        return self._solver.last_reduced_terms()

    def hold_reference(self, q: np.ndarray, contact: Sequence[bool] = (True, True)) -> WbcReference:
        """A reference that holds configuration ``q``: its COM, torso orientation, sole poses and
        arm posture, zero velocities and accelerations."""
        t = self.evaluate(q)
        arm = np.array([q[i] for i in self._model.arm_idx_q], dtype=float)
        return WbcReference(
            contact=tuple(bool(c) for c in contact),
            com_pos=np.array(t["com"]),
            torso_rot=np.array(t["R_torso"]),
            foot_pos=np.array(t["p_sole"]),
            foot_rot=np.array(t["R_sole"]),
            arm_posture=arm,
        )

    # ---- internals -----------------------------------------------------------------------
    def _pack_reference(self, ref: WbcReference, double_support: bool) -> np.ndarray:
        """The flat reference of ``_wbc.WbcSolver.solve_packed`` (layout in bind_solver.cpp)."""
        parts = [
            _array("ref.com_pos", ref.com_pos, (3,)),
            _array("ref.com_vel", ref.com_vel, (3,)),
            _array("ref.com_acc", ref.com_acc, (3,)),
            _array("ref.torso_rot", ref.torso_rot, (3, 3)).ravel(),
            _array("ref.torso_angvel", ref.torso_angvel, (3,)),
            _array("ref.torso_angacc", ref.torso_angacc, (3,)),
        ]
        if double_support:  # swing fields are ignored
            parts.append(self._no_swing)
        else:
            pos = _array("ref.foot_pos", ref.foot_pos, (2, 3))
            vel = _array("ref.foot_vel", ref.foot_vel, (2, 3))
            acc = _array("ref.foot_acc", ref.foot_acc, (2, 3))
            rot = _array("ref.foot_rot", ref.foot_rot, (2, 3, 3)).reshape(2, 9)
            angvel = _array("ref.foot_angvel", ref.foot_angvel, (2, 3))
            angacc = _array("ref.foot_angacc", ref.foot_angacc, (2, 3))
            parts.append(np.concatenate((pos, vel, acc, rot, angvel, angacc), axis=1).ravel())
        parts.append(_array("ref.max_normal_force", ref.max_normal_force, (2,)))
        parts.append(_array("ref.arm_posture", ref.arm_posture, self._arm_shape))
        return np.concatenate(parts)

    def _unpack(self, arr: np.ndarray, status: int, iterations: int, solve_us: float, tick_us: float,
                fallback: bool) -> WbcOutput:
        nu, nv, na = self.nu, self.nv, self.n_arm
        i = nu + 2 * nv
        e = i + 12  # errors start
        tau = arr[:nu]
        if not fallback:
            self._u_last = tau
        errors = _frozen(
            WbcTaskErrors,
            com_pos=arr[e:e + 3],
            com_vel=arr[e + 3:e + 6],
            torso_rot=arr[e + 6:e + 9],
            torso_angvel=arr[e + 9:e + 12],
            foot_pos=arr[e + 12:e + 18].reshape(2, 3),
            foot_rot=arr[e + 18:e + 24].reshape(2, 3),
            angular_momentum=arr[e + 24:e + 27],
            arm_posture=arr[e + 27:e + 27 + na],
        )
        lf = e + 27 + na
        return _frozen(
            WbcOutput,
            tau=tau,
            tau_joint=arr[nu:nu + nv],
            qdd=arr[nu + nv:i],
            wrenches=arr[i:i + 12].reshape(2, 6),
            status=_STATUS_NAMES.get(status, "unknown"),
            status_code=status,
            iterations=iterations,
            solve_time_us=solve_us,
            tick_time_us=tick_us,
            used_fallback=fallback,
            errors=errors,
            loop_forces=arr[lf:lf + self.n_loop_rows],
            spring_torques=arr[lf + self.n_loop_rows:lf + self.n_loop_rows + self.n_springs],
        )

    def _python_fallback(self, v: np.ndarray) -> WbcOutput:
        """Fallback when the C++ call itself raised (it should not): same rule as in C++."""
        self._py_failures += 1
        lo, hi = self.u_limits
        tau = np.clip(self._u_last - self.params.fallback_damping * (self._B.T @ v), lo, hi)
        z3 = np.zeros(3)
        return WbcOutput(
            tau=tau,
            tau_joint=self._B @ tau,
            qdd=np.zeros(self.nv),
            wrenches=np.zeros((2, 6)),
            status="exception",
            status_code=int(_wbc.QpStatus.exception),  # type: ignore[attr-defined]
            iterations=0,
            solve_time_us=0.0,
            tick_time_us=0.0,
            used_fallback=True,
            errors=WbcTaskErrors(z3, z3, z3, z3, np.zeros((2, 3)), np.zeros((2, 3)), np.zeros(self.n_arm), z3),
            loop_forces=np.zeros(self.n_loop_rows),
            spring_torques=np.zeros(self.n_springs),
        )


# ------------------------------------------------------------------------------------------------
# Model specification from the description + MuJoCo
# ------------------------------------------------------------------------------------------------
_EQ_NAMES = {0: "connect", 1: "weld", 2: "joint", 3: "tendon", 4: "flex"}


def _check_equalities(desc: RobotDescription, mj: Any) -> None:
    """Every equality constraint must be an active ``connect`` (a loop closure)."""
    import mujoco

    problems = []
    for e in range(mj.neq):
        name = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_EQUALITY, e) or f"equality {e}"
        kind = _EQ_NAMES.get(int(mj.eq_type[e]), str(int(mj.eq_type[e])))
        if kind != "connect":
            problems.append(f"an <equality connect> loop closure instead of the <equality {kind}> '{name}' "
                            "(only connect constraints are supported)")
        elif not bool(mj.eq_active0[e]):
            problems.append(f"an active <equality connect> '{name}' (it is inactive at start)")
        elif int(mj.eq_objtype[e]) != int(mujoco.mjtObj.mjOBJ_BODY):
            problems.append(f"a body-and-anchor <equality connect> '{name}' (site-based connects are not read)")
    if problems:
        raise RobotDescriptionError(str(desc.mjcf_path), problems)


def _pinocchio_configuration(mj: Any, qpos: np.ndarray) -> np.ndarray:
    """Pinocchio's q for MuJoCo's qpos: every free/ball quaternion (w, x, y, z) → (x, y, z, w)."""
    import mujoco

    q = np.array(qpos, dtype=float)
    for j in range(mj.njnt):
        t = int(mj.jnt_type[j])
        if t in (int(mujoco.mjtJoint.mjJNT_FREE), int(mujoco.mjtJoint.mjJNT_BALL)):
            a = int(mj.jnt_qposadr[j]) + (3 if t == int(mujoco.mjtJoint.mjJNT_FREE) else 0)
            q[a:a + 4] = (q[a + 1], q[a + 2], q[a + 3], q[a])
    return q


def _standing_qpos(desc: RobotDescription, mj: Any) -> np.ndarray | None:
    """MuJoCo qpos of the description's standing configuration (keyframe or standing_qpos), or None."""
    import mujoco

    if desc.standing_keyframe:
        k = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_KEY, desc.standing_keyframe)
        if k >= 0:
            return np.array(mj.key_qpos[k], dtype=float)
    if desc.standing_qpos is not None and len(desc.standing_qpos) == mj.nq:
        return np.asarray(desc.standing_qpos, dtype=float)
    return None


def _loop_reference(desc: RobotDescription, mj: Any) -> np.ndarray | None:
    """Pinocchio configuration at which the loops are checked and their dependent coordinates
    chosen: the standing configuration, else MuJoCo's qpos0 (where connect anchors coincide)."""
    qpos = _standing_qpos(desc, mj)
    return _pinocchio_configuration(mj, mj.qpos0 if qpos is None else qpos)


def _connect_residuals(mj: Any, qpos: np.ndarray) -> np.ndarray:
    """MuJoCo's anchor offsets (anchor 1 - anchor 2, world) of every connect at ``qpos`` [m], (neq, 3)."""
    import mujoco

    d = mujoco.MjData(mj)
    d.qpos[:] = qpos
    mujoco.mj_kinematics(mj, d)
    out = np.zeros((mj.neq, 3))
    for e in range(mj.neq):
        b1, b2 = int(mj.eq_obj1id[e]), int(mj.eq_obj2id[e])
        p1 = d.xpos[b1] + d.xmat[b1].reshape(3, 3) @ mj.eq_data[e, 0:3]
        p2 = d.xpos[b2] + d.xmat[b2].reshape(3, 3) @ mj.eq_data[e, 3:6]
        out[e] = p1 - p2
    return out


def _check_loops_close(desc: RobotDescription, mj: Any, wbc: "WholeBodyController", q_ref: np.ndarray | None) -> None:
    """Pinocchio's loops are MuJoCo's connects: same count, same anchor offsets at the reference
    configuration (1 µm), and closed there (1 mm)."""
    path = str(desc.mjcf_path)
    if wbc.n_loops != mj.neq:
        raise RobotDescriptionError(path, [f"{mj.neq} loop closures in Pinocchio's reading of the file "
                                           f"(it parsed {wbc.n_loops} of the {mj.neq} <equality connect>)"])
    qpos = _standing_qpos(desc, mj)
    qpos = mj.qpos0 if qpos is None else qpos
    mj_res = _connect_residuals(mj, qpos)
    pin_res = np.asarray(wbc.evaluate(q_ref)["loop_residual"]).reshape(-1, 3)
    if not np.allclose(pin_res, mj_res, atol=1e-6):
        raise RobotDescriptionError(path, ["the same loop anchors in Pinocchio and MuJoCo (the <equality connect> "
                                           f"offsets differ by {np.max(np.abs(pin_res - mj_res)):.2e} m)"])
    worst = float(np.max(np.linalg.norm(mj_res, axis=1)))
    if worst > 1e-3:
        raise RobotDescriptionError(path, [f"a standing configuration in which the loops close (the <equality "
                                           f"connect> anchors are {worst * 1e3:.1f} mm apart)"])


def _model_spec(desc: RobotDescription, mj: Any, friction: float | None) -> tuple[Any, list[str]]:
    """The C++ WbcModelSpec: frames from the description, actuators, springs and friction from MuJoCo."""
    import mujoco

    path = str(desc.mjcf_path)

    def name(obj: Any, i: int) -> str:
        return mujoco.mj_id2name(mj, obj, i) or ""

    spec = _wbc.WbcModelSpec()
    spec.mjcf_path = path
    spec.foot_bodies = [desc.left_foot_body, desc.right_foot_body]
    spec.sole_sites = [desc.left_sole_site or "", desc.right_sole_site or ""]
    offset = np.asarray(desc.sole_offset, dtype=float)
    spec.sole_offsets = [offset, offset]
    spec.torso_body = desc.torso_body
    if not (desc.foot_length > 0 and desc.foot_width > 0):
        raise RobotDescriptionError(path, [f"a positive foot size (got {desc.foot_length} x {desc.foot_width} m)"])
    spec.foot_half_length = 0.5 * float(desc.foot_length)
    spec.foot_half_width = 0.5 * float(desc.foot_width)
    spec.sole_cop_centers = _sole_centers(desc, mj)

    # actuators: pure motors on 1-DoF joints
    hinge_slide = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    joints, gains, lo, hi, names = [], [], [], [], []
    for a in range(mj.nu):
        aname = name(mujoco.mjtObj.mjOBJ_ACTUATOR, a) or f"actuator {a}"
        pure_motor = (
            int(mj.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT)
            and int(mj.actuator_dyntype[a]) == int(mujoco.mjtDyn.mjDYN_NONE)
            and int(mj.actuator_gaintype[a]) == int(mujoco.mjtGain.mjGAIN_FIXED)
            and int(mj.actuator_biastype[a]) == int(mujoco.mjtBias.mjBIAS_NONE)
        )
        j = int(mj.actuator_trnid[a, 0])
        if not pure_motor or int(mj.jnt_type[j]) not in hinge_slide:
            raise RobotDescriptionError(path, [f"a motor actuator (joint transmission, fixed gain, no bias) "
                                               f"on a hinge/slide joint for '{aname}'"])
        gear, gain = float(mj.actuator_gear[a, 0]), float(mj.actuator_gainprm[a, 0])
        u_lo, u_hi = -math.inf, math.inf
        if mj.actuator_ctrllimited[a]:
            u_lo, u_hi = float(mj.actuator_ctrlrange[a, 0]), float(mj.actuator_ctrlrange[a, 1])
        if mj.actuator_forcelimited[a] and gain != 0.0:
            f_lo, f_hi = (float(x) / gain for x in mj.actuator_forcerange[a])
            f_lo, f_hi = min(f_lo, f_hi), max(f_lo, f_hi)
            u_lo, u_hi = max(u_lo, f_lo), min(u_hi, f_hi)
        joints.append(name(mujoco.mjtObj.mjOBJ_JOINT, j))
        gains.append(gear * gain)
        lo.append(u_lo)
        hi.append(u_hi)
        names.append(aname)
    spec.actuated_joints = joints
    spec.actuation_gains = np.asarray(gains)
    spec.u_min = np.asarray(lo)
    spec.u_max = np.asarray(hi)
    spec.arm_joints = list(desc.arm_joints)
    spec.damping = np.array(mj.dof_damping, dtype=float)  # Pinocchio's reader skips ball joints
    spec.frictionloss = np.array(mj.dof_frictionloss, dtype=float)
    spec.gravity = np.array(mj.opt.gravity, dtype=float)  # 9.80665 in digit_like and Digit v3 (Pinocchio: 9.81)

    # passive springs on 1-DoF joints
    sj, sk, sr = [], [], []
    for j in range(mj.njnt):
        if float(mj.jnt_stiffness[j]) != 0.0 and int(mj.jnt_type[j]) not in hinge_slide:
            jname = name(mujoco.mjtObj.mjOBJ_JOINT, j) or f"joint {j}"
            raise RobotDescriptionError(path, [f"springs on hinge or slide joints only (joint '{jname}' is a "
                                               "ball or free joint with a stiffness)"])
        if int(mj.jnt_type[j]) in hinge_slide and float(mj.jnt_stiffness[j]) != 0.0:
            sj.append(name(mujoco.mjtObj.mjOBJ_JOINT, j))
            sk.append(float(mj.jnt_stiffness[j]))
            sr.append(float(mj.qpos_spring[mj.jnt_qposadr[j]]))
    spec.spring_joints = sj
    spec.spring_stiffness = np.asarray(sk, dtype=float)
    spec.spring_reference = np.asarray(sr, dtype=float)

    if friction is None:
        friction = _foot_friction(desc, mj)
    elif not (isinstance(friction, (int, float)) and math.isfinite(friction) and friction > 0):
        raise ParameterError("friction", friction, "a positive friction coefficient")
    spec.friction = float(friction)
    return spec, names


def _sole_centers(desc: RobotDescription, mj: Any) -> list[np.ndarray]:
    """Centre (x, y) of each sole rectangle in its sole frame [m]: the centre of the foot's colliding
    box when the foot body has exactly one (the Digit v3 sole sites sit 1.5 cm ahead of it), else 0."""
    import mujoco

    d = mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, d)
    out = []
    box = int(mujoco.mjtGeom.mjGEOM_BOX)
    feet = ((desc.left_foot_body, desc.left_sole_site), (desc.right_foot_body, desc.right_sole_site))
    for body_name, site_name in feet:
        b = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, body_name)
        boxes = [g for g in range(mj.ngeom) if int(mj.geom_bodyid[g]) == b and int(mj.geom_type[g]) == box
                 and (mj.geom_contype[g] or mj.geom_conaffinity[g])]
        if len(boxes) != 1 or b < 0:
            out.append(np.zeros(2))
            continue
        if site_name:
            s = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_SITE, site_name)
            origin, R = d.site_xpos[s], d.site_xmat[s].reshape(3, 3)
        else:
            R = d.xmat[b].reshape(3, 3)
            origin = d.xpos[b] + R @ np.asarray(desc.sole_offset, dtype=float)
        out.append(np.asarray(R.T @ (d.geom_xpos[boxes[0]] - origin))[:2].copy())
    return out


def _foot_friction(desc: RobotDescription, mj: Any) -> float:
    """Pyramid coefficient inside MuJoCo's friction cone for the foot geoms."""
    import mujoco

    feet = {
        mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, desc.left_foot_body),
        mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, desc.right_foot_body),
    }
    mus = [
        float(mj.geom_friction[g, 0])
        for g in range(mj.ngeom)
        if int(mj.geom_bodyid[g]) in feet and (mj.geom_contype[g] or mj.geom_conaffinity[g])
    ]
    if not mus:
        raise RobotDescriptionError(str(desc.mjcf_path), ["a colliding geom on each foot body"])
    mu = min(mus)
    pyramidal = int(mj.opt.cone) == int(mujoco.mjtCone.mjCONE_PYRAMIDAL)
    return mu / 2.0 if pyramidal else mu / math.sqrt(2.0)


def _check_consistency(desc: RobotDescription, mj: Any, model: Any) -> None:
    """Pinocchio and MuJoCo must agree on the velocity layout (and the damping passed on)."""
    if int(model.nv) != int(mj.nv) or int(model.nq) != int(mj.nq):
        raise RobotDescriptionError(
            str(desc.mjcf_path),
            [f"the same nq/nv in Pinocchio ({model.nq}/{model.nv}) and MuJoCo ({mj.nq}/{mj.nv})"],
        )
    damping = np.asarray(model.damping)
    if not np.allclose(damping[6:], mj.dof_damping[6:], rtol=1e-9, atol=1e-12):
        raise RobotDescriptionError(str(desc.mjcf_path), ["the same joint damping in Pinocchio and MuJoCo"])
