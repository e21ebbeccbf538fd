"""Studies: one named experiment each, run by ``lipmpcc run NAME`` (and all of them by ``lipmpcc reproduce``).

A study is a function ``run(options: RunOptions) -> RunResult``, registered here by name with the module
that holds it. The robot is an option: one module per study runs it on the reduced model or on a full
body. Modules are imported lazily, so that one study's heavy dependencies never slow down another's.

Modules::

    path_following  -- paper A: ``circle``, ``circle-push``, ``overtake``; ``follow-path`` (LIP or full body)
    stepping_stones -- paper B: ``stones``, ``push`` (ALIP or full body)
    walking         -- full-body walking without an MPC: ``walk``, ``stand``
    stone_field     -- beyond both papers: ``stone-field``, a path across a stone field with a pedestrian (ALIP)
    paper           -- the papers' reported numbers (``data/reference/paper_results.json``)
    options         -- :class:`RunOptions` (what the CLI fills), :class:`RunResult` (what a study returns) and
                       :func:`run_outcome` (completed, trailing, stalled, incomplete, fell, collided or stopped
                       early; :func:`is_success`: completed or trailing, never an unknown outcome)
    applicability   -- which options each scenario reads, with which robot (:func:`check_options`)
    run_size        -- a run's estimated wall time, refused over a bound (:func:`check_run_size`)
    outputs         -- output folders written whole or not at all, locked, with ``failed.json`` on failure
    video           -- videos and frames of full-body runs
    replay          -- a full-body run's ``replay.npz``, replayed in the viewer or to a video (``lipmpcc replay``)
    viewer          -- the live viewer of ``--viewer`` (MuJoCo's passive viewer, refreshed from the loop)
    outcome         -- how a run ended: collided, fell, stopped early or completed (summary fields)
    clearance       -- the whole robot's clearance to the obstacles, from its MuJoCo geometry
"""

from __future__ import annotations

import importlib
from typing import Callable

from ..exceptions import InvalidInputError
from .applicability import OptionNotApplicableError, check_options, hints, options_help
from .options import RunOptions, RunResult
from .outcome import OUTCOMES, is_expected, is_success, run_outcome
from .run_size import RunSize, check_run_size, estimate_run_size

__all__ = ["RunOptions", "RunResult", "OptionNotApplicableError", "check_options", "hints", "options_help", "names", "get", "run",
           "OUTCOMES", "run_outcome", "is_expected", "is_success", "RunSize", "check_run_size", "estimate_run_size"]

# name -> (module, function)
_REGISTRY: dict[str, tuple[str, str]] = {
    "circle": ("path_following", "run_circle"),
    "circle-push": ("circle_pushes", "run_circle_push_study"),
    "overtake": ("path_following", "run_overtake"),
    "follow-path": ("path_following", "run_follow_path"),
    "stones": ("stepping_stones", "run_stones"),
    "push": ("stepping_stones", "run_push"),
    "walk": ("walking", "run_walk"),
    "stand": ("walking", "run_stand"),
    "stone-field": ("stone_field", "run_stone_field"),
}


def names() -> list[str]:
    """Registered study names."""
    return list(_REGISTRY)


def get(name: str) -> Callable[[RunOptions], RunResult]:
    """The run function of study ``name``."""
    if name not in _REGISTRY:
        raise InvalidInputError("scenario", name, f"one of {', '.join(_REGISTRY)}")
    module, func = _REGISTRY[name]
    mod = importlib.import_module(f"{__name__}.{module}")
    return getattr(mod, func)


def run(options: RunOptions) -> RunResult:
    """Run the study ``options.scenario``, after :func:`check_options` (an option the scenario would
    ignore raises :class:`OptionNotApplicableError`) and :func:`check_run_size` (a run estimated over
    an hour raises :class:`~lipmpcc.exceptions.RunTooLongError` unless ``options.allow_long``). A ``--layout``
    given is named in the summary as ``layout_file``."""
    fn = get(options.scenario)
    check_options(options)
    check_run_size(options)
    result = fn(options)
    if options.layout is not None:  # --layout: which file described --robot
        result.summary.setdefault("layout_file", str(options.layout))
    return result
