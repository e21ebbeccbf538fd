"""Your own footstep planner (``my_planner.py``) on the full body: digit_like in MuJoCo under the
whole-body QP.

    python examples/own_planner_fullbody.py --out results/examples

Walks 12 steps (6 in fast mode, ``LIPMPCC_FAST=1``) and writes ``own_planner_fullbody.png`` (top view).
"""

import matplotlib.pyplot as plt

from lipmpcc import config
from lipmpcc.loops.fullbody import FullBodyLoop
from lipmpcc.plots.walking import top_view
from lipmpcc.robots import load_robot

from _common import parse_out
from my_planner import CapturePointPlanner

out = parse_out(__doc__.splitlines()[0])
robot = load_robot("digit_like")                          # or load_robot("my_robot.xml"): own_robot.py
loop = FullBodyLoop(robot, CapturePointPlanner(step=0.15, T=robot.step_duration))
result = loop.run(n_steps=int(config.horizon(12, 6)))
print(f"{result.n_steps} steps in {result.sim_time:.1f} s (real-time factor {result.real_time_factor:.1f}), fell={result.fell}")

fig = top_view(result, title="Your capture-point planner on digit_like")
fig.savefig(out / "own_planner_fullbody.png", dpi=110, bbox_inches="tight")
plt.close(fig)
print(f"-> {out / 'own_planner_fullbody.png'}")
