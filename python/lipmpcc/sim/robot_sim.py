"""The MuJoCo plant: a biped stepped at the model's rate, measured in Pinocchio's convention.

:class:`RobotSim` owns a ``mujoco.MjModel`` / ``MjData`` for a
:class:`~lipmpcc.robots.RobotDescription` (``"digit_like"`` by default, or a user MJCF): a copy of the
description's compiled scene (robot + floor; a model without a ground plane gets one), or the scene
edited by a ``scene_editor`` (terrain) and compiled for this simulator. It steps the robot, applies
pushes (:class:`~lipmpcc.push.Push`), measures the state for a controller
(:class:`~lipmpcc.sim.types.Measurement`), sums the foot contact forces, and tells when the robot
has fallen (:class:`~lipmpcc.sim.types.FallCriterion`: the torso origin less than ``min_height``
above the lower sole, the torso tilted more than ``max_tilt``, or a robot geom other than a foot
touching something).

State: MuJoCo's ``qpos``/``qvel`` and Pinocchio's ``(q, v)`` (:meth:`RobotSim.pinocchio_state`)
are related by :class:`~lipmpcc.robots.state_map.StateMap` (quaternion order, free-joint
velocity frame); the joint order is the MJCF tree order in both libraries.

Derived quantities (COM, foot poses, contacts) are computed on demand after a step (one
``mj_forward``-equivalent pass, shared by every accessor until the state changes, whose position and
velocity stages the next :meth:`RobotSim.step` reuses: it starts with ``mj_step2``); :meth:`RobotSim.measure`
returns all of them at once for a control tick. ``sim.data`` is the raw MuJoCo data — call
:meth:`RobotSim.forward` before reading its derived fields after :meth:`RobotSim.step` or after
changing its state by hand (prefer :meth:`RobotSim.set_state`).

Compiled tick: when the private module ``lipmpcc._mjtick`` is built against the running MuJoCo
(:mod:`lipmpcc.sim._tick`), :meth:`RobotSim.step` (without a log) and :meth:`RobotSim.measure` run
their MuJoCo calls, pushes, contact sums and state map in C++ on the same ``MjModel`` / ``MjData``
(:attr:`RobotSim.compiled_tick`); the results are bit-identical to the Python path, which runs
otherwise (or with ``LIPMPCC_PYTHON_TICK=1``). The simulation runs at the model's time step
(2 kHz by default).

MuJoCo's warnings: MuJoCo counts its warnings in ``data.warning`` (on either path of the tick, which
share the ``MjData``). A bad position, velocity or acceleration (NaN, inf or huge, e.g. after an
absurd push) means that the simulation diverged: MuJoCo then resets the state to the model's
``qpos0`` and the time to 0, and goes on. :meth:`RobotSim.divergence` tells which of them happened
since the last :meth:`RobotSim.reset`, and :meth:`RobotSim.warning_messages` describes the other
warnings (contact or constraint buffer full, bad inertia, bad controls) in one line each.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from . import render as _render  # noqa: F401  (chooses a headless GL backend before mujoco is imported)
import mujoco  # noqa: E402

from .. import _deprecated
from ..exceptions import InvalidInputError, ParameterError, RenderUnavailableError, StateError
from ..exclusive import exclusive
from ..robots.description import RobotDescription, reset_data
from ..robots.loading import load_robot
from ..robots.mjcf import compile_scene
from . import _tick
from .render import VideoRecorder, VideoSettings

# the plant's value types under private names: their public names read from this module warn (moved)
from ..push import Push as _Push  # noqa: I001
from ..robots.state_map import StateMap as _StateMap
from .types import FALL_HEIGHT_FRACTION
from .types import FallCriterion as _FallCriterion
from .types import FramePose as _FramePose
from .types import Measurement as _Measurement
from .types import SimLog as _SimLog

if TYPE_CHECKING:  # pragma: no cover
    import mujoco.viewer

    from .. import _mjtick
    from ..push import Push
    from ..robots.state_map import StateMap
    from .types import FallCriterion, FramePose, Measurement, SimLog

__all__ = ["RobotSim"]

# names that moved (a DeprecationWarning when read here; removed in lipmpcc 0.3)
__getattr__, _ = _deprecated.forward(__name__, "lipmpcc.sim._legacy", renames={
    "Push": "lipmpcc.push:Push",
    "StateMap": "lipmpcc.robots.state_map:StateMap",
    "FallCriterion": "lipmpcc.sim.types:FallCriterion",
    "FramePose": "lipmpcc.sim.types:FramePose",
    "Measurement": "lipmpcc.sim.types:Measurement",
    "SimLog": "lipmpcc.sim.types:SimLog",
    "mujoco_to_pinocchio": "lipmpcc.robots.state_map:mujoco_to_pinocchio",
    "pinocchio_to_mujoco": "lipmpcc.robots.state_map:pinocchio_to_mujoco",
    "LEFT": "lipmpcc.conventions:LEFT",
    "RIGHT": "lipmpcc.conventions:RIGHT",
})

_F64 = np.dtype(np.float64)  # the float64 descriptor (``a.dtype is _F64`` is a fast exact-type test)

_W = mujoco.mjtWarning
#: MuJoCo warnings after which MuJoCo resets the state (the simulation diverged), and what went bad
_DIVERGENCE = {int(_W.mjWARN_BADQACC): "bad acceleration", int(_W.mjWARN_BADQVEL): "bad velocity",
               int(_W.mjWARN_BADQPOS): "bad position"}
#: the other MuJoCo warnings, in words
_WARNING_TEXT = {
    int(_W.mjWARN_INERTIA): "a body's mass or inertia is too small (mjWARN_INERTIA)",
    int(_W.mjWARN_CONTACTFULL): "the contact buffer was full and contacts were dropped (mjWARN_CONTACTFULL)",
    int(_W.mjWARN_CNSTRFULL): "the constraint buffer was full and constraints were dropped (mjWARN_CNSTRFULL)",
    int(_W.mjWARN_BADCTRL): "non-finite or huge motor commands were set to zero (mjWARN_BADCTRL)",
}


def _all_finite(a: np.ndarray) -> bool:
    """True when every entry of the float array ``a`` is finite (a finite ``a·a`` proves it cheaply)."""
    return math.isfinite(a.dot(a)) or bool(np.isfinite(a).all())


class RobotSim:
    """A biped in MuJoCo.

    Args:
        robot: a :class:`~lipmpcc.robots.RobotDescription` (its compiled
            :attr:`~lipmpcc.robots.RobotDescription.scene_model` is copied, not compiled again),
            ``"digit_like"``, or an MJCF path (resolved with :func:`~lipmpcc.robots.load_robot`).
        timestep: simulation step [s] (0.5 ms: 2 kHz).
        fall: the :class:`~lipmpcc.sim.types.FallCriterion`.
        scene_editor: called with the ``mujoco.MjSpec`` of the scene before it is compiled (to add
            terrain such as stepping stones: geoms with conaffinity bit 0 touch the feet); the edited
            scene is compiled for this simulator.
        log_every: record a :class:`~lipmpcc.sim.types.SimLog` sample every this many steps (None: no log).
        contact_threshold: normal force [N] above which a foot counts as touching.

    Raises:
        ModelFileError / RobotDescriptionError: bad model (see :func:`~lipmpcc.robots.load_robot`).
        ParameterError: bad time step or threshold.
    """

    def __init__(
        self,
        robot: RobotDescription | str | Path = "digit_like",
        timestep: float = 0.0005,
        *,
        fall: FallCriterion | None = None,
        scene_editor: Callable[[mujoco.MjSpec], None] | None = None,
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
        if scene_editor is None:
            self._model = copy.copy(desc.scene_model)  # this simulator's own copy (its time step is set)
        else:
            self._model = compile_scene(Path(desc.scene_path), scene_editor)
        self._model.opt.timestep = float(timestep)
        self._data = mujoco.MjData(self._model)
        self.contact_threshold = float(contact_threshold)
        self._index_model()
        self.state_map = _StateMap(self._model)
        self._init_state(log_every)
        self._tick = self._make_tick()
        self.reset(desc.standing_keyframe if desc.standing_keyframe else ("stand" if desc.standing_qpos else None))
        self.fall_criterion = self._resolve_fall(fall or _FallCriterion())

    def _resolve_fall(self, crit: FallCriterion) -> FallCriterion:
        """``crit`` with its ``min_height`` set: as given, else the layout's ``fall_height``, else
        :data:`~lipmpcc.sim.types.FALL_HEIGHT_FRACTION` of the torso height above the lower sole in the
        standing pose (the simulator has just been reset to it)."""
        if crit.min_height is not None:
            return crit
        height = self.description.fall_height
        if height is None:
            (pl, _), (pr, _) = self.foot_poses()
            height = FALL_HEIGHT_FRACTION * float(self.torso_pose().position[2] - min(pl[2], pr[2]))
        return dataclasses.replace(crit, min_height=float(height))

    def _index_model(self) -> None:
        """Ids of the torso, feet and sole sites; which geom belongs to which foot and to the robot;
        the motor ranges."""
        m, desc = self._model, self.description

        def body_id(name: str) -> int:
            return int(mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name))

        self._torso = body_id(desc.torso_body)
        self._feet = (body_id(desc.left_foot_body), body_id(desc.right_foot_body))
        self._sole_sites: tuple[int, int] = tuple(  # type: ignore[assignment]
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
        self._geom_side = [int(self._body_side[b]) for b in m.geom_bodyid]
        self._geom_robot = [bool(self._robot_body[b]) for b in m.geom_bodyid]
        self._ctrl_lo = m.actuator_ctrlrange[:, 0].copy()
        self._ctrl_hi = m.actuator_ctrlrange[:, 1].copy()
        self._gear = m.actuator_gear[:, 0].copy()
        self._ctrl_shape = (int(m.nu),)  # shape of a motor command vector

    def _init_state(self, log_every: int | None) -> None:
        """Pushes, log, caches and the views of MjData's arrays."""
        m, d = self._model, self._data
        self._pushes: list[tuple[Push, int, np.ndarray]] = []
        self._pushed_bodies: set[int] = set()
        self._stale = True
        # mj_step splits into mj_step1 (position and velocity stages) + mj_step2 (the rest and the
        # integration) for every integrator but RK4. The accessors compute a state's derived fields as
        # mj_step1 + the acceleration stages (= mj_forward); the next step() then runs only mj_step2 for
        # its first substep, on the same state (bit-identical to mj_step, one position stage less).
        self._split = int(m.opt.integrator) != int(mujoco.mjtIntegrator.mjINT_RK4)
        self._primed = False  # data's position/velocity stages match the state saved below
        self._primed_state = (b"", b"", b"")  # qpos, qvel, act as bytes (cheap to compare)
        self._log_every = log_every
        self.log: SimLog | None = _SimLog(every=log_every) if log_every else None
        self._steps = 0
        self._cforce = np.zeros(6)
        self._version = 0  # bumped whenever the state changes; keys the contact cache
        self._contact_version = -1
        self._contact_cache: tuple[np.ndarray, np.ndarray, bool] = (np.zeros(3), np.zeros(3), False)
        # the largest vertical force on each foot [N] over the substep states since the last measure(),
        # and whether the current state's contacts are in a measurement (Tick::step does the same)
        self._peak = [-math.inf, -math.inf]
        self._measured = False
        # views of MjData's fixed-size arrays (their buffers live as long as the MjData)
        self._qpos, self._qvel, self._ctrl = d.qpos, d.qvel, d.ctrl
        self._xpos, self._xmat = d.xpos, d.xmat
        self._site_xpos, self._site_xmat = d.site_xpos, d.site_xmat
        self._subtree_com, self._subtree_linvel = d.subtree_com, d.subtree_linvel
        self._warning_number = d.warning.number  # a live view of MuJoCo's warning counters

    def _make_tick(self) -> "_mjtick.Tick | None":
        """The compiled control tick (``lipmpcc._mjtick.Tick``) on this model and data, or None.

        None when the module is missing or unusable (see :func:`lipmpcc.sim._tick.check_tick_module`),
        or when the robot has no sole sites. It writes its measurements into ``self._tick_buf``, read
        through the views ``self._tick_views``; the Python path gives identical results.
        """
        if _tick.TICK is None or min(self._sole_sites) < 0:
            return None
        tick, self._tick_buf, self._tick_other, views = _tick.build_tick(
            _tick.TICK, self._model, self._data, self.state_map, self._torso, self._sole_sites,
            self._geom_side, self._geom_robot, self._split,
        )
        self._tick_views = tuple(views)  # a plain tuple: the per-tick indexing and unpacking stay on the fast path
        self._tick_time = int(_tick.TICK[0].layout(self.state_map.nq, self.state_map.nv)["time"])  # buffer index
        return tick

    @property
    def compiled_tick(self) -> bool:
        """True when :meth:`step` and :meth:`measure` run in the compiled module ``lipmpcc._mjtick``
        (identical results; the Python path otherwise)."""
        return self._tick is not None

    # ---- basic properties -----------------------------------------------------------------
    @property
    def model(self) -> mujoco.MjModel:
        """The ``mujoco.MjModel``."""
        return self._model

    @property
    def data(self) -> mujoco.MjData:
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
    @exclusive("simulator")
    def reset(self, keyframe: str | None = "stand") -> None:
        """Reset the state, time, pushes and log.

        Args:
            keyframe: a keyframe name; ``"stand"`` also selects the description's standing
                configuration when the model has no such keyframe; None: the model's qpos0.
        """
        m, d = self._model, self._data
        desc = self.description
        reset_data(m, d, keyframe, desc.standing_keyframe, desc.standing_qpos)
        self._pushes.clear()
        if self._tick is not None:
            self._tick.clear_pushes()
        self._forget_contacts()
        self._clear_push_forces()
        self._steps = 0
        if self._log_every:
            self.log = _SimLog(every=self._log_every)
        mujoco.mj_forward(m, d)
        self._stale = False
        self._version += 1

    @exclusive("simulator")
    def set_state(self, qpos: np.ndarray, qvel: np.ndarray | None = None) -> None:
        """Set the MuJoCo state (validated; velocity zero when omitted)."""
        qpos = self.state_map.check(qpos, self._model.nq, "qpos")
        qvel = np.zeros(self._model.nv) if qvel is None else self.state_map.check(qvel, self._model.nv, "qvel")
        self._data.qpos[:] = qpos
        self._data.qvel[:] = qvel
        mujoco.mj_forward(self._model, self._data)
        self._forget_contacts()
        self._stale = False
        self._version += 1

    def _forget_contacts(self) -> None:
        """Forget the contact peaks (a reset or a new state): the next measurement starts them afresh."""
        self._peak = [-math.inf, -math.inf]
        self._measured = False
        if self._tick is not None:
            self._tick.forget_contacts()

    @exclusive("simulator")
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
        return self.state_map.pinocchio_copy(qpos, qvel)

    @exclusive("simulator")
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
    @exclusive("simulator")
    def step(self, ctrl: np.ndarray, n: int = 1) -> None:
        """Hold motor commands ``ctrl`` (nu,) for ``n`` simulation steps.

        Commands outside ``ctrl_range`` are clamped by MuJoCo. Active pushes are applied at each step.

        Raises:
            InvalidInputError: ``ctrl`` of the wrong shape or not finite, ``n`` not a positive integer.
        """
        tick = self._tick
        if (tick is not None and type(ctrl) is np.ndarray and ctrl.dtype is _F64 and type(n) is int and n >= 1
                and ctrl.shape == self._ctrl_shape and self.log is None):  # the loop's tick: the checks below, passed
            if not tick.step(ctrl, n):  # nothing done: ctrl not finite
                self._check_ctrl_finite(ctrl)
            self._steps += n
            self._version += 1
            self._stale = True
            return
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
        # After each substep, data's contacts are those of the state it started from: the first one's
        # are in the last measurement unless a step came since; the others are latched into the peaks.
        seen = self._measured
        pushes = bool(self._pushes)
        for i in range(n):
            if pushes:
                self._apply_pushes()
            if i == 0 and step2:  # its position/velocity stages are done (see _ensure_forward)
                mujoco.mj_step2(m, d)
            else:
                mujoco.mj_step(m, d)
            if not seen:
                self._latch_contacts()
            seen = False
            if log is not None:
                self._steps += 1
                self._version += 1
                if self._steps % log.every == 0:
                    self._stale = True
                    self._record()
        if log is None:
            self._steps += n
            self._version += 1
        self._measured = False
        self._stale = True

    def _latch_contacts(self) -> None:
        """Raise the contact peaks to the feet's vertical forces of data's contacts (after a substep)."""
        fl, fr, _ = self._contact_sums()
        self._peak[0] = max(self._peak[0], fl[2])
        self._peak[1] = max(self._peak[1], fr[2])

    @staticmethod
    def _check_ctrl_finite(c: np.ndarray) -> None:
        if not _all_finite(c):
            bad = np.flatnonzero(~np.isfinite(c))
            raise InvalidInputError("ctrl", c, "finite motor commands", f"non-finite entries at {bad.tolist()}")

    @exclusive("simulator")
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
            True when the run ended without a fall; False also when the simulation diverged (it stops
            in the control period where MuJoCo reset itself; :meth:`divergence` tells how).
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
                t_before = self._data.time
                self.step(ctrl, k)
                if self._data.time <= t_before and self.divergence():  # MuJoCo reset itself: stop there
                    ok = False
                    break
                done += k
                bar.update(k)
                if stop_on_fall and self.fallen():
                    ok = False
                    break
        return ok

    # ---- pushes ----------------------------------------------------------------------------
    @exclusive("simulator")
    def add_push(self, force_xyz: np.ndarray, t_start: float, duration: float, body: str | None = None) -> Push:
        """Push ``body`` (default: the torso) with a world-frame force [N] for ``t_start <= t < t_start + duration``.

        Applied through ``xfrc_applied`` at the body's centre of mass; several pushes add up. Cleared
        by :meth:`reset`.

        Returns:
            The registered :class:`~lipmpcc.push.Push` (absolute times, ``body`` set).
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
        push = _Push(
            force=(float(f[0]), float(f[1]), float(f[2])), t_start=float(t_start), duration=float(duration), body=name
        )
        self._pushes.append((push, int(b), f.copy()))
        if self._tick is not None:
            self._tick.add_push(int(b), push.force[0], push.force[1], push.force[2], push.t_start, push.t_end)
        self._pushed_bodies.add(int(b))
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
        return _FramePose(self._xpos[b].copy(), self._xmat[b].reshape(3, 3).copy())

    def foot_poses(self) -> tuple[FramePose, FramePose]:
        """(left, right) sole frames: centre of the sole on the contact surface; x forward, z up when flat."""
        self._ensure_forward()
        return self._foot_pose(0), self._foot_pose(1)

    def _foot_pose(self, side: int) -> FramePose:
        s = self._sole_sites[side]
        if s >= 0:
            return _FramePose(self._site_xpos[s].copy(), self._site_xmat[s].reshape(3, 3).copy())
        b = self._feet[side]
        R = self._xmat[b].reshape(3, 3).copy()
        return _FramePose(self._xpos[b] + R @ self._sole_offset, R)

    @exclusive("simulator")
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
            return self._measure_compiled(tick, on_state)
        q, v = self.pinocchio_state()
        if on_state is not None:
            on_state(q, v)
        self._ensure_forward()
        mujoco.mj_subtreeVel(self._model, self._data)
        t = self._torso
        fl, fr, _ = self._foot_contacts()
        peak = (max(self._peak[0], float(fl[2])), max(self._peak[1], float(fr[2])))
        self._peak = [-math.inf, -math.inf]
        self._measured = True
        return self._measurement(
            q, v, self._subtree_com[t].copy(), self._subtree_linvel[t].copy(),
            _FramePose(self._xpos[t].copy(), self._xmat[t].reshape(3, 3).copy()),
            (self._foot_pose(0), self._foot_pose(1)), fl, fr, peak,
        )

    def _measure_compiled(self, tick: "_mjtick.Tick", on_state: Callable[[np.ndarray, np.ndarray], object] | None
                          ) -> Measurement:
        """:meth:`measure` by the compiled tick: its buffer read once, the tuples built directly (the
        per-tick path of the full-body loop; the same values as the Python path, to the bit)."""
        views = self._tick_views
        mapped = False
        if on_state is not None and tick.state() == 0:
            q, v = views[0].copy(), views[1].copy()
            on_state(q, v)
            mapped = True
        if tick.measure(self._stale, mapped):  # nothing done: raise the Python path's error
            self.pinocchio_state()
            raise StateError("simulation state", "a state the compiled tick rejects", "a finite state")
        self._stale = False
        q0, v0, com, com_vel, tp, tR, lp, lR, rp, rR, fl, fr, peak = views
        if not mapped:
            q, v = q0.copy(), v0.copy()
        fl, fr = fl.copy(), fr.copy()
        buf = self._tick_buf
        self._contact_cache = (fl, fr, buf.item(self._tick_other) != 0.0)
        self._contact_version = self._version
        # with a log the steps run in Python: their peaks are Python's (max(a, b): b only when b > a)
        a0, a1 = self._peak
        b0, b1 = peak.tolist()
        pk = (b0 if b0 > a0 else a0, b1 if b1 > a1 else a1)
        self._peak = [-math.inf, -math.inf]
        self._measured = True
        nl, nr = fl.item(2), fr.item(2)
        thr = self.contact_threshold
        new = tuple.__new__  # the NamedTuples without their keyword-processing __new__
        return new(_Measurement, (
            buf.item(self._tick_time), q, v, com.copy(), com_vel.copy(), new(_FramePose, (tp.copy(), tR.copy())),
            (new(_FramePose, (lp.copy(), lR.copy())), new(_FramePose, (rp.copy(), rR.copy()))),
            (nl > thr, nr > thr), (nl, nr), (pk[0] > thr, pk[1] > thr), pk,
        ))

    def _measurement(self, q: np.ndarray, v: np.ndarray, com: np.ndarray, com_vel: np.ndarray, torso: FramePose,
                     feet: tuple[FramePose, FramePose], fl: np.ndarray, fr: np.ndarray,
                     peak: tuple[float, float]) -> Measurement:
        """:meth:`measure`'s result from its parts (``fl``, ``fr``: world-frame foot forces [N]; ``peak``: the
        largest vertical force on each foot [N] since the previous measurement, this state included)."""
        nl, nr = float(fl[2]), float(fr[2])
        thr = self.contact_threshold
        return _Measurement(
            time=float(self._data.time), q=q, v=v, com=com, com_vel=com_vel, torso=torso, feet=feet,
            contact=(nl > thr, nr > thr), normal_force=(nl, nr),
            touched=(peak[0] > thr, peak[1] > thr), peak_normal_force=peak,
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
        fl, fr, other = self._contact_sums()
        self._contact_cache = (np.array(fl), np.array(fr), other)
        self._contact_version = self._version
        return self._contact_cache

    def _contact_sums(self) -> tuple[list[float], list[float], bool]:
        """:meth:`_foot_contacts` of data's contacts as they are (no forward pass, no cache)."""
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
        return fl, fr, other

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
        """Why the robot counts as fallen (see :class:`FallCriterion`), or None.

        The reason names the measure and its threshold, or the contact (the robot's body and geom, and
        what it touches)."""
        detail = self.fall_detail()
        return None if detail is None else detail["reason"]

    def fall_detail(self) -> dict[str, str] | None:
        """Why the robot counts as fallen, or None: ``reason`` (one line), ``kind`` (``"height"``,
        ``"tilt"`` or ``"contact"``), ``body`` (the robot body: the torso, or the one that touched)
        and ``contact`` (what it touched; ``""`` for height and tilt)."""
        crit = self.fall_criterion
        pose = self.torso_pose()
        (pl, _), (pr, _) = self.foot_poses()
        height = pose.position[2] - min(pl[2], pr[2])
        torso = self.description.torso_body
        if height < crit.min_height:
            return {"reason": f"torso {height:.3f} m above the lower sole (< {crit.min_height:.3g} m)",
                    "kind": "height", "body": torso, "contact": ""}
        tilt = math.acos(max(-1.0, min(1.0, float(pose.rotation[2, 2]))))
        if tilt > crit.max_tilt:
            return {"reason": f"torso tilted {tilt:.2f} rad (> {crit.max_tilt} rad)", "kind": "tilt", "body": torso,
                    "contact": ""}
        if crit.non_foot_contact and self._foot_contacts()[2]:
            pair = self._fall_contact()
            if pair is not None:
                body, other = pair
                return {"reason": f"the robot's '{body}' touches {other}", "kind": "contact", "body": body,
                        "contact": other}
        return None

    def _geom_label(self, g: int) -> str:
        m = self._model
        b = int(m.geom_bodyid[g])
        gname = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)
        bname = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"body {b}"
        return f"geom '{gname}'" if gname else (f"'{bname}'" if b else "the ground")

    def _fall_contact(self) -> tuple[str, str] | None:
        """(robot body, what it touches) of the first contact that counts as a fall: a robot geom other
        than a foot against a geom that is not the robot's (with ``self_contact``: or against another
        robot geom other than a foot), or None."""
        m, d = self._model, self._data
        gside, grobot = self._geom_side, self._geom_robot
        self_contact = self.fall_criterion.self_contact
        for g1, g2 in d.contact.geom[: int(d.ncon)].tolist():
            if gside[g1] >= 0 or gside[g2] >= 0 or not (grobot[g1] or grobot[g2]):
                continue
            if grobot[g1] and grobot[g2] and not self_contact:
                continue
            mine, other = (g1, g2) if grobot[g1] else (g2, g1)
            body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[mine])) or f"body {mine}"
            return body, self._geom_label(other)
        return None

    def fallen(self) -> bool:
        """True when the robot has fallen (:meth:`fall_reason` is not None)."""
        return self.fall_reason() is not None

    # ---- MuJoCo's warnings -------------------------------------------------------------------
    def divergence(self) -> str | None:
        """How the simulation diverged since the last :meth:`reset` (``"bad acceleration"``,
        ``"bad velocity"`` or ``"bad position"``: MuJoCo's warning, after which it reset the state and
        the time), ``"non-finite state"`` (with MuJoCo's automatic reset disabled), or None."""
        counts = self._warning_number
        for w, kind in _DIVERGENCE.items():
            if counts[w]:
                return kind
        if not (_all_finite(self._qpos) and _all_finite(self._qvel)):
            return "non-finite state"
        return None

    def warning_messages(self) -> list[str]:
        """One line per kind of MuJoCo warning other than a divergence raised since the last
        :meth:`reset`, with its count (e.g. ``"MuJoCo: the contact buffer was full ... (3 times)"``)."""
        counts = self._warning_number
        return [f"MuJoCo: {text} ({int(counts[w])} time{'s' if counts[w] > 1 else ''})"
                for w, text in _WARNING_TEXT.items() if counts[w]]

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
    def view(self) -> "mujoco.viewer.Handle":
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

    def recorder(self, settings: VideoSettings | None = None) -> VideoRecorder:
        """A :class:`~lipmpcc.sim.render.VideoRecorder` for this model, tracking the torso by default."""
        if settings is None:
            settings = VideoSettings(track_body=self.description.torso_body)
        return VideoRecorder(self._model, settings)
