"""Notebooks run under nbval in fast mode: ``LIPMPCC_FAST=1`` shortens every run's
horizon (steps / seconds simulated) and changes nothing else. The exercises run with their
solutions (``LIPMPCC_SOLUTIONS``, :mod:`lipmpcc.course.exercises`): a check that fails, or a solution
that no longer matches the library, fails the notebook's test. The kernel that nbval starts inherits
this environment."""

import os
from pathlib import Path

os.environ["LIPMPCC_FAST"] = "1"
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ["LIPMPCC_SOLUTIONS"] = str(Path(__file__).resolve().parent / "solutions")
