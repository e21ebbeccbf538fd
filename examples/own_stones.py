"""Your own stepping stones on the ALIP, with paper B's ALIP-MPC (adaptive step duration).

    python examples/own_stones.py --out results/examples

Reads ``data/examples/my_stones.csv`` (rows x,y[,size_x,size_y] [m]; the robot stands at the origin
facing +x, walks 6 approach steps ending on its left foot at (1.05, 0.14), then steps on the stones, the
first with its right foot: docs/formats.md), walks them and writes ``own_stones.png``.
"""

import matplotlib.pyplot as plt

from lipmpcc.loops.alip import loop_metrics
from lipmpcc.plots.stepping_stones import plot_footprints
from lipmpcc.studies.stepping_stones import run_case
from lipmpcc.terrain import load_stones

from _common import parse_out, sample

out = parse_out(__doc__.splitlines()[0])
stones = load_stones(sample("my_stones.csv"))  # refuses a stone the robot cannot reach, naming the row
log, metrics = run_case("alip-mpc", stones)  # the approach + your stones, ALIP-MPC throughout
print(f"{metrics['n_stones']} stones: completed={metrics['completed']}, fell={metrics['fell']}, "
      f"stones missed {metrics['stones_violated']}, foot-placement RMSE {1000 * metrics['step_rmse_m']:.1f} mm, "
      f"step durations {metrics['step_duration_min_s']:.2f}-{metrics['step_duration_max_s']:.2f} s")

fig = plot_footprints(log, title="ALIP-MPC on your stones")
fig.savefig(out / "own_stones.png", dpi=110, bbox_inches="tight")
plt.close(fig)
print(f"-> {out / 'own_stones.png'}")
