"""The planners' named presets and the parameters a user may set by name (``lipmpcc run --preset/--set``).

:data:`PRESETS` names the papers' parameter sets: paper A's three MPCC presets (``circle``,
``overtake``, ``cartesian``, the values of :meth:`~lipmpcc.planners.mpcc.MpccParams.circle` and its
siblings, which read them from here) and paper B's ALIP-MPC and ALIP-QP parameters (``paper-b``,
``paper-b-qp``: the classes' defaults). :data:`SETTABLE` names, for each planner family, the weights and
bounds that ``--set KEY=VALUE`` may change, each with its parameter field, unit and accepted range.

:class:`PlannerSettings` holds a run's choice (a preset name, the values set); :meth:`PlannerSettings.apply`
turns a planner's parameters into the effective ones. This module imports no planner (it is read to
build ``lipmpcc run --help``): the parameter classes are given to it.

Families (the planners that read a family's parameters):

- ``mpcc``: :class:`~lipmpcc.planners.mpcc.MpccParams`, for ``--planner mpcc`` and ``cartesian``
  (the Cartesian MPC is the MPCC with Q̄ = W̄ = 200 I).
- ``alip-mpc``: :class:`~lipmpcc.planners.alip_mpc.AlipMpcParams`.
- ``alip-qp``: :class:`~lipmpcc.planners.alip_qp.AlipQpParams`.
"""

from __future__ import annotations

import dataclasses
import math
import textwrap
from dataclasses import dataclass, field
from typing import Any, Mapping

from ..exceptions import InvalidInputError

__all__ = [
    "FAMILIES",
    "PLANNER_FAMILY",
    "MPCC_PRESET_FIELDS",
    "Preset",
    "PRESETS",
    "Settable",
    "SETTABLE",
    "PlannerSettings",
    "preset_names",
    "get_preset",
    "check_preset",
    "check_settings",
    "params_dict",
    "presets_help",
]

#: family -> the ``--planner`` names that read its parameters
FAMILIES: dict[str, tuple[str, ...]] = {"mpcc": ("mpcc", "cartesian"), "alip-mpc": ("alip-mpc",), "alip-qp": ("alip-qp",)}
#: ``--planner`` name -> its family
PLANNER_FAMILY: dict[str, str] = {p: fam for fam, planners in FAMILIES.items() for p in planners}

#: paper A's MPCC presets: the fields each sets on :class:`~lipmpcc.planners.mpcc.MpccParams` (Q̄, W̄ [1/m²], ρ)
MPCC_PRESET_FIELDS: dict[str, dict[str, Any]] = {
    "circle": {"Q_bar": (300.0, 3.0), "W_bar": (300.0, 3.0), "rho": 10.0},
    "overtake": {"Q_bar": (1.0, 1000.0), "W_bar": (1.0, 1000.0), "rho": 50.0},
    "cartesian": {"Q_bar": (200.0, 200.0), "W_bar": (200.0, 200.0), "rho": 50.0},
}


@dataclass(frozen=True)
class Preset:
    """A named parameter set of one planner family.

    Attributes:
        name: the ``--preset`` name.
        family: the planner family (:data:`FAMILIES`).
        fields: the parameter fields it sets over the run's own parameters ({}: the class defaults).
        source: where it comes from (a paper section).
        doc: what it is for, in one line.
    """

    name: str
    family: str
    fields: Mapping[str, Any]
    source: str
    doc: str

    def describe(self) -> str:
        """``Q_bar=(300, 3) W_bar=(300, 3) rho=10`` (the fields it sets), or the defaults' summary."""
        if not self.fields:
            return "the class defaults"
        return " ".join(f"{k}={_short(v)}" for k, v in self.fields.items())


def _short(v: Any) -> str:
    if isinstance(v, tuple):
        return "(" + ", ".join(f"{x:g}" for x in v) + ")"
    return f"{v:g}" if isinstance(v, float) else str(v)


PRESETS: dict[str, Preset] = {
    "circle": Preset("circle", "mpcc", MPCC_PRESET_FIELDS["circle"], "paper A §IV-A",
                     "contouring-accurate path following (circle, circle-push and follow-path)"),
    "overtake": Preset("overtake", "mpcc", MPCC_PRESET_FIELDS["overtake"], "paper A §IV-B(b)",
                       "overtaking: contouring weight 1 lets the robot leave the path (it cuts bends)"),
    "cartesian": Preset("cartesian", "mpcc", MPCC_PRESET_FIELDS["cartesian"], "paper A §IV-B(a)",
                        "the Cartesian MPC's weights (Q = W = 200 I): tracks a point moving along the path"),
    "paper-b": Preset("paper-b", "alip-mpc", {}, "paper B §V",
                      "N=4, T in [0.35, 0.65] s (0.5), alpha_z = alpha_u = (1e4, 2e4), alpha_sigma=1, beta=10"),
    "paper-b-qp": Preset("paper-b-qp", "alip-qp", {}, "paper B §V, Khadiv's QP",
                         "paper B's limits and durations, weights u 10, tau 1, b 1000, slacks 1e6"),
}


@dataclass(frozen=True)
class Settable:
    """A parameter that ``--set KEY=VALUE`` changes.

    Attributes:
        key: the name after ``--set``.
        field: the parameter field (``"Q_bar"``), or a nested one (``"limits.x_max"``).
        index: the element(s) of a tuple field it sets (None: the whole field).
        lo, hi: the accepted range [unit], inclusive unless ``open_lo`` / ``open_hi``.
        unit: the unit (``""``: none).
        integer: an integer value.
        doc: what it is.
    """

    key: str
    field: str
    index: tuple[int, ...] | None
    lo: float
    hi: float
    unit: str
    doc: str
    integer: bool = False
    open_lo: bool = False
    open_hi: bool = False

    def range_text(self) -> str:
        """``[0, 1e+06] 1/m²`` or ``(0, 1)``."""
        text = f"{'(' if self.open_lo else '['}{self.lo:g}, {self.hi:g}{')' if self.open_hi else ']'}"
        return text + (f" {self.unit}" if self.unit else "") + (" (an integer)" if self.integer else "")

    def check(self, value: object) -> float | int:
        """``value`` as a number within the range.

        Raises:
            InvalidInputError: naming ``--set KEY``, the value and the range.
        """
        name = f"--set {self.key}"
        expected = f"a finite number in {self.range_text()}"
        try:
            v = float(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise InvalidInputError(name, value, expected) from None
        if isinstance(value, bool) or not math.isfinite(v):
            raise InvalidInputError(name, value, expected)
        below = v <= self.lo if self.open_lo else v < self.lo
        above = v >= self.hi if self.open_hi else v > self.hi
        if below or above or (self.integer and not v.is_integer()):
            raise InvalidInputError(name, value, expected)
        return int(v) if self.integer else v


_W = 1e6  # the largest weight accepted
_MPCC: tuple[Settable, ...] = (
    Settable("q_c", "Q_bar", (0,), 0.0, _W, "1/m²", "running contouring weight (Q̄ contouring)"),
    Settable("q_l", "Q_bar", (1,), 0.0, _W, "1/m²", "running lag weight (Q̄ lag)"),
    Settable("w_c", "W_bar", (0,), 0.0, _W, "1/m²", "terminal contouring weight (W̄ contouring)"),
    Settable("w_l", "W_bar", (1,), 0.0, _W, "1/m²", "terminal lag weight (W̄ lag)"),
    Settable("r_x", "R", (0,), 0.0, _W, "1/m²", "input weight on the forward foot offset uˣ"),
    Settable("r_y", "R", (1,), 0.0, _W, "1/m²", "input weight on the lateral foot offset uʸ"),
    Settable("r_theta", "R", (2,), 0.0, _W, "1/rad²", "input weight on the heading change u^θ"),
    Settable("heading_weight", "heading_weight", None, 0.0, _W, "", "weight of the heading error to the path"),
    Settable("l_nom", "lateral_nominal", None, 0.0, 1.0, "m", "lateral foot offset the weight r_y is measured from"),
    Settable("rho", "rho", None, 0.0, 1e4, "", "progress reward ρ (per metre of progress)"),
    Settable("v_max", "v_max", None, 0.0, 1.0, "m", "largest path progress per step", open_lo=True),
    Settable("delta_min", "delta_min", None, 0.0, 1.0, "m", "least COM distance per step (< delta_max)", open_hi=True),
    Settable("delta_max", "delta_max", None, 0.0, 1.0, "m", "largest COM distance per step", open_lo=True),
    Settable("gamma", "gamma", None, 0.0, 1.0, "", "CBF decay rate γ", open_lo=True, open_hi=True),
    Settable("N", "N", None, 1.0, 20.0, "steps", "horizon", integer=True),
    Settable("robot_radius", "robot_radius", None, 0.0, 1.0, "m", "radius of the body disk around the COM"),
    Settable("obstacle_margin", "obstacle_margin", None, 0.0, 0.5, "m", "extra inflation of the obstacles"),
)
_ALIP_STEP: tuple[Settable, ...] = (
    Settable("T_nom", "T_nom", None, 0.2, 1.0, "s", "nominal step duration (T_min <= T_nom <= T_max)"),
    Settable("T_min", "T_min", None, 0.2, 1.0, "s", "shortest step duration"),
    Settable("T_max", "T_max", None, 0.2, 1.0, "s", "longest step duration"),
    Settable("w", "w", None, 0.0, 0.5, "m", "nominal step width", open_lo=True),
    Settable("x_max", "limits.x_max", None, 0.0, 1.0, "m", "largest forward/backward step", open_lo=True),
    Settable("y_min", "limits.y_min", None, 0.0, 1.0, "m", "least lateral distance between the feet (< y_max)"),
    Settable("y_max", "limits.y_max", None, 0.0, 1.0, "m", "largest lateral distance between the feet", open_lo=True),
)
_ALIP_MPC: tuple[Settable, ...] = (
    Settable("horizon", "horizon", None, 1.0, 20.0, "steps", "number of future steps N", integer=True),
    *_ALIP_STEP,
    Settable("alpha_z_x", "alpha_z", (0,), 0.0, 1e9, "", "weight on the initial DCM, x", open_lo=True),
    Settable("alpha_z_y", "alpha_z", (1,), 0.0, 1e9, "", "weight on the initial DCM, y", open_lo=True),
    Settable("alpha_u_x", "alpha_u", (0,), 0.0, 1e9, "", "weight on the foothold, x", open_lo=True),
    Settable("alpha_u_y", "alpha_u", (1,), 0.0, 1e9, "", "weight on the foothold, y", open_lo=True),
    Settable("alpha_sigma", "alpha_sigma", None, 0.0, 1e9, "", "weight on sigma (the step duration)", open_lo=True),
    Settable("beta_base", "beta_base", None, 0.0, 1e3, "", "stage weights beta^k = beta_base^(N-k)", open_lo=True),
    Settable("alpha_cop_x", "alpha_cop", (0,), 0.0, 1e9, "1/m²", "weight on the centre-of-pressure offset, x", open_lo=True),
    Settable("alpha_cop_y", "alpha_cop", (1,), 0.0, 1e9, "1/m²", "weight on the centre-of-pressure offset, y", open_lo=True),
)
_ALIP_QP: tuple[Settable, ...] = (
    *_ALIP_STEP,
    Settable("u_x", "weights", (0,), 0.0, 1e9, "", "weight on the foothold, x", open_lo=True),
    Settable("u_y", "weights", (1,), 0.0, 1e9, "", "weight on the foothold, y", open_lo=True),
    Settable("tau", "weights", (2,), 0.0, 1e9, "", "weight on the step timing", open_lo=True),
    Settable("b_x", "weights", (3,), 0.0, 1e9, "", "weight on the DCM offset, x", open_lo=True),
    Settable("b_y", "weights", (4,), 0.0, 1e9, "", "weight on the DCM offset, y", open_lo=True),
    Settable("slack", "weights", (5, 6, 7, 8), 0.0, 1e12, "", "weight on the four slacks", open_lo=True),
)
#: family -> key -> :class:`Settable`
SETTABLE: dict[str, dict[str, Settable]] = {
    "mpcc": {s.key: s for s in _MPCC},
    "alip-mpc": {s.key: s for s in _ALIP_MPC},
    "alip-qp": {s.key: s for s in _ALIP_QP},
}


def preset_names(family: str | None = None) -> list[str]:
    """The preset names (of ``family`` only, when given)."""
    return [n for n, p in PRESETS.items() if family is None or p.family == family]


def get_preset(name: str) -> Preset:
    """The preset ``name``.

    Raises:
        InvalidInputError: naming ``--preset`` and listing the valid names.
    """
    if not isinstance(name, str) or name not in PRESETS:
        raise InvalidInputError("--preset", name, f"one of {', '.join(PRESETS)}")
    return PRESETS[name]


def check_preset(name: str, planner: str) -> Preset:
    """The preset ``name``, checked against ``--planner planner`` (its family).

    Raises:
        InvalidInputError: an unknown name, or a preset of another planner family (naming the valid ones).
    """
    preset = get_preset(name)
    family = PLANNER_FAMILY.get(planner)
    if family is None:
        raise InvalidInputError("--planner", planner, f"a planner with presets: {', '.join(PLANNER_FAMILY)}")
    if preset.family != family:
        raise InvalidInputError("--preset", name, f"a preset of --planner {planner}: {', '.join(preset_names(family))}",
                                f"{name!r} is a preset of {preset.family}")
    return preset


def check_settings(values: Mapping[str, object], planner: str) -> dict[str, float | int]:
    """``--set`` values checked for ``--planner planner``: known keys, numbers within their ranges.

    Raises:
        InvalidInputError: an unknown key (listing the planner's keys), or a bad value (naming it).
    """
    family = PLANNER_FAMILY.get(planner)
    if family is None:
        raise InvalidInputError("--planner", planner, f"a planner whose parameters --set changes: {', '.join(PLANNER_FAMILY)}")
    keys = SETTABLE[family]
    out: dict[str, float | int] = {}
    for key, value in values.items():
        if key not in keys:
            raise InvalidInputError("--set", key, f"a parameter of --planner {planner}: {', '.join(keys)}")
        out[key] = keys[key].check(value)
    return out


def _updates(params: Any, values: Mapping[str, float | int], keys: Mapping[str, Settable]) -> dict[str, Any]:
    """The top-level fields of ``params`` that ``values`` change, with their new values (a nested field,
    ``"limits.x_max"``, as the keyword arguments of its dataclass)."""
    updates: dict[str, Any] = {}
    for key, value in values.items():
        s = keys[key]
        head, _, sub = s.field.partition(".")
        if sub:
            updates.setdefault(head, {})[sub] = float(value)
        elif s.index is not None:
            items = list(updates.get(head, getattr(params, head)))
            for i in s.index:
                items[i] = float(value)
            updates[head] = tuple(items)
        else:
            updates[head] = value if s.integer else float(value)
    return updates


@dataclass(frozen=True)
class PlannerSettings:
    """A run's planner choice from the CLI: a preset and values set by key.

    Attributes:
        preset: a :data:`PRESETS` name, or None (the study's own parameters).
        values: key -> value (:data:`SETTABLE`), applied after the preset.
    """

    preset: str | None = None
    values: Mapping[str, float | int] = field(default_factory=dict)

    @property
    def given(self) -> bool:
        """True when a preset or a value was given (else :meth:`apply` returns its argument unchanged)."""
        return self.preset is not None or bool(self.values)

    def apply(self, params: Any, planner: str) -> Any:
        """The effective parameters: ``params`` (a study's) with the preset's fields, then the values set.
        The result is built by the parameter class, which checks it (e.g. delta_min < delta_max).

        Raises:
            InvalidInputError: a preset or key that ``planner`` does not read, a bad value, or parameters the
                class refuses (named as ``--set`` / ``--preset``).
        """
        if not self.given:
            return params
        out = params
        if self.preset is not None:
            out = _replace_checked(out, "--preset", self.preset, check_preset(self.preset, planner).fields)
        values = check_settings(self.values, planner)
        if not values:
            return out
        updates = _updates(out, values, SETTABLE[PLANNER_FAMILY[planner]])
        given = " ".join(f"{k}={v:g}" for k, v in values.items())
        for head, v in updates.items():
            if isinstance(v, dict):
                updates[head] = _replace_checked(getattr(out, head), "--set", given, v)
        return _replace_checked(out, "--set", given, updates)


def _replace_checked(params: Any, name: str, value: object, fields: Mapping[str, Any]) -> Any:
    """``dataclasses.replace(params, **fields)``; the class's refusal as an error naming the option ``name``."""
    try:
        return dataclasses.replace(params, **fields)
    except InvalidInputError as exc:
        raise InvalidInputError(name, value, "parameters the planner accepts", str(exc)) from None


def params_dict(params: Any) -> dict[str, Any]:
    """A parameter dataclass as a JSON-ready dict (nested dataclasses as dicts, tuples as lists)."""
    def plain(v: Any) -> Any:
        if isinstance(v, dict):
            return {k: plain(x) for k, x in v.items()}
        if isinstance(v, (tuple, list)):
            return [plain(x) for x in v]
        return v

    return plain(dataclasses.asdict(params))


def presets_help(width: int = 100) -> str:
    """The presets and the keys of ``--set``, for ``lipmpcc run --help``."""
    lines = ["planner presets (--preset NAME; the study's own without it):"]
    for p in PRESETS.values():
        lines.append(textwrap.fill(f"{p.name:<11} {p.family}: {p.describe()}. {p.source}: {p.doc}", width=width,
                                   initial_indent="  ", subsequent_indent=" " * 14))
    lines.append("planner parameters (--set KEY=VALUE, repeated; after the preset):")
    for family, keys in SETTABLE.items():
        text = f"{family}: " + ", ".join(f"{s.key} {s.range_text()}" for s in keys.values())
        lines.append(textwrap.fill(text, width=width, initial_indent="  ", subsequent_indent="    "))
    return "\n".join(lines)
