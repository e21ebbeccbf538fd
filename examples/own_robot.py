"""Your own robot: an MJCF and a layout file that tells lipmpcc which bodies are the feet, the torso
and the legs (docs/formats.md, "Robot layouts"; docs/architecture.md, "Add a robot").

    python examples/own_robot.py --out results/examples [--mjcf my_robot.xml --layout my_layout.toml]

Without arguments it reads the packaged digit_like MJCF with the commented sample layout
``data/examples/my_layout.toml`` (a copy of digit_like's). For your robot, ``lipmpcc robot init my_robot.xml
--out my_layout.toml`` writes a first layout from the MJCF (docs/add_a_robot.md explains every key), or edit a
copy of that file. It prints what lipmpcc understood, lets the robot stand for 2 s under the whole-body QP
and writes ``own_robot.png``.
"""

import argparse
from pathlib import Path

import matplotlib.pyplot as plt

from lipmpcc.loops.fullbody import FullBodyLoop
from lipmpcc.plots.walking import stand_view
from lipmpcc.resources import data_path
from lipmpcc.robots import load_robot

from _common import sample

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--out", default="results/examples")
p.add_argument("--mjcf", default=str(data_path("models", "digit_like", "digit_like.xml")), help="your robot's MJCF")
p.add_argument("--layout", default=str(sample("my_layout.toml")), help="its layout file (TOML)")
args = p.parse_args()
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)

robot = load_robot(args.mjcf, layout=args.layout)  # every named part is checked against the model
print(f"{robot.name}: {robot.total_mass:.1f} kg, {len(robot.motor_names)} motors, "
      f"{len(robot.leg_joints)} leg joints, feet {robot.left_foot_body!r}/{robot.right_foot_body!r}, "
      f"standing COM height {robot.standing.com[2]:.3f} m, closed loops: {robot.closed_loops}")

result = FullBodyLoop(robot).run(duration=2.0)  # no planner: the robot stands (double support)
print(f"stood {result.sim_time:.1f} s, fell={result.fell}, WBC median {result.wbc_ms['median']:.2f} ms")
fig = stand_view(result)
fig.savefig(out / "own_robot.png", dpi=110, bbox_inches="tight")
plt.close(fig)
print(f"-> {out / 'own_robot.png'}")
