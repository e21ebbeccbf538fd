"""Fuzz cases of issue 30 (what landed after the first hardening): sweeps (spec, runner, store, CLI),
replays (the replay file field by field, --speed, --video), the timed MPCC's entry, a student's planner
(StepPlan, PlannerInput, rate_hz) and layouts. Each states the clean behaviour it expects; all are cheap
(no case runs a study: a sweep's executor answers at once, a replay is a small synthetic file)."""

from __future__ import annotations

import math
from concurrent.futures import Executor, Future
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .cases_api import api
from .cases_cli import cli
from .harness import Case

NAN = float("nan")
TINY = {"name": "fz", "study": "circle-push", "robot": "lip", "planners": ["mpcc"], "options": {"steps": 10},
        "axes": {"impulse": {"values": [1.0, 2.0]}, "push_step": {"value": 4}}}
TINY_TOML = ('name = "fz"\nstudy = "circle-push"\nrobot = "lip"\nplanners = ["mpcc"]\n[options]\nsteps = 10\n'
             '[axes]\nimpulse = { values = [1.0, 2.0] }\npush_step = 4\n')


def _spec(**changes: Any) -> dict[str, Any]:
    return {**TINY, **changes}


def parse(raw: Any, **kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.sweep import parse_spec

        return parse_spec(raw(tmp) if callable(raw) else raw, **kw)
    return run


class _Canned(Executor):
    """An executor whose futures answer at once with ``answer(case)``."""

    def __init__(self, answer: Callable[[dict], Any]) -> None:
        self.answer = answer

    def submit(self, fn: Any, /, *args: Any, **kwargs: Any) -> Future:  # type: ignore[override]
        f: Future = Future()
        f.set_result(self.answer(args[0]))
        return f


def _record(case: dict) -> dict:
    return {"id": case["id"], "status": "error", "summary": None, "push": {}, "error": "canned", "wall_s": 0.0,
            "worker": "fuzz"}


def sweep(out: str = "out", setup: Callable[[Path], None] | None = None, answer: Callable[[dict], Any] = _record,
          **kw: Any) -> Callable[[Path], Any]:
    """``run_sweep`` of the tiny spec into ``tmp/out`` (after ``setup(tmp)``), on a canned executor by default."""
    def run(tmp: Path) -> Any:
        from lipmpcc.sweep import parse_spec, run_sweep

        if setup is not None:
            setup(tmp)
        kw.setdefault("executor", _Canned(answer))
        return run_sweep(kw.pop("spec", None) or parse_spec(TINY), tmp / out, progress=False, **kw)
    return run


def _garbage_store(tmp: Path) -> None:
    (tmp / "out").mkdir()
    (tmp / "out" / "results.sqlite").write_bytes(b"not sqlite at all " * 64)


def _metaless_store(tmp: Path) -> None:
    import sqlite3

    (tmp / "out").mkdir()
    con = sqlite3.connect(tmp / "out" / "results.sqlite")
    con.execute("CREATE TABLE cases (case_id TEXT PRIMARY KEY, status TEXT)")
    con.execute("INSERT INTO cases VALUES ('a', 'done')")
    con.commit()
    con.close()


def _truncated_store(tmp: Path) -> None:
    from lipmpcc.sweep import ResultStore, parse_spec

    spec = parse_spec(TINY)
    store = ResultStore(tmp / "out" / "results.sqlite", spec)
    for case in spec.cases():
        store.record(case, _record(case))
    store.close()
    data = (tmp / "out" / "results.sqlite").read_bytes()
    (tmp / "out" / "results.sqlite").write_bytes(data[: len(data) // 3])


def _other_store(tmp: Path) -> None:
    from lipmpcc.sweep import ResultStore, parse_spec

    ResultStore(tmp / "out" / "results.sqlite", parse_spec(_spec(options={"steps": 9}))).close()


def _loop(tmp: Path) -> None:
    (tmp / "out").symlink_to(tmp / "out")


def _file(tmp: Path) -> None:
    (tmp / "out").write_text("a file")


def held_sweep(tmp: Path) -> Any:
    from lipmpcc.studies.outputs import OutputLock

    with OutputLock(tmp / "out"):
        return sweep()(tmp)


def _stones(tmp: Path) -> str:
    p = tmp / "bad_stones.csv"
    p.write_text("x,y\nfoo,bar\n")
    return str(p)


def _path(tmp: Path) -> str:
    p = tmp / "bad_path.csv"
    p.write_text("a,b\n1,2\n")
    return str(p)


SWEEP_API = [
    api("harden-parse_spec-None", "sweeps", parse(None), ("sweep spec",)),
    api("harden-parse_spec-int", "sweeps", parse(3), ("sweep spec",)),
    api("harden-parse_spec-str", "sweeps", parse("push"), ("sweep spec",)),
    api("harden-parse_spec-list", "sweeps", parse(["study", "push"]), ("sweep spec",)),
    api("harden-parse_spec-empty", "sweeps", parse({}), ("study",)),
    api("harden-parse_spec-unknown-key", "sweeps", parse(_spec(colour="red")), ("colour",)),
    api("harden-parse_spec-1e9-grid", "sweeps",
        parse(_spec(axes={"impulse": {"range": [0, 10], "n": 100000}, "direction": {"range": [0, 6], "n": 10000}})),
        ("1000000000 cases", "CPU time", "--allow-long")),
    api("harden-parse_spec-axis-n-1e9", "sweeps", parse(_spec(axes={"impulse": {"range": [0, 10], "n": 10**9}}),
                                                        allow_long=True), ("axes.impulse.n", "1000000")),
    api("harden-parse_spec-draws-1e6", "sweeps", parse(_spec(draws=10**6, axes={"seed": {"random": [0, 9]}})),
        ("1000000 cases",)),
    api("harden-parse_spec-missing-stones", "sweeps",
        parse({"name": "s", "study": "stones", "planners": ["alip-mpc"], "options": {"stones": "gone.csv"}}),
        ("options.stones", "gone.csv", "no such file")),
    api("harden-parse_spec-bad-stones", "sweeps",
        parse(lambda tmp: {"name": "s", "study": "stones", "planners": ["alip-mpc"], "options": {"stones": _stones(tmp)}}),
        ("options.stones", "bad_stones.csv")),
    api("harden-parse_spec-missing-path", "sweeps",
        parse({"name": "p", "study": "follow-path", "robot": "lip", "planners": ["mpcc"], "options": {"path": "gone.csv"}}),
        ("options.path", "gone.csv")),
    api("harden-parse_spec-bad-path", "sweeps",
        parse(lambda tmp: {"name": "p", "study": "follow-path", "robot": "lip", "planners": ["mpcc"],
                           "options": {"path": _path(tmp)}}), ("options.path", "bad_path.csv")),
    api("harden-parse_spec-missing-obstacles", "sweeps",
        parse({"name": "o", "study": "overtake", "robot": "lip", "planners": ["mpcc"],
               "options": {"obstacles": "gone.json"}}), ("options.obstacles", "gone.json")),
    api("harden-parse_spec-planner-file", "sweeps",
        parse({"name": "p", "study": "follow-path", "robot": "lip",
               "planners": [{"planner": "mpcc", "path": "gone.csv"}]}), ("planners['mpcc'].path", "gone.csv")),
    api("harden-parse_spec-path-empty", "sweeps",
        parse({"name": "p", "study": "follow-path", "robot": "lip", "planners": ["mpcc"], "options": {"path": ""}}),
        ("options.path",)),
    api("harden-parse_spec-timeout-negative", "sweeps", parse(_spec(timeout_s=-1)), ("timeout_s",)),
    api("harden-parse_spec-small-grid-ok", "sweeps", parse(TINY), (), "ok"),
    api("harden-load_spec-None", "sweeps", lambda tmp: __import__("lipmpcc.sweep", fromlist=["x"]).load_spec(None),
        ("sweep spec",)),
    api("harden-load_spec-blank", "sweeps", lambda tmp: __import__("lipmpcc.sweep", fromlist=["x"]).load_spec("  "),
        ("sweep spec",)),
    api("harden-run_sweep-workers-0", "sweeps", sweep(workers=0, executor=None), ("workers", "0")),
    api("harden-run_sweep-workers-negative", "sweeps", sweep(workers=-1, executor=None), ("workers", "-1")),
    api("harden-run_sweep-workers-float", "sweeps", sweep(workers=1.5, executor=None), ("workers", "1.5")),
    api("harden-run_sweep-workers-str", "sweeps", sweep(workers="2", executor=None), ("workers", "'2'")),
    api("harden-run_sweep-workers-bool", "sweeps", sweep(workers=True, executor=None), ("workers", "True")),
    api("harden-run_sweep-max_in_flight-0", "sweeps", sweep(max_in_flight=0), ("max_in_flight", "0")),
    api("harden-run_sweep-max_in_flight-negative", "sweeps", sweep(max_in_flight=-5), ("max_in_flight",)),
    api("harden-run_sweep-max_in_flight-nan", "sweeps", sweep(max_in_flight=NAN), ("max_in_flight",)),
    api("harden-run_sweep-executor-object", "sweeps", sweep(executor=object()), ("executor", "Executor")),
    api("harden-run_sweep-spec-dict", "sweeps", sweep(spec=TINY), ("spec", "SweepSpec")),
    api("harden-run_sweep-futures-str", "sweeps", sweep(answer=lambda c: "hello"), ("executor", "hello", "run_case")),
    api("harden-run_sweep-futures-None", "sweeps", sweep(answer=lambda c: None), ("executor", "None")),
    api("harden-run_sweep-futures-other-id", "sweeps", sweep(answer=lambda c: {**_record(c), "id": "other"}),
        ("executor", "other")),
    api("harden-run_sweep-futures-ok", "sweeps", sweep(), (), "ok",
        check=lambda r: None if r.value.errors == 2 else f"expected 2 canned errors, got {r.value}"),
    api("harden-run_sweep-out-symlink-loop", "sweeps", sweep(setup=_loop), ("--out", "symbolic link")),
    api("harden-run_sweep-out-file", "sweeps", sweep(setup=_file), ("--out", "existing file")),
    api("harden-run_sweep-out-busy", "sweeps", held_sweep, ("pid", "is writing to this folder")),
    api("harden-run_sweep-store-garbage", "sweeps", sweep(setup=_garbage_store), ("store", "results.sqlite", "--replace")),
    api("harden-run_sweep-store-metaless", "sweeps", sweep(setup=_metaless_store),
        ("store", "no sweep specification", "1 rows")),
    api("harden-run_sweep-store-truncated", "sweeps", sweep(setup=_truncated_store), ("store", "results.sqlite")),
    api("harden-run_sweep-store-other-spec", "sweeps", sweep(setup=_other_store), ("spec changed", "--replace")),
    api("harden-run_sweep-store-replace-ok", "sweeps", sweep(setup=_garbage_store, replace=True), (), "ok"),
]

SWEEP_CLI = [
    cli("harden-sweep-workers-0", "sweep spec.toml --workers 0", ("--workers", "0"), "usage", "sweeps",
        files={"spec.toml": TINY_TOML}),
    cli("harden-sweep-no-spec", "sweep", ("spec",), "usage", "sweeps"),
    cli("harden-sweep-report-nowhere", "sweep --report {tmp}/nowhere", ("nowhere",), "usage", "sweeps"),
    cli("harden-sweep-huge-grid", "sweep big.toml --out {tmp}/o", ("cases", "--allow-long"), "usage", "sweeps",
        files={"big.toml": TINY_TOML.replace("values = [1.0, 2.0]", "range = [0.0, 9.0], n = 1000000")
               .replace("push_step = 4", "push_step = 4\ndirection = { range = [0.0, 6.0], n = 1000 }")}),
    cli("harden-sweep-missing-stones", "sweep s.toml --out {tmp}/o", ("options.stones", "gone.csv"), "usage", "sweeps",
        files={"s.toml": 'study = "stones"\nplanners = ["alip-mpc"]\n[options]\nstones = "gone.csv"\n'}),
    cli("harden-sweep-damaged-store", "sweep spec.toml --out {tmp}/o --no-progress", ("store", "--replace"), "error",
        "sweeps", files={"spec.toml": TINY_TOML, "o/results.sqlite": b"garbage" * 100}, rcs=(1,)),
    cli("harden-sweep-not-toml", "sweep spec.toml", ("sweep spec", "TOML"), "usage", "sweeps",
        files={"spec.toml": "study = = push"}),
    cli("harden-sweep-out-loop", "sweep spec.toml --out {tmp}/loop", ("--out", "symbolic link"), "usage", "sweeps",
        files={"spec.toml": TINY_TOML}, setup=lambda tmp: (tmp / "loop").symlink_to(tmp / "loop")),
]


# ---- replays ---------------------------------------------------------------------------------------------
def _replay(tmp: Path, **changes: Any) -> Path:
    """A small synthetic replay (5 frames of a 3-coordinate model) with ``changes``, saved in ``tmp/run``."""
    from dataclasses import replace

    from lipmpcc.studies import replay as rp

    base = rp.RunReplay(scenario="walk", robot="x", robot_mjcf="", torso_body="torso", fps=30.0,
                        model_mjb=np.arange(16, dtype=np.uint8), t=np.arange(5) / 30.0, qpos=np.zeros((5, 3)))
    fixed = {}
    for k, v in changes.items():
        fixed[k] = v(base) if callable(v) else v
    return rp.save_replay(replace(base, **fixed), tmp / "run").parent


def load(**changes: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from lipmpcc.studies.replay import load_replay

        return load_replay(_replay(tmp, **changes))
    return run


def _nan_frame(r: Any) -> np.ndarray:
    q = r.qpos.copy()
    q[2, 1] = NAN
    return q


def _speed(speed: Any, video: str | None = None) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from lipmpcc.studies.replay import replay_run

        return replay_run(tmp / "run", speed, video)
    return run


REPLAY = [
    api("harden-replay-fps-0", "replays", load(fps=0.0), ("fps", "positive frame rate")),
    api("harden-replay-fps-nan", "replays", load(fps=NAN), ("fps",)),
    api("harden-replay-fps-negative", "replays", load(fps=-30.0), ("fps",)),
    api("harden-replay-nan-frame", "replays", load(qpos=_nan_frame), ("qpos", "frame 2", "nan")),
    api("harden-replay-inf-time", "replays", load(t=lambda r: np.r_[r.t[:4], math.inf]), ("field t", "frame 4")),
    api("harden-replay-times-backwards", "replays", load(t=lambda r: r.t[::-1].copy()), ("field t", "in order")),
    api("harden-replay-frames-short", "replays", load(qpos=lambda r: r.qpos[:3]), ("qpos", "shape")),
    api("harden-replay-qpos-1d", "replays", load(qpos=lambda r: r.qpos[:, 0]), ("qpos", "shape")),
    api("harden-replay-plan-shape", "replays", load(plan_t=np.zeros(2), plan_yaw=np.zeros(2), plan_xy=np.zeros((2, 3))),
        ("plan_xy", "(p, 2)")),
    api("harden-replay-plan-count", "replays", load(plan_t=np.zeros(2), plan_yaw=np.zeros(3), plan_xy=np.zeros((2, 2))),
        ("plan_yaw",)),
    api("harden-replay-touchdown-side", "replays",
        load(touchdown_t=np.zeros(1), touchdown_xyz=np.zeros((1, 3)), touchdown_side=np.array([7], dtype=np.int8)),
        ("touchdown_side",)),
    api("harden-replay-push-force-shape", "replays", load(push_window=np.zeros((1, 2)), push_force=np.zeros((1, 2))),
        ("push_force",)),
    api("harden-replay-obstacles-frames", "replays",
        load(obstacle_xy=np.zeros((3, 1, 2)), obstacle_heading=np.zeros((3, 1)), obstacle_axes=np.ones((1, 2)),
             obstacle_circle=np.ones(1, dtype=np.int8)), ("obstacle_xy",)),
    api("harden-replay-mjb-empty", "replays", load(model_mjb=np.zeros(0, dtype=np.uint8)), ("model_mjb",)),
    api("harden-replay-strings-in-t", "replays", load(t=np.array(["a"] * 5)), ("field t",)),
    api("harden-replay-good-ok", "replays", load(), (), "ok"),
    api("harden-replay-speed-0", "replays", _speed(0.0), ("--speed", "positive")),
    api("harden-replay-speed-nan", "replays", _speed(NAN), ("--speed",)),
    api("harden-replay-speed-str", "replays", _speed("fast"), ("--speed", "fast")),
    api("harden-replay-speed-bool", "replays", _speed(True), ("--speed", "True")),
    api("harden-replay-video-avi", "replays", _speed(1.0, "v.avi"), ("--video", ".mp4 or .gif")),
    api("harden-replay-video-dir", "replays", lambda tmp: (tmp.joinpath("d.mp4").mkdir(), _speed(1.0, str(tmp / "d.mp4"))(tmp)),
        ("--video", "existing folder")),
    api("harden-replay-video-missing-folder", "replays", _speed(1.0, "nowhere/v.gif"), ("--video", "does not exist")),
    cli("harden-replay-cli-fps-0", "replay {tmp}/run --video {tmp}/v.mp4", ("RUN_DIR", "fps"), "usage", "replays",
        setup=lambda tmp: _replay(tmp, fps=0.0)),
    cli("harden-replay-cli-speed-with-video", "replay {tmp}/run --video {tmp}/v.gif --speed 0.0001", ("--speed",),
        "usage", "replays", setup=lambda tmp: _replay(tmp)),
    cli("harden-replay-cli-missing-field", "replay {tmp}/run", ("RUN_DIR", "has no field"), "usage", "replays",
        setup=lambda tmp: (tmp.joinpath("run").mkdir(), np.savez(tmp / "run" / "replay.npz", version=np.int64(1)))),
]


# ---- the timed MPCC, student planners, layouts ----------------------------------------------------------------
def timed_plan(inp: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.paths import ArcPath
        from lipmpcc.planners.mpcc import MpccParams
        from lipmpcc.planners.mpcc_timed import TimedMpccParams, TimedMpccPlanner

        return TimedMpccPlanner(ArcPath.circle(2.0), TimedMpccParams(mpcc=MpccParams.circle(), T_min=0.3, T_max=0.5)).plan(inp)
    return run


def step_plan(**kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.planners.base import StepPlan

        return StepPlan(**{"foothold": (0.1, 0.0), "yaw": 0.0, "duration": 0.4, **kw})
    return run


def planner_input(**kw: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.planners.base import PlannerInput

        good = dict(t=0.2, com_pos=np.array([0.0, 0.0, 0.9]), com_vel=np.zeros(3), dcm=np.zeros(2), omega=3.3,
                    stance_side="left", stance_pos=np.zeros(3), stance_yaw=0.0, swing_pos=np.zeros(3), swing_yaw=0.0,
                    time_since_touchdown=0.1, step_index=2, torso_yaw=0.0)
        return PlannerInput(**{**good, **kw})
    return run


def rate(value: Any) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:  # noqa: ARG001
        from lipmpcc.planners.base import check_rate_hz

        class Student:
            name, rate_hz = "student", value

            def reset(self) -> None:
                pass

        return check_rate_hz(Student(), 400.0)
    return run


def layout(text: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from lipmpcc.robots.layouts import read_layout_file

        (tmp / "l.toml").write_text(text)
        return read_layout_file(tmp / "l.toml")
    return run


STUDENT = [
    api("harden-TimedMpcc-plan-None", "api-planners", timed_plan(None), ("inp", "PlannerInput")),
    api("harden-TimedMpcc-plan-str", "api-planners", timed_plan("state"), ("inp", "'state'")),
    api("harden-TimedMpcc-plan-dict", "api-planners", timed_plan({"t": 0.0}), ("inp", "PlannerInput")),
    api("harden-StepPlan-foothold-str", "api-planners", step_plan(foothold="abc"), ("StepPlan.foothold", "'abc'")),
    api("harden-StepPlan-foothold-None", "api-planners", step_plan(foothold=None), ("StepPlan.foothold", "None")),
    api("harden-StepPlan-duration-None", "api-planners", step_plan(duration=None), ("StepPlan.duration", "None")),
    api("harden-StepPlan-duration-str", "api-planners", step_plan(duration="0.4"), ("StepPlan.duration", "'0.4'")),
    api("harden-StepPlan-yaw-None", "api-planners", step_plan(yaw=None), ("StepPlan.yaw",)),
    api("harden-StepPlan-cop-str", "api-planners", step_plan(cop_offset="xy"), ("StepPlan.cop_offset",)),
    api("harden-StepPlan-status-int", "api-planners", step_plan(status=3), ("StepPlan.status",)),
    api("harden-StepPlan-numpy-ok", "api-planners", step_plan(foothold=np.array([[0.1], [0.0]]), duration=np.float32(0.4)),
        (), "ok"),
    api("harden-PlannerInput-com_pos-str", "api-planners", planner_input(com_pos="abc"), ("PlannerInput.com_pos",)),
    api("harden-PlannerInput-com_vel-nan", "api-planners", planner_input(com_vel=[0.0, NAN, 0.0]), ("PlannerInput.com_vel",)),
    api("harden-PlannerInput-omega-0", "api-planners", planner_input(omega=0.0), ("PlannerInput.omega",)),
    api("harden-PlannerInput-side", "api-planners", planner_input(stance_side="middle"), ("PlannerInput.stance_side",)),
    api("harden-PlannerInput-step_index", "api-planners", planner_input(step_index=-1), ("PlannerInput.step_index",)),
    api("harden-PlannerInput-t-None", "api-planners", planner_input(t=None), ("PlannerInput.t",)),
    api("harden-PlannerInput-lists-ok", "api-planners", planner_input(com_pos=[0, 0, 0.9], step_index=np.int64(1)), (), "ok"),
    api("harden-rate_hz-str", "api-planners", rate("25"), ("planner.rate_hz", "'25'")),
    api("harden-rate_hz-1e9", "api-planners", rate(1e9), ("planner.rate_hz", "400")),
    api("harden-rate_hz-nan", "api-planners", rate(NAN), ("planner.rate_hz",)),
    api("harden-rate_hz-None", "api-planners", rate(None), ("planner.rate_hz",)),
    api("harden-step-duration-range-lip", "api-planners",
        lambda tmp: __import__("lipmpcc.studies", fromlist=["x"]).RunOptions("circle", robot="lip",
                                                                             step_duration_range=(0.5, 0.7)),
        ("--step-duration-range", "T = 0.4 s")),
    api("harden-layout-same-foot-body", "layout",
        layout('left_foot_body = "foot"\nright_foot_body = "foot"\ntorso_body = "torso"\n'),
        ("left_foot_body", "right_foot_body", "'foot'")),
    api("harden-layout-same-sole-site", "layout",
        layout('left_foot_body = "l"\nright_foot_body = "r"\ntorso_body = "t"\nleft_sole_site = "s"\nright_sole_site = "s"\n'),
        ("left_sole_site", "right_sole_site")),
    api("harden-layout-distinct-ok", "layout", layout('left_foot_body = "l"\nright_foot_body = "r"\ntorso_body = "t"\n'),
        (), "ok"),
]

CASES: list[Case] = SWEEP_API + SWEEP_CLI + REPLAY + STUDENT
