"""The one-click start: the hosted-notebook configurations (``binder/``, ``.devcontainer/``) install this
package with extras that pyproject declares, on a Python that pyproject allows, and the site's landing page
links the "Start here" page, which names the same install command."""

from __future__ import annotations

import json
import re
import tomllib

from ..conftest import REPO

PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))


def _extras(spec: str) -> set[str]:
    m = re.fullmatch(r"\.\[([\w,\s-]+)\]", spec.strip().strip("'\""))
    assert m, f"{spec!r}: expected '.[extra,...]' (this checkout with extras)"
    return {e.strip() for e in m.group(1).split(",")}


def test_binder_installs_this_package_with_declared_extras() -> None:
    lines = [ln.strip() for ln in (REPO / "binder" / "requirements.txt").read_text(encoding="utf-8").splitlines()
             if ln.strip() and not ln.lstrip().startswith("#")]
    assert len(lines) == 1, lines
    declared = set(PYPROJECT["project"]["optional-dependencies"])
    assert _extras(lines[0]) <= declared and "notebooks" in _extras(lines[0])
    apt = (REPO / "binder" / "apt.txt").read_text(encoding="utf-8").split()
    assert "cmake" in apt and "build-essential" in apt  # scikit-build-core compiles the C++ QP


def test_devcontainer_runs_the_same_install_on_an_allowed_python() -> None:
    cfg = json.loads((REPO / ".devcontainer" / "devcontainer.json").read_text(encoding="utf-8"))
    m = re.search(r"pip install (\S+)", cfg["postCreateCommand"])
    assert m, cfg["postCreateCommand"]
    binder = [ln for ln in (REPO / "binder" / "requirements.txt").read_text(encoding="utf-8").splitlines()
              if ln.strip() and not ln.startswith("#")][0]
    assert _extras(m.group(1)) == _extras(binder)
    version = re.search(r"python:(\d+)\.(\d+)", cfg["image"])
    need = re.search(r">=\s*(\d+)\.(\d+)", PYPROJECT["project"]["requires-python"])
    assert version and need and tuple(map(int, version.groups())) >= tuple(map(int, need.groups()))
    assert "notebooks/00_roadmap.ipynb" in cfg["customizations"]["codespaces"]["openFiles"]


def test_start_page_is_linked_and_names_the_install() -> None:
    start = (REPO / "docs" / "start.md").read_text(encoding="utf-8")
    assert 'pip install ".[notebooks]"' in start and "15 hours" in start and "00_roadmap" in start
    assert "binder/" in start and ".devcontainer/" in start
    index = (REPO / "docs" / "index.md").read_text(encoding="utf-8")
    assert "(start.md)" in index and "\nstart\n" in index
