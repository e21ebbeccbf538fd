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
  (``RobotSim.pinocchio_state()``, :class:`lipmpcc.robots.state_map.StateMap`).
- Actuation: actuator k applies the generalised force ``gear_k · gain_k · u_k`` on its joint (MuJoCo
  ``motor`` actuators); ``u`` is the MuJoCo ``ctrl`` vector, bounded by ``ctrlrange`` (and
  ``forcerange``). For ``digit_like`` (gear 1) u is the joint torque [N m].
- Model: what the controller reads from the MJCF besides Pinocchio's model (motors, springs,
  friction, sole rectangles, loop reference) is :func:`lipmpcc.robots.wbc_model.wbc_model_data`; the
  parameters, reference and output types are in :mod:`lipmpcc.control.wbc_types`.

Robustness: a QP failure (any status other than solved, a non-finite solution, a solver exception)
never raises. The controller then returns ``u_last - fallback_damping · Bᵀ v`` clipped to the motor
bounds, where ``u_last`` is the last successful solution (zero before the first), sets
``used_fallback`` and counts it in :attr:`WholeBodyController.qp_failures`. Invalid *input* (wrong
shape or dtype, NaN, a reference rotation that is not a rotation) raises
:class:`~lipmpcc.exceptions.InvalidInputError` / :class:`~lipmpcc.exceptions.StateError`.

Threads: a controller holds one C++ workspace (and its own worker for :meth:`WholeBodyController.prepare`).
It may be handed from one thread to another, but two threads must not call it at the same time: a
call that finds another thread inside a call on the same controller raises
:class:`~lipmpcc.exceptions.ConcurrentUseError` at once (a non-blocking lock; it costs well under a
microsecond per tick). Use one controller per thread.
"""

from __future__ import annotations

import math
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Sequence, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from ..config import threads_enabled
from ..exceptions import (
    ConcurrentUseError,
    InvalidInputError,
    ModelFileError,
    ParameterError,
    RobotDescriptionError,
    StateError,
)
from ..robots.description import RobotDescription
from ..robots.loading import load_robot
from ..robots.wbc_model import WbcModelData, check_consistency, loop_closure_problems, wbc_model_data
from .wbc_types import (PACKED_REFERENCE_FIXED_SIZE, PackedWbcReference, PostureGains, TaskGains, WbcOutput, WbcParams,
                        WbcReference, WbcTaskErrors)

try:
    from .. import _wbc
except ImportError as _err:  # pragma: no cover - depends on the build
    raise ImportError(
        "lipmpcc._wbc (the C++ whole-body QP) is not built or cannot load its libraries: install the "
        f"package with `pip install .` ({_err})"
    ) from _err

__all__ = ["WholeBodyController"]

_T = TypeVar("_T")
_F64 = np.dtype(np.float64)  # the float64 descriptor (``a.dtype is _F64`` is a fast exact-type test)
_STATUS_NAMES = {int(s): _wbc.status_name(s) for s in _wbc.QpStatus.__members__.values()}
_FORMULATIONS = {"eliminate": _wbc.LoopFormulation.eliminate, "multipliers": _wbc.LoopFormulation.multipliers}
_SPRING_MODELS = {"compliant": _wbc.SpringModel.compliant, "rigid": _wbc.SpringModel.rigid}


# ------------------------------------------------------------------------------------------------
# Python values -> the C++ structs
# ------------------------------------------------------------------------------------------------
def _task_gains_to_cpp(gains: TaskGains) -> _wbc.TaskGains:
    g = _wbc.TaskGains()
    g.weight = np.asarray(gains.weight)
    g.kp = np.asarray(gains.kp)
    g.kd = np.asarray(gains.kd)
    return g


def _posture_gains_to_cpp(gains: PostureGains) -> _wbc.ScalarTaskGains:
    a = _wbc.ScalarTaskGains()
    a.weight, a.kp, a.kd = gains.weight, gains.kp, gains.kd
    return a


def _params_to_cpp(params: WbcParams) -> _wbc.WbcParams:
    p = _wbc.WbcParams()
    p.com = _task_gains_to_cpp(params.com)
    p.torso = _task_gains_to_cpp(params.torso)
    p.swing_position = _task_gains_to_cpp(params.swing_position)
    p.swing_orientation = _task_gains_to_cpp(params.swing_orientation)
    p.arm_posture = _posture_gains_to_cpp(params.arm_posture)
    for name in ("angular_momentum_weight", "angular_momentum_kd", "qdd_regularization", "force_regularization",
                 "min_normal_force", "cop_safety_factor", "contact_velocity_gain", "spring_damping_gain",
                 "friction_compensation_velocity", "qp_eps_abs", "fallback_damping", "joint_limit_horizon"):
        setattr(p, name, float(getattr(params, name)))
    p.qp_max_iter = int(params.qp_max_iter)
    p.torsion_cone = bool(params.torsion_cone)
    p.qp_solver = getattr(_wbc.QpSolverKind, params.qp_solver)
    return p


def _spec_to_cpp(data: WbcModelData, loop_formulation: str, spring_model: str) -> _wbc.WbcModelSpec:
    """The C++ ``WbcModelSpec`` of the model data and the two formulation choices."""
    spec = _wbc.WbcModelSpec()
    spec.mjcf_path = data.mjcf_path
    spec.foot_bodies = list(data.foot_bodies)
    spec.sole_sites = list(data.sole_sites)
    spec.sole_offsets = list(data.sole_offsets)
    spec.torso_body = data.torso_body
    spec.foot_half_length = data.foot_half_length
    spec.foot_half_width = data.foot_half_width
    spec.sole_cop_centers = list(data.sole_cop_centers)
    spec.actuated_joints = list(data.actuated_joints)
    spec.actuation_gains = data.actuation_gains
    spec.u_min = data.u_min
    spec.u_max = data.u_max
    spec.arm_joints = list(data.arm_joints)
    spec.damping = data.damping
    spec.frictionloss = data.frictionloss
    spec.gravity = data.gravity
    spec.spring_joints = list(data.spring_joints)
    spec.spring_stiffness = data.spring_stiffness
    spec.spring_reference = data.spring_reference
    spec.friction = data.friction
    spec.loop_formulation = _FORMULATIONS[loop_formulation]
    spec.spring_model = _SPRING_MODELS[spring_model]
    spec.loop_reference_configuration = data.loop_reference_configuration
    return spec


# ------------------------------------------------------------------------------------------------
# Input checks
# ------------------------------------------------------------------------------------------------
def _array(name: str, value: ArrayLike, shape: tuple[int, ...]) -> np.ndarray:
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


def _frozen(cls: type[_T], **fields: object) -> _T:
    """An instance of the frozen dataclass ``cls`` from all its fields, without the per-field
    ``object.__setattr__`` of the generated ``__init__`` (per-tick outputs built from trusted data)."""
    obj = object.__new__(cls)
    obj.__dict__.update(fields)
    return obj


def _state(name: str, value: object, n: int) -> np.ndarray:
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
#: the swing fields of a WbcReference and their shapes
_SWING_SHAPES = (("foot_pos", (2, 3)), ("foot_vel", (2, 3)), ("foot_acc", (2, 3)), ("foot_rot", (2, 3, 3)),
                 ("foot_angvel", (2, 3)), ("foot_angacc", (2, 3)))

class WholeBodyController:
    """The whole-body QP for one robot (wraps the C++ ``WbcModel`` + ``WbcSolver``).

    Args:
        robot: a :class:`~lipmpcc.robots.RobotDescription` (its compiled :attr:`~RobotDescription.model`
            is used, not compiled again), ``"digit_like"`` or an MJCF path (see
            :func:`~lipmpcc.robots.load_robot`). Pinocchio and the motor data are read from
            ``robot.mjcf_path``, the file the simulator's scene includes.
        params: :class:`WbcParams` (None: :meth:`WbcParams.for_robot`, the defaults with the
            robot description's ``wbc_overrides``).
        friction: friction-pyramid coefficient (None: from the foot geoms, see
            :mod:`lipmpcc.robots.wbc_model`).
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
        if not isinstance(loop_formulation, str) or loop_formulation not in _FORMULATIONS:
            raise ParameterError("loop_formulation", loop_formulation, "'eliminate' or 'multipliers'")
        if spring_model is None:
            spring_model = "rigid"
        if not isinstance(spring_model, str) or spring_model not in _SPRING_MODELS:
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
        mj = desc.model  # compiled once per description
        data = wbc_model_data(desc, mj, friction)
        self.actuator_names = list(data.actuator_names)
        self.friction = float(data.friction)
        self._model = self._build_model(data)
        check_consistency(data, mj, self._model.nq, self._model.nv, self._model.damping)
        self._solver = _wbc.WbcSolver(self._model, _params_to_cpp(params))
        self._busy = threading.Lock()  # held during every call into the C++ workspace (see the module doc)
        self._init_buffers()
        if mj.neq > 0:
            problems = loop_closure_problems(
                data, mj, self.n_loops, self.evaluate(data.loop_reference_configuration)["loop_residual"])
            if problems:
                raise RobotDescriptionError(data.mjcf_path, problems)

    def _build_model(self, data: WbcModelData) -> _wbc.WbcModel:
        """The C++ model (Pinocchio reads the MJCF) of the model data."""
        try:
            return _wbc.WbcModel(_spec_to_cpp(data, self.loop_formulation, self.spring_model))
        except ValueError as err:
            raise RobotDescriptionError(data.mjcf_path, [str(err)]) from None
        except RuntimeError as err:
            raise ModelFileError(data.mjcf_path, str(err)) from None

    def _init_buffers(self) -> None:
        """Sizes, the actuation matrix and the per-tick constants, from the C++ model."""
        no_swing = np.zeros((2, 24))
        no_swing[:, 9:18] = np.eye(3).ravel()
        self._no_swing = no_swing.ravel()
        self._py_failures = 0
        self._u_last = np.zeros(self._model.nu)
        self.nq = int(self._model.nq)
        self.nv = int(self._model.nv)
        self._q_shape, self._v_shape = (self.nq,), (self.nv,)  # the state's shapes (compared per tick)
        self.nu = int(self._model.nu)
        self.n_arm = int(self._model.n_arm)
        self.n_loop_rows = int(self._model.n_loop_rows)
        self.n_springs = len(self._model.spring_idx_v)
        self._arm_shape = (self.n_arm,)
        self._packed_size = PACKED_REFERENCE_FIXED_SIZE + self.n_arm
        self._B = np.array(self._model.actuation)
        self._iq = int(self._model.base_quaternion_idx)
        self._errors_at = self.nu + 2 * self.nv + 12  # where the task errors start in the packed output

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
    def model(self) -> _wbc.WbcModel:
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
        with self._exclusive("reset"):
            self._solver.reset()
        self._py_failures = 0
        self._u_last = np.zeros(self.nu)

    def solve(self, q: np.ndarray, v: np.ndarray, ref: WbcReference | PackedWbcReference) -> WbcOutput:
        """One control tick.

        Args:
            q: Pinocchio configuration, float64, C-contiguous, shape (nq,), base quaternion
                (x, y, z, w) at ``q[3:7]`` of unit norm (to 1e-3; it is normalised).
            v: Pinocchio velocity, float64, C-contiguous, shape (nv,).
            ref: the :class:`WbcReference`, or the same as a :class:`PackedWbcReference` (no packing: the
                per-tick path of the full-body loop; the same output to the bit).

        Returns:
            The :class:`WbcOutput`. Never raises because the QP failed (see the module doc).

        Raises:
            StateError: bad q or v (type, dtype, shape, contiguity, NaN/inf, quaternion norm).
            InvalidInputError: a bad reference field (named in the message).
            ConcurrentUseError: another thread is inside a call on this controller (use one per thread).
        """
        res = self._solve_raw(q, v, ref)
        return self._python_fallback(v) if res is None else self._unpack(*res)

    def solve_tick(self, q: np.ndarray, v: np.ndarray,
                   ref: WbcReference | PackedWbcReference) -> tuple[np.ndarray, int, bool, np.ndarray]:
        """The full-body loop's tick: (efforts [N m], QP status code, fallback used, angular momentum
        [kg m²/s]) of :meth:`solve` — the same arrays and numbers, with the same effect on the controller,
        without building the :class:`WbcOutput` (the loop reads no other field).

        Args, Raises: as :meth:`solve`.
        """
        if type(self).solve is not WholeBodyController.solve:  # a subclass's own tick (the course's student QP)
            out = self.solve(q, v, ref)
            return out.tau, out.status_code, bool(out.used_fallback), out.errors.angular_momentum
        if (type(ref) is PackedWbcReference and type(q) is np.ndarray and type(v) is np.ndarray
                and q.dtype is _F64 and v.dtype is _F64):  # the loop's tick: _solve_raw's checks, inlined
            res = self._solve_packed_tick(q, v, ref)
        else:
            res = self._solve_raw(q, v, ref)
        if res is None:
            out = self._python_fallback(v)
            return out.tau, out.status_code, True, out.errors.angular_momentum
        arr, status, _, _, _, fallback = res
        tau = arr[:self.nu]
        if not fallback:
            self._u_last = tau
        e = self._errors_at + 24
        return tau, status, fallback, arr[e:e + 3]

    def _solve_packed_tick(self, q: np.ndarray, v: np.ndarray,
                           ref: PackedWbcReference) -> tuple[np.ndarray, int, int, float, float, bool] | None:
        """:meth:`_solve_raw` for float64 arrays ``q``, ``v`` and a :class:`PackedWbcReference`: the same
        checks in one frame (shapes, contiguity, the quaternion's norm; the same errors), then the C++ call."""
        if q.shape != self._q_shape or not q.flags.c_contiguous:
            _state("q", q, self.nq)
        if v.shape != self._v_shape or not v.flags.c_contiguous:
            _state("v", v, self.nv)
        qx, qy, qz, qw = q[3:7].tolist()
        qn = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
        if not abs(qn - 1.0) <= 1e-3:  # also catches NaN
            raise StateError("q[3:7]", q[3:7], "a finite unit quaternion (x, y, z, w) (norm 1 +/- 1e-3)")
        cl, cr = ref.contact
        if ref.buf.size != self._packed_size:
            raise InvalidInputError("ref.arm_posture", ref.arm_posture, f"{self.n_arm} arm joint angles [rad]")
        return self._call_packed(q, v, cl, cr, ref.packed(cl and cr), ref)

    def _call_packed(self, q: np.ndarray, v: np.ndarray, cl: bool, cr: bool, packed: np.ndarray,
                     ref: WbcReference | PackedWbcReference) -> tuple[np.ndarray, int, int, float, float, bool] | None:
        """The C++ solve of the checked state and ``packed`` reference, one at a time: C++'s value errors as
        :class:`StateError`/:class:`InvalidInputError` naming ``ref``'s field, None when it raised otherwise
        (the loop goes on with the Python fallback)."""
        busy = self._busy
        if not busy.acquire(False):
            raise self._concurrent("solve")
        try:
            return self._solver.solve_packed(q, v, cl, cr, packed)
        except ValueError as err:  # C++ checks values: "<argument>: <what was expected>"
            name, _, expected = str(err).partition(": ")
            if name in ("q", "v"):
                raise StateError(name, q if name == "q" else v, expected) from None
            value = getattr(ref, name[4:], None) if name.startswith("ref.") else None
            raise InvalidInputError(name, value, expected) from None
        except Exception:  # noqa: BLE001 - the loop must go on: fallback
            return None
        finally:
            busy.release()

    def _solve_raw(self, q: np.ndarray, v: np.ndarray,
                   ref: WbcReference | PackedWbcReference) -> tuple[np.ndarray, int, int, float, float, bool] | None:
        """:meth:`solve`'s checks and the C++ call: its packed output, status, iterations, times [µs] and
        fallback flag (:meth:`_unpack`), or None when the C++ call raised (the Python fallback's case)."""
        _state("q", q, self.nq)
        _state("v", v, self.nv)
        qx, qy, qz, qw = q[3:7].tolist()
        qn = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
        if not abs(qn - 1.0) <= 1e-3:  # also catches NaN
            raise StateError("q[3:7]", q[3:7], "a finite unit quaternion (x, y, z, w) (norm 1 +/- 1e-3)")
        if type(ref) is PackedWbcReference:  # already flat (shapes fixed by construction)
            cl, cr = ref.contact
            if ref.buf.size != self._packed_size:
                raise InvalidInputError("ref.arm_posture", ref.arm_posture, f"{self.n_arm} arm joint angles [rad]")
            packed = ref.packed(cl and cr)
        else:
            if not isinstance(ref, WbcReference):
                raise InvalidInputError("ref", type(ref).__name__, "a WbcReference or a PackedWbcReference")
            contact = ref.contact
            if len(contact) != 2:
                raise InvalidInputError("ref.contact", contact, "two flags (left, right)")
            cl, cr = bool(contact[0]), bool(contact[1])
            packed = self._pack_reference(ref, cl and cr)
        return self._call_packed(q, v, cl, cr, packed, ref)

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
            ConcurrentUseError: another thread is inside a call on this controller.
        """
        if not (type(q) is np.ndarray and type(v) is np.ndarray and q.dtype is _F64 and v.dtype is _F64
                and q.shape == self._q_shape and v.shape == self._v_shape and q.flags.c_contiguous
                and v.flags.c_contiguous):  # else the checks that name what is wrong
            _state("q", q, self.nq)
            _state("v", v, self.nv)
        busy = self._busy
        if not busy.acquire(False):
            raise self._concurrent("prepare")
        try:
            self._solver.prepare(q, v, self.threaded)
        finally:
            busy.release()

    def evaluate(self, q: np.ndarray, v: np.ndarray | None = None) -> dict[str, np.ndarray | list[np.ndarray]]:
        """Kinematic and dynamic terms at (q, v) without solving (``v`` None: zero).

        Returns a dict: ``com`` (3,), ``vcom``, ``p_sole`` [(3,), (3,)], ``R_sole``, ``R_torso``,
        ``M``, ``h``, ``J_sole``, ``J_com``, ... (see ``cpp/wbc/include/lipmpcc/wbc/dynamics.hpp``).
        """
        q = _state("q", q, self.nq)
        v = np.zeros(self.nv) if v is None else _state("v", v, self.nv)
        try:
            with self._exclusive("evaluate"):
                return self._solver.evaluate(q, v)
        except ValueError as err:
            raise StateError("q/v", "see message", str(err)) from None

    def last_qp(self) -> dict[str, np.ndarray | int]:
        """The QP of the last tick in proxsuite form (``0.5 xᵀHx + gᵀx``, ``Ax = b``,
        ``l <= Cx <= u``): keys H, g, A, b, C, l, u, n_var, n_eq, n_in, wrench_offset."""
        with self._exclusive("last_qp"):
            return self._solver.last_qp()

    def last_terms(self) -> dict[str, np.ndarray | list[np.ndarray]]:
        """The dynamics terms of the last tick (same keys as :meth:`evaluate`)."""
        with self._exclusive("last_terms"):
            return self._solver.last_terms()

    def last_reduced_terms(self) -> dict[str, np.ndarray | list[np.ndarray]]:
        """With eliminated loops: the terms in the independent accelerations the last QP was built
        from (M, h, Jacobians, drifts, ``qdd_metric``); see :meth:`last_terms`."""
        with self._exclusive("last_reduced_terms"):
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
    def _concurrent(self, method: str) -> ConcurrentUseError:
        """The error of a call that found another thread inside this controller."""
        return ConcurrentUseError(f"WholeBodyController(robot={self.description.name!r}, id={id(self):#x})", method,
                                  "controller")

    @contextmanager
    def _exclusive(self, method: str) -> Iterator[None]:
        """Hold the controller's lock for a call into C++, or raise :class:`ConcurrentUseError` at once."""
        busy = self._busy
        if not busy.acquire(False):
            raise self._concurrent(method)
        try:
            yield
        finally:
            busy.release()

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
        if double_support:  # swing fields are ignored, but must still be what they claim to be
            for name, shape in _SWING_SHAPES:
                if np.shape(getattr(ref, name)) != shape:
                    _array(f"ref.{name}", getattr(ref, name), shape)  # raises, naming the field
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
        e = self._errors_at
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
