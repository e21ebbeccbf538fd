"""The robot description: which MJCF to load, what the stack needs to know about it, resolved once.

A :class:`RobotDescription` names the parts of a MuJoCo model that the simulator, the whole-body
controller and the planners use (the foot bodies and their sole frames, the torso, the leg and arm
joints, the motors and their torque limits, a standing configuration) and the per-robot settings of
the controllers. It is built by :func:`lipmpcc.robots.load_robot`.

It also carries what every layer would otherwise compute again, each computed once per description
on first use and then shared:

- :attr:`RobotDescription.model`: the compiled robot MJCF (the whole-body controller reads it);
- :attr:`RobotDescription.scene_model`: the compiled scene (robot + floor; the simulator starts
  from a copy of it);
- :attr:`RobotDescription.standing`: the :class:`StandingPose` (sole positions, COM, heading) of
  the robot in its standing configuration, as a simulator reset to it measures them.

The compiled models are shared: do not modify them (copy one with ``copy.copy`` first).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..conventions import Side, parse_side
from ..exceptions import InvalidInputError
from .mjcf import compile_mjcf, compile_scene, torque_drive

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

__all__ = ["RobotDescription", "StandingPose", "DIGIT_PUBLISHED_MASS", "reset_data"]

#: Published total mass of Agility Robotics' Digit [kg] (also the body-mass sum of the reference
#: Digit v3 MJCF). Paper A's figures use 48 kg (:data:`lipmpcc.loops.lip.DIGIT_MASS`).
DIGIT_PUBLISHED_MASS = 47.9


def _read_only(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.flags.writeable = False
    return a


@dataclass(frozen=True)
class StandingPose:
    """The robot in its standing configuration on flat ground (world frame), measured once.

    The values a :class:`~lipmpcc.sim.robot_sim.RobotSim` reset to
    :attr:`RobotDescription.standing_reset` measures (after MuJoCo's forward pass), to the bit.

    Attributes:
        qpos: the standing configuration, MuJoCo's order (nq,) (read-only).
        left_sole, right_sole: sole centre positions (3,) [m] (read-only).
        com: centre of mass (3,) [m] (read-only).
        com_height: ``com[2]`` [m].
        torso_yaw: heading of the torso's x axis [rad].
    """

    qpos: np.ndarray
    left_sole: np.ndarray
    right_sole: np.ndarray
    com: np.ndarray
    com_height: float
    torso_yaw: float

    @property
    def feet_xy(self) -> np.ndarray:
        """(2, 2) horizontal sole positions [m], left row first (a new array)."""
        return np.array([self.left_sole[:2], self.right_sole[:2]], dtype=float)

    def sole(self, side: Side | str) -> np.ndarray:
        """The sole position (3,) [m] of ``side``."""
        return self.left_sole if parse_side(side) is Side.LEFT else self.right_sole


def reset_data(
    model: "mujoco.MjModel",
    data: "mujoco.MjData",
    keyframe: str | None,
    standing_keyframe: str | None = None,
    standing_qpos: tuple[float, ...] | None = None,
) -> None:
    """``mj_resetData``, then the configuration named ``keyframe`` (no forward pass).

    ``keyframe``: a keyframe of the model; ``"stand"`` selects ``standing_qpos`` when there is no
    ``standing_keyframe`` (even if the model has a keyframe named "stand"), and ``standing_keyframe``
    selects it when the model has no such keyframe; None: the model's qpos0.

    Raises:
        InvalidInputError: an unknown keyframe.
    """
    import mujoco

    mujoco.mj_resetData(model, data)
    if keyframe is None:
        return
    if keyframe == "stand" and standing_keyframe is None and standing_qpos:
        data.qpos[:] = standing_qpos  # the layout's pose, before a model keyframe that is also named "stand"
        return
    k = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_KEY, keyframe)
    if k >= 0:
        mujoco.mj_resetDataKeyframe(model, data, k)
    elif keyframe in ("stand", standing_keyframe) and standing_qpos:
        data.qpos[:] = standing_qpos
    else:
        keys = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_KEY, i) for i in range(model.nkey)]
        raise InvalidInputError("keyframe", keyframe, f"one of {keys} or None")


@dataclass(frozen=True)
class RobotDescription:
    """What the stack needs to know about a robot model (immutable).

    Attributes:
        name: short name (``"digit_like"``, ``"digit_v3"``, or the file stem).
        mjcf_path: the robot MJCF, loadable by MuJoCo and by ``pinocchio.buildModelFromMJCF``.
        scene_path: the file the simulator loads (robot + floor); may equal ``mjcf_path``.
        left_foot_body, right_foot_body: bodies whose geoms touch the ground.
        left_sole_site, right_sole_site: sites at the sole centres, on the contact surface, x forward
            and z up when the foot is flat; None to use ``sole_offset`` in the foot body frame.
        sole_offset: sole centre in the foot body frame [m] (used when there is no sole site; the
            sole frame then has the foot body's orientation).
        foot_length, foot_width: support rectangle of one foot [m].
        torso_body: the floating-base body (root of the robot's tree).
        base_joint: the free joint of the floating base (None: a slide+ball or other base).
        leg_joints: actuated leg joints, left leg then right leg.
        arm_joints: actuated arm joints, left arm then right arm.
        motor_names: actuators in MuJoCo order (the order of a control vector).
        motor_joints: the joint each actuator drives, in the same order.
        torque_limits: joint-side torque limit of each actuator [N m] (|gear| x ctrlrange bound).
        motor_gears: actuator gear (ctrl = torque / gear).
        standing_keyframe: name of a keyframe in which the robot stands on flat ground, or None.
        standing_qpos: MuJoCo qpos of a standing configuration when the model has no such keyframe.
        total_mass: sum of body masses [kg].
        closed_loops: True when the model has equality constraints (rods) a tree model cannot express.
        wbc_overrides: whole-body controller parameters for this robot, as (field, value) pairs of
            :class:`~lipmpcc.control.wbc_types.WbcParams` (used when no parameters are given).
        min_lateral_step: smallest lateral offset of a new foothold from the COM at the support
            exchange that a footstep planner may command [m] (the lower bound of the MPCC's lateral
            reachability; below it the legs touch). The full-body Cartesian MPC steps about it through its
            cost when it is above the reachability's own 0.10 m, which stays its bound
            (:func:`~lipmpcc.studies.path_params.fullbody_params`, ``lateral_nominal``).
        step_duration: the footstep planner's step duration T on this robot [s] (paper A's MPCC on
            the full body; paper A leaves it open, Digit walks 0.35–0.45 s per step).
        alip_com_gains: (k_p [1/s²], k_d [1/s]) of the whole-body QP's horizontal COM task in paper B's
            (ALIP) runs, or None for the controller's own.
        alip_cop_range: half-extents (x, y) [m] of the box about the stance sole centre in which paper
            B's ALIP-MPC may place the centre of pressure for the rest of a step (its ankle strategy),
            or None for paper B's point foot. It must fit in the sole on a 0.2 × 0.1 m stone with
            room for landing errors.
        alip_dcm_settle_time: how long after a touch-down paper B's footstep source reads the DCM from
            which it learns the touch-down DCM bias [s]
            (:attr:`~lipmpcc.planners.sources.alip.AlipSourceParams.dcm_settle_time`; 0: at the touch-down).
        touchdown_timing: who times the touch-down on this robot when the loop is not told
            (:attr:`~lipmpcc.loops.fullbody.LoopParams.touchdown_timing` ``"auto"``): ``"planner"`` (the swing
            ends at the detected contact; the built-in footstep sources learn the offset), ``"loop"`` (the loop
            keeps the planned time, for every planner) or None (the layout does not say: the loop decides by
            the planner). ``lipmpcc robot init`` writes ``"loop"``.
        landing_depth: how far below the ground the swing foot aims in paper A's full-body MPCC runs (``circle``,
            ``circle-push``, ``overtake``, ``follow-path``: their
            :attr:`~lipmpcc.loops.fullbody.LoopParams.landing_depth`) [m], so that a foot that lags its reference
            is on the ground at the planned touch-down (``touchdown_timing = "loop"`` changes the stance then,
            contact or not); 0 (a layout without it, Digit's, and ``robot init``'s): at the ground. Booster T1
            needs 0.02 m there, while the same makes Unitree G1's circle fall, and T1's capture-point ``walk``
            with it fell at 9.9 s (docs/add_a_robot.md), so ``walk`` and ``stand`` keep 0; paper B's
            stepping-stone runs set their own (0.015 m below the stone top).
        steady_heading: paper A's fixed-T MPCC runs on this robot (``circle``, ``circle-push``, ``overtake``,
            ``follow-path``) hold the planned heading to the path
            (:func:`~lipmpcc.studies.path_params.steady_heading_params`: a heading weight and R_θ ≥ 50), as they
            do on any robot's scene with obstacles; False (Digit's layouts): paper A's near-free heading. On T1
            and G1 paper A's heading flipped by the ±0.3 rad bound from step to step, and with feet landing
            firmly (``landing_depth``) both walked backwards along the circle (docs/add_a_robot.md).
        alip_touchdown_timing: who times the touch-down in paper B's (ALIP) runs
            (:attr:`~lipmpcc.loops.fullbody.LoopParams.touchdown_timing`): ``"planner"`` (the swing ends at the
            detected contact; paper B's source learns the contact phase) or ``"loop"`` (the loop keeps the
            planned time). A layout that states ``touchdown_timing`` but no ``alip_touchdown_timing`` gets its
            ``touchdown_timing`` here (``robot init``'s ``"loop"``); one that states neither, ``"planner"``.
        alip_com_resync: paper B's (ALIP) runs restart the loop's LIP COM reference from the measured COM
            state at every planner update (:attr:`~lipmpcc.loops.fullbody.LoopParams.com_resync_on_plan`), not
            only at each touch-down.
        alip_step_reference, alip_stone_bounds: the ALIP-MPC's ``step_reference`` (``"plan"``: paper B's eq. 9, or
            ``"stones"``) and ``stone_bounds`` (``"relative"``: paper B's, or ``"world"``) in paper B's runs on this
            robot (:class:`~lipmpcc.planners.alip_mpc.AlipMpcParams`).
        alip_max_speed: the ALIP-MPC's fastest nominal walk in paper B's runs [m/s]: a longer desired step gets a
            longer nominal duration (:attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.max_speed`); 0: paper B's
            T_nom for every step.
        alip_cop_safety_factor: the whole-body controller's ``cop_safety_factor`` in paper B's runs (the fraction
            of the sole's half-length and half-width the CoP may use), or None for the controller's own (its
            ``wbc_overrides`` included). Its lateral room beyond ``alip_cop_range`` is what the controller has
            for tracking the COM reference after the planner has spent its ankle (docs/design.md).
        alip_wbc_overrides: whole-body controller parameters for paper B's runs only, (field, value) pairs of
            :class:`~lipmpcc.control.wbc_types.WbcParams` applied over ``wbc_overrides``. ``lipmpcc robot init``
            wrote a free upper body that damps the centroidal angular momentum here in session 40 (docs/design.md,
            "Paper B on smaller humanoids"); since session 41 into ``wbc_overrides``, for every run (T1's circle
            completes with it: docs/add_a_robot.md, Appendix B). The shipped layouts state none.
        layout_file: the layout file the description was read from, or None.
        waist_joints, head_joints: actuated waist and head joints (posture tasks, like the arms).
        fall_height: torso-origin height above the lower sole [m] below which the robot has fallen,
            or None for :data:`~lipmpcc.sim.types.FALL_HEIGHT_FRACTION` of its standing height.
        step_width, max_step_length: the robot's nominal lateral distance between the feet and its
            forward reach per step [m] (the footstep planners' reach rectangles scale with them), or
            None for Digit's (0.26 m and 0.55 m).
        lip_height: the LIP's COM height [m] (the standing COM height above the soles), or None for
            the standing pose's as measured at the start of a run.
        actuator_notes: what was changed in the model's actuators at load (servos driven as torque
            sources, :func:`~lipmpcc.robots.mjcf.torque_drive`); empty for a model of motors.
    """

    name: str
    mjcf_path: Path
    scene_path: Path
    left_foot_body: str
    right_foot_body: str
    left_sole_site: str | None
    right_sole_site: str | None
    sole_offset: tuple[float, float, float]
    foot_length: float
    foot_width: float
    torso_body: str
    base_joint: str | None
    leg_joints: tuple[str, ...]
    arm_joints: tuple[str, ...]
    motor_names: tuple[str, ...] = ()
    motor_joints: tuple[str, ...] = ()
    torque_limits: tuple[float, ...] = ()
    motor_gears: tuple[float, ...] = ()
    standing_keyframe: str | None = None
    standing_qpos: tuple[float, ...] | None = None
    total_mass: float = float("nan")
    closed_loops: bool = False
    wbc_overrides: tuple[tuple[str, object], ...] = ()
    min_lateral_step: float = 0.10
    step_duration: float = 0.4
    alip_com_gains: tuple[float, float] | None = None
    alip_cop_range: tuple[float, float] | None = None
    alip_dcm_settle_time: float = 0.0
    touchdown_timing: str | None = None
    landing_depth: float = 0.0
    steady_heading: bool = False
    alip_touchdown_timing: str = "planner"
    alip_com_resync: bool = False
    alip_step_reference: str = "plan"
    alip_stone_bounds: str = "relative"
    alip_max_speed: float = 0.0
    alip_cop_safety_factor: float | None = None
    alip_wbc_overrides: tuple[tuple[str, object], ...] = ()
    layout_file: Path | None = None
    waist_joints: tuple[str, ...] = ()
    head_joints: tuple[str, ...] = ()
    fall_height: float | None = None
    step_width: float | None = None
    max_step_length: float | None = None
    lip_height: float | None = None
    actuator_notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        # what is computed once per description (compiled models, standing pose); not a field
        object.__setattr__(self, "_cache", {})

    def __getstate__(self) -> dict[str, object]:
        return {k: v for k, v in self.__dict__.items() if k != "_cache"}

    def __setstate__(self, state: dict[str, object]) -> None:
        self.__dict__.update(state)
        object.__setattr__(self, "_cache", {})

    # ---- parts ---------------------------------------------------------------------------
    def foot_body(self, side: Side | str) -> str:
        """Foot body of ``side`` (:class:`~lipmpcc.conventions.Side`, ``"left"`` or ``"right"``)."""
        return self.left_foot_body if parse_side(side) is Side.LEFT else self.right_foot_body

    def sole_site(self, side: Side | str) -> str | None:
        """Sole site of ``side``, or None."""
        return self.left_sole_site if parse_side(side) is Side.LEFT else self.right_sole_site

    @property
    def posture_joints(self) -> tuple[str, ...]:
        """The actuated joints the whole-body controller holds at their standing angle (posture tasks):
        the arm, waist and head joints, then every other actuated joint that is not a leg joint (a
        joint the layout leaves out is held), each once, in that order."""
        named = list(dict.fromkeys(self.arm_joints + self.waist_joints + self.head_joints))
        legs = set(self.leg_joints)
        rest = [j for j in self.motor_joints if j not in legs and j not in named]
        return tuple(named + list(dict.fromkeys(rest)))

    @property
    def push_scale(self) -> float:
        """Factor of the studies' pushes [N] on this robot: 1 for a Digit-sized robot (total mass within
        20 % of :data:`DIGIT_PUBLISHED_MASS`: the papers' pushes stay in newtons), else the mass ratio."""
        ratio = float(self.total_mass) / DIGIT_PUBLISHED_MASS
        return 1.0 if not math.isfinite(ratio) or abs(ratio - 1.0) <= 0.2 else ratio

    @property
    def nu(self) -> int:
        """Number of actuators."""
        return len(self.motor_names)

    @property
    def standing_reset(self) -> str | None:
        """The argument of ``RobotSim.reset`` that puts the robot in its standing configuration:
        the standing keyframe, else ``"stand"`` (the ``standing_qpos``), else None (qpos0)."""
        if self.standing_keyframe:
            return self.standing_keyframe
        return "stand" if self.standing_qpos is not None else None

    # ---- resolved once ---------------------------------------------------------------------
    @property
    def model(self) -> "mujoco.MjModel":
        """The compiled robot MJCF (``mjcf_path``), compiled on first use, its servos driven as torque
        sources (:func:`~lipmpcc.robots.mjcf.torque_drive`); shared: do not modify.

        Raises:
            ModelFileError: MuJoCo cannot load the file.
        """
        cache: dict[str, object] = self._cache  # type: ignore[attr-defined]
        if "model" not in cache:
            model = compile_mjcf(Path(self.mjcf_path))
            torque_drive(model)
            cache["model"] = model
        return cache["model"]  # type: ignore[return-value]

    def unlimited_motors(self) -> tuple[str, ...]:
        """The motors whose effort MuJoCo does not bound: no control range (``ctrllimited`` false;
        ``ctrlrange="0 0"`` means none) and no force range. MuJoCo applies whatever is commanded."""
        m = self.model
        return tuple(self.motor_names[a] for a in range(int(m.nu))
                     if not m.actuator_ctrllimited[a] and not m.actuator_forcelimited[a])

    @property
    def scene_model(self) -> "mujoco.MjModel":
        """The compiled scene (``scene_path``; a floor added when it has none,
        :func:`~lipmpcc.robots.mjcf.compile_scene`), compiled on first use; shared: do not modify.

        Raises:
            ModelFileError: MuJoCo cannot load the file.
        """
        cache: dict[str, object] = self._cache  # type: ignore[attr-defined]
        if "scene_model" not in cache:
            cache["scene_model"] = compile_scene(Path(self.scene_path))
        return cache["scene_model"]  # type: ignore[return-value]

    @property
    def standing(self) -> StandingPose:
        """The :class:`StandingPose` (computed on first use from :attr:`scene_model`)."""
        cache: dict[str, object] = self._cache  # type: ignore[attr-defined]
        if "standing" not in cache:
            cache["standing"] = self._measure_standing()
        return cache["standing"]  # type: ignore[return-value]

    def _attach(self, model: "mujoco.MjModel | None" = None, scene_model: "mujoco.MjModel | None" = None) -> None:
        """Keep models already compiled from ``mjcf_path`` / ``scene_path`` (by :func:`load_robot`)."""
        cache: dict[str, object] = self._cache  # type: ignore[attr-defined]
        if model is not None:
            cache["model"] = model
        if scene_model is not None:
            cache["scene_model"] = scene_model

    def _share_models(self, other: "RobotDescription") -> None:
        """Take ``other``'s compiled models of the same files instead of compiling them again."""
        cache: dict[str, object] = self._cache  # type: ignore[attr-defined]
        theirs: dict[str, object] = other._cache  # type: ignore[attr-defined]
        for key, path, other_path in (("model", self.mjcf_path, other.mjcf_path),
                                      ("scene_model", self.scene_path, other.scene_path)):
            if key in theirs and Path(path) == Path(other_path):
                cache[key] = theirs[key]

    def _measure_standing(self) -> StandingPose:
        """Reset a fresh ``MjData`` of the scene to :attr:`standing_reset`, run ``mj_forward`` and
        read the soles, COM and torso heading as ``RobotSim`` does."""
        import mujoco

        m = self.scene_model
        d = mujoco.MjData(m)
        reset_data(m, d, self.standing_reset, self.standing_keyframe, self.standing_qpos)
        mujoco.mj_forward(m, d)
        torso = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, self.torso_body)
        soles = []
        for body, site in ((self.left_foot_body, self.left_sole_site), (self.right_foot_body, self.right_sole_site)):
            s = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, site) if site else -1
            if s >= 0:
                soles.append(d.site_xpos[s].copy())
            else:
                b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, body)
                R = d.xmat[b].reshape(3, 3).copy()
                soles.append(d.xpos[b] + R @ np.asarray(self.sole_offset, dtype=float))
        com = d.subtree_com[torso].copy()
        R = d.xmat[torso].reshape(3, 3)
        return StandingPose(
            qpos=_read_only(d.qpos), left_sole=_read_only(soles[0]), right_sole=_read_only(soles[1]),
            com=_read_only(com), com_height=float(com[2]), torso_yaw=math.atan2(R[1, 0], R[0, 0]),
        )
