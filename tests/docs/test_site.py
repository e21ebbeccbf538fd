"""The rendered site (``tools/build_docs.py``): it builds with warnings as errors, each notebook of the book
executes without error (in fast mode) and its page shows every figure it made, every public module has its
API page, nothing is fetched from outside the site, and in a real headless Chromium the pages load without a
console error, their equations typeset (MathJax's output elements) and their images load.

The notebooks execute once here (the book, two kernels at a time); ``notebooks/`` is not collected again by
nbval in the default run (pyproject.toml's ``testpaths``). Outside CI a missing docs package or a missing
Chromium skips with the reason; in CI (``CI`` set) it fails.
"""

from __future__ import annotations

import functools
import http.server
import importlib.util
import json
import os
import re
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from html.parser import HTMLParser
from pathlib import Path

import pytest

from ..conftest import REPO, package_env

_spec = importlib.util.spec_from_file_location("lipmpcc_build_docs", REPO / "tools" / "build_docs.py")
build_docs = importlib.util.module_from_spec(_spec)
sys.modules.setdefault(_spec.name, build_docs)
_spec.loader.exec_module(build_docs)

NOTEBOOKS = build_docs.book_notebooks()
DESIGN_PAGES = ["architecture", "design", "formats", "benchmarks", "sweeps", "changelog"]
#: a notebook whose code draws: its page must show at least one figure
PLOTS = re.compile(r"\bplt\.|\.plot\(|\bplot_\w+\(|\bfigure_\w+\(|\bsubplots\(|\bImage\(")


def _unavailable(reason: str) -> None:
    """Skip outside CI; fail in CI, where every part of the site test must run."""
    if os.environ.get("CI"):
        pytest.fail(f"{reason} (in CI this must not be missing: .ci/run installs it)")
    pytest.skip(reason)


@dataclass
class Site:
    out: Path
    returncode: int
    log: str
    seconds: float
    runs: dict


@pytest.fixture(scope="session")
def site(tmp_path_factory) -> Site:
    """The site built once, as ``tools/build_docs.py`` builds it (``-W --keep-going``), into a fresh folder."""
    for mod in ("sphinx", "myst_nb", "furo", "nbclient", "ipykernel"):
        if importlib.util.find_spec(mod) is None:
            _unavailable(f"{mod} is not installed (pip install '.[docs]')")
    if importlib.util.find_spec("sphinx-mathjax-offline") is None:
        _unavailable("sphinx-mathjax-offline is not installed (pip install '.[docs]')")
    out = tmp_path_factory.mktemp("site") / "html"
    env = package_env()
    env.setdefault("LIPMPCC_FAST", "1")
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", "-q",
                           str(build_docs.DOCS), str(out)], env=env, capture_output=True, text=True, cwd=REPO)
    seconds = time.perf_counter() - t0
    runs = {p.stem: build_docs._read_run(build_docs.BOOK_DIR / p.name, None) for p in NOTEBOOKS}
    print(f"[docs] site built in {seconds:.0f} s (exit {proc.returncode})")
    return Site(out, proc.returncode, proc.stdout + proc.stderr, seconds, runs)


def _warnings(log: str) -> str:
    lines = [ln for ln in log.splitlines() if "WARNING" in ln or "ERROR" in ln or "Error" in ln]
    return "\n".join(lines[:60]) or log[-4000:]


def test_site_builds_without_warnings(site: Site) -> None:
    assert site.returncode == 0, f"sphinx -W failed:\n{_warnings(site.log)}"
    assert (site.out / "index.html").is_file()


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_executes(site: Site, notebook: Path) -> None:
    run = site.runs[notebook.stem]
    assert run is not None, f"{notebook.name} was not executed into docs/book/"
    assert not run.errors, "\n\n".join(
        f"code cell {e['cell']}: {e['ename']}: {e['evalue']}\n{e['traceback']}" for e in run.errors)


class _Images(HTMLParser):
    """The ``src`` of every ``<img>`` of a page, and of those inside a notebook cell's output."""

    def __init__(self) -> None:
        super().__init__()
        self.stack: list[bool] = []
        self.all: list[str] = []
        self.outputs: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "div":
            self.stack.append("cell_output" in (a.get("class") or "").split())
        elif tag == "img" and a.get("src"):  # an <img> without src is a script's (an animation's frame holder)
            self.all.append(a["src"])
            if any(self.stack):
                self.outputs.append(a["src"])

    def handle_endtag(self, tag):
        if tag == "div" and self.stack:
            self.stack.pop()


def _images(page: Path) -> _Images:
    parser = _Images()
    parser.feed(page.read_text(encoding="utf-8"))
    return parser


def _image_ok(page: Path, src: str) -> str | None:
    """Why the image ``src`` of ``page`` would not show (``None`` when it is a data URI or a real image file)."""
    if src.startswith("data:image/"):
        return None
    path = (page.parent / src.split("#")[0].split("?")[0]).resolve()
    if not path.is_file():
        return f"{src}: no such file"
    head = path.read_bytes()[:16]
    if not (head.startswith(b"\x89PNG") or head.startswith(b"GIF8") or head.startswith(b"\xff\xd8")
            or b"<svg" in path.read_bytes()[:400]):
        return f"{src}: not an image"
    return None


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_page_shows_its_figures(site: Site, notebook: Path) -> None:
    """A notebook's page has an image per image output of the executed notebook (a file that exists or a
    data URI), and a notebook that draws has at least one."""
    run = site.runs[notebook.stem]
    page = site.out / "book" / f"{notebook.stem}.html"
    assert page.is_file(), f"no page for {notebook.name}"
    assert run is not None
    imgs = _images(page)
    assert len(imgs.outputs) == run.images, (
        f"{page.name}: {len(imgs.outputs)} images in the cell outputs, the executed notebook made {run.images}")
    code = "\n".join("".join(c["source"]) for c in json.loads(notebook.read_text(encoding="utf-8"))["cells"]
                      if c["cell_type"] == "code")
    if PLOTS.search(code):
        assert run.images >= 1, f"{notebook.name} draws but its page shows no figure"
    bad = [why for src in imgs.all if (why := _image_ok(page, src))]
    assert not bad, f"{page.name}: " + "; ".join(bad)


@pytest.mark.parametrize("notebook", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_page_links_the_api_it_uses(site: Site, notebook: Path) -> None:
    """The names of a notebook's "**API used:**" line link to their API pages, and its exercises ran with
    their solutions (every check printed "solved")."""
    cells = json.loads(notebook.read_text(encoding="utf-8"))["cells"]
    api = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
    names = re.findall(r"`(lipmpcc(?:\.\w+)+)`", api.partition("**API used:**")[2].partition("\n\n")[0])
    page = (site.out / "book" / f"{notebook.stem}.html").read_text(encoding="utf-8")
    if names:
        linked = set(re.findall(r'href="\.\./api/(lipmpcc[\w.]*)\.html', page))
        assert linked, f"{notebook.name}: none of its {len(names)} API names links to an API page"
    code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    if "@ex.check(" in code:
        assert "solved (by the solution in notebooks/solutions/)" in page and "not yet solved (fill in" not in page


def test_offline_outputs_drop_the_cdn_and_solution_links() -> None:
    import nbformat

    html = ('<link rel="stylesheet"\n href="https://maxcdn.bootstrapcdn.com/font-awesome/4.4.0/css/font-awesome.min.css">\n'
            '<button><i class="fa fa-play"></i></button>')
    cell = nbformat.v4.new_code_cell("anim")
    cell.outputs = [nbformat.v4.new_output("display_data", data={"text/html": html})]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell("See [the solution](solutions/01_x.py)."), cell])
    assert build_docs.offline_outputs(nb) == 3
    assert nb.cells[0].source == "See the solution."
    out = nb.cells[1].outputs[0]["data"]["text/html"]
    assert "http" not in out and "<button>▶</button>" in out


def test_site_tags_collapse_drawing_code_and_drop_install_hints() -> None:
    """A cell that is mostly drawing and made a figure gets ``hide-input``; a computing cell, an exercise and a
    cell without a figure keep their code shown; the ipywidgets hint leaves a cell's output, its figure stays."""
    import nbformat

    png = nbformat.v4.new_output("display_data", data={"image/png": "AA"})
    draw = "\n".join(["fig, ax = plt.subplots()", "ax.plot(t, x)", "ax.set(xlabel='t [s]')", "ax.legend()",
                      "for a in axs:", "    a.grid(True)", "x = f(t)", "plt.show()"])
    compute = "\n".join([f"x{i} = solve(problem, {i})" for i in range(8)] + ["ax.plot(x0)"])
    cells = [nbformat.v4.new_code_cell(draw), nbformat.v4.new_code_cell(compute), nbformat.v4.new_code_cell(draw),
             nbformat.v4.new_code_cell("@ex.check(f)\n" + draw), nbformat.v4.new_code_cell("interact(f)")]
    for c in cells[:2] + cells[3:4]:
        c.outputs = [png]
    cells[4].outputs = [png, nbformat.v4.new_output("stream", name="stdout", text="ipywidgets is not installed: pip "
                                                    "...\n  and restart\n"),
                        nbformat.v4.new_output("stream", name="stdout", text="kept\nipywidgets is not installed\n")]
    nb = nbformat.v4.new_notebook(cells=cells)
    assert build_docs.site_tags(nb) == 3 and build_docs.site_tags(nb) == 0
    tags = [c.metadata.get("tags", []) for c in nb.cells]
    assert tags == [["hide-input"], [], [], [], []]
    assert [o.get("text", "image") for o in nb.cells[4].outputs] == ["image", "kept\n"]  # the figure stays


def test_bars_inside_table_cells_are_escaped_for_the_site() -> None:
    """md_table's rows separate columns with " | "; a bar inside a cell (an absolute value) would add a column,
    and a header with more cells than its delimiter row renders as pipes: it is escaped, the rest is kept."""
    import nbformat

    cell = nbformat.v4.new_code_cell("md_table(...)")
    cell.outputs = [nbformat.v4.new_output("display_data", data={"text/markdown": (
        "Title\n\n| quantity | max |·| |\n|---|:--|\n| a \\| b | max |ē_c| ≤ 0.1 |\n|  | 3 |\n\ntext |x| here")})]
    nb = nbformat.v4.new_notebook(cells=[cell])
    assert build_docs.site_tags(nb) == 1 and build_docs.site_tags(nb) == 0
    assert cell.outputs[0]["data"]["text/markdown"] == (
        "Title\n\n| quantity | max \\|·\\| |\n|---|:--|\n| a \\| b | max \\|ē_c\\| ≤ 0.1 |\n|  | 3 |\n\ntext |x| here")


def test_the_api_index_groups_modules_by_layer_with_summaries() -> None:
    modules = ["lipmpcc.paths", "lipmpcc.models.lip", "lipmpcc.planners.mpcc", "lipmpcc.course.grader", "lipmpcc.cli"]
    text = build_docs.api_index(modules)
    heads = [ln for ln in text.splitlines() if ln.startswith("## ")]
    assert [h.split(":")[0] for h in heads] == ["## Foundations", "## Models", "## Planners", "## The course", "## Command line"]
    line = next(ln for ln in text.splitlines() if "lipmpcc.paths.rst" in ln)
    assert line.startswith("- [`lipmpcc.paths`](lipmpcc.paths.rst): ") and len(line.split("): ", 1)[1]) > 10


def test_link_api_links_only_the_api_paragraph_once() -> None:
    import nbformat

    nb = nbformat.v4.new_notebook(cells=[
        nbformat.v4.new_markdown_cell("Uses `lipmpcc.paths.Path`.\n\n**API used:** `lipmpcc.paths.Path`, `x.y`,\n"
                                      "`lipmpcc.models.lip.dcm`.\n\nLater `lipmpcc.paths.Path`."),
        nbformat.v4.new_code_cell("`lipmpcc.paths.Path`")])
    assert build_docs.link_api(nb) == 2 and build_docs.link_api(nb) == 0
    md = nb.cells[0].source
    assert md.startswith("Uses `lipmpcc.paths.Path`.") and md.endswith("Later `lipmpcc.paths.Path`.")
    assert "{py:obj}`lipmpcc.paths.Path`, `x.y`,\n{py:obj}`lipmpcc.models.lip.dcm`" in md
    assert nb.cells[1].source == "`lipmpcc.paths.Path`"


def test_every_public_module_has_its_api_page(site: Site) -> None:
    """Each public module (``__all__``, no ``_`` part) has ``api/<module>.html`` with its module target, an
    entry for each name it defines and a link for each name it re-exports."""
    modules = build_docs.public_modules()
    assert len(modules) > 50 and "lipmpcc.paths" in modules and not any("._" in m for m in modules)
    public = set(modules)
    problems = []
    for mod in modules:
        page = site.out / "api" / f"{mod}.html"
        if not page.is_file():
            problems.append(f"{mod}: no page")
            continue
        html = page.read_text(encoding="utf-8")
        if f'id="module-{mod}"' not in html:
            problems.append(f"{mod}: no module target")
        own, reexported, lazy = build_docs._split_members(mod, public)
        names = [n for n, _ in own] + [n for n, _ in lazy]
        problems += [f"{mod}.{n}: not documented" for n in names if f'id="{mod}.{n}"' not in html]
        problems += [f"{mod}.{n}: no link to {home}" for n, home in reexported if f"{home}.html#{home}.{n}" not in html]
    assert not problems, "\n".join(problems)
    index = (site.out / "api" / "index.html").read_text(encoding="utf-8")
    assert all(f'href="{m}.html"' in index for m in modules)


def test_design_pages_and_report(site: Site) -> None:
    for name in DESIGN_PAGES:
        assert (site.out / f"{name}.html").is_file(), name
    index = (site.out / "index.html").read_text(encoding="utf-8")
    for href in [f"{n}.html" for n in DESIGN_PAGES] + [f"book/{p.stem}.html" for p in NOTEBOOKS]:
        assert f'href="{href}"' in index, f"the index does not link {href}"
    report = site.out / "reproduction" / "report.html"
    assert report.is_file()
    if os.environ.get("LIPMPCC_DOCS_REPORT", "lip-"):
        imgs = _images(report).all
        assert imgs and not [why for src in imgs if (why := _image_ok(report, src))]
        assert "lip-circle" in report.read_text(encoding="utf-8")


RESOURCE = re.compile(r"<(?:script|img|iframe|source|video)\b[^>]*\bsrc=\"([^\"]+)\"|<link\b[^>]*\bhref=\"([^\"]+)\"")


def test_nothing_is_fetched_from_outside(site: Site) -> None:
    """No page loads a script, a style sheet, a font or an image from another host; MathJax is served locally."""
    remote = []
    for page in site.out.rglob("*.html"):
        for m in RESOURCE.finditer(page.read_text(encoding="utf-8")):
            url = m.group(1) or m.group(2)
            if re.match(r"(https?:)?//", url):
                remote.append(f"{page.relative_to(site.out)}: {url}")
    assert not remote, "\n".join(remote[:20])
    assert (site.out / "_static" / "mathjax" / "tex-chtml.js").is_file()
    math_pages = [p for p in site.out.rglob("*.html") if "mathjax/tex-chtml.js" in p.read_text(encoding="utf-8")]
    assert math_pages, "no page loads MathJax"


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:
        pass


@pytest.fixture(scope="session")
def served(site: Site):
    """The built site over HTTP on 127.0.0.1 (a free port), for the browser."""
    if site.returncode != 0 and not (site.out / "index.html").is_file():
        pytest.fail("the site did not build")
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_QuietHandler, directory=str(site.out)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def test_pages_in_a_headless_browser(site: Site, served: str) -> None:
    """Every page of the site in Chromium: no console error, no uncaught exception, no failed load; every
    image has a natural width, every video its first frame (decoded: its size is known); on a page with math, MathJax made an output element per equation and no
    error element. At least one page has math, one has images."""
    from .browser import Chromium, find_chromium

    exe = find_chromium()
    if exe is None:
        _unavailable("chromium is not installed (apt-get install -y chromium)")
    if importlib.util.find_spec("websocket") is None:
        _unavailable("websocket-client is not installed (pip install '.[test]')")
    pages = sorted(p.relative_to(site.out).as_posix() for p in site.out.rglob("*.html"))
    problems, math_pages, images, videos = [], 0, 0, 0
    with Chromium(exe) as browser:
        for rel in pages:
            rep = browser.open(f"{served}/{rel}")
            problems += [f"{rel}: {e}" for e in rep.errors]
            probe = rep.probe
            if not probe:
                problems.append(f"{rel}: the page could not be probed")
                continue
            for img in probe["images"]:
                images += 1
                if not img["complete"] or img["width"] <= 0:
                    problems.append(f"{rel}: image {img['src']} did not load")
            for vid in probe.get("videos", []):
                videos += 1
                if vid["ready"] < 1 or vid["width"] <= 0 or vid["error"]:
                    problems.append(f"{rel}: a video did not load (readyState {vid['ready']}, error {vid['error']})")
            problems += [f"{rel}: {what}" for what in unrendered(probe)]
            if probe["math"]:
                math_pages += 1
                if not probe["mathjax"]:
                    problems.append(f"{rel}: {probe['math']} equations but MathJax did not load")
                elif probe["mjx"] < probe["math"] or probe["mjx_errors"]:
                    problems.append(f"{rel}: {probe['math']} equations, {probe['mjx']} typeset, "
                                    f"{probe['mjx_errors']} MathJax errors")
    assert not problems, "\n".join(problems[:40])
    assert math_pages >= 1 and images >= 1, f"{math_pages} pages with math, {images} images: nothing was checked"
    embeds = sum("<video" in (site.out / p).read_text(encoding="utf-8") for p in pages)
    assert videos >= embeds, f"{embeds} pages embed a video, {videos} videos were checked"


#: what :data:`browser.RAW_TEXT` finds, as a reader would name it
RAW_KINDS = {"pipes": "a Markdown table shown as raw pipes", "dollars": "TeX shown as raw $…$",
             "mermaid": "a Mermaid diagram shown as its source", "nag": "an install hint in a published output"}


def unrendered(probe: dict) -> list[str]:
    """One line per thing the page shows unrendered (the probe's ``raw`` lists), with the text it shows."""
    raw = probe.get("raw") or {}
    return [f"{why}: {text!r}" for kind, why in RAW_KINDS.items() for text in raw.get(kind, [])[:3]]


def test_the_checks_catch_unrendered_results(tmp_path: Path) -> None:
    """The browser check fails on a page that shows a table as pipes, math as raw dollars, a Mermaid source
    or an install hint, and passes the same content rendered (a table, typeset-ready math, code blocks that
    hold pipes and dollars)."""
    from .browser import Chromium, find_chromium

    exe = find_chromium()
    if exe is None:
        _unavailable("chromium is not installed (apt-get install -y chromium)")
    bad = tmp_path / "bad.html"
    bad.write_text('<article><p>| run | steps | | --- | --- | | circle | 40 |</p><p>force $F^* = 139$ N</p>'
                   '<div class="highlight-mermaid"><pre>flowchart LR\n A --> B</pre></div>'
                   '<div class="cell_output"><pre>ipywidgets is not installed: pip install ipywidgets</pre></div>'
                   '</article>', encoding="utf-8")
    good = tmp_path / "good.html"
    good.write_text('<article><table><tr><th>run</th><th>steps</th></tr><tr><td>circle</td><td>40</td></tr>'
                    '</table><p>force <span class="math">\\(F^* = 139\\)</span> N</p>'
                    '<pre>| a | b |\n|---|---|\nx = $y$</pre><p>|x| + |y| ≤ 1</p></article>', encoding="utf-8")
    with Chromium(exe) as browser:
        found_bad = unrendered(browser.open(bad.as_uri()).probe)
        found_good = unrendered(browser.open(good.as_uri()).probe)
    text = "\n".join(found_bad)
    for why in RAW_KINDS.values():
        assert why in text, f"not caught: {why}\n{text}"
    assert not found_good, found_good


def test_the_checks_catch_a_broken_page(tmp_path: Path) -> None:
    """The page checks can fail: a missing image file and a cell output image are told apart; in Chromium a
    console error, an uncaught exception, a missing image and unrendered math are reported."""
    page = tmp_path / "p.html"
    page.write_text('<div class="cell_output"><img src="gone.png"></div><img src="data:image/png;base64,AA">'
                    '<script>console.error("boom"); throw new Error("bad");</script>'
                    '<span class="math">\\(x\\)</span>', encoding="utf-8")
    imgs = _images(page)
    assert imgs.outputs == ["gone.png"] and len(imgs.all) == 2
    assert "no such file" in _image_ok(page, "gone.png") and _image_ok(page, imgs.all[1]) is None
    from .browser import Chromium, find_chromium

    exe = find_chromium()
    if exe is None:
        _unavailable("chromium is not installed (apt-get install -y chromium)")
    with Chromium(exe) as browser:
        rep = browser.open(page.as_uri())
    text = "\n".join(rep.errors)
    assert "boom" in text and "bad" in text and "gone.png" in text, text
    assert rep.probe["math"] == 1 and rep.probe["mjx"] == 0 and not rep.probe["mathjax"]
    assert [i["width"] for i in rep.probe["images"]] == [0, 0]  # the data URI above is no valid PNG either


def test_the_notebooks_conftest_leaves_this_process_environment_alone() -> None:
    """``notebooks/conftest.py`` is loaded in the same pytest process as ``tests/`` (testpaths): it must give
    its fast mode and inline backend to nbval's kernels only, never to the tests (a global LIPMPCC_FAST=1
    once shortened every test's runs, and a timeout test's case ended before its limit)."""
    before = dict(os.environ)
    spec = importlib.util.spec_from_file_location("lipmpcc_notebooks_conftest_probe", REPO / "notebooks" / "conftest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert dict(os.environ) == before
    assert module.KERNEL_ENV["LIPMPCC_FAST"] == "1" and module.KERNEL_ENV["MPLBACKEND"] == build_docs.INLINE_BACKEND
