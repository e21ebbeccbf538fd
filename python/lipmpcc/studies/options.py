"""What a study is given and what it returns: :class:`RunOptions` (the CLI's options) and
:class:`RunResult` (the summary.json content, the figures and the run's own record)."""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import config
from ..exceptions import InvalidInputError
from ..models.lip3d import STEP_DURATION
from ..planners.presets import PlannerSettings, get_preset
from ..validation import count, finite_number, finite_vector, flag, number_in

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = [
    "DEFAULT_SEED",
    "WALKABLE_STEP_DURATION",
    "NOMINAL_STEP_DURATION",
    "REPLAN_HZ_RANGE",
    "PUSH_SETS",
    "PAPER_B_PUSHED_STEPS",
    "check_step_duration_range",
    "robot_step_duration",
    "check_replan_hz",
    "check_paper_b_steps",
    "option_flag",
    "parse_settings",
    "RunOptions",
    "RunResult",
    "jsonable",
]

DEFAULT_SEED = 0  # the seed of a run without --seed
WALKABLE_STEP_DURATION = (0.2, 1.0)  # [s] the step durations a robot walks (as a robot description's step_duration)
REPLAN_HZ_RANGE = (1.0, 1000.0)  # [Hz] the within-step re-planning rates --replan-hz accepts
PUSH_SETS = ("paper-a", "paper-b")  # circle-push's pushes: paper A's random series, paper B's four (walking frame)
#: the footsteps paper B's four pushes hit on the circle (0-based, one foot's): (full, fast) (studies.circle_pushes)
PAPER_B_PUSHED_STEPS = ((10, 26, 40, 56), (6, 14, 20, 28))
NOMINAL_STEP_DURATION = STEP_DURATION  # [s] the LIP MPCC presets' T, the nominal duration of the timed MPCC


def check_step_duration_range(value: object, nominal: float | None = NOMINAL_STEP_DURATION) -> tuple[float, float]:
    """``--step-duration-range TMIN TMAX`` [s] as two floats, checked: finite, 0 < TMIN <= TMAX, within
    :data:`WALKABLE_STEP_DURATION`, and containing the MPCC's nominal step duration ``nominal`` [s] (the
    duration the timed MPCC's cost pulls towards, :class:`~lipmpcc.planners.mpcc_timed.TimedMpccParams`:
    the robot's own ``step_duration``, :func:`robot_step_duration`), unless TMIN = TMAX: a fixed duration,
    which becomes the nominal (paper A's MPCC at that T). ``nominal`` None: not checked (the robot is not
    known yet: :class:`RunOptions`).

    Raises:
        InvalidInputError: naming ``--step-duration-range``, the value and what was expected.
    """
    name = "--step-duration-range"
    lo, hi = finite_vector(name, value, 2, "s")
    if lo <= 0.0 or hi <= 0.0:
        raise InvalidInputError(name, value, "step durations TMIN, TMAX > 0 [s]")
    if lo > hi:
        raise InvalidInputError(name, value, "TMIN <= TMAX [s]")
    a, b = WALKABLE_STEP_DURATION
    if lo < a or hi > b:
        raise InvalidInputError(name, value, f"a range within [{a:g}, {b:g}] s", "the step durations a robot walks")
    if nominal is not None and lo < hi and not lo <= nominal <= hi:
        raise InvalidInputError(name, value, f"a range that contains the MPCC's nominal step duration T = {nominal:g} s "
                                "(or TMIN = TMAX: a fixed duration)", "the robot's own step duration")
    return lo, hi


def robot_step_duration(robot: str | None) -> float:
    """The nominal step duration [s] of a run's MPCC on ``robot``: :data:`NOMINAL_STEP_DURATION` on the
    reduced models (``None``, ``lip``, ``alip``), a full body's own ``step_duration`` (its layout's)."""
    if robot is None or robot in ("lip", "alip"):
        return NOMINAL_STEP_DURATION
    from ..robots import load_robot

    return float(load_robot(robot).step_duration)


def check_paper_b_steps(steps: int, last_pushed: int) -> None:
    """``--steps`` with paper B's four pushes: the run must reach two steps past the last pushed footstep
    ``last_pushed`` (0-based; the step after the push is measured too).

    Raises:
        InvalidInputError: naming ``--steps``, the value and the least number of steps.
    """
    if steps < last_pushed + 3:
        raise InvalidInputError("--steps", steps, f"at least {last_pushed + 3} with --push-set paper-b",
                                f"its last push acts in footstep {last_pushed}")


def check_replan_hz(value: object) -> float:
    """``--replan-hz HZ`` as a float, checked: a finite rate in [:data:`REPLAN_HZ_RANGE`] [Hz] (paper B
    re-plans at 25 Hz; below 1 Hz a step of at most 1 s would never be re-planned within).

    Raises:
        InvalidInputError: naming ``--replan-hz``, the value and the range.
    """
    lo, hi = REPLAN_HZ_RANGE
    return number_in("--replan-hz", value, lo, hi, "Hz")


@dataclass(frozen=True)
class RunOptions:
    """Every option the CLI accepts; a study reads the ones it needs.

    ``None`` means "the study's default" (and "not given": :func:`lipmpcc.studies.check_options` refuses
    the options a scenario does not read). A study draws with :attr:`rng_seed`.
    """

    scenario: str
    planner: str | None = None
    robot: str | None = None
    obstacle_speed: float | None = None  # [m/s]
    path: str | None = None  # CSV of waypoints
    obstacles: str | None = None  # JSON list of obstacles
    steps: int | None = None
    seed: int | None = None  # None: DEFAULT_SEED
    out: str = "results"
    profile: str | None = None  # stepping-stone profile I..IV
    L: float | None = None  # [m] profile I step length
    W: float | None = None  # [m] profile I lateral offset
    stones: str | None = None  # CSV of stones
    video: bool = False
    duration: float | None = None  # [s]
    speed: float | None = None  # [m/s] commanded walking speed
    yaw_rate: float | None = None  # [rad/s] commanded yaw rate
    cop_range: tuple[float, float] | None = None  # [m] the ALIP-MPC's centre-of-pressure box (a foot)
    allow_long: bool = False  # run even when the estimated wall time is over the bound (studies.run_size)
    step_duration_range: tuple[float, float] | None = None  # [s] (TMIN, TMAX): the MPCC chooses each step's duration
    replan_hz: float | None = None  # [Hz] the timed MPCC re-planned within steps on the LIP (None: at exchanges)
    preset: str | None = None  # a planner preset (lipmpcc.planners.presets.PRESETS)
    set: dict[str, float] | None = None  # planner parameters by key (--set KEY=VALUE; planners.presets.SETTABLE)
    viewer: str | None = None  # live viewer: "realtime" or "fast" (studies.viewer)
    video_format: str | None = None  # "mp4" (the default) or "gif", with --video
    push_set: str | None = None  # circle-push's pushes: "paper-a" (random, the default) or "paper-b" (its four)
    layout: str | None = None  # the layout file of --robot PATH.xml (None: MODEL.lipmpcc.toml beside the model)
    extra: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Check the types (a study checks the ranges): a wrong one is an InvalidInputError naming the option."""
        if not isinstance(self.scenario, str):
            raise InvalidInputError("scenario", self.scenario, "a scenario name (text)")
        for name in ("planner", "robot", "path", "obstacles", "profile", "stones", "layout"):
            value = getattr(self, name)
            if value is not None and not isinstance(value, (str, PathLike)):
                raise InvalidInputError(f"--{name}", value, "text (a name or a file path) or None")
        if not isinstance(self.out, (str, PathLike)):
            raise InvalidInputError("--out", self.out, "a folder path")
        for name, unit in (("obstacle_speed", "m/s"), ("L", "m"), ("W", "m"), ("duration", "s"), ("speed", "m/s"),
                           ("yaw_rate", "rad/s")):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, finite_number(option_flag(name), getattr(self, name), unit))
        if self.steps is not None:
            object.__setattr__(self, "steps", count("--steps", self.steps, 1))
        if self.seed is not None:
            object.__setattr__(self, "seed", count("--seed", self.seed, 0))
        for name in ("video", "allow_long"):
            flag(option_flag(name), getattr(self, name))
        if self.cop_range is not None:
            object.__setattr__(self, "cop_range", finite_vector("--cop-range", self.cop_range, 2, "m"))
        if self.step_duration_range is not None:
            reduced = self.robot is None or self.robot in ("lip", "alip")  # a full body's T: check_options, from its layout
            object.__setattr__(self, "step_duration_range", check_step_duration_range(
                self.step_duration_range, NOMINAL_STEP_DURATION if reduced else None))
        if self.replan_hz is not None:
            object.__setattr__(self, "replan_hz", check_replan_hz(self.replan_hz))
        if self.preset is not None:
            get_preset(self.preset)  # an unknown name: the valid ones (the planner's are checked by check_options)
        if self.set is not None:
            object.__setattr__(self, "set", parse_settings(self.set))
        if self.viewer is not None and self.viewer not in ("realtime", "fast"):
            raise InvalidInputError("--viewer", self.viewer, "realtime (the default) or fast")
        if self.video_format is not None and self.video_format not in ("mp4", "gif"):
            raise InvalidInputError("--video-format", self.video_format, "mp4 or gif")
        if self.video_format is not None and not self.video:
            raise InvalidInputError("--video-format", self.video_format, "given with --video")
        if self.push_set is not None and self.push_set not in PUSH_SETS:
            raise InvalidInputError("--push-set", self.push_set, " or ".join(PUSH_SETS))
        if self.push_set == "paper-b" and self.steps is not None:
            check_paper_b_steps(self.steps, config.horizon(*PAPER_B_PUSHED_STEPS)[-1])
        if not isinstance(self.extra, dict):
            raise InvalidInputError("extra", self.extra, "a dict")

    @property
    def planner_settings(self) -> PlannerSettings:
        """``--preset`` and ``--set`` as a :class:`~lipmpcc.planners.presets.PlannerSettings`."""
        return PlannerSettings(self.preset, dict(self.set or {}))

    @property
    def rng_seed(self) -> int:
        """The seed the run uses: ``seed``, or :data:`DEFAULT_SEED` when not given."""
        return DEFAULT_SEED if self.seed is None else self.seed


def parse_settings(value: object) -> dict[str, float]:
    """``--set`` values as {key: number}: a mapping, or ``KEY=VALUE`` texts / (key, value) pairs (a key given
    twice: the last). The keys and ranges are the planner's to check (:func:`lipmpcc.planners.presets.check_settings`).

    Raises:
        InvalidInputError: not KEY=VALUE, or a value that is not a finite number (naming the key).
    """
    items: list[tuple[object, object]]
    if isinstance(value, dict):
        items = list(value.items())
    elif isinstance(value, (list, tuple)):
        items = []
        for item in value:
            if isinstance(item, str):
                key, eq, text = item.partition("=")
                if not eq or not key.strip():
                    raise InvalidInputError("--set", item, "KEY=VALUE (e.g. --set q_c=50)")
                items.append((key.strip(), text.strip()))
            elif isinstance(item, (list, tuple)) and len(item) == 2:
                items.append((item[0], item[1]))
            else:
                raise InvalidInputError("--set", item, "KEY=VALUE (e.g. --set q_c=50)")
    else:
        raise InvalidInputError("--set", value, "KEY=VALUE texts or a {key: value} dict")
    out: dict[str, float] = {}
    for key, v in items:
        if not isinstance(key, str) or not key:
            raise InvalidInputError("--set", key, "a parameter name (text)")
        try:
            number = float(v)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise InvalidInputError(f"--set {key}", v, "a finite number") from None
        if isinstance(v, bool) or not math.isfinite(number):
            raise InvalidInputError(f"--set {key}", v, "a finite number")
        out[key] = number
    return out


def option_flag(field_name: str) -> str:
    """The CLI flag of a RunOptions field: ``obstacle_speed`` -> ``--obstacle-speed``."""
    return "--" + field_name.replace("_", "-")


def jsonable(obj: Any) -> Any:
    """``obj`` with numpy scalars and arrays as plain Python values and non-finite floats as None."""
    if isinstance(obj, dict):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return jsonable(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (np.bool_,)):
        return bool(obj)
    return obj


@dataclass
class RunResult:
    """What a study returns.

    Attributes:
        summary: the content of ``summary.json`` (JSON values; numpy values are converted on saving).
        figures: name -> matplotlib figure, saved as ``NAME.png``.
        log: the run's own record (a :class:`~lipmpcc.loops.lip.LipLog`, an
            :class:`~lipmpcc.loops.alip.AlipLoopLog`, a full-body loop result or a study's run object).
        files: files the study wrote itself (a video).
        replay: a full-body run's replay (:class:`lipmpcc.studies.replay.RunReplay`), written by
            :meth:`save` as ``replay.npz``; None for the reduced models.
    """

    summary: dict[str, Any]
    figures: dict[str, Figure] = field(default_factory=dict)
    log: object = None
    files: list[Path] = field(default_factory=list)
    replay: Any = None

    def close_figures(self) -> None:
        """Close this result's figures in pyplot (for a run used only for its numbers: a reference run)."""
        if self.figures:
            import matplotlib.pyplot as plt

            for fig in self.figures.values():
                plt.close(fig)

    def save(self, out: str | Path) -> Path:
        """Write every figure (``NAME.png``, 110 dpi), a full-body run's ``replay.npz``, and then
        ``summary.json`` to the folder ``out``, close the figures, and return the path of ``summary.json``.

        ``summary.json`` comes last and through a file renamed over it: a figure that cannot be written
        leaves no new summary (the error goes on). ``lipmpcc run`` saves into a staging folder moved into
        place whole (:class:`lipmpcc.studies.outputs.StagedFolder`).
        """
        import matplotlib.pyplot as plt

        out = Path(out)
        try:
            out.mkdir(parents=True, exist_ok=True)
            for name, fig in self.figures.items():
                fig.savefig(out / f"{name}.png", dpi=110, bbox_inches="tight")
            if self.replay is not None:
                self.replay.save(out)
            tmp = out / ".summary.json.tmp"
            try:
                with open(tmp, "w") as f:
                    json.dump(jsonable(self.summary), f, indent=2, sort_keys=False)
                os.replace(tmp, out / "summary.json")
            finally:
                if tmp.exists():
                    tmp.unlink()
        finally:
            for fig in self.figures.values():
                plt.close(fig)
        return out / "summary.json"
