"""MuJoCo simulation of a biped: stepping, state in Pinocchio's convention, contacts, pushes, falls.

:class:`RobotSim` owns a ``mujoco.MjModel`` / ``MjData`` built from a
:class:`~lipmpcc.robot.RobotDescription` (``"digit_like"`` by default, or a user MJCF). It loads the
description's scene (robot + floor); a model without a ground plane gets one.

State conventions (tested in ``tests/sim/test_state_mapping.py``):

- MuJoCo free joint: ``qpos = [p (world), quat (w, x, y, z)]``, ``qvel = [ṗ (world), ω (body)]``.
- Pinocchio free-flyer: ``q = [p (world), quat (x, y, z, w)]``, ``v = [Rᵀ ṗ, ω]``, both in the body
  frame. :class:`StateMap` converts (ball joints: the quaternion is reordered; 1-DoF joints are
  copied); the joint order is the MJCF tree order in both libraries.

Derived quantities (COM, foot poses, contacts) are computed on demand after a step (one
``mj_forward``-equivalent pass, shared by every accessor until the state changes, whose position and
velocity stages the next :meth:`RobotSim.step` reuses: it starts with ``mj_step2``); :meth:`RobotSim.measure` returns
all of them at once for a control tick. ``sim.data`` is the raw MuJoCo data — call
:meth:`RobotSim.forward` before reading its derived fields after :meth:`RobotSim.step` or after
changing its state by hand (prefer :meth:`RobotSim.set_state`).

Compiled tick: when the private module ``lipmpcc._mjtick`` is built against the running MuJoCo,
:meth:`RobotSim.step` (without a log) and :meth:`RobotSim.measure` run their MuJoCo calls, pushes,
contact sums and state map in C++ on the same ``MjModel`` / ``MjData`` (:attr:`RobotSim.compiled_tick`);
the results are bit-identical to the Python path, which runs otherwise (or with
``LIPMPCC_PYTHON_TICK=1``).

Rates: the simulation runs at the model's time step (2 kHz by default). :class:`Rates` holds the
simulation, whole-body-control and planner rates and checks that the controller rate divides the
simulation rate.

Fall criterion (:class:`FallCriterion`): the torso origin less than ``min_height`` [m] above the lower
sole, or the torso's z axis tilted more than ``max_tilt`` [rad] from the vertical, or a robot geom
other than a foot touching something.
"""

from __future__ import annotations

import bisect
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, NamedTuple

import numpy as np

from . import render as _render  # noqa: F401  (chooses a headless GL backend before mujoco is imported)
import mujoco  # noqa: E402

from ..exceptions import InvalidInputError, ModelFileError, ParameterError, RenderUnavailableError, StateError
from ..robot import LEFT, RIGHT, RobotDescription, load_robot


# ------------------------------------------------------------------------------------------------
# Small value types
# ------------------------------------------------------------------------------------------------
class FramePose(NamedTuple):
    """A frame in the world: ``position`` (3,) [m] and ``rotation`` (3, 3) (columns = frame axes)."""

    position: np.ndarray
    rotation: np.ndarray


class Measurement(NamedTuple):
    """The state a controller reads at one instant (world frame unless noted), from :meth:`RobotSim.measure`.

    Attributes:
        time: simulated time [s].
        q, v: configuration and velocity in Pinocchio's convention (see :class:`StateMap`).
        com: centre of mass (3,) [m]; com_vel: its velocity (3,) [m/s].
        torso: torso (floating base) frame.
        feet: (left, right) sole frames.
        contact: (left, right) vertical force above the simulator's ``contact_threshold``.
        normal_force: (left, right) vertical contact force [N].
    """

    time: float
    q: np.ndarray
    v: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    torso: FramePose
    feet: tuple[FramePose, FramePose]
    contact: tuple[bool, bool]
    normal_force: tuple[float, float]


@dataclass(frozen=True)
class Rates:
    """Loop rates [Hz]: simulation, whole-body control (a divisor of it), planner (its own rate).

    Attributes:
        sim_hz: MuJoCo rate (2000 Hz: 0.5 ms steps).
        wbc_hz: whole-body QP rate (400 Hz default; up to ``sim_hz``).
        planner_hz: footstep planner rate (e.g. 15 Hz for paper A, 25 Hz for paper B); rounded to
            whole controller ticks by the loop.
    """

    sim_hz: float = 2000.0
    wbc_hz: float = 400.0
    planner_hz: float = 15.0

    def __post_init__(self) -> None:
        for name in ("sim_hz", "wbc_hz", "planner_hz"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ParameterError(name, v, "a positive rate [Hz]")
        if self.wbc_hz > self.sim_hz:
            raise ParameterError("wbc_hz", self.wbc_hz, f"at most sim_hz = {self.sim_hz:g} Hz")
        ratio = self.sim_hz / self.wbc_hz
        if abs(ratio - round(ratio)) > 1e-9:
            raise ParameterError(
                "wbc_hz", self.wbc_hz, f"a divisor of sim_hz = {self.sim_hz:g} Hz (e.g. 400, 500, 1000)"
            )
        if self.planner_hz > self.wbc_hz:
            raise ParameterError("planner_hz", self.planner_hz, f"at most wbc_hz = {self.wbc_hz:g} Hz")

    @property
    def timestep(self) -> float:
        """Simulation time step [s]."""
        return 1.0 / self.sim_hz

    @property
    def sim_steps_per_wbc(self) -> int:
        """Simulation steps per controller tick (5 at 2 kHz / 400 Hz)."""
        return int(round(self.sim_hz / self.wbc_hz))

    @property
    def wbc_ticks_per_plan(self) -> int:
        """Controller ticks per planner update (rounded, at least 1)."""
        return max(1, int(round(self.wbc_hz / self.planner_hz)))


@dataclass(frozen=True)
class FallCriterion:
    """When the robot counts as fallen (any condition).

    Attributes:
        min_height: torso origin height above the lower sole [m] below which the robot has fallen
            (standing: about 1.0 m for Digit).
        max_tilt: largest angle between the torso z axis and the vertical [rad].
        non_foot_contact: a contact of any robot geom other than the feet counts as a fall.
    """

    min_height: float = 0.55
    max_tilt: float = 1.0
    non_foot_contact: bool = True

    def __post_init__(self) -> None:
        if not (math.isfinite(self.min_height) and self.min_height > 0):
            raise ParameterError("min_height", self.min_height, "a positive height [m]")
        if not (math.isfinite(self.max_tilt) and 0 < self.max_tilt <= math.pi):
            raise ParameterError("max_tilt", self.max_tilt, "an angle in (0, pi] [rad]")


@dataclass(frozen=True)
class Push:
    """A force on a body over a time window, applied at the body's centre of mass.

    Attributes:
        force: (3,) world-frame force [N].
        t_start: start time [s].
        duration: length of the window [s]; the force acts for ``t_start <= t < t_start + duration``.
        body: name of the pushed body.
    """

    force: tuple[float, float, float]
    t_start: float
    duration: float
    body: str

    def active(self, t: float) -> bool:
        """True while the push acts at time ``t`` [s]."""
        return self.t_start <= t < self.t_start + self.duration


# ------------------------------------------------------------------------------------------------
# State mapping MuJoCo <-> Pinocchio
# ------------------------------------------------------------------------------------------------
_F64 = np.dtype(np.float64)  # the float64 descriptor (``a.dtype is _F64`` is a fast exact-type test)


def _all_finite(a: np.ndarray) -> bool:
    """True when every entry of the float array ``a`` is finite (a finite ``a·a`` proves it cheaply)."""
    return math.isfinite(a.dot(a)) or bool(np.isfinite(a).all())


def _quat_wxyz_to_rot(qw: float, qx: float, qy: float, qz: float) -> np.ndarray:
    n = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    if not n > 0.0:
        raise StateError("quaternion", (qw, qx, qy, qz), "a non-zero quaternion")
    qw, qx, qy, qz = qw / n, qx / n, qy / n, qz / n
    return np.array(
        [
            1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw),
            2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
            2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy),
        ]
    ).reshape(3, 3)


class StateMap:
    """Converts MuJoCo (qpos, qvel) to Pinocchio (q, v) and back for a model loaded by both.

    Pinocchio's ``buildModelFromMJCF`` keeps MuJoCo's joint order (the MJCF tree order), turns a free
    joint into a free-flyer and a ball joint into a spherical joint; nq and nv are equal. Per joint:

    - free: position copied; quaternion (w, x, y, z) → (x, y, z, w); linear velocity rotated from the
      world frame into the body frame (angular velocity is in the body frame in both);
    - ball: quaternion reordered; angular velocity (body frame in both) copied;
    - hinge, slide: copied.
    """

    def __init__(self, model: Any) -> None:
        self.nq = int(model.nq)
        self.nv = int(model.nv)
        self._free: list[tuple[int, int]] = []
        self._ball: list[int] = []
        for j in range(model.njnt):
            t = model.jnt_type[j]
            if t == mujoco.mjtJoint.mjJNT_FREE:
                self._free.append((int(model.jnt_qposadr[j]), int(model.jnt_dofadr[j])))
            elif t == mujoco.mjtJoint.mjJNT_BALL:
                self._ball.append(int(model.jnt_qposadr[j]))
        # q_pinocchio = qpos[_perm]: every quaternion (w, x, y, z) -> (x, y, z, w), the rest copied
        perm = np.arange(self.nq)
        for a in [a + 3 for a, _ in self._free] + self._ball:
            perm[a : a + 4] = (a + 1, a + 2, a + 3, a)
        self._perm = perm
        self._free_quat = [(a + 3, b) for a, b in self._free]  # (qpos address of w, dof address)

    def _check(self, a: np.ndarray, n: int, name: str) -> np.ndarray:
        a = np.asarray(a, dtype=float)
        if a.shape != (n,):
            raise StateError(name, f"array of shape {a.shape}", f"shape ({n},)")
        if not np.all(np.isfinite(a)):
            raise StateError(name, "non-finite values", "finite numbers")
        return a

    def to_pinocchio(self, qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) in Pinocchio's convention from MuJoCo's (qpos, qvel)."""
        q = self._check(qpos, self.nq, "qpos").copy()
        v = self._check(qvel, self.nv, "qvel").copy()
        return self._convert_to_pinocchio(q, v)

    def _convert_to_pinocchio(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """In-place conversion of copies ``q``, ``v`` (no validation)."""
        q[:] = q[self._perm]
        self._rotate_free_velocities(q, v)
        return q, v

    def _pinocchio_copy(self, qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """New (q, v) arrays in Pinocchio's convention from MuJoCo's (no validation)."""
        q = qpos.take(self._perm)
        v = qvel.copy()
        self._rotate_free_velocities(q, v)
        return q, v

    def _rotate_free_velocities(self, q: np.ndarray, v: np.ndarray) -> None:
        """Free joints: linear velocity world -> base frame (``q`` already in Pinocchio order)."""
        for a, b in self._free_quat:
            x, y, z, w = q[a : a + 4].tolist()
            R = _quat_wxyz_to_rot(w, x, y, z)
            v[b : b + 3] = R.T @ v[b : b + 3]

    def to_mujoco(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(qpos, qvel) in MuJoCo's convention from Pinocchio's (q, v)."""
        qpos = self._check(q, self.nq, "q").copy()
        qvel = self._check(v, self.nv, "v").copy()
        for a, b in self._free:
            x, y, z, w = qpos[a + 3 : a + 7]
            R = _quat_wxyz_to_rot(w, x, y, z)
            qpos[a + 3 : a + 7] = (w, x, y, z)
            qvel[b : b + 3] = R @ qvel[b : b + 3]
        for a in self._ball:
            x, y, z, w = qpos[a : a + 4]
            qpos[a : a + 4] = (w, x, y, z)
        return qpos, qvel


def mujoco_to_pinocchio(qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) for Pinocchio from a MuJoCo state whose first joint is a free joint, the rest 1-DoF.

    Quaternion (w, x, y, z) → (x, y, z, w); base linear velocity world → body frame.
    """
    qpos = np.asarray(qpos, dtype=float)
    qvel = np.asarray(qvel, dtype=float)
    if qpos.ndim != 1 or qvel.ndim != 1 or qpos.size < 7 or qvel.size != qpos.size - 1:
        raise StateError(
            "qpos/qvel", f"shapes {qpos.shape}/{qvel.shape}", "(7 + n,) and (6 + n,) for a free-joint base"
        )
    if not (np.all(np.isfinite(qpos)) and np.all(np.isfinite(qvel))):
        raise StateError("qpos/qvel", "non-finite values", "finite numbers")
    R = _quat_wxyz_to_rot(*qpos[3:7])
    q = np.concatenate([qpos[:3], qpos[4:7], qpos[3:4], qpos[7:]])
    v = np.concatenate([R.T @ qvel[:3], qvel[3:]])
    return q, v


def pinocchio_to_mujoco(q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`mujoco_to_pinocchio`."""
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    if q.ndim != 1 or v.ndim != 1 or q.size < 7 or v.size != q.size - 1:
        raise StateError("q/v", f"shapes {q.shape}/{v.shape}", "(7 + n,) and (6 + n,) for a free-flyer base")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
        raise StateError("q/v", "non-finite values", "finite numbers")
    R = _quat_wxyz_to_rot(q[6], q[3], q[4], q[5])
    qpos = np.concatenate([q[:3], q[6:7], q[3:6], q[7:]])
    qvel = np.concatenate([R @ v[:3], v[3:]])
    return qpos, qvel


# ------------------------------------------------------------------------------------------------
# The compiled control tick (lipmpcc._mjtick)
# ------------------------------------------------------------------------------------------------
def _check_tick_module(mod: Any) -> tuple[Any, bool] | None:
    """(module, fma_rotation) when ``mod`` (``lipmpcc._mjtick``) can stand in for the Python tick, else None.

    It must be built against the MuJoCo that runs (headers and linked library: ``mj_version()``),
    and reproduce :class:`StateMap`'s base velocity rotation (numpy's ``R.T @ v``, whose BLAS kernel
    may or may not fuse multiply-adds) bit for bit on probe values; either mode is tried.
    """
    try:
        running = int(mujoco.mj_version())
        if int(mod.mujoco_version) != running or int(mod.linked_mujoco_version()) != running:
            return None
        rng = np.random.default_rng(12345)
        probes = [(rng.normal(size=4), rng.normal(size=3) * 10.0 ** rng.integers(-3, 3)) for _ in range(64)]
        for fma in (True, False):
            if all(
                np.array_equal(
                    mod.rotate_transposed(*qt.tolist(), v, fma), _quat_wxyz_to_rot(*qt.tolist()).T @ v
                )
                for qt, v in probes
            ):
                return mod, fma
    except Exception:  # an incompatible or broken build: keep the Python path
        return None
    return None


def _load_tick_module() -> tuple[Any, bool] | None:
    """The compiled tick, if it is installed and usable (see :func:`_check_tick_module`).

    ``LIPMPCC_PYTHON_TICK=1`` in the environment keeps the Python path (identical results).
    """
    if os.environ.get("LIPMPCC_PYTHON_TICK", "") not in ("", "0"):
        return None
    try:
        from .. import _mjtick
    except ImportError:
        return None
    return _check_tick_module(_mjtick)


_TICK = _load_tick_module()


# ------------------------------------------------------------------------------------------------
# Log
# ------------------------------------------------------------------------------------------------
@dataclass
class SimLog:
    """Samples of a run (every ``every`` simulation steps), as lists; :meth:`arrays` stacks them.

    Fields per sample: ``t`` [s], ``qpos``, ``qvel``, ``ctrl``, ``com`` [m], ``com_vel`` [m/s],
    ``contact`` (left, right), ``normal_force`` (left, right) [N], ``push`` (3,) [N] on the torso.
    """

    every: int = 10
    t: list[float] = field(default_factory=list)
    qpos: list[np.ndarray] = field(default_factory=list)
    qvel: list[np.ndarray] = field(default_factory=list)
    ctrl: list[np.ndarray] = field(default_factory=list)
    com: list[np.ndarray] = field(default_factory=list)
    com_vel: list[np.ndarray] = field(default_factory=list)
    contact: list[tuple[bool, bool]] = field(default_factory=list)
    normal_force: list[tuple[float, float]] = field(default_factory=list)
    push: list[np.ndarray] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.t)

    def arrays(self) -> dict[str, np.ndarray]:
        """Every field as a NumPy array (first axis: sample)."""
        names = ("t", "qpos", "qvel", "ctrl", "com", "com_vel", "contact", "normal_force", "push")
        return {n: np.asarray(getattr(self, n)) for n in names}

    def save(self, path: str | Path) -> Path:
        """Write :meth:`arrays` to an ``.npz`` file."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(path, **self.arrays())
        return path


# ------------------------------------------------------------------------------------------------
# The simulator
# ------------------------------------------------------------------------------------------------
def _has_ground(model: Any) -> bool:
    ground = (int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_HFIELD))
    return any(int(model.geom_bodyid[g]) == 0 and int(model.geom_type[g]) in ground for g in range(model.ngeom))


def _compile_scene(path: Path, scene_editor: Callable[[Any], None] | None) -> Any:
    if not path.is_file():
        raise ModelFileError(str(path), "file not found")
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        if scene_editor is not None:
            scene_editor(spec)
        model = spec.compile()
        if not _has_ground(model):
            spec.worldbody.add_geom(
                name="lipmpcc_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.0, 0.0, 0.05],
                contype=0, conaffinity=1, condim=3, rgba=[0.35, 0.4, 0.45, 1.0],
            )
            model = spec.compile()
    except (ValueError, RuntimeError) as err:
        raise ModelFileError(str(path), f"MuJoCo cannot load it: {' '.join(str(err).split())}") from None
    return model


class RobotSim:
    """A biped in MuJoCo.

    Args:
        robot: a :class:`~lipmpcc.robot.RobotDescription`, ``"digit_like"``, or an MJCF path.
        timestep: simulation step [s] (0.5 ms: 2 kHz).
        fall: the :class:`FallCriterion`.
        scene_editor: called with the ``mujoco.MjSpec`` of the scene before it is compiled (to add
            terrain such as stepping stones: geoms with conaffinity bit 0 touch the feet).
        log_every: record a :class:`SimLog` sample every this many steps (None: no log).
        contact_threshold: normal force [N] above which a foot counts as touching.

    Raises:
        ModelFileError / RobotDescriptionError: bad model (see :func:`~lipmpcc.robot.load_robot`).
        ParameterError: bad time step or threshold.
    """

    def __init__(
        self,
        robot: RobotDescription | str | Path = "digit_like",
        timestep: float = 0.0005,
        *,
        fall: FallCriterion | None = None,
        scene_editor: Callable[[Any], None] | None = None,
        log_every: int | None = None,
        contact_threshold: float = 1.0,
    ) -> None:
        if not (isinstance(timestep, (int, float)) and math.isfinite(timestep) and 0.0 < timestep <= 0.005):
            raise ParameterError("timestep", timestep, "a time step in (0, 0.005] s (0.0005 for 2 kHz)")
        if not (math.isfinite(contact_threshold) and contact_threshold >= 0.0):
            raise ParameterError("contact_threshold", contact_threshold, "a non-negative force [N]")
        if log_every is not None and (int(log_every) != log_every or log_every < 1):
            raise ParameterError("log_every", log_every, "a positive integer number of steps or None")
        self.description = robot if isinstance(robot, RobotDescription) else load_robot(robot)
        desc = self.description
        self._model = _compile_scene(Path(desc.scene_path), scene_editor)
        self._model.opt.timestep = float(timestep)
        self._data = mujoco.MjData(self._model)
        self.fall_criterion = fall or FallCriterion()
        self.contact_threshold = float(contact_threshold)
        m = self._model

        def body_id(name: str) -> int:
            return int(mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name))

        self._torso = body_id(desc.torso_body)
        self._feet = (body_id(desc.left_foot_body), body_id(desc.right_foot_body))
        self._sole_sites = tuple(
            int(mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, s)) if s else -1
            for s in (desc.left_sole_site, desc.right_sole_site)
        )
        self._sole_offset = np.asarray(desc.sole_offset, dtype=float)
        # which robot body belongs to which foot (the foot body and its subtree)
        self._body_side = np.full(m.nbody, -1, dtype=int)
        self._robot_body = np.zeros(m.nbody, dtype=bool)
        for b in range(m.nbody):
            a = b
            while a != 0:
                if a == self._feet[0]:
                    self._body_side[b] = 0
                if a == self._feet[1]:
                    self._body_side[b] = 1
                if a == self._torso:
                    self._robot_body[b] = True
                a = int(m.body_parentid[a])
        self._ctrl_lo = m.actuator_ctrlrange[:, 0].copy()
        self._ctrl_hi = m.actuator_ctrlrange[:, 1].copy()
        self._gear = m.actuator_gear[:, 0].copy()
        self._ctrl_shape = (int(m.nu),)  # shape of a motor command vector
        self.state_map = StateMap(m)
        self._pushes: list[tuple[Push, int, np.ndarray]] = []
        self._pushed_bodies: set[int] = set()
        self._push_bounds: list[float] = []  # start and end time of every push, sorted [s]
        self._stale = True
        # mj_step splits into mj_step1 (position and velocity stages) + mj_step2 (the rest and the
        # integration) for every integrator but RK4. The accessors compute a state's derived fields as
        # mj_step1 + the acceleration stages (= mj_forward); the next step() then runs only mj_step2 for
        # its first substep, on the same state (bit-identical to mj_step, one position stage less).
        self._split = int(m.opt.integrator) != int(mujoco.mjtIntegrator.mjINT_RK4)
        self._primed = False  # data's position/velocity stages match the state saved below
        self._primed_state = (b"", b"", b"")  # qpos, qvel, act as bytes (cheap to compare)
        self._log_every = log_every
        self.log: SimLog | None = SimLog(every=log_every) if log_every else None
        self._steps = 0
        self._cforce = np.zeros(6)
        self._geom_side = [int(self._body_side[b]) for b in m.geom_bodyid]
        self._geom_robot = [bool(self._robot_body[b]) for b in m.geom_bodyid]
        self._version = 0  # bumped whenever the state changes; keys the contact cache
        self._contact_version = -1
        self._contact_cache: tuple[np.ndarray, np.ndarray, bool] = (np.zeros(3), np.zeros(3), False)
        # views of MjData's fixed-size arrays (their buffers live as long as the MjData)
        d = self._data
        self._qpos, self._qvel, self._ctrl = d.qpos, d.qvel, d.ctrl
        self._xpos, self._xmat = d.xpos, d.xmat
        self._site_xpos, self._site_xmat = d.site_xpos, d.site_xmat
        self._subtree_com, self._subtree_linvel = d.subtree_com, d.subtree_linvel
        self._tick = self._make_tick()
        self.reset(desc.standing_keyframe if desc.standing_keyframe else ("stand" if desc.standing_qpos else None))

    def _make_tick(self) -> Any:
        """The compiled control tick (``lipmpcc._mjtick.Tick``) on this model and data, or None.

        None when the module is missing or unusable (see :func:`_check_tick_module`), or when the
        robot has no sole sites. It writes its measurements into ``self._tick_buf``, read through the
        views ``self._tick_views``; the Python path gives identical results.
        """
        if _TICK is None or min(self._sole_sites) < 0:
            return None
        mod, fma = _TICK
        m, sm = self._model, self.state_map
        cfg = mod.TickConfig()
        cfg.torso = self._torso
        cfg.sole_site = self._sole_sites
        cfg.geom_side = self._geom_side
        cfg.geom_robot = [int(r) for r in self._geom_robot]
        cfg.perm = sm._perm.tolist()
        cfg.free_quat = sm._free_quat
        cfg.split = self._split
        cfg.fma_rotation = fma
        lay = mod.layout(sm.nq, sm.nv)
        buf = np.zeros(lay["size"])
        tick = mod.Tick(m._address, self._data._address, cfg, buf)

        def vec(a: int, n: int) -> np.ndarray:
            return buf[a : a + n]

        def mat(a: int) -> np.ndarray:
            return buf[a : a + 9].reshape(3, 3)

        self._tick_buf = buf
        self._tick_other = int(lay["other"])
        self._tick_views = (
            vec(lay["q"], sm.nq), vec(lay["v"], sm.nv), vec(lay["com"], 3), vec(lay["com_vel"], 3),
            vec(lay["torso_pos"], 3), mat(lay["torso_rot"]),
            vec(lay["foot_pos"][0], 3), mat(lay["foot_rot"][0]), vec(lay["foot_pos"][1], 3), mat(lay["foot_rot"][1]),
            vec(lay["force"][0], 3), vec(lay["force"][1], 3),
        )
        return tick

    @property
    def compiled_tick(self) -> bool:
        """True when :meth:`step` and :meth:`measure` run in the compiled module ``lipmpcc._mjtick``
        (identical results; the Python path otherwise)."""
        return self._tick is not None

    # ---- basic properties -----------------------------------------------------------------
    @property
    def model(self) -> Any:
        """The ``mujoco.MjModel``."""
        return self._model

    @property
    def data(self) -> Any:
        """The ``mujoco.MjData`` (derived fields are current only after :meth:`forward`)."""
        return self._data

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self._data.time)

    @property
    def timestep(self) -> float:
        """Simulation step [s]."""
        return float(self._model.opt.timestep)

    @property
    def nu(self) -> int:
        """Number of motors."""
        return int(self._model.nu)

    @property
    def qpos(self) -> np.ndarray:
        """MuJoCo configuration (a copy)."""
        return self._data.qpos.copy()

    @property
    def qvel(self) -> np.ndarray:
        """MuJoCo velocity (a copy)."""
        return self._data.qvel.copy()

    @property
    def ctrl_range(self) -> tuple[np.ndarray, np.ndarray]:
        """(lower, upper) motor command bounds (MuJoCo clamps commands to them)."""
        return self._ctrl_lo.copy(), self._ctrl_hi.copy()

    def torque_to_ctrl(self, tau: np.ndarray) -> np.ndarray:
        """Motor commands producing joint torques ``tau`` [N m] (ctrl = tau / gear; gear 1 for digit_like)."""
        tau = np.asarray(tau, dtype=float)
        if tau.shape != (self.nu,):
            raise InvalidInputError("tau", f"array of shape {tau.shape}", f"shape ({self.nu},)")
        return tau / self._gear

    # ---- state -----------------------------------------------------------------------------
    def reset(self, keyframe: str | None = "stand") -> None:
        """Reset the state, time, pushes and log.

        Args:
            keyframe: a keyframe name; ``"stand"`` also selects the description's standing
                configuration when the model has no such keyframe; None: the model's qpos0.
        """
        m, d = self._model, self._data
        mujoco.mj_resetData(m, d)
        if keyframe is not None:
            k = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_KEY, keyframe)
            if k >= 0:
                mujoco.mj_resetDataKeyframe(m, d, k)
            elif keyframe in ("stand", self.description.standing_keyframe) and self.description.standing_qpos:
                d.qpos[:] = self.description.standing_qpos
            else:
                keys = [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_KEY, i) for i in range(m.nkey)]
                raise InvalidInputError("keyframe", keyframe, f"one of {keys} or None")
        self._pushes.clear()
        self._push_bounds.clear()
        if self._tick is not None:
            self._tick.clear_pushes()
        self._clear_push_forces()
        self._steps = 0
        if self._log_every:
            self.log = SimLog(every=self._log_every)
        mujoco.mj_forward(m, d)
        self._stale = False
        self._version += 1

    def set_state(self, qpos: np.ndarray, qvel: np.ndarray | None = None) -> None:
        """Set the MuJoCo state (validated; velocity zero when omitted)."""
        qpos = self.state_map._check(qpos, self._model.nq, "qpos")
        qvel = np.zeros(self._model.nv) if qvel is None else self.state_map._check(qvel, self._model.nv, "qvel")
        self._data.qpos[:] = qpos
        self._data.qvel[:] = qvel
        mujoco.mj_forward(self._model, self._data)
        self._stale = False
        self._version += 1

    def set_pinocchio_state(self, q: np.ndarray, v: np.ndarray) -> None:
        """Set the state from Pinocchio's (q, v)."""
        self.set_state(*self.state_map.to_mujoco(q, v))

    def pinocchio_state(self) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) in Pinocchio's convention for ``pinocchio.buildModelFromMJCF(description.mjcf_path)``.

        Quaternion (x, y, z, w); free-flyer linear and angular velocity in the base (local) frame.
        """
        qpos, qvel = self._qpos, self._qvel
        if not (_all_finite(qpos) and _all_finite(qvel)):
            raise StateError("simulation state", "non-finite values", "a finite state (the simulation diverged)")
        return self.state_map._pinocchio_copy(qpos, qvel)

    def forward(self) -> None:
        """Run ``mj_forward``: derived fields of :attr:`data` (positions, contacts, ...) match its state.

        Needed before reading ``sim.data`` after :meth:`step`, or after writing ``sim.data.qpos``
        directly; the accessor methods of this class do it themselves.
        """
        mujoco.mj_forward(self._model, self._data)
        self._stale = False
        self._version += 1

    def _ensure_forward(self) -> None:
        if self._stale:
            if self._tick is not None:  # the same stages and snapshot, in C++
                self._tick.prime()
                self._stale = False
                return
            m, d = self._model, self._data
            if self._split:  # = mj_forward, and leaves the next step only mj_step2 to do
                mujoco.mj_step1(m, d)
                mujoco.mj_fwdActuation(m, d)
                mujoco.mj_fwdAcceleration(m, d)
                mujoco.mj_fwdConstraint(m, d)
                mujoco.mj_sensorAcc(m, d)
                self._primed_state = (d.qpos.tobytes(), d.qvel.tobytes(), d.act.tobytes())
                self._primed = True
            else:
                mujoco.mj_forward(m, d)
            self._stale = False

    def _take_primed(self) -> bool:
        """True (once) when data's position/velocity stages are those of its current state, so that
        mj_step2 may start the next step (the state was not edited by hand since)."""
        if self._tick is not None:
            return self._tick.take_primed()
        if not self._primed:
            return False
        self._primed = False
        d = self._data
        return self._primed_state == (d.qpos.tobytes(), d.qvel.tobytes(), d.act.tobytes())

    # ---- stepping --------------------------------------------------------------------------
    def step(self, ctrl: np.ndarray, n: int = 1) -> None:
        """Hold motor commands ``ctrl`` (nu,) for ``n`` simulation steps.

        Commands outside ``ctrl_range`` are clamped by MuJoCo. Active pushes are applied at each step.

        Raises:
            InvalidInputError: ``ctrl`` of the wrong shape or not finite, ``n`` not a positive integer.
        """
        if type(ctrl) is np.ndarray and ctrl.dtype is _F64:
            c = ctrl
        else:
            try:
                c = np.asarray(ctrl, dtype=float)
            except (TypeError, ValueError):
                raise InvalidInputError("ctrl", ctrl, f"a real vector of shape ({self.nu},) [motor commands]") from None
        if c.shape != self._ctrl_shape:
            raise InvalidInputError(
                "ctrl", f"array of shape {c.shape}", f"a vector of shape ({self.nu},) [motor commands]"
            )
        tick = self._tick
        if tick is not None and self.log is None:  # the compiled tick (identical results)
            if isinstance(n, bool) or int(n) != n or n < 1:
                self._check_ctrl_finite(c)
                raise InvalidInputError("n", n, "a positive integer number of steps")
            if not tick.step(c, int(n)):  # nothing done: ctrl not finite
                self._check_ctrl_finite(c)
            self._steps += int(n)
            self._version += 1
            self._stale = True
            return
        self._check_ctrl_finite(c)
        if isinstance(n, bool) or int(n) != n or n < 1:
            raise InvalidInputError("n", n, "a positive integer number of steps")
        n = int(n)
        m, d = self._model, self._data
        self._ctrl[:] = c
        log = self.log
        step2 = self._take_primed()
        if log is None:
            left = n
            if step2:  # the first substep's position/velocity stages are done (see _ensure_forward)
                if self._pushes:
                    self._apply_pushes()
                mujoco.mj_step2(m, d)
                left -= 1
            # runs of steps with the same active pushes go to MuJoCo in one call (mj_step's nstep)
            while left > 0:
                if self._pushes:
                    k = self._steps_with_same_pushes(left)
                    self._apply_pushes()
                else:
                    k = left
                mujoco.mj_step(m, d, k)
                left -= k
            self._steps += n
            self._version += 1
        else:
            pushes = bool(self._pushes)
            for i in range(n):
                if pushes:
                    self._apply_pushes()
                if i == 0 and step2:
                    mujoco.mj_step2(m, d)
                else:
                    mujoco.mj_step(m, d)
                self._steps += 1
                self._version += 1
                if self._steps % log.every == 0:
                    self._stale = True
                    self._record()
        self._stale = True

    @staticmethod
    def _check_ctrl_finite(c: np.ndarray) -> None:
        if not _all_finite(c):
            bad = np.flatnonzero(~np.isfinite(c))
            raise InvalidInputError("ctrl", c, "finite motor commands", f"non-finite entries at {bad.tolist()}")

    def run(
        self,
        duration: float,
        controller: Callable[["RobotSim"], np.ndarray] | None = None,
        steps_per_control: int = 1,
        progress: bool | None = None,
        stop_on_fall: bool = True,
    ) -> bool:
        """Simulate ``duration`` [s], calling ``controller(sim) -> ctrl`` every ``steps_per_control`` steps.

        Args:
            duration: simulated time [s].
            controller: returns the motor commands; None holds zero commands.
            steps_per_control: simulation steps per controller call (5: 400 Hz at 2 kHz).
            progress: progress bar (tqdm); None shows it only on a terminal, False never.
            stop_on_fall: stop as soon as :meth:`fallen` is true.

        Returns:
            True when the run ended without a fall.
        """
        from tqdm.auto import tqdm

        if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
            raise InvalidInputError("duration", duration, "a positive simulated time [s]")
        if int(steps_per_control) != steps_per_control or steps_per_control < 1:
            raise InvalidInputError("steps_per_control", steps_per_control, "a positive integer")
        n_total = int(round(duration / self.timestep))
        zero = np.zeros(self.nu)
        done = 0
        ok = True
        with tqdm(total=n_total, desc="sim", unit="step", unit_scale=True, leave=False,
                  disable=(None if progress is None else not progress)) as bar:
            while done < n_total:
                ctrl = zero if controller is None else controller(self)
                k = min(int(steps_per_control), n_total - done)
                self.step(ctrl, k)
                done += k
                bar.update(k)
                if stop_on_fall and self.fallen():
                    ok = False
                    break
        return ok

    # ---- pushes ----------------------------------------------------------------------------
    def add_push(self, force_xyz: np.ndarray, t_start: float, duration: float, body: str | None = None) -> Push:
        """Push ``body`` (default: the torso) with a world-frame force [N] for ``t_start <= t < t_start + duration``.

        Applied through ``xfrc_applied`` at the body's centre of mass; several pushes add up. Cleared
        by :meth:`reset`.
        """
        f = np.asarray(force_xyz, dtype=float)
        if f.shape != (3,) or not np.all(np.isfinite(f)):
            raise InvalidInputError("force_xyz", force_xyz, "a finite 3-vector [N]")
        if not (math.isfinite(t_start) and t_start >= 0):
            raise InvalidInputError("t_start", t_start, "a non-negative time [s]")
        if not (math.isfinite(duration) and duration > 0):
            raise InvalidInputError("duration", duration, "a positive duration [s]")
        name = body or self.description.torso_body
        b = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_BODY, name)
        if b < 0:
            raise InvalidInputError("body", name, "the name of a body of the model")
        push = Push(
            force=(float(f[0]), float(f[1]), float(f[2])), t_start=float(t_start), duration=float(duration), body=name
        )
        self._pushes.append((push, int(b), f.copy()))
        if self._tick is not None:
            self._tick.add_push(int(b), push.force[0], push.force[1], push.force[2], push.t_start,
                                push.t_start + push.duration)
        self._pushed_bodies.add(int(b))
        bisect.insort(self._push_bounds, push.t_start)
        bisect.insort(self._push_bounds, push.t_start + push.duration)
        return push

    @property
    def pushes(self) -> tuple[Push, ...]:
        """Registered pushes."""
        return tuple(p for p, _, _ in self._pushes)

    def push_force(self, t: float | None = None) -> np.ndarray:
        """Total push force on the torso at time ``t`` (default: now) [N]."""
        t = self.time if t is None else t
        total = np.zeros(3)
        for p, b, f in self._pushes:
            if b == self._torso and p.active(t):
                total += f
        return total

    def _clear_push_forces(self) -> None:
        for b in self._pushed_bodies:
            self._data.xfrc_applied[b, :] = 0.0

    def _steps_with_same_pushes(self, n: int) -> int:
        """How many of the next ``n`` steps (at least 1) start with the same pushes active as now.

        Step i starts at the time MuJoCo reaches after i additions of the time step; a push's
        active state changes only when its start or end lies in (now, that time].
        """
        t0 = float(self._data.time)
        dt = float(self._model.opt.timestep)
        bounds = self._push_bounds  # sorted
        k = bisect.bisect_right(bounds, t0)  # bounds[k:] > t0
        if k == len(bounds) or bounds[k] > t0 + n * dt:  # none before the last step (clear margin)
            return n
        t = t0
        for i in range(1, n):
            t += dt
            if bounds[k] <= t:
                return i
        return n

    def _apply_pushes(self) -> None:
        t = self._data.time
        xfrc = self._data.xfrc_applied
        for b in self._pushed_bodies:
            xfrc[b, :3] = 0.0
        for p, b, f in self._pushes:
            if p.active(t):
                xfrc[b, :3] += f

    # ---- measurements ----------------------------------------------------------------------
    def com(self) -> np.ndarray:
        """Centre of mass of the robot (the torso's subtree) [m], world frame."""
        self._ensure_forward()
        return self._subtree_com[self._torso].copy()

    def com_velocity(self) -> np.ndarray:
        """Velocity of the robot's centre of mass [m/s], world frame."""
        self._ensure_forward()
        mujoco.mj_subtreeVel(self._model, self._data)
        return self._subtree_linvel[self._torso].copy()

    def torso_pose(self) -> FramePose:
        """Torso (floating base) frame in the world."""
        self._ensure_forward()
        b = self._torso
        return FramePose(self._xpos[b].copy(), self._xmat[b].reshape(3, 3).copy())

    def foot_poses(self) -> tuple[FramePose, FramePose]:
        """(left, right) sole frames: centre of the sole on the contact surface; x forward, z up when flat."""
        self._ensure_forward()
        return self._foot_pose(0), self._foot_pose(1)

    def _foot_pose(self, side: int) -> FramePose:
        s = self._sole_sites[side]
        if s >= 0:
            return FramePose(self._site_xpos[s].copy(), self._site_xmat[s].reshape(3, 3).copy())
        b = self._feet[side]
        R = self._xmat[b].reshape(3, 3).copy()
        return FramePose(self._xpos[b] + R @ self._sole_offset, R)

    def measure(self, on_state: Callable[[np.ndarray, np.ndarray], object] | None = None) -> Measurement:
        """Everything a controller reads at this instant, from one ``mj_forward`` (see :class:`Measurement`).

        Equal to calling :meth:`pinocchio_state`, :meth:`com`, :meth:`com_velocity`,
        :meth:`torso_pose`, :meth:`foot_poses`, :meth:`contact_state` and :meth:`normal_forces` one
        after the other, in a fraction of their time. The arrays are new (not views of :attr:`data`).

        Args:
            on_state: called with the Pinocchio state ``(q, v)`` (the arrays of the returned
                measurement) before the forward pass, so that work on it can start early (the
                full-body loop hands it to ``WholeBodyController.prepare``).

        Raises:
            StateError: the simulation diverged (non-finite state).
        """
        tick = self._tick
        if tick is not None:
            views = self._tick_views
            mapped = False
            q = v = None
            if on_state is not None and tick.state() == 0:
                q, v = views[0].copy(), views[1].copy()
                on_state(q, v)
                mapped = True
            if tick.measure(self._stale, mapped):  # nothing done: raise the Python path's error
                self.pinocchio_state()
                raise StateError("simulation state", "a state the compiled tick rejects", "a finite state")
            self._stale = False
            _, _, com, com_vel, tp, tR, lp, lR, rp, rR, fl, fr = views
            if q is None:
                q, v = views[0].copy(), views[1].copy()
            fl, fr = fl.copy(), fr.copy()
            self._contact_cache = (fl, fr, bool(self._tick_buf[self._tick_other]))
            self._contact_version = self._version
            return self._measurement(
                q, v, com.copy(), com_vel.copy(), FramePose(tp.copy(), tR.copy()),
                (FramePose(lp.copy(), lR.copy()), FramePose(rp.copy(), rR.copy())), fl, fr,
            )
        q, v = self.pinocchio_state()
        if on_state is not None:
            on_state(q, v)
        self._ensure_forward()
        mujoco.mj_subtreeVel(self._model, self._data)
        t = self._torso
        fl, fr, _ = self._foot_contacts()
        return self._measurement(
            q, v, self._subtree_com[t].copy(), self._subtree_linvel[t].copy(),
            FramePose(self._xpos[t].copy(), self._xmat[t].reshape(3, 3).copy()),
            (self._foot_pose(0), self._foot_pose(1)), fl, fr,
        )

    def _measurement(self, q: np.ndarray, v: np.ndarray, com: np.ndarray, com_vel: np.ndarray, torso: FramePose,
                     feet: tuple[FramePose, FramePose], fl: np.ndarray, fr: np.ndarray) -> Measurement:
        """:meth:`measure`'s result from its parts (``fl``, ``fr``: world-frame foot forces [N])."""
        nl, nr = float(fl[2]), float(fr[2])
        thr = self.contact_threshold
        return Measurement(
            time=float(self._data.time), q=q, v=v, com=com, com_vel=com_vel, torso=torso, feet=feet,
            contact=(nl > thr, nr > thr), normal_force=(nl, nr),
        )

    def _foot_contacts(self) -> tuple[np.ndarray, np.ndarray, bool]:
        """World-frame contact force on each foot [N], and whether a non-foot robot geom touches (cached per state).

        Only contacts that involve a foot geom get their force computed (``mj_contactForce``, in the
        contact frame, rotated to the world frame and summed per foot in contact order).
        """
        if self._contact_version == self._version:
            return self._contact_cache
        self._ensure_forward()
        if self._tick is not None:  # the same sums in C++
            other = self._tick.contacts()
            fl, fr = self._tick_views[10:12]
            self._contact_cache = (fl.copy(), fr.copy(), bool(other))
            self._contact_version = self._version
            return self._contact_cache
        m, d = self._model, self._data
        fl = [0.0, 0.0, 0.0]
        fr = [0.0, 0.0, 0.0]
        other = False
        ncon = int(d.ncon)
        if ncon:
            con = d.contact
            gside, grobot = self._geom_side, self._geom_robot
            f6 = self._cforce
            frames = None
            for i, (g1, g2) in enumerate(con.geom[:ncon].tolist()):
                s1, s2 = gside[g1], gside[g2]
                if s1 < 0 and s2 < 0:
                    other = other or grobot[g1] or grobot[g2]
                    continue
                if frames is None:
                    frames = con.frame[:ncon].tolist()
                mujoco.mj_contactForce(m, d, i, f6)  # contact frame: normal, tangent 1, tangent 2
                fn, t1, t2 = f6[:3].tolist()
                a = frames[i]  # rows: the contact frame's axes in the world
                x = a[0] * fn + a[3] * t1 + a[6] * t2
                y = a[1] * fn + a[4] * t1 + a[7] * t2
                z = a[2] * fn + a[5] * t1 + a[8] * t2
                if s2 >= 0:  # the force of geom1 on geom2
                    acc = fr if s2 else fl
                    acc[0] += x
                    acc[1] += y
                    acc[2] += z
                if s1 >= 0:
                    acc = fr if s1 else fl
                    acc[0] -= x
                    acc[1] -= y
                    acc[2] -= z
        self._contact_cache = (np.array(fl), np.array(fr), other)
        self._contact_version = self._version
        return self._contact_cache

    def contact_forces(self) -> tuple[np.ndarray, np.ndarray]:
        """(left, right) total contact force on each foot [N], world frame."""
        fl, fr, _ = self._foot_contacts()
        return fl, fr

    def normal_forces(self) -> tuple[float, float]:
        """(left, right) vertical contact force on each foot [N] (the normal force on flat ground)."""
        fl, fr, _ = self._foot_contacts()
        return float(fl[2]), float(fr[2])

    def contact_state(self) -> tuple[bool, bool]:
        """(left, right): the foot carries more than ``contact_threshold`` newtons of vertical force."""
        fl, fr = self.normal_forces()
        return fl > self.contact_threshold, fr > self.contact_threshold

    def fall_reason(self) -> str | None:
        """Why the robot counts as fallen (see :class:`FallCriterion`), or None."""
        crit = self.fall_criterion
        pose = self.torso_pose()
        (pl, _), (pr, _) = self.foot_poses()
        height = pose.position[2] - min(pl[2], pr[2])
        if height < crit.min_height:
            return f"torso {height:.3f} m above the lower sole (< {crit.min_height} m)"
        tilt = math.acos(max(-1.0, min(1.0, float(pose.rotation[2, 2]))))
        if tilt > crit.max_tilt:
            return f"torso tilted {tilt:.2f} rad (> {crit.max_tilt} rad)"
        if crit.non_foot_contact and self._foot_contacts()[2]:
            return "a robot geom other than a foot touches something"
        return None

    def fallen(self) -> bool:
        """True when the robot has fallen (:meth:`fall_reason` is not None)."""
        return self.fall_reason() is not None

    def _record(self) -> None:
        log = self.log
        assert log is not None
        d = self._data
        fl, fr, _ = self._foot_contacts()
        log.t.append(float(d.time))
        log.qpos.append(d.qpos.copy())
        log.qvel.append(d.qvel.copy())
        log.ctrl.append(d.ctrl.copy())
        log.com.append(d.subtree_com[self._torso].copy())
        mujoco.mj_subtreeVel(self._model, d)
        log.com_vel.append(d.subtree_linvel[self._torso].copy())
        log.contact.append((fl[2] > self.contact_threshold, fr[2] > self.contact_threshold))
        log.normal_force.append((float(fl[2]), float(fr[2])))
        log.push.append(self.push_force())

    # ---- viewing -----------------------------------------------------------------------------
    def view(self) -> Any:
        """Open MuJoCo's passive viewer on this simulation (needs a display); returns the handle.

        Call ``handle.sync()`` after steps to refresh it; close it with ``handle.close()``.

        Raises:
            RenderUnavailableError: no display (``DISPLAY`` unset).
        """
        if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
            raise RenderUnavailableError(
                "viewer", "no display (DISPLAY is not set); render a video with lipmpcc.sim.render instead"
            )
        import mujoco.viewer

        self._ensure_forward()
        return mujoco.viewer.launch_passive(self._model, self._data)

    def recorder(self, settings: Any = None) -> Any:
        """A :class:`~lipmpcc.sim.render.VideoRecorder` for this model, tracking the torso by default."""
        from .render import VideoRecorder, VideoSettings

        if settings is None:
            settings = VideoSettings(track_body=self.description.torso_body)
        return VideoRecorder(self._model, settings)


__all__ = [
    "FallCriterion",
    "FramePose",
    "Measurement",
    "Push",
    "Rates",
    "RobotSim",
    "SimLog",
    "StateMap",
    "mujoco_to_pinocchio",
    "pinocchio_to_mujoco",
    "LEFT",
    "RIGHT",
]
