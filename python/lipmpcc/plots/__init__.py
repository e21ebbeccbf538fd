"""Figures, one module per study: ``path_following`` (paper A), ``stepping_stones`` (paper B) and
``walking`` (full-body runs). They read the records of :mod:`lipmpcc.plots.logs`, never a loop."""

from .logs import FullBodyRunResult, PathFollowingLog, SteppingStonesLog

__all__ = ["PathFollowingLog", "SteppingStonesLog", "FullBodyRunResult"]
