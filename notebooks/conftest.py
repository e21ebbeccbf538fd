"""Notebooks run under nbval in fast mode: ``LIPMPCC_FAST=1`` shortens every run's
horizon (steps / seconds simulated) and changes nothing else. The exercises run with their
solutions (``LIPMPCC_SOLUTIONS``, :mod:`lipmpcc.course.exercises`): a check that fails, or a solution
that no longer matches the library, fails the notebook's test. The kernels that nbval starts get these
variables and matplotlib's inline backend (as in Jupyter and in the site's build, so that every figure is
drawn under test); this pytest process keeps its own environment, which the tests of ``tests/`` share.

A notebook whose cells all passed is also written, with its outputs, to ``docs/book/`` as
``tools/build_docs.py`` writes it (the same key): the site's build then renders it without executing it
again (in CI, ``pytest`` runs ``notebooks/`` before ``tests/docs``).
"""

from __future__ import annotations

import atexit
import copy
import importlib.util
import shutil
import sys
import tempfile
from pathlib import Path

import pytest

from lipmpcc.config import scoped_env

HERE = Path(__file__).resolve().parent


def _build_docs():  # noqa: ANN202 - tools/build_docs.py as a module (None without it)
    name = "lipmpcc_build_docs"
    if name not in sys.modules:
        path = HERE.parent / "tools" / "build_docs.py"
        spec = importlib.util.spec_from_file_location(name, path)
        if spec is None or spec.loader is None or not path.is_file():
            return None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


BUILD_DOCS = _build_docs()
INLINE = getattr(BUILD_DOCS, "INLINE_BACKEND", "module://matplotlib_inline.backend_inline")
#: the run cache of this session (lipmpcc.studies.run_cache): a notebook and its deep dive (09 and 09b) share
#: one run, simulated once per test session, never one stored by an earlier session
RUN_CACHE = tempfile.mkdtemp(prefix="lipmpcc-nbval-runs-")
atexit.register(shutil.rmtree, RUN_CACHE, True)
#: the kernels' environment on top of this process's; only while nbval starts a kernel, so that the tests
#: of tests/ (the same pytest process) keep theirs (no fast mode)
KERNEL_ENV = {"LIPMPCC_FAST": "1", "LIPMPCC_SOLUTIONS": str(HERE / "solutions"), "MPLBACKEND": INLINE,
              "LIPMPCC_CACHE_DIR": RUN_CACHE}
#: per notebook (nbval's file node): [cells passed, seconds, every cell passed so far]
_RUNS: dict[object, list] = {}


def _is_cell(item: pytest.Item) -> bool:
    return hasattr(item, "cell") and hasattr(item, "test_outputs") and hasattr(item.parent, "nb")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item: pytest.Item):  # noqa: ANN201
    """nbval starts a notebook's kernel in its first cell's setup: with :data:`KERNEL_ENV`."""
    if not _is_cell(item):
        yield
        return
    with scoped_env(KERNEL_ENV):
        yield


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo):  # noqa: ANN201
    """Keep each passed cell's outputs in the notebook nbval read."""
    outcome = yield
    if not _is_cell(item) or call.when != "call":
        return
    rep = outcome.get_result()
    run = _RUNS.setdefault(item.parent, [0, 0.0, True])
    if not rep.passed:
        run[2] = False
        return
    run[0] += 1
    run[1] += call.duration
    item.cell.outputs = list(item.test_outputs or [])
    item.cell.execution_count = run[0]


def pytest_runtest_teardown(item: pytest.Item, nextitem: pytest.Item | None) -> None:
    """After a notebook's last cell: write its executed copy for the site when every cell passed."""
    if not _is_cell(item) or (nextitem is not None and nextitem.parent is item.parent):
        return
    passed, seconds, ok = _RUNS.pop(item.parent, [0, 0.0, False])
    nb = item.parent.nb
    if BUILD_DOCS is None or not ok or passed != sum(c.cell_type == "code" for c in nb.cells):
        return
    write_book_copy(Path(str(item.parent.fspath)), copy.deepcopy(nb), seconds)


def write_book_copy(src: Path, nb, seconds: float) -> Path:  # noqa: ANN001 - an nbformat notebook
    """Write the executed ``nb`` of ``src`` to the site's book folder, as ``tools/build_docs.py`` does."""
    bd = BUILD_DOCS
    env = {**bd._kernel_env(), **KERNEL_ENV}
    key = bd._run_key(src, env, bd._source_key())
    bd.link_api(nb)
    bd.offline_outputs(nb)
    bd.site_tags(nb)
    errors, images = bd._summarise(nb)
    nb.metadata[bd.META_KEY] = {"key": key, "seconds": round(seconds, 2), "errors": errors, "images": images,
                                "fast": env.get("LIPMPCC_FAST", ""), "executed_by": "nbval"}
    import nbformat

    dest = bd.BOOK_DIR / src.name
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_suffix(".ipynb.part")
    nbformat.write(nb, tmp)
    tmp.replace(dest)
    return dest
