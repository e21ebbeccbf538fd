"""Deprecated: moved to :mod:`lipmpcc.control` in lipmpcc 0.2 (see CHANGELOG.md); removed in 0.3.

``WholeBodyController`` → :mod:`lipmpcc.control.wbc`; ``TaskGains``, ``PostureGains``,
``WbcParams``, ``WbcReference``, ``WbcTaskErrors``, ``WbcOutput`` → :mod:`lipmpcc.control.wbc_types`;
the reading of the MJCF for the controller → :mod:`lipmpcc.robots.wbc_model`.
"""

from ._deprecated import forward

__getattr__, __dir__ = forward(__name__, "lipmpcc.control.wbc_types", renames={
    "WholeBodyController": "lipmpcc.control.wbc:WholeBodyController",
})
