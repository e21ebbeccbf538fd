"""Your own path and obstacles on the full body: digit_like in MuJoCo, paper A's MPCC choosing its
footsteps, the whole-body QP tracking them.

    python examples/digit_own_path.py --out results/examples

The same files as ``lip_own_path.py`` (``data/examples/my_waypoints.csv``, ``my_obstacles.json``); the path
starts where the robot stands (the origin, facing +x). Walks 20 s (6 s in fast mode) and writes
``digit_own_path.png``. The CLI does the same: ``lipmpcc run overtake --robot digit_like --path ... --obstacles ...``.
"""

import matplotlib.pyplot as plt

from lipmpcc import config
from lipmpcc.obstacles import obstacles_from_json
from lipmpcc.paths import load_path_csv
from lipmpcc.plots.path_following import plot_path
from lipmpcc.robots import load_robot
from lipmpcc.studies.path_following import simulate_full_body

from _common import parse_out, sample

out = parse_out(__doc__.splitlines()[0])
path = load_path_csv(sample("my_waypoints.csv"))
obstacles = obstacles_from_json(sample("my_obstacles.json"), path)
run = simulate_full_body(load_robot("digit_like"), "overtake", "mpcc", path=path, obstacles=obstacles,
                         duration=config.horizon(20.0, 6.0))
s = run.summary
print(f"{s['steps']} steps in {s['duration_s']:.1f} s, fell={s['fell']}, min clearance {s['min_clearance_m']:.2f} m, "
      f"solver failures {s['solver_failures']}, real-time factor {run.result.real_time_factor:.1f}")

fig, ax = plt.subplots(figsize=(7, 5))
plot_path(ax, run.log, path, obstacles)
ax.set_title("MPCC on digit_like: your path and obstacles")
fig.savefig(out / "digit_own_path.png", dpi=110, bbox_inches="tight")
print(f"-> {out / 'digit_own_path.png'}")
