"""Reading MuJoCo models: compiling an MJCF, the names of its parts, its closed kinematic loops.

- :func:`compile_mjcf`: ``mujoco.MjModel`` of a file, with MuJoCo's reason on one line when it fails;
- :func:`compile_scene`: the simulator's model of a scene file (optionally edited as a
  ``mujoco.MjSpec`` first; a ground plane is added when the scene has none);
- :func:`names`: the names of the model's objects of one type;
- :func:`torque_drive`: ``<position>``/``<velocity>``/``<general>`` servos on joints turned into torque
  sources (ctrl = actuator force), as the whole-body controller drives them;
- :func:`check_equalities`: every equality constraint is an active body ``<equality connect>``;
- :func:`connect_residuals`, :func:`loop_closure_errors`: how far apart the two anchors of every
  ``<equality connect>`` (a closed loop) are [m] — the one definition, used by the simulator's
  diagnostics and by the whole-body controller's model checks.

``mujoco`` is imported inside the functions: importing this module does not import MuJoCo, so that
:mod:`lipmpcc.sim.render` can choose the OpenGL backend first.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from ..exceptions import ModelFileError, RobotDescriptionError

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

__all__ = [
    "compile_mjcf",
    "compile_scene",
    "has_ground",
    "names",
    "torque_drive",
    "add_light",
    "robot_in_scene",
    "check_equalities",
    "connect_residuals",
    "connect_residuals_at",
    "loop_closure_errors",
]

#: MuJoCo's equality types, by their ``mjtEq`` value
_EQ_NAMES = {0: "connect", 1: "weld", 2: "joint", 3: "tendon", 4: "flex"}


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def compile_mjcf(path: Path) -> "mujoco.MjModel":
    """``mujoco.MjModel`` of ``path``.

    Raises:
        ModelFileError: the file is missing or MuJoCo cannot load it (its reason on one line).
    """
    import mujoco

    path = Path(path)
    if not path.is_file():
        raise ModelFileError(str(path), "file not found" if not path.exists() else "not a regular file")
    try:
        return mujoco.MjModel.from_xml_path(str(path))
    except (ValueError, RuntimeError) as err:  # MuJoCo raises ValueError with the XML/compile reason
        if _is_binary(path):
            raise ModelFileError(str(path), "not an MJCF file: expected XML text, the file is binary") from None
        raise ModelFileError(str(path), f"MuJoCo cannot load it: {_one_line(err)}") from None


def _is_binary(path: Path) -> bool:
    """True when the first 4 kB of ``path`` hold a NUL byte or are not UTF-8 text."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except OSError:
        return False
    if b"\x00" in head:
        return True
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as err:
        return err.start < len(head) - 4  # a character cut at the end of the 4 kB is not binary
    return False


def has_ground(model: "mujoco.MjModel") -> bool:
    """True when the world body has a plane or a height field."""
    import mujoco

    ground = (int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_HFIELD))
    return any(int(model.geom_bodyid[g]) == 0 and int(model.geom_type[g]) in ground for g in range(model.ngeom))


def compile_scene(
    path: Path, scene_editor: Callable[["mujoco.MjSpec"], None] | None = None
) -> "mujoco.MjModel":
    """The simulator's model of the scene file ``path``.

    The file is read as a ``mujoco.MjSpec``, handed to ``scene_editor`` (if any) and compiled; a
    scene without a ground plane (or height field) gets one at z = 0 (geom ``lipmpcc_floor``), a
    scene without a light gets one (:func:`add_light`: videos are not black), and its servos are
    driven as torque sources (:func:`torque_drive`).

    Raises:
        ModelFileError: the file is missing or MuJoCo cannot load it (its reason on one line).
    """
    import mujoco

    path = Path(path)
    if not path.is_file():
        raise ModelFileError(str(path), "file not found")
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        if scene_editor is not None:
            scene_editor(spec)
        model = spec.compile()
        if not has_ground(model) or model.nlight == 0:
            if not has_ground(model):
                spec.worldbody.add_geom(
                    name="lipmpcc_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.0, 0.0, 0.05],
                    contype=0, conaffinity=1, condim=3, rgba=[0.35, 0.4, 0.45, 1.0],
                )
            if model.nlight == 0:
                add_light(spec)
            model = spec.compile()
        torque_drive(model)
    except (ValueError, RuntimeError) as err:
        raise ModelFileError(str(path), f"MuJoCo cannot load it: {_one_line(err)}") from None
    return model


def _has_free_body(path: Path) -> bool:
    """True when the MJCF text of ``path`` has a free joint (``<freejoint>`` or ``<joint type="free">``)."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError):
        return False
    return any(el.tag == "freejoint" or (el.tag == "joint" and el.get("type") == "free") for el in root.iter())


def robot_in_scene(path: Path) -> Path | None:
    """The robot file a scene file includes, or None when ``path`` is not such a scene.

    A scene (Menagerie's ``scene.xml``) has no free joint of its own and includes
    (``<include file="..."/>``) exactly one file that has one: that file is the robot (Pinocchio reads it;
    the simulator loads the scene)."""
    import xml.etree.ElementTree as ET

    path = Path(path)
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError):
        return None
    if _has_free_body(path):
        return None
    robots = [path.parent / el.get("file", "") for el in root.iter("include")]
    robots = [r for r in robots if r.is_file() and _has_free_body(r)]
    return robots[0] if len(robots) == 1 else None


def add_light(spec: "mujoco.MjSpec") -> None:
    """Add a directional light from above (``lipmpcc_light``, with shadows) and a head light to ``spec``'s
    world. Lights change what a camera sees, nothing of the physics."""
    import mujoco

    spec.worldbody.add_light(name="lipmpcc_light", pos=[0.0, 0.0, 4.0], dir=[0.0, 0.0, -1.0],
                             type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL, castshadow=True,
                             diffuse=[0.6, 0.6, 0.6])
    spec.visual.headlight.ambient = [0.3, 0.3, 0.3]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]


def _force_bound(model: "mujoco.MjModel", a: int) -> tuple[float, float, str] | None:
    """(lower, upper) actuator-force bound of actuator ``a`` and where it comes from: its
    ``forcerange``, else its joint's ``actuatorfrcrange`` (divided by the gear), else None."""
    if model.actuator_forcelimited[a]:
        lo, hi = (float(x) for x in model.actuator_forcerange[a])
        return lo, hi, "forcerange"
    j = int(model.actuator_trnid[a, 0])
    gear = abs(float(model.actuator_gear[a, 0])) or 1.0
    if model.jnt_actfrclimited[j]:
        lo, hi = (float(x) / gear for x in model.jnt_actfrcrange[j])
        return lo, hi, "actuatorfrcrange"
    return None


def torque_drive(model: "mujoco.MjModel") -> tuple[str, ...]:
    """Turn every servo on a joint into a torque source, in place; the notes of what changed.

    A ``<position>``, ``<velocity>`` or ``<general>`` actuator with a joint transmission, no activation
    dynamics and a fixed gain (``gaintype="fixed"``, ``biastype`` none or affine) becomes a motor:
    gain 1, no bias, so that ``ctrl`` is the actuator force and ``gear × ctrl`` the joint torque
    [N m]. Its control range becomes its force bound: ``forcerange`` if limited, else the joint's
    ``actuatorfrcrange`` / |gear|, else none (a servo's ``ctrlrange`` is a position, not a force).
    Motors (no bias, any fixed gain) are left exactly as they are; other actuators (activation dynamics,
    tendon or site transmissions) too, and the whole-body controller refuses them by name.

    Returns:
        One note per kind of servo turned (e.g. ``"29 position servos driven as torque sources
        (limits from actuatorfrcrange)"``); empty when the model had only motors.
    """
    import mujoco

    fixed, none_bias = int(mujoco.mjtGain.mjGAIN_FIXED), int(mujoco.mjtBias.mjBIAS_NONE)
    affine, joint_trn = int(mujoco.mjtBias.mjBIAS_AFFINE), int(mujoco.mjtTrn.mjTRN_JOINT)
    counts: dict[tuple[str, str], int] = {}
    for a in range(int(model.nu)):
        gaintype, biastype = int(model.actuator_gaintype[a]), int(model.actuator_biastype[a])
        if (int(model.actuator_trntype[a]) != joint_trn or int(model.actuator_dyntype[a]) != 0
                or gaintype != fixed or biastype != affine):
            continue  # a motor (fixed gain, no bias: the controller reads gear x gain), or not a joint servo
        kind = ("position" if model.actuator_biasprm[a, 1] != 0 else "velocity" if model.actuator_biasprm[a, 2] != 0
                else "general")
        bound = _force_bound(model, a)
        model.actuator_gainprm[a, :] = 0.0
        model.actuator_gainprm[a, 0] = 1.0
        model.actuator_biasprm[a, :] = 0.0
        model.actuator_biastype[a] = none_bias
        if bound is None:
            model.actuator_ctrllimited[a] = 0
            source = "none"
        else:
            model.actuator_ctrllimited[a] = 1
            model.actuator_ctrlrange[a] = bound[:2]
            source = bound[2]
        counts[(kind, source)] = counts.get((kind, source), 0) + 1
    return tuple(f"{n} {kind} servo{'s' if n > 1 else ''} driven as torque sources (ctrl = actuator force; "
                 f"limits from {source if source != 'none' else 'nothing: unlimited'})"
                 for (kind, source), n in sorted(counts.items()))


def names(model: "mujoco.MjModel", objtype: "mujoco.mjtObj", n: int) -> list[str]:
    """Names of the objects ``0..n-1`` of type ``objtype`` (``""`` for an unnamed one)."""
    import mujoco

    return [mujoco.mj_id2name(model, objtype, i) or "" for i in range(n)]


def check_equalities(model: "mujoco.MjModel", path: Path | str) -> None:
    """Every equality constraint must be an active body-anchored ``<equality connect>`` (a loop closure).

    Raises:
        RobotDescriptionError: naming each constraint that is not (``path``: the file, for the message).
    """
    import mujoco

    problems = []
    for e in range(model.neq):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_EQUALITY, e) or f"equality {e}"
        kind = _EQ_NAMES.get(int(model.eq_type[e]), str(int(model.eq_type[e])))
        if kind != "connect":
            problems.append(f"an <equality connect> loop closure instead of the <equality {kind}> '{name}' "
                            "(only connect constraints are supported)")
        elif not bool(model.eq_active0[e]):
            problems.append(f"an active <equality connect> '{name}' (it is inactive at start)")
        elif int(model.eq_objtype[e]) != int(mujoco.mjtObj.mjOBJ_BODY):
            problems.append(f"a body-and-anchor <equality connect> '{name}' (site-based connects are not read)")
    if problems:
        raise RobotDescriptionError(str(path), problems)


def connect_residuals(model: "mujoco.MjModel", data: "mujoco.MjData") -> np.ndarray:
    """Anchor 1 minus anchor 2 (world frame) of every body ``<equality connect>`` [m], (neq, 3).

    Reads the body poses of ``data`` (current after ``mj_kinematics``/``mj_forward``/``mj_step``);
    rows of other equality types are NaN. MuJoCo's loop constraints are soft: in a simulation these
    are the rods' stretch.
    """
    import mujoco

    connect, body = int(mujoco.mjtEq.mjEQ_CONNECT), int(mujoco.mjtObj.mjOBJ_BODY)
    out = np.full((model.neq, 3), np.nan)
    for e in range(model.neq):
        if int(model.eq_type[e]) != connect or int(model.eq_objtype[e]) != body:
            continue
        b1, b2 = int(model.eq_obj1id[e]), int(model.eq_obj2id[e])
        p1 = data.xpos[b1] + data.xmat[b1].reshape(3, 3) @ model.eq_data[e, 0:3]
        p2 = data.xpos[b2] + data.xmat[b2].reshape(3, 3) @ model.eq_data[e, 3:6]
        out[e] = p1 - p2
    return out


def connect_residuals_at(model: "mujoco.MjModel", qpos: np.ndarray) -> np.ndarray:
    """:func:`connect_residuals` at the configuration ``qpos`` (MuJoCo's order) [m], (neq, 3)."""
    import mujoco

    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    return connect_residuals(model, data)


def loop_closure_errors(model: "mujoco.MjModel", data: "mujoco.MjData") -> np.ndarray:
    """Distance between the two anchors of every ``<equality connect>`` (closed loop) [m], (neq,).

    The norms of :func:`connect_residuals`' rows (NaN for other equality types).
    """
    res = connect_residuals(model, data)
    out = np.full(model.neq, np.nan)
    for e in range(model.neq):
        if not np.isnan(res[e, 0]):
            out[e] = float(np.linalg.norm(res[e]))
    return out
