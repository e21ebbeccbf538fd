"""The files of the reproduction report: ``results.json`` (each study's results beside the paper's),
``report.md`` and ``report.html`` (the same report as one self-contained page, the figures embedded),
each written through a file renamed over it."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping

from ..studies.outputs import write_text_atomic
from .content import TITLE, report_blocks
from .document import to_html, to_markdown

__all__ = ["REPORT_FILE", "HTML_FILE", "RESULTS_FILE", "report_markdown", "report_html", "write_report"]

REPORT_FILE = "report.md"
HTML_FILE = "report.html"
RESULTS_FILE = "results.json"


def report_markdown(results: Mapping[str, Any]) -> str:
    """``report.md`` of ``results`` (the content of ``results.json``): :func:`~lipmpcc.report.content.report_blocks`
    as markdown, the figures linked by their paths relative to the report."""
    return to_markdown(report_blocks(results))


def report_html(results: Mapping[str, Any], root: str | Path) -> str:
    """``report.html``: the same report as one HTML page, the figures read from ``root`` (the report's
    folder) and embedded as base64 ``data:`` URIs."""
    return to_html(report_blocks(results), root, TITLE)


def write_report(results: Mapping[str, Any], out: str | Path) -> Path:
    """Write ``results.json``, ``report.md`` and ``report.html`` to the folder ``out``, each through a file
    renamed over it; returns the path of ``report.md``."""
    out = Path(out)
    write_text_atomic(out / RESULTS_FILE, json.dumps(results, indent=2, default=str))
    blocks = report_blocks(results)
    write_text_atomic(out / REPORT_FILE, to_markdown(blocks))
    write_text_atomic(out / HTML_FILE, to_html(blocks, out, TITLE))
    return out / REPORT_FILE
