"""Your own path and obstacles on the 3D-LIP, with paper A's MPCC.

    python examples/lip_own_path.py --out results/examples

Reads ``data/examples/my_waypoints.csv`` (a spline through waypoints [m]) and
``data/examples/my_obstacles.json`` (circles and ellipses, static or moving), walks 60 steps and
writes ``lip_own_path.png``. Replace the two files by yours (docs/formats.md).
"""

import numpy as np
import matplotlib.pyplot as plt

from lipmpcc import config
from lipmpcc.loops.lip import run_lip_loop, summarize
from lipmpcc.obstacles import obstacles_from_json
from lipmpcc.paths import load_path_csv
from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
from lipmpcc.plots.path_following import plot_path
from lipmpcc.studies.path_metrics import lip_path_log

from _common import parse_out, sample

out = parse_out(__doc__.splitlines()[0])
path = load_path_csv(sample("my_waypoints.csv"))
obstacles = obstacles_from_json(sample("my_obstacles.json"), path)  # "s" positions are along this path
params = MpccParams.overtake_mpcc()  # paper A's overtaking weights: contouring 1, lag 1000 (the path is a loose guide)
planner = MpccPlanner(path, params)

p0 = path.position(0.0)
x0 = np.array([p0[0], 0.0, p0[1], 0.0, path.slope(0.0)])              # [x, ẋ, y, ẏ, heading] at rest
log = run_lip_loop(planner, x0, int(config.horizon(60, 25)), path, obstacles,
                   com_height=params.model.H, robot_radius=params.robot_radius, foot_radius=params.foot_radius)
s = summarize(log, obstacles)
print(f"{s['steps']} steps, stopped: {log.stopped_reason}, min clearance {s['min_clearance_m']:.2f} m, "
      f"solver failures {s['solver_failures']}")

fig, ax = plt.subplots(figsize=(7, 5))
plot_path(ax, lip_path_log(log), path, obstacles)
ax.set_title("MPCC on the LIP: your path and obstacles")
fig.savefig(out / "lip_own_path.png", dpi=110, bbox_inches="tight")
print(f"-> {out / 'lip_own_path.png'}")
