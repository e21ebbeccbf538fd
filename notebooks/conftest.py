"""Notebooks run under nbval in fast mode: ``LIPMPCC_FAST=1`` shortens every run's
horizon (steps / seconds simulated) and changes nothing else. The kernel that nbval
starts inherits this environment."""

import os

os.environ["LIPMPCC_FAST"] = "1"
os.environ.setdefault("MPLBACKEND", "Agg")
