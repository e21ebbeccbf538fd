"""lipmpcc.studies.viewer: ``--viewer`` refused in one line (exit 2, before the run) without a display and
on the reduced models; the live view's decorations and pacing with a stand-in viewer; and, where Xvfb is
installed (.ci/run installs it in CI), MuJoCo's real passive viewer on a virtual display."""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from lipmpcc.cli import main
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.planners.base import StepPlan
from lipmpcc.studies import viewer as vw


@pytest.fixture
def no_display(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")


def test_no_display_names_the_cause_and_the_ways_out(no_display) -> None:
    assert vw.display_problem() == "no display (DISPLAY and WAYLAND_DISPLAY are not set)"
    with pytest.raises(vw.ViewerUnavailableError) as err:
        vw.check_display()
    text = str(err.value)
    assert isinstance(err.value, InvalidInputError) and "\n" not in text
    for words in ("--viewer", "no display", "--video", "MUJOCO_GL=egl", "MUJOCO_GL=osmesa", "mjpython"):
        assert words in text


def test_run_with_viewer_and_no_display_is_exit_2_before_the_run(no_display, tmp_path, capsys) -> None:
    out = tmp_path / "run"
    assert main(["run", "walk", "--duration", "0.5", "--viewer", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lipmpcc: error: --viewer: the viewer cannot open: no display") and err.count("\n") == 1
    assert not out.exists()  # nothing ran, nothing written


@pytest.mark.parametrize("args, words", [
    (["circle", "--viewer"], "--viewer does not apply to scenario 'circle' with --robot lip"),
    (["stones", "--viewer", "fast"], "--viewer does not apply to scenario 'stones' with --robot alip"),
    (["circle", "--video-format", "gif"], "--video-format"),
    (["walk", "--video-format", "gif"], "--video-format = 'gif': expected given with --video"),
])
def test_viewer_and_video_format_are_full_body_options(tmp_path, capsys, args, words) -> None:
    assert main(["run", *args, "--out", str(tmp_path / "x")]) == 2
    assert words in capsys.readouterr().err


def test_a_bad_viewer_mode_is_refused(tmp_path, capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main(["run", "walk", "--viewer", "slow", "--out", str(tmp_path / "x")])
    assert exc.value.code == 2 and "realtime" in capsys.readouterr().err
    with pytest.raises(InvalidInputError, match="--viewer"):
        vw.LiveViewer("slow")


class _Fake:
    def __init__(self, model, data, **kw) -> None:
        import mujoco

        self.user_scn = mujoco.MjvScene(model, maxgeom=2000)
        self.data, self.syncs, self.running, self.closed = data, 0, True, False

    def is_running(self) -> bool:
        return self.running

    def lock(self):
        return contextlib.nullcontext()

    def sync(self) -> None:
        self.syncs += 1

    def close(self) -> None:
        self.closed = True


def _sim():
    import mujoco

    model = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body name='torso' pos='0 0 1'><freejoint/><geom size='0.1'/></body></worldbody></mujoco>")
    data = mujoco.MjData(model)
    return SimpleNamespace(model=model, qpos=data.qpos.copy(), description=SimpleNamespace(torso_body="torso"))


def test_the_live_view_draws_the_plan_its_preview_the_landed_feet_and_the_push() -> None:
    from lipmpcc.paths import LinePath

    made: list[_Fake] = []
    live = vw.LiveViewer("fast", launch=lambda m, d, **kw: made.append(_Fake(m, d, **kw)) or made[-1])
    windows: list = []
    live.set_scene(path=LinePath((0.0, 0.0), (1.0, 0.0)), pushes=lambda: windows)
    plan = StepPlan(foothold=np.array([0.3, 0.1]), yaw=0.0, duration=0.4, preview=np.array([[0.6, -0.1, 0.0, 0.4]]))
    td = SimpleNamespace(pos=np.array([0.0, -0.1, 0.0]), side="right")
    gait = SimpleNamespace(plans=[(0.0, plan)], touchdowns=[td])
    sim = _sim()
    live(0.0, sim, gait)
    v = made[0]
    n_quiet = v.user_scn.ngeom
    assert v.syncs == 1 and n_quiet == 10 + 1 + 2  # 10 path segments, a landed foot, the plan and its preview
    windows.append((0.5, 0.6, (40.0, 0.0)))  # a push registered during the run
    live(0.55, sim, gait)
    assert v.user_scn.ngeom == n_quiet + 1  # the arrow, drawn afresh (not piled up)
    d = live.decorations(0.55, gait)
    np.testing.assert_array_equal(d.planned, [[0.3, 0.1], [0.6, -0.1]])
    np.testing.assert_array_equal(d.push[3:], [40.0, 0.0, 0.0])
    v.running = False  # the window closed: the run goes on unseen
    live(0.6, sim, gait)
    assert v.syncs == 2 and live.refreshes == 2
    live.close()
    assert v.closed


def test_realtime_holds_the_run_to_the_wall_clock() -> None:
    live = vw.LiveViewer("realtime", launch=_Fake)
    sim, gait = _sim(), SimpleNamespace(plans=[], touchdowns=[])
    t0 = time.perf_counter()
    for t in np.arange(0.0, 0.31, 0.05):
        live(float(t), sim, gait)
    assert time.perf_counter() - t0 >= 0.29
    fast = vw.LiveViewer("fast", launch=_Fake)
    t0 = time.perf_counter()
    for t in np.arange(0.0, 0.31, 0.05):
        fast(float(t), sim, gait)
    assert time.perf_counter() - t0 < 0.25


_XVFB = shutil.which("Xvfb")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="Xvfb is a Linux X server")
def test_the_live_viewer_and_a_replay_run_on_a_virtual_display(tmp_path: Path) -> None:
    if _XVFB is None:  # skipped outside CI; in CI, where .ci/run installs it, a missing Xvfb fails (as tests/docs)
        if os.environ.get("CI"):
            pytest.fail("needs Xvfb (in CI this must not be missing: .ci/run installs it)")
        pytest.skip("needs Xvfb (apt-get install xvfb)")
    display = f":{90 + os.getpid() % 100}"
    xvfb = subprocess.Popen([_XVFB, display, "-screen", "0", "640x480x24", "-nolisten", "tcp"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(1.0)
        if xvfb.poll() is not None:
            pytest.skip("Xvfb did not start")
        env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "WAYLAND_DISPLAY")}
        env.update(DISPLAY=display, LIPMPCC_FAST="1")
        script = ("from lipmpcc.loops.fullbody.loop import FullBodyLoop\n"
                  "from lipmpcc.planners.capture_point import CapturePointPlanner\n"
                  "from lipmpcc.robots import load_robot\n"
                  "from lipmpcc.studies.viewer import LiveViewer, check_display\n"
                  "check_display()\n"
                  "live = LiveViewer('fast')\n"
                  "robot = load_robot('digit_like')\n"
                  "loop = FullBodyLoop(robot, planner=CapturePointPlanner(speed=0.4))\n"
                  "res = loop.run(duration=0.5, on_tick=live, record_video=True)\n"
                  "print('refreshes', live.refreshes, 'running', live._viewer.is_running(), 'fell', res.fell)\n"
                  "live.close()\n"
                  "from lipmpcc.studies import replay as rp\n"
                  f"rp.save_replay(rp.replay_from_run('walk', robot, loop.sim.model, res), {str(tmp_path)!r})\n"
                  f"print(rp.replay_run({str(tmp_path)!r}, speed=10.0))\n")
        done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=300)
        assert done.returncode == 0, done.stderr[-2000:]
        assert "refreshes 31 running True fell False" in done.stdout  # 60 Hz over 0.5 s, and the first tick
        assert "walk on digit_like: showed 15 of 15 frames at 10x real time" in done.stdout  # lipmpcc replay
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)
