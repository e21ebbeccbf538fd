"""A report as a list of blocks (headings, paragraphs, lists, tables, figures), written as markdown
(:func:`to_markdown`) or as one self-contained HTML page (:func:`to_html`: the figures embedded as
base64 ``data:`` URIs, a small style sheet, no script, so that it reads offline).

Text in a block may use three inline marks, the same in both outputs: ``**bold**``, ```code``` and
``[text](link)``.
"""

from __future__ import annotations

import base64
import html
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence, Union

from .tables import md_table

__all__ = ["Heading", "Paragraph", "Bullets", "Table", "Figure", "Block", "slug", "to_markdown", "to_html", "inline_html"]


@dataclass(frozen=True)
class Heading:
    """A heading of ``level`` 1 (the title) to 4; its anchor is :func:`slug` of its text."""

    level: int
    text: str

    @property
    def anchor(self) -> str:
        return slug(self.text)


@dataclass(frozen=True)
class Paragraph:
    """A paragraph of text."""

    text: str


@dataclass(frozen=True)
class Bullets:
    """A bulleted list, one item per line."""

    items: tuple[str, ...]


@dataclass(frozen=True)
class Table:
    """A table: ``header`` and ``rows`` of text cells; column ``mark_col`` (if any) holds a mark
    (``pass``, ``differs``, ...), coloured in the HTML page."""

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]
    mark_col: int | None = None


@dataclass(frozen=True)
class Figure:
    """Figure ``number``: an image at ``path`` (relative to the report's folder) with its ``caption``."""

    number: int
    path: str
    caption: str
    alt: str = field(default="")


Block = Union[Heading, Paragraph, Bullets, Table, Figure]


def slug(text: str) -> str:
    """The anchor of a heading as GitHub makes it: lower case, punctuation dropped, spaces to ``-``."""
    text = re.sub(r"[*`]", "", text.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def to_markdown(blocks: Sequence[Block]) -> str:
    """The blocks as markdown (figures as images with their relative paths, the caption above)."""
    out: list[str] = []
    for b in blocks:
        if isinstance(b, Heading):
            out.append("#" * b.level + " " + b.text)
        elif isinstance(b, Paragraph):
            out.append(b.text)
        elif isinstance(b, Bullets):
            out.append("\n".join(f"- {item}" for item in b.items))
        elif isinstance(b, Table):
            out.append(md_table(b.header, b.rows))
        elif isinstance(b, Figure):
            out.append(f"**Figure {b.number}.** {b.caption}\n\n![{b.alt or f'Figure {b.number}'}]({b.path})")
        out.append("")
    return "\n".join(out)


_INLINE = [
    (re.compile(r"`([^`]+)`"), r"<code>\1</code>"),
    (re.compile(r"\*\*([^*]+)\*\*"), r"<strong>\1</strong>"),
    (re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)"), r'<a href="\2">\1</a>'),
]


def inline_html(text: str) -> str:
    """``text`` escaped for HTML, with its inline marks (bold, code, links) as tags."""
    out = html.escape(text, quote=False)
    for pattern, repl in _INLINE:
        out = pattern.sub(repl, out)
    return out


CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; max-width: 72rem; margin: 2rem auto;
       padding: 0 1rem; line-height: 1.45; color: #222; }
h1, h2, h3 { line-height: 1.2; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2rem; margin-top: 2.5rem; }
table { border-collapse: collapse; margin: .8rem 0; font-size: .88rem; }
th, td { border: 1px solid #ccc; padding: .25rem .45rem; vertical-align: top; text-align: left; }
th { background: #f2f2f2; } tr:nth-child(even) td { background: #fafafa; }
code { background: #f3f3f3; padding: 0 .2rem; border-radius: 3px; font-size: .9em; } td code { white-space: nowrap; }
figure { margin: 1.2rem 0; } figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: .9rem; color: #444; margin-top: .3rem; }
.mark { font-weight: 600; white-space: nowrap; } .mark-pass { color: #1a7f37; } .mark-differs { color: #b35900; }
.mark-expected-fail { color: #5a5a9e; } .mark-error, .mark-skipped { color: #b00020; }
.missing { color: #b00020; }
"""


def _mark_cell(text: str) -> str:
    kind = re.split(r"[ :,]", text, maxsplit=1)[0] if text else ""  # "pass, better than the paper (3.1×)": pass
    return f'<span class="mark mark-{html.escape(kind)}">{inline_html(text)}</span>'


def _table_html(t: Table) -> str:
    head = "".join(f"<th>{inline_html(h)}</th>" for h in t.header)
    rows = []
    for r in t.rows:
        cells = [(_mark_cell(c) if i == t.mark_col else inline_html(c)) for i, c in enumerate(r)]
        rows.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    return f"<table>\n<thead><tr>{head}</tr></thead>\n<tbody>\n" + "\n".join(rows) + "\n</tbody>\n</table>"


def _figure_html(f: Figure, root: Path) -> str:
    cap = f"<figcaption><strong>Figure {f.number}.</strong> {inline_html(f.caption)}</figcaption>"
    src = root / f.path
    if not src.is_file():
        return f'<figure><p class="missing">image not found: {html.escape(f.path)}</p>{cap}</figure>'
    data = base64.b64encode(src.read_bytes()).decode("ascii")
    alt = html.escape(f.alt or f"Figure {f.number}")
    return f'<figure id="figure-{f.number}"><img alt="{alt}" src="data:image/png;base64,{data}">{cap}</figure>'


def to_html(blocks: Sequence[Block], root: str | Path, title: str) -> str:
    """The blocks as one HTML page, each figure read from ``root`` and embedded (a missing image is
    named in its place)."""
    root = Path(root)
    body: list[str] = []
    for b in blocks:
        if isinstance(b, Heading):
            body.append(f'<h{b.level} id="{b.anchor}">{inline_html(b.text)}</h{b.level}>')
        elif isinstance(b, Paragraph):
            body.append(f"<p>{inline_html(b.text)}</p>")
        elif isinstance(b, Bullets):
            body.append("<ul>\n" + "\n".join(f"<li>{inline_html(i)}</li>" for i in b.items) + "\n</ul>")
        elif isinstance(b, Table):
            body.append(_table_html(b))
        elif isinstance(b, Figure):
            body.append(_figure_html(b, root))
    return (f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>{html.escape(title)}</title>\n'
            f"<style>{CSS}</style>\n</head>\n<body>\n" + "\n".join(body) + "\n</body>\n</html>\n")
