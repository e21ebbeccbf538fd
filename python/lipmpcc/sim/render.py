"""Offscreen rendering of MuJoCo runs to GIF / MP4, for notebooks and the CLI.

Backend: without a display, MuJoCo needs a headless OpenGL backend. Importing this module before
MuJoCo sets ``MUJOCO_GL=egl`` (or ``osmesa`` when only libOSMesa is present) unless the variable is
already set; when MuJoCo was imported first and chose GLFW without a display, the EGL (or OSMesa)
context class is swapped in before the first renderer is made. :func:`gl_backend` tells which one is
in use. Settings follow TOOLCHAIN.md: no multisampling, no shadows or reflections (primitives only:
a few ms per frame).

Video: MP4 (H.264, through ``imageio-ffmpeg``, a dependency of the package) or GIF (imageio + Pillow).
Without ``imageio-ffmpeg`` (an install that skipped it), asking for MP4 raises
:class:`~lipmpcc.exceptions.RenderUnavailableError` naming the remedy. :class:`VideoWriter` writes
frames as they come (a long run is not held in memory); :func:`overlay_text` writes lines of text
onto a frame (the time, the push).

Typical use::

    with VideoRecorder(sim.model, VideoSettings(fps=30)) as rec:
        ...  # each frame: rec.capture(sim.data)
        rec.save("walk.gif")

or, from MuJoCo configurations recorded during a run, :func:`write_video`.
"""

from __future__ import annotations

import ctypes.util
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Sequence

import numpy as np

from ..exceptions import InvalidInputError, ParameterError, RenderUnavailableError


def _headless() -> bool:
    return not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY") and sys.platform.startswith("linux")


def _preferred_headless_backend() -> str:
    if ctypes.util.find_library("EGL"):
        return "egl"
    if ctypes.util.find_library("OSMesa"):
        return "osmesa"
    return "egl"


def prepare_gl() -> None:
    """Choose a headless OpenGL backend before MuJoCo is imported (no-op when it is set or not needed)."""
    if "mujoco" not in sys.modules and "MUJOCO_GL" not in os.environ and _headless():
        os.environ["MUJOCO_GL"] = _preferred_headless_backend()


prepare_gl()

import mujoco  # noqa: E402  (after prepare_gl on purpose)

__all__ = [
    "prepare_gl",
    "gl_backend",
    "mp4_available",
    "video_formats",
    "VideoSettings",
    "VideoRecorder",
    "save_frames",
    "write_video",
    "VideoWriter",
    "overlay_text",
]

_SWAPPED: str | None = None


def gl_backend() -> str:
    """The OpenGL backend offscreen rendering uses: ``"egl"``, ``"osmesa"``, ``"glfw"``, ..."""
    if _SWAPPED:
        return _SWAPPED
    try:
        from mujoco.rendering.classic import gl_context
    except ImportError:  # pragma: no cover - older MuJoCo layout
        from mujoco import gl_context  # type: ignore[no-redef]
    chosen = getattr(gl_context, "_MUJOCO_GL", os.environ.get("MUJOCO_GL", ""))
    return chosen or "glfw"


def _ensure_headless_context() -> None:
    """If MuJoCo picked GLFW although there is no display, swap in EGL or OSMesa."""
    global _SWAPPED
    if _SWAPPED or not _headless() or gl_backend() not in ("glfw", "", "enable", "enabled", "on", "true", "1"):
        return
    try:
        from mujoco.rendering.classic import gl_context
    except ImportError:  # pragma: no cover
        return
    errors = []
    for name in ("egl", "osmesa"):
        try:
            module = __import__(f"mujoco.{name}", fromlist=["GLContext"])
            gl_context.GLContext = module.GLContext  # the Renderer reads this attribute when it is made
            _SWAPPED = name
            return
        except Exception as err:  # noqa: BLE001 - any import problem means "try the next one"
            errors.append(f"{name}: {' '.join(str(err).split())}")
    raise RenderUnavailableError(
        "offscreen rendering",
        "no display and no headless OpenGL backend (" + "; ".join(errors) + "); install libegl1 or libosmesa6, "
        "or set MUJOCO_GL before importing mujoco",
    )


def mp4_available() -> bool:
    """True when MP4 files can be written (``imageio-ffmpeg`` importable)."""
    try:
        import imageio_ffmpeg  # noqa: F401
    except ImportError:
        return False
    return True


def video_formats() -> tuple[str, ...]:
    """File suffixes :meth:`VideoRecorder.save` can write here."""
    return (".gif", ".mp4") if mp4_available() else (".gif",)


@dataclass(frozen=True)
class VideoSettings:
    """How to film a run.

    Attributes:
        width, height: image size [px] (multiples of 16 keep MP4 encoders happy).
        fps: frames per second of the video [Hz].
        camera: a named MJCF camera, or None for a free camera tracking ``track_body``.
        track_body: body the free camera follows (None: the model's first body under the world).
        distance: free-camera distance [m].
        azimuth, elevation: free-camera angles [deg].
    """

    width: int = 640
    height: int = 480
    fps: float = 30.0
    camera: str | None = None
    track_body: str | None = None
    distance: float = 3.0
    azimuth: float = 150.0
    elevation: float = -15.0

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            v = getattr(self, name)
            if not isinstance(v, (int, np.integer)) or not 16 <= v <= 4096:
                raise ParameterError(name, v, "an integer number of pixels in [16, 4096]")
        if not (np.isfinite(self.fps) and 0.0 < self.fps <= 240.0):
            raise ParameterError("fps", self.fps, "a frame rate in (0, 240] Hz")
        if not (np.isfinite(self.distance) and self.distance > 0.0):
            raise ParameterError("distance", self.distance, "a positive camera distance [m]")


class VideoRecorder:
    """Renders frames of a model offscreen and writes them to a GIF or MP4 file.

    Close it (or use it as a context manager): an open MuJoCo renderer left to the interpreter's exit
    prints a traceback with some backends.
    """

    def __init__(self, model: mujoco.MjModel, settings: VideoSettings | None = None) -> None:
        self.model = model
        self.settings = settings or VideoSettings()
        s = self.settings
        self.frames: list[np.ndarray] = []
        _ensure_headless_context()
        # the offscreen buffer must hold the image
        model.vis.global_.offwidth = max(int(model.vis.global_.offwidth), s.width)
        model.vis.global_.offheight = max(int(model.vis.global_.offheight), s.height)
        model.vis.quality.offsamples = 0
        try:
            self._renderer = mujoco.Renderer(model, height=s.height, width=s.width)
        except Exception as err:  # noqa: BLE001 - GL failures come as several exception types
            raise RenderUnavailableError(
                "offscreen rendering",
                f"MuJoCo renderer with backend {gl_backend()!r} failed: {' '.join(str(err).split())}; "
                "try MUJOCO_GL=egl or MUJOCO_GL=osmesa (apt-get install libosmesa6) before importing mujoco",
            ) from None
        scene = self._renderer.scene
        scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = False
        scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = False
        self._option = mujoco.MjvOption()
        if s.camera is not None:
            cam_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, s.camera)
            if cam_id < 0:
                self.close()
                raise InvalidInputError("camera", s.camera, "the name of a camera of the model or None")
            self._camera: int | mujoco.MjvCamera = cam_id
        else:
            cam = mujoco.MjvCamera()
            cam.type = mujoco.mjtCamera.mjCAMERA_TRACKING
            body = 1 if model.nbody > 1 else 0
            if s.track_body is not None:
                body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, s.track_body)
                if body < 0:
                    self.close()
                    raise InvalidInputError("track_body", s.track_body, "the name of a body of the model")
            cam.trackbodyid = body
            cam.distance = s.distance
            cam.azimuth = s.azimuth
            cam.elevation = s.elevation
            cam.lookat[:] = 0.0
            self._camera = cam

    # ---- frames ------------------------------------------------------------------------------
    def render(self, data: mujoco.MjData, decorate: Callable[[mujoco.MjvScene], object] | None = None) -> np.ndarray:
        """One RGB image (height, width, 3) of ``data`` (its kinematics must be up to date);
        ``decorate(scene)`` may add geoms to the scene before it is drawn
        (:func:`lipmpcc.sim.decorations.draw_decorations`)."""
        if self._renderer is None:
            raise InvalidInputError("recorder", "closed", "an open VideoRecorder")
        self._renderer.update_scene(data, camera=self._camera, scene_option=self._option)
        if decorate is not None:
            decorate(self._renderer.scene)
        return self._renderer.render().copy()

    def capture(self, data: mujoco.MjData) -> None:
        """Render ``data`` and append the image to :attr:`frames`."""
        self.frames.append(self.render(data))

    def save(self, path: str | Path) -> Path:
        """Write the frames to ``path`` (``.gif``, or ``.mp4`` when imageio-ffmpeg is installed)."""
        return save_frames(self.frames, path, self.settings.fps)

    # ---- lifetime ----------------------------------------------------------------------------
    def close(self) -> None:
        """Free the renderer and its OpenGL context (idempotent)."""
        r = getattr(self, "_renderer", None)
        if r is not None:
            r.close()
        self._renderer = None

    def __enter__(self) -> "VideoRecorder":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:  # pragma: no cover - best effort
        try:
            self.close()
        except Exception:  # noqa: BLE001
            pass


def save_frames(frames: list[np.ndarray], path: str | Path, fps: float) -> Path:
    """Write RGB ``frames`` to ``path``; the suffix picks the format (``.gif`` or ``.mp4``)."""
    import imageio.v3 as iio

    path = Path(path)
    if not frames:
        raise InvalidInputError("frames", "[]", "at least one frame")
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise InvalidInputError("path", str(path), "a file name ending in .gif or .mp4")
    path.parent.mkdir(parents=True, exist_ok=True)
    stack = np.stack([np.asarray(f, dtype=np.uint8) for f in frames])
    if suffix == ".gif":
        # Pillow plugin: duration per frame in ms, loop forever
        iio.imwrite(path, stack, extension=".gif", duration=1000.0 / float(fps), loop=0)
    else:
        if not mp4_available():
            raise RenderUnavailableError(
                "MP4 video", "needs imageio-ffmpeg (pip install imageio-ffmpeg); write a .gif instead"
            )
        import imageio.v2 as iio2

        iio2.mimwrite(path, list(stack), fps=float(fps), format="FFMPEG", codec="libx264", quality=7,
                      macro_block_size=16)
    return path


def write_video(
    model: mujoco.MjModel,
    qpos_frames: Iterable[np.ndarray] | np.ndarray,
    path: str | Path,
    settings: VideoSettings | None = None,
    progress: bool | None = None,
) -> Path:
    """Render recorded MuJoCo configurations and write them as a video.

    Args:
        model: the ``mujoco.MjModel`` the configurations belong to.
        qpos_frames: (k, nq) configurations, one per frame (e.g. recorded at ``settings.fps``).
        path: output file (``.gif``, or ``.mp4`` with imageio-ffmpeg).
        settings: :class:`VideoSettings` (fps is the playback rate).
        progress: show a progress bar (None: only on a terminal).

    Returns:
        The written path.
    """
    from tqdm.auto import tqdm

    frames = np.asarray(list(qpos_frames) if not isinstance(qpos_frames, np.ndarray) else qpos_frames, dtype=float)
    if frames.ndim != 2 or frames.shape[1] != model.nq or frames.shape[0] == 0:
        raise InvalidInputError("qpos_frames", f"array of shape {frames.shape}", f"a (k >= 1, nq = {model.nq}) array")
    if not np.all(np.isfinite(frames)):
        raise InvalidInputError("qpos_frames", "non-finite values", "finite configurations")
    data = mujoco.MjData(model)
    with VideoRecorder(model, settings) as rec:
        for q in tqdm(frames, desc="render", unit="frame", disable=(None if progress is None else not progress),
                      leave=False):
            data.qpos[:] = q
            mujoco.mj_forward(model, data)
            rec.capture(data)
        return rec.save(path)


def _check_suffix(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise InvalidInputError("path", str(path), "a file name ending in .gif or .mp4")
    if suffix == ".mp4" and not mp4_available():
        raise RenderUnavailableError(
            "MP4 video", "needs imageio-ffmpeg (pip install imageio-ffmpeg); write a .gif instead"
        )
    return suffix


class VideoWriter:
    """Writes RGB frames to an ``.mp4`` (H.264, ``yuv420p``) or ``.gif`` file as they come.

    Use it as a context manager; :attr:`count` is the number of frames written. An MP4's frame size
    must be a multiple of 16 pixels (:class:`VideoSettings`' default 640x480 is).
    """

    def __init__(self, path: str | Path, fps: float) -> None:
        import imageio.v2 as iio2

        if not (np.isfinite(fps) and 0.0 < fps <= 240.0):
            raise ParameterError("fps", fps, "a frame rate in (0, 240] Hz")
        self.path = Path(path)
        self.fps = float(fps)
        suffix = _check_suffix(self.path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.count = 0
        if suffix == ".gif":
            self._writer = iio2.get_writer(self.path, format="GIF", mode="I", duration=1000.0 / self.fps, loop=0)
        else:
            self._writer = iio2.get_writer(self.path, format="FFMPEG", mode="I", fps=self.fps, codec="libx264",
                                           quality=7, macro_block_size=16)

    def append(self, frame: np.ndarray) -> None:
        """Write one RGB frame (height, width, 3), uint8."""
        if self._writer is None:
            raise InvalidInputError("writer", "closed", "an open VideoWriter")
        self._writer.append_data(np.asarray(frame, dtype=np.uint8))
        self.count += 1

    def close(self) -> Path:
        """Finish the file (idempotent); its path."""
        if self._writer is not None:
            self._writer.close()
            self._writer = None
        return self.path

    def __enter__(self) -> "VideoWriter":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def overlay_text(image: np.ndarray, lines: Sequence[str], corner: tuple[int, int] = (8, 6)) -> np.ndarray:
    """``image`` (RGB, uint8) with ``lines`` of text written at its top-left ``corner`` [px], white on a
    dark band (Pillow's default font)."""
    from PIL import Image, ImageDraw

    img = Image.fromarray(np.asarray(image, dtype=np.uint8))
    if lines:
        draw = ImageDraw.Draw(img)
        x, y = corner
        step = 14
        width = max(draw.textlength(line) for line in lines)
        draw.rectangle((x - 4, y - 3, x + width + 4, y + step * len(lines) + 1), fill=(0, 0, 0))
        for i, line in enumerate(lines):
            draw.text((x, y + step * i), line, fill=(255, 255, 255))
    return np.asarray(img)
