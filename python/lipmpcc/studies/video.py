"""Videos and frames of full-body runs: the configurations recorded during a run
(``record_video=True``), rendered offscreen, optionally with a reference path and obstacles drawn into
the MuJoCo scene (the model has neither)."""

from __future__ import annotations

from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..obstacles import Obstacle
from ..paths import Path

if TYPE_CHECKING:  # pragma: no cover
    from ..loops.fullbody.loop import FullBodyLoop, LoopResult
    from ..sim.render import VideoRecorder, VideoSettings

__all__ = ["video_file", "write_run_video", "render_path_frames", "write_path_video"]


def video_file(out: str | FsPath, name: str) -> FsPath:
    """``out/NAME.mp4``, or ``out/NAME.gif`` when MP4 is not available (imageio-ffmpeg missing)."""
    from ..sim import render

    suffix = ".mp4" if ".mp4" in render.video_formats() else ".gif"
    return FsPath(out) / f"{name}{suffix}"


def write_run_video(loop: FullBodyLoop, result: LoopResult, out: str | FsPath, name: str) -> list[FsPath]:
    """Render the configurations ``result`` recorded to :func:`video_file` ``(out, name)``, tracking the
    torso; ``[]`` when nothing was recorded."""
    if result.frames is None or len(result.frames) == 0:
        return []
    from ..sim import render

    settings = render.VideoSettings(fps=loop.params.video_fps, track_body=loop.robot.torso_body)
    return [FsPath(render.write_video(loop.sim.model, result.frames, video_file(out, name), settings))]


def _path_recorder(loop: FullBodyLoop, path: Path, obstacles: Sequence[Obstacle], settings: VideoSettings) -> VideoRecorder:
    """A video recorder that also draws the reference path (red, on the floor, within 4 m of the robot)
    and the obstacles at the time ``t`` [s] of each frame (:func:`lipmpcc.sim.decorations.draw_decorations`,
    as the live viewer and the replays do)."""
    import mujoco

    from ..sim import render
    from ..sim.decorations import PATH_SAMPLE_M, SceneDecorations, draw_decorations

    pts = path.position(np.arange(0.0, path.length + 1e-9, PATH_SAMPLE_M))

    class SceneRecorder(render.VideoRecorder):
        t = 0.0  # time of the frame being rendered [s]

        def render(self, data: mujoco.MjData, decorate: object = None) -> np.ndarray:
            t = self.t
            obs = [(*ob.center(t), ob.axes[0], ob.axes[1], ob.heading(t), float(ob.is_circle)) for ob in obstacles]
            deco = SceneDecorations(path_xy=pts, obstacles=np.reshape(obs, (-1, 6)),
                                    near_xy=np.asarray(data.subtree_com[0][:2]))
            return super().render(data, lambda scn: draw_decorations(scn, deco))

    return SceneRecorder(loop.sim.model, settings)


def render_path_frames(
    loop: FullBodyLoop,
    result: LoopResult,
    path: Path,
    obstacles: Sequence[Obstacle] = (),
    times: Sequence[float] | None = None,
    settings: VideoSettings | None = None,
    size: tuple[int, int] = (640, 480),
) -> tuple[list[np.ndarray], np.ndarray]:
    """Render a run recorded with ``record_video=True``, with its path and obstacles drawn in.

    Args:
        loop: the loop that ran (its ``sim.model`` is rendered).
        result: the run.
        path: the reference path; obstacles: the obstacles.
        times: wanted times [s] (the nearest recorded frames); None: every recorded frame.
        settings: :class:`~lipmpcc.sim.render.VideoSettings` (None: tracking the torso, seen from behind
            on its right, 4.5 m away).
        size: (width, height) of the images [px] when ``settings`` is None.

    Returns:
        (RGB images, their times [s]).
    """
    import mujoco

    from ..sim import render

    frames, ftimes = result.frames, result.frame_times
    if frames is None or len(frames) == 0:
        raise InvalidInputError("run", "no recorded frames", "a run simulated with record_video=True")
    idx = np.arange(len(frames)) if times is None else np.unique(
        [int(np.argmin(np.abs(ftimes - float(t)))) for t in times]
    )
    if settings is None:
        settings = render.VideoSettings(width=int(size[0]), height=int(size[1]), fps=loop.params.video_fps,
                                        track_body=loop.robot.torso_body, distance=4.5, azimuth=35.0, elevation=-20.0)
    model = loop.sim.model
    data = mujoco.MjData(model)
    images = []
    with _path_recorder(loop, path, obstacles, settings) as rec:
        for i in idx:
            data.qpos[:] = frames[i]
            mujoco.mj_forward(model, data)
            rec.t = float(ftimes[i])
            images.append(rec.render(data))
    return images, np.asarray(ftimes)[idx]


def write_path_video(
    loop: FullBodyLoop,
    result: LoopResult,
    path: Path,
    obstacles: Sequence[Obstacle],
    file: str | FsPath,
    size: tuple[int, int] | None = None,
    every: int | None = None,
) -> FsPath:
    """Write the video of a run with its path and obstacles drawn in.

    Args:
        loop, result, path, obstacles: as :func:`render_path_frames`.
        file: ``.mp4`` (needs imageio-ffmpeg) or ``.gif``.
        size: (width, height) [px]; None: 640×480 for MP4, 400×300 for GIF.
        every: keep every ``every``-th recorded frame; None: all for MP4 (30 fps), every 2nd for GIF
            (15 fps), which keeps a 45 s GIF near 20 MB.

    Raises:
        InvalidInputError: ``file`` cannot be written (:func:`lipmpcc.studies.replay.check_video_file`).
    """
    from ..sim import render
    from .replay import check_video_file

    check_video_file(file)  # one line for an existing folder, a missing or read-only one, another suffix
    gif = FsPath(file).suffix.lower() == ".gif"
    size = size or ((400, 300) if gif else (640, 480))
    every = max(1, int(every or (2 if gif else 1)))
    times = result.frame_times[::every] if result.frame_times is not None else None
    images, _ = render_path_frames(loop, result, path, obstacles, times, size=size)
    return FsPath(render.save_frames(images, file, loop.params.video_fps / every))
