"""Plot a saved full-body run from its folder alone: ``summary.json`` and ``replay.npz`` (no simulation):
the torso's path seen from above, the footholds where each foot landed, the planned footholds, the
reference path and the obstacles when the run had them.

    python examples/plot_saved_run.py --out results/examples [--run RUN_DIR]

Without ``--run``, first makes a run to plot: a digit_like walk of 6 s (2 s in fast mode), turning.
Writes ``plot_saved_run.png``. Any folder of ``lipmpcc run ... --robot digit_like`` works, e.g.
``lipmpcc run overtake --robot digit_like --out runs/ot`` then ``--run runs/ot``.
"""

import json
import shutil
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from lipmpcc import config, studies
from lipmpcc.studies.replay import load_replay

from _common import parse_out

run_dir = None
if "--run" in sys.argv:
    i = sys.argv.index("--run")
    run_dir = Path(sys.argv[i + 1])
    del sys.argv[i:i + 2]
out = parse_out(__doc__.splitlines()[0])
if run_dir is None:
    run_dir = out / "plot_saved_run_walk"
    shutil.rmtree(run_dir, ignore_errors=True)
    opts = studies.RunOptions(scenario="walk", robot="digit_like", duration=config.horizon(6.0, 2.0), speed=0.5,
                              yaw_rate=0.3, out=str(run_dir))
    studies.run(opts).save(run_dir)

summary = json.loads((run_dir / "summary.json").read_text())
replay = load_replay(run_dir)
base_xy = replay.qpos[:, :2]  # the floating base (x, y) of each frame [m]

fig, ax = plt.subplots(figsize=(7, 5))
if len(replay.path_xy):
    ax.plot(*replay.path_xy.T, "r-", lw=1, label="reference path")
for j in range(replay.obstacle_xy.shape[1]):
    ax.plot(*replay.obstacle_xy[:, j].T, ":", color="grey", lw=1)
    circle = plt.Circle(replay.obstacle_xy[-1, j], replay.obstacle_axes[j, 0], color="grey", alpha=0.4)
    ax.add_patch(circle)
ax.plot(*base_xy.T, "k-", lw=1.5, label="torso (base)")
for side, colour, name in ((0, "tab:blue", "left foot"), (1, "tab:orange", "right foot")):
    xy = replay.touchdown_xyz[replay.touchdown_side == side, :2]
    ax.plot(*xy.T, "o", color=colour, ms=6, label=f"{name} landed")
ax.plot(*replay.plan_xy.T, "x", color="tab:green", ms=4, alpha=0.6, label="planned footholds")
ax.set_aspect("equal")
ax.set_xlabel("x [m]")
ax.set_ylabel("y [m]")
ax.legend(loc="best", fontsize=8)
ax.set_title(f"{summary['scenario']} on {summary['robot']}: {summary['steps']} steps in {replay.duration:.1f} s, "
             f"fell={summary['fell']}")
fig.savefig(out / "plot_saved_run.png", dpi=110, bbox_inches="tight")
steps = np.linalg.norm(np.diff(replay.touchdown_xyz[:, :2], axis=0), axis=1)  # foot-to-foot distance [m]
print(f"{len(replay.touchdown_t)} footholds, {len(replay.plan_t)} plans, mean step (foot to foot) "
      f"{(np.mean(steps) if len(steps) else float('nan')):.2f} m -> {out / 'plot_saved_run.png'}")
