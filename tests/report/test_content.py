"""What the report says: both papers in order, each result beside the paper's with its mark and reason,
every figure once, the solver counts, the exit status."""

from __future__ import annotations

import re

from lipmpcc.report.content import report_blocks
from lipmpcc.report.document import Figure, Heading, Table, to_markdown

from .synthetic import results


def _headings(blocks, level):
    return [b.text for b in blocks if isinstance(b, Heading) and b.level == level]


def test_paper_a_then_paper_b_each_in_the_papers_order() -> None:
    blocks = report_blocks(results())
    h2 = _headings(blocks, 2)
    assert h2[0] == "Summary"
    a, b = h2.index(next(h for h in h2 if h.startswith("Paper A"))), h2.index(next(h for h in h2 if h.startswith("Paper B")))
    assert 0 < a < b < h2.index("Beyond the papers") < h2.index("Where and why the results differ from the papers")
    h3 = [h.split(":")[0] for h in _headings(blocks, 3)]
    assert h3[:9] == ["Fig. 5(a,b)", "Fig. 5(c,d)", "Fig. 6(a–d)", "Fig. 6(e–h)", "Table II", "Fig. 4", "Fig. 5", "Fig. 6",
                      "Fig. 7"]


def test_every_figure_once_numbered_in_order() -> None:
    res = results()
    figs = [b for b in report_blocks(res) if isinstance(b, Figure)]
    paths = [f.path for f in figs]
    assert sorted(paths) == sorted(p for e in res["studies"].values() for p in e["figures"])  # each exactly once
    assert [f.number for f in figs] == list(range(1, len(figs) + 1))
    assert all(f.caption.endswith("`).") for f in figs)  # each names its study
    assert paths.index("alip-stones-II-alip-mpc/footprints.png") < paths.index("alip-stones-II-alip-mpc/durations_dcm.png")
    # profile I's footprints are in no figure of paper B: in the appendix, after the papers
    assert paths[-1] == "alip-stones-I_L0.2_W+0.15-alip-qp/footprints.png"


def _row(md: str, start: str) -> list[str]:
    line = next(ln for ln in md.splitlines() if ln.startswith(start))
    return [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]


def test_results_beside_the_paper_with_marks_solver_counts_and_reasons() -> None:
    md = to_markdown(report_blocks(results()))
    row = _row(md, "| `digit-overtake-mpcc` |")
    assert row[4:7] == ["differs: collided", "4", "0"] and "thigh" in row[7]
    assert "**collides with the obstacle**" in row[2] and "{" not in row[3]  # the paper's claim as text, no dict
    push = _row(md, "| `alip-push-alip-mpc` |")
    assert push[5] == "expected-fail: fell" and "point foot" in push[8]
    relaxed = _row(md, "| `digit-push-alip-mpc` |")
    assert relaxed[5:8] == ["pass", "11", "11"]  # relaxed solves shown
    table_ii = _row(md, "| II | alip-mpc |")
    assert table_ii[2:5] == ["0.003 m", "0.023 m", "pass, better than the paper (7.4×)"] and "exactly" in table_ii[8]
    assert _row(md, "| I L=0.2 W=+0.15 | alip-qp |")[4] == "pass"
    assert "`lip-circle` | 3D-LIP | max contouring error 0.012 m; solve time median 1.3 ms, p90 1.5 ms" in md


def test_the_summary_counts_the_marks_and_explains_the_exit_status() -> None:
    md = to_markdown(report_blocks(results()))
    assert ("7 studies in 12 s: 4 pass, 1 better than the paper, 1 expected-fail, 1 differs. Runs that did not complete: "
            "1 fell, 1 collided.") in md
    assert "**better**: pass, better than the paper" in md  # the legend
    summary = md.split("## Paper A")[0]
    assert "**exits 1**" in summary and "`digit-overtake-mpcc` (differs: collided)" in summary
    assert "**expected-fail**:" in summary and "Fast mode" in summary
    assert "Fast mode: the courses end after at most 16 steps" in md


def test_a_partial_report_says_so_first_and_an_older_results_json_still_reads() -> None:
    res = results()
    res.update(status="interrupted", not_run=["lip-circle-push"])
    res["studies"]["old"] = {"title": "Old", "ours": {"err": 0.1}, "paper": 0.2, "criterion": "c",
                             "meets_criterion": True, "figures": []}
    blocks = report_blocks(res)
    md = to_markdown(blocks)
    assert md.splitlines()[2] == "**PARTIAL REPORT (interrupted)**: 8 of 9 studies ran. Not run: lip-circle-push."
    assert "Other studies" in _headings(blocks, 2) and "| `old` |" in md
    assert all(isinstance(b.rows, tuple) for b in blocks if isinstance(b, Table))


def test_the_reasons_in_full_name_the_studies_they_explain() -> None:
    md = to_markdown(report_blocks(results()))
    why = md.split("## Where and why the results differ from the papers")[1].split("\n## ")[0]
    line = next(ln for ln in why.splitlines() if "thigh" in ln)
    assert line.startswith("- **The body disk holds") and line.endswith("Applies here to: `digit-overtake-mpcc`.")
    assert "- **digit_like (and Digit v3) has a foot" in why  # a name keeps its spelling
    assert "Applies here to: no study of this report." in why  # a reason this run did not need is still listed
