"""A study's mark beside the paper, and the reasons where it differs.

:func:`judge` marks one study of ``results.json``:

- ``pass``: the run meets its criterion and agrees with the paper (the same outcome; a number within a
  factor of :data:`RATIO` of the paper's);
- ``better``: shown as "pass, better than the paper (N×)": the run meets its criterion and the paper's claim
  (the same outcome), with a number better than the paper's by more than a factor of :data:`RATIO` (a Table
  II step RMSE N times below the paper's);
- ``expected-fail``: the run misses its criterion as the reproduction expects (paper B's push test on the
  point-foot ALIP);
- ``differs``: the run misses its criterion, ends unlike the paper's run, or gives a number worse than the
  paper's by more than a factor of :data:`RATIO`;
- ``error``, ``skipped``: the study could not run.

The reasons are read from ``data/reference/paper_results.json`` (``reasons``: the one definition; each
names the studies it applies to and the kinds of difference it explains, :class:`Reason`).
"""

from __future__ import annotations

from dataclasses import dataclass
from fnmatch import fnmatchcase
from typing import Any, Mapping

from ..studies import paper

__all__ = ["RATIO", "MARKS", "Reason", "Judgement", "reasons", "better_factor", "judge", "exit_failures"]

#: a number differs from the paper's when it is more than RATIO times worse (an RMSE: larger); more than RATIO
#: times better (smaller) it is marked ``better``
RATIO = 2.0

#: the marks, with what each means (the report's legend)
MARKS = {
    "pass": "meets its criterion and agrees with the paper (same outcome; numbers within a factor of 2)",
    "better": "pass, better than the paper: meets its criterion with the paper's outcome, and a number more than "
              "a factor of 2 better than the paper's (the factor is given: the paper's step RMSE over ours)",
    "expected-fail": "misses its criterion, as the reproduction expects (the reason is given)",
    "differs": "misses its criterion, ends unlike the paper's run, or a number is worse than the paper's by more "
               "than a factor of 2 (the reason is given)",
    "error": "the study could not run (the error is given)",
}


@dataclass(frozen=True)
class Reason:
    """Why results differ from the paper: ``short`` (a table cell), ``text`` (the full line), ``doc`` (where
    it is explained), the study-name patterns it applies to and the kinds of difference it explains
    (``expected-fail``, ``outcome``, ``number``, ``solve-time``)."""

    key: str
    short: str
    text: str
    doc: str
    studies: tuple[str, ...]
    when: tuple[str, ...]

    def applies(self, name: str, kinds: tuple[str, ...]) -> bool:
        """True when the reason explains a difference of one of ``kinds`` of study ``name``."""
        return bool(set(kinds) & set(self.when)) and any(fnmatchcase(name, p) for p in self.studies)


def reasons() -> dict[str, Reason]:
    """The reasons of ``data/reference/paper_results.json``, by key."""
    raw = paper.reference().get("reasons", {})
    return {k: Reason(k, v["short"], v["text"], v.get("doc", ""), tuple(v["studies"]), tuple(v["when"]))
            for k, v in raw.items() if not k.startswith("_")}


@dataclass(frozen=True)
class Judgement:
    """A study's ``mark``, how its run ended (``outcome``), the kinds of difference found, and the reasons
    that explain them (empty for a difference no reason explains); ``factor``: how many times better than the
    paper's its number is (``better`` only); ``criterion``: the criterion the run missed (the parts it missed,
    with their values, when the study names its parts: ``results.json``'s ``criterion_missed``; empty when it
    met it or has none), named by :attr:`why` when no recorded reason explains the difference."""

    mark: str
    outcome: str
    kinds: tuple[str, ...]
    reasons: tuple[Reason, ...]
    factor: float | None = None
    criterion: str = ""

    @property
    def label(self) -> str:
        """The mark with the run's outcome when it did not complete: ``"differs: collided"``; a ``better`` mark
        as ``"pass, better than the paper (7.7×)"``."""
        mark = f"pass, better than the paper ({self.factor:.1f}×)" if self.mark == "better" else self.mark
        if self.outcome in ("", "completed", "-"):  # trailing is named: "pass: trailing"
            return mark
        return f"{mark}: {self.outcome.replace('_', ' ')}"

    @property
    def why(self) -> str:
        """The short reasons; for a difference none explains, the criterion the run missed
        (``"misses its criterion: …"``) or ``"no reason recorded"``; empty for a pass."""
        if self.mark in ("error", "skipped"):
            return ""
        if self.mark in ("pass", "better"):
            return "; ".join(r.short for r in self.reasons)
        missed = f"misses its criterion: {self.criterion} (no reason recorded)" if self.criterion else ""
        return "; ".join(r.short for r in self.reasons) or missed or "**no reason recorded**"


def _first_lateral_push_stone() -> int:
    return min((p.stone for p in paper.push_test().pushes if p.force[1] != 0.0), default=0)


def _fell(entry: Mapping[str, Any]) -> bool:
    return entry.get("outcome") == "fell" or bool((entry.get("ours") or {}).get("fell"))


def _paper_differences(entry: Mapping[str, Any]) -> list[str]:
    """The kinds of difference between a run and the paper's claim (``outcome``, ``number``)."""
    claim, ours, fell = entry.get("paper"), entry.get("ours") or {}, _fell(entry)
    if isinstance(claim, (int, float)) and not isinstance(claim, bool):  # a Table II RMSE: the paper completes
        if fell:
            return ["outcome"]
        rmse = ours.get("step_rmse_m")
        if isinstance(rmse, (int, float)) and claim > 0 and rmse > claim * RATIO:
            return ["number"]
        return []
    if isinstance(claim, str):
        words = claim.lower()
        if "fail" in words or "falls" in words:
            if not fell:
                return ["outcome"]
            stone = ours.get("fall_step")
            if "lateral" in words and isinstance(stone, int) and stone < _first_lateral_push_stone():
                return ["outcome"]
            return []
        if words.startswith("survives"):
            return ["outcome"] if fell else []
        return []
    if isinstance(claim, Mapping) and isinstance(ours.get("overtook"), bool) and "overtook" in claim:
        return [] if ours["overtook"] == claim["overtook"] else ["outcome"]
    return []


def better_factor(entry: Mapping[str, Any]) -> float | None:
    """How many times better than the paper's number a run's is, when by more than :data:`RATIO` (a Table II
    step RMSE: the paper's over ours), with the paper's outcome (no fall); None otherwise."""
    claim, ours = entry.get("paper"), entry.get("ours") or {}
    if not isinstance(claim, (int, float)) or isinstance(claim, bool) or claim <= 0 or _fell(entry):
        return None
    rmse = ours.get("step_rmse_m")
    if isinstance(rmse, bool) or not isinstance(rmse, (int, float)) or not rmse < claim / RATIO:
        return None
    return float(claim) / float(rmse) if rmse > 0 else float("inf")


def judge(name: str, entry: Mapping[str, Any], known: Mapping[str, Reason] | None = None) -> Judgement:
    """The mark of study ``name`` from its ``results.json`` entry, with the reasons (``known``: by
    default :func:`reasons`) that explain its differences from the paper."""
    known = reasons() if known is None else known
    outcome = str(entry.get("outcome") or "")
    if "error" in entry:
        return Judgement("skipped" if entry.get("status") == "skipped" else "error", outcome, (), ())
    if entry.get("expected_failure"):
        kinds: tuple[str, ...] = ("expected-fail",)
        mark = "expected-fail"
    else:
        found = (["outcome"] if entry.get("meets_criterion") is False else []) + _paper_differences(entry)
        kinds = tuple(dict.fromkeys(found))
        factor = None if kinds else better_factor(entry)
        if factor is not None:  # the reasons of a number off the paper's explain a better one too
            return Judgement("better", outcome, (), tuple(r for r in known.values() if r.applies(name, ("number",))),
                             factor)
        mark = "differs" if kinds else "pass"
    missed = ""
    if entry.get("meets_criterion") is False:  # the parts missed when the study names them, else the whole criterion
        missed = "; ".join(entry.get("criterion_missed") or ()) or str(entry.get("criterion") or "")
    return Judgement(mark, outcome, kinds, tuple(r for r in known.values() if r.applies(name, kinds)),
                     criterion=missed)


def exit_failures(results: Mapping[str, Any]) -> list[str]:
    """The studies that make ``lipmpcc reproduce`` exit 1: those that could not run, and those that missed
    their criterion where the reproduction does not expect it (as :func:`lipmpcc.reproduce.missed`)."""
    return [n for n, e in results["studies"].items()
            if "error" in e or (e.get("meets_criterion") is False and not e.get("expected_failure"))]
