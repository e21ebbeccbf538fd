"""lipmpcc.resources: the data folder of a source checkout (or of an installed wheel)."""

from __future__ import annotations

import json
from pathlib import Path

from lipmpcc import resources

REPO_DATA = Path(__file__).resolve().parents[1] / "data"


def test_data_dir_is_the_installed_or_the_checkouts_data_folder() -> None:
    """An installed wheel carries lipmpcc/data; a source checkout uses the repository's data/. Either
    way it holds the same files as the repository's."""
    d = resources.data_dir()
    installed = Path(resources.__file__).resolve().parent / "data"
    assert d.is_dir() and d.resolve() == (installed if installed.is_dir() else REPO_DATA).resolve()
    assert {"models", "stones", "reference"} <= {p.name for p in d.iterdir()}
    assert {p.name for p in (d / "stones").iterdir()} == {p.name for p in (REPO_DATA / "stones").iterdir()}


def test_data_path_finds_the_shipped_files() -> None:
    stones = resources.data_path("stones", "profile_II_seed0.csv")
    assert stones.is_file() and stones.parent == resources.data_dir() / "stones"
    ref = json.loads(resources.data_path("reference", "paper_results.json").read_text())
    assert {"paper_a", "paper_b"} <= set(ref)
    assert resources.data_path("models", "digit_like").is_dir()
    assert resources.data_path() == resources.data_dir()
    assert not resources.data_path("stones", "no_such_profile.csv").exists()  # a path, not a check


def test_an_installed_data_folder_wins(tmp_path: Path, monkeypatch) -> None:
    pkg = tmp_path / "lipmpcc"
    (pkg / "data").mkdir(parents=True)
    monkeypatch.setattr(resources, "_PKG", pkg)
    assert resources.data_dir() == pkg / "data"
    assert resources.data_path("stones", "x.csv") == pkg / "data" / "stones" / "x.csv"
