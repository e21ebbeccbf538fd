"""What the reproduction report says, in order (:func:`report_blocks`): a summary with the exit status and
the marks' legend; paper A, then paper B, each figure and table in the paper's order with every result
beside the paper's, its mark (:mod:`lipmpcc.report.marks`), its solver failures and relaxed solves and,
where it differs, the reason; the studies beyond the papers; the reasons in full; every other figure once,
in an appendix.

It reads ``results.json`` alone (each study's entry, with where it belongs: ``paper_id``, ``item``,
``robot``, ``planner``, ``course``); an entry without them (an older ``results.json``) is listed under
"Other studies".
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import PurePosixPath
from typing import Any, Callable, Mapping, Sequence

from ..studies import paper
from ..studies.outcome import SUCCESS_OUTCOMES
from .document import Block, Bullets, Figure, Heading, Paragraph, Table, slug
from .marks import MARKS, Judgement, Reason, exit_failures, judge, reasons
from .models import full_body_robots, models_table
from .values import describe, length, model_name, paper_text, run_text

__all__ = ["TITLE", "PAPERS", "ITEMS", "FIGURE_TEXT", "report_blocks"]

TITLE = "lipmpcc reproduction report"

#: the papers, as the report names them
PAPERS = {
    "A": "Paper A: MPCC path following and overtaking (Narkhede et al.)",
    "B": "Paper B: ALIP-MPC with adaptive step duration on stepping stones (Xiang et al.)",
}

#: each paper's figures and tables in the paper's order: (paper, item, heading, what the paper shows)
ITEMS: tuple[tuple[str, str, str, str], ...] = (
    ("A", "Fig. 5(a,b)", "Fig. 5(a,b): a circle of radius 2 m",
     "Paper A: Digit follows the circle with Q̄ = W̄ = diag(300, 3), ρ = 10; the contouring error stays small."),
    ("A", "Fig. 5(c,d)", "Fig. 5(c,d): the circle under random pushes",
     "Paper A: the same circle under pushes of U[−50, 50] N for 0.1 s, at most 2 s apart; spikes of error at "
     "the pushes, then back on the path."),
    ("A", "Fig. 6(a-d)", "Fig. 6(a–d): Cartesian MPC behind a 0.1 m/s obstacle",
     "Paper A: with Q = W = 200 I, ρ = 50 the robot catches up with the obstacle and trails it; the Cartesian "
     "error stays below 0.06 m."),
    ("A", "Fig. 6(e-h)", "Fig. 6(e–h): MPCC overtaking a 0.6 m/s obstacle",
     "Paper A: with Q̄ = W̄ = diag(1, 1000), ρ = 50 the robot overtakes; the lag error stays near zero while "
     "the contouring error grows for a while, and v_avg stays near v_max."),
    ("B", "Table II", "Table II: step-position RMSE on the courses",
     "Paper B: the RMSE between the footholds and the stones' centres, ALIP-MPC against ALIP-QP, on profile I "
     "(Table II) and on seed 0 of profiles II–IV (§V-A). “fails”, “falls”: the paper's QP does not finish."),
    ("B", "Fig. 4", "Fig. 4: profile II, footprints of both planners",
     "Paper B: ALIP-MPC crosses profile II; ALIP-QP falls at the 14th step."),
    ("B", "Fig. 5", "Fig. 5: profile II, step durations and initial DCM",
     "Paper B: ALIP-MPC keeps the initial DCM within its viable bounds with smoother changes of step duration."),
    ("B", "Fig. 6", "Fig. 6: profiles III and IV, footprints of ALIP-MPC",
     "Paper B: ALIP-MPC crosses both (RMSE 0.027 and 0.024 m); ALIP-QP falls after a few steps."),
    ("B", "Fig. 7", "Fig. 7: the push test",
     "Paper B: 24 steps on (L, W) = (0.4, 0) m with pushes of +150 N (step 5), −150 N (10), +75 N lateral (15), "
     "−75 N (20); ALIP-MPC survives, ALIP-QP fails on the lateral pushes."),
)

#: what each figure of a study shows, by its file name
FIGURE_TEXT = {
    "circle": "the path (reference red, COM blue, footholds) and the contouring error",
    "circle-push": "the path with the pushes (arrows) and the contouring error, the pushes shaded",
    "overtake": "the path with the obstacle at four instants; the errors; the step offsets; v_avg against v_max",
    "footprints": "the stones (step bounds), the footholds, the COM and DCM paths",
    "durations_dcm": "the step durations (actual and planned) and the initial DCM within its viable bounds",
    "push_response": "COM velocity, step durations and initial DCM, the pushes shaded",
    "cop_offsets": "the centre-of-pressure offset the ALIP-MPC planned, within its box",
    "walk_top": "top view: COM and DCM paths, planned and actual footholds",
    "walk_tracking": "tracking: COM, speed, heights and tilt, swing-foot error",
    "stand": "standing under pushes: COM excursion and support feet",
    "stand_tracking": "tracking under pushes: COM, speed, heights and tilt",
    "wbc_timing": "the whole-body QP's time per tick against the real-time budget",
}

#: the figures paper B's Figs. 4-6 show: (item, course, planner or None for both, figure file name)
_B_FIGURES = (
    ("Fig. 4", ("II",), None, "footprints"),
    ("Fig. 5", ("II",), None, "durations_dcm"),
    ("Fig. 6", ("III", "IV"), "alip-mpc", "footprints"),
)


@dataclass
class _Ctx:
    """The report being built: the results, the reasons, the marks, the figures shown so far."""

    results: Mapping[str, Any]
    known: dict[str, Reason]
    marks: dict[str, Judgement]
    shown: set[str]
    number: int = 0

    def figure(self, name: str, path: str, titled: bool = True) -> Figure:
        """Figure ``path`` of study ``name``, numbered, captioned with what it shows (after the study's
        title unless ``titled`` is false: under a heading that names the study)."""
        self.shown.add(path)
        self.number += 1
        e = self.results["studies"][name]
        stem = PurePosixPath(path).stem
        what = FIGURE_TEXT.get(stem, stem.replace("_", " "))
        text = f"{e.get('title', name)}: {what}" if titled else what[0].upper() + what[1:]
        return Figure(self.number, path, f"{text} (`{name}`).", alt=f"{name}: {stem}")


def _studies(ctx: _Ctx, keep: Callable[[Mapping[str, Any]], bool]) -> list[tuple[str, Mapping[str, Any]]]:
    return [(n, e) for n, e in ctx.results["studies"].items() if keep(e)]


def _counts(e: Mapping[str, Any]) -> tuple[str, str]:
    """A study's solver failures and relaxed solves as table cells (``"–"`` when not recorded)."""
    def cell(key: str) -> str:
        return "–" if "error" in e or e.get(key) is None else str(e[key])

    return cell("solver_failures"), cell("relaxed_solves")


def _result(e: Mapping[str, Any]) -> str:
    return e["error"] if "error" in e else describe(e.get("ours") or {})


def _study_table(ctx: _Ctx, rows: Sequence[tuple[str, Mapping[str, Any]]], planner: bool = False) -> Table:
    """Each study beside the paper: its model (and planner), its numbers, the paper's, the mark, the
    solver failures and relaxed solves, the reason where it differs."""
    header = ["study", "model", *(["planner"] if planner else []), "ours", "paper", "mark", "solver failures",
              "relaxed solves", "why it differs"]
    out = []
    for n, e in rows:
        j = ctx.marks[n]
        out.append((f"`{n}`", model_name(e.get("robot"), e.get("cop_range")), *([e.get("planner") or "–"] if planner else []),
                    _result(e), paper_text(e.get("paper")), j.label, *_counts(e), j.why))
    return Table(tuple(header), tuple(out), mark_col=header.index("mark"))


def _table_ii(ctx: _Ctx, rows: Sequence[tuple[str, Mapping[str, Any]]]) -> Table:
    """Table II for one model: per course and planner, the step RMSE beside the paper's, the mark, how the run
    ended, the solver counts, the reason where it differs."""
    header = ("course", "planner", "step RMSE", "paper", "mark", "run", "solver failures", "relaxed solves",
              "why it differs")
    out = []
    for n, e in rows:
        j, ours = ctx.marks[n], e.get("ours") or {}
        if "error" in e:
            run, rmse = e["error"], "–"
        else:
            steps, lo, hi = ours.get("steps_completed"), ours.get("step_duration_min_s"), ours.get("step_duration_max_s")
            run = run_text(e) + (f", {steps} steps" if steps is not None else "")
            run += f", T {lo:.2f}–{hi:.2f} s" if isinstance(lo, (int, float)) and isinstance(hi, (int, float)) else ""
            rmse = length(ours.get("step_rmse_m"))
        out.append((str(e.get("course")), str(e.get("planner")), rmse, paper_text(e.get("paper")), j.label, run,
                    *_counts(e), j.why))
    return Table(header, tuple(out), mark_col=4)


def _figures_of(ctx: _Ctx, rows: Sequence[tuple[str, Mapping[str, Any]]], stem: str | None = None) -> list[Block]:
    return [ctx.figure(n, f) for n, e in rows for f in e.get("figures", [])
            if (stem is None or PurePosixPath(f).stem == stem) and f not in ctx.shown]


def _item_blocks(ctx: _Ctx, pid: str, item: str, heading: str, text: str) -> list[Block]:
    """One figure or table of a paper: the paper's claim, our results beside it, the figures."""
    blocks: list[Block] = [Heading(3, heading), Paragraph(text)]
    if pid == "B" and item == "Table II":
        rows = _studies(ctx, lambda e: e.get("paper_id") == "B" and e.get("item") == "Table II")
        steps = [s for _, e in rows if isinstance(s := (e.get("ours") or {}).get("steps_completed"), int)]
        if ctx.results.get("fast") and steps:
            blocks.append(Paragraph(f"Fast mode: the courses end after at most {max(steps)} steps of the paper's 32, "
                                    "so a fall the paper reports later in a course cannot show here."))
        for robot in dict.fromkeys(e.get("robot") for _, e in rows):
            blocks += [Paragraph(f"On the **{model_name(robot)}**:"),
                       _table_ii(ctx, [(n, e) for n, e in rows if e.get("robot") == robot])]
        side = models_table(dict(rows), ctx.marks)
        if side is not None:
            blocks += [Paragraph("The full body on each model, side by side (step RMSE, or how the run ended):"), side]
        return blocks
    for fig, courses, planner, stem in _B_FIGURES:
        if pid == "B" and item == fig:
            rows = _studies(ctx, lambda e: e.get("paper_id") == "B" and e.get("course") in courses
                            and (planner is None or e.get("planner") == planner))
            figs = _figures_of(ctx, rows, stem)
            return blocks + (figs or [Paragraph("No study of this report ran these courses.")])
    rows = _studies(ctx, lambda e: e.get("paper_id") == pid and e.get("item") == item)
    if not rows:
        return blocks + [Paragraph("No study of this report reproduces this (see `--only`).")]
    return blocks + [_study_table(ctx, rows, planner=(pid == "B"))] + _figures_of(ctx, rows)


def _solve_time(ctx: _Ctx, pid: str) -> list[Block]:
    """Our solve times beside the paper's, with the reason they differ."""
    med = [e["ours"]["solve_ms"]["median"] for _, e in _studies(ctx, lambda e: e.get("paper_id") == pid)
           if isinstance((e.get("ours") or {}).get("solve_ms"), Mapping) and "median" in e["ours"]["solve_ms"]]
    if not med:
        return []
    ref = paper.reference()
    theirs = ("12 ms mean per solve (CasADi + IPOPT, i7 2.6 GHz)" if pid == "A"
              else "%d–%d ms per solve (IPOPT)" % tuple(ref["paper_b"]["solver"]["solve_ms"]))
    why = ctx.known.get("solve-times")
    text = (f"**Solve times** on the reduced models: median {min(med):.2g}–{max(med):.2g} ms per solve here; "
            f"the paper: {theirs}." + (f" Why: {why.short} (`{why.doc}`)." if why else ""))
    return [Paragraph(text)]


def _paper_blocks(ctx: _Ctx, pid: str) -> list[Block]:
    blocks: list[Block] = [Heading(2, PAPERS[pid])]
    for p, item, heading, text in ITEMS:
        if p == pid:
            blocks += _item_blocks(ctx, pid, item, heading, text)
    return blocks + _solve_time(ctx, pid)


def _partial_banner(results: Mapping[str, Any]) -> list[Block]:
    """A report of a run that did not end (``status`` ``"running"`` or ``"interrupted"``) says so first,
    with the studies not run."""
    status = results.get("status", "complete")
    if status == "complete":
        return []
    done, rest = list(results["studies"]), list(results.get("not_run", []))
    why = "interrupted" if status == "interrupted" else "still running or stopped"
    text = f"**PARTIAL REPORT ({why})**: {len(done)} of {len(done) + len(rest)} studies ran."
    return [Paragraph(text + (" Not run: " + ", ".join(rest) + "." if rest else ""))]


def _summary(ctx: _Ctx) -> list[Block]:
    """The counts of each mark and outcome, why the command exits as it does, and the marks' legend."""
    res = ctx.results
    n = len(res["studies"])
    by_mark: dict[str, int] = {}
    for j in ctx.marks.values():
        by_mark[j.mark] = by_mark.get(j.mark, 0) + 1
    outcomes: dict[str, int] = {}
    for e in res["studies"].values():
        o = e.get("outcome")
        if o and o not in SUCCESS_OUTCOMES:
            outcomes[o.replace("_", " ")] = outcomes.get(o.replace("_", " "), 0) + 1
    trailing = sum(e.get("outcome") == "trailing" for e in res["studies"].values())
    mode = ("**Fast mode**: every run shortened (`--fast`), so the numbers are not taken under the papers' "
            "conditions." if res.get("fast") else "Full runs.")
    order = [*MARKS, "skipped"]
    shown = {"better": "better than the paper"}
    counts = ", ".join(f"{by_mark[k]} {'differ' if k == 'differs' and by_mark[k] > 1 else shown.get(k, k)}"
                       for k in sorted(by_mark, key=lambda k: order.index(k) if k in order else len(order)))
    ends = ", ".join(f"{v} {k}" for k, v in outcomes.items()) or "none"
    blocks: list[Block] = [Heading(2, "Summary"),
                           Paragraph(f"{mode} {n} studies in {res.get('wall_s', 0.0):.0f} s: {counts}. "
                                     f"Runs that did not complete: {ends}."
                                     + (f" Runs that trailed a slower obstacle along their path, as their preset "
                                        f"chooses: {trailing}." if trailing else ""))]
    bad = exit_failures(res)
    if bad:
        lines = [f"`{b}` ({ctx.marks[b].label}): {ctx.marks[b].why or res['studies'][b].get('error', '')}" for b in bad]
        blocks += [Paragraph(f"`lipmpcc reproduce` **exits 1**: {len(bad)} {'study misses' if len(bad) == 1 else 'studies miss'} "
                             "its criterion or could not run. It reports such a result as it is:"), Bullets(tuple(lines))]
    else:
        blocks.append(Paragraph("`lipmpcc reproduce` exits 0: every study met its criterion or failed as expected."))
    blocks += [Paragraph("**Marks.** Each result stands beside the paper's, with a mark:"),
               Bullets(tuple(f"**{k}**: {v}" for k, v in MARKS.items())),
               Paragraph("A mark is followed by how the run ended when it did not complete (fell, collided, stopped "
                         "early, stalled, incomplete; trailing: behind a slower obstacle along the path, the preset's "
                         "choice). Models: the **3D-LIP** and the **ALIP** are the papers' planning models (the reduced "
                         "loops); **digit_like** is the full body in MuJoCo under the whole-body QP, in place of the "
                         "papers' Digit; a model named by its file (`--robot MODEL.xml`, such as Digit v3) is "
                         "another full body, under the same studies.")]
    return blocks


def _contents(blocks: Sequence[Block]) -> Bullets:
    return Bullets(tuple(f"[{b.text}](#{slug(b.text)})" for b in blocks if isinstance(b, Heading) and b.level == 2))


def _models(ctx: _Ctx) -> list[Block]:
    """Every full-body study with one column per model, when more than one model ran them
    (``lipmpcc reproduce --robot MODEL.xml``)."""
    table = models_table(ctx.results["studies"], ctx.marks)
    if table is None:
        return []
    names = ", ".join(f"**{model_name(r)}**" for r in full_body_robots(ctx.results["studies"]))
    return [Heading(2, "The full body on each model"),
            Paragraph(f"Each full-body study on {names}, beside the paper's claim: the result, its mark and its "
                      "solver failures and relaxed solves. The rows are the studies' names on digit_like; the "
                      "other model's studies are named with its prefix (`lipmpcc reproduce --robot MODEL.xml`)."),
            table]


def _beyond(ctx: _Ctx) -> list[Block]:
    """The studies beyond the papers, and those without a place (an older results.json)."""
    blocks: list[Block] = []
    extra = _studies(ctx, lambda e: "paper_id" in e and not e.get("paper_id"))
    if extra:
        blocks += [Heading(2, "Beyond the papers"),
                   Paragraph("The low-level loop alone, on the full body: not in the papers, checked on their own criteria."),
                   _study_table(ctx, extra)] + _figures_of(ctx, extra)
    other = _studies(ctx, lambda e: "paper_id" not in e)
    if other:
        blocks += [Heading(2, "Other studies"), _study_table(ctx, other)]
    return blocks


def _reasons(ctx: _Ctx) -> list[Block]:
    """Every reason in full, with the studies of this report it explains."""
    used: dict[str, list[str]] = {}
    for n, j in ctx.marks.items():
        for r in j.reasons:
            used.setdefault(r.key, []).append(n)
    items = []
    for key, r in ctx.known.items():
        where = ", ".join(f"`{n}`" for n in used.get(key, []))
        if key == "solve-times":
            where = "every solve time"
        items.append(f"**{_cap(r.short)}.** {_cap(r.text)}. See `{r.doc}`. Applies here to: "
                     f"{where or 'no study of this report'}.")
    return [Heading(2, "Where and why the results differ from the papers"),
            Paragraph("The reasons are kept in `data/reference/paper_results.json` (`reasons`) and explained in "
                      "`docs/design.md`."), Bullets(tuple(items))]


def _cap(text: str) -> str:
    """``text`` with a capital first letter, unless it starts with a name (``digit_like``, ``alip-qp``)."""
    first = text.split(" ", 1)[0]
    return text if "_" in first or "-" in first.rstrip("-") or first.lower() != first else text[:1].upper() + text[1:]


def _warnings(ctx: _Ctx) -> list[Block]:
    warned = [f"`{n}`: {w}" for n, e in ctx.results["studies"].items() for w in e.get("warnings") or []]
    return [Heading(2, "Warnings of the runs"), Bullets(tuple(warned))] if warned else []


def _appendix(ctx: _Ctx) -> list[Block]:
    """Every figure not shown above, once, under its study."""
    blocks: list[Block] = []
    for n, e in ctx.results["studies"].items():
        figs = [f for f in e.get("figures", []) if f not in ctx.shown]
        if figs:
            blocks += [Heading(3, f"{e.get('title', n)} (`{n}`)")] + [ctx.figure(n, f, titled=False) for f in figs]
    return [Heading(2, "Appendix: the other figures of the runs")] + blocks if blocks else []


def report_blocks(results: Mapping[str, Any]) -> list[Block]:
    """The report of ``results`` (the content of ``results.json``) as blocks, in reading order."""
    known = reasons()
    # a study repeated on another model (--robot) takes the reasons of the study it repeats (its variant)
    ctx = _Ctx(results, known, {n: judge(str(e.get("variant") or n), e, known) for n, e in results["studies"].items()},
               set())
    body: list[Block] = []
    for pid in PAPERS:
        if _studies(ctx, lambda e, pid=pid: e.get("paper_id") == pid):
            body += _paper_blocks(ctx, pid)
    body += _models(ctx) + _beyond(ctx) + _reasons(ctx) + _warnings(ctx) + _appendix(ctx)
    head = [Heading(1, TITLE), *_partial_banner(results)]
    summary = _summary(ctx)
    return head + summary + [Paragraph("**Contents**"), _contents(summary + body)] + body
