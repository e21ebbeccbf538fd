"""lipmpcc.plots.stone_field: the field, a relaxation's binaries and a branch-and-bound's nodes are drawn."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from lipmpcc.planners.stone_milp import MilpStoneFieldPlanner, branch_and_bound, relax  # noqa: E402
from lipmpcc.plots.stone_field import plot_bnb_tree, plot_field, plot_relaxation  # noqa: E402
from lipmpcc.stone_field import make_stone_field  # noqa: E402
from lipmpcc.terrain import entry_foothold  # noqa: E402


def test_the_figures_draw_what_they_are_given() -> None:
    fld = make_stone_field(3, length=1.6, density=5.0, pedestrian_speed=0.4)
    ax = plot_field(fld, footholds=np.array([entry_foothold()]), highlight=[0, 1], times=[1.0, 2.0])
    assert len(ax.patches) == fld.n_stones + 1 + 2  # the stones, the goal, the pedestrian twice
    prob = MilpStoneFieldPlanner(fld).problem(entry_foothold(), +1, horizon=2)
    ax2 = plot_relaxation(prob, relax(prob)[1])
    assert ax2.images[0].get_array().shape == (2, len(set(np.concatenate(prob.candidates))))
    res = branch_and_bound(prob)
    ax3 = plot_bnb_tree(res)
    assert sum(len(c.get_offsets()) for c in ax3.collections) >= res.n_nodes
    plt.close("all")
