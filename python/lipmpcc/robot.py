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

A *layout* is the small robot description the stack needs beyond the MJCF: the foot bodies and
their sole sites, the foot size, the torso, the leg and arm joints, a standing configuration and,
optionally, whole-body controller parameters for that robot. Two ship here (``digit_like`` and
``digit_v3``); users write their own as a TOML or JSON file with the same keys (see
:func:`read_layout_file`) and pass it as ``load_robot(path, layout="my_robot.toml")``, or put it
next to the model as ``<model>.lipmpcc.toml`` (found automatically, also by the CLI's
``--robot PATH.xml``).

The Digit v3 layout has a slide+ball base, closed-loop rods (knee/tarsus and toes) and passive shin
and heel springs; :class:`~lipmpcc.wbc.WholeBodyController` and the simulator take it as is.

Errors: a missing or unparsable file raises :class:`~lipmpcc.exceptions.ModelFileError` (with
MuJoCo's reason on one line); a model that lacks a named part raises
:class:`~lipmpcc.exceptions.RobotDescriptionError` listing every missing part.
"""

from __future__ import annotations

import dataclasses
import math
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


#: Upper bound [m] (exclusive) of each half-extent of a robot's ``alip_cop_range`` (layout files and
#: ``--cop-range``): the centre-of-pressure box must fit in a sole on a 0.2 × 0.1 m stone.
MAX_ALIP_COP_RANGE = 0.2


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
            :class:`~lipmpcc.wbc.WbcParams` (used when no parameters are given).
        min_lateral_step: smallest lateral offset of a new foothold from the COM at the support
            exchange that a footstep planner may command [m] (the lower bound of the MPCC's lateral
            reachability; below it the legs touch).
        step_duration: the footstep planner's step duration T on this robot [s] (paper A's MPCC on
            the full body; paper A leaves it open, Digit walks 0.35–0.45 s per step).
        alip_com_gains: (k_p [1/s²], k_d [1/s]) of the whole-body QP's horizontal COM task in paper B's
            (ALIP) runs, or None for the controller's own (see
            :func:`lipmpcc.scenarios.fullbody_stepping_stones.stones_wbc_params`).
        alip_cop_range: half-extents (x, y) [m] of the box about the stance sole centre in which paper
            B's ALIP-MPC may place the centre of pressure for the rest of a step (its ankle strategy,
            :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`), or None for paper B's point
            foot. It must fit in the sole on a 0.2 × 0.1 m stone with room for landing errors.
        layout_file: the layout file the description was read from, or None.
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
    wbc_overrides: tuple[tuple[str, Any], ...] = ()
    min_lateral_step: float = 0.10
    step_duration: float = 0.4
    alip_com_gains: tuple[float, float] | None = None
    alip_cop_range: tuple[float, float] | None = None
    layout_file: Path | None = None

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

    @property
    def standing_reset(self) -> str | None:
        """The argument of ``RobotSim.reset`` that puts the robot in its standing configuration:
        the standing keyframe, else ``"stand"`` (the ``standing_qpos``), else None (qpos0)."""
        if self.standing_keyframe:
            return self.standing_keyframe
        return "stand" if self.standing_qpos is not None else None


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
        wbc_overrides=(),
        # with 0.10 m the feet stay >= 0.14 m apart (the hip housings are 0.2 m apart)
        min_lateral_step=0.10,
        step_duration=0.4,
        # paper B's low level leaves the horizontal COM to the ALIP: a soft COM task (critically damped
        # at 4 1/s); with the default 100/20 digit_like falls on L = 0.55 m and Profile III
        alip_com_gains=(16.0, 8.0),
        # the ALIP-MPC's ankle: the CoP within ±6 cm along and ±2.5 cm across the 0.235 × 0.08 m sole
        # (a 0.2 × 0.1 m stone under it, landing errors of ~1 cm); with a point foot digit_like falls
        # after each of paper B's four pushes
        alip_cop_range=(0.06, 0.025),
    )


#: Standing configuration of the Digit v3 model (61 qpos: slide x, y, z, ball quaternion w x y z,
#: then the joints in tree order), derived from osudrl/roadrunner's ``MjDigitSim.reset_qpos``
#: (sim/digit_sim/mj_digitsim.py, MIT): that pose has unloaded springs, the feet 0.4 mm above the
#: floor and the COM 4 cm behind the feet. Here it was settled in MuJoCo 4.0 under the whole-body
#: controller with the COM moved over the centres of the foot boxes (3 s, final speeds < 0.03 rad/s),
#: then its six loops were closed exactly (rods, tarsus, toe motors; 0.15 mm of MuJoCo's soft-constraint
#: stretch removed) and the base set so that the lowest foot-box corner is 0.05 mm into the floor:
#: the springs carry the robot's weight, so that a run starts in equilibrium. The shoulders are rolled
#: 0.25 rad further out than roadrunner's (elbow-to-hip clearance 16 cm instead of 11 cm: a wide side
#: step otherwise brings the hip housing against the elbow).
DIGIT_V3_STANDING_QPOS: tuple[float, ...] = (
    4.548843701e-02, -6.316025957e-05, 1.000544519e+00,
    9.999991286e-01, 3.646964465e-05, 1.319583224e-03, -1.396648659e-05,
    3.326076624e-01, -2.451292795e-02, 2.622509151e-01, 9.921170053e-01, -1.418865033e-03,
    1.962283173e-03, 1.252915958e-01, 2.633390369e-01, -1.357627995e-02, -2.365592163e-01,
    -1.049099981e-02, -9.125305062e-02, 9.801618499e-01, 1.924258171e-01, 8.300103396e-03,
    4.675640367e-02, 6.063542414e-02, 9.789984345e-01, 2.013953087e-01, -5.577358691e-03,
    -3.115907578e-02, 7.913785054e-02, -4.937941468e-02, -3.555053959e-01, 8.947620927e-01,
    -8.693193001e-03, 4.465674856e-02, -3.326715306e-01, 2.328249076e-02, -2.623239716e-01,
    9.921215771e-01, 1.422882750e-03, 1.960866371e-03, -1.252553657e-01, -2.632674378e-01,
    1.357808978e-02, 2.364860614e-01, 1.048973965e-02, 9.130304965e-02, 9.801624957e-01,
    -1.924165108e-01, 8.299839854e-03, -4.678120494e-02, -6.083387273e-02, 9.789972057e-01,
    -2.013850099e-01, -5.588822795e-03, 3.126202368e-02, -7.926377277e-02, 4.913795557e-02,
    3.554172831e-01, -8.947431530e-01, 8.928652327e-03, -4.459649626e-02,
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
        # The sole sites sit 1.5 cm ahead of the foot boxes' centres (the controller centres the CoP
        # rectangle on the boxes); a CoP kept within 60 % of the half-length and width keeps the
        # stance foot flat on its box when turning (at 90 % it rolls onto an edge and slips in yaw).
        wbc_overrides=(("cop_safety_factor", 0.6),),
        # Digit v3's tarsi and toe rods reach inward: a foot landing less than 0.16 m beside the
        # COM brings the swing tarsus against the stance one.
        min_lateral_step=0.16,
        # At 0.4 s per step (0.3 m of progress at most: 0.75 m/s) Digit v3 walks beside the 0.6 m/s
        # obstacle of paper A's overtaking study for 15 s without passing it; at 0.35 s (0.86 m/s)
        # it passes.
        step_duration=0.35,
        # the controller's own 100/20: with 16/8 Digit v3 falls on Profile I (0.4, +0.15) and II
        alip_com_gains=None,
        # the ALIP-MPC's ankle: inside the controller's CoP box (60 % of the sole, above). Measured (seed 0):
        # completes Profile I L = 0.2 and 0.4 with both W, II and III (RMSE 7.8-16 mm); falls on L = 0.55
        # (1.1 m/s), IV and the push test. With the point foot it completed I (0.2, ±0.15), (0.4, +0.15)
        # and II only (12.7-25 mm).
        alip_cop_range=(0.04, 0.015),
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
    model: Any,
    mjcf_path: Path,
    scene_path: Path | None = None,
    name: str | None = None,
    layout: dict[str, Any] | None = None,
    layout_file: Path | None = None,
    **overrides: Any,
) -> RobotDescription:
    """A :class:`RobotDescription` of a compiled ``mujoco.MjModel``.

    The layout (part names) is ``layout`` when given (e.g. read from a layout file), else it is
    recognised from the body names; ``overrides`` set or replace any field. Every named part is
    checked against the model.

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

    key = None
    if layout is None:
        key = _detect_layout(bodies)
        # an unrecognised model is checked against the digit_like names (plus overrides), so that the
        # error lists exactly the parts to add or to name
        layout = _LAYOUTS[key or "digit_like"]()
    else:
        base = _digit_like_layout()
        base.update({"standing_keyframe": None, "wbc_overrides": (), "alip_com_gains": None, "alip_cop_range": None})
        base.update(layout)
        layout = base
        key = layout.pop("name", None)
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
    mls = layout.get("min_lateral_step", 0.10)
    if isinstance(mls, bool) or not isinstance(mls, (int, float)) or not (0.0 <= float(mls) < 0.4):
        problems.append(f"a min_lateral_step in [0, 0.4) m (got {mls!r})")
    acg = layout.get("alip_com_gains")
    if acg is not None and not _number_pair(acg, lambda x: x > 0):
        problems.append(f"alip_com_gains as two positive numbers [k_p, k_d] (got {acg!r})")
    acr = layout.get("alip_cop_range")
    if acr is not None and not _number_pair(acr, lambda x: 0 <= x < MAX_ALIP_COP_RANGE):
        problems.append(f"alip_cop_range as two numbers in [0, {MAX_ALIP_COP_RANGE:g}) m [x, y] (got {acr!r})")
    sd = layout.get("step_duration", 0.4)
    if isinstance(sd, bool) or not isinstance(sd, (int, float)) or not (0.2 <= float(sd) <= 1.0):
        problems.append(f"a step_duration in [0.2, 1.0] s (got {sd!r})")
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
        wbc_overrides=_overrides_tuple(mjcf_path, layout.get("wbc_overrides", ())),
        min_lateral_step=float(layout.get("min_lateral_step", 0.10)),
        step_duration=float(layout.get("step_duration", 0.4)),
        alip_com_gains=None if layout.get("alip_com_gains") is None else (
            float(layout["alip_com_gains"][0]), float(layout["alip_com_gains"][1])),
        alip_cop_range=None if layout.get("alip_cop_range") is None else (
            float(layout["alip_cop_range"][0]), float(layout["alip_cop_range"][1])),
        layout_file=Path(layout_file) if layout_file is not None else None,
    )


def loop_closure_errors(model: Any, data: Any) -> np.ndarray:
    """Distance between the two anchors of every ``<equality connect>`` (closed loop) [m], (neq,).

    Reads the body poses of ``data`` (current after ``mj_forward``/``mj_step``); other equality types
    give NaN. MuJoCo's loop constraints are soft, so these are the simulated rods' stretch.
    """
    import mujoco

    out = np.full(model.neq, np.nan)
    for e in range(model.neq):
        connect = int(model.eq_type[e]) == int(mujoco.mjtEq.mjEQ_CONNECT)
        if not connect or int(model.eq_objtype[e]) != int(mujoco.mjtObj.mjOBJ_BODY):
            continue
        b1, b2 = int(model.eq_obj1id[e]), int(model.eq_obj2id[e])
        p1 = data.xpos[b1] + data.xmat[b1].reshape(3, 3) @ model.eq_data[e, 0:3]
        p2 = data.xpos[b2] + data.xmat[b2].reshape(3, 3) @ model.eq_data[e, 3:6]
        out[e] = float(np.linalg.norm(p1 - p2))
    return out


def digit_like_paths() -> tuple[Path, Path]:
    """(robot MJCF, scene MJCF) of the packaged digit_like model."""
    folder = data_path("models", "digit_like")
    return folder / "digit_like.xml", folder / "scene.xml"


def _number_pair(value: Any, ok: Any) -> bool:
    """True when ``value`` is a list or tuple of two finite real numbers (not booleans) that pass ``ok``."""
    return isinstance(value, (list, tuple)) and len(value) == 2 and all(
        isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and ok(x) for x in value
    )


def _overrides_tuple(path: Path, value: Any) -> tuple[tuple[str, Any], ...]:
    """``wbc_overrides`` as (field, value) pairs from a dict or pairs; fields checked by the controller."""
    if value is None:
        return ()
    items = value.items() if isinstance(value, dict) else value
    try:
        pairs = tuple((str(k), v) for k, v in items)
    except (TypeError, ValueError):
        raise RobotDescriptionError(str(path), ["wbc_overrides as a table of WbcParams fields"]) from None
    return pairs


#: Keys of a layout file (all optional except the foot bodies and the torso).
LAYOUT_KEYS = (
    "name", "left_foot_body", "right_foot_body", "left_sole_site", "right_sole_site", "sole_offset",
    "foot_length", "foot_width", "torso_body", "base_joint", "leg_joints", "arm_joints", "standing_keyframe",
    "standing_qpos", "wbc_overrides", "min_lateral_step", "step_duration", "alip_com_gains",
    "alip_cop_range",
)


def read_layout_file(path: str | Path) -> dict[str, Any]:
    """Read a robot layout from a TOML (``.toml``) or JSON (``.json``) file.

    The keys are those of :data:`LAYOUT_KEYS`: the names of the foot bodies, sole sites, torso, leg
    and arm joints of the MJCF, the foot size [m], a standing keyframe name or a standing ``qpos``,
    ``base_joint`` (the free joint's name, or absent for a slide+ball base), ``min_lateral_step``
    [m] (default 0.10), ``step_duration`` [s] (the MPCC's T, default 0.4), ``alip_com_gains``
    (``[k_p, k_d]`` of the horizontal COM task in paper B's runs; absent: the controller's own),
    ``alip_cop_range`` (``[x, y]`` [m], the ALIP-MPC's centre-of-pressure box in the sole; absent: a
    point foot) and a
    ``wbc_overrides`` table of :class:`~lipmpcc.wbc.WbcParams` fields.
    Example (TOML)::

        name = "my_biped"
        left_foot_body = "l_foot"
        right_foot_body = "r_foot"
        left_sole_site = "l_sole"
        right_sole_site = "r_sole"
        foot_length = 0.22
        foot_width = 0.09
        torso_body = "pelvis"
        base_joint = "root"
        leg_joints = ["l_hip", "l_knee", "l_ankle", "r_hip", "r_knee", "r_ankle"]
        arm_joints = []
        standing_keyframe = "home"
        min_lateral_step = 0.12
        step_duration = 0.4
        [wbc_overrides]
        cop_safety_factor = 0.7

    Raises:
        ModelFileError: the file is missing or not valid TOML/JSON.
        RobotDescriptionError: an unknown key, or a required one missing.
    """
    import json
    import tomllib

    path = Path(path)
    if not path.is_file():
        raise ModelFileError(str(path), "layout file not found")
    try:
        if path.suffix.lower() == ".json":
            data = json.loads(path.read_text())
        else:
            data = tomllib.loads(path.read_text())
    except (ValueError, tomllib.TOMLDecodeError) as err:
        raise ModelFileError(str(path), f"not a valid layout file: {_one_line(err)}") from None
    if not isinstance(data, dict):
        raise RobotDescriptionError(str(path), ["a table of layout keys"])
    unknown = sorted(set(data) - set(LAYOUT_KEYS))
    missing = [k for k in ("left_foot_body", "right_foot_body", "torso_body") if k not in data]
    problems = [f"no unknown key '{k}' (known: {', '.join(LAYOUT_KEYS)})" for k in unknown]
    problems += [f"the key '{k}'" for k in missing]
    if problems:
        raise RobotDescriptionError(str(path), problems)
    layout = dict(data)
    for k in ("leg_joints", "arm_joints"):
        layout[k] = tuple(layout.get(k, ()))
    for k in ("left_sole_site", "right_sole_site", "base_joint", "standing_keyframe", "standing_qpos"):
        layout.setdefault(k, None)
    layout.setdefault("sole_offset", (0.0, 0.0, 0.0))
    return layout


def _sidecar_layout(path: Path) -> Path | None:
    """``<model>.lipmpcc.toml`` (or ``.json``) next to the MJCF, if present."""
    for suffix in (".lipmpcc.toml", ".lipmpcc.json"):
        candidate = path.with_name(path.stem + suffix)
        if candidate.is_file():
            return candidate
    return None


def load_robot(
    robot: str | Path | RobotDescription = "digit_like",
    *,
    layout: str | Path | None = None,
    **overrides: Any,
) -> RobotDescription:
    """Describe a robot model.

    Args:
        robot: ``"digit_like"`` (the packaged model), or the path of an MJCF file (a ``str`` that
            ends in ``.xml`` or any ``Path``), or a description (returned as is, with overrides
            applied).
        layout: for an MJCF path: a shipped layout name (``"digit_like"``, ``"digit_v3"``) or the
            path of a layout file (:func:`read_layout_file`). None: ``<model>.lipmpcc.toml`` next
            to the model if present, else the layout recognised from the body names.
        overrides: layout fields of :class:`RobotDescription` to set (names of parts, foot size,
            standing configuration, ``wbc_overrides``, ``name``), e.g. ``left_foot_body="l_foot"``
            for a model whose names are not recognised. Fields computed from the model (motors,
            limits, mass) cannot be overridden.

    Returns:
        The description; the robot file (and the scene file, when different) compile in MuJoCo.

    Raises:
        ModelFileError: the file (or the layout file) is missing or cannot be read.
        RobotDescriptionError: the model lacks a part the stack needs (all of them are listed).
        InvalidInputError: ``robot`` or ``layout`` is an unknown name.
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
        layout_dict, layout_path = _resolve_layout(path, layout)
        return describe_model(model, path, path, layout=layout_dict, layout_file=layout_path, **overrides)
    raise InvalidInputError("robot", robot, "'digit_like' or the path of an MJCF file (.xml)")


def _resolve_layout(path: Path, layout: str | Path | None) -> tuple[dict[str, Any] | None, Path | None]:
    if layout is None:
        sidecar = _sidecar_layout(path)
        return (read_layout_file(sidecar), sidecar) if sidecar is not None else (None, None)
    if isinstance(layout, str) and layout in _LAYOUTS:
        return dict(_LAYOUTS[layout](), name=layout), None
    if isinstance(layout, Path) or (isinstance(layout, str) and layout.lower().endswith((".toml", ".json"))):
        return read_layout_file(layout), Path(layout)
    raise InvalidInputError("layout", layout, f"one of {sorted(_LAYOUTS)} or the path of a .toml/.json layout file")
