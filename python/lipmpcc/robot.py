"""Robot descriptions: which MJCF to load and what the stack needs to know about it.

A :class:`RobotDescription` names the parts of a MuJoCo model that the simulator, the whole-body
controller and the planners use: the foot bodies and their sole frames, the torso, the leg and arm
joints, the motors and their torque limits, and a standing configuration. :func:`load_robot` builds
one for

- ``"digit_like"``: the project's own Digit-class biped, ``data/models/digit_like/`` (a free-joint
  base, 6 joints per leg, 4 per arm, 20 motors with gear 1 so that a motor command is a joint torque);
- any MJCF path: the layout is recognised from its body names (the digit_like names, or those of the
  Digit v3 model of osudrl/roadrunner: ``left-leg/toe-roll``, ``torso/base``, ...). Keyword overrides
  name the parts of any other model.

The Digit v3 layout has a slide+ball base, closed-loop rods and passive springs. Its description is
given here (names, foot size, standing configuration) for the reference tests and for later use; the
whole-body controller of this release handles free-joint, open-chain models only.

Errors: a missing or unparsable file raises :class:`~lipmpcc.exceptions.ModelFileError` (with
MuJoCo's reason on one line); a model that lacks a named part raises
:class:`~lipmpcc.exceptions.RobotDescriptionError` listing every missing part.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .exceptions import InvalidInputError, ModelFileError, RobotDescriptionError
from .resources import data_path

LEFT = "left"
RIGHT = "right"

#: Published total mass of Agility Robotics' Digit [kg] (also the reference MJCF's body mass sum).
DIGIT_MASS = 47.9


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

    def foot_body(self, side: str) -> str:
        """Foot body of ``side`` (``"left"`` or ``"right"``)."""
        return self.left_foot_body if _side(side) == LEFT else self.right_foot_body

    def sole_site(self, side: str) -> str | None:
        """Sole site of ``side``, or None."""
        return self.left_sole_site if _side(side) == LEFT else self.right_sole_site

    @property
    def nu(self) -> int:
        """Number of actuators."""
        return len(self.motor_names)


def _side(side: str) -> str:
    if side not in (LEFT, RIGHT):
        raise InvalidInputError("side", side, "'left' or 'right'")
    return side


# ------------------------------------------------------------------------------------------------
# Layouts: names of the parts, per model family
# ------------------------------------------------------------------------------------------------
def _digit_like_layout() -> dict[str, Any]:
    legs = ("hip_roll", "hip_yaw", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")
    arms = ("shoulder_roll", "shoulder_pitch", "shoulder_yaw", "elbow")
    return dict(
        left_foot_body="left_foot",
        right_foot_body="right_foot",
        left_sole_site="left_sole",
        right_sole_site="right_sole",
        sole_offset=(-0.0018525, 0.0, -0.062067),
        foot_length=0.235,
        foot_width=0.08,
        torso_body="torso",
        base_joint="base",
        leg_joints=tuple(f"{s}_{j}" for s in (LEFT, RIGHT) for j in legs),
        arm_joints=tuple(f"{s}_{j}" for s in (LEFT, RIGHT) for j in arms),
        standing_keyframe="stand",
        standing_qpos=None,
    )


#: Standing configuration of the roadrunner Digit v3 model (61 qpos: slide x, y, z, ball quaternion
#: w x y z, then the joints in tree order). Source: osudrl/roadrunner, sim/digit_sim/mj_digitsim.py,
#: ``MjDigitSim.reset_qpos`` (MIT). Its closed loops close to 1e-5 m in digit-v3.xml, and its feet
#: rest on the floor (lowest foot-box corner 0.4 mm above it).
DIGIT_V3_STANDING_QPOS: tuple[float, ...] = (
    0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0,
    3.33020155e-01, -2.66178730e-02, 1.92369587e-01,
    9.93409734e-01, -1.04126145e-03, 1.82534311e-03, 1.14597921e-01,
    2.28971047e-01, 1.48527831e-03, -2.31455693e-01, 4.55857916e-04,
    -1.29734322e-02,
    9.89327705e-01, 1.45524756e-01, 1.73630859e-03, 7.08678995e-03,
    -2.03852305e-02,
    9.88035432e-01, 1.53876629e-01, 6.59769560e-05, 1.03905844e-02,
    -3.52778547e-03, -5.54992074e-02,
    -1.05542715e-01, 8.94852532e-01, -8.63756398e-03, 4.4780280e-02,
    -3.33020070e-01, 2.66195360e-02, -1.92382190e-01,
    9.93409659e-01, 1.04481446e-03, 1.82489637e-03, -1.14598546e-01,
    -2.28971188e-01, -1.48636971e-03, 2.31454977e-01, -4.53425792e-04,
    1.41299940e-02,
    9.89323654e-01, -1.45521550e-01, 1.80177609e-03, -7.67726135e-03,
    1.93767895e-02,
    9.88041418e-01, -1.53872399e-01, 1.26073837e-05, -9.87117790e-03,
    2.36874210e-03, 5.55559678e-02,
    1.05444698e-01, -8.94890429e-01, 8.85979401e-03, -4.4723293e-02,
)


def _digit_v3_layout() -> dict[str, Any]:
    legs = ("hip-roll", "hip-yaw", "hip-pitch", "knee", "toe-a", "toe-b")
    arms = ("shoulder-roll", "shoulder-pitch", "shoulder-yaw", "elbow")
    return dict(
        left_foot_body="left-leg/toe-roll",
        right_foot_body="right-leg/toe-roll",
        # roadrunner's foot sites: flat-foot frame (x forward, z up), 1.5 cm ahead of the foot-box
        # centre and 4.6 mm below its bottom face.
        left_sole_site="left-foot-mid",
        right_sole_site="right-foot-mid",
        sole_offset=(0.0, 0.0, 0.0),
        foot_length=0.235,  # the foot collision box: 2 x 0.1175 m
        foot_width=0.08,  # 2 x 0.04 m
        torso_body="torso/base",
        base_joint=None,
        leg_joints=tuple(f"{s}-leg/{j}" for s in (LEFT, RIGHT) for j in legs),
        arm_joints=tuple(f"{s}-arm/{j}" for s in (LEFT, RIGHT) for j in arms),
        standing_keyframe=None,
        standing_qpos=DIGIT_V3_STANDING_QPOS,
    )


_LAYOUTS = {"digit_like": _digit_like_layout, "digit_v3": _digit_v3_layout}


# ------------------------------------------------------------------------------------------------
# Loading
# ------------------------------------------------------------------------------------------------
def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def compile_mjcf(path: Path) -> Any:
    """``mujoco.MjModel`` of ``path``; :class:`ModelFileError` when missing or unparsable."""
    import mujoco

    path = Path(path)
    if not path.is_file():
        raise ModelFileError(str(path), "file not found" if not path.exists() else "not a regular file")
    try:
        return mujoco.MjModel.from_xml_path(str(path))
    except (ValueError, RuntimeError) as err:  # MuJoCo raises ValueError with the XML/compile reason
        raise ModelFileError(str(path), f"MuJoCo cannot load it: {_one_line(err)}") from None


def _names(model: Any, objtype: Any, n: int) -> list[str]:
    import mujoco

    return [mujoco.mj_id2name(model, objtype, i) or "" for i in range(n)]


def _detect_layout(body_names: set[str]) -> str | None:
    for key, layout in _LAYOUTS.items():
        lay = layout()
        if lay["left_foot_body"] in body_names and lay["torso_body"] in body_names:
            return key
    return None


def describe_model(
    model: Any, mjcf_path: Path, scene_path: Path | None = None, name: str | None = None, **overrides: Any
) -> RobotDescription:
    """A :class:`RobotDescription` of a compiled ``mujoco.MjModel``.

    The layout (part names) is recognised from the body names; ``overrides`` set or replace any
    field. Every named part is checked against the model.

    Raises:
        RobotDescriptionError: a named body, site, joint or keyframe is missing (a model whose layout
            is not recognised is checked against the digit_like names).
        InvalidInputError: an override that is not a layout field.
    """
    import mujoco

    bodies = set(_names(model, mujoco.mjtObj.mjOBJ_BODY, model.nbody))
    sites = set(_names(model, mujoco.mjtObj.mjOBJ_SITE, model.nsite))
    joints = _names(model, mujoco.mjtObj.mjOBJ_JOINT, model.njnt)
    keys = set(_names(model, mujoco.mjtObj.mjOBJ_KEY, model.nkey))
    fields = set(_digit_like_layout()) | {"name"}  # the fields not computed from the model
    unknown = sorted(set(overrides) - fields)
    if unknown:
        raise InvalidInputError("overrides", unknown, f"some of {', '.join(sorted(fields))}")
    name = overrides.pop("name", None) or name

    key = _detect_layout(bodies)
    # an unrecognised model is checked against the digit_like names (plus overrides), so that the
    # error lists exactly the parts to add or to name
    layout: dict[str, Any] = _LAYOUTS[key or "digit_like"]()
    layout.update(overrides)

    problems: list[str] = []
    for f in ("left_foot_body", "right_foot_body", "torso_body"):
        if layout[f] not in bodies:
            problems.append(f"body '{layout[f]}' ({f})")
    for f in ("left_sole_site", "right_sole_site"):
        if layout[f] is not None and layout[f] not in sites:
            problems.append(f"site '{layout[f]}' ({f})")
    for j in tuple(layout["leg_joints"]) + tuple(layout["arm_joints"]):
        if j not in joints:
            problems.append(f"joint '{j}'")
    if layout["base_joint"] is not None:
        if layout["base_joint"] not in joints:
            problems.append(f"joint '{layout['base_joint']}' (base_joint)")
        elif model.jnt_type[joints.index(layout["base_joint"])] != mujoco.mjtJoint.mjJNT_FREE:
            problems.append(f"a free joint named '{layout['base_joint']}' (base_joint)")
    if layout["standing_keyframe"] is not None and layout["standing_keyframe"] not in keys:
        problems.append(f"keyframe '{layout['standing_keyframe']}' (standing_keyframe)")
    if layout["standing_qpos"] is not None and len(layout["standing_qpos"]) != model.nq:
        problems.append(f"a standing_qpos of length nq = {model.nq} (got {len(layout['standing_qpos'])})")
    if model.nu == 0:
        problems.append("actuators (the model has none)")
    if problems:
        raise RobotDescriptionError(str(mjcf_path), problems)

    motor_names = tuple(_names(model, mujoco.mjtObj.mjOBJ_ACTUATOR, model.nu))
    motor_joints, limits, gears = [], [], []
    for a in range(model.nu):
        if model.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
            raise RobotDescriptionError(str(mjcf_path), [f"a joint transmission for actuator '{motor_names[a]}'"])
        motor_joints.append(joints[model.actuator_trnid[a, 0]])
        gear = float(model.actuator_gear[a, 0])
        gears.append(gear)
        if model.actuator_ctrllimited[a]:
            bound = float(np.max(np.abs(model.actuator_ctrlrange[a])))
            limits.append(abs(gear) * bound)
        else:
            limits.append(float("inf"))
    return RobotDescription(
        name=name or (key if key else Path(mjcf_path).stem),
        mjcf_path=Path(mjcf_path),
        scene_path=Path(scene_path) if scene_path is not None else Path(mjcf_path),
        left_foot_body=layout["left_foot_body"],
        right_foot_body=layout["right_foot_body"],
        left_sole_site=layout["left_sole_site"],
        right_sole_site=layout["right_sole_site"],
        sole_offset=tuple(float(x) for x in layout["sole_offset"]),  # type: ignore[arg-type]
        foot_length=float(layout["foot_length"]),
        foot_width=float(layout["foot_width"]),
        torso_body=layout["torso_body"],
        base_joint=layout["base_joint"],
        leg_joints=tuple(layout["leg_joints"]),
        arm_joints=tuple(layout["arm_joints"]),
        motor_names=motor_names,
        motor_joints=tuple(motor_joints),
        torque_limits=tuple(limits),
        motor_gears=tuple(gears),
        standing_keyframe=layout["standing_keyframe"],
        standing_qpos=None if layout["standing_qpos"] is None else tuple(float(x) for x in layout["standing_qpos"]),
        total_mass=float(np.sum(model.body_mass)),
        closed_loops=bool(model.neq > 0),
    )


def digit_like_paths() -> tuple[Path, Path]:
    """(robot MJCF, scene MJCF) of the packaged digit_like model."""
    folder = data_path("models", "digit_like")
    return folder / "digit_like.xml", folder / "scene.xml"


def load_robot(robot: str | Path | RobotDescription = "digit_like", **overrides: Any) -> RobotDescription:
    """Describe a robot model.

    Args:
        robot: ``"digit_like"`` (the packaged model), or the path of an MJCF file (a ``str`` that
            ends in ``.xml`` or any ``Path``), or a description (returned as is, with overrides
            applied).
        overrides: layout fields of :class:`RobotDescription` to set (names of parts, foot size,
            standing configuration, ``name``), e.g. ``left_foot_body="l_foot"`` for a model whose
            names are not recognised. Fields computed from the model (motors, limits, mass) cannot
            be overridden.

    Returns:
        The description; the robot file (and the scene file, when different) compile in MuJoCo.

    Raises:
        ModelFileError: the file is missing or MuJoCo cannot load it.
        RobotDescriptionError: the model lacks a part the stack needs (all of them are listed).
        InvalidInputError: ``robot`` is an unknown name.
    """
    if isinstance(robot, RobotDescription):
        return dataclasses.replace(robot, **overrides) if overrides else robot
    if isinstance(robot, str) and robot == "digit_like":
        mjcf, scene = digit_like_paths()
        model = compile_mjcf(mjcf)
        compile_mjcf(scene)
        overrides.setdefault("name", "digit_like")
        return describe_model(model, mjcf, scene, **overrides)
    if isinstance(robot, Path) or (isinstance(robot, str) and robot.lower().endswith(".xml")):
        path = Path(robot).expanduser()
        model = compile_mjcf(path)
        return describe_model(model, path, path, **overrides)
    raise InvalidInputError("robot", robot, "'digit_like' or the path of an MJCF file (.xml)")
