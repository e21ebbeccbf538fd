"""Building a :class:`~lipmpcc.robots.description.RobotDescription`: :func:`load_robot`, :func:`describe_model`.

:func:`load_robot` describes

- ``"digit_like"``: the project's own Digit-class biped, ``data/models/digit_like/`` (a free-joint
  base, 6 joints per leg, 4 per arm, 20 motors with gear 1 so that a motor command is a joint torque);
- any MJCF path: the layout (:mod:`lipmpcc.robots.layouts`) is a given name or file, the file next
  to the model, or recognised from its body names (the digit_like names, or those of the Digit v3
  model of osudrl/roadrunner: ``left-leg/toe-roll``, ``torso/base``, ...). Keyword overrides name
  the parts of any other model.

The description carries the models it compiled (:attr:`~RobotDescription.model`, and for
``digit_like`` also :attr:`~RobotDescription.scene_model`), so nothing compiles them again.

Errors: a missing or unparsable file raises :class:`~lipmpcc.exceptions.ModelFileError` (with
MuJoCo's reason on one line); a model that lacks a named part raises
:class:`~lipmpcc.exceptions.RobotDescriptionError` listing every missing part.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable

import numpy as np

from ..exceptions import InvalidInputError, LayoutError, RobotDescriptionError
from ..resources import data_path
from ..validation import is_finite_number
from .description import RobotDescription
from .layouts import (
    LAYOUT_KEYS,
    MAX_ALIP_COP_RANGE,
    REQUIRED_LAYOUT_KEYS,
    SHIPPED_LAYOUTS,
    detect_layout,
    layout_problems,
    resolve_layout,
    shipped_layout,
)
from .mjcf import compile_mjcf, compile_scene, names, robot_in_scene, torque_drive

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

__all__ = ["load_robot", "describe_model", "digit_like_paths"]

#: A layout: layout key -> value (part names, sizes, settings of mixed types; see LAYOUT_KEYS)
Layout = dict[str, Any]


def digit_like_paths() -> tuple[Path, Path]:
    """(robot MJCF, scene MJCF) of the packaged digit_like model."""
    folder = data_path("models", "digit_like")
    return folder / "digit_like.xml", folder / "scene.xml"


# ------------------------------------------------------------------------------------------------
# describe_model and its steps
# ------------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class _ModelNames:
    """Names of a model's bodies, sites, joints (in order) and keyframes."""

    bodies: set[str]
    sites: set[str]
    joints: list[str]
    keys: set[str]

    @classmethod
    def read(cls, model: "mujoco.MjModel") -> "_ModelNames":
        import mujoco

        return cls(
            bodies=set(names(model, mujoco.mjtObj.mjOBJ_BODY, model.nbody)),
            sites=set(names(model, mujoco.mjtObj.mjOBJ_SITE, model.nsite)),
            joints=names(model, mujoco.mjtObj.mjOBJ_JOINT, model.njnt),
            keys=set(names(model, mujoco.mjtObj.mjOBJ_KEY, model.nkey)),
        )


def _complete_layout(layout: Layout | None, bodies: set[str]) -> tuple[Layout, str | None]:
    """(full layout, its key) from a given layout (completed with the digit_like values and no
    robot-specific settings) or, for None, the shipped layout recognised from the body names (an
    unrecognised model is checked against the digit_like names, so that the error lists exactly the
    parts to add or to name)."""
    if layout is None:
        key = detect_layout(bodies)
        full = shipped_layout(key or "digit_like")
        full.pop("name", None)
        return full, key
    full = shipped_layout("digit_like")
    full.pop("name", None)
    full.update({"standing_keyframe": None, "wbc_overrides": (), "alip_wbc_overrides": (), "alip_com_gains": None,
                 "alip_cop_range": None})
    full.update(layout)
    key = full.pop("name", None)
    return full, key


def _near_shipped(bodies: set[str]) -> bool:
    """True when a shipped layout is recognised from the body names, or its torso is among them (a
    variant of a shipped model: the error then lists the parts it lacks)."""
    return detect_layout(bodies) is not None or any(
        shipped_layout(k)["torso_body"] in bodies for k in SHIPPED_LAYOUTS)


def _no_layout(path: Path) -> str:
    """The message of a model without a layout: where it was looked for, and the command that writes one."""
    return (f"a layout: no layout found (no {path.stem}.lipmpcc.toml beside {path.name}, and its body names are "
            f"not those of a shipped layout); write one with `lipmpcc robot init {path}` (or pass a layout file)")


def _number_pair(value: object, ok: Callable[[float], bool]) -> bool:
    """True when ``value`` is a list or tuple of two finite real numbers (not booleans) that pass ``ok``."""
    return isinstance(value, (list, tuple)) and len(value) == 2 and all(is_finite_number(x) and ok(x) for x in value)


def _number_in(value: object, lo: float, hi: float, hi_open: bool) -> bool:
    if not is_finite_number(value):
        return False
    return lo <= float(value) < hi if hi_open else lo <= float(value) <= hi


def _part_problems(layout: Layout, model: "mujoco.MjModel", n: _ModelNames) -> list[str]:
    """The named parts (bodies, sites, joints, keyframe, standing qpos, actuators) the model lacks."""
    import mujoco

    problems: list[str] = []
    for f in ("left_foot_body", "right_foot_body", "torso_body"):
        if layout[f] not in n.bodies:
            problems.append(f"body '{layout[f]}' ({f})")
    for f in ("left_sole_site", "right_sole_site"):
        if layout[f] is not None and layout[f] not in n.sites:
            problems.append(f"site '{layout[f]}' ({f})")
    for key in ("leg_joints", "arm_joints", "waist_joints", "head_joints"):
        for j in layout.get(key, ()):
            if j not in n.joints:
                problems.append(f"joint '{j}' ({key})")
    base = layout["base_joint"]
    if base is not None:
        if base not in n.joints:
            problems.append(f"joint '{base}' (base_joint)")
        elif model.jnt_type[n.joints.index(base)] != mujoco.mjtJoint.mjJNT_FREE:
            problems.append(f"a free joint named '{base}' (base_joint)")
    if layout["standing_keyframe"] is not None and layout["standing_keyframe"] not in n.keys:
        problems.append(f"keyframe '{layout['standing_keyframe']}' (standing_keyframe)")
    qpos = layout["standing_qpos"]
    if qpos is not None and len(qpos) != model.nq:
        problems.append(f"a standing_qpos of length nq = {model.nq} (got {len(qpos)})")
    if model.nu == 0:
        problems.append("actuators (the model has none)")
    return problems


def _setting_problems(layout: Layout) -> list[str]:
    """The per-robot settings out of their ranges."""
    problems: list[str] = []
    mls = layout.get("min_lateral_step", 0.10)
    if not _number_in(mls, 0.0, 0.4, hi_open=True):
        problems.append(f"a min_lateral_step in [0, 0.4) m (got {mls!r})")
    acg = layout.get("alip_com_gains")
    if acg is not None and not _number_pair(acg, lambda x: x > 0):
        problems.append(f"alip_com_gains as two positive numbers [k_p, k_d] (got {acg!r})")
    acr = layout.get("alip_cop_range")
    if acr is not None and not _number_pair(acr, lambda x: 0 <= x < MAX_ALIP_COP_RANGE):
        problems.append(f"alip_cop_range as two numbers in [0, {MAX_ALIP_COP_RANGE:g}) m [x, y] (got {acr!r})")
    dst = layout.get("alip_dcm_settle_time", 0.0)
    if not _number_in(dst, 0.0, 0.3, hi_open=False):
        problems.append(f"an alip_dcm_settle_time in [0, 0.3] s (got {dst!r})")
    ld = layout.get("landing_depth", 0.0)
    if not _number_in(ld, 0.0, 0.05, hi_open=False):
        problems.append(f"a landing_depth in [0, 0.05] m (got {ld!r})")
    sh = layout.get("steady_heading", False)
    if not isinstance(sh, bool):
        problems.append(f"steady_heading as true or false (got {sh!r})")
    tdt = layout.get("touchdown_timing")
    if tdt not in (None, "planner", "loop"):
        problems.append(f"a touchdown_timing 'planner' or 'loop' (got {tdt!r})")
    att = layout.get("alip_touchdown_timing", "planner")
    if att not in ("planner", "loop"):
        problems.append(f"an alip_touchdown_timing 'planner' or 'loop' (got {att!r})")
    acs = layout.get("alip_com_resync", False)
    if not isinstance(acs, bool):
        problems.append(f"alip_com_resync as true or false (got {acs!r})")
    asr = layout.get("alip_step_reference", "plan")
    if asr not in ("plan", "stones"):
        problems.append(f"an alip_step_reference 'plan' or 'stones' (got {asr!r})")
    asb = layout.get("alip_stone_bounds", "relative")
    if asb not in ("relative", "world"):
        problems.append(f"an alip_stone_bounds 'relative' or 'world' (got {asb!r})")
    ams = layout.get("alip_max_speed", 0.0)
    if not _number_in(ams, 0.0, 5.0, hi_open=False):
        problems.append(f"an alip_max_speed in [0, 5] m/s (got {ams!r})")
    acf = layout.get("alip_cop_safety_factor")
    if acf is not None and (not _number_in(acf, 0.0, 1.0, hi_open=False) or float(acf) <= 0.0):
        problems.append(f"an alip_cop_safety_factor in (0, 1] (got {acf!r})")
    sd = layout.get("step_duration", 0.4)
    if not _number_in(sd, 0.2, 1.0, hi_open=False):
        problems.append(f"a step_duration in [0.2, 1.0] s (got {sd!r})")
    return problems


def _motors(model: "mujoco.MjModel", joints: list[str], path: Path) -> dict[str, tuple[Any, ...]]:
    """Motor names, driven joints, joint-side torque limits [N m] and gears, in actuator order."""
    import mujoco

    motor_names = tuple(names(model, mujoco.mjtObj.mjOBJ_ACTUATOR, model.nu))
    motor_joints, limits, gears = [], [], []
    for a in range(model.nu):
        if model.actuator_trntype[a] != mujoco.mjtTrn.mjTRN_JOINT:
            raise RobotDescriptionError(str(path), [f"a joint transmission for actuator '{motor_names[a]}'"])
        motor_joints.append(joints[model.actuator_trnid[a, 0]])
        gear = float(model.actuator_gear[a, 0])
        gears.append(gear)
        if model.actuator_ctrllimited[a]:
            bound = float(np.max(np.abs(model.actuator_ctrlrange[a])))
            limits.append(abs(gear) * bound)
        else:
            limits.append(float("inf"))
    return {"motor_names": motor_names, "motor_joints": tuple(motor_joints), "torque_limits": tuple(limits),
            "motor_gears": tuple(gears)}


def _overrides_tuple(path: Path, value: Any) -> tuple[tuple[str, object], ...]:
    """``wbc_overrides`` as (field, value) pairs from a dict or pairs; fields checked by the controller."""
    if value is None:
        return ()
    items = value.items() if isinstance(value, dict) else value
    try:
        pairs = tuple((str(k), v) for k, v in items)
    except (TypeError, ValueError):
        raise RobotDescriptionError(str(path), ["wbc_overrides as a table of WbcParams fields"]) from None
    return pairs


def _pair_or_none(value: Any) -> tuple[float, float] | None:
    return None if value is None else (float(value[0]), float(value[1]))


def _layout_fields(layout: Layout, path: Path) -> dict[str, Any]:
    """The :class:`RobotDescription` fields a (checked) layout gives."""
    qpos = layout["standing_qpos"]
    return dict(
        left_foot_body=layout["left_foot_body"],
        right_foot_body=layout["right_foot_body"],
        left_sole_site=layout["left_sole_site"],
        right_sole_site=layout["right_sole_site"],
        sole_offset=tuple(float(x) for x in layout["sole_offset"]),
        foot_length=float(layout["foot_length"]),
        foot_width=float(layout["foot_width"]),
        torso_body=layout["torso_body"],
        base_joint=layout["base_joint"],
        leg_joints=tuple(layout["leg_joints"]),
        arm_joints=tuple(layout["arm_joints"]),
        waist_joints=tuple(layout.get("waist_joints", ())),
        head_joints=tuple(layout.get("head_joints", ())),
        **{k: None if layout.get(k) is None else float(layout[k])
           for k in ("fall_height", "step_width", "max_step_length", "lip_height")},
        standing_keyframe=layout["standing_keyframe"],
        standing_qpos=None if qpos is None else tuple(float(x) for x in qpos),
        wbc_overrides=_overrides_tuple(path, layout.get("wbc_overrides", ())),
        alip_wbc_overrides=_overrides_tuple(path, layout.get("alip_wbc_overrides", ())),
        min_lateral_step=float(layout.get("min_lateral_step", 0.10)),
        step_duration=float(layout.get("step_duration", 0.4)),
        alip_com_gains=_pair_or_none(layout.get("alip_com_gains")),
        alip_cop_range=_pair_or_none(layout.get("alip_cop_range")),
        alip_dcm_settle_time=float(layout.get("alip_dcm_settle_time", 0.0)),
        touchdown_timing=layout.get("touchdown_timing"),
        landing_depth=float(layout.get("landing_depth", 0.0)),
        steady_heading=bool(layout.get("steady_heading", False)),
        # paper B's runs follow the layout's touchdown_timing when it states no alip_touchdown_timing (Digit's state neither)
        alip_touchdown_timing=str(layout.get("alip_touchdown_timing", layout.get("touchdown_timing") or "planner")),
        alip_com_resync=bool(layout.get("alip_com_resync", False)),
        alip_step_reference=str(layout.get("alip_step_reference", "plan")),
        alip_stone_bounds=str(layout.get("alip_stone_bounds", "relative")),
        alip_max_speed=float(layout.get("alip_max_speed", 0.0)),
        alip_cop_safety_factor=None if layout.get("alip_cop_safety_factor") is None
        else float(layout["alip_cop_safety_factor"]),
    )


def describe_model(
    model: "mujoco.MjModel",
    mjcf_path: Path,
    scene_path: Path | None = None,
    name: str | None = None,
    layout: Layout | None = None,
    layout_file: Path | None = None,
    **overrides: Any,
) -> RobotDescription:
    """A :class:`RobotDescription` of a compiled ``mujoco.MjModel`` (of ``mjcf_path``).

    The layout (part names) is ``layout`` when given (e.g. read from a layout file), else it is
    recognised from the body names; ``overrides`` set or replace any layout field. Every named part
    is checked against the model. ``model``'s servos are driven as torque sources, in place
    (:func:`~lipmpcc.robots.mjcf.torque_drive`; the notes in
    :attr:`~RobotDescription.actuator_notes`), and the description keeps it as its compiled
    :attr:`~RobotDescription.model`.

    Raises:
        RobotDescriptionError: a named body, site, joint or keyframe is missing (a model whose layout
            is not recognised is checked against the digit_like names).
        LayoutError: a layout field or override of the wrong type.
        InvalidInputError: an override that is not a layout field.
    """
    notes = torque_drive(model)
    n = _ModelNames.read(model)
    unknown = sorted(set(overrides) - set(LAYOUT_KEYS))
    if unknown:
        raise InvalidInputError("overrides", unknown, f"some of {', '.join(sorted(LAYOUT_KEYS))}")
    name = overrides.pop("name", None) or name
    if layout is None and not (set(overrides) & set(REQUIRED_LAYOUT_KEYS)) and not _near_shipped(n.bodies):
        raise RobotDescriptionError(str(mjcf_path), [_no_layout(Path(mjcf_path))])
    full, key = _complete_layout(layout, n.bodies)
    full.update(overrides)
    bad = layout_problems(full)
    if bad:
        raise LayoutError(str(layout_file if layout_file is not None and not overrides else mjcf_path), bad)
    problems = _part_problems(full, model, n) + _setting_problems(full)
    if problems:
        raise RobotDescriptionError(str(mjcf_path), problems)
    desc = RobotDescription(
        name=name or (key if key else Path(mjcf_path).stem),
        mjcf_path=Path(mjcf_path),
        scene_path=Path(scene_path) if scene_path is not None else Path(mjcf_path),
        **_layout_fields(full, Path(mjcf_path)),
        **_motors(model, n.joints, Path(mjcf_path)),
        total_mass=float(np.sum(model.body_mass)),
        closed_loops=bool(model.neq > 0),
        layout_file=Path(layout_file) if layout_file is not None else None,
        actuator_notes=notes,
    )
    desc._attach(model=model)
    return desc


# ------------------------------------------------------------------------------------------------
# load_robot
# ------------------------------------------------------------------------------------------------
def load_robot(
    robot: str | Path | RobotDescription = "digit_like",
    *,
    layout: str | Path | None = None,
    **overrides: Any,
) -> RobotDescription:
    """Describe a robot model.

    Args:
        robot: ``"digit_like"`` (the packaged model), or the path of an MJCF file (a ``str`` that
            ends in ``.xml`` or any ``Path``; a scene file that includes one robot file, such as
            Menagerie's ``scene.xml``, describes that robot, simulated in the scene), or a description (returned as is, with overrides
            applied; its compiled models are kept).
        layout: for an MJCF path: a shipped layout name (``"digit_like"``, ``"digit_v3"``) or the
            path of a layout file (:func:`~lipmpcc.robots.layouts.read_layout_file`). None:
            ``<model>.lipmpcc.toml`` next to the model if present, else the layout recognised from
            the body names.
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
        if not overrides:
            return robot
        fields = {f.name for f in dataclasses.fields(RobotDescription)}
        unknown = sorted(set(overrides) - fields)
        if unknown:
            raise InvalidInputError("overrides", unknown, f"fields of RobotDescription ({', '.join(sorted(fields))})")
        bad = layout_problems(overrides)
        if bad:
            raise LayoutError(str(robot.mjcf_path), bad)
        desc = dataclasses.replace(robot, **overrides)
        desc._share_models(robot)
        return desc
    if isinstance(robot, str) and robot == "digit_like":
        mjcf, scene = digit_like_paths()
        model = compile_mjcf(mjcf)
        scene_model = compile_scene(scene)
        overrides.setdefault("name", "digit_like")
        desc = describe_model(model, mjcf, scene, **overrides)
        desc._attach(scene_model=scene_model)
        return desc
    if isinstance(robot, Path) or (isinstance(robot, str) and robot.lower().endswith(".xml")):
        path = scene = Path(robot).expanduser()
        included = robot_in_scene(path) if path.is_file() else None
        if included is not None:  # a scene file: the robot it includes, simulated in the scene
            path = included
        model = compile_mjcf(path)
        layout_dict, layout_path = resolve_layout(path, layout)
        return describe_model(model, path, scene, layout=layout_dict, layout_file=layout_path, **overrides)
    raise InvalidInputError("robot", robot, "'digit_like' or the path of an MJCF file (.xml)")
