"""Shared pytest fixtures."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

REPO = Path(__file__).resolve().parents[1]
SHARED_DIGIT = REPO.parent / "shared" / "models" / "digit-v3" / "digit-v3.xml"


@pytest.fixture
def shared_digit_xml() -> Path:
    """Path of the reference Digit v3 MJCF; skips when ../shared is absent."""
    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT}")
    return SHARED_DIGIT


@pytest.fixture(scope="session")
def shared_digit():
    """The reference Digit v3 described once (:func:`lipmpcc.robots.load_robot`); skips when ../shared is absent."""
    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT}")
    from lipmpcc.robots import load_robot

    return load_robot(SHARED_DIGIT)
