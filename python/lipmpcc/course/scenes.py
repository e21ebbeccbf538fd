"""Seeded random scenes for ``follow-path`` / ``overtake`` and a benchmark over them (issue 31).

A scene is a smooth path through random waypoints (a natural cubic spline, :class:`~lipmpcc.paths.SplinePath`)
from the origin heading +x, of a given length and largest turn per waypoint, with 1–3 circular obstacles of
four kinds:

- ``ahead``: moving along the path, more slowly than the robot (``{"s0", "speed" > 0}``);
- ``oncoming``: moving along the path towards the robot (``{"s0", "speed" < 0}``);
- ``crossing``: crossing the path at constant velocity, timed to be there about when the robot arrives
  (at :attr:`SceneSpec.robot_speed`);
- ``static``: standing still, its centre within :attr:`SceneSpec.static_offset` of the path.

:func:`make_scene` draws one scene from a seed (the same seed gives the same scene, bit for bit);
:func:`write_scene` writes it in the formats of ``docs/formats.md`` (the path CSV and the obstacle JSON of
``lipmpcc run follow-path --path P.csv --obstacles O.json``). :func:`run_scene` runs one scene on the LIP or
a full body with either MPCC planner and either weights, and :func:`judge` says whether it succeeded (the
end reached or a slower obstacle trailed, without contact); :func:`success_table` gives the success rate
per obstacle kind with Wilson intervals. ``benchmarks/bench_scenes.py`` runs the benchmark.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path as FsPath
from typing import Any, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..paths import SplinePath
from ..metrics import wilson_interval

__all__ = [
    "OBSTACLE_KINDS",
    "SceneSpec",
    "Scene",
    "make_scene",
    "write_scene",
    "SceneRun",
    "run_scene",
    "reached_end",
    "trailing",
    "judge",
    "success_table",
    "benchmark_report",
]

#: the obstacle kinds of a scene
OBSTACLE_KINDS = ("ahead", "oncoming", "crossing", "static")


@dataclass(frozen=True)
class SceneSpec:
    """How random scenes are drawn.

    Attributes:
        length: path length [m].
        n_waypoints: waypoints after the start (the path's segments).
        max_turn: largest heading change between segments [rad] (sets the curvature).
        n_obstacles: (least, most) obstacles per scene.
        radius: (min, max) obstacle radius [m].
        kinds: the kinds drawn from (uniformly).
        ahead_speed: (min, max) speed of an ``ahead`` obstacle along the path [m/s].
        oncoming_speed: (min, max) speed of an ``oncoming`` obstacle towards the robot [m/s].
        crossing_speed: (min, max) speed of a ``crossing`` obstacle [m/s].
        static_offset: largest distance of a ``static`` obstacle's centre from the path [m].
        robot_speed: the robot's assumed walking speed, to time the crossings [m/s].
        clear_start: no obstacle within this distance of the start at t = 0 [m] (and none on the last
            ``clear_start`` metres of the path, so that its end can be reached).
    """

    length: float = 19.0
    n_waypoints: int = 6
    max_turn: float = 0.6
    n_obstacles: tuple[int, int] = (1, 3)
    radius: tuple[float, float] = (0.2, 0.4)
    kinds: tuple[str, ...] = OBSTACLE_KINDS
    ahead_speed: tuple[float, float] = (0.05, 0.15)
    oncoming_speed: tuple[float, float] = (0.2, 0.5)
    crossing_speed: tuple[float, float] = (0.3, 0.7)
    static_offset: float = 0.3
    robot_speed: float = 0.29
    clear_start: float = 2.0

    def __post_init__(self) -> None:
        for name in ("length", "max_turn", "robot_speed", "clear_start"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InvalidInputError(name, v, "a positive number")
        if self.length < 4 * self.clear_start:
            raise InvalidInputError("length", self.length, f">= 4 clear_start = {4 * self.clear_start} m")
        if not (isinstance(self.n_waypoints, int) and self.n_waypoints >= 2):
            raise InvalidInputError("n_waypoints", self.n_waypoints, "an integer >= 2")
        lo, hi = self.n_obstacles
        if not (isinstance(lo, int) and isinstance(hi, int) and 0 <= lo <= hi <= 16):
            raise InvalidInputError("n_obstacles", self.n_obstacles, "(least, most) integers, 0 <= least <= most <= 16")
        bad = [k for k in self.kinds if k not in OBSTACLE_KINDS]
        if bad or not self.kinds:
            raise InvalidInputError("kinds", self.kinds, f"a non-empty subset of {OBSTACLE_KINDS}")
        for name in ("radius", "ahead_speed", "oncoming_speed", "crossing_speed"):
            a, b = getattr(self, name)
            if not (0 < a <= b and math.isfinite(b)):
                raise InvalidInputError(name, getattr(self, name), "(min, max) with 0 < min <= max")


@dataclass
class Scene:
    """One random scene.

    Attributes:
        seed: the seed it was drawn from.
        waypoints: (n, 2) path waypoints [m], the first at the origin.
        obstacles: the obstacle JSON items (docs/formats.md).
        kinds: each obstacle's kind (:data:`OBSTACLE_KINDS`).
        path: the spline through ``waypoints``.
    """

    seed: int
    waypoints: np.ndarray
    obstacles: list[dict[str, Any]]
    kinds: list[str]
    path: SplinePath = field(repr=False)

    @property
    def length(self) -> float:
        """Path length [m]."""
        return float(self.path.length)


def _waypoints(rng: np.random.Generator, spec: SceneSpec) -> tuple[np.ndarray, SplinePath]:
    """Waypoints of a path of ``spec.length`` from the origin heading +x (the first segment straight)."""
    seg = spec.length / spec.n_waypoints
    heading, pts = 0.0, [np.zeros(2), np.array([seg, 0.0])]
    for _ in range(spec.n_waypoints - 1):
        heading += rng.uniform(-spec.max_turn, spec.max_turn)
        pts.append(pts[-1] + seg * np.array([math.cos(heading), math.sin(heading)]))
    w = np.array(pts)
    w *= spec.length / SplinePath(w).length  # the spline scales with its waypoints: exactly the length
    return w, SplinePath(w)


def _normal(path: SplinePath, s: float) -> np.ndarray:
    t = path.tangent(s)
    return np.array([-t[1], t[0]]) / np.linalg.norm(t)


def _obstacle(rng: np.random.Generator, spec: SceneSpec, path: SplinePath, kind: str) -> dict[str, Any]:
    """One obstacle item of ``kind``."""
    L, c = path.length, spec.clear_start
    r = round(float(rng.uniform(*spec.radius)), 3)
    if kind == "ahead":
        return {"shape": "circle", "radius": r, "s0": round(float(rng.uniform(c + 1.0, 0.5 * L)), 3),
                "speed": round(float(rng.uniform(*spec.ahead_speed)), 3)}
    if kind == "oncoming":
        return {"shape": "circle", "radius": r, "s0": round(float(rng.uniform(0.5 * L, L - c)), 3),
                "speed": -round(float(rng.uniform(*spec.oncoming_speed)), 3)}
    s = float(rng.uniform(c + 1.0, L - c))
    p, n = path.position(s), _normal(path, s)
    if kind == "static":
        q = p + n * rng.uniform(-spec.static_offset, spec.static_offset)
        return {"shape": "circle", "radius": r, "position": [round(float(q[0]), 3), round(float(q[1]), 3)],
                "velocity": [0.0, 0.0]}
    speed = float(rng.uniform(*spec.crossing_speed))
    side = 1.0 if rng.uniform() < 0.5 else -1.0  # which side it comes from
    t_cross = s / spec.robot_speed * rng.uniform(0.8, 1.2)  # about when the robot gets there
    vel = -side * speed * n
    q = p - vel * t_cross
    return {"shape": "circle", "radius": r, "position": [round(float(q[0]), 3), round(float(q[1]), 3)],
            "velocity": [round(float(vel[0]), 3), round(float(vel[1]), 3)]}


def _valid(item: dict[str, Any], path: SplinePath, spec: SceneSpec) -> bool:
    """The obstacle is clear of the start at t = 0 and of the path's last ``clear_start`` metres for good."""
    if "position" not in item:
        return True  # along the path: s0 drawn away from both ends
    q = np.array(item["position"], dtype=float)
    v = np.array(item["velocity"], dtype=float)
    if np.linalg.norm(q) < spec.clear_start + item["radius"]:
        return False
    if np.any(v):
        return True  # a crossing obstacle passes: it only must not start on the robot
    end = path.position(np.linspace(path.length - spec.clear_start, path.length, 20))
    return bool(np.min(np.linalg.norm(end - q, axis=1)) > spec.clear_start)


def make_scene(seed: int, spec: SceneSpec | None = None) -> Scene:
    """The scene of ``seed`` (a non-negative integer): the same seed and spec give the same scene."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InvalidInputError("seed", seed, "a non-negative integer")
    spec = spec if spec is not None else SceneSpec()
    if not isinstance(spec, SceneSpec):
        raise InvalidInputError("spec", spec, "a lipmpcc.course.scenes.SceneSpec or None")
    rng = np.random.default_rng(int(seed))
    w, path = _waypoints(rng, spec)
    n = int(rng.integers(spec.n_obstacles[0], spec.n_obstacles[1] + 1))
    items, kinds = [], []
    while len(items) < n:
        kind = str(spec.kinds[int(rng.integers(len(spec.kinds)))])
        item = _obstacle(rng, spec, path, kind)
        if _valid(item, path, spec):
            items.append(item)
            kinds.append(kind)
    return Scene(int(seed), w, items, kinds, path)


def write_scene(scene: Scene, folder: str | FsPath) -> tuple[FsPath, FsPath]:
    """Write ``scene`` as ``folder/scene_SEED.csv`` (waypoints x,y) and ``folder/scene_SEED.json`` (obstacles,
    with the kinds as a comment line); returns the two paths."""
    folder = FsPath(folder)
    folder.mkdir(parents=True, exist_ok=True)
    csv = folder / f"scene_{scene.seed}.csv"
    js = folder / f"scene_{scene.seed}.json"
    rows = "\n".join(f"{x!r},{y!r}" for x, y in scene.waypoints.tolist())
    csv.write_text(f"# lipmpcc random scene {scene.seed} (lipmpcc.course.scenes)\nx,y\n{rows}\n")
    js.write_text(f"# lipmpcc random scene {scene.seed}: kinds {', '.join(scene.kinds)}\n"
                  + json.dumps(scene.obstacles, indent=1) + "\n")
    return csv, js


# ---- the benchmark ----------------------------------------------------------------------------------
#: the planner variants: label -> step-duration range (None: paper A's fixed T)
PLANNERS: dict[str, tuple[float, float] | None] = {"fixed T": None, "timed": (0.3, 0.5)}
#: the weights: label -> the study whose preset is used
WEIGHTS: dict[str, str] = {"follow-path": "follow-path", "overtake": "overtake"}
#: [m] how far behind an obstacle moving along the path a robot that did not reach the end counts as trailing it
TRAILING_GAP = 2.0


@dataclass
class SceneRun:
    """One scene run and its judgement.

    Attributes:
        seed, robot, planner, weights: what ran.
        kinds: the scene's obstacle kinds.
        summary: the run's ``summary.json`` content.
        success: reached the end or trailed a slower obstacle, without contact.
        reason: ``"ok"``, ``"trailing"``, or why not (``collided``, ``fell``, ``stalled at x m of L m``).
    """

    seed: int
    robot: str
    planner: str
    weights: str
    kinds: list[str]
    summary: dict[str, Any]
    success: bool
    reason: str


def reached_end(summary: dict[str, Any], path_length: float) -> bool:
    """``summary["reached_end"]`` where the run reports it; else the end was reached when the run stopped
    there (``stopped_reason == "end of path"``) or its progress is within 0.3 m of ``path_length`` [m]."""
    if "reached_end" in summary:
        return bool(summary["reached_end"])
    return summary.get("stopped_reason") == "end of path" or float(summary.get("progress_m") or 0.0) >= path_length - 0.3


def trailing(summary: dict[str, Any], scene: Scene) -> bool:
    """``summary["outcome"] == "trailing"`` where the run reports its outcome as such; else the robot ended at
    most :data:`TRAILING_GAP` behind an obstacle that moves forward along the path."""
    if summary.get("outcome") == "trailing":
        return True
    if "reached_end" in summary:  # the honest outcome fields are there: trust them
        return False
    prog, t_end = float(summary.get("progress_m") or 0.0), float(summary.get("duration_s") or 0.0)
    for item in scene.obstacles:
        if item.get("speed", 0.0) > 0.0:
            s_ob = min(item["s0"] + item["speed"] * t_end, scene.length)
            if 0.0 <= s_ob - prog <= TRAILING_GAP:
                return True
    return False


def judge(summary: dict[str, Any], scene: Scene) -> tuple[bool, str]:
    """(success, reason): success is (the end reached or a slower obstacle trailed) and no contact.

    The reason of a failure says what and where: ``fell at t s, x m of L m`` (and ``after reaching the end``
    when it had), ``collided (clearance c m)``, or the run's own outcome where its summary has one
    (``stalled``, with what was binding, ``incomplete``: the run's duration or steps ran out while it still
    progressed, ``stopped_early``), else ``stalled``, ``at x m of L m``."""
    prog = float(summary.get("progress_m") or 0.0)
    where = f"{prog:.2f} m of {scene.length:.2f} m"
    if summary.get("fell"):
        t_fall = summary.get("fall_time_s")
        when = f" at {float(t_fall):.1f} s," if t_fall is not None else " at"
        return False, f"fell{when} {where}" + (" after reaching the end" if summary.get("reached_end") else "")
    clear = summary.get("min_body_clearance_m")
    clear = summary.get("min_clearance_m") if clear is None else clear
    if summary.get("collided") or (clear is not None and clear < 0.0):
        return False, f"collided (clearance {clear:.3f} m)"
    if reached_end(summary, scene.length):
        return True, "ok"
    if trailing(summary, scene):
        return True, "trailing"
    out = summary.get("outcome")
    word = out if out in ("stalled", "incomplete", "stopped_early") else "stalled"
    binding = ((summary.get("stall") or {}).get("binding") or {}).get("kind") if word == "stalled" else None
    return False, f"{word} at {where}" + (f" (binding: {binding})" if binding else "")


def run_scene(scene: Scene, robot: str = "lip", planner: str = "fixed T", weights: str = "follow-path",
              folder: str | FsPath | None = None, save_failures: bool = False) -> SceneRun:
    """Run ``scene`` on ``robot`` (``"lip"`` or a full body such as ``"digit_like"``) with the MPCC,
    ``planner`` in :data:`PLANNERS`, ``weights`` in :data:`WEIGHTS` (``follow-path``: paper A's contouring
    weights; ``overtake``: its overtaking weights), through :func:`lipmpcc.studies.run` — the code path of
    ``lipmpcc run follow-path --path P.csv --obstacles O.json`` — with the scene's files written to
    ``folder`` (None: a temporary folder), and follow-path's budget (:func:`~lipmpcc.studies.path_following.
    follow_path_steps` on the LIP, :func:`~lipmpcc.studies.path_scenarios.follow_path_duration` on a full body)
    whatever the weights. With ``save_failures`` and a ``folder``, a run that does not succeed
    is saved whole (its figure and ``summary.json``) in ``folder/SEED-ROBOT-PLANNER-WEIGHTS/``."""
    import tempfile

    import matplotlib.pyplot as plt

    from .. import studies
    from ..studies import path_scenarios as pf
    from ..studies.options import RunOptions

    if planner not in PLANNERS:
        raise InvalidInputError("planner", planner, f"one of {list(PLANNERS)}")
    if weights not in WEIGHTS:
        raise InvalidInputError("weights", weights, f"one of {list(WEIGHTS)}")
    with tempfile.TemporaryDirectory() as tmp:
        csv, js = write_scene(scene, folder if folder is not None else tmp)
        # the same budget for both weights: follow-path's (the overtake study's own is shorter)
        budget = {"steps": pf.follow_path_steps(scene.length)} if robot == "lip" else \
            {"duration": pf.follow_path_duration(scene.length)}
        opts = RunOptions(scenario=WEIGHTS[weights], planner="mpcc", robot=robot, path=str(csv), obstacles=str(js),
                          step_duration_range=PLANNERS[planner], out=str(tmp), **budget)
        result = studies.run(opts)
    summary = json.loads(json.dumps(result.summary, default=_jsonable))
    ok, why = judge(summary, scene)
    if save_failures and folder is not None and not ok:
        result.save(FsPath(folder) / f"{scene.seed}-{robot}-{planner.replace(' ', '')}-{weights}")
    for fig in result.figures.values():
        plt.close(fig)
    return SceneRun(scene.seed, robot, planner, weights, list(scene.kinds), summary, ok, why)


def _jsonable(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    return str(v)


def success_table(runs: Sequence[SceneRun]) -> list[dict[str, Any]]:
    """Per (robot, planner, weights, kind) — a scene counts for every kind it holds — and ``all``: the runs,
    successes, rate and its 95 % Wilson interval."""
    groups: dict[tuple[str, str, str, str], list[bool]] = {}
    for r in runs:
        for kind in sorted(set(r.kinds)) + ["all"]:
            groups.setdefault((r.robot, r.planner, r.weights, kind), []).append(r.success)
    rows = []
    for (robot, planner, weights, kind), oks in sorted(groups.items()):
        k, n = sum(oks), len(oks)
        lo, hi = wilson_interval(k, n)
        rows.append({"robot": robot, "planner": planner, "weights": weights, "kind": kind, "n": n, "ok": k,
                     "rate": k / n, "wilson_lo": lo, "wilson_hi": hi})
    return rows


def _quantiles(values: Sequence[float]) -> str:
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)], dtype=float)
    if not len(v):
        return "none"
    q = np.percentile(v, [0, 10, 50, 90, 100])
    return f"min {q[0]:.3g}, p10 {q[1]:.3g}, median {q[2]:.3g}, p90 {q[3]:.3g}, max {q[4]:.3g} (n = {len(v)})"


def benchmark_report(runs: Sequence[SceneRun]) -> str:
    """A markdown report of scene runs: the success rate per (robot, planner, weights) and obstacle kind with
    95 % Wilson intervals, every failure with its reason, and the distributions of the solve times (each run's
    median and p90 [ms]) and of the clearance (each run's smallest, [m])."""
    lines = ["| robot | planner | weights | kind | ok / n | rate | 95 % Wilson |", "|---|---|---|---|---|---|---|"]
    for r in success_table(runs):
        lines.append(f"| {r['robot']} | {r['planner']} | {r['weights']} | {r['kind']} | {r['ok']} / {r['n']} | "
                     f"{100 * r['rate']:.0f} % | {100 * r['wilson_lo']:.0f}–{100 * r['wilson_hi']:.0f} % |")
    fails = [r for r in runs if not r.success]
    lines += ["", f"Failures ({len(fails)}):"]
    lines += [f"- seed {r.seed} ({', '.join(r.kinds)}), {r.robot}, {r.planner}, {r.weights}: {r.reason}" for r in fails]
    groups: dict[tuple[str, str, str], list[SceneRun]] = {}
    for r in runs:
        groups.setdefault((r.robot, r.planner, r.weights), []).append(r)
    lines += ["", "Distributions per (robot, planner, weights):"]
    for key, rs in sorted(groups.items()):
        med = [(r.summary.get("solve_ms") or {}).get("median") for r in rs]
        p90 = [(r.summary.get("solve_ms") or {}).get("p90") for r in rs]
        body = [r.summary.get("min_body_clearance_m") for r in rs]
        clear = [b if b is not None else r.summary.get("min_clearance_m") for b, r in zip(body, rs)]
        lines += [f"- {' / '.join(key)}: solve median [ms] {_quantiles(med)}; solve p90 [ms] {_quantiles(p90)}; "
                  f"clearance [m] {_quantiles(clear)}"]
    return "\n".join(lines) + "\n"
