"""lipmpcc.studies.replay: replay.npz of a full-body run, read back bit for bit, replayed frame by frame
(in a stand-in viewer), rendered to MP4 / GIF with the expected frame count; bad run folders refused
in one line (exit 2 from ``lipmpcc replay``)."""

from __future__ import annotations

import contextlib
import json
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from lipmpcc.cli import main
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.push import Push
from lipmpcc.studies import replay as rp


@pytest.fixture(scope="module")
def walked():
    """A 1.2 s digit_like walk with a push: (robot, loop, result)."""
    from lipmpcc.loops.fullbody.loop import FullBodyLoop
    from lipmpcc.planners.capture_point import CapturePointPlanner
    from lipmpcc.robots import load_robot

    robot = load_robot("digit_like")
    loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.4))
    result = loop.run(duration=1.2, pushes=[Push(force=(30.0, 10.0), t_start=0.6, duration=0.1)], record_video=True)
    return robot, loop, result


@pytest.fixture(scope="module")
def saved(walked, tmp_path_factory):
    robot, loop, result = walked
    replay = rp.replay_from_run("walk", robot, loop.sim.model, result,
                                pushes=rp.push_windows([Push(force=(30.0, 10.0), t_start=0.6, duration=0.1)]))
    folder = tmp_path_factory.mktemp("run")
    return rp.save_replay(replay, folder), replay


def test_the_saved_replay_reads_back_bit_for_bit(walked, saved) -> None:
    _, loop, result = walked
    file, replay = saved
    assert file.name == rp.REPLAY_FILE
    back = rp.load_replay(file.parent)
    np.testing.assert_array_equal(back.qpos, result.frames)
    np.testing.assert_array_equal(back.t, result.frame_times)
    assert back.n_frames == len(result.frames) == 36  # 30 Hz over [0, 1.2) s
    assert (back.scenario, back.robot, back.fps, back.torso_body) == ("walk", "digit_like", 30.0, loop.robot.torso_body)
    assert len(back.touchdown_t) == len(result.touchdowns) >= 1 and len(back.plan_t) == len(result.plans) >= 1
    np.testing.assert_array_equal(back.plan_xy, [p.foothold for _, p in result.plans])
    np.testing.assert_array_equal(back.push_window, [[0.6, 0.7]])
    np.testing.assert_array_equal(back.push_force, [[30.0, 10.0, 0.0]])
    assert back.path_xy.shape == (0, 2) and back.obstacle_xy.shape == (36, 0, 2)
    assert file.stat().st_size < 60_000  # compressed: model ~17 kB, frames ~8 kB per second


def test_a_replay_sets_the_saved_configurations_frame_by_frame(saved) -> None:
    import mujoco

    _, replay = saved
    model = rp.replay_model(replay)
    data = mujoco.MjData(model)
    seen = [i for i in rp.replay_frames(replay, model, data) if np.array_equal(data.qpos, replay.qpos[i])]
    assert seen == list(range(replay.n_frames))
    assert list(rp.replay_frames(replay, model, data, every=2)) == list(range(0, replay.n_frames, 2))


class _FakeViewer:
    """What play() uses of MuJoCo's passive viewer handle, recording the configuration at each sync."""

    def __init__(self, model, data, **kw) -> None:
        import mujoco

        self.data, self.kw, self.synced, self.closed = data, kw, [], False
        self.user_scn = mujoco.MjvScene(model, maxgeom=2000)
        self.geoms = []

    def is_running(self) -> bool:
        return len(self.synced) < 1000

    def lock(self):
        return contextlib.nullcontext()

    def sync(self) -> None:
        self.synced.append(self.data.qpos.copy())
        self.geoms.append(self.user_scn.ngeom)

    def close(self) -> None:
        self.closed = True


def test_play_shows_every_frame_with_its_decorations_at_the_asked_speed(saved) -> None:
    import time

    _, replay = saved
    made = []
    t0 = time.perf_counter()
    shown = rp.play(replay, speed=4.0, launch=lambda m, d, **kw: made.append(_FakeViewer(m, d, **kw)) or made[-1])
    wall = time.perf_counter() - t0
    v = made[0]
    assert shown == replay.n_frames and v.closed and v.kw == {"show_left_ui": False, "show_right_ui": False}
    np.testing.assert_array_equal(np.array(v.synced), replay.qpos)
    assert v.geoms[-1] >= len(replay.touchdown_t) + 1  # the landed footholds and the plan
    assert wall >= replay.duration / 4.0 - 0.05  # paced: a quarter of real time
    with pytest.raises(InvalidInputError, match="--speed"):
        rp.play(replay, speed=0.0, launch=_FakeViewer)


@pytest.mark.parametrize("suffix, every", [(".mp4", 1), (".gif", 2)])
def test_a_replay_video_has_one_frame_per_saved_frame_or_every_second_for_gif(saved, tmp_path, suffix, every) -> None:
    import imageio.v3 as iio

    _, replay = saved
    out = rp.write_replay_video(replay, tmp_path / f"walk{suffix}", progress=False)
    frames = iio.imread(out, index=None)
    assert len(frames) == math.ceil(replay.n_frames / every)
    assert frames.shape[1:3] == ((480, 640) if suffix == ".mp4" else (300, 400))
    i_push = int(np.searchsorted(replay.t, 0.65)) // every  # the overlay's band is wider while the push acts
    band = lambda f: int(np.count_nonzero(f[:40, :, :].max(axis=2) < 10))  # noqa: E731
    assert band(frames[i_push]) > band(frames[0]) > 0


def test_push_at_and_decorations_follow_the_time(saved) -> None:
    _, replay = saved
    assert replay.push_at(0.5) is None
    np.testing.assert_array_equal(replay.push_at(0.65), [30.0, 10.0, 0.0])
    i = int(np.searchsorted(replay.t, 0.65))
    d = replay.decorations(i, np.array([0.1, 0.0, 1.0]))
    np.testing.assert_array_equal(d.push, [0.1, 0.0, 1.0, 30.0, 10.0, 0.0])
    assert len(d.landed) == int(np.sum(replay.touchdown_t <= replay.t[i] + 1e-9)) and len(d.planned) == 1
    assert replay.decorations(0).push is None  # no torso position: no arrow


def _corrupt(folder: Path, how: str) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    if how == "garbage":
        (folder / rp.REPLAY_FILE).write_bytes(b"not a zip file at all")
    elif how == "lip":
        (folder / "summary.json").write_text(json.dumps({"scenario": "circle", "robot": "lip"}))
    elif how == "version":
        np.savez(folder / rp.REPLAY_FILE, version=np.int64(99))
    elif how == "missing-arrays":
        np.savez(folder / rp.REPLAY_FILE, version=np.int64(rp.REPLAY_VERSION), t=np.zeros(3))


@pytest.mark.parametrize("how, words", [("absent", "no such folder"), ("lip", "LIP/ALIP run has no replay"),
                                        ("garbage", "unreadable"), ("version", "version 99"),
                                        ("missing-arrays", "has no field")])
def test_a_bad_run_folder_is_one_line_and_exit_2(tmp_path, capsys, how, words) -> None:
    folder = tmp_path / "run"
    if how != "absent":
        _corrupt(folder, how)
    with pytest.raises(InvalidInputError, match=words):
        rp.load_replay(folder)
    assert main(["replay", str(folder), "--video", str(tmp_path / "x.mp4")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lipmpcc: error: RUN_DIR") and words in err and "\n" not in err


def test_replay_cli_renders_a_video_and_refuses_the_viewer_without_a_display(saved, tmp_path, capsys, monkeypatch):
    file, replay = saved
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "r.gif")]) == 0
    assert (tmp_path / "r.gif").stat().st_size > 0 and f"{replay.n_frames} frames" in capsys.readouterr().out
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "r.avi")]) == 2
    assert "--video" in capsys.readouterr().err
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert main(["replay", str(file.parent)]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and "--video" in err and "MUJOCO_GL=egl" in err and err.count("\n") == 1
    assert main(["replay", str(file.parent), "--speed", "-1"]) == 2


def test_a_run_without_frames_has_no_replay() -> None:
    robot = SimpleNamespace(name="x", mjcf_path=None, torso_body="t")
    with pytest.raises(InvalidInputError, match="record_video"):
        rp.replay_from_run("walk", robot, None, SimpleNamespace(frames=None))


def test_a_full_body_cli_run_saves_its_replay_and_a_study_alone_writes_nothing(tmp_path, capsys) -> None:
    """``lipmpcc run stand`` leaves replay.npz with the stand's four pushes; ``studies.run`` (as a sweep
    calls it) writes nothing until ``RunResult.save``; a LIP run has no replay."""
    from lipmpcc import studies

    out = tmp_path / "stand"
    assert main(["run", "stand", "--duration", "1", "--out", str(out)]) == 0
    rep = rp.load_replay(out)
    assert rep.scenario == "stand" and rep.n_frames == 30 and len(rep.push_window) == 4
    np.testing.assert_allclose(rep.push_window[0], [0.2, 0.3])
    res = studies.run(studies.RunOptions("stand", robot="digit_like", duration=0.5, out=str(tmp_path / "lib")))
    assert not (tmp_path / "lib").exists() and isinstance(res.replay, rp.RunReplay)
    res.save(tmp_path / "lib")
    assert rp.load_replay(tmp_path / "lib").n_frames == 15
    lip = tmp_path / "lip"
    assert main(["run", "circle", "--steps", "3", "--out", str(lip)]) == 0
    assert not (lip / rp.REPLAY_FILE).exists()
    capsys.readouterr()
    assert main(["replay", str(lip)]) == 2 and "LIP/ALIP run has no replay" in capsys.readouterr().err


def test_a_model_binary_this_mujoco_cannot_read_is_rebuilt_from_the_robot(saved, tmp_path, monkeypatch) -> None:
    import dataclasses

    import mujoco

    _, replay = saved
    monkeypatch.chdir(tmp_path)
    handler = mujoco.get_mju_user_warning()
    broken = dataclasses.replace(replay, model_mjb=np.zeros(16, dtype=np.uint8))
    model = rp.replay_model(broken)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()  # MuJoCo's warning kept out of the user's folder
    assert mujoco.get_mju_user_warning() is handler
    assert model.nq == replay.qpos.shape[1] and model.nbody == rp.replay_model(replay).nbody
    with pytest.raises(InvalidInputError, match="nq"):
        rp.replay_model(dataclasses.replace(broken, qpos=replay.qpos[:, :5]))


@pytest.mark.parametrize("change, words", [
    ({"fps": 0.0}, "field fps = 0.0: expected a positive frame rate"),
    ({"fps": math.nan}, "field fps = nan"),
    ("nan-frame", "field qpos: frame 3 holds nan: expected finite numbers"),
    ("times-backwards", "field t: frame 2"),
    ("plan-shape", "field plan_xy has shape (1, 3): expected (p, 2) with p ="),
    ("frames-short", "field qpos has shape"),
    ("side", "field touchdown_side"),
    ("mjb", "field model_mjb"),
])
def test_a_damaged_replay_names_the_field(saved, tmp_path, change, words) -> None:
    from dataclasses import replace

    _, replay = saved
    if change == "nan-frame":
        q = replay.qpos.copy()
        q[3, 2] = math.nan
        bad = replace(replay, qpos=q)
    elif change == "times-backwards":
        t = replay.t.copy()
        t[2] = t[1] - 0.5
        bad = replace(replay, t=t)
    elif change == "plan-shape":
        bad = replace(replay, plan_t=np.zeros(1), plan_yaw=np.zeros(1), plan_xy=np.zeros((1, 3)))
    elif change == "frames-short":
        bad = replace(replay, qpos=replay.qpos[:-1])
    elif change == "side":
        bad = replace(replay, touchdown_side=np.full(len(replay.touchdown_t), 5, dtype=np.int8))
    elif change == "mjb":
        bad = replace(replay, model_mjb=np.zeros(0, dtype=np.uint8))
    else:
        bad = replace(replay, **change)
    rp.save_replay(bad, tmp_path)
    with pytest.raises(InvalidInputError) as err:
        rp.load_replay(tmp_path)
    assert words in str(err.value) and "\n" not in str(err.value) and "inconsistent" not in str(err.value)


def test_video_files_that_cannot_be_written_are_one_line(saved, tmp_path, capsys, monkeypatch) -> None:
    file, _ = saved
    (tmp_path / "taken.mp4").mkdir()
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "taken.mp4")]) == 2
    assert "it is an existing folder" in capsys.readouterr().err
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "nowhere" / "v.mp4")]) == 2
    assert "does not exist" in capsys.readouterr().err
    monkeypatch.setattr("os.access", lambda path, mode: False)  # as root, chmod would not stop us
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "v.mp4")]) == 2
    err = capsys.readouterr().err
    assert "read-only" in err and err.count("\n") == 1 and not (tmp_path / "v.mp4").exists()


def test_replay_speed_is_honoured_in_a_video_or_refused_when_it_leaves_no_frame_rate(saved, tmp_path, capsys) -> None:
    import imageio.v3 as iio

    file, replay = saved
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "fast.gif"), "--speed", "2"]) == 0
    assert "at 2x real time" in capsys.readouterr().out
    assert len(iio.imread(tmp_path / "fast.gif", index=None)) == math.ceil(replay.n_frames / 4)  # every 2nd of the GIF's
    assert main(["replay", str(file.parent), "--video", str(tmp_path / "slow.gif"), "--speed", "0.001"]) == 2
    err = capsys.readouterr().err
    assert "--speed = 0.001" in err and "frame per second" in err and err.count("\n") == 1
