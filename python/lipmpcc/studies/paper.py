"""The papers' reported numbers, read from ``data/reference/paper_results.json`` (the one place they are kept).

One key scheme, the JSON's: planners are spelled as on the command line (``"alip-mpc"``, ``"alip-qp"``);
paper B's Table II courses are keyed by :func:`case_key` (``"I L=0.4 W=+0.15"`` for profile I, the
profile name ``"II"``, ``"III"``, ``"IV"`` for the random profiles, whose Table II row is seed 0).
Paper B's push test (stones, forces, window) is read from here by the stepping-stone study.
"""

from __future__ import annotations

import copy
import functools
import json
from dataclasses import dataclass
from typing import Any

from ..exceptions import InvalidInputError
from ..resources import data_path
from ..terrain import paper_cases

__all__ = [
    "PaperPush",
    "PushTest",
    "reference",
    "paper_a",
    "case_key",
    "table_ii_cases",
    "table_ii_claim",
    "table_ii_rmse",
    "push_test",
    "push_test_claim",
]


@functools.cache
def _load() -> dict[str, Any]:
    with open(data_path("reference", "paper_results.json")) as f:
        return json.load(f)


def reference() -> dict[str, Any]:
    """The whole reference file (a copy: edit it freely)."""
    return copy.deepcopy(_load())


def paper_a(study: str) -> dict[str, Any]:
    """Paper A's numbers for ``study``: ``"circle"``, ``"overtake_cartesian"``, ``"overtake_mpcc"``,
    ``"solver"`` or ``"settings"``."""
    ref = _load()["paper_a"]
    if study not in ref:
        raise InvalidInputError("study", study, f"one of {', '.join(ref)}")
    return copy.deepcopy(ref[study])


def case_key(profile: str, L: float | None = None, W: float | None = None) -> str:
    """The Table II key of a course: ``"I L=0.4 W=+0.15"`` (profile I, L and W [m]) or the profile name."""
    if profile == "I":
        return f"I L={L:g} W={W:+.2f}"
    return profile


def table_ii_cases() -> list[dict[str, Any]]:
    """Table II's courses, in the paper's order: the six of profile I, then seed 0 of profiles II, III
    and IV (dicts with ``profile``, ``L``, ``W``, ``seed`` as :func:`lipmpcc.terrain.paper_cases`)."""
    return [c for c in paper_cases() if c["profile"] == "I" or c["seed"] == 0]


def _table_ii() -> dict[str, dict[str, Any]]:
    return _load()["paper_b"]["table_ii_step_rmse_m"]


def table_ii_claim(case: str, planner: str) -> float | str:
    """Paper B Table II for course ``case`` (:func:`case_key`) and ``planner``: the step-position RMSE
    [m], or the paper's words where the planner fails (``"fails"``, ``"falls at step 14"``)."""
    table = _table_ii()
    if case not in table or planner not in table[case]:
        raise InvalidInputError("case, planner", (case, planner), f"a course of {', '.join(table)} and alip-mpc or alip-qp")
    return table[case][planner]


def table_ii_rmse(case: str | None, planner: str) -> float | None:
    """The step-position RMSE [m] paper B reports for ``case`` and ``planner``; None where the paper
    reports a failure, or when ``case`` is None or not in Table II (a course of one's own)."""
    row = _table_ii().get(case, {}) if case is not None else {}
    v = row.get(planner)
    return float(v) if isinstance(v, (int, float)) else None


@dataclass(frozen=True)
class PaperPush:
    """One push of paper B's push test: ``force`` (F_x, F_y) [N] on the COM during the swing towards
    stone number ``stone`` (1-based)."""

    stone: int
    force: tuple[float, float]


@dataclass(frozen=True)
class PushTest:
    """Paper B's push test (§V-B).

    Attributes:
        n_stones: the stones of the course.
        L, W: their step length and lateral offset [m].
        pushes: the pushes, in order.
        window: (start, end) of every push after the touch-down that starts the pushed swing [s].
    """

    n_stones: int
    L: float
    W: float
    pushes: tuple[PaperPush, ...]
    window: tuple[float, float]


def push_test() -> PushTest:
    """Paper B's push test as the reference file states it."""
    p = _load()["paper_b"]["push_test"]
    pushes = tuple(PaperPush(int(s), (float(fx), float(fy))) for s, fx, fy in p["pushes"])
    a, b = p["window_s"]
    return PushTest(int(p["steps"]), float(p["L"]), float(p["W"]), pushes, (float(a), float(b)))


def push_test_claim(planner: str) -> str:
    """What paper B reports of ``planner`` in the push test (``"survives"``, ...)."""
    p = _load()["paper_b"]["push_test"]
    if planner not in p:
        raise InvalidInputError("planner", planner, "alip-mpc or alip-qp")
    return p[planner]
