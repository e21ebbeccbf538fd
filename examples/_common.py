"""What every example shares: where its output goes and where the sample files are."""

from __future__ import annotations

import argparse
from pathlib import Path

from lipmpcc.resources import data_path

__all__ = ["parse_out", "sample"]


def parse_out(description: str) -> Path:
    """``--out DIR`` (default ``results/examples``), created."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--out", default="results/examples", help="folder for the figures")
    out = Path(p.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)
    return out


def sample(name: str) -> Path:
    """A sample file of ``data/examples/`` (docs/formats.md describes each format)."""
    return data_path("examples", name)
