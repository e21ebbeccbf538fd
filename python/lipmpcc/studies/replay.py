"""Replays of full-body runs: ``replay.npz`` in a run's folder, read back, shown in MuJoCo's viewer or
rendered to a video.

Every full-body run (``lipmpcc run ... --robot digit_like|PATH.xml``) saves :data:`REPLAY_FILE` beside
``summary.json``: the MuJoCo configurations the loop recorded at its video rate (``LoopParams.video_fps``,
30 Hz) with their times, the compiled MuJoCo model (MuJoCo's binary ``.mjb``, with the stepping
stones when the run had them), the robot's name and MJCF path, the planned footholds and the
touch-downs, the reference path, the obstacles at each frame and the pushes. The format is in
``docs/formats.md``. :func:`load_replay` reads it back; :func:`play` shows it in MuJoCo's passive
viewer in real time (or ``speed`` times faster); :func:`write_replay_video` renders it to an MP4 or a
GIF, with the path, the obstacles, the footholds and the push drawn into the scene
(:func:`lipmpcc.sim.decorations.draw_decorations`) and the time and the push written on each frame.
"""

from __future__ import annotations

import math
import tempfile
import time
import zipfile
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any, Iterator, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..push import Push

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

    from ..loops.fullbody.loop import LoopResult
    from ..obstacles import Obstacle
    from ..paths import Path
    from ..robots import RobotDescription
    from ..sim.decorations import SceneDecorations

__all__ = [
    "REPLAY_FILE",
    "REPLAY_VERSION",
    "PATH_SAMPLE_M",
    "RunReplay",
    "push_windows",
    "replay_from_run",
    "save_replay",
    "load_replay",
    "replay_model",
    "replay_frames",
    "play",
    "video_size",
    "write_replay_video",
    "check_video_file",
    "MIN_VIDEO_FPS",
    "run_outputs",
    "replay_run",
]

#: the replay file in a run's folder
REPLAY_FILE = "replay.npz"
#: the version of its layout (``version`` in the file)
REPLAY_VERSION = 1
#: the slowest video ``replay --video --speed`` writes [frames/s]
MIN_VIDEO_FPS = 1.0
#: spacing of the saved path points [m]
PATH_SAMPLE_M = 0.1  # = lipmpcc.sim.decorations.PATH_SAMPLE_M (the sim layer is not imported at start-up)

_ARRAYS = ("t", "qpos", "plan_t", "plan_xy", "plan_yaw", "touchdown_t", "touchdown_xyz", "touchdown_side", "path_xy",
           "obstacle_xy", "obstacle_heading", "obstacle_axes", "obstacle_circle", "push_window", "push_force")


@dataclass(frozen=True)
class RunReplay:
    """What a replay needs (the arrays of :data:`REPLAY_FILE`; world frame, simulation time).

    Attributes:
        scenario: the scenario (``"walk"``, ``"circle"``, ...); robot: the robot's name;
            robot_mjcf: its MJCF file (for a model rebuilt without the saved binary).
        torso_body: the body the camera follows.
        fps: the frames' rate [Hz].
        model_mjb: the compiled MuJoCo model (``mj_saveModel``), uint8.
        t: (k,) frame times [s]; qpos: (k, nq) MuJoCo configurations.
        plan_t, plan_xy, plan_yaw: the planner's answers: time [s], foothold (p, 2) [m], yaw [rad].
        touchdown_t, touchdown_xyz, touchdown_side: the touch-downs: time [s], sole position (d, 3) [m],
            side (0 left, 1 right).
        path_xy: (m, 2) the reference path sampled every :data:`PATH_SAMPLE_M` [m] (empty: none).
        obstacle_xy: (k, n, 2) obstacle centres at each frame [m]; obstacle_heading: (k, n) [rad];
            obstacle_axes: (n, 2) semi-axes [m]; obstacle_circle: (n,) 1 for a circle.
        push_window: (q, 2) (start, end) [s]; push_force: (q, 3) [N].
    """

    scenario: str
    robot: str
    robot_mjcf: str
    torso_body: str
    fps: float
    model_mjb: np.ndarray
    t: np.ndarray
    qpos: np.ndarray
    plan_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    plan_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    plan_yaw: np.ndarray = field(default_factory=lambda: np.zeros(0))
    touchdown_t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    touchdown_xyz: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    touchdown_side: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8))
    path_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    obstacle_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 2)))
    obstacle_heading: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    obstacle_axes: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    obstacle_circle: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8))
    push_window: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    push_force: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @property
    def n_frames(self) -> int:
        """The number of frames."""
        return int(len(self.t))

    @property
    def duration(self) -> float:
        """From the first frame to the last [s]."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    def save(self, folder: str | FsPath) -> FsPath:
        """Write it to ``folder/replay.npz`` (:func:`save_replay`)."""
        return save_replay(self, folder)

    def push_at(self, t: float) -> np.ndarray | None:
        """The force (3,) [N] of the push acting at ``t`` [s] (their sum), or None."""
        on = (self.push_window[:, 0] <= t) & (t < self.push_window[:, 1])
        return self.push_force[on].sum(axis=0) if np.any(on) else None

    def decorations(self, i: int, torso_xyz: np.ndarray | None = None) -> SceneDecorations:
        """What to draw at frame ``i``: the path near the torso (``torso_xyz``, [m]), the obstacles, the
        touch-downs so far, the last plan and the push acting (at the torso)."""
        from ..sim.decorations import SceneDecorations

        t = float(self.t[i])
        landed = self.touchdown_t <= t + 1e-9
        planned = self.plan_t <= t + 1e-9
        obstacles = np.zeros((0, 6))
        if self.obstacle_xy.shape[1:2] != (0,) and len(self.obstacle_xy):
            n = self.obstacle_xy.shape[1]
            obstacles = np.column_stack([self.obstacle_xy[i], self.obstacle_axes, self.obstacle_heading[i],
                                         self.obstacle_circle.astype(float)]) if n else obstacles
        push = self.push_at(t)
        at = np.zeros(3) if torso_xyz is None else np.asarray(torso_xyz, dtype=float)
        return SceneDecorations(
            path_xy=self.path_xy,
            obstacles=obstacles,
            landed=np.column_stack([self.touchdown_xyz[landed, :2], self.touchdown_side[landed]]),
            planned=self.plan_xy[planned][-1:],
            push=None if push is None or torso_xyz is None else np.r_[at, push],
            near_xy=None if torso_xyz is None else at[:2],
        )


def push_windows(pushes: Sequence[Push]) -> list[tuple[float, float, tuple[float, float, float]]]:
    """(start, end [s], force (3,) [N]) of pushes with absolute times (``Push.step`` None)."""
    return [(float(p.t_start), float(p.t_start + p.duration), tuple(float(f) for f in p.force_xyz))
            for p in pushes if p.step is None]


def _model_bytes(model: mujoco.MjModel) -> np.ndarray:
    import mujoco

    buf = np.zeros(mujoco.mj_sizeModel(model), dtype=np.uint8)
    mujoco.mj_saveModel(model, None, buf)
    return buf


def replay_from_run(
    scenario: str,
    robot: RobotDescription,
    model: mujoco.MjModel,
    result: LoopResult,
    path: Path | None = None,
    obstacles: Sequence[Obstacle] = (),
    pushes: Sequence[tuple[float, float, Sequence[float]]] = (),
    fps: float = 30.0,
) -> RunReplay:
    """The replay of a full-body run that recorded its frames (``record_video=True``).

    Args:
        scenario: the scenario's name; robot: the robot; model: the simulator's model (``loop.sim.model``).
        result: the loop's result; path: the reference path (None: none); obstacles: the obstacles.
        pushes: (start, end [s], force (2,) or (3,) [N]) per push (:func:`push_windows`).
        fps: the rate the frames were recorded at [Hz] (``LoopParams.video_fps``).

    Raises:
        InvalidInputError: the run recorded no frames.
    """
    if result.frames is None or len(result.frames) == 0:
        raise InvalidInputError("result", "a run without recorded frames", "a run simulated with record_video=True")
    t = np.asarray(result.frame_times, dtype=float)
    plans = result.plans
    tds = result.touchdowns
    n_obs = len(obstacles)
    oxy = np.array([[ob.center(float(ti)) for ob in obstacles] for ti in t], dtype=float).reshape(len(t), n_obs, 2)
    ohd = np.array([[ob.heading(float(ti)) for ob in obstacles] for ti in t], dtype=float).reshape(len(t), n_obs)
    pw = [(float(a), float(b), tuple(float(f) for f in (*force, 0.0)[:3])) for a, b, force in pushes]
    return RunReplay(
        scenario=str(scenario), robot=str(robot.name), robot_mjcf=str(robot.mjcf_path or ""),
        torso_body=str(robot.torso_body), fps=float(fps), model_mjb=_model_bytes(model),
        t=t, qpos=np.asarray(result.frames, dtype=float),
        plan_t=np.array([pt for pt, _ in plans], dtype=float),
        plan_xy=np.array([p.foothold[:2] for _, p in plans], dtype=float).reshape(-1, 2),
        plan_yaw=np.array([p.yaw for _, p in plans], dtype=float),
        touchdown_t=np.array([td.t for td in tds], dtype=float),
        touchdown_xyz=np.array([td.pos[:3] for td in tds], dtype=float).reshape(-1, 3),
        touchdown_side=np.array([0 if str(td.side) == "left" else 1 for td in tds], dtype=np.int8),
        path_xy=(np.asarray(path.position(np.arange(0.0, path.length + 1e-9, PATH_SAMPLE_M)), dtype=float)
                 if path is not None else np.zeros((0, 2))),
        obstacle_xy=oxy, obstacle_heading=ohd,
        obstacle_axes=np.array([ob.axes[:2] for ob in obstacles], dtype=float).reshape(-1, 2),
        obstacle_circle=np.array([bool(ob.is_circle) for ob in obstacles], dtype=np.int8),
        push_window=np.array([(a, b) for a, b, _ in pw], dtype=float).reshape(-1, 2),
        push_force=np.array([f for _, _, f in pw], dtype=float).reshape(-1, 3),
    )


def save_replay(replay: RunReplay, folder: str | FsPath) -> FsPath:
    """Write ``replay`` to ``folder/replay.npz`` (compressed) and return its path."""
    out = FsPath(folder) / REPLAY_FILE
    out.parent.mkdir(parents=True, exist_ok=True)
    meta = {"version": np.int64(REPLAY_VERSION), "scenario": np.str_(replay.scenario), "robot": np.str_(replay.robot),
            "robot_mjcf": np.str_(replay.robot_mjcf), "torso_body": np.str_(replay.torso_body),
            "fps": np.float64(replay.fps), "model_mjb": replay.model_mjb}
    with open(out, "wb") as fh:
        np.savez_compressed(fh, **meta, **{name: getattr(replay, name) for name in _ARRAYS})
    return out


def _bad(run_dir: FsPath, why: str) -> InvalidInputError:
    return InvalidInputError("RUN_DIR", str(run_dir), "the folder of a full-body run (lipmpcc run ... --robot "
                             f"digit_like|PATH.xml), holding {REPLAY_FILE}", why)


def load_replay(run_dir: str | FsPath) -> RunReplay:
    """Read ``run_dir/replay.npz`` (``run_dir`` may also be the file itself).

    Raises:
        InvalidInputError: no such folder, no replay file (a LIP/ALIP run, or a run of lipmpcc < 0.2), or
            a file that is not a readable replay.
    """
    run_dir = FsPath(run_dir)
    file = run_dir if run_dir.suffix == ".npz" else run_dir / REPLAY_FILE
    if not run_dir.exists():
        raise _bad(run_dir, "no such folder")
    if not file.is_file():
        why = "a LIP/ALIP run has no replay" if (run_dir / "summary.json").is_file() else f"no {REPLAY_FILE} in it"
        raise _bad(run_dir, why)
    try:
        with np.load(file, allow_pickle=False) as z:
            version = int(z["version"]) if "version" in z.files else None
            if version is not None and version != REPLAY_VERSION:
                raise _bad(run_dir, f"{REPLAY_FILE} of version {version}, this lipmpcc reads version {REPLAY_VERSION}")
            missing = [k for k in ("version", "scenario", "robot", "robot_mjcf", "torso_body", "fps", "model_mjb", *_ARRAYS)
                       if k not in z.files]
            if missing:
                raise _bad(run_dir, f"{REPLAY_FILE} has no field {', '.join(missing)}")
            kw: dict[str, Any] = {name: np.asarray(z[name]) for name in _ARRAYS}
            kw.update(scenario=str(z["scenario"]), robot=str(z["robot"]), robot_mjcf=str(z["robot_mjcf"]),
                      torso_body=str(z["torso_body"]), fps=float(z["fps"]), model_mjb=np.asarray(z["model_mjb"]))
    except InvalidInputError:
        raise
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError) as err:
        raise _bad(run_dir, f"{REPLAY_FILE} is unreadable: {' '.join(str(err).split())[:120]}") from None
    replay = RunReplay(**kw)
    _check_replay(replay, run_dir)
    return replay


#: the shape of each array of the file: a symbol is a size that must agree across the fields that name it
#: (k: frames, nq: coordinates, p: plans, d: touch-downs, m: path points, n: obstacles, q: pushes;
#: k0: k, or 0 for a run without obstacles)
_SHAPES: dict[str, tuple[str | int, ...]] = {
    "t": ("k",), "qpos": ("k", "nq"), "plan_t": ("p",), "plan_xy": ("p", 2), "plan_yaw": ("p",),
    "touchdown_t": ("d",), "touchdown_xyz": ("d", 3), "touchdown_side": ("d",), "path_xy": ("m", 2),
    "obstacle_xy": ("k0", "n", 2), "obstacle_heading": ("k0", "n"), "obstacle_axes": ("n", 2),
    "obstacle_circle": ("n",), "push_window": ("q", 2), "push_force": ("q", 3),
}


def _field_problem(replay: RunReplay) -> str | None:
    """The first field of ``replay`` that is wrong, as ``"field NAME ..."`` (None: all are right)."""
    if not (math.isfinite(replay.fps) and replay.fps > 0):
        return f"field fps = {replay.fps!r}: expected a positive frame rate [Hz]"
    mjb = replay.model_mjb
    if mjb.dtype != np.uint8 or mjb.ndim != 1 or mjb.size == 0:
        return f"field model_mjb ({mjb.dtype}, shape {mjb.shape}): expected the model's bytes (uint8, non-empty)"
    sizes: dict[str, int] = {"k": replay.n_frames if replay.t.ndim == 1 else -1}
    for name, shape in _SHAPES.items():
        a = getattr(replay, name)
        want = "(" + ", ".join(str(d) for d in shape) + ")"
        ok = a.ndim == len(shape)
        for dim, got in zip(shape, a.shape if ok else ()):
            if dim == "k0":
                ok = ok and got in (sizes["k"], 0)
            elif isinstance(dim, str):
                ok = ok and sizes.setdefault(dim, got) == got
            else:
                ok = ok and got == dim
        if not ok:
            known = ", ".join(f"{d} = {v}" for d, v in sizes.items() if d in shape and v >= 0)
            return f"field {name} has shape {a.shape}: expected {want}" + (f" with {known}" if known else "")
        if not np.issubdtype(a.dtype, np.number):
            return f"field {name} holds {a.dtype} values: expected numbers"
        bad = ~np.isfinite(a.astype(float))
        if np.any(bad):
            where = np.argwhere(bad)[0]
            at = f"frame {where[0]}" if shape[0] in ("k", "k0") else f"row {where[0]}"
            return f"field {name}: {at} holds {a[tuple(where)].item()!r}: expected finite numbers"
    if replay.n_frames < 1:
        return "field t has no frame: expected at least one"
    if np.any(np.diff(replay.t) < 0):
        i = int(np.argmax(np.diff(replay.t) < 0)) + 1
        return f"field t: frame {i} ({replay.t[i]:g} s) is before frame {i - 1} ({replay.t[i - 1]:g} s): expected times in order"
    if not np.all(np.isin(replay.touchdown_side, (0, 1))):
        return "field touchdown_side: expected 0 (left) or 1 (right) per touch-down"
    return None


def _check_replay(replay: RunReplay, run_dir: FsPath) -> None:
    """Every field has its shape (the sizes that belong together agree), finite values, the frames in order."""
    problem = _field_problem(replay)
    if problem is not None:
        raise _bad(run_dir, f"{REPLAY_FILE} {problem}")


def replay_model(replay: RunReplay) -> mujoco.MjModel:
    """The run's MuJoCo model, from the saved binary (or, when this MuJoCo cannot read it, rebuilt from
    the robot's name or MJCF file: the same robot, without a scenario's stones).

    Raises:
        InvalidInputError: neither works, or the model's ``nq`` does not match the frames.
    """
    import mujoco

    model = None
    with tempfile.TemporaryDirectory() as tmp:
        f = FsPath(tmp) / "model.mjb"
        f.write_bytes(replay.model_mjb.tobytes())
        previous = mujoco.get_mju_user_warning()
        mujoco.set_mju_user_warning(lambda msg: None)  # else MuJoCo writes MUJOCO_LOG.TXT into the working folder
        try:
            model = mujoco.MjModel.from_binary_path(str(f))
        except Exception:  # noqa: BLE001 - a binary of another MuJoCo version
            model = None
        finally:
            mujoco.set_mju_user_warning(previous)
    if model is None:
        from ..robots import load_robot
        from ..sim.robot_sim import RobotSim

        model = RobotSim(load_robot(replay.robot_mjcf or replay.robot)).model
    if model.nq != replay.qpos.shape[1]:
        raise InvalidInputError("replay", f"frames of {replay.qpos.shape[1]} coordinates",
                                f"frames of the model's nq = {model.nq}")
    return model


def replay_frames(replay: RunReplay, model: mujoco.MjModel, data: mujoco.MjData,
                  every: int = 1) -> Iterator[int]:
    """Set ``data`` to every ``every``-th saved frame in turn (its kinematics computed) and yield its index."""
    import mujoco

    for i in range(0, replay.n_frames, max(1, int(every))):
        data.qpos[:] = replay.qpos[i]
        mujoco.mj_forward(model, data)
        yield i


def _torso_id(model: mujoco.MjModel, name: str) -> int:
    import mujoco

    body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    return body if body >= 0 else (1 if model.nbody > 1 else 0)


def play(replay: RunReplay, speed: float = 1.0, launch: Any = None) -> int:
    """Show ``replay`` in MuJoCo's passive viewer, ``speed`` times real time; returns the frames shown
    (fewer when the window is closed first).

    Args:
        replay: the replay; speed: playback speed (1: real time) [-].
        launch: the viewer's launcher (None: ``mujoco.viewer.launch_passive``; a test passes its own).

    Raises:
        RenderUnavailableError: no display, or the viewer does not start (:mod:`lipmpcc.studies.viewer`).
    """
    import mujoco

    from ..sim.decorations import draw_decorations
    from .viewer import check_display, close_viewer, launch_viewer

    if not (math.isfinite(speed) and speed > 0.0):
        raise InvalidInputError("--speed", speed, "a positive playback speed (1 = real time)")
    model = replay_model(replay)
    data = mujoco.MjData(model)
    if launch is None:
        check_display("lipmpcc replay")
    viewer = launch_viewer(model, data, launch)
    torso = _torso_id(model, replay.torso_body)
    shown = 0
    wall0 = time.perf_counter()
    try:
        for i in replay_frames(replay, model, data):
            if not viewer.is_running():
                break
            with viewer.lock():
                viewer.user_scn.ngeom = 0
                draw_decorations(viewer.user_scn, replay.decorations(i, data.xpos[torso]))
            viewer.sync()
            shown += 1
            lag = wall0 + (replay.t[i] - replay.t[0]) / speed - time.perf_counter()
            if lag > 0:
                time.sleep(lag)
    finally:
        close_viewer(viewer)
    return shown


def video_size(gif: bool) -> tuple[int, int, int]:
    """(width, height [px], keep every n-th frame) of a video: 640x480 at the recorded 30 Hz for MP4,
    400x300 at 15 Hz for GIF (a GIF is some 10x bigger per frame)."""
    return (400, 300, 2) if gif else (640, 480, 1)


def _overlay_lines(replay: RunReplay, i: int) -> list[str]:
    t = float(replay.t[i])
    lines = [f"t = {t:6.2f} s"]
    push = replay.push_at(t)
    if push is not None:
        norm = float(np.linalg.norm(push[:2]))
        lines.append(f"push {float(np.linalg.norm(push)):.0f} N toward {math.degrees(math.atan2(push[1], push[0])):+.0f} deg"
                     if norm > 0 else f"push {float(np.linalg.norm(push)):.0f} N vertical")
    return lines


def write_replay_video(replay: RunReplay, file: str | FsPath, size: tuple[int, int] | None = None,
                       every: int | None = None, progress: bool | None = None, speed: float = 1.0) -> FsPath:
    """Render ``replay`` to ``file`` (``.mp4`` or ``.gif``; sizes and rates: :func:`video_size`), the camera
    following the torso, with the path, the obstacles, the footholds and the push drawn into the scene
    and the time and the push written at the top left. ``speed`` [-]: the video plays the run that many
    times faster than real time (frames are skipped above 1, the video's rate lowered below 1). Returns the
    written path.

    Raises:
        InvalidInputError: ``file`` cannot be written (an existing folder, a missing or read-only folder,
            a writer's error), in one line."""
    from tqdm.auto import tqdm

    import mujoco

    from ..sim import render
    from ..sim.decorations import draw_decorations

    check_video_file(file)
    gif = FsPath(file).suffix.lower() == ".gif"
    w, h, n = video_size(gif)
    w, h = size or (w, h)
    every = max(1, int(every or n))
    if speed > 1.0:  # faster: skip frames, so that the video's rate stays the recorded one's
        every = max(every, int(round(every * speed)))
    fps = replay.fps * speed / every
    if not (math.isfinite(speed) and speed > 0 and fps >= MIN_VIDEO_FPS):
        raise InvalidInputError("--speed", speed, f"a positive speed that gives the video at least {MIN_VIDEO_FPS:g} "
                                f"frame per second (here >= {MIN_VIDEO_FPS * every / replay.fps:g})")
    model = replay_model(replay)
    data = mujoco.MjData(model)
    torso = _torso_id(model, replay.torso_body)
    settings = render.VideoSettings(width=int(w), height=int(h), fps=min(240.0, fps),
                                    track_body=mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, torso),
                                    distance=4.5, azimuth=35.0, elevation=-20.0)
    try:
        with render.VideoRecorder(model, settings) as rec, render.VideoWriter(file, settings.fps) as out:
            frames = replay_frames(replay, model, data, every)
            for i in tqdm(frames, total=-(-replay.n_frames // every), desc="video", unit="frame", leave=False,
                          disable=(None if progress is None else not progress)):
                deco = replay.decorations(i, data.xpos[torso])
                image = rec.render(data, lambda scn, d=deco: draw_decorations(scn, d))
                out.append(render.overlay_text(image, _overlay_lines(replay, i)))
    except (OSError, RuntimeError, BrokenPipeError) as exc:  # the writer (ffmpeg) failed: its first line
        text = next((ln.strip() for ln in str(exc).splitlines() if ln.strip()), type(exc).__name__)
        raise InvalidInputError("--video", str(file), _VIDEO_EXPECTED, f"the video could not be written: {text[:200]}") from None
    return FsPath(file)


_VIDEO_EXPECTED = "a new .mp4 or .gif file in a folder that can be written"


def check_video_file(file: str | FsPath) -> FsPath:
    """``file`` checked as the video to write: ``.mp4`` or ``.gif``, not an existing folder, in an
    existing folder that can be written.

    Raises:
        InvalidInputError: one line naming ``file`` and what is wrong.
    """
    import os

    if not isinstance(file, (str, FsPath)) or not str(file).strip():
        raise InvalidInputError("--video", file, _VIDEO_EXPECTED)
    f = FsPath(file)
    if f.suffix.lower() not in (".mp4", ".gif"):
        raise InvalidInputError("--video", str(file), "a file name ending in .mp4 or .gif")
    if f.is_dir():
        raise InvalidInputError("--video", str(file), _VIDEO_EXPECTED, "it is an existing folder")
    folder = f.parent if str(f.parent) else FsPath(".")
    if not folder.is_dir():
        raise InvalidInputError("--video", str(file), _VIDEO_EXPECTED, f"its folder {folder} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK) or (f.exists() and not os.access(f, os.W_OK)):
        raise InvalidInputError("--video", str(file), _VIDEO_EXPECTED, f"{folder if not f.exists() else f} is read-only")
    return f



def run_outputs(opts: Any, robot: RobotDescription, model: mujoco.MjModel, result: LoopResult, path: Path | None = None,
                obstacles: Sequence[Obstacle] = (), pushes: Sequence[tuple[float, float, Sequence[float]]] = (),
                fps: float = 30.0) -> tuple[RunReplay, list[FsPath]]:
    """A full-body study's replay (``RunResult.replay``: ``RunResult.save`` writes it as ``replay.npz``)
    and the files it writes itself: with ``--video``, the video rendered from the replay
    (``OUT/SCENARIO.mp4``, or ``.gif`` with ``--video-format gif``).

    Args:
        opts: the run's :class:`~lipmpcc.studies.options.RunOptions`; the others: :func:`replay_from_run`.
    """
    replay = replay_from_run(opts.scenario, robot, model, result, path, obstacles, pushes, fps)
    files: list[FsPath] = []
    if opts.video:
        suffix = "." + (getattr(opts, "video_format", None) or "mp4")
        files.append(write_replay_video(replay, FsPath(opts.out) / f"{opts.scenario}{suffix}", progress=None))
    return replay, files


def replay_run(run_dir: str | FsPath, speed: float = 1.0, video: str | FsPath | None = None) -> str:
    """``lipmpcc replay RUN_DIR``: show the run in the viewer at ``speed`` times real time, or, with
    ``video`` (a ``.mp4`` or ``.gif`` file), render it there instead (headless). Returns a one-line report.

    Raises:
        InvalidInputError: a bad ``RUN_DIR`` (missing, not a full-body run, an unreadable replay), a bad
            ``speed`` or video name; ViewerUnavailableError (one): no display for the viewer.
    """
    if not (isinstance(speed, (int, float)) and not isinstance(speed, bool) and math.isfinite(speed) and speed > 0.0):
        raise InvalidInputError("--speed", speed, "a positive playback speed (1 = real time)")
    if video is not None:
        check_video_file(video)
    replay = load_replay(run_dir)
    if video is not None:
        out = write_replay_video(replay, video, speed=speed)
        at = f" at {speed:g}x real time" if speed != 1.0 else ""
        return f"{replay.scenario} on {replay.robot}: {replay.n_frames} frames, {replay.duration:.2f} s{at} -> {out}"
    from .viewer import check_display

    check_display("lipmpcc replay")
    shown = play(replay, speed)
    return f"{replay.scenario} on {replay.robot}: showed {shown} of {replay.n_frames} frames at {speed:g}x real time"
