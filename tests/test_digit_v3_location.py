"""Where the tests look for the optional Digit v3 model: ``$LIPMPCC_DIGIT_V3`` first, else
``../shared/models/digit-v3/digit-v3.xml`` beside the repository (CONTRIBUTING.md, docs/formats.md)."""

from __future__ import annotations

from pathlib import Path

import pytest

from .conftest import DEFAULT_SHARED_DIGIT, DIGIT_V3_ENV, REPO, shared_digit_path


def test_the_variable_names_the_file(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    model = tmp_path / "my models" / "digit-v3.xml"
    monkeypatch.setenv(DIGIT_V3_ENV, str(model))
    assert shared_digit_path() == model


def test_a_relative_path_is_taken_from_the_working_directory(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv(DIGIT_V3_ENV, "models/digit-v3.xml")
    assert shared_digit_path() == tmp_path / "models" / "digit-v3.xml"


@pytest.mark.parametrize("value", [None, "", "  "])
def test_unset_or_empty_falls_back_beside_the_repository(monkeypatch: pytest.MonkeyPatch, value: str | None) -> None:
    if value is None:
        monkeypatch.delenv(DIGIT_V3_ENV, raising=False)
    else:
        monkeypatch.setenv(DIGIT_V3_ENV, value)
    assert shared_digit_path() == DEFAULT_SHARED_DIGIT == REPO.parent / "shared" / "models" / "digit-v3" / "digit-v3.xml"
