"""The whole-body controller's values: gains and parameters, the per-tick reference, the output.

These are the immutable side of :class:`~lipmpcc.control.wbc.WholeBodyController` (the reference is
a mutable record filled once per tick): plain Python, importable without the compiled controller.
Units: lengths [m], angles [rad], forces [N], torques [N m], gains kp [1/s²] and kd [1/s].
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..exceptions import InvalidInputError, ParameterError
from ..robots.description import RobotDescription
from ..validation import count, finite_array, non_negative_number, number_in

__all__ = [
    "QP_SOLVERS",
    "QP_SOLVER_ENV",
    "default_qp_solver",
    "TaskGains",
    "PostureGains",
    "WbcParams",
    "WbcReference",
    "PackedWbcReference",
    "PACKED_REFERENCE_FIXED_SIZE",
    "WbcTaskErrors",
    "WbcOutput",
]


# ------------------------------------------------------------------------------------------------
# Parameters (immutable)
# ------------------------------------------------------------------------------------------------
def _triple(name: str, value: float | Sequence[float]) -> tuple[float, float, float]:
    arr = finite_array(name, value, None, error=ParameterError,
                       what="a finite number >= 0 or three of them (x, y, z)")
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
            non_negative_number(f"arm_posture.{name}", getattr(self, name), error=ParameterError)


#: The QP solvers of the whole-body controller (:attr:`WbcParams.qp_solver`).
QP_SOLVERS: tuple[str, ...] = ("proxsuite", "daqp")
#: environment variable that replaces the default QP solver ``"proxsuite"`` (``daqp`` for every controller of a run)
QP_SOLVER_ENV = "LIPMPCC_WBC_QP_SOLVER"


def default_qp_solver() -> str:
    """The default of :attr:`WbcParams.qp_solver`: ``$LIPMPCC_WBC_QP_SOLVER`` when set, else ``"proxsuite"``.

    Raises:
        ParameterError: the variable names no solver of :data:`QP_SOLVERS`.
    """
    env = os.environ.get(QP_SOLVER_ENV, "").strip().lower()
    if not env:
        return "proxsuite"
    if env not in QP_SOLVERS:
        raise ParameterError(QP_SOLVER_ENV, env, "one of " + ", ".join(repr(s) for s in QP_SOLVERS))
    return env


def _positive(name: str, v: object, *, strict: bool = True, upper: float | None = None) -> None:
    number_in(name, v, 0.0, upper, lo_open=strict, error=ParameterError)


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
        qp_eps_abs: proxsuite absolute tolerance; DAQP's primal feasibility tolerance.
        qp_max_iter: proxsuite limit on outer and on inner iterations per solve (bounds the time
            of a failing solve); DAQP may change its working set ``20 ×`` this many times.
        fallback_damping: [N m s/rad] damping of the fallback efforts ``u_last - d · Bᵀ v``.
        joint_limit_horizon: [s] horizon h of the joint position limit rows: every actuated joint
            with a range keeps ``q + v h + q̈ h²/2`` within it; 0 (the default): no such rows (the
            paper studies' controller). ``lipmpcc robot init`` writes 0.1 into a new robot's
            ``wbc_overrides``.
        torsion_cone: add the yaw rows of each sole's contact wrench cone (Caron et al. 2015; eight per
            stance foot, :func:`~lipmpcc.control.reference_qp.contact_wrench_rows`): the yaw moment a foot is
            asked for shrinks with its CoP's distance to the CoP rectangle's edges and with its tangential
            force, to none at a corner (the constant torsion bound alone lets the QP ask a foot rolled onto
            a corner for a full flat sole's yaw moment, and it spins). False (the default): the paper studies'
            controller (on digit_like these rows bind and move every study's numbers; paper A's MPCC overtake
            then trails the obstacle). ``lipmpcc robot init`` writes it, ``false``, into a new robot's
            ``wbc_overrides`` (on T1 the cone lengthens paper A's runs but costs paper B's stones).
        qp_solver: the dense QP solver, one of :data:`QP_SOLVERS`: ``"proxsuite"`` (proxsuite 0.8,
            warm-started from its previous result) or ``"daqp"`` (DAQP 0.11, a dual active-set solver
            compiled into the controller, warm-started from the previous working set). Both reach the
            same optimum (``tests/control/test_wbc_daqp.py``); DAQP is faster and exact to rounding, but
            it is not the default: with it, paper A's MPCC overtaking on digit_like (``lipmpcc reproduce
            --only digit-overtake-mpcc``) trails the obstacle instead of passing it, and Digit v3's
            ALIP-MPC stepping-stone run (Profile III seed 0) fell (docs/benchmarks.md). The default is
            ``$LIPMPCC_WBC_QP_SOLVER`` when set (:func:`default_qp_solver`); a robot description's
            ``wbc_overrides`` sets it per robot.
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
    joint_limit_horizon: float = 0.0
    torsion_cone: bool = False
    qp_solver: str = field(default_factory=default_qp_solver)

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
        count("qp_max_iter", self.qp_max_iter, 1, error=ParameterError)
        _positive("fallback_damping", self.fallback_damping, strict=False)
        _positive("joint_limit_horizon", self.joint_limit_horizon, strict=False)
        if not isinstance(self.torsion_cone, bool):
            raise ParameterError("torsion_cone", self.torsion_cone, "true or false")
        if not isinstance(self.qp_solver, str) or self.qp_solver not in QP_SOLVERS:
            raise ParameterError("qp_solver", self.qp_solver, "one of " + ", ".join(repr(s) for s in QP_SOLVERS))

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
    com_pos: ArrayLike = field(default_factory=lambda: np.zeros(3))
    com_vel: ArrayLike = field(default_factory=lambda: np.zeros(3))
    com_acc: ArrayLike = field(default_factory=lambda: np.zeros(3))
    torso_rot: ArrayLike = field(default_factory=lambda: np.eye(3))
    torso_angvel: ArrayLike = field(default_factory=lambda: np.zeros(3))
    torso_angacc: ArrayLike = field(default_factory=lambda: np.zeros(3))
    foot_pos: ArrayLike = field(default_factory=lambda: np.zeros((2, 3)))
    foot_vel: ArrayLike = field(default_factory=lambda: np.zeros((2, 3)))
    foot_acc: ArrayLike = field(default_factory=lambda: np.zeros((2, 3)))
    foot_rot: ArrayLike = field(default_factory=_eye2)
    foot_angvel: ArrayLike = field(default_factory=lambda: np.zeros((2, 3)))
    foot_angacc: ArrayLike = field(default_factory=lambda: np.zeros((2, 3)))
    arm_posture: ArrayLike = field(default_factory=lambda: np.zeros(0))
    max_normal_force: ArrayLike = (math.inf, math.inf)

    def __setattr__(self, name: str, value: object) -> None:
        """Set a field; a name that is not a field, or a ``contact`` that is not two flags, raises
        :class:`~lipmpcc.exceptions.InvalidInputError` (array fields are checked by the controller)."""
        if name not in _REFERENCE_FIELDS:
            raise InvalidInputError(f"WbcReference.{name}", value, "one of the fields " + ", ".join(_REFERENCE_FIELDS))
        if name == "contact" and not _two_flags(value):
            raise InvalidInputError("WbcReference.contact", value, "two flags (left, right), e.g. (True, False)")
        object.__setattr__(self, name, value)


def _two_flags(value: object) -> bool:
    """True for a sequence of two booleans (numpy booleans, 0 and 1 too)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:  # type: ignore[arg-type]
        return False
    return all(isinstance(c, (bool, np.bool_)) or (isinstance(c, (int, np.integer)) and c in (0, 1)) for c in value)  # type: ignore[union-attr]


_REFERENCE_FIELDS = tuple(WbcReference.__dataclass_fields__)


#: entries of the flat reference before the arm posture (``_wbc.PACKED_REFERENCE_FIXED_SIZE``): COM (9),
#: torso rotation (9, row-major), torso rates (6), 2 feet × 24 (pos, vel, acc, rot row-major, angvel, angacc),
#: normal-force bounds (2)
PACKED_REFERENCE_FIXED_SIZE = 24 + 2 * 24 + 2
_FEET = slice(24, 72)


def _no_swing_block() -> np.ndarray:
    """The feet block of a double-support tick (2, 24): zero motion, identity rotations."""
    block = np.zeros((2, 24))
    block[:, 9:18] = np.eye(3).ravel()
    return block


class PackedWbcReference:
    """A :class:`WbcReference` held as one flat float64 buffer in the layout the C++ controller reads
    (``_wbc.WbcSolver.solve_packed``, documented in ``cpp/wbc/bindings/bind_solver.cpp``), so that a tick's
    reference is written once and handed over without packing.

    :meth:`~lipmpcc.control.wbc.WholeBodyController.solve` takes it in place of a :class:`WbcReference`
    and gives the same output to the bit for the same values. Fields read as numpy views of the buffer
    (write into them in place: ``ref.com_pos[:] = c``); assigning a field copies the value into the
    buffer (shape checked, like the controller does for a :class:`WbcReference`). Units as in
    :class:`WbcReference`. The per-foot fields live in their own block (:attr:`feet`), copied into the
    buffer by :meth:`packed` unless both feet are in contact (then the buffer gets the fixed block a
    :class:`WbcReference` is packed with: the swing fields are ignored).

    Args:
        arm_posture: (n_arm,) [rad] arm joint angles.
    """

    __slots__ = ("buf", "feet", "_contact", "com_pos", "com_vel", "com_acc", "torso_rot", "torso_angvel",
                 "torso_angacc", "foot_pos", "foot_vel", "foot_acc", "foot_rot", "foot_angvel", "foot_angacc",
                 "arm_posture", "_max_normal_force", "_feet_flat", "_no_swing")

    def __init__(self, arm_posture: ArrayLike = ()) -> None:
        arm = finite_array("arm_posture", arm_posture, None)
        if arm.ndim != 1:
            raise InvalidInputError("arm_posture", arm_posture, "a vector (n_arm,) of joint angles [rad]")
        buf = np.zeros(PACKED_REFERENCE_FIXED_SIZE + arm.size)
        s = object.__setattr__
        s(self, "buf", buf)
        for name, (i, shape) in _PACKED_FIELDS.items():
            s(self, name, buf[i:i + math.prod(shape)].reshape(shape))
        feet = _no_swing_block()
        s(self, "feet", feet)
        s(self, "_feet_flat", feet.reshape(48))
        s(self, "_no_swing", _no_swing_block().reshape(48))
        for k, name in enumerate(("foot_pos", "foot_vel", "foot_acc")):
            s(self, name, feet[:, 3 * k:3 * k + 3])
        s(self, "foot_rot", feet[:, 9:18].reshape(2, 3, 3))
        s(self, "foot_angvel", feet[:, 18:21])
        s(self, "foot_angacc", feet[:, 21:24])
        s(self, "_max_normal_force", buf[72:74])
        s(self, "arm_posture", buf[74:])
        s(self, "_contact", (True, True))
        self.torso_rot[:] = np.eye(3)
        self._max_normal_force[:] = math.inf
        self.arm_posture[:] = arm

    @property
    def contact(self) -> tuple[bool, bool]:
        """(left, right) support flags."""
        return self._contact

    @property
    def max_normal_force(self) -> tuple[float, float]:
        """(left, right) normal force bound [N] (inf: none), as floats."""
        a, b = self._max_normal_force.tolist()
        return a, b

    def __setattr__(self, name: str, value: object) -> None:
        """Copy a field's value into the buffer; an unknown name, a bad ``contact`` or a wrong shape raises
        :class:`~lipmpcc.exceptions.InvalidInputError`."""
        if name == "contact":
            if not _two_flags(value):
                raise InvalidInputError("PackedWbcReference.contact", value, "two flags (left, right), e.g. (True, False)")
            object.__setattr__(self, "_contact", (bool(value[0]), bool(value[1])))  # type: ignore[index]
            return
        if name not in _REFERENCE_FIELDS:
            raise InvalidInputError(f"PackedWbcReference.{name}", value, "one of the fields " + ", ".join(_REFERENCE_FIELDS))
        view = self._max_normal_force if name == "max_normal_force" else getattr(self, name)
        arr = np.asarray(value, dtype=float)
        if arr.shape != view.shape:
            raise InvalidInputError(f"ref.{name}", value, f"an array of shape {view.shape}")
        view[...] = arr

    def write(self, contact: tuple[bool, bool], com_pos: np.ndarray, com_vel: np.ndarray, com_acc: np.ndarray,
              torso_rot: np.ndarray, torso_angvel: np.ndarray, torso_angacc: np.ndarray,
              max_normal_force: tuple[float, float]) -> None:
        """The per-tick write of everything but the feet block, from trusted values: two bools, float64
        arrays (3,) [m, m/s, m/s²], (3, 3), (3,) [rad/s], (3,) [rad/s²], two floats [N]; no checks."""
        np.concatenate((com_pos, com_vel, com_acc, torso_rot.ravel(), torso_angvel, torso_angacc), out=self.buf[:24])
        self.set_support(contact, max_normal_force)

    def set_support(self, contact: tuple[bool, bool], max_normal_force: tuple[float, float]) -> None:
        """The per-tick write of the support flags (two bools) and the normal-force bounds [N]; no checks."""
        self._max_normal_force[:] = max_normal_force
        object.__setattr__(self, "_contact", contact)

    def packed(self, double_support: bool) -> np.ndarray:
        """The buffer, its feet block made current: :attr:`feet`, or the fixed block when ``double_support``."""
        self.buf[_FEET] = self._no_swing if double_support else self._feet_flat
        return self.buf


#: offset into the flat buffer and shape of the fields before the feet block
_PACKED_FIELDS = {"com_pos": (0, (3,)), "com_vel": (3, (3,)), "com_acc": (6, (3,)), "torso_rot": (9, (3, 3)),
                  "torso_angvel": (18, (3,)), "torso_angacc": (21, (3,))}


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
        iterations: the QP solver's iterations (proxsuite; DAQP: changes of its working set).
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
