"""Where the package's data lives (robot models, stone profiles, reference numbers).

An installed wheel carries ``lipmpcc/data``; a source checkout has ``data/`` at the
repository root. :func:`data_dir` returns whichever exists.
"""

from __future__ import annotations

from pathlib import Path

__all__ = [
    "data_dir",
    "data_path",
]

_PKG = Path(__file__).resolve().parent


def data_dir() -> Path:
    """The folder holding ``models/``, ``stones/`` and ``reference/``."""
    installed = _PKG / "data"
    if installed.is_dir():
        return installed
    for parent in _PKG.parents:
        cand = parent / "data"
        if (cand / "models").is_dir() or (cand / "reference").is_dir() or (cand / "stones").is_dir():
            return cand
    return installed


def data_path(*parts: str) -> Path:
    """Path of a file under :func:`data_dir`, e.g. ``data_path("stones", "profile_I.csv")``."""
    return data_dir().joinpath(*parts)
