"""Figures, one module per study: ``path_following`` (paper A), ``stepping_stones``
(paper B) and ``walking`` (full-body runs)."""
