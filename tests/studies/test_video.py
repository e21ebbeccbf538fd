"""lipmpcc.studies.video: video file names, runs without recorded frames, and (where offscreen rendering
works) frames with the reference path and the obstacles drawn into the scene."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, RenderUnavailableError
from lipmpcc.obstacles import Obstacle
from lipmpcc.paths import LinePath
from lipmpcc.sim import render
from lipmpcc.studies import video

SCENE = """
<mujoco>
  <worldbody>
    <light pos="0 0 3"/>
    <geom type="plane" size="5 5 0.1" rgba="0.9 0.9 0.9 1"/>
    <body name="torso" pos="0 0 0.5"><freejoint/><geom type="sphere" size="0.1" rgba="0.2 0.2 0.8 1"/></body>
  </worldbody>
</mujoco>
"""


def _run(frames: np.ndarray | None) -> tuple[SimpleNamespace, SimpleNamespace]:
    """What the video functions read of a full-body loop and its result (a ball for a robot)."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(SCENE)
    loop = SimpleNamespace(sim=SimpleNamespace(model=model), params=SimpleNamespace(video_fps=10.0),
                           robot=SimpleNamespace(torso_body="torso"))
    times = None if frames is None else 0.1 * np.arange(len(frames))
    return loop, SimpleNamespace(frames=frames, frame_times=times)


def test_video_file_is_mp4_when_it_can_be_written_else_gif(tmp_path: Path) -> None:
    f = video.video_file(tmp_path, "walk")
    assert f.parent == tmp_path and f.stem == "walk"
    assert f.suffix == (".mp4" if render.mp4_available() else ".gif")


def test_a_run_without_recorded_frames(tmp_path: Path) -> None:
    loop, result = _run(None)
    assert video.write_run_video(loop, result, tmp_path, "walk") == []
    loop, empty = _run(np.zeros((0, 7)))
    assert video.write_run_video(loop, empty, tmp_path, "walk") == []
    with pytest.raises(InvalidInputError, match="record_video=True"):
        video.render_path_frames(loop, result, LinePath((0, 0), (3, 0)))
    assert not any(tmp_path.iterdir())


def test_frames_show_the_path_and_the_obstacles(tmp_path: Path) -> None:
    q = np.zeros((3, 7))
    q[:, 2] = 0.5
    q[:, 3] = 1.0
    q[:, 0] = [0.0, 0.5, 1.0]
    loop, result = _run(q)
    path = LinePath((-2, 0), (3, 0))
    settings = render.VideoSettings(width=96, height=64, track_body="torso", distance=3.0, elevation=-60.0)
    try:
        bare, times = video.render_path_frames(loop, result, LinePath((-2, 40), (3, 40)), settings=settings)
    except RenderUnavailableError as err:
        pytest.skip(f"no OpenGL backend here: {err}")
    drawn, _ = video.render_path_frames(loop, result, path, [Obstacle.circle(0.25, path=path, s0=3.0, speed=0.0)],
                                        times=[0.0, 0.19], settings=settings)
    assert len(bare) == 3 and np.allclose(times, [0.0, 0.1, 0.2])
    assert len(drawn) == 2 and drawn[0].shape == (64, 96, 3)  # the nearest frames of 0 and 0.19 s
    # the red path line on the floor: pixels far redder than anything in the frame without it
    redness = lambda img: (img[..., 0].astype(int) - img[..., 1].astype(int)).max()  # noqa: E731
    assert redness(drawn[0]) > redness(bare[0]) + 50
    out = video.write_path_video(loop, result, path, [], tmp_path / "walk.gif", size=(96, 64), every=2)
    import imageio.v3 as iio

    assert out == tmp_path / "walk.gif" and iio.imread(out, index=None).shape[0] == 2


def test_write_path_video_refuses_a_file_it_cannot_write_in_one_line(tmp_path, monkeypatch) -> None:
    loop = SimpleNamespace()  # nothing is rendered: the file is checked first
    (tmp_path / "taken.mp4").mkdir()
    for file, words in ((tmp_path / "taken.mp4", "existing folder"), (tmp_path / "no" / "v.gif", "does not exist"),
                        (tmp_path / "v.avi", ".mp4 or .gif")):
        with pytest.raises(InvalidInputError, match=words) as err:
            video.write_path_video(loop, SimpleNamespace(), LinePath((0, 0), (1, 0)), [], file)
        assert "\n" not in str(err.value)
    monkeypatch.setattr("os.access", lambda path, mode: False)
    with pytest.raises(InvalidInputError, match="read-only"):
        video.write_path_video(loop, SimpleNamespace(), LinePath((0, 0), (1, 0)), [], tmp_path / "v.mp4")
