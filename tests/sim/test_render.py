"""lipmpcc.sim.render: videos (GIF; MP4 with imageio-ffmpeg) of the simulator, and the viewer's error without a display.
Skipped where no OpenGL backend is available (RenderUnavailableError)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, RenderUnavailableError
from lipmpcc.sim import render
from lipmpcc.exceptions import ParameterError
from lipmpcc.sim.robot_sim import RobotSim

BALL = "<mujoco><worldbody><body><freejoint/><geom size='0.1'/></body></worldbody></mujoco>"


@pytest.fixture
def sim() -> RobotSim:
    return RobotSim("digit_like")


def test_settings_are_checked() -> None:
    assert render.VideoSettings().fps == 30.0
    for field, value in (("width", 8), ("height", 640.0), ("fps", 0.0), ("fps", 500.0), ("distance", -1.0)):
        with pytest.raises(ParameterError, match=field):
            render.VideoSettings(**{field: value})


def test_gif_frames_are_written_without_opengl(tmp_path: Path) -> None:
    """save_frames needs no renderer: a GIF of hand-made frames reads back with the same size and count."""
    import imageio.v3 as iio

    frames = [np.full((32, 48, 3), v, np.uint8) for v in (0, 128, 255)]
    path = render.save_frames(frames, tmp_path / "sub" / "three.gif", fps=10)
    back = iio.imread(path, index=None)
    assert back.shape[:3] == (3, 32, 48) and back[0].max() < back[2].min()
    with pytest.raises(InvalidInputError, match="frame"):
        render.save_frames([], tmp_path / "none.gif", fps=10)
    assert render.video_formats() == ((".gif", ".mp4") if render.mp4_available() else (".gif",))
    assert isinstance(render.gl_backend(), str) and render.gl_backend()


def test_write_video_checks_the_configurations_before_rendering(tmp_path: Path) -> None:
    import mujoco

    model = mujoco.MjModel.from_xml_string(BALL)
    with pytest.raises(InvalidInputError, match="qpos_frames"):
        render.write_video(model, np.zeros((2, model.nq + 1)), tmp_path / "x.gif")
    with pytest.raises(InvalidInputError, match="qpos_frames"):
        render.write_video(model, np.full((2, model.nq), np.nan), tmp_path / "x.gif")
    with pytest.raises(InvalidInputError, match="qpos_frames"):
        render.write_video(model, np.zeros((0, model.nq)), tmp_path / "x.gif")


def test_short_gif_is_written_with_frames(tmp_path: Path) -> None:
    import imageio.v3 as iio

    sim = RobotSim("digit_like")
    settings = render.VideoSettings(width=160, height=128, fps=20, track_body="torso")
    try:
        rec = sim.recorder(settings)
    except RenderUnavailableError as err:
        pytest.skip(f"no OpenGL backend here: {err}")
    with rec:
        for _ in range(6):
            sim.step(np.zeros(20), 100)  # falling: every frame differs
            sim.forward()
            rec.capture(sim.data)
        path = rec.save(tmp_path / "fall.gif")
    frames = iio.imread(path, index=None)
    assert frames.shape[0] >= 4 and frames.shape[1:3] == (128, 160)
    assert frames.std() > 1.0  # not a blank image
    # the same from recorded configurations
    qs = np.stack([sim.qpos, sim.model.key("stand").qpos])
    path2 = render.write_video(sim.model, qs, tmp_path / "two.gif", settings, progress=False)
    assert iio.imread(path2, index=None).shape[0] == 2


def test_mp4_needs_imageio_ffmpeg(tmp_path: Path) -> None:
    frames = [np.zeros((32, 32, 3), np.uint8), np.full((32, 32, 3), 255, np.uint8)]
    if render.mp4_available():
        assert render.save_frames(frames, tmp_path / "v.mp4", 10).stat().st_size > 0
    else:
        with pytest.raises(RenderUnavailableError, match="imageio-ffmpeg"):
            render.save_frames(frames, tmp_path / "v.mp4", 10)
    with pytest.raises(InvalidInputError, match=".gif or .mp4"):
        render.save_frames(frames, tmp_path / "v.avi", 10)


def test_viewer_without_display_is_a_clear_error(monkeypatch: pytest.MonkeyPatch, sim: RobotSim) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(RenderUnavailableError, match="DISPLAY"):
        sim.view()


@pytest.mark.parametrize("suffix", [".mp4", ".gif"])
def test_video_writer_streams_frames_and_counts_them(tmp_path: Path, suffix: str) -> None:
    import imageio.v3 as iio

    frames = [np.full((64, 96, 3), 20 * i, dtype=np.uint8) for i in range(7)]
    with render.VideoWriter(tmp_path / f"v{suffix}", fps=10.0) as w:
        for f in frames:
            w.append(f)
        assert w.count == 7
    back = iio.imread(tmp_path / f"v{suffix}", index=None)
    assert back.shape[:3] == (7, 64, 96)
    with pytest.raises(InvalidInputError, match="writer"):
        w.append(frames[0])
    with pytest.raises(InvalidInputError, match=".gif or .mp4"):
        render.VideoWriter(tmp_path / "v.avi", fps=10.0)
    with pytest.raises(ParameterError, match="fps"):
        render.VideoWriter(tmp_path / "v.gif", fps=0.0)


def test_mp4_is_available_as_a_dependency() -> None:
    assert render.mp4_available() and render.video_formats() == (".gif", ".mp4")


def test_overlay_text_writes_white_on_a_dark_band_at_the_top_left() -> None:
    img = np.full((100, 200, 3), 128, dtype=np.uint8)
    out = render.overlay_text(img, ["t =   1.25 s", "push 50 N toward +90 deg"])
    assert out.shape == img.shape and np.array_equal(out[60:], img[60:])  # below the band: untouched
    corner = out[:40, :120]
    assert np.any(corner.max(axis=2) < 10) and np.any(corner.min(axis=2) > 240)
    assert np.array_equal(render.overlay_text(img, []), img)
