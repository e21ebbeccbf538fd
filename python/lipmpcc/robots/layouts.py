"""Robot layouts: what the stack needs to know about a robot beyond its MJCF, as a small table.

A *layout* names the foot bodies and their sole sites, the foot size, the torso, the leg and arm
joints and a standing configuration, and holds the per-robot settings of the controllers
(whole-body controller overrides, the smallest lateral step, the step duration, paper B's COM gains
and centre-of-pressure box). It is a TOML (or JSON) file with the keys of :data:`LAYOUT_KEYS`
(:func:`read_layout_file`).

Two ship with the package, as the same kind of file (``data/layouts/``): ``digit_like`` (the
packaged biped) and ``digit_v3`` (the Digit v3 model of osudrl/roadrunner). A user's layout is
passed as ``load_robot(path, layout="my_robot.toml")``, or put next to the model as
``<model>.lipmpcc.toml`` (:func:`sidecar_layout`, found automatically, also by the CLI's
``--robot PATH.xml``), or named for the rest of the process with :func:`use_layout` (the CLI's ``--layout FILE``:
a model in a read-only folder). :data:`DIGIT_V3_STANDING_QPOS` is the Digit v3 layout's standing ``qpos``.
"""

from __future__ import annotations

import copy
import functools
import json
import tomllib
from pathlib import Path
from typing import Any

from ..exceptions import InvalidInputError, LayoutError, ModelFileError, RobotDescriptionError
from ..resources import data_path
from ..validation import is_finite_number, read_text_file

__all__ = [
    "LAYOUT_KEYS",
    "REQUIRED_LAYOUT_KEYS",
    "SHIPPED_LAYOUTS",
    "MAX_ALIP_COP_RANGE",
    "DIGIT_V3_STANDING_QPOS",
    "read_layout_file",
    "use_layout",
    "shipped_layout",
    "detect_layout",
    "sidecar_layout",
    "resolve_layout",
    "layout_problems",
    "distinct_feet_problems",
]

#: Keys of a layout file (all optional except :data:`REQUIRED_LAYOUT_KEYS`).
LAYOUT_KEYS = (
    "name", "left_foot_body", "right_foot_body", "left_sole_site", "right_sole_site", "sole_offset",
    "foot_length", "foot_width", "torso_body", "base_joint", "leg_joints", "arm_joints", "standing_keyframe",
    "standing_qpos", "wbc_overrides", "min_lateral_step", "step_duration", "alip_com_gains",
    "alip_cop_range", "waist_joints", "head_joints", "fall_height", "step_width", "max_step_length", "lip_height", "alip_dcm_settle_time",
    "touchdown_timing", "landing_depth", "steady_heading",
    "alip_touchdown_timing", "alip_com_resync", "alip_step_reference", "alip_stone_bounds", "alip_max_speed",
    "alip_cop_safety_factor", "alip_wbc_overrides",
)

#: The keys every layout file must have.
REQUIRED_LAYOUT_KEYS = ("left_foot_body", "right_foot_body", "torso_body")

#: The layouts shipped with the package (``data/layouts/<name>.toml``), in detection order.
SHIPPED_LAYOUTS = ("digit_like", "digit_v3")

#: Upper bound [m] (exclusive) of each half-extent of a robot's ``alip_cop_range`` (layout files and
#: ``--cop-range``): the centre-of-pressure box must fit in a sole on a 0.2 × 0.1 m stone.
MAX_ALIP_COP_RANGE = 0.2


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _shown(value: object) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


_is_number = is_finite_number


def _names_ok(value: object) -> bool:
    return isinstance(value, (list, tuple)) and all(isinstance(x, str) and x for x in value)


def _is_overrides(v: Any) -> bool:
    """Whether ``v`` reads as a table of WbcParams fields: None, a dict, or (name, value) pairs."""
    return v is None or isinstance(v, dict) or (isinstance(v, (list, tuple)) and all(
        isinstance(p, (list, tuple)) and len(p) == 2 and isinstance(p[0], str) for p in v))


#: What each layout key must be (a check, and its description); range checks of the settings are
#: made by :func:`lipmpcc.robots.loading.describe_model`.
_KEY_TYPES: dict[str, tuple[Any, str]] = {
    "name": (lambda v: isinstance(v, str) and bool(v), "a non-empty string"),
    "left_foot_body": (lambda v: isinstance(v, str) and bool(v), "a body name (string)"),
    "right_foot_body": (lambda v: isinstance(v, str) and bool(v), "a body name (string)"),
    "torso_body": (lambda v: isinstance(v, str) and bool(v), "a body name (string)"),
    "left_sole_site": (lambda v: v is None or (isinstance(v, str) and bool(v)), "a site name (string)"),
    "right_sole_site": (lambda v: v is None or (isinstance(v, str) and bool(v)), "a site name (string)"),
    "base_joint": (lambda v: v is None or (isinstance(v, str) and bool(v)), "a joint name (string)"),
    "standing_keyframe": (lambda v: v is None or (isinstance(v, str) and bool(v)), "a keyframe name (string)"),
    "leg_joints": (_names_ok, "a list of joint names"),
    "arm_joints": (_names_ok, "a list of joint names"),
    "waist_joints": (_names_ok, "a list of joint names"),
    "head_joints": (_names_ok, "a list of joint names"),
    "fall_height": (lambda v: v is None or (_is_number(v) and 0 < v <= 3.0), "a number in (0, 3] m"),
    "step_width": (lambda v: v is None or (_is_number(v) and 0 < v <= 1.0), "a number in (0, 1] m"),
    "max_step_length": (lambda v: v is None or (_is_number(v) and 0 < v <= 1.5), "a number in (0, 1.5] m"),
    "lip_height": (lambda v: v is None or (_is_number(v) and 0 < v <= 3.0), "a number in (0, 3] m"),
    "sole_offset": (lambda v: isinstance(v, (list, tuple)) and len(v) == 3 and all(_is_number(x) for x in v),
                    "three numbers [x, y, z] in metres"),
    "foot_length": (lambda v: _is_number(v) and 0 < v <= 1.0, "a number in (0, 1] m"),
    "foot_width": (lambda v: _is_number(v) and 0 < v <= 1.0, "a number in (0, 1] m"),
    "standing_qpos": (lambda v: v is None or (isinstance(v, (list, tuple)) and len(v) > 0 and all(_is_number(x) for x in v)),
                      "a list of finite numbers (MuJoCo qpos)"),
    "wbc_overrides": (_is_overrides, "a table of WbcParams fields"),
    "alip_wbc_overrides": (_is_overrides, "a table of WbcParams fields"),
}


def _unknown_key(key: str) -> str:
    """What an unknown layout key should be: the nearest known key, else the list of them."""
    import difflib

    near = difflib.get_close_matches(key, LAYOUT_KEYS, n=1, cutoff=0.6)
    hint = f"did you mean '{near[0]}'?" if near else f"known keys: {', '.join(LAYOUT_KEYS)}"
    return f"a known key instead of the unknown key '{key}' ({hint})"


def layout_problems(layout: dict[str, Any]) -> list[str]:
    """What the keys of ``layout`` of the wrong type should be, each with the value received
    (empty when every key present has the right type)."""
    problems = []
    for key, (ok, expected) in _KEY_TYPES.items():
        if key in layout and not ok(layout[key]):
            problems.append(f"{key} as {expected} (got {_shown(layout[key])})")
    return problems + distinct_feet_problems(layout)


def distinct_feet_problems(layout: dict[str, Any]) -> list[str]:
    """The left and right foot bodies (and sole sites, when both are given) must be two different ones:
    a layout naming one body for both feet loads, and the robot just falls."""
    problems = []
    for left, right, what in (("left_foot_body", "right_foot_body", "bodies"), ("left_sole_site", "right_sole_site", "sites")):
        a, b = layout.get(left), layout.get(right)
        if isinstance(a, str) and a and a == b:
            problems.append(f"{left} and {right} as two different {what} (both are {a!r})")
    return problems


def read_layout_file(path: str | Path) -> dict[str, Any]:
    """Read a robot layout from a TOML (``.toml``) or JSON (``.json``) file.

    The keys are those of :data:`LAYOUT_KEYS`: the names of the foot bodies, sole sites, torso, leg
    and arm joints of the MJCF, the foot size [m], a standing keyframe name or a standing ``qpos``,
    ``base_joint`` (the free joint's name, or absent for a slide+ball base), ``min_lateral_step``
    [m] (default 0.10), ``step_duration`` [s] (the MPCC's T, default 0.4), ``alip_com_gains``
    (``[k_p, k_d]`` of the horizontal COM task in paper B's runs; absent: the controller's own),
    ``alip_cop_range`` (``[x, y]`` [m], the ALIP-MPC's centre-of-pressure box in the sole; absent: a
    point foot), ``alip_dcm_settle_time`` [s] (how long after a touch-down paper B's footstep source reads the
    DCM it learns its touch-down bias from; absent: 0, at the touch-down), ``touchdown_timing`` (``"planner"``
    or ``"loop"``: who times the full-body loop's touch-downs for every planner; absent: the loop decides by the
    planner), ``landing_depth`` [m] (how far below the ground the full-body loop's swing foot aims, so that
    it is on the ground at the planned touch-down; absent: 0), ``steady_heading`` (true: paper A's fixed-T MPCC
    runs hold the planned heading to the path; absent: false, paper A's near-free heading), ``alip_touchdown_timing``
    (``"planner"``, the default, or ``"loop"``: who times the touch-down in paper B's runs), ``alip_com_resync``
    (true: paper B's runs restart the LIP COM reference from the measured state at every planner update;
    absent: false, at each touch-down only), ``alip_step_reference`` (``"plan"``, paper B's and the default, or
    ``"stones"``: what the ALIP-MPC's desired steps start from, :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.step_reference`),
    ``alip_stone_bounds`` (``"relative"``, paper B's and the default, or ``"world"``: the ALIP-MPC's stone constraint,
    :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.stone_bounds`), ``alip_max_speed`` [m/s] (the ALIP-MPC's
    fastest nominal walk: longer steps get longer nominal durations, :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.max_speed`;
    absent: 0, paper B's T_nom for every step), ``alip_cop_safety_factor`` (the whole-body controller's CoP
    safety factor in paper B's runs, in (0, 1]; absent: the controller's own, ``wbc_overrides`` included), a
    ``wbc_overrides`` table of :class:`~lipmpcc.control.wbc_types.WbcParams`
    fields and an ``alip_wbc_overrides`` table of the same fields, applied over ``wbc_overrides`` in paper B's runs only. Example (TOML)::

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

    Returns:
        The layout: the file's keys, with ``leg_joints``/``arm_joints`` as tuples, the sole sites,
        ``base_joint``, ``standing_keyframe`` and ``standing_qpos`` None and ``sole_offset`` zero
        when absent.

    Raises:
        ModelFileError: the file is missing, binary, or not valid TOML/JSON.
        RobotDescriptionError: an unknown key, or a required one missing.
        LayoutError: a key of the wrong type (e.g. ``leg_joints = 5``, ``sole_offset = [1.0]``).
    """
    if not isinstance(path, (str, Path)) and not hasattr(path, "__fspath__"):
        raise InvalidInputError("layout", path, "the path of a .toml/.json layout file")
    path = Path(path)
    if not path.is_file():
        raise ModelFileError(str(path), "layout file not found")
    try:
        text = read_text_file("layout", path, "TOML or JSON layout file")
    except InvalidInputError as err:
        raise ModelFileError(str(path), f"not a valid layout file: {err.detail or err.expected}") from None
    try:
        if path.suffix.lower() == ".json":
            data = json.loads(text)
        else:
            data = tomllib.loads(text)
    except (ValueError, tomllib.TOMLDecodeError) as err:
        raise ModelFileError(str(path), f"not a valid layout file: {_one_line(err)}") from None
    if not isinstance(data, dict):
        raise RobotDescriptionError(str(path), ["a table of layout keys"])
    unknown = sorted(set(data) - set(LAYOUT_KEYS))
    if unknown:
        raise LayoutError(str(path), [_unknown_key(k) for k in unknown])
    missing = [k for k in REQUIRED_LAYOUT_KEYS if k not in data]
    if missing:
        raise RobotDescriptionError(str(path), [f"the key '{k}'" for k in missing])
    bad = layout_problems(data)
    if bad:
        raise LayoutError(str(path), bad)
    layout = dict(data)
    for k in ("leg_joints", "arm_joints", "waist_joints", "head_joints"):
        layout[k] = tuple(layout.get(k, ()))
    for k in ("left_sole_site", "right_sole_site", "base_joint", "standing_keyframe", "standing_qpos"):
        layout.setdefault(k, None)
    layout.setdefault("sole_offset", (0.0, 0.0, 0.0))
    return layout


@functools.cache
def _shipped(name: str) -> dict[str, Any]:
    return read_layout_file(data_path("layouts", f"{name}.toml"))


def shipped_layout(name: str) -> dict[str, Any]:
    """A shipped layout (one of :data:`SHIPPED_LAYOUTS`) as :func:`read_layout_file` reads it (a new dict).

    Raises:
        InvalidInputError: an unknown name.
    """
    if name not in SHIPPED_LAYOUTS:
        raise InvalidInputError("layout", name, f"one of {list(SHIPPED_LAYOUTS)}")
    return copy.deepcopy(_shipped(name))


def detect_layout(body_names: set[str]) -> str | None:
    """The shipped layout whose left foot body and torso are among ``body_names``, or None."""
    for key in SHIPPED_LAYOUTS:
        lay = _shipped(key)
        if lay["left_foot_body"] in body_names and lay["torso_body"] in body_names:
            return key
    return None


def sidecar_layout(path: Path) -> Path | None:
    """``<model>.lipmpcc.toml`` (or ``.json``) next to the MJCF ``path``, if present."""
    for suffix in (".lipmpcc.toml", ".lipmpcc.json"):
        candidate = path.with_name(path.stem + suffix)
        if candidate.is_file():
            return candidate
    return None


_LAYOUT_FILES: dict[Path, Path] = {}  # use_layout: robot file (resolved) -> layout file


def use_layout(model: str | Path, layout: str | Path | None) -> None:
    """For the rest of this process, describe the robot file ``model`` with the layout file ``layout``
    (``.toml``/``.json``) wherever it is loaded without an explicit layout, instead of its sidecar
    ``<model>.lipmpcc.toml`` (the CLI's ``--layout``: a model in a read-only folder, its layout written
    elsewhere by ``lipmpcc robot init --out``). ``layout`` None forgets ``model``'s.

    Raises:
        InvalidInputError: ``layout`` is not an existing ``.toml``/``.json`` file.
    """
    key = Path(model).expanduser().resolve()
    if layout is None:
        _LAYOUT_FILES.pop(key, None)
        return
    file = Path(layout).expanduser()
    if file.suffix.lower() not in (".toml", ".json") or not file.is_file():
        raise InvalidInputError("--layout", str(layout), "an existing .toml/.json layout file "
                                "(lipmpcc robot init MODEL.xml --out FILE writes one)")
    _LAYOUT_FILES[key] = file


def resolve_layout(path: Path, layout: str | Path | None) -> tuple[dict[str, Any] | None, Path | None]:
    """(layout, layout file) for the MJCF ``path``: ``layout`` as a shipped name or a file, else the
    file :func:`use_layout` named for ``path``, else the sidecar file, else (None, None) (the layout is then
    recognised from the model's body names).

    Raises:
        InvalidInputError: ``layout`` is neither a shipped name nor a ``.toml``/``.json`` path.
    """
    if layout is None:
        named = _LAYOUT_FILES.get(Path(path).expanduser().resolve())
        if named is not None:
            return read_layout_file(named), named
        sidecar = sidecar_layout(path)
        return (read_layout_file(sidecar), sidecar) if sidecar is not None else (None, None)
    if isinstance(layout, str) and layout in SHIPPED_LAYOUTS:
        return dict(shipped_layout(layout), name=layout), None
    if isinstance(layout, Path) or (isinstance(layout, str) and layout.lower().endswith((".toml", ".json"))):
        return read_layout_file(layout), Path(layout)
    raise InvalidInputError("layout", layout, f"one of {sorted(SHIPPED_LAYOUTS)} or the path of a .toml/.json layout file")


def __getattr__(name: str) -> object:
    if name == "DIGIT_V3_STANDING_QPOS":  # read from the shipped layout on first use
        return tuple(float(x) for x in _shipped("digit_v3")["standing_qpos"])
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
