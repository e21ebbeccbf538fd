"""Which ``lipmpcc run`` options mean something for which scenario and robot, in one table.

:data:`APPLICABILITY` says, for every option of :class:`~lipmpcc.studies.options.RunOptions`, the
scenarios that read it and on which kind of robot: the reduced model (``--robot lip`` for paper A's
studies, ``alip`` for paper B's, their default) or a full body (``digit_like`` or ``PATH.xml``).
:data:`RULES` adds the options that a scenario reads only in some set-ups (``--seed`` draws the
stones of profiles II–IV only, ``--obstacle-speed`` moves the study's obstacle, not a file's).
:func:`check_options` refuses a given option that the run would ignore, with
:class:`OptionNotApplicableError`; :func:`options_help` prints the same table for ``lipmpcc run --help``.
:data:`NOT_YET` names the options that a robot kind does not read *yet* (the refusal says so).
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Mapping

from ..exceptions import InvalidInputError
from .options import RunOptions
from .options import option_flag as flag  # one definition, in options (below this module)

__all__ = [
    "REDUCED",
    "FULL",
    "SCENARIOS",
    "SCENARIO_ROBOTS",
    "EVERY_SCENARIO",
    "APPLICABILITY",
    "RULES",
    "NOT_YET",
    "REQUIRED",
    "DEFAULT_PLANNER",
    "PATH_FOLLOWING",
    "PAPER_A",
    "check_planner_settings",
    "hints",
    "Rule",
    "OptionNotApplicableError",
    "flag",
    "given_options",
    "robot_kind",
    "check_options",
    "options_help",
]

REDUCED = "reduced"  # the LIP (paper A's studies) or the ALIP (paper B's)
FULL = "full"  # a full-body robot: digit_like or a PATH.xml

PAPER_A = ("circle", "circle-push", "overtake")
PATH_FOLLOWING = PAPER_A + ("follow-path",)  # follow-path: the user's path (--path), the path-following weights
STEPPING = ("stones", "push")
WALKING = ("walk", "stand")
FIELD = ("stone-field",)  # issue 29: a path across a stone field with a pedestrian, on the ALIP
SCENARIOS = PATH_FOLLOWING + STEPPING + WALKING + FIELD

#: scenario -> the robot kinds it runs on, and the name of its reduced model (None: full body only)
SCENARIO_ROBOTS: dict[str, tuple[frozenset[str], str | None]] = {
    **{s: (frozenset({REDUCED, FULL}), "lip") for s in PATH_FOLLOWING},
    **{s: (frozenset({REDUCED, FULL}), "alip") for s in STEPPING},
    **{s: (frozenset({FULL}), None) for s in WALKING},
    **{s: (frozenset({REDUCED, FULL}), "alip") for s in FIELD},
}


def _on(scenarios: tuple[str, ...], kinds: frozenset[str] = frozenset({REDUCED, FULL})) -> dict[str, frozenset[str]]:
    return {s: kinds & SCENARIO_ROBOTS[s][0] for s in scenarios}


_FULL = frozenset({FULL})
_REDUCED = frozenset({REDUCED})
#: options every scenario reads, whatever the robot
EVERY_SCENARIO = ("robot", "out", "allow_long")

#: option (a RunOptions field) -> scenario -> the robot kinds on which the scenario reads it
APPLICABILITY: dict[str, dict[str, frozenset[str]]] = {
    "robot": _on(SCENARIOS),
    "out": _on(SCENARIOS),
    "allow_long": _on(SCENARIOS),  # every run has a length (studies.run_size)
    "planner": _on(PATH_FOLLOWING + STEPPING + ("walk",) + FIELD),  # stand runs no planner
    "path": _on(PATH_FOLLOWING),
    "obstacles": _on(PATH_FOLLOWING),
    "obstacle_speed": _on(("overtake", "stone-field")),  # the study's obstacle (stone-field: the pedestrian's speed)
    "steps": _on(PATH_FOLLOWING + STEPPING + ("walk",)),  # stand runs for --duration only
    "seed": _on(("circle-push", "stones", "stone-field")),  # paper A's random pushes; profiles II-IV (RULES); the field
    "profile": _on(("stones",)),
    "L": _on(("stones",)),
    "W": _on(("stones",)),
    "stones": _on(("stones",)),
    "cop_range": _on(STEPPING + FIELD),  # stone-field: the ALIP-MPC with a foot
    "duration": _on(PATH_FOLLOWING + WALKING, _FULL),  # the LIP/ALIP run --steps; full-body stones run the course
    "video": _on(SCENARIOS, _FULL),
    "video_format": _on(SCENARIOS, _FULL),
    "viewer": _on(PATH_FOLLOWING + STEPPING + WALKING, _FULL),  # stone-field on a full body: not yet
    "speed": _on(("walk",)),
    "yaw_rate": _on(("walk",)),
    "step_duration_range": _on(PATH_FOLLOWING),  # the timed MPCC: at exchanges on the LIP, at 25 Hz on a full body
    "replan_hz": _on(PATH_FOLLOWING, _REDUCED),  # the timed MPCC within steps on the LIP (a full body: always 25 Hz)
    "preset": _on(PATH_FOLLOWING + STEPPING),  # the MPCC's and the ALIP planners' presets (planners.presets)
    "set": _on(PATH_FOLLOWING + STEPPING),
    "push_set": _on(("circle-push", "stone-field")),  # paper A's random pushes or paper B's four
    # (studies.circle_pushes); stone-field: paper B's four only (studies.stone_field.field_pushes)
    "layout": _on(SCENARIOS, _FULL),  # --robot PATH.xml's layout file (checked and named in check_options)
}

#: scenario -> options it cannot run without
REQUIRED: dict[str, tuple[str, ...]] = {"follow-path": ("path",)}
#: scenario -> the planner it runs without --planner (the one --preset and --set are checked against)
DEFAULT_PLANNER: dict[str, str] = {**{s: "mpcc" for s in PATH_FOLLOWING}, **{s: "alip-mpc" for s in STEPPING}}

#: option -> (robot kind, note): the kind does not read the option (yet, or for the reason in the note, said in the refusal)
NOT_YET: dict[str, tuple[str, str]] = {
    "replan_hz": (FULL, "a full body always re-plans the timed MPCC at 25 Hz within steps"),
}


class OptionNotApplicableError(InvalidInputError):
    """An option was given that the scenario (with this robot or set-up) does not read.

    Attributes (besides :class:`~lipmpcc.exceptions.InvalidInputError`'s ``name``, ``value``, ``expected``):
        scenario: the scenario.
        context: the set-up that rules the option out (``" with --robot lip"``) or ``""``.
    """

    def __init__(self, name: str, value: object, scenario: str, applies_to: str, context: str = "") -> None:
        super().__init__(name, value, f"not given for scenario {scenario!r}{context}", f"it applies to: {applies_to}")
        self.scenario = scenario
        self.context = context
        self.args = (f"{name} does not apply to scenario {scenario!r}{context} (it applies to: {applies_to})",)

    def __str__(self) -> str:
        return str(self.args[0])


def _profile(opts: RunOptions) -> str:
    return str(opts.profile or "I").strip().upper()


def _seed_off(opts: RunOptions) -> str | None:
    if opts.stones is not None:
        return " with --stones"
    return " with profile I" if _profile(opts) == "I" else None


def _lw_off(opts: RunOptions) -> str | None:
    if opts.stones is not None:
        return " with --stones"
    p = _profile(opts)
    return f" with --profile {p}" if p in ("II", "III", "IV") else None  # a bad profile: the study says so


@dataclass(frozen=True)
class Rule:
    """An option that ``scenario`` reads only in some set-ups.

    Attributes:
        option: the RunOptions field.
        scenario: the scenario.
        off: the set-up in which the option is ignored, as a context (``" with --stones"``), or None.
        applies: where it applies within the scenario (``"with profile I"``, for the error and the help).
    """

    option: str
    scenario: str
    off: Callable[[RunOptions], str | None]
    applies: str


RULES: tuple[Rule, ...] = (
    Rule("seed", "stones", _seed_off, "with profile II-IV"),
    Rule("L", "stones", _lw_off, "with profile I"),
    Rule("W", "stones", _lw_off, "with profile I"),
    Rule("profile", "stones", lambda o: " with --stones" if o.stones is not None else None, "without --stones"),
    *(Rule("replan_hz", s, lambda o: " without --step-duration-range" if o.step_duration_range is None else None,
           "with --step-duration-range") for s in PATH_FOLLOWING),
    Rule("seed", "circle-push", lambda o: " with --push-set paper-b" if o.push_set == "paper-b" else None,
         "with --push-set paper-a"),
    Rule("push_set", "stone-field", lambda o: " with --push-set paper-a" if o.push_set == "paper-a" else None,
         "with --push-set paper-b"),
    Rule("obstacle_speed", "overtake", lambda o: " with --obstacles" if o.obstacles is not None else None,
         "without --obstacles"),
)


def given_options(opts: RunOptions) -> list[str]:
    """The options of :data:`APPLICABILITY` that ``opts`` sets (not None; ``video`` when True), but
    :data:`EVERY_SCENARIO`'s: every scenario reads them (their values are the studies' to check)."""
    out = []
    for option in APPLICABILITY:
        value = getattr(opts, option)
        if option in EVERY_SCENARIO:
            continue
        given = bool(value) if option == "video" else value is not None
        if given:
            out.append(option)
    return out


def robot_kind(scenario: str, robot: str | None) -> str:
    """:data:`REDUCED` when ``robot`` is the scenario's reduced model (None or ``""``: its default), else
    :data:`FULL` (a robot the scenario cannot run is the study's to refuse)."""
    reduced = SCENARIO_ROBOTS[scenario][1]
    if reduced is not None and (not robot or robot == reduced):
        return REDUCED
    return FULL


def _where(option: str) -> str:
    """Where ``option`` applies: ``"circle, overtake, walk on a full-body robot"``, ``"stones, push; walk"``."""
    where = {s: kinds for s, kinds in APPLICABILITY[option].items() if kinds}
    full_only = [s for s, kinds in where.items() if kinds == _FULL and SCENARIO_ROBOTS[s][1] is not None]
    groups: dict[str, list[str]] = {"any": [], "full": [], "reduced": []}
    for s in where:
        if s in full_only or (SCENARIO_ROBOTS[s][1] is None and full_only):  # walk/stand join the full-body group
            groups["full"].append(s)
        elif where[s] == _REDUCED:
            groups["reduced"].append(s)
        else:
            groups["any"].append(s)
    parts = [", ".join(_with_rule(option, s) for s in groups["any"])] if groups["any"] else []
    if groups["full"]:
        parts.append(", ".join(_with_rule(option, s) for s in groups["full"]) + " on a full-body robot")
    if groups["reduced"]:
        parts.append(", ".join(_with_rule(option, s) for s in groups["reduced"]) + " on the reduced model")
    return "; ".join(parts)


def _with_rule(option: str, scenario: str) -> str:
    rule = next((r for r in RULES if r.option == option and r.scenario == scenario), None)
    return scenario if rule is None else f"{scenario} {rule.applies}"


def _use_layout(opts: RunOptions) -> None:
    """Name ``opts.layout`` as the layout of ``opts.robot`` (a robot file, or a scene that includes one)."""
    from ..robots.layouts import use_layout
    from ..robots.mjcf import robot_in_scene

    robot = str(opts.robot or "")
    if not robot.lower().endswith(".xml"):
        raise InvalidInputError("--layout", str(opts.layout), "only with --robot PATH.xml (your model's layout file)")
    model = Path(robot).expanduser()
    if model.is_file():
        model = robot_in_scene(model) or model
    use_layout(model, opts.layout)


def check_options(opts: RunOptions) -> None:
    """Refuse every option given in ``opts`` that ``opts.scenario`` does not read with its robot and set-up.

    A ``--layout`` given is checked and named for ``--robot PATH.xml`` for the rest of the process
    (:func:`~lipmpcc.robots.layouts.use_layout`).

    Raises:
        InvalidInputError: the scenario is not a registered one, a text option is empty, or ``--layout`` is given
            without ``--robot PATH.xml`` or is not an existing layout file.
        ViewerUnavailableError: ``--viewer`` without a display (:func:`lipmpcc.studies.viewer.check_display`).
        OptionNotApplicableError: one line naming the first such option, the scenario and where it applies.
    """
    scenario = opts.scenario
    if scenario not in SCENARIO_ROBOTS:
        raise InvalidInputError("scenario", scenario, f"one of {', '.join(SCENARIOS)}")
    for option in ("planner", "robot", "path", "obstacles", "profile", "stones"):
        value = getattr(opts, option)
        if isinstance(value, str) and not value.strip():
            raise InvalidInputError(flag(option), value, "a non-empty value (leave the option out for the default)")
    kind = robot_kind(scenario, opts.robot)
    for option in given_options(opts):
        kinds = APPLICABILITY[option].get(scenario, frozenset())
        value = getattr(opts, option)
        if not kinds:
            raise OptionNotApplicableError(flag(option), value, scenario, _where(option))
        if kind not in kinds:
            robot = opts.robot or SCENARIO_ROBOTS[scenario][1]
            later = NOT_YET.get(option)
            note = f" ({later[1]})" if later is not None and later[0] == kind else ""
            raise OptionNotApplicableError(flag(option), value, scenario, _where(option), f" with --robot {robot}{note}")
        for rule in RULES:
            off = rule.off(opts) if (rule.option, rule.scenario) == (option, scenario) else None
            if off is not None:
                raise OptionNotApplicableError(flag(option), value, scenario, _where(option), off)
    if opts.layout is not None:
        _use_layout(opts)
    for option in REQUIRED.get(scenario, ()):
        if getattr(opts, option) is None:
            raise InvalidInputError(flag(option), None, f"{flag(option)} FILE: scenario {scenario!r} needs one",
                                    "a CSV of waypoints; sample: data/examples/my_waypoints.csv" if option == "path" else "")
    if opts.viewer is not None:  # before the run: a viewer that cannot open is a usage error
        from .viewer import check_display

        check_display()
    check_planner_settings(opts)
    if opts.step_duration_range is not None:  # judged against the robot's own nominal step duration
        from .options import check_step_duration_range, robot_step_duration

        check_step_duration_range(opts.step_duration_range, robot_step_duration(opts.robot))


def check_planner_settings(opts: RunOptions) -> None:
    """``--preset`` and ``--set`` checked against the run's planner (``--planner`` or the scenario's
    :data:`DEFAULT_PLANNER`): a preset of its family, known keys, values in range, and parameters its class
    accepts together (e.g. delta_min < delta_max; the class is imported only when one is given).

    Raises:
        InvalidInputError: naming the preset or the key and listing the valid ones.
    """
    settings = opts.planner_settings
    if not settings.given or opts.scenario not in DEFAULT_PLANNER:
        return
    from ..planners.presets import PLANNER_FAMILY

    planner = opts.planner or DEFAULT_PLANNER[opts.scenario]
    family = PLANNER_FAMILY.get(planner)
    if family is None:  # a planner of another scenario: the study names its own planners
        return
    settings.apply(_default_params(family), planner)


def _default_params(family: str) -> object:
    if family == "mpcc":
        from ..planners.mpcc import MpccParams

        return MpccParams()
    if family == "alip-mpc":
        from ..planners.alip_mpc import AlipMpcParams

        return AlipMpcParams.paper()
    from ..planners.alip_qp import AlipQpParams

    return AlipQpParams.paper()


def hints(opts: RunOptions) -> list[str]:
    """One-line hints for a run that works but may not do what its user meant (the CLI prints them on
    stderr): ``overtake --path`` follows the path with the overtaking weights, which cut bends (``circle
    --path`` has the path-following weights: no hint)."""
    if opts.path is None or opts.planner_settings.given or (opts.planner or "mpcc") != "mpcc":
        return []
    if opts.scenario == "overtake":
        return ["overtake --path follows your path with the overtaking weights (contouring weight 1), which cut "
                "bends; for path following use 'lipmpcc run follow-path --path FILE' (or --preset circle)"]
    return []  # circle --path: the path-following weights already (follow-path titles its figures for it)

def _scenario_line(scenario: str, notes: Mapping[str, str]) -> str:
    kinds, reduced = SCENARIO_ROBOTS[scenario]
    common, full = [], []
    for option, where in APPLICABILITY.items():
        if option in EVERY_SCENARIO or not where.get(scenario):
            continue
        text = flag(option) + notes.get(f"{option}/{scenario}", "")
        if where[scenario] == _REDUCED and reduced is not None:
            text += f" (--robot {reduced} only)"
        (common if REDUCED in where[scenario] or reduced is None else full).append(text)
    line = " ".join(common) or "-"
    if full:
        line += "; on a full body also: " + " ".join(full)
    robots = f"--robot {reduced} (default) | digit_like | PATH.xml" if reduced else "--robot digit_like (default) | PATH.xml"
    indent = " " * 17
    return f"  {scenario:<13}  {robots}\n" + textwrap.fill(line, width=100, initial_indent=indent, subsequent_indent=indent,
                                                                     break_on_hyphens=False)


def options_help() -> str:
    """The table of :data:`APPLICABILITY` and :data:`RULES`, one scenario per entry (``lipmpcc run --help``)."""
    notes = {f"{r.option}/{r.scenario}": f" ({r.applies})" for r in RULES}
    notes.update({f"{option}/{scenario}": " (required)" for scenario, options in REQUIRED.items() for option in options})
    lines = ["options by scenario (every scenario also takes --out, --replace and --allow-long; any other option is "
             "refused):"]
    lines += [_scenario_line(s, notes) for s in SCENARIOS]
    return "\n".join(lines)
