"""results.json, report.md and report.html written whole, the HTML self-contained."""

from __future__ import annotations

import json
import re

from lipmpcc.report import HTML_FILE, REPORT_FILE, RESULTS_FILE, report_markdown, write_report

from .synthetic import results, write_figures
from .test_document import Tags


def test_the_three_files_and_every_figure_they_reference_exists(tmp_path) -> None:
    res = results()
    write_figures(res, tmp_path)
    assert write_report(res, tmp_path) == tmp_path / REPORT_FILE
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_file()) == [HTML_FILE, REPORT_FILE, RESULTS_FILE]
    assert json.loads((tmp_path / RESULTS_FILE).read_text()) == res
    md = (tmp_path / REPORT_FILE).read_text()
    assert md == report_markdown(res)
    linked = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md)
    assert linked and all((tmp_path / p).is_file() for p in linked) and len(linked) == len(set(linked))
    parser = Tags()
    parser.feed((tmp_path / HTML_FILE).read_text())
    srcs = [a["src"] for t, a in parser.tags if t == "img"]
    assert len(srcs) == len(linked) and all(s.startswith("data:image/png;base64,") for s in srcs)
    hrefs = [a["href"] for t, a in parser.tags if t == "a"]
    assert hrefs and all(h.startswith("#") for h in hrefs)  # nothing outside the page
    ids = {a.get("id") for t, a in parser.tags}
    assert all(h[1:] in ids for h in hrefs)  # every link of the contents lands on a heading
