"""A study's numbers as a reader reads them: labelled, with units, never a raw dict or a Python repr.

:func:`describe` writes the fields a study reports (its ``ours`` in ``results.json``) as one line,
:func:`paper_text` the paper's claim, :func:`run_text` how the run ended. Lengths are in metres with
three decimals, as the papers give them; times in seconds; solve times as median and p90 [ms].
"""

from __future__ import annotations

import math
from pathlib import PurePath
from typing import Any, Callable, Mapping

from .tables import fmt

__all__ = ["length", "describe", "paper_text", "run_text", "MODEL_NAMES", "model_name"]

#: how the report names the robot a study runs on
MODEL_NAMES = {"lip": "3D-LIP", "alip": "ALIP (point foot)", "digit_like": "digit_like (MuJoCo)"}

#: fields shown elsewhere (their own columns) or folded into another field's text
_SKIP = {"solver_failures", "relaxed_solves", "fall_step", "step_duration_max_s"}


def model_name(robot: str | None, cop_range: Any = None) -> str:
    """The report's name of ``robot`` (``"ALIP with a foot"`` when the planner has a centre-of-pressure box;
    a model file by its stem: ``"digit-v3 (MuJoCo)"``)."""
    if robot == "alip" and cop_range:
        half = [float(c) for c in cop_range]
        return f"ALIP with a foot (CoP within ±{100 * half[0]:g} × ±{100 * half[1]:g} cm)"
    if robot and str(robot) not in MODEL_NAMES and str(robot).lower().endswith((".xml", ".mjcf")):
        return f"{PurePath(str(robot)).stem} (MuJoCo)"  # a model file (lipmpcc reproduce --robot MODEL.xml)
    return MODEL_NAMES.get(str(robot), str(robot) if robot else "–")


def length(v: Any) -> str:
    """A length [m] to three decimals (``"0.012 m"``); ``"–"`` for a missing value."""
    if not isinstance(v, (int, float)) or isinstance(v, bool):
        return "–"
    return "nan" if math.isnan(v) else f"{v:.3f} m"


def _ms(v: Any) -> str:
    if isinstance(v, Mapping) and "median" in v:
        return f"median {v['median']:.2g} ms, p90 {v.get('p90', float('nan')):.2g} ms"
    return fmt(v)


def _recovery(v: Any) -> str:
    if not isinstance(v, list) or not v:
        return "no push"
    done = [x for x in v if isinstance(x, (int, float))]
    text = f"{len(v)} pushes, error back below 0.05 m within {max(done):.2f} s at worst" if done else f"{len(v)} pushes"
    lost = len(v) - len(done)
    return text + (f", **{lost} not recovered**" if lost else "")


def _count(word: str, none: str) -> Callable[[Any], str]:
    return lambda v: none if not v else f"**{v} {word}**"


_FIELDS: dict[str, Callable[[Any], str]] = {
    "contouring_error_max_m": lambda v: f"max contouring error {length(v)}",
    "contouring_error_rms_m": lambda v: f"RMS contouring error {length(v)}",
    "contouring_error_continuous_max_m": lambda v: f"max contouring error of the COM at 400 Hz {length(v)}",
    "push_recovery_s": _recovery,
    "overtook": lambda v: "overtakes the obstacle" if v else "trails the obstacle",
    "collided": lambda v: "**collides with the obstacle**" if v else "no collision",
    "cartesian_error_max_m": lambda v: f"max Cartesian error {length(v)}",
    "min_clearance_m": lambda v: f"min clearance of the planner's disks {length(v)}",
    "min_body_clearance_m": lambda v: f"min clearance of the body {length(v)}",
    "lag_error_rms_m": lambda v: f"RMS lag error {length(v)}",
    "v_avg_mean": lambda v: f"mean v_avg {v:.3f} m/step" if isinstance(v, (int, float)) else "v_avg –",
    "steps_completed": lambda v: f"{v} steps",
    "step_rmse_m": lambda v: f"step RMSE {length(v)}",
    "stones_violated": _count("footholds off their stone", "every foothold on its stone"),
    "real_time_factor": lambda v: f"{v:.1f}× real time" if isinstance(v, (int, float)) else "",
    "solve_ms": lambda v: f"solve time {_ms(v)}",
    "wbc_ms": lambda v: f"WBC tick {_ms(v)}",
    "qp_failures": _count("WBC QP failures", "no WBC QP failure"),
    "distance_walked_m": lambda v: f"walked {v:.2f} m" if isinstance(v, (int, float)) else "",
    "min_base_height_m": lambda v: f"min base height {length(v)}",
    "pushes": lambda v: f"{v} pushes",
}


def describe(ours: Mapping[str, Any]) -> str:
    """The fields of a study's ``ours`` as one line: ``"no fall; 16 steps; step RMSE 0.003 m; ..."``
    (a fall with its stone, the step durations as a range; the solver counts are left to their columns)."""
    parts = []
    for key, v in ours.items():
        if key in _SKIP:
            continue
        if key == "fell":
            stone = ours.get("fall_step")
            parts.append(("**falls at stone %s**" % stone if stone is not None else "**falls**") if v else "no fall")
        elif key == "step_duration_min_s":
            hi = ours.get("step_duration_max_s")
            if isinstance(v, (int, float)) and isinstance(hi, (int, float)):
                parts.append(f"step durations {v:.2f}–{hi:.2f} s")
        elif v is None:
            parts.append(f"{key.replace('_', ' ')}: –")
        elif key in _FIELDS:
            text = _FIELDS[key](v)
            if text:
                parts.append(text)
        else:
            parts.append(f"{key.replace('_', ' ')}: {fmt(v)}")
    return "; ".join(parts)


_CLAIMS: dict[str, Callable[[Any], str]] = {
    "cartesian_error_max_m": lambda v: f"Cartesian error below {length(v)}",
    "overtook": lambda v: "overtakes the obstacle" if v else "trails the obstacle",
    "lag_error": lambda v: f"lag error {v}",
    "v_avg": lambda v: f"v_avg {v}",
}


def paper_text(claim: Any) -> str:
    """The paper's claim as text: a Table II RMSE as a length, a claim of several parts joined by ``;``."""
    if claim is None:
        return "–"
    if isinstance(claim, (int, float)) and not isinstance(claim, bool):
        return length(claim)
    if isinstance(claim, Mapping):
        return "; ".join(_CLAIMS[k](v) if k in _CLAIMS else f"{k.replace('_', ' ')}: {fmt(v)}" for k, v in claim.items())
    return str(claim)


def run_text(entry: Mapping[str, Any]) -> str:
    """How a run ended, in a few words: ``completed``, ``fell at stone 9``, ``collided``, ``stopped early``,
    ``trailing obstacle 0 by 0.82 m``, ``stalled at 1.7 of 14.0 m (obstacles 5, 6)``, ``incomplete at 10.5 of
    19.0 m`` (``"–"`` for a results.json of an older lipmpcc)."""
    outcome = entry.get("outcome")
    if outcome is None:
        return "–"
    if outcome == "fell":
        stone = (entry.get("ours") or {}).get("fall_step")
        return f"fell at stone {stone}" if stone is not None else "fell"
    text = str(outcome).replace("_", " ")
    if entry.get("path_length_m") is not None and outcome in ("stalled", "incomplete"):
        text += f" at {float(entry.get('progress_m') or 0.0):.1f} of {float(entry['path_length_m']):.1f} m"
        stall = entry.get("stall")
        if isinstance(stall, dict) and (stall.get("binding") or {}).get("obstacles"):
            text += " (obstacles " + ", ".join(str(j) for j in stall["binding"]["obstacles"]) + ")"
    elif outcome == "trailing" and entry.get("trailing_obstacle") is not None:
        text += f" obstacle {entry['trailing_obstacle']} by {float(entry.get('trailing_gap_m') or 0.0):.2f} m"
    return text
