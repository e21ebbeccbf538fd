"""Your own footstep planner (``my_planner.py``) in the 3D-LIP loop.

    python examples/own_planner_lip.py --out results/examples

Walks 20 steps along a line from rest and writes ``own_planner_lip.png`` (footholds and COM).
"""

import matplotlib.pyplot as plt
import numpy as np

from lipmpcc.loops.lip import run_lip_loop, summarize
from lipmpcc.paths import LinePath

from _common import parse_out
from my_planner import CapturePointPlanner

out = parse_out(__doc__.splitlines()[0])
path = LinePath((0.0, 0.0), (10.0, 0.0))                 # only for the contouring error of the summary
log = run_lip_loop(CapturePointPlanner(step=0.15), x0=np.zeros(5), n_steps=20, path=path)
s = summarize(log)
print(f"{s['steps']} steps, fell={s['fell']}, walked {s['progress_m']:.2f} m, "
      f"max lateral sway {s['contouring_error_max_m']:.3f} m")

fig, ax = plt.subplots(figsize=(8, 2.5))
ax.plot(log.com[:, 0], log.com[:, 1], label="COM")
ax.plot(log.footholds[::2, 0], log.footholds[::2, 1], "o", label="left foot")
ax.plot(log.footholds[1::2, 0], log.footholds[1::2, 1], "s", label="right foot")
ax.set(xlabel="x [m]", ylabel="y [m]", title="Your capture-point planner on the 3D-LIP", aspect="equal")
ax.legend(loc="upper left", fontsize=8)
fig.savefig(out / "own_planner_lip.png", dpi=110, bbox_inches="tight")
print(f"-> {out / 'own_planner_lip.png'}")
