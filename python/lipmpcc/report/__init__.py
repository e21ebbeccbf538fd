"""The reproduction report of ``lipmpcc reproduce`` and the stepping-stone tables.

Modules:
    tables -- markdown tables: :func:`md_table`, :func:`fmt`, Table II and the push sweep.
    document -- a report as blocks, written as markdown or as one self-contained HTML page.
    values -- a study's numbers as text, with units.
    marks -- a study's mark beside the paper (pass, expected-fail, differs) and the reasons.
    models -- the full-body studies with one column per model (digit_like, lipmpcc reproduce --robot).
    content -- what the report says, in the papers' order.
    files -- ``results.json``, ``report.md`` and ``report.html``.
"""

from __future__ import annotations

from .files import HTML_FILE, REPORT_FILE, RESULTS_FILE, report_html, report_markdown, write_report
from .marks import judge
from .tables import fmt, md_table, sweep_markdown, table_markdown

__all__ = ["REPORT_FILE", "HTML_FILE", "RESULTS_FILE", "md_table", "fmt", "report_markdown", "report_html",
           "write_report", "table_markdown", "sweep_markdown", "judge"]
