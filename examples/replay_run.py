"""Watch a full-body run again: a short digit_like walk saves ``replay.npz`` in its folder, and the replay
shows it in MuJoCo's viewer, or, without a display, renders it to a video.

    python examples/replay_run.py --out results/examples

Walks 6 s (2 s in fast mode) at 0.5 m/s turning at 0.3 rad/s, writes the run to ``OUT/replay_run_walk/``
(``summary.json``, ``replay.npz``, figures), then replays it: first in the viewer with ``--viewer-replay``
when there is a display, then always headless to ``OUT/replay_run.mp4``; ``replay_run.png`` is a frame of it. The CLI does
the same: ``lipmpcc run walk --robot digit_like --out DIR`` then ``lipmpcc replay DIR`` (or
``lipmpcc replay DIR --video walk.mp4``).
"""

import shutil
import sys

import imageio.v3 as iio

from lipmpcc import config, studies
from lipmpcc.studies.replay import load_replay, play, write_replay_video
from lipmpcc.studies.viewer import display_problem

from _common import parse_out

show = "--viewer-replay" in sys.argv  # opt in: CI and scripts stay headless
if show:
    sys.argv.remove("--viewer-replay")
out = parse_out(__doc__.splitlines()[0])
run_dir = out / "replay_run_walk"
shutil.rmtree(run_dir, ignore_errors=True)
opts = studies.RunOptions(scenario="walk", robot="digit_like", duration=config.horizon(6.0, 2.0), speed=0.5,
                          yaw_rate=0.3, out=str(run_dir))
result = studies.run(opts)  # result.replay: the run's replay, which save() writes as replay.npz
result.save(run_dir)
print(f"walk: {result.summary['steps']} steps, fell={result.summary['fell']} -> {run_dir}")

replay = load_replay(run_dir)
print(f"replay: {replay.n_frames} frames at {replay.fps:g} Hz over {replay.duration:.2f} s, "
      f"{len(replay.touchdown_t)} touch-downs, robot {replay.robot}")
if show and display_problem() is None:
    play(replay, speed=1.0)
video = write_replay_video(replay, out / "replay_run.mp4", progress=False)
frame = iio.imread(video, index=replay.n_frames // 2)
iio.imwrite(out / "replay_run.png", frame)
print(f"-> {video}, {out / 'replay_run.png'}")
