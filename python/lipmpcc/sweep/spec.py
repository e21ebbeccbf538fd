"""Sweep specifications: a TOML file naming a study, the planners to compare and the axes to vary, expanded
into plain, seeded, reproducible cases.

A specification (``data/sweeps/*.toml``; every key below is checked, any other is refused)::

    name = "push grid"                  # free text
    study = "push"                      # a `lipmpcc run` scenario
    robot = "alip"                      # lip | alip | digit_like | PATH.xml (default: the study's reduced model)
    planners = ["alip-qp", { label = "alip-mpc foot", planner = "alip-mpc", cop_range = [0.05, 0.02] }]
    seed = 7                            # seeds the random draws (default 0)
    draws = 20                          # number of random draws (needed when an axis is random)
    timeout_s = 600                     # optional: a case running longer is stopped, recorded "timeout"

    [options]                           # fixed `lipmpcc run` options (RunOptions fields), e.g.
    steps = 12

    [axes]                              # each axis: one value, a grid, or random draws
    impulse = { unit = "N*s", values = [5, 10, 15] }
    direction = { unit = "deg", range = [0, 315], n = 8 }
    onset = { unit = "fraction", value = 0.3 }
    seed = { random = [0, 999] }

An axis is ``{value = x}``, ``{values = [...]}``, ``{range = [a, b], n = k}`` (k evenly spaced values, ends
included) or ``{random = [low, high]}`` (uniform; integers for integer axes; one value per draw, drawn from
``seed``). The grid axes form a product; the random axes vary together over ``draws`` draws; every
planner runs every point. :data:`AXES` lists the axes, their units and what they set.

Pushes (``circle-push`` and ``push`` only; they replace the study's pushes): either ``push_scale`` (the
study's own pushes, forces scaled: paper A's random series seeded by ``seed``, paper B's four pushes) or one
push per case given by its magnitude (``force`` [N], ``impulse`` [N·s] = force × duration, or
``weight_fraction``, of the robot's weight m·g), ``direction`` (world frame, 0 = +x, the walking direction at
the start), ``duration`` (default 0.1 s), and its timing: ``onset`` after the touch-down that starts footstep
``push_step`` (in s, or as a ``fraction`` of the nominal step duration), or ``push_time``, the run time [s].

Every case is a plain dict (study, robot, planner, options, parameters, fast mode): a worker rebuilds the run
from it through :func:`lipmpcc.studies.run`, the code path of ``lipmpcc run``. A case's id is the hash of that
dict; the specification's hash (:attr:`SweepSpec.hash`) guards a results store against a changed campaign.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import tomllib
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .. import config, studies
from ..exceptions import InvalidInputError
from ..studies.applicability import SCENARIO_ROBOTS
from ..studies.run_size import format_seconds

__all__ = [
    "AXES",
    "PUSH_STUDIES",
    "AxisDef",
    "Axis",
    "Planner",
    "SweepSpec",
    "MAX_CASES",
    "MAX_CPU_S",
    "MAX_AXIS_VALUES",
    "SweepSize",
    "sweep_size",
    "load_spec",
    "parse_spec",
    "canonical_json",
    "digest",
]

PUSH_STUDIES = ("circle-push", "push", "stone-field")  # the studies whose pushes a sweep may replace
MAX_CASES = 100_000  # a sweep of more cases is refused without allow_long (--allow-long)
MAX_CPU_S = 7 * 24 * 3600.0  # [s] a sweep estimated at more CPU time (all its cases on one core) is refused likewise
MAX_AXIS_VALUES = 1_000_000  # an axis's range with more values (n) is refused (its values would not fit in memory)
#: the RunOptions fields that name a file, and the reader that checks it
_FILE_OPTIONS = ("path", "obstacles", "stones")


@dataclass(frozen=True)
class AxisDef:
    """One kind of axis.

    Attributes:
        units: unit -> factor to the SI unit stored (the first unit is the default).
        kind: ``"float"``, ``"int"`` or ``"str"``.
        option: the RunOptions field it sets, or None (a push parameter).
        doc: what it means.
    """

    units: dict[str, float]
    kind: str = "float"
    option: str | None = None
    doc: str = ""


_NONE = {"1": 1.0}
#: axis name -> its definition
AXES: dict[str, AxisDef] = {
    "force": AxisDef({"N": 1.0}, doc="push magnitude [N]"),
    "impulse": AxisDef({"N*s": 1.0, "N s": 1.0, "Ns": 1.0}, doc="push impulse = force x duration [N s]"),
    "weight_fraction": AxisDef(_NONE, doc="push magnitude as a fraction of the robot's weight m g"),
    "direction": AxisDef({"rad": 1.0, "deg": math.pi / 180.0}, doc="push direction, world frame, 0 = +x [rad]"),
    "duration": AxisDef({"s": 1.0}, doc="push duration [s] (default 0.1 s)"),
    "onset": AxisDef({"s": 1.0, "fraction": 1.0}, doc="push start after the touch-down of push_step [s or fraction]"),
    "push_time": AxisDef({"s": 1.0}, doc="push start, run time [s]"),
    "push_step": AxisDef({"step": 1.0}, "int", doc="the footstep pushed (0-based, counted from the run's start)"),
    "push_scale": AxisDef(_NONE, doc="the study's own pushes, forces multiplied by this"),
    "push_set": AxisDef(_NONE, "str", option="push_set",
                        doc="circle-push's pushes: paper-a (random, seeded) or paper-b (its four, walking frame)"),
    "obstacle_speed": AxisDef({"m/s": 1.0}, option="obstacle_speed", doc="the obstacle's speed [m/s] (overtake)"),
    "seed": AxisDef(_NONE, "int", option="seed", doc="the run's seed (paper A's pushes, stone profiles II-IV)"),
    "profile": AxisDef(_NONE, "str", option="profile", doc="stone profile I..IV (stones)"),
    "L": AxisDef({"m": 1.0}, option="L", doc="profile I step length [m]"),
    "W": AxisDef({"m": 1.0}, option="W", doc="profile I lateral offset [m]"),
    "steps": AxisDef(_NONE, "int", option="steps", doc="steps / stones walked"),
    "duration_run": AxisDef({"s": 1.0}, option="duration", doc="full-body run duration [s]"),
    "robot": AxisDef(_NONE, "str", doc="the robot (lip, alip, digit_like or PATH.xml)"),
}
_MAGNITUDES = ("force", "impulse", "weight_fraction")
_SINGLE_PUSH = _MAGNITUDES + ("direction", "duration", "onset", "push_time", "push_step")
_TOP_KEYS = ("name", "study", "robot", "planners", "seed", "draws", "timeout_s", "options", "axes")
_AXIS_KEYS = ("unit", "value", "values", "range", "n", "random")
_OPTION_FIELDS = tuple(f.name for f in fields(studies.RunOptions) if f.name not in ("scenario", "out", "video", "extra"))


def canonical_json(obj: Any) -> str:
    """``obj`` as JSON with sorted keys and no spaces (what the hashes are taken of)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False)


def digest(obj: Any, n: int = 16) -> str:
    """The first ``n`` hex digits of the SHA-256 of :func:`canonical_json` of ``obj``."""
    return hashlib.sha256(canonical_json(obj).encode()).hexdigest()[:n]


def _finite(name: str, v: Any, kind: str) -> Any:
    """``v`` checked for an axis of ``kind`` (NaN, inf, bools and wrong types refused)."""
    if kind == "str":
        if not isinstance(v, str) or not v:
            raise InvalidInputError(name, v, "a non-empty string")
        return v
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise InvalidInputError(name, v, "a number" if kind == "float" else "an integer")
    if not math.isfinite(float(v)):
        raise InvalidInputError(name, v, "a finite number")
    if kind == "int":
        if float(v) != int(v):
            raise InvalidInputError(name, v, "an integer")
        return int(v)
    return float(v)


@dataclass(frozen=True)
class Axis:
    """One axis of a sweep: its name, unit, and grid values (SI) or random bounds (SI).

    Attributes:
        name: a key of :data:`AXES`.
        unit: the unit the file gave (values are stored converted to SI).
        values: the grid's values, or () for a random axis.
        random: (low, high) of a random axis (SI), or None.
    """

    name: str
    unit: str
    values: tuple[Any, ...] = ()
    random: tuple[float, float] | None = None

    @property
    def is_random(self) -> bool:
        """True for an axis drawn at random."""
        return self.random is not None

    def draw(self, rng: np.random.Generator, n: int) -> list[Any]:
        """``n`` uniform draws within :attr:`random` (integers, both ends included, for an integer axis)."""
        assert self.random is not None
        lo, hi = self.random
        if AXES[self.name].kind == "int":
            return [int(x) for x in rng.integers(int(lo), int(hi) + 1, size=n)]
        return [float(x) for x in rng.uniform(lo, hi, size=n)]


def _grid(where: str, table: Mapping[str, Any], kind: str, factor: float) -> tuple[Any, ...]:
    """The grid values of an axis table (``value``, ``values`` or ``range`` + ``n``), in SI."""
    given = [k for k in ("value", "values", "range", "random") if k in table]
    if len(given) != 1:
        raise InvalidInputError(where, dict(table), "exactly one of value, values, range (with n) or random")
    if "value" in table:
        raw = [table["value"]]
    elif "values" in table:
        raw = table["values"]
        if not isinstance(raw, list) or not raw:
            raise InvalidInputError(f"{where}.values", raw, "a non-empty list")
    else:
        r, n = table["range"], table.get("n")
        if not isinstance(r, list) or len(r) != 2:
            raise InvalidInputError(f"{where}.range", r, "[low, high]")
        lo, hi = (_finite(f"{where}.range", x, "float") for x in r)
        n = _finite(f"{where}.n", n, "int") if n is not None else None
        if n is None or n < 1 or hi < lo or (n > 1 and hi == lo):
            raise InvalidInputError(f"{where}.range", (r, n), "low <= high with n >= 1 values (an empty range)")
        if n > MAX_AXIS_VALUES:
            raise InvalidInputError(f"{where}.n", n, f"at most {MAX_AXIS_VALUES} values on one axis")
        raw = np.linspace(lo, hi, n).tolist()
        if kind == "int":
            raw = sorted(set(int(round(x)) for x in raw))
    vals = [_finite(f"{where}.value", v, kind) for v in raw]
    if kind == "float":
        return tuple(float(v) * factor for v in vals)
    return tuple(vals)


def _parse_axis(name: str, table: Any) -> Axis:
    where = f"axes.{name}"
    if name not in AXES:
        raise InvalidInputError("axes", name, f"one of {', '.join(AXES)}")
    d = AXES[name]
    if not isinstance(table, dict):
        table = {"value": table}
    bad = [k for k in table if k not in _AXIS_KEYS]
    if bad:
        raise InvalidInputError(f"{where}.{bad[0]}", table[bad[0]], f"one of the keys {', '.join(_AXIS_KEYS)}")
    unit = table.get("unit", next(iter(d.units)))
    if unit not in d.units:
        raise InvalidInputError(f"{where}.unit", unit, f"one of {', '.join(repr(u) for u in d.units)}")
    factor = d.units[unit]
    if "random" in table:
        r = table["random"]
        if d.kind == "str" or not isinstance(r, list) or len(r) != 2 or len(table.keys() - {"random", "unit"}):
            raise InvalidInputError(f"{where}.random", r, "[low, high] alone, on a numeric axis")
        lo, hi = (_finite(f"{where}.random", x, "float") for x in r)
        if not hi > lo:
            raise InvalidInputError(f"{where}.random", r, "low < high (an empty range)")
        return Axis(name, unit, (), (lo * factor, hi * factor))
    if "n" in table and "range" not in table:
        raise InvalidInputError(f"{where}.n", table["n"], "n only with range")
    return Axis(name, unit, _grid(where, table, d.kind, factor))


@dataclass(frozen=True)
class Planner:
    """A planner under comparison: its label in the results, the study's planner name, and the
    ``lipmpcc run`` options it adds (e.g. ``cop_range``)."""

    label: str
    planner: str
    options: dict[str, Any] = field(default_factory=dict)


def _parse_planner(entry: Any, i: int) -> Planner:
    where = f"planners[{i}]"
    if isinstance(entry, str) and entry:
        return Planner(entry, entry)
    if not isinstance(entry, dict) or not isinstance(entry.get("planner"), str):
        raise InvalidInputError(where, entry, "a planner name or a table with planner = NAME (label, options)")
    label = entry.get("label", entry["planner"])
    if not isinstance(label, str) or not label:
        raise InvalidInputError(f"{where}.label", label, "a non-empty string")
    opts = {k: v for k, v in entry.items() if k not in ("label", "planner")}
    return Planner(label, entry["planner"], _check_options(f"{where}", opts))


def _check_options(where: str, opts: Any) -> dict[str, Any]:
    if not isinstance(opts, dict):
        raise InvalidInputError(where, opts, "a table of lipmpcc run options")
    for k, v in opts.items():
        if k not in _OPTION_FIELDS:
            raise InvalidInputError(f"{where}.{k}", v, f"a lipmpcc run option: {', '.join(_OPTION_FIELDS)}")
        for x in v if isinstance(v, list) else [v]:
            if isinstance(x, float) and not math.isfinite(x):
                raise InvalidInputError(f"{where}.{k}", v, "finite numbers")
    return {k: (tuple(v) if isinstance(v, list) else v) for k, v in opts.items()}


@dataclass(frozen=True)
class SweepSpec:
    """A parsed, validated sweep (:func:`parse_spec`).

    Attributes:
        name, study, robot: the campaign's name, the scenario and the robot (default for the robot axis).
        planners: the planners compared.
        axes: the axes, in the file's order.
        seed, draws: the seed of the random draws and their number.
        options: fixed ``lipmpcc run`` options.
        raw: the file's content (what :attr:`hash` is taken of, with the fast mode).
        fast: the fast mode the cases run in (``LIPMPCC_FAST``, when the spec was parsed).
    """

    name: str
    study: str
    robot: str
    planners: tuple[Planner, ...]
    axes: tuple[Axis, ...]
    seed: int
    draws: int
    options: dict[str, Any]
    raw: dict[str, Any]
    fast: bool
    timeout_s: float | None = None  # [s] per case; None: no limit

    @property
    def hash(self) -> str:
        """The campaign's identity: the hash of the file's content and the fast mode."""
        return digest({"spec": self.raw, "fast": self.fast})

    @property
    def axis_names(self) -> list[str]:
        """The axes' names."""
        return [a.name for a in self.axes]

    def points(self) -> list[dict[str, Any]]:
        """Every point of the axes (SI values): the grid's product, times the random draws."""
        grid = [a for a in self.axes if not a.is_random]
        rand = [a for a in self.axes if a.is_random]
        rng = np.random.default_rng(self.seed)
        draws = {a.name: a.draw(rng, self.draws) for a in rand}
        out = []
        for combo in itertools.product(*(a.values for a in grid)):
            base = dict(zip((a.name for a in grid), combo))
            for i in range(self.draws if rand else 1):
                out.append({**base, **{name: v[i] for name, v in draws.items()}})
        return out

    def cases(self) -> list[dict[str, Any]]:
        """Every case: one per point and planner, a plain dict with its ``id`` (the hash of the rest)."""
        out = []
        for point in self.points():
            for pl in self.planners:
                case = {"study": self.study, "robot": point.get("robot", self.robot), "planner": pl.label,
                        "planner_name": pl.planner, "options": {**self.options, **pl.options, **_as_options(point)},
                        "params": {k: v for k, v in point.items() if k != "robot"},
                        "units": {a.name: a.unit for a in self.axes}, "fast": self.fast}
                if self.timeout_s is not None:  # only when given: the ids of specs without it are unchanged
                    case["timeout_s"] = self.timeout_s
                case = json.loads(canonical_json(case))  # plain JSON values (tuples -> lists)
                case["id"] = digest(case)
                case["index"] = len(out)
                out.append(case)
        return out


def _as_options(point: dict[str, Any]) -> dict[str, Any]:
    """The RunOptions fields set by a point's axes (``seed``, ``obstacle_speed``, ``profile``, ...)."""
    return {AXES[k].option: v for k, v in point.items() if AXES[k].option is not None}


def load_spec(path: str | Path, allow_long: bool = False, robot: str | None = None) -> SweepSpec:
    """Read and validate a sweep specification (TOML); a name under ``data/sweeps/`` (without ``.toml``)
    is found there. ``allow_long``: as :func:`parse_spec`. ``robot`` (``lipmpcc sweep --robot``) replaces the
    file's ``robot`` (its name then says so, and the campaign's :attr:`~SweepSpec.hash` is another: its own store).

    Raises:
        InvalidInputError: the file is missing, not TOML, or a bad entry (one line naming it); ``robot`` with
            a specification that has a ``robot`` axis.
        RunTooLongError: a sweep over :data:`MAX_CASES` cases or :data:`MAX_CPU_S` (without ``allow_long``).
    """
    if not isinstance(path, (str, Path)) or not str(path).strip():
        raise InvalidInputError("sweep spec", path, "the path of a TOML file (or a name in data/sweeps)")
    p = Path(path)
    if not p.exists() and p.suffix == "" and not p.parent.parts:
        from ..resources import data_path

        p = data_path("sweeps", f"{p.name}.toml")
    if not p.is_file():
        raise InvalidInputError("sweep spec", str(path), "an existing TOML file (or a name in data/sweeps)")
    try:
        raw = tomllib.loads(p.read_text())
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise InvalidInputError("sweep spec", str(path), "a TOML file", str(exc).splitlines()[0]) from None
    if robot is not None:
        if "robot" in (raw.get("axes") or {}):
            raise InvalidInputError("--robot", robot, "no --robot with a specification that sweeps the robot (axes.robot)")
        label = Path(robot).stem if str(robot).lower().endswith(".xml") else str(robot)
        raw = {**raw, "robot": str(robot), "name": f"{raw.get('name', raw.get('study'))} [on {label}]"}
    return parse_spec(raw, allow_long=allow_long)


def parse_spec(raw: Mapping[str, Any], allow_long: bool = False) -> SweepSpec:
    """Validate a specification's content (a dict as read from TOML), the files it names (``path``,
    ``obstacles``, ``stones``, a robot's MJCF: each read as a run would), its size (:func:`sweep_size`,
    before any case is built) and every case it expands to.

    Args:
        raw: the specification's content.
        allow_long: accept a sweep over :data:`MAX_CASES` cases or :data:`MAX_CPU_S` of estimated CPU time.

    Raises:
        InvalidInputError: the first bad entry (unknown key, study, planner, axis or unit, NaN, an empty
            range, an option or push the study does not read, a file that is missing or unreadable),
            named in one line.
        RunTooLongError: the sweep is too big (the message gives the count and the estimate).
    """
    if not isinstance(raw, Mapping):
        raise InvalidInputError("sweep spec", raw, "a table (dict) of name, study, planners, options, axes, ...")
    raw = dict(raw)
    for k in raw:
        if k not in _TOP_KEYS:
            raise InvalidInputError(k, raw[k], f"one of the keys {', '.join(_TOP_KEYS)}")
    study = raw.get("study")
    if study not in studies.names():
        raise InvalidInputError("study", study, f"one of {', '.join(studies.names())}")
    robot = raw.get("robot", SCENARIO_ROBOTS[study][1] or "digit_like")
    _finite("robot", robot, "str")
    planners_raw = raw.get("planners", [])
    if not isinstance(planners_raw, list) or not planners_raw:
        raise InvalidInputError("planners", planners_raw, "a non-empty list of planners")
    planners = tuple(_parse_planner(e, i) for i, e in enumerate(planners_raw))
    if len({p.label for p in planners}) != len(planners):
        raise InvalidInputError("planners", [p.label for p in planners], "distinct labels")
    axes_raw = raw.get("axes", {})
    if not isinstance(axes_raw, dict):
        raise InvalidInputError("axes", axes_raw, "a table of axes")
    axes = tuple(_parse_axis(n, t) for n, t in axes_raw.items())
    seed = _finite("seed", raw.get("seed", 0), "int")
    draws = _finite("draws", raw.get("draws", 0), "int")
    if any(a.is_random for a in axes) and draws < 1:
        raise InvalidInputError("draws", draws, "a number of draws >= 1 (an axis is random)")
    name = raw.get("name", study)
    timeout = raw.get("timeout_s")
    if timeout is not None:
        timeout = _finite("timeout_s", timeout, "float")
        if timeout <= 0:
            raise InvalidInputError("timeout_s", timeout, "a time limit per case > 0 [s]")
    spec = SweepSpec(str(name), study, robot, planners, axes, seed, draws, _check_options("options", raw.get("options", {})),
                     json.loads(canonical_json(raw)), config.fast_mode(), timeout)
    _check_pushes(spec)
    _check_files(spec)
    size = sweep_size(spec)
    if not allow_long and (size.cases > MAX_CASES or size.cpu_s > MAX_CPU_S):
        from ..exceptions import RunTooLongError

        raise RunTooLongError("sweep", f"{size.cases} cases", f"at most {MAX_CASES} cases and "
                              f"{format_seconds(MAX_CPU_S)} of CPU time", f"{size.describe()}; pass --allow-long "
                              "(allow_long=True) to run it anyway", wall_s=size.cpu_s, bound_s=MAX_CPU_S)
    _check_cases(spec)
    return spec


@dataclass(frozen=True)
class SweepSize:
    """A sweep's size, counted before it is expanded.

    Attributes:
        cases: the number of cases (points x planners).
        cpu_s: their estimated CPU time [s] (each case on one core: :func:`lipmpcc.studies.estimate_run_size`
            of each planner's first case, times the points).
    """

    cases: int
    cpu_s: float

    def describe(self, workers: int = 1) -> str:
        """``"N cases, about T of CPU time"`` (and the wall time on ``workers`` processes when more than one)."""
        text = f"{self.cases} cases, about {format_seconds(self.cpu_s)} of CPU time"
        if workers > 1:
            text += f" (about {format_seconds(self.cpu_s / workers)} on {workers} workers)"
        return text


def sweep_size(spec: SweepSpec) -> SweepSize:
    """The number of cases of ``spec`` and their estimated CPU time, without expanding the grid."""
    points = math.prod(len(a.values) for a in spec.axes if not a.is_random)
    if any(a.is_random for a in spec.axes):
        points *= spec.draws
    first = SweepSpec(spec.name, spec.study, spec.robot, spec.planners,
                      tuple(a if a.is_random else Axis(a.name, a.unit, a.values[:1]) for a in spec.axes),
                      spec.seed, min(spec.draws, 1), spec.options, spec.raw, spec.fast, spec.timeout_s)
    from .worker import case_options

    per_planner = []
    for case in first.cases():
        try:
            per_planner.append(studies.estimate_run_size(case_options(case, with_pushes=False)).wall_s)
        except Exception:  # noqa: BLE001 - a case the study will refuse: _check_cases names it
            per_planner.append(0.0)
    cpu = points * float(np.mean(per_planner)) * len(spec.planners) if per_planner else 0.0
    return SweepSize(points * len(spec.planners), cpu)


def _check_files(spec: SweepSpec) -> None:
    """Every file the spec's options and planners name, read as the study reads it (:data:`_FILE_OPTIONS`)."""
    from ..obstacles import obstacles_from_json
    from ..paths import load_path_csv
    from ..terrain import load_stones

    for where, opts in [("options", spec.options)] + [(f"planners[{p.label!r}]", p.options) for p in spec.planners]:
        for key in _FILE_OPTIONS:
            value = opts.get(key)
            if value is None:
                continue
            if not isinstance(value, str) or not value.strip():
                raise InvalidInputError(f"{where}.{key}", value, "the path of an existing file")
            if not Path(value).is_file():
                raise InvalidInputError(f"{where}.{key}", value, "an existing file", "no such file")
            try:
                if key == "path":
                    load_path_csv(value)
                elif key == "stones":
                    load_stones(value)
                else:
                    from ..studies.path_scenarios import study_path

                    path_file = opts.get("path", spec.options.get("path"))
                    obstacles_from_json(value, load_path_csv(path_file) if path_file else study_path(spec.study))
            except InvalidInputError as exc:
                raise InvalidInputError(f"{where}.{key}", value, "a file the study can read", str(exc)) from None


def _paper_b_pushes(spec: SweepSpec) -> bool:
    """True when some case of ``spec`` runs ``circle-push`` with paper B's four pushes (option or axis)."""
    if spec.options.get("push_set") == "paper-b":
        return True
    return any("paper-b" in [str(v) for v in a.values] for a in spec.axes if a.name == "push_set")


def _check_pushes(spec: SweepSpec) -> None:
    """The push axes: only for :data:`PUSH_STUDIES`, one magnitude, one timing, not mixed with push_scale."""
    names = set(spec.axis_names)
    pushy = names & set(_SINGLE_PUSH + ("push_scale",))
    if pushy and spec.study not in PUSH_STUDIES:
        raise InvalidInputError(f"axes.{sorted(pushy)[0]}", spec.study, f"a push axis only with study {' or '.join(PUSH_STUDIES)}")
    single = names & set(_SINGLE_PUSH)
    if single and _paper_b_pushes(spec):
        raise InvalidInputError(f"axes.{sorted(single)[0]}", "push_set = paper-b",
                                "either paper B's four pushes (push_set) or one push (force ...), not both")
    if "push_scale" in names and single:
        raise InvalidInputError(f"axes.{sorted(single)[0]}", "push_scale", "either push_scale or one push (force ...), not both")
    mags = names & set(_MAGNITUDES)
    if single and len(mags) != 1:
        raise InvalidInputError("axes", sorted(mags) or sorted(single), "exactly one push magnitude: force, impulse or weight_fraction")
    if {"onset", "push_time"} <= names:
        raise InvalidInputError("axes.push_time", "onset", "either onset (after a touch-down) or push_time, not both")
    if "push_step" in names and "push_time" in names:
        raise InvalidInputError("axes.push_step", "push_time", "push_step only with onset")
    for a in spec.axes:
        low = min(a.values) if a.values else a.random[0]  # type: ignore[index]
        if a.name in _MAGNITUDES + ("duration", "push_scale", "onset", "push_time", "push_step", "obstacle_speed") and low < 0:
            raise InvalidInputError(f"axes.{a.name}", low, "values >= 0")
        if a.name == "duration" and low <= 0:
            raise InvalidInputError("axes.duration", low, "a push duration > 0 [s]")


def _check_cases(spec: SweepSpec) -> None:
    """Every case's options through the study's own check (:func:`lipmpcc.studies.check_options`), its
    planner against the study's, its robot against the study's."""
    import sys

    module = sys.modules[studies.get(spec.study).__module__]
    known = getattr(module, "PLANNERS", None)
    for pl in spec.planners:
        if known is not None and pl.planner not in known:
            raise InvalidInputError(f"planners[{pl.label!r}]", pl.planner, f"one of {', '.join(known)} for {spec.study}")
    robots = next((a.values for a in spec.axes if a.name == "robot"), (spec.robot,))
    reduced = SCENARIO_ROBOTS[spec.study][1]
    for robot in robots:
        if robot not in (reduced, "digit_like") and not str(robot).lower().endswith(".xml"):
            raise InvalidInputError("robot", robot, f"{reduced + ', ' if reduced else ''}digit_like or a PATH.xml for {spec.study}")
        if str(robot).lower().endswith(".xml") and not Path(robot).is_file():
            raise InvalidInputError("robot", robot, "an existing MJCF file")
        if "onset" in spec.axis_names and spec.study == "circle-push" and robot != reduced:
            raise InvalidInputError("axes.onset", robot, "push_time on a full body (its path-following loop times pushes "
                                    "from the run's start)")
    from .worker import case_options

    for case in spec.cases():
        studies.check_options(case_options(case, with_pushes=False))
