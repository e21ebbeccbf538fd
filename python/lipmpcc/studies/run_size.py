"""How long a run will take, estimated before it starts, and the bound past which it is refused.

:func:`estimate_run_size` turns a run's options into its length (steps on the reduced models,
simulated seconds on a full body) and an estimated wall time from rough measured rates
(:data:`REDUCED_S_PER_STEP`, :data:`FULL_S_PER_SIM_S`; one core of a 2020s laptop, with a margin of
about 2: the LIP's MPCC takes 0.01-0.03 s a step, the ALIP-MPC 0.03 s, ``digit_like`` runs 4-6 times
faster than real time). :func:`check_run_size` refuses a run estimated over :data:`MAX_WALL_S` with
:class:`~lipmpcc.exceptions.RunTooLongError` naming the estimate and the bound, unless
``RunOptions.allow_long`` (``lipmpcc run --allow-long``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import config
from ..exceptions import RunTooLongError
from .applicability import FULL, PATH_FOLLOWING, REDUCED, robot_kind
from .options import RunOptions

__all__ = [
    "MAX_WALL_S",
    "NOTICE_WALL_S",
    "REDUCED_S_PER_STEP",
    "FULL_S_PER_SIM_S",
    "FULL_SETUP_S",
    "UNREADABLE_PATH_M",
    "RunSize",
    "PAPER_B_PUSH_RUNS",
    "format_seconds",
    "estimate_run_size",
    "check_run_size",
]

MAX_WALL_S = 3600.0  # [s] a run estimated longer is refused without --allow-long
NOTICE_WALL_S = 60.0  # [s] the CLI says how long a run estimated longer will take
#: [s of wall time per step] on the reduced models (measured 0.007-0.03 s; margin 2)
REDUCED_S_PER_STEP = {"circle": 0.05, "circle-push": 0.05, "overtake": 0.05, "follow-path": 0.05, "stones": 0.06,
                      "push": 0.06, "stone-field": 0.06}
FULL_S_PER_SIM_S = 0.5  # [s of wall time per simulated s] on a full body (measured 0.16-0.25 on digit_like)
FULL_SETUP_S = 5.0  # [s] loading and compiling a full-body model
FULL_SIM_S_PER_STEP = 0.5  # [s] simulated time of a step on a full body (0.35-0.65 s; the loop's bound: 1 s)
FULL_SIM_S_START = 2.0  # [s] simulated time before the first step
STAND_DEFAULT_S = 5.0  # [s] stand's default --duration
WALK_DEFAULT_S = (20.0, 6.0)  # [s] walk's default --duration (full, fast)
PAPER_B_PUSH_RUNS = 4.0  # circle-push --push-set paper-b: the reference, the pushed run and three shorter runs (~2)
UNREADABLE_PATH_M = 20.0  # [m] follow-path's length estimate when --path cannot be read (the study refuses it)


@dataclass(frozen=True)
class RunSize:
    """A run's length and estimated wall time.

    Attributes:
        scenario: the scenario.
        kind: :data:`~lipmpcc.studies.applicability.REDUCED` or :data:`~lipmpcc.studies.applicability.FULL`.
        amount: the run's length in ``unit``.
        unit: ``"steps"`` (reduced models) or ``"simulated s"`` (full body).
        option: the option that sets the length (``"--steps"``, ``"--duration"``), ``""`` for the study's default.
        value: that option's value (None for the default).
        wall_s: the estimated wall time [s].
        rate: wall seconds per step or per simulated second.
    """

    scenario: str
    kind: str
    amount: float
    unit: str
    option: str
    value: object
    wall_s: float
    rate: float

    def describe(self) -> str:
        """``"about 1.4 h: 10000 simulated s at ~0.5 s of wall time per simulated s"``."""
        per = "step" if self.unit == "steps" else "simulated s"
        return f"about {format_seconds(self.wall_s)}: {self.amount:.6g} {self.unit} at ~{self.rate:g} s of wall time per {per}"


def format_seconds(s: float) -> str:
    """A duration [s] in the largest fitting unit: ``"42 s"``, ``"3.5 min"``, ``"2.1 h"``, ``"4 days"``,
    ``"3.2e+07 years"``."""
    if not math.isfinite(s):
        return "forever"
    for unit, size in (("years", 365.25 * 86400.0), ("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if s >= size:
            v = s / size
            text = f"{v:.1f}".removesuffix(".0") if v < 100 else (f"{v:.0f}" if v < 1e6 else f"{v:.1e}")
            return f"{text} {unit}"
    return f"{s:.0f} s"


def _stones(opts: RunOptions) -> float:
    """The stones walked in ``stones``/``push``: those of ``--stones`` (walked to its end), else the profile's."""
    from ..terrain import N_STONES, load_stones

    if getattr(opts, "stones", None):
        try:
            return float(len(load_stones(opts.stones)))
        except Exception:  # noqa: BLE001 - the study reports the file's error
            return float(N_STONES)
    return float(N_STONES)


def _reduced_steps(opts: RunOptions) -> float:
    if opts.steps is not None:
        return float(opts.steps)
    from ..terrain import N_APPROACH

    if opts.scenario == "follow-path":
        from .path_scenarios import follow_path_steps

        return float(follow_path_steps(_path_length(opts)))
    if opts.scenario in PATH_FOLLOWING:
        from .path_scenarios import LIP_STEPS

        return float(config.horizon(*LIP_STEPS[opts.scenario]))
    return _stones(opts) + N_APPROACH


def _path_length(opts: RunOptions) -> float:
    """The length [m] of ``--path`` (a path that cannot be read: :data:`UNREADABLE_PATH_M`; the study says why)."""
    from ..paths import load_path_csv

    try:
        return float(load_path_csv(opts.path).length) if opts.path else UNREADABLE_PATH_M
    except Exception:  # noqa: BLE001 - the study reports the file's error
        return UNREADABLE_PATH_M


def _full_sim_s(opts: RunOptions) -> float:
    """Simulated seconds of a full-body run: ``--duration`` or ``--steps`` (:data:`FULL_SIM_S_PER_STEP`
    each), whichever ends first, else the study's default."""
    if opts.scenario in ("stones", "push"):
        from ..terrain import N_APPROACH

        n = float(opts.steps) if opts.steps is not None else _stones(opts)
        return FULL_SIM_S_START + FULL_SIM_S_PER_STEP * (n + N_APPROACH + 2)  # 2: the exit steps
    by_steps = None if opts.steps is None else FULL_SIM_S_START + FULL_SIM_S_PER_STEP * float(opts.steps)
    if opts.duration is not None:
        d = float(opts.duration)
        return d if by_steps is None else min(d, by_steps)
    if by_steps is not None:
        return by_steps
    if opts.scenario == "stand":
        return STAND_DEFAULT_S
    if opts.scenario == "walk":
        return float(config.horizon(*WALK_DEFAULT_S))
    if opts.scenario == "follow-path":
        from .path_scenarios import follow_path_duration

        return follow_path_duration(_path_length(opts))
    from .path_scenarios import DEFAULT_DURATION

    key = opts.scenario if opts.scenario.startswith("circle") else f"overtake-{opts.planner or 'mpcc'}"
    return float(config.horizon(*DEFAULT_DURATION.get(key, DEFAULT_DURATION["overtake-mpcc"])))


def _length_option(opts: RunOptions) -> tuple[str, object]:
    if opts.duration is not None:
        return "--duration", opts.duration
    if opts.steps is not None:
        return "--steps", opts.steps
    return "", None


def estimate_run_size(opts: RunOptions) -> RunSize:
    """The length and the estimated wall time of the run ``opts`` (nothing is run; the options are
    assumed checked by :func:`~lipmpcc.studies.applicability.check_options`)."""
    option, value = _length_option(opts)
    runs = PAPER_B_PUSH_RUNS if getattr(opts, "push_set", None) == "paper-b" else 1.0
    if robot_kind(opts.scenario, opts.robot) == REDUCED:
        rate = runs * REDUCED_S_PER_STEP.get(opts.scenario, 0.06)
        steps = _reduced_steps(opts)
        return RunSize(opts.scenario, REDUCED, steps, "steps", "--steps" if opts.steps is not None else "",
                       opts.steps, steps * rate, rate)
    sim_s = _full_sim_s(opts)
    return RunSize(opts.scenario, FULL, sim_s, "simulated s", option, value,
                   runs * (FULL_SETUP_S + sim_s * FULL_S_PER_SIM_S), runs * FULL_S_PER_SIM_S)


def check_run_size(opts: RunOptions, max_wall_s: float = MAX_WALL_S) -> RunSize:
    """:func:`estimate_run_size`, refused when over ``max_wall_s`` [s] unless ``opts.allow_long``.

    Raises:
        RunTooLongError: one line naming the option, the estimate and the bound, and ``--allow-long``.
    """
    size = estimate_run_size(opts)
    if size.wall_s > max_wall_s and not getattr(opts, "allow_long", False):
        raise RunTooLongError(
            size.option or "run length", size.value if size.option else f"{size.amount:g} {size.unit}",
            f"a run of at most {format_seconds(max_wall_s)} of wall time",
            f"this one would take {size.describe()}; pass --allow-long to run it anyway",
            wall_s=size.wall_s, bound_s=max_wall_s,
        )
    return size
