"""The live viewer of a full-body run (``lipmpcc run ... --viewer``) and the checks before any viewer opens.

:class:`LiveViewer` is a per-tick hook of the full-body loop (:data:`lipmpcc.loops.fullbody.loop.TickHook`):
it opens MuJoCo's passive viewer (``mujoco.viewer.launch_passive``) at the run's first tick on copies
of the model and the data (the window's mouse and panels never touch the simulation: results are the
same with a viewer or without), copies the configuration in at :data:`REFRESH_HZ` per simulated second
and draws the path, the obstacles, the footholds and the push as decorations (``viewer.user_scn``,
:func:`lipmpcc.sim.decorations.draw_decorations`). :data:`VIEWER_MODES`: ``realtime`` holds the run to
real time (never faster: a run slower than real time is shown as it goes), ``fast`` shows it as fast as
it simulates. Closing the window lets the run go on unseen.

:func:`check_display` runs before the run starts: without a display (no ``DISPLAY`` or
``WAYLAND_DISPLAY`` on Linux), outside ``mjpython`` on macOS, or when GLFW cannot start, it raises
:class:`ViewerUnavailableError`, one line that names the cause and the ways out (``--video``, offscreen
rendering with ``MUJOCO_GL=egl``/``osmesa``, ``mjpython`` on macOS).
"""

from __future__ import annotations

import copy
import os
import sys
import time
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np

from ..exceptions import InvalidInputError

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

    from ..loops.fullbody.gait import Gait
    from ..obstacles import Obstacle
    from ..paths import Path
    from ..sim.robot_sim import RobotSim

__all__ = ["VIEWER_MODES", "REFRESH_HZ", "ViewerUnavailableError", "display_problem", "check_display",
           "launch_viewer", "close_viewer", "LiveViewer", "live_viewer"]

#: ``--viewer`` modes: ``realtime`` (the default) or ``fast`` (as fast as the run simulates)
VIEWER_MODES = ("realtime", "fast")
#: viewer refreshes per simulated second [Hz]
REFRESH_HZ = 60.0

_WAYS_OUT = ("write a video instead (--video, headless: MuJoCo renders offscreen with MUJOCO_GL=egl or "
             "MUJOCO_GL=osmesa), or run where there is a display (on macOS: under mjpython)")


class ViewerUnavailableError(InvalidInputError):
    """The viewer cannot open here (a usage error of ``--viewer`` / ``lipmpcc replay``: exit 2).

    Attributes (besides :class:`~lipmpcc.exceptions.InvalidInputError`'s): cause: why.
    """

    def __init__(self, what: str, cause: str) -> None:
        super().__init__(what, "the viewer", "a display for MuJoCo's viewer")
        self.cause = cause
        self.args = (f"{what}: the viewer cannot open: {cause}; {_WAYS_OUT}",)

    def __str__(self) -> str:
        return str(self.args[0])


def display_problem() -> str | None:
    """Why MuJoCo's viewer cannot open here, without trying it (None: it may)."""
    if sys.platform.startswith("linux") and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        return "no display (DISPLAY and WAYLAND_DISPLAY are not set)"
    if sys.platform == "darwin":
        import mujoco.viewer as mv

        if type(getattr(mv, "_MJPYTHON", None)).__name__ in ("NoneType",):
            return "on macOS the viewer needs the script run under mjpython (mjpython -m lipmpcc ...)"
    return None


def check_display(what: str = "--viewer") -> None:
    """Raise :class:`ViewerUnavailableError` when the viewer cannot open: no display, or GLFW (the
    viewer's window library) does not start on it."""
    problem = display_problem()
    if problem is None and sys.platform != "darwin":
        try:
            import glfw

            # left initialised: MuJoCo's viewer initialises GLFW once per process, and a terminate here
            # would pull it from under a later viewer
            if not glfw.init():
                problem = f"GLFW could not start on display {os.environ.get('DISPLAY') or os.environ.get('WAYLAND_DISPLAY')!r}"
        except Exception as err:  # noqa: BLE001 - a missing or broken GLFW
            problem = f"GLFW could not start ({' '.join(str(err).split())[:100]})"
    if problem is not None:
        raise ViewerUnavailableError(what, problem)


def launch_viewer(model: mujoco.MjModel, data: mujoco.MjData, launch: Any = None, what: str = "--viewer") -> Any:
    """MuJoCo's passive viewer on ``model`` and ``data``, panels hidden (``launch``: the launcher, None:
    ``mujoco.viewer.launch_passive``).

    Raises:
        ViewerUnavailableError: the viewer did not start.
    """
    if launch is None:
        import mujoco.viewer

        launch = mujoco.viewer.launch_passive
    try:
        return launch(model, data, show_left_ui=False, show_right_ui=False)
    except Exception as err:  # noqa: BLE001 - GL and window errors come as several types
        raise ViewerUnavailableError(what, f"MuJoCo's viewer failed to start ({' '.join(str(err).split())[:120]})") from None


def close_viewer(handle: Any, timeout: float = 5.0) -> None:
    """Close a passive viewer and wait (up to ``timeout`` [s]) for its window thread to end: an
    interpreter that exits while the thread still draws can crash."""
    handle.close()
    alive = getattr(handle, "_sim", None)  # MuJoCo's handle: a weak reference to the window, dead once it ends
    deadline = time.perf_counter() + timeout
    while callable(alive) and alive() is not None and time.perf_counter() < deadline:
        time.sleep(0.02)


class LiveViewer:
    """A live view of a full-body run, as the loop's per-tick hook (see the module doc).

    Args:
        mode: ``"realtime"`` or ``"fast"`` (:data:`VIEWER_MODES`).
        launch: the viewer's launcher (None: ``mujoco.viewer.launch_passive``; a test passes its own).

    Attributes:
        refreshes: how many times the view was refreshed.
    """

    def __init__(self, mode: str = "realtime", launch: Any = None) -> None:
        if mode not in VIEWER_MODES:
            raise InvalidInputError("--viewer", mode, " or ".join(VIEWER_MODES))
        self.mode = mode
        self._launch = launch
        self._viewer: Any = None
        self._model: Any = None
        self._data: Any = None
        self._path_xy = np.zeros((0, 2))
        self._obstacles: list[Obstacle] = []
        self._pushes: Sequence[tuple[float, float, Sequence[float]]] | Callable[[], Sequence] = []
        self._t0 = 0.0
        self._wall0 = 0.0
        self._torso = 0
        self.refreshes = 0

    def set_scene(self, path: Path | None = None, obstacles: Sequence[Obstacle] = (),
                  pushes: Sequence[tuple[float, float, Sequence[float]]] | Callable[[], Sequence] = ()) -> None:
        """The run's reference path, obstacles and pushes ((start, end [s], force [N]) each, or a function
        that returns them, read at each refresh: pushes registered during the run), to draw."""
        from ..sim.decorations import PATH_SAMPLE_M

        self._path_xy = (np.asarray(path.position(np.arange(0.0, path.length + 1e-9, PATH_SAMPLE_M)), dtype=float)
                         if path is not None else np.zeros((0, 2)))
        self._obstacles = list(obstacles)
        self._pushes = pushes if callable(pushes) else list(pushes)

    def _start(self, t: float, sim: RobotSim, torso_body: str) -> None:
        import mujoco

        self._model = copy.deepcopy(sim.model)
        self._data = mujoco.MjData(self._model)
        self._viewer = launch_viewer(self._model, self._data, self._launch)
        body = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_BODY, torso_body)
        self._torso = body if body >= 0 else (1 if self._model.nbody > 1 else 0)
        self._t0, self._wall0 = t, time.perf_counter()

    def decorations(self, t: float, gait: Gait) -> Any:
        """The :class:`~lipmpcc.sim.decorations.SceneDecorations` at ``t`` [s] (the viewer's data up to date)."""
        from ..sim.decorations import SceneDecorations

        torso = np.asarray(self._data.xpos[self._torso], dtype=float)
        obstacles = [(*ob.center(t), ob.axes[0], ob.axes[1], ob.heading(t), float(ob.is_circle)) for ob in self._obstacles]
        landed = [(td.pos[0], td.pos[1], 0.0 if str(td.side) == "left" else 1.0) for td in gait.touchdowns]
        planned = np.zeros((0, 2))
        if gait.plans:
            plan = gait.plans[-1][1]
            preview = np.zeros((0, 2)) if plan.preview is None else np.asarray(plan.preview, dtype=float)[:, :2]
            planned = np.vstack([np.asarray(plan.foothold, dtype=float)[None, :2], preview])
        pushes = self._pushes() if callable(self._pushes) else self._pushes
        force = sum((np.asarray((*f, 0.0)[:3], dtype=float) for a, b, f in pushes if a <= t < b), np.zeros(3))
        push = np.r_[torso, force] if np.any(force != 0.0) else None
        return SceneDecorations(path_xy=self._path_xy, obstacles=np.reshape(obstacles, (-1, 6)),
                                landed=np.reshape(landed, (-1, 3)), planned=planned, push=push, near_xy=torso[:2])

    def __call__(self, t: float, sim: RobotSim, gait: Gait) -> None:
        """The hook: refresh the view at time ``t`` [s] (opening it on the first call)."""
        import mujoco

        from ..sim.decorations import draw_decorations

        if self._viewer is None:
            self._start(t, sim, sim.description.torso_body)
        viewer = self._viewer
        if not viewer.is_running():
            return
        self._data.qpos[:] = sim.qpos
        mujoco.mj_forward(self._model, self._data)
        with viewer.lock():
            viewer.user_scn.ngeom = 0
            draw_decorations(viewer.user_scn, self.decorations(t, gait))
        viewer.sync()
        self.refreshes += 1
        if self.mode == "realtime":
            lag = self._wall0 + (t - self._t0) - time.perf_counter()
            if lag > 0:
                time.sleep(lag)

    def close(self) -> None:
        """Close the window (idempotent)."""
        if self._viewer is not None:
            try:
                close_viewer(self._viewer)
            finally:
                self._viewer = None


def live_viewer(opts: Any) -> LiveViewer | None:
    """The :class:`LiveViewer` a run's options ask for (``opts.viewer``: a mode), or None."""
    mode = getattr(opts, "viewer", None)
    return None if mode is None else LiveViewer(mode)
