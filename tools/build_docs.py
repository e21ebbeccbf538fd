"""Build the rendered site: the book, the API reference, the design pages and a short reproduction report.

One command (from the repository root)::

    python3 -m pip install ".[docs]" && python3 tools/build_docs.py      # -> docs/_build/html/index.html

which is ``python3 -m sphinx -W --keep-going -b html docs docs/_build/html``; the plain Sphinx command works
as well, ``docs/conf.py`` does the same preparation. Before Sphinx reads anything, :func:`prepare` writes three
generated (git-ignored) parts into ``docs/``:

- ``docs/book/``: every ``notebooks/*.ipynb`` (the top level only: not ``notebooks/solutions/`` nor checkpoints),
  executed in fast mode (``LIPMPCC_FAST=1`` unless the environment sets it) by a Jupyter kernel started in
  ``notebooks/`` as nbval does, two at a time, with matplotlib's inline backend so that the figures are
  kept. An executed copy is reused while its key (the notebook's bytes, the package's sources, the fast
  switch) is unchanged; a copy with a cell error is never reused. ``pytest notebooks/`` (nbval) writes
  the same copies (``notebooks/conftest.py``), so that the test suite executes each notebook once.
- ``docs/api/``: a page per public module of ``lipmpcc`` (each module that declares ``__all__``; any module
  with a ``_``-prefixed name part is private and left out), rendered by autodoc.
- ``docs/reproduction/``: the report of ``lipmpcc reproduce --fast --only lip-`` (a few seconds; the prefix is
  ``$LIPMPCC_DOCS_REPORT``, an empty value leaves the report out).

Sphinx itself executes nothing (myst-nb's execution is off): it renders the executed copies.
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

__all__ = [
    "ROOT",
    "DOCS",
    "NOTEBOOKS",
    "BOOK_DIR",
    "API_DIR",
    "REPORT_DIR",
    "NotebookRun",
    "book_notebooks",
    "public_modules",
    "execute_book",
    "link_api",
    "offline_outputs",
    "site_tags",
    "write_api_pages",
    "api_index",
    "write_report",
    "prepare",
    "build",
    "main",
]

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
NOTEBOOKS = ROOT / "notebooks"
PACKAGE_SRC = ROOT / "python" / "lipmpcc"
#: generated, git-ignored parts of the Sphinx source tree
BOOK_DIR = DOCS / "book"
API_DIR = DOCS / "api"
REPORT_DIR = DOCS / "reproduction"
#: metadata key of an executed notebook (``metadata.lipmpcc_docs``)
META_KEY = "lipmpcc_docs"
#: seconds a cell may run (nbval's ``--nbval-cell-timeout`` in pyproject.toml)
CELL_TIMEOUT_S = 900
INLINE_BACKEND = "module://matplotlib_inline.backend_inline"
IMAGE_MIMES = ("image/png", "image/jpeg", "image/gif", "image/svg+xml")


@dataclass
class NotebookRun:
    """An executed notebook of the book: where its copy is, how long it took [s], its cell errors
    (``{"cell": index among the code cells, "ename": ..., "evalue": ...}``), its image outputs and
    whether the copy was reused from an earlier build."""

    name: str
    path: Path
    seconds: float
    errors: list[dict] = field(default_factory=list)
    images: int = 0
    reused: bool = False
    log: str = ""


def book_notebooks(notebooks: Path = NOTEBOOKS) -> list[Path]:
    """The book's notebooks: ``notebooks/*.ipynb`` in name order (subfolders such as ``solutions/`` and
    ``.ipynb_checkpoints/`` are not the book)."""
    return sorted(p for p in notebooks.glob("*.ipynb") if p.is_file())


def _declares_all(path: Path) -> bool:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    for node in tree.body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        if isinstance(node, (ast.Assign, ast.AnnAssign)) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in targets
        ):
            return True
    return False


def public_modules(package_dir: Path = PACKAGE_SRC) -> list[str]:
    """Dotted names of the public modules of ``lipmpcc`` (the sources under ``package_dir``): every module
    that declares ``__all__``, except those with a ``_``-prefixed part (``lipmpcc._entry``,
    ``lipmpcc.sim._tick``, ``__main__``); packages are named by their ``__init__``."""
    mods = []
    for path in sorted(package_dir.rglob("*.py")):
        rel = path.relative_to(package_dir.parent).with_suffix("")
        parts = list(rel.parts[:-1]) if rel.name == "__init__" else list(rel.parts)
        if any(p.startswith("_") for p in parts) or "__pycache__" in rel.parts:
            continue
        if _declares_all(path):
            mods.append(".".join(parts))
    return sorted(mods)


def _source_key() -> str:
    """A digest of the package's sources: an executed notebook is stale once they change."""
    h = hashlib.sha256()
    for path in sorted(PACKAGE_SRC.rglob("*.py")):
        h.update(str(path.relative_to(PACKAGE_SRC)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _kernel_env() -> dict[str, str]:
    env = dict(os.environ)
    env.setdefault("LIPMPCC_FAST", "1")
    env.setdefault("LIPMPCC_SOLUTIONS", str(NOTEBOOKS / "solutions"))  # the exercises run their solutions, checked
    env["MPLBACKEND"] = INLINE_BACKEND  # Agg (CI, tests) would drop every figure
    env.setdefault("PYDEVD_DISABLE_FILE_VALIDATION", "1")
    try:  # a checkout without an installed package: the kernels import the sources
        import lipmpcc  # noqa: F401
    except ImportError:
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PACKAGE_SRC.parent), env.get("PYTHONPATH")]))
    return env


def _run_key(src: Path, env: dict[str, str], package_key: str) -> str:
    h = hashlib.sha256(src.read_bytes())
    h.update(package_key.encode())
    h.update(env.get("LIPMPCC_FAST", "").encode())
    solutions = Path(env.get("LIPMPCC_SOLUTIONS", "")) / f"{src.stem}.py"
    h.update(solutions.read_bytes() if env.get("LIPMPCC_SOLUTIONS") and solutions.is_file() else b"-")
    h.update(_LINKER_VERSION.encode())
    return h.hexdigest()


#: changes when :func:`link_api` or :func:`site_tags` changes (so that executed copies are re-made)
_LINKER_VERSION = "api-links-2+site-tags-3"
_API_NAME = re.compile(r"(?<![}\w])`(lipmpcc(?:\.\w+)+)`")


#: matplotlib's to_jshtml() animations load Font Awesome from a CDN for their buttons' icons; the site
#: works offline, so the link goes and each icon becomes a character
_CDN_CSS = re.compile(r'<link rel="stylesheet"\s+href="https?://[^"]*font-awesome[^"]*"\s*/?>\s*')
_FA_ICONS = {"minus": "−", "plus": "+", "fast-backward": "⏮", "step-backward": "⏴", "play": "▶", "pause": "⏸",
             "step-forward": "⏵", "fast-forward": "⏭", "backward": "◀"}
_FA_ICON = re.compile(r'<i class="fa fa-([\w-]+)"></i>')
_SOLUTIONS_LINK = re.compile(r"\[([^\]]+)\]\((?:\./)?solutions/[^)]+\)")


def offline_outputs(nb) -> int:
    """Make an executed copy self-contained for the site: no stylesheet from a CDN in HTML outputs (the
    icons of an animation's buttons become characters), and links to ``solutions/*.py`` (files the site
    does not carry) become their text. Returns how many changes were made."""
    n = 0
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            cell.source, k = _SOLUTIONS_LINK.subn(r"\1", cell.source)
            n += k
            continue
        for out in cell.get("outputs", []):
            html = out.get("data", {}).get("text/html")
            if html is None:
                continue
            text = "".join(html) if isinstance(html, list) else html
            text, k1 = _CDN_CSS.subn("", text)
            text, k2 = _FA_ICON.subn(lambda m: _FA_ICONS.get(m.group(1), m.group(1)), text)
            if k1 or k2:
                out["data"]["text/html"] = text
                n += k1 + k2
    return n


#: a line of drawing code (matplotlib calls on a figure or axes, or a plotting helper)
_PLOT_LINE = re.compile(r"^\s*(?:(?:plt|fig\w*|axs?\w*|ax\[[^\]]*\])\s*[.\[=,]|for ax\b|\w+\s*=\s*(?:plt|ax\w*)\.)|"
                        r"^\s*(?:%matplotlib|import matplotlib|from matplotlib)|"
                        r"\.(?:set|set_\w+|axis|plot|legend|scatter|fill\w*|imshow|annotate|text|axhline|axvline|grid|"
                        r"add_patch|tight_layout|colorbar|tick_params|invert_\w+)\(")
#: the share of a cell's code lines that draw, from which the site collapses the cell's code under its figure
PLOT_SHARE = 0.4
_WIDGET_NAG = "ipywidgets is not installed"


def site_tags(nb) -> int:
    """Tag cells for the site (myst-nb's cell tags; the notebooks themselves keep theirs): a code cell that
    makes a figure and whose code is mostly drawing (at least :data:`PLOT_SHARE` of its lines, 6 lines or
    more, no exercise) gets ``hide-input`` (its code collapsed, one click away); the "ipywidgets is not
    installed" hint is removed from a cell's printed output (its figure stays). Returns how many changes
    were made."""
    n = 0
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        tags = cell.setdefault("metadata", {}).setdefault("tags", [])
        lines = [ln for ln in cell.source.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
        drawn = any(m in out.get("data", {}) for out in cell.get("outputs", []) for m in IMAGE_MIMES)
        plotting = sum(bool(_PLOT_LINE.search(ln)) for ln in lines)
        if (drawn and len(lines) >= 6 and plotting >= PLOT_SHARE * len(lines) and "ex." not in cell.source
                and "hide-input" not in tags):
            tags.append("hide-input")
            n += 1
        n += _drop_widget_hint(cell) + _escape_cell_bars(cell)
    return n


_TABLE_SEP = re.compile(r"(?<=\s)\|(?=\s)")  # a column separator of md_table's rows: " | "


def _escape_cell_bars(cell) -> int:  # noqa: ANN001 - an nbformat code cell
    """In a Markdown output's table rows, escape the bars that are not column separators (``|x|``, an
    absolute value, in "max |ē_c|"): unescaped, GFM counts them as columns, and a header with more cells than
    its delimiter row is no table. A separator is a bar with white space on both sides, or at the row's ends.
    Returns how many outputs changed."""
    n = 0
    for out in cell.get("outputs", []):
        md = out.get("data", {}).get("text/markdown")
        if md is None:
            continue
        text = "".join(md) if isinstance(md, list) else md
        lines = text.split("\n")
        for i, line in enumerate(lines):
            row = line.strip()
            if len(row) > 1 and row[0] == "|" and row[-1] == "|" and not re.fullmatch(r"[|:\s-]+", row):
                parts = _TABLE_SEP.split(row[1:-1])
                lines[i] = "|" + "|".join(re.sub(r"(?<!\\)\|", r"\\|", p) for p in parts) + "|"
        new = "\n".join(lines)
        if new != text:
            out["data"]["text/markdown"] = new
            n += 1
    return n


def _drop_widget_hint(cell) -> int:  # noqa: ANN001 - an nbformat code cell
    """Remove the lines of the "ipywidgets is not installed" hint from the cell's stream outputs (a stream
    left empty goes); the figure drawn without the sliders stays. Returns how many outputs changed."""
    n, kept = 0, []
    for out in cell.get("outputs", []):
        if out.get("output_type") == "stream" and _WIDGET_NAG in "".join(out.get("text", "")):
            text = "".join(out["text"])
            lines = text.splitlines(keepends=True)
            start = next(i for i, ln in enumerate(lines) if _WIDGET_NAG in ln)
            end = next((j for j in range(start, len(lines)) if lines[j].endswith(("\n",)) and
                        (j + 1 == len(lines) or not lines[j + 1].startswith(" "))), len(lines) - 1)
            rest = "".join(lines[:start] + lines[end + 1:])
            n += 1
            if rest.strip():
                out["text"] = rest
                kept.append(out)
            continue
        kept.append(out)
    if n:
        cell["outputs"] = kept
    return n


def link_api(nb) -> int:
    """Turn the backticked ``lipmpcc.x.y`` names of each markdown cell's ``**API used:**`` paragraph into
    links to their API pages (MyST's ``{py:obj}`` role, resolved by Sphinx; a name without an entry stays
    plain text). The notebooks themselves keep plain names, which read well in Jupyter. Returns how many
    names were linked."""
    n = 0
    for cell in nb.cells:
        if cell.cell_type != "markdown" or "**API used:**" not in cell.source:
            continue
        head, _, rest = cell.source.partition("**API used:**")
        para, sep, tail = rest.partition("\n\n")
        para, k = _API_NAME.subn(r"{py:obj}`\1`", para)
        n += k
        cell.source = head + "**API used:**" + para + sep + tail
    return n


def _summarise(nb) -> tuple[list[dict], int]:
    errors, images, code_index = [], 0, -1
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        code_index += 1
        for out in cell.get("outputs", []):
            if out.get("output_type") == "error":
                errors.append({"cell": code_index, "ename": out.get("ename", ""), "evalue": out.get("evalue", ""),
                               "traceback": "\n".join(out.get("traceback", []))})
            elif any(m in out.get("data", {}) for m in IMAGE_MIMES):
                images += 1
    return errors, images


def _execute_one(src: Path, dest: Path, key: str) -> None:
    """Execute ``src`` in a kernel started in its folder and write it to ``dest`` (run in a child process)."""
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(src, as_version=4)
    t0 = time.perf_counter()
    kernel = nb.metadata.get("kernelspec", {}).get("name", "python3")
    client = NotebookClient(nb, timeout=CELL_TIMEOUT_S, kernel_name=kernel, allow_errors=True,
                            resources={"metadata": {"path": str(src.parent)}})
    failure = []
    try:
        client.execute()
    except Exception as exc:  # a timeout or a dead kernel: keep what ran, and say so
        failure = [{"cell": -1, "ename": type(exc).__name__, "evalue": str(exc)[:2000], "traceback": ""}]
    link_api(nb)
    offline_outputs(nb)
    site_tags(nb)
    errors, images = _summarise(nb)
    errors += failure
    nb.metadata[META_KEY] = {"key": key, "seconds": round(time.perf_counter() - t0, 2), "errors": errors,
                             "images": images, "fast": os.environ.get("LIPMPCC_FAST", "")}
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_suffix(".ipynb.part")
    nbformat.write(nb, tmp)
    tmp.replace(dest)


def _read_run(dest: Path, key: str | None) -> NotebookRun | None:
    """The run recorded in ``dest`` when it exists, is complete and (``key`` given) has that key."""
    if not dest.is_file():
        return None
    try:
        meta = json.loads(dest.read_text(encoding="utf-8"))["metadata"][META_KEY]
    except (ValueError, KeyError):
        return None
    if key is not None and meta.get("key") != key:
        return None
    return NotebookRun(dest.stem, dest, float(meta["seconds"]), list(meta["errors"]), int(meta["images"]))


def execute_book(dest_dir: Path = BOOK_DIR, notebooks: list[Path] | None = None, jobs: int | None = None,
                 log=print) -> list[NotebookRun]:
    """Execute the book's notebooks into ``dest_dir`` (``jobs`` kernels at a time, default min(2, CPUs)),
    reusing an executed copy whose key still matches and that had no error; stale ``.ipynb`` files of
    notebooks that no longer exist are removed. Returns a run per notebook, in name order."""
    notebooks = book_notebooks() if notebooks is None else notebooks
    jobs = jobs or max(1, min(2, os.cpu_count() or 1))
    env, package_key = _kernel_env(), _source_key()
    dest_dir.mkdir(parents=True, exist_ok=True)
    wanted = {f"{p.stem}.ipynb" for p in notebooks}
    for old in dest_dir.glob("*.ipynb"):
        if old.name not in wanted:
            old.unlink()
    runs: dict[str, NotebookRun] = {}
    todo: list[tuple[Path, Path, str]] = []
    for src in notebooks:
        dest, key = dest_dir / src.name, _run_key(src, env, package_key)
        done = _read_run(dest, key)
        if done is not None and not done.errors:
            done.reused = True
            runs[src.stem] = done
        else:
            todo.append((src, dest, key))
    todo.reverse()  # the later chapters (full body) run longest: starting them first shortens the wall time
    running: list[tuple[Path, Path, str, subprocess.Popen, float]] = []
    while todo or running:
        while todo and len(running) < jobs:
            src, dest, key = todo.pop(0)
            log(f"[docs] executing {src.name} (LIPMPCC_FAST={env.get('LIPMPCC_FAST')})")
            cmd = [sys.executable, str(Path(__file__).resolve()), "execute", str(src), str(dest), key]
            proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            running.append((src, dest, key, proc, time.perf_counter()))
        src, dest, key, proc, t0 = running.pop(0)
        out, _ = proc.communicate()
        run = _read_run(dest, key) if proc.returncode == 0 else None
        if run is None:
            run = NotebookRun(src.stem, dest, time.perf_counter() - t0, [{
                "cell": -1, "ename": "ExecutionFailed", "evalue": f"the kernel run exited {proc.returncode}",
                "traceback": out[-4000:]}])
        run.log = out
        log(f"[docs] {src.name}: {run.seconds:.0f} s, {run.images} images, {len(run.errors)} errors")
        runs[src.stem] = run
    return [runs[p.stem] for p in notebooks]


API_INDEX = """# API reference

A page per public module of `lipmpcc` (each module that declares `__all__`), generated from the docstrings,
grouped by layer from the bottom (paths, models) to the top (the course, the command line): a layer imports
only the layers above it in this list. Modules whose name has a `_`-prefixed part are private.

{groups}

```{{toctree}}
:hidden:
:maxdepth: 1

{entries}
```
"""

#: the API index's groups, bottom layer first (``tests/test_architecture.py`` has the layers): a module goes to
#: the first group whose prefix it has; top-level modules that match none are the foundations
API_GROUPS = [
    ("Foundations: paths, errors, obstacles, terrain, configuration", ()),
    ("Models: LIP, ALIP and the full body's description", ("lipmpcc.models",)),
    ("Robots", ("lipmpcc.robots",)),
    ("Solvers", ("lipmpcc.solvers",)),
    ("Planners: MPCC, ALIP-MPC, ALIP-QP, capture point", ("lipmpcc.planners",)),
    ("Control: references and the whole-body QP", ("lipmpcc.control", "lipmpcc.wbc")),
    ("Simulation: MuJoCo", ("lipmpcc.sim",)),
    ("Closed loops", ("lipmpcc.loops",)),
    ("Plots", ("lipmpcc.plots",)),
    ("Studies: scenarios and runs", ("lipmpcc.studies", "lipmpcc.scenarios")),
    ("Reports, reproduction and sweeps", ("lipmpcc.report", "lipmpcc.reproduce", "lipmpcc.sweep")),
    ("The course: exercises and grading", ("lipmpcc.course",)),
    ("Command line", ("lipmpcc.cli",)),
]


def _summary(mod: str) -> str:
    """The first sentence of ``mod``'s docstring (read from its source, not imported), one line."""
    parts = mod.split(".")[1:]
    candidates = [PACKAGE_SRC.joinpath(*parts, "__init__.py")]
    if parts:
        candidates.append(PACKAGE_SRC.joinpath(*parts[:-1], parts[-1] + ".py"))
    path = next((p for p in candidates if p.is_file()), None)
    doc = (ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or "") if path else ""
    para = " ".join(doc.split("\n\n")[0].split())
    para = re.sub(r":\w+:`~?([^`]+)`", r"`\1`", para)  # a reStructuredText role, as code in Markdown
    para = re.sub(rf"^{re.escape(mod.split('.')[-1])}:\s+", "", para)  # "lipmpcc: what it is" says what it is
    m = re.match(r"(.+?[.:;])(\s|$)", para)
    return (m.group(1) if m else para).rstrip(":;.") or "(no summary)"


def api_index(modules: list[str]) -> str:
    """The API index: a section per :data:`API_GROUPS` group, a linked line with its summary per module."""
    groups: dict[str, list[str]] = {title: [] for title, _ in API_GROUPS}
    for mod in modules:
        title = next((t for t, prefixes in API_GROUPS[1:] if any(mod == p or mod.startswith(p + ".") for p in prefixes)),
                     API_GROUPS[0][0])
        groups[title].append(mod)
    parts = []
    for title, mods in groups.items():
        if mods:
            parts.append(f"## {title}\n\n" + "\n".join(f"- [`{m}`]({m}.rst): {_summary(m)}" for m in mods))
    return API_INDEX.format(groups="\n\n".join(parts), entries="\n".join(modules))

MODULE_PAGE = """{title}
{underline}

.. automodule:: {mod}
   :no-members:
{body}"""


def _split_members(mod: str, public: set[str]) -> tuple[list[tuple[str, str]], list[tuple[str, str]], list[tuple[str, str]]]:
    """Sort the names of ``mod.__all__`` for its page: those documented there, as ``(name, kind)`` with kind
    ``class``, ``function`` or ``data``; those only re-exported there, as ``(name, home module)`` (a class or
    a function whose home module is another public module that lists it in ``__all__``: its page documents
    it, and documenting it twice would make every short cross-reference ambiguous); and those the module
    makes on first access (a module ``__getattr__``, which autodoc cannot see), as ``(name, type name)``.
    Imports ``mod``."""
    import importlib
    import inspect

    import importlib.util

    module = importlib.import_module(mod)
    own, reexported, lazy = [], [], []
    for name in getattr(module, "__all__", []):
        if hasattr(module, "__path__") and importlib.util.find_spec(f"{mod}.{name}") is not None:
            continue  # a submodule, imported or not: it has its own page
        obj = getattr(module, name, None)
        if inspect.ismodule(obj):
            continue  # a submodule: it has its own page
        code = inspect.isclass(obj) or inspect.isroutine(obj)
        home = getattr(obj, "__module__", None) if code else None
        if home and home != mod and home in public and name in getattr(importlib.import_module(home), "__all__", ()):
            reexported.append((name, home))
        elif name not in vars(module):
            lazy.append((name, type(obj).__name__))
        else:
            own.append((name, "class" if inspect.isclass(obj) else "function" if code else "data"))
    return own, reexported, lazy


def _module_page(mod: str, public: set[str]) -> str:
    """The page of ``mod``: its docstring, its data, then its classes and functions (in ``__all__`` order),
    then links to what it re-exports."""
    own, reexported, lazy = _split_members(mod, public)
    lines = []
    for name, kind in [o for o in own if o[1] == "data"]:
        lines += ["", f".. autodata:: {mod}.{name}"]
    for name, type_name in lazy:
        lines += ["", f".. py:data:: {name}", f"   :module: {mod}", "",
                  f"   A ``{type_name}``, made on first access (the module's ``__getattr__``)."]
    for name, kind in [o for o in own if o[1] != "data"]:
        lines += ["", f".. auto{kind}:: {mod}.{name}"]
        if kind == "class":
            lines += ["   :members:", "   :undoc-members:", "   :show-inheritance:"]
    if reexported:
        lines += ["", ".. rubric:: Re-exported here", "", "Documented in the module that defines them:", ""]
        lines += [f"- :py:obj:`{name} <{home}.{name}>` (``{home}``)" for name, home in reexported]
    title = f"``{mod}``"
    return MODULE_PAGE.format(title=title, underline="=" * len(title), mod=mod, body="\n".join(lines) + "\n")


def write_api_pages(dest_dir: Path = API_DIR, modules: list[str] | None = None) -> list[str]:
    """Write ``index.md`` and a page ``<module>.rst`` per public module into ``dest_dir`` (pages of modules
    that are gone are removed; unchanged pages are not rewritten, so Sphinx keeps their cache). Imports
    every public module (to tell what it defines from what it re-exports)."""
    modules = public_modules() if modules is None else modules
    dest_dir.mkdir(parents=True, exist_ok=True)
    pages = {"index.md": api_index(modules)}
    for mod in modules:
        pages[f"{mod}.rst"] = _module_page(mod, set(modules))
    for old in dest_dir.iterdir():
        if old.name not in pages:
            old.unlink() if old.is_file() else shutil.rmtree(old)
    for name, text in pages.items():
        path = dest_dir / name
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
    return modules


def write_report(dest_dir: Path = REPORT_DIR, only: str | None = None, log=print) -> Path | None:
    """Run ``lipmpcc reproduce --fast --only ONLY`` (``$LIPMPCC_DOCS_REPORT``, default ``lip-``) and put its
    ``report.md`` and the files beside it (figures, ``summary.json``) into ``dest_dir``; ``None`` when the
    prefix is empty (the page then says that no study ran). Raises ``RuntimeError`` when the command leaves no ``report.md``."""
    only = os.environ.get("LIPMPCC_DOCS_REPORT", "lip-") if only is None else only
    if dest_dir.exists():
        shutil.rmtree(dest_dir)
    if not only:  # the page stays (the index links it) and says why it is empty
        dest_dir.mkdir(parents=True)
        (dest_dir / "report.md").write_text("# Reproduction report\n\nThis build ran no study "
                                            "(`LIPMPCC_DOCS_REPORT` was empty).\n", encoding="utf-8")
        return None
    work = DOCS / "_build" / "reproduce"
    cmd = [sys.executable, "-m", "lipmpcc", "reproduce", "--fast", "--only", only, "--out", str(work)]
    log("[docs] " + " ".join(cmd[1:]))
    env = dict(os.environ, MPLBACKEND="Agg")
    if "PYTHONPATH" not in env and _kernel_env().get("PYTHONPATH"):
        env["PYTHONPATH"] = _kernel_env()["PYTHONPATH"]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    report = work / "report.md"
    if not report.is_file():
        raise RuntimeError(f"`lipmpcc reproduce --fast --only {only}` wrote no report.md "
                           f"(exit {proc.returncode}): {(proc.stderr or proc.stdout).strip()[-2000:]}")
    # the report and what it links to; no other page source (another .md would be an orphan page)
    shutil.copytree(work, dest_dir, ignore=lambda d, names: [
        n for n in names if n.endswith((".md", ".ipynb", ".rst", ".lock")) and not (Path(d) == work and n == "report.md")])
    return dest_dir / "report.md"


def prepare(log=print) -> dict:
    """Write the generated parts of ``docs/`` (book, API pages, report); returns what was written."""
    t0 = time.perf_counter()
    runs = execute_book(log=log)
    modules = write_api_pages()
    report = write_report(log=log)
    return {"runs": runs, "modules": modules, "report": report, "seconds": time.perf_counter() - t0}


def build(out: Path = DOCS / "_build" / "html", builder: str = "html", extra: list[str] | None = None) -> int:
    """``python -m sphinx -W --keep-going -b html docs OUT``: warnings are errors."""
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", builder, str(DOCS), str(out), *(extra or [])]
    return subprocess.call(cmd)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="tools/build_docs.py", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="cmd")
    ex = sub.add_parser("execute", help=argparse.SUPPRESS)
    ex.add_argument("src", type=Path)
    ex.add_argument("dest", type=Path)
    ex.add_argument("key")
    parser.add_argument("--out", type=Path, default=DOCS / "_build" / "html", help="output folder")
    args = parser.parse_args(argv)
    if args.cmd == "execute":
        _execute_one(args.src, args.dest, args.key)
        return 0
    t0 = time.perf_counter()
    code = build(args.out)
    print(f"[docs] {'built' if code == 0 else 'FAILED'}: {args.out / 'index.html'} ({time.perf_counter() - t0:.0f} s)")
    return code


if __name__ == "__main__":
    sys.exit(main())
