"""Sphinx configuration of the rendered site (build: ``python3 tools/build_docs.py``, or
``python3 -m sphinx -W --keep-going -b html docs docs/_build/html``).

Before reading, ``tools/build_docs.py``'s ``prepare`` executes the notebooks into ``docs/book/`` (fast mode),
writes the API pages into ``docs/api/`` and the reproduction report into ``docs/reproduction/``; a notebook
cell that raised is a warning, so an error fails the ``-W`` build. Nothing is fetched at view time: the
theme (furo) has no remote assets and MathJax is served from ``_static/mathjax`` (sphinx-mathjax-offline).
"""

from __future__ import annotations

import importlib.util
import inspect
import os
import re
import sys
from pathlib import Path

from sphinx.util import logging

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent

try:  # the installed package (CI); a checkout with its compiled modules otherwise
    import lipmpcc
except ImportError:
    sys.path.insert(0, str(ROOT / "python"))
    import lipmpcc

_spec = importlib.util.spec_from_file_location("lipmpcc_build_docs", ROOT / "tools" / "build_docs.py")
build_docs = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = build_docs
_spec.loader.exec_module(build_docs)

project = "lipmpcc"
author = "the lipmpcc authors"
copyright = "the lipmpcc authors, MIT licence"
release = lipmpcc.__version__ if hasattr(lipmpcc, "__version__") else ""
version = release

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",
]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "**/solutions", "Thumbs.db", ".DS_Store"]
suppress_warnings = [
    "myst.header",  # notebooks and the report step from a title to ### headings
    # "more than one target found": a field name in a docstring's inline type ("B (nv, nu): ...") that
    # several classes have; the link goes to the first one. Duplicate descriptions are still errors.
    "ref.python",
]

# -- MathJax, served from _static/mathjax (no CDN) -------------------------------------------------------------
mathjax_path = "mathjax/tex-chtml.js"

# -- notebooks: executed by tools/build_docs.py, rendered as they are -----------------------------------------
nb_execution_mode = "off"
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
# a code cell's Markdown output (display(Markdown(...)): the results tables, Table II, the claims tables)
# is parsed as MyST, like the markdown cells: GFM tables and $…$ math, not CommonMark's run-on "| a | b |"
nb_render_markdown_format = "myst"
myst_heading_anchors = 3

# -- API reference ------------------------------------------------------------------------------------------
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_google_docstring = True
napoleon_numpy_docstring = True
napoleon_use_ivar = True  # a dataclass's "Attributes:" as fields, not a second description of each attribute

# -- HTML ---------------------------------------------------------------------------------------------------
html_theme = "furo"
html_title = f"lipmpcc {release}"
html_static_path = ["_static"]
html_css_files = ["course.css"]  # code that fits the column (wrapped, not scrolled sideways)
html_show_sourcelink = True  # "Show source": each book page's .ipynb as executed for the site (a download)
html_copy_source = True
html_sourcelink_suffix = ""  # the source keeps its own suffix: _sources/book/NN_x.ipynb, opens in Jupyter as it is


def repository_url() -> str:
    """The repository's address: ``$LIPMPCC_REPOSITORY_URL``, else pyproject's ``[project.urls] Repository``;
    "" when neither names one (the site then links no repository rather than a guessed one)."""
    url = os.environ.get("LIPMPCC_REPOSITORY_URL", "").strip()
    if not url:
        import tomllib

        meta = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8")).get("project", {})
        url = str(meta.get("urls", {}).get("Repository", "")).strip()
    return url.rstrip("/")


REPOSITORY = repository_url()
html_context = {"repository_url": REPOSITORY}
html_theme_options = {}
if REPOSITORY:  # furo's "view source" / "edit" buttons on every page, and a footer link to the repository
    html_theme_options = {
        "source_repository": REPOSITORY + "/",
        "source_branch": "main",
        "source_directory": "docs/",
        "footer_icons": [{"name": "repository", "url": REPOSITORY, "html": "repository", "class": ""}],
    }


def _prepare(app, config) -> None:
    """Write the book, the API pages and the report into the source tree before Sphinx looks for files."""
    log = logging.getLogger("lipmpcc.docs")
    info = build_docs.prepare(log=log.info)
    for run in info["runs"]:
        for err in run.errors:
            where = f"code cell {err['cell']}" if err["cell"] >= 0 else "the kernel"
            log.warning(f"notebook {run.name}: {where} raised {err['ename']}: {err['evalue']}\n{err['traceback']}",
                        location=f"book/{run.name}")
    log.info(f"[docs] prepared in {info['seconds']:.0f} s: {len(info['runs'])} notebooks, "
             f"{len(info['modules'])} API pages, report: {info['report']}")


_LITERAL = re.compile(r"(``.+?``|`[^`]+`)")


def _escape_bars(app, what, name, obj, options, lines: list[str]) -> None:
    """The docstrings write an absolute value or a norm as ``|x|`` in plain text, which reStructuredText would
    read as a substitution: escape each ``|`` outside inline literals and roles."""
    for i, line in enumerate(lines):
        if "|" in line:
            parts = _LITERAL.split(line)
            lines[i] = "".join(p if k % 2 else p.replace("|", "\\|") for k, p in enumerate(parts))


def _drop_type_docstrings(app, what, name, obj, options, lines: list[str]) -> None:
    """An undocumented constant or attribute would show its type's docstring (a tuple's "Built-in immutable
    sequence..."): show nothing instead."""
    if what in ("data", "attribute") and lines and not inspect.isclass(obj) and not inspect.isroutine(obj):
        type_doc = inspect.getdoc(type(obj)) or ""
        if type_doc and "\n".join(lines).strip() == type_doc.strip():
            lines.clear()


#: links of the design pages to repository files that the site includes as pages (the links stay right on GitHub)
SITE_PAGES = {"](../CHANGELOG.md": "](changelog.md"}


def _site_links(app, docname: str, source: list[str]) -> None:
    """Point a design page's link to a repository file at the site's page of that file."""
    if "/" not in docname:
        for old, new in SITE_PAGES.items():
            source[0] = source[0].replace(old, new)


def setup(app) -> None:
    app.set_html_assets_policy("always")  # MathJax on every page: the sidebar shows the notebooks' titles, with math
    app.connect("config-inited", _prepare)
    app.connect("source-read", _site_links)
    app.connect("autodoc-process-docstring", _drop_type_docstrings, priority=400)  # before napoleon's
    app.connect("autodoc-process-docstring", _escape_bars, priority=900)  # after napoleon's conversion
