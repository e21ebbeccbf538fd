"""A report as blocks, written as markdown and as one self-contained HTML page."""

from __future__ import annotations

import base64
from html.parser import HTMLParser

from lipmpcc.report.document import Bullets, Figure, Heading, Paragraph, Table, inline_html, slug, to_html, to_markdown


class Tags(HTMLParser):
    """The tags of a page, with their attributes; fails on an unclosed element of the report's kinds."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []
        self.open: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        if tag not in ("meta", "img", "br"):
            self.open.append(tag)

    def handle_endtag(self, tag):
        assert self.open and self.open[-1] == tag, (tag, self.open[-3:])
        self.open.pop()


def _png(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(1, 1))
    fig.savefig(tmp_path / "a.png", dpi=20)
    plt.close(fig)
    return (tmp_path / "a.png").read_bytes()


BLOCKS = [Heading(1, "Title"), Heading(2, "Paper A: Fig. 5(a,b)"), Paragraph("**bold** and `code` [link](#x)"),
          Bullets(("one", "two")), Table(("s", "mark"), (("a | b", "differs: collided"),), mark_col=1),
          Figure(1, "a.png", "a caption", alt="alt")]


def test_markdown_has_each_block_and_the_figure_under_its_caption() -> None:
    md = to_markdown(BLOCKS)
    assert md.startswith("# Title\n\n## Paper A: Fig. 5(a,b)\n\n**bold** and `code` [link](#x)\n\n- one\n- two\n")
    assert "| s | mark |\n|---|---|\n| a \\| b | differs: collided |" in md
    assert "**Figure 1.** a caption\n\n![alt](a.png)" in md


def test_html_is_one_parseable_page_with_the_images_embedded(tmp_path) -> None:
    png = _png(tmp_path)
    page = to_html(BLOCKS, tmp_path, "T")
    parser = Tags()
    parser.feed(page)
    assert parser.open == []  # every element closed
    imgs = [a for t, a in parser.tags if t == "img"]
    assert len(imgs) == 1 and imgs[0]["src"].startswith("data:image/png;base64,")
    assert base64.b64decode(imgs[0]["src"].split(",", 1)[1]) == png
    assert not [a for t, a in parser.tags if t in ("script", "link")]  # nothing to fetch: it reads offline
    assert ("h2", {"id": "paper-a-fig-5ab"}) in parser.tags
    assert '<span class="mark mark-differs">differs: collided</span>' in page and "a | b" in page


def test_a_missing_image_is_named_in_its_place(tmp_path) -> None:
    page = to_html([Figure(3, "gone/x.png", "c")], tmp_path, "T")
    assert "image not found: gone/x.png" in page and "<strong>Figure 3.</strong> c" in page


def test_inline_marks_and_anchors() -> None:
    assert inline_html("a < b **c** `d` [e](#f)") == 'a &lt; b <strong>c</strong> <code>d</code> <a href="#f">e</a>'
    assert slug("Fig. 6(a–d): Cartesian MPC") == "fig-6ad-cartesian-mpc"
