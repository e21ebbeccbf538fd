"""``lipmpcc reproduce``: run every study and write a report beside the papers' numbers.

:func:`reproduce` writes, under ``out``:

- ``<study>/summary.json`` and figures for every run (:meth:`~lipmpcc.studies.RunResult.save`), each
  study's folder written whole through a staging folder (:class:`~lipmpcc.studies.outputs.StagedFolder`),
  or ``<study>/failed.json`` when the study could not run;
- ``results.json``: each study's key results beside the paper's (:mod:`lipmpcc.studies.paper`);
- ``report.md`` and ``report.html`` (the same, one page with the figures embedded): paper A then paper
  B, each result beside the paper's with its mark and, where it differs, the reason (:mod:`lipmpcc.report`).
  Each entry of ``results.json`` carries where the report puts it (:meth:`Study.placement`).

``results.json`` and the report are rewritten after every study, marked PARTIAL (``status``
``"running"``) until the last one; an earlier report is removed first, and a Ctrl-C leaves a report
marked PARTIAL (``status`` ``"interrupted"``) that names the studies not run. ``OUT.lock`` keeps a
second command out of ``out`` meanwhile.

``fast`` shortens every run's horizon (the ``LIPMPCC_FAST`` switch); ``only`` picks studies by name
prefix; ``robot`` (a MuJoCo model, ``MODEL.xml``, with its layout) runs every full-body study on that model
as well, under names that start with the model's prefix (:func:`model_prefix`: ``digit-v3-stones-II-alip-mpc``
beside ``digit_like``'s ``digit-stones-II-alip-mpc``), and the report puts it as its own column beside
``digit_like`` and the papers. The command line takes ``--robot MODEL.xml``, else ``$LIPMPCC_DIGIT_V3``
when it is set (:func:`extra_robot`). Studies on the full body are run when the whole-body controller is built (``lipmpcc._wbc``).
A study that misses its criterion where the reproduction expects it to (:attr:`Study.expected_failure`:
paper B's push test on the point-foot ALIP) is reported as an expected failure, not as missed.
"""

from __future__ import annotations

import os
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from . import config
from .exceptions import InvalidInputError
from .report import HTML_FILE, REPORT_FILE, RESULTS_FILE, write_report
from .studies import RunOptions, outputs, paper, run, run_outcome

__all__ = ["Study", "Criterion", "all_studies", "select_studies", "full_body_studies", "reproduce", "missed", "expected_failures",
           "model_prefix", "extra_robot", "ROBOT_ENV", "BASE_ROBOT"]

#: the environment variable naming a model whose full-body studies ``lipmpcc reproduce`` adds when
#: ``--robot`` is not given (the Digit v3 MJCF the tests also use)
ROBOT_ENV = "LIPMPCC_DIGIT_V3"

#: the full-body robot every reproduction runs (the studies named ``digit-...``)
BASE_ROBOT = "digit_like"



def _reason(key: str) -> str:
    """The full line of reason ``key`` of ``data/reference/paper_results.json`` (its ``reasons``: the one
    definition the report also reads)."""
    return str(paper.reference()["reasons"][key]["text"])


#: why paper B's push test on the point-foot ALIP is expected to fail (docs/design.md)
POINT_FOOT_PUSH = _reason("point-foot-push")


@dataclass(frozen=True)
class Criterion:
    """A study's acceptance criterion as named parts, all of which must hold: ``parts`` is a tuple of
    (label, test of the summary, the summary field the label is about or ""). It is the study's ``check``;
    :meth:`missed` names the parts a run missed, with the measured value, for the report's reason."""

    parts: tuple[tuple[str, Callable[[dict], bool], str], ...]

    def __call__(self, summary: dict[str, Any]) -> bool:
        return not self.missed(summary)

    @property
    def text(self) -> str:
        """The criterion as one line: the labels joined by "; "."""
        return "; ".join(label for label, _, _ in self.parts)

    def missed(self, summary: dict[str, Any]) -> list[str]:
        """The labels of the parts ``summary`` misses (a missing field misses), each followed by the measured
        value of its field: ``"no part of the body in the obstacle (min_body_clearance_m = -0.009)"``."""
        out = []
        for label, test, key in self.parts:
            try:
                ok = bool(test(summary))
            except (KeyError, TypeError):
                ok = False
            if not ok:
                v = summary.get(key) if key else None
                shown = f"{v:.3f}" if isinstance(v, float) else (None if v is None else str(v))
                out.append(f"{label} ({key} = {shown})" if key and shown is not None else label)
        return out


@dataclass
class Study:
    """One run of the report: a study with options, and what to compare with the paper."""

    name: str
    title: str
    options: dict[str, Any]
    paper: Callable[[], Any]  # the paper's claim for this study
    keys: list[str]  # summary fields to report
    check: Callable[[dict], bool] | None = None  # the acceptance criterion
    criterion: str = ""
    tags: list[str] = field(default_factory=list)
    expected_failure: str = ""  # why the reproduction expects the criterion to be missed ("": it is met)
    paper_id: str = ""  # "A" or "B": the paper the study reproduces ("": beyond the papers)
    item: str = ""  # the paper's figure or table: "Fig. 5(a,b)", "Table II", "Fig. 7"
    variant: str = ""  # the study it repeats on another model (digit_like's name; "": itself)

    def placement(self) -> dict[str, Any]:
        """Where the report puts the study: ``paper`` ("A", "B" or ""), ``item`` (the paper's figure or
        table), ``robot``, ``planner``, ``course`` (the Table II key of a stepping-stone course, else None),
        ``cop_range`` (the planner's foot [m], None for the point foot) and ``variant`` (the name of the study
        this one repeats on another model, its own name otherwise: the row of the report's model columns)."""
        o = self.options
        course = paper.case_key(o["profile"], o.get("L"), o.get("W")) if "profile" in o else None
        return {"paper_id": self.paper_id, "item": self.item, "robot": o.get("robot"),
                "planner": o.get("planner"), "course": course, "cop_range": o.get("cop_range"),
                "variant": self.variant or self.name}


def _table_ii_courses() -> list[tuple[str, dict[str, Any]]]:
    """(name, options) of Table II's courses: ``I_L0.2_W+0.15`` ... for profile I, ``II`` ... (seed 0)."""
    out = []
    for c in paper.table_ii_cases():
        if c["profile"] == "I":
            out.append((f"I_L{c['L']:g}_W{c['W']:+.2f}", {"profile": "I", "L": c["L"], "W": c["W"]}))
        else:
            out.append((c["profile"], {"profile": c["profile"], "seed": c["seed"]}))
    return out


def _table_ii_claim(options: dict[str, Any], planner: str) -> Callable[[], Any]:
    key = paper.case_key(options["profile"], options.get("L"), options.get("W"))
    return lambda: paper.table_ii_claim(key, planner)


def _circle_claim() -> str:
    return paper.paper_a("circle")["claim"]


def _overtake_cartesian_claim() -> dict[str, Any]:
    c = paper.paper_a("overtake_cartesian")
    return {"cartesian_error_max_m": c["cartesian_error_max_m"], "overtook": c["overtook"]}


def _overtake_mpcc_claim() -> dict[str, Any]:
    c = paper.paper_a("overtake_mpcc")
    return {k: c[k] for k in ("overtook", "lag_error", "v_avg")}


def _paper_a_lip() -> list[Study]:
    return [
        Study(
            "lip-circle", "Paper A Fig. 5(a,b): circle r = 2 m, LIP", {"scenario": "circle", "planner": "mpcc", "robot": "lip"},
            _circle_claim,
            ["contouring_error_max_m", "contouring_error_rms_m", "solver_failures", "solve_ms"],
            lambda s: s["contouring_error_max_m"] <= 0.05 and s["solver_failures"] == 0,
            "max abs contouring error after 2 s <= 0.05 m", paper_id="A", item="Fig. 5(a,b)",
        ),
        Study(
            "lip-circle-push", "Paper A Fig. 5(c,d): circle with random pushes, LIP",
            {"scenario": "circle-push", "planner": "mpcc", "robot": "lip", "seed": 0},
            _circle_claim,
            ["contouring_error_max_m", "push_recovery_s", "solver_failures", "solve_ms"],
            lambda s: s["solver_failures"] == 0 and all(x is not None and x <= 2.0 for x in s["push_recovery_s"]),
            "no planner failure; error back below 0.05 m within 2 s of each push", paper_id="A", item="Fig. 5(c,d)",
        ),
        Study(
            "lip-overtake-cartesian", "Paper A Fig. 6(a-d): Cartesian MPC, obstacle 0.1 m/s, LIP",
            {"scenario": "overtake", "planner": "cartesian", "robot": "lip"},
            _overtake_cartesian_claim,
            ["overtook", "collided", "cartesian_error_max_m", "min_clearance_m", "v_avg_mean", "solve_ms"],
            lambda s: (not s["overtook"]) and s["cartesian_error_max_m"] <= 0.06 and s["min_clearance_m"] >= 0 and not s.get("collided"),
            "trails; Cartesian error <= 0.06 m; min clearance >= 0; no collision", paper_id="A", item="Fig. 6(a-d)",
        ),
        Study(
            "lip-overtake-mpcc", "Paper A Fig. 6(e-h): MPCC, obstacle 0.6 m/s, LIP",
            {"scenario": "overtake", "planner": "mpcc", "robot": "lip"},
            _overtake_mpcc_claim,
            ["overtook", "collided", "min_clearance_m", "lag_error_rms_m", "contouring_error_max_m", "v_avg_mean", "solve_ms"],
            lambda s: s["overtook"] and s["min_clearance_m"] >= 0 and s["v_avg_mean"] >= 0.9 * 0.3 and not s.get("collided"),
            "overtakes; min clearance >= 0; no collision; mean v_avg >= 0.9 v_max", paper_id="A", item="Fig. 6(e-h)",
        ),
    ]


def _paper_b_alip() -> list[Study]:
    out = []
    for case, opts in _table_ii_courses():
        for planner in ("alip-mpc", "alip-qp"):
            out.append(
                Study(
                    f"alip-stones-{case}-{planner}", f"Paper B Table II, profile {case}, {planner}, ALIP",
                    {"scenario": "stones", "planner": planner, "robot": "alip", **opts},
                    _table_ii_claim(opts, planner),
                    ["fell", "fall_step", "steps_completed", "step_rmse_m", "stones_violated", "step_duration_min_s",
                     "step_duration_max_s", "solver_failures", "solve_ms"],
                    (lambda s: (not s["fell"]) and s["step_rmse_m"] <= 0.04 and s["solver_failures"] == 0) if planner == "alip-mpc" else None,
                    "no fall, step RMSE <= 0.04 m, no solver failure" if planner == "alip-mpc" else "reported",
                    paper_id="B", item="Table II",
                )
            )
    for planner in ("alip-mpc", "alip-qp"):
        out.append(
            Study(
                f"alip-push-{planner}", f"Paper B Fig. 7: push test, {planner}, ALIP",
                {"scenario": "push", "planner": planner, "robot": "alip"},
                lambda p=planner: paper.push_test_claim(p),
                ["fell", "fall_step", "steps_completed", "step_rmse_m", "step_duration_min_s", "step_duration_max_s", "solve_ms"],
                (lambda s: not s["fell"]) if planner == "alip-mpc" else None,
                "survives" if planner == "alip-mpc" else "reported",
                expected_failure=POINT_FOOT_PUSH if planner == "alip-mpc" else "", paper_id="B", item="Fig. 7",
            )
        )
    out.append(
        Study(
            "alip-push-alip-mpc-foot", "Paper B Fig. 7: push test, alip-mpc with a foot (CoP within 0.12 x 0.05 m), ALIP",
            {"scenario": "push", "planner": "alip-mpc", "robot": "alip", "cop_range": (0.06, 0.025)},
            lambda: paper.push_test_claim("alip-mpc"),
            ["fell", "fall_step", "steps_completed", "step_rmse_m", "step_duration_min_s", "step_duration_max_s",
             "solver_failures", "solve_ms"],
            lambda s: not s["fell"] and s["solver_failures"] == 0,
            "survives, no solver failure", paper_id="B", item="Fig. 7",
        )
    )
    return out


def all_studies(robot: str | None = None) -> list[Study]:
    """All studies of the report, reduced models first; with ``robot`` (a model file, ``MODEL.xml``) the
    full-body studies once more on that model, last."""
    extra = full_body_studies(robot) if robot is not None else []
    return _paper_a_lip() + _paper_b_alip() + full_body_studies() + extra


def model_prefix(robot: str) -> str:
    """The prefix of the study names of the full-body studies on ``robot``: ``"digit"`` for ``digit_like``,
    else the model file's stem in lower case with every run of other characters than letters and digits
    made one ``-`` (``.../digit-v3.xml``: ``"digit-v3"``), followed by ``-model`` when that stem is ``digit``,
    ``lip`` or ``alip`` (the other studies' prefixes)."""
    if robot == BASE_ROBOT:
        return "digit"
    stem = re.sub(r"[^a-z0-9]+", "-", Path(str(robot)).stem.lower()).strip("-") or "model"
    return f"{stem}-model" if stem in ("digit", "lip", "alip") else stem


def extra_robot(robot: str | None = None) -> str | None:
    """The model whose full-body studies ``lipmpcc reproduce`` adds: ``robot`` (``--robot``), else the
    file named by ``$LIPMPCC_DIGIT_V3`` when that is set and not empty, else None (``digit_like`` only).
    A variable naming no file is left aside with a warning (the tests skip Digit v3 then, too).

    Raises:
        InvalidInputError: ``robot`` is not an existing MuJoCo model file (``.xml``/``.mjcf``), or is
            ``digit_like`` itself (which every reproduction runs).
    """
    source = "--robot"
    if robot is None:
        env = os.environ.get(ROBOT_ENV, "").strip()
        if not env:
            return None
        if not Path(env).expanduser().is_file():
            import warnings

            warnings.warn(f"${ROBOT_ENV} = {env!r} names no file: the full-body studies run on digit_like only",
                          UserWarning, stacklevel=2)
            return None
        robot, source = env, f"${ROBOT_ENV}"
    if robot == BASE_ROBOT:
        raise InvalidInputError(source, robot, "another model than digit_like (a MODEL.xml file), which every "
                                "reproduction runs; leave it out for digit_like alone")
    path = Path(robot).expanduser()
    if path.suffix.lower() not in (".xml", ".mjcf") or not path.is_file():
        raise InvalidInputError(source, robot, "an existing MuJoCo model file MODEL.xml (its layout MODEL.lipmpcc.toml "
                                "beside it, or one the package ships: docs/formats.md)")
    return str(path.resolve())


def select_studies(only: str | None = None, robot: str | None = None) -> list[Study]:
    """The studies whose name starts with ``only`` (None: all of them), with ``robot``'s full-body studies
    (:func:`all_studies`); a study on ``robot`` is also chosen when the ``digit_like`` study it repeats is
    (``only="digit-stones-II"`` picks both models' profile II, ``"digit-v3-"`` the model's alone).

    Raises:
        InvalidInputError: ``only`` is empty or matches no study (the message lists the names' prefixes).
    """
    if only is not None and (not isinstance(only, str) or not only.strip()):
        raise InvalidInputError("--only", only, "the start of a study name (leave --only out for every study)")
    studies = all_studies(robot)
    chosen = [st for st in studies if only is None or st.name.startswith(only) or (st.variant or st.name).startswith(only)]
    if not chosen:
        prefixes = list(dict.fromkeys(st.name.split("-")[0] + "-" for st in studies))
        if robot is not None:
            prefixes.append(model_prefix(robot) + "-")
        raise InvalidInputError("--only", only, f"the start of a study name ({', '.join(prefixes)}...)", "it matches no study")
    return chosen


def _wbc_available() -> bool:
    try:
        from . import _wbc  # noqa: F401
    except ImportError:
        return False
    return True


def _criterion(*parts: tuple[str, Callable[[dict], bool], str]) -> tuple[Criterion, str]:
    """A study's ``check`` and ``criterion`` text from its named parts (:class:`Criterion`)."""
    c = Criterion(tuple(parts))
    return c, c.text


def _no_fall(s: dict[str, Any]) -> bool:
    return not s["fell"]


#: the whole body's part of a full-body overtaking criterion: no robot geom inside the obstacle
_NO_CONTACT = ("no part of the body in the obstacle", lambda s: not s.get("collided"), "min_body_clearance_m")


def _full_body_paper_a(fb: dict[str, Any]) -> list[Study]:
    return [
        Study(
            "digit-circle", "Paper A Fig. 5(a,b): circle r = 2 m, digit_like", {"scenario": "circle", "planner": "mpcc", **fb},
            _circle_claim,
            ["fell", "contouring_error_max_m", "contouring_error_continuous_max_m", "solver_failures", "real_time_factor", "solve_ms", "wbc_ms"],
            *_criterion(("no fall", _no_fall, "fall_time_s"),
                        ("max abs contouring error after 3 s <= 0.10 m", lambda s: s["contouring_error_max_m"] <= 0.10,
                         "contouring_error_max_m")),
            paper_id="A", item="Fig. 5(a,b)",
        ),
        Study(
            "digit-circle-push", "Paper A Fig. 5(c,d): circle with random pushes, digit_like",
            {"scenario": "circle-push", "planner": "mpcc", "seed": 0, **fb},
            _circle_claim,
            ["fell", "pushes", "contouring_error_max_m", "solver_failures", "real_time_factor"],
            lambda s: not s["fell"], "no fall", paper_id="A", item="Fig. 5(c,d)",
        ),
        Study(
            "digit-overtake-cartesian", "Paper A Fig. 6(a-d): Cartesian MPC, obstacle 0.1 m/s, digit_like",
            {"scenario": "overtake", "planner": "cartesian", **fb},
            _overtake_cartesian_claim,
            ["fell", "overtook", "collided", "cartesian_error_max_m", "min_clearance_m", "min_body_clearance_m", "real_time_factor"],
            *_criterion(("no fall", _no_fall, "fall_time_s"), ("trails", lambda s: not s["overtook"], "overtook"),
                        ("Cartesian error <= 0.06 m", lambda s: s["cartesian_error_max_m"] <= 0.06, "cartesian_error_max_m"),
                        ("clearance >= 0", lambda s: s["min_clearance_m"] >= 0, "min_clearance_m"), _NO_CONTACT),
            paper_id="A", item="Fig. 6(a-d)",
        ),
        Study(
            "digit-overtake-mpcc", "Paper A Fig. 6(e-h): MPCC, obstacle 0.6 m/s, digit_like",
            {"scenario": "overtake", "planner": "mpcc", **fb},
            _overtake_mpcc_claim,
            ["fell", "overtook", "collided", "min_clearance_m", "min_body_clearance_m", "lag_error_rms_m", "v_avg_mean", "real_time_factor"],
            *_criterion(("no fall", _no_fall, "fall_time_s"), ("overtakes", lambda s: s["overtook"], "overtook"),
                        ("clearance >= 0", lambda s: s["min_clearance_m"] >= 0, "min_clearance_m"), _NO_CONTACT),
            paper_id="A", item="Fig. 6(e-h)",
        ),
        Study(
            "digit-overtake-timed", "Beyond paper A: timed MPCC (T in [0.3, 0.5] s), obstacle 0.8 m/s, digit_like",
            {"scenario": "overtake", "planner": "mpcc", "obstacle_speed": 0.8, "step_duration_range": (0.3, 0.5), **fb},
            lambda: "(not in the papers: the MPCC chooses each step's duration in [0.3, 0.5] s to pass a 0.8 m/s obstacle)",
            ["fell", "overtook", "collided", "min_clearance_m", "min_body_clearance_m", "solver_failures",
             "contouring_error_rms_m", "real_time_factor"],
            *_criterion(("no fall", _no_fall, "fall_time_s"), ("overtakes", lambda s: s["overtook"], "overtook"),
                        ("body clearance >= 0.03 m", lambda s: s["min_body_clearance_m"] >= 0.03, "min_body_clearance_m")),
        ),
    ]


def _full_body_paper_b(fb: dict[str, Any]) -> list[Study]:
    out = []
    for case, opts in _table_ii_courses():
        for planner in ("alip-mpc", "alip-qp"):
            out.append(
                Study(
                    f"digit-stones-{case}-{planner}", f"Paper B Table II, profile {case}, {planner}, digit_like",
                    {"scenario": "stones", "planner": planner, **opts, **fb},
                    _table_ii_claim(opts, planner),
                    ["fell", "fall_step", "steps_completed", "step_rmse_m", "stones_violated", "step_duration_min_s",
                     "step_duration_max_s", "solver_failures", "real_time_factor"],
                    (lambda s: (not s["fell"]) and s["step_rmse_m"] <= 0.05) if planner == "alip-mpc" else None,
                    "no fall, step RMSE <= 0.05 m" if planner == "alip-mpc" else "reported",
                    paper_id="B", item="Table II",
                )
            )
    for planner in ("alip-mpc", "alip-qp"):
        out.append(
            Study(
                f"digit-push-{planner}", f"Paper B Fig. 7: push test, {planner}, digit_like",
                {"scenario": "push", "planner": planner, **fb},
                lambda p=planner: paper.push_test_claim(p),
                ["fell", "fall_step", "steps_completed", "step_rmse_m", "step_duration_min_s", "step_duration_max_s", "real_time_factor"],
                (lambda s: not s["fell"]) if planner == "alip-mpc" else None,
                "survives" if planner == "alip-mpc" else "reported", paper_id="B", item="Fig. 7",
            )
        )
    return out


def full_body_studies(robot: str = BASE_ROBOT) -> list[Study]:
    """The studies on a full-body robot in MuJoCo (the C++ WBC is needed): ``digit_like`` (named ``digit-...``)
    or ``robot``, a model file, named with its :func:`model_prefix` and titled with its name, each with
    ``variant`` the ``digit_like`` study it repeats."""
    fb = {"robot": robot}
    out = [
        Study(
            "digit-walk", "Walking 10 m+ under the whole-body QP (capture-point footsteps)", {"scenario": "walk", **fb},
            lambda: "(not in the papers: the low-level loop alone)",
            ["fell", "distance_walked_m", "real_time_factor", "wbc_ms", "qp_failures", "min_base_height_m"],
            lambda s: not s["fell"], "no fall",
        ),
        Study(
            "digit-stand-push", "Standing with four 50 N pushes", {"scenario": "stand", **fb},
            lambda: "(not in the papers)",
            ["fell", "real_time_factor", "wbc_ms", "qp_failures"], lambda s: not s["fell"], "no fall",
        ),
    ]
    out += _full_body_paper_a(fb) + _full_body_paper_b(fb)
    for st in out:
        st.tags.append("fullbody")
    if robot != BASE_ROBOT:
        prefix, label = model_prefix(robot), Path(str(robot)).stem
        for st in out:
            st.variant = st.name
            st.name = prefix + st.name[len("digit"):]
            st.title = st.title.replace(BASE_ROBOT, label)
    return out


def _missed_parts(st: Study, summary: dict[str, Any]) -> list[str]:
    """The parts of ``st``'s criterion the run missed (:meth:`Criterion.missed`; [] for a plain check)."""
    return st.check.missed(summary) if isinstance(st.check, Criterion) else []


def _check(st: Study, summary: dict[str, Any]) -> bool | None:
    if st.check is None:
        return None
    try:
        return bool(st.check(summary))
    except (KeyError, TypeError):  # a field the run did not produce: criterion not met
        return False


def _run_one(st: Study, out: Path) -> dict[str, Any]:
    """Run one study, save its outputs whole under ``out/NAME`` (``failed.json`` when it cannot run),
    and return its entry of results.json.

    Raises:
        KeyboardInterrupt: Ctrl-C (also when a library turned it into another error).
    """
    t0 = time.perf_counter()
    try:
        with outputs.StagedFolder(out / st.name, {"study": st.name, **st.options}) as stage:
            res = run(RunOptions(out=str(stage.tmp), **st.options))
            res.save(stage.tmp)
    except Exception as exc:  # a study that cannot run is reported, not fatal
        if outputs.is_interrupt(exc):
            raise KeyboardInterrupt from exc
        print(f"[reproduce] {st.name}: ERROR {exc}")
        return {"title": st.title, **st.placement(), "error": f"{type(exc).__name__}: {exc}", "status": "error"}
    s = res.summary
    entry = {
        "title": st.title,
        **st.placement(),
        "ours": {k: s.get(k) for k in st.keys},
        "paper": st.paper(),
        "criterion": st.criterion,
        "meets_criterion": _check(st, s),
        "criterion_missed": _missed_parts(st, s),  # the parts of a Criterion missed, with their values
        "figures": [f"{st.name}/{n}.png" for n in res.figures],
        "wall_s": time.perf_counter() - t0,
        "outcome": run_outcome(s),  # how the run ended, beside whether the criterion is met
        "expected_outcome": s.get("expected_outcome"),
        "solver_failures": s.get("solver_failures"),
        "relaxed_solves": s.get("relaxed_solves"),
        "warnings": list(s.get("warnings") or []),
    }
    for k in ("reached_end", "progress_m", "path_length_m", "stall", "trailing_obstacle", "trailing_gap_m"):
        if k in s:  # a path-following study: how far along its path, and why it stopped progressing
            entry[k] = s[k]
    if entry["meets_criterion"] is False and st.expected_failure:
        entry["expected_failure"] = st.expected_failure
    entry["status"] = _status(entry)
    print(f"[reproduce] {st.name}: {entry['status']} ({entry['wall_s']:.1f} s)")
    return entry


def _status(entry: dict[str, Any]) -> str:
    if "error" in entry:
        return "error"
    if entry.get("expected_failure"):
        return "expected failure"
    return {True: "ok", False: "MISSED", None: "-"}[entry["meets_criterion"]]


def _write(results: dict[str, Any], out: Path, t_all: float) -> None:
    results["wall_s"] = time.perf_counter() - t_all
    with outputs.deferred_interrupt():
        write_report(results, out)


def _run_all(chosen: list[Study], out: Path, results: dict[str, Any], t_all: float) -> None:
    wbc = _wbc_available()
    for st in chosen:
        if "fullbody" in st.tags and not wbc:
            entry = {"title": st.title, **st.placement(),
                     "error": "skipped: the C++ whole-body controller lipmpcc._wbc is not built", "status": "skipped"}
        else:
            entry = _run_one(st, out)
        results["studies"][st.name] = entry
        results["not_run"].remove(st.name)
        _write(results, out, t_all)


def reproduce(out: str | Path, fast: bool = False, only: str | None = None, robot: str | None = None) -> dict[str, Any]:
    """Run the studies and write the report.

    Args:
        out: output folder.
        fast: shorter runs (sets the fast mode for the rest of the process).
        only: run only the studies whose name starts with this.
        robot: a model file (``MODEL.xml``) to run every full-body study on as well (None: ``digit_like``
            only; the environment is not read here, see :func:`extra_robot`).

    Returns:
        The content of ``results.json``: ``fast``, ``status`` (``"complete"``), ``studies`` (name ->
        entry, with its ``status``: ``ok``, ``MISSED``, ``-``, ``expected failure``, ``error`` or
        ``skipped``), ``not_run`` (empty), ``robots`` (the full-body models, ``digit_like`` first) and
        ``wall_s``.

    Raises:
        InvalidInputError: ``only`` matches no study (nothing is run or written).
        OutputFolderError: ``out`` cannot be a folder (empty, a file, not writable).
        OutputBusyError: another command writes to ``out``.
        KeyboardInterrupt: Ctrl-C; ``report.md`` is then marked PARTIAL (``status`` ``"interrupted"``).
    """
    chosen = select_studies(only, robot)
    out = outputs.check_folder_path(out)
    if fast:
        config.set_fast_mode(True)
    with outputs.OutputLock(out):
        out.mkdir(parents=True, exist_ok=True)
        for stale in (REPORT_FILE, HTML_FILE, RESULTS_FILE):  # an earlier report never stands beside new results
            (out / stale).unlink(missing_ok=True)
        results: dict[str, Any] = {"fast": config.fast_mode(), "status": "running", "studies": {},
                                   "not_run": [st.name for st in chosen],
                                   "robots": [BASE_ROBOT] + ([robot] if robot is not None else [])}
        t_all = time.perf_counter()
        try:
            _run_all(chosen, out, results, t_all)
        except KeyboardInterrupt:
            results["status"] = "interrupted"
            _write(results, out, t_all)
            raise
        results["status"] = "complete"
        _write(results, out, t_all)
    return results


def missed(results: dict[str, Any]) -> list[str]:
    """The studies of ``results`` that missed their criterion (not as expected) or could not run."""
    return [n for n, e in results["studies"].items()
            if "error" in e or (e.get("meets_criterion") is False and not e.get("expected_failure"))]


def expected_failures(results: dict[str, Any]) -> list[str]:
    """The studies of ``results`` that missed their criterion as the reproduction expects (:attr:`Study.expected_failure`)."""
    return [n for n, e in results["studies"].items() if e.get("expected_failure")]


# --------------------------------------------------------------------------------------------
# The 0.1 names, kept for one release
# --------------------------------------------------------------------------------------------
def _main_0_1(ns: object) -> int:
    """The 0.1 entry ``reproduce.main(namespace)``: :func:`reproduce` with the namespace's ``out``,
    ``fast`` and ``only``; prints the report's path and the studies missed."""
    res = reproduce(Path(getattr(ns, "out")), fast=bool(getattr(ns, "fast", False)), only=getattr(ns, "only", None))
    bad = missed(res)
    print(f"report: {Path(getattr(ns, 'out')) / 'report.md'}; {len(res['studies'])} studies, {len(bad)} missed or failed"
          + (f": {', '.join(bad)}" if bad else ""))
    return 0


_RENAMED = {
    "studies": (all_studies, "lipmpcc.reproduce.all_studies"),
    "fullbody_studies": (full_body_studies, "lipmpcc.reproduce.full_body_studies"),
    "main": (_main_0_1, "lipmpcc.reproduce.reproduce (the command line: lipmpcc.cli.main)"),
}


def __getattr__(name: str) -> object:
    import warnings

    from ._deprecated import REMOVED_IN

    if name == "TABLE_II_CASES":
        value: object = dict(_table_ii_courses())
        new = "lipmpcc.studies.paper.table_ii_cases()"
    elif name in _RENAMED:
        value, new = _RENAMED[name]
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    warnings.warn(f"{__name__}.{name} is {new} now; the old name is removed in lipmpcc {REMOVED_IN}",
                  DeprecationWarning, stacklevel=2)
    return value
