"""Figures of the stone field (issue 29, notebook 13): the field with footholds and pedestrians, an LP
relaxation's binaries, and the nodes a branch-and-bound explored."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..planners.stone_milp import BnbResult, FootstepMilp
from ..stone_field import StoneField

__all__ = ["plot_field", "plot_relaxation", "plot_bnb_tree", "BNB_COLORS"]

#: a branch-and-bound node's colour by status
BNB_COLORS = {"branched": "tab:blue", "pruned": "0.6", "infeasible": "tab:red", "integral": "tab:green", "open": "k"}


def plot_field(fld: StoneField, ax: Any = None, footholds: np.ndarray | None = None, label: str = "footholds",
               highlight: Sequence[int] = (), times: Sequence[float] = (), color: str = "tab:blue",
               title: str | None = None) -> Any:
    """Draw the stones (grey; ``highlight``ed ones orange, numbered), the goal (green), the path, optional
    ``footholds`` (k, 2) [m] joined in order, and each pedestrian's disk at ``times`` [s]; returns the axes."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle, Rectangle

    if ax is None:
        _, ax = plt.subplots(figsize=(9, 3.6))
    hi = set(int(j) for j in highlight)
    for j, (c, sz) in enumerate(zip(fld.centers, fld.sizes)):
        ax.add_patch(Rectangle(tuple(c - 0.5 * sz), sz[0], sz[1], color="tab:orange" if j in hi else "0.7", zorder=1))
        if hi or fld.n_stones <= 16:
            ax.text(c[0], c[1], str(j), ha="center", va="center", fontsize=6, zorder=2)
    g = fld.goal
    ax.add_patch(Rectangle(tuple(g.lower), g.size[0], g.size[1], color="tab:green", alpha=0.25, zorder=0))
    ax.plot(*fld.path.T, "k--", lw=0.8, label="path")
    if footholds is not None and len(footholds):
        f = np.asarray(footholds, float)
        ax.plot(f[:, 0], f[:, 1], "o-", ms=4, lw=0.8, color=color, label=label, zorder=3)
    for ped in fld.pedestrians:
        for i, t in enumerate(times):
            ax.add_patch(Circle(tuple(ped.center(float(t))), ped.axes[0], fill=False, color="tab:red",
                                alpha=0.3 + 0.7 * (i + 1) / len(times), lw=1.0))
        if len(times):
            track = np.array([ped.center(float(t)) for t in (times[0], times[-1])])
            ax.plot(track[:, 0], track[:, 1], color="tab:red", lw=0.8, label=f"pedestrian, t = {times[0]:.1f}–{times[-1]:.1f} s")
    lo = np.minimum(fld.centers.min(axis=0), g.lower) - 0.3
    hi_ = np.maximum(fld.centers.max(axis=0), g.upper) + 0.3
    ax.set_xlim(min(lo[0], 0.8), hi_[0])
    ax.set_ylim(lo[1], hi_[1])
    ax.set_aspect("equal")
    ax.set(xlabel="x [m]", ylabel="y [m]", title=title or fld.name)
    ax.legend(loc="upper left", fontsize=7)
    return ax


def plot_relaxation(prob: FootstepMilp, x: np.ndarray, ax: Any = None, title: str = "") -> Any:
    """The binaries z_kj of a (relaxed) solution ``x``: one row per step, one column per candidate node."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 2.4))
    nodes = sorted(set(int(j) for cand in prob.candidates for j in cand))
    Z = np.zeros((len(prob.candidates), len(nodes)))
    for k, (cand, zi) in enumerate(zip(prob.candidates, prob.z_index)):
        for j, v in zip(cand, x[zi]):
            Z[k, nodes.index(int(j))] = v
    im = ax.imshow(Z, cmap="Blues", vmin=0.0, vmax=1.0, aspect="auto")
    ax.set_xticks(range(len(nodes)), [str(j) for j in nodes], fontsize=7)
    ax.set_yticks(range(len(prob.candidates)), [f"step {k + 1}" for k in range(len(prob.candidates))])
    ax.set(xlabel="stone (the last: the goal)", title=title)
    ax.figure.colorbar(im, ax=ax, label="$z_{kj}$")
    return ax


def plot_bnb_tree(res: BnbResult, ax: Any = None, title: str = "") -> Any:
    """Every node a branch-and-bound explored: its depth against the order it was explored in, its LP bound
    as the height of a bar, coloured by what became of it (:data:`BNB_COLORS`); the optimum dashed."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(8, 3))
    ids = np.array([n.id for n in res.nodes])
    bounds = np.array([n.bound if np.isfinite(n.bound) else np.nan for n in res.nodes])
    for status, color in BNB_COLORS.items():
        sel = np.array([n.status == status for n in res.nodes])
        if sel.any():
            ax.scatter(ids[sel], bounds[sel], s=10, color=color, label=f"{status} ({int(sel.sum())})")
    bad = np.array([n.status == "infeasible" for n in res.nodes])
    if bad.any():
        ax.scatter(ids[bad], np.full(int(bad.sum()), np.nanmax(bounds) if np.isfinite(np.nanmax(bounds)) else 0.0),
                   s=10, marker="x", color=BNB_COLORS["infeasible"])
    if np.isfinite(res.cost):
        ax.axhline(res.cost, color="k", ls="--", lw=0.8, label=f"optimum {res.cost:.3f}")
    ax.set(xlabel="node (in the order explored)", ylabel="LP relaxation bound", title=title)
    ax.legend(fontsize=7, loc="lower right")
    return ax
