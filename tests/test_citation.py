"""CITATION.cff: valid YAML of the Citation File Format, citing the package and both papers with the
arXiv DOIs that README links to."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

yaml = pytest.importorskip("yaml")
ROOT = Path(__file__).resolve().parents[1]
CFF = ROOT / "CITATION.cff"


@pytest.mark.skipif(not CFF.is_file(), reason="needs the source tree")
def test_citation_cites_both_papers_with_their_dois() -> None:
    cff = yaml.safe_load(CFF.read_text())
    assert cff["cff-version"] == "1.2.0" and cff["type"] == "software" and cff["license"] == "MIT"
    refs = {r["doi"]: r for r in cff["references"]}
    readme = (ROOT / "README.md").read_text()
    for arxiv, word in (("2308.00119", "Overtaking"), ("2403.17136", "Adaptive Step Duration")):
        ref = refs[f"10.48550/arXiv.{arxiv}"]
        assert ref["title"].startswith(word) and ref["url"] == f"https://arxiv.org/abs/{arxiv}"
        assert len(ref["authors"]) == 4
        assert f"(https://arxiv.org/abs/{arxiv})" in readme
    version = re.search(r'^version = "([^"]+)"', (ROOT / "pyproject.toml").read_text(), re.M)
    assert version and cff["version"] == version.group(1)
