"""Deprecated: moved to :mod:`lipmpcc.planners.sources.mpcc` in lipmpcc 0.2 (issue 24: one MPCC source module; see
CHANGELOG.md); removed in 0.3."""

from ..._deprecated import forward

__getattr__, __dir__ = forward(__name__, "lipmpcc.planners.sources.mpcc")
