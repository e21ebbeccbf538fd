"""Solutions to the exercises of notebook 00 (the roadmap)."""

from __future__ import annotations

import numpy as np


def dcm(x, xdot, omega):
    """ξ = x + ẋ/ω."""
    return np.asarray(x, dtype=float) + np.asarray(xdot, dtype=float) / float(omega)


def reading_order(needs, target):
    """A depth-first post-order from ``target`` over "b needs a": every prerequisite before its dependents."""
    order: list[str] = []

    def visit(b: str) -> None:
        if b in order:
            return
        for a, bb in needs:
            if bb == b:
                visit(a)
        order.append(b)

    visit(target)
    return order
