"""Scenarios: one named study each, run by ``lipmpcc run NAME``.

A scenario is a function ``run(options: RunOptions) -> RunResult``. It is
registered here by name with the module that holds it; modules are imported
lazily so that one scenario's heavy dependencies never slow down another's.

Modules:
    path_following  -- paper A on the LIP: ``circle``, ``circle-push``, ``overtake``
    stepping_stones -- paper B on the ALIP: ``stones``, ``push``
    walking         -- full-body walking without an MPC: ``walk``, ``stand``
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from ..exceptions import InvalidInputError


@dataclass(frozen=True)
class RunOptions:
    """Every option the CLI accepts; a scenario reads the ones it needs.

    ``None`` means "the scenario's default".
    """

    scenario: str
    planner: str | None = None
    robot: str | None = None
    obstacle_speed: float | None = None  # [m/s]
    path: str | None = None  # CSV of waypoints
    obstacles: str | None = None  # JSON list of obstacles
    steps: int | None = None
    seed: int = 0
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
    extra: dict[str, Any] = field(default_factory=dict)


@dataclass
class RunResult:
    """What a scenario returns: the summary.json content, figures and raw logs."""

    summary: dict[str, Any]
    figures: dict[str, Any] = field(default_factory=dict)  # name -> matplotlib Figure
    log: Any = None
    files: list[Path] = field(default_factory=list)


# name -> (module, function)
_REGISTRY: dict[str, tuple[str, str]] = {
    "circle": ("path_following", "run_circle"),
    "circle-push": ("path_following", "run_circle_push"),
    "overtake": ("path_following", "run_overtake"),
    "stones": ("stepping_stones", "run_stones"),
    "push": ("stepping_stones", "run_push"),
    "walk": ("walking", "run_walk"),
    "stand": ("walking", "run_stand"),
}


def names() -> list[str]:
    """Registered scenario names."""
    return list(_REGISTRY)


def get(name: str) -> Callable[[RunOptions], RunResult]:
    """The run function of scenario ``name``."""
    if name not in _REGISTRY:
        raise InvalidInputError("scenario", name, f"one of {', '.join(_REGISTRY)}")
    module, func = _REGISTRY[name]
    mod = importlib.import_module(f"{__name__}.{module}")
    return getattr(mod, func)


def run(options: RunOptions) -> RunResult:
    """Run a scenario by name."""
    return get(options.scenario)(options)
