"""A stone field: more stones than steps, scattered in a corridor around a path, and pedestrians.

Beyond both papers (issue 29): paper B lands each foot on the stone it is given, in order; here the
planner chooses. A :class:`StoneField` holds

- ``stones``: axis-aligned rectangles (centres and full sizes [m], world frame) a foot may land on;
- ``path``: a polyline of waypoints [m] (x strictly increasing) from the robot's entry onto the field
  to its end; the **corridor** is the band within ``corridor_width / 2`` of it;
- ``goal``: the solid ground after the field (a rectangle around the path's end): a foothold inside
  it reaches the end of the path;
- ``pedestrians``: circles moving with constant velocity (:class:`~lipmpcc.obstacles.Obstacle`),
  their clock the run's time [s] (t = 0 when the robot starts standing at the origin).

The robot starts at the origin and walks paper B's approach (:func:`lipmpcc.terrain.approach_footholds`)
on solid ground to :func:`lipmpcc.terrain.entry_foothold` (1.05, 0.14) m, where the path starts.

:func:`make_stone_field` draws a field from a seed: a **backbone** of stones that crosses it (step
lengths ``size_x + gap``, gaps U[0, ``max_gap``] along the path, alternating feet about the path, 0.16 to
0.42 m across from one to the next, so a way always exists) and **distractors** scattered uniformly in the corridor up to ``density`` stones
per m², never overlapping; with ``pedestrian_speed`` a pedestrian crosses the corridor at that speed,
timed to meet a robot walking at 0.6 m/s mid-field (give or take a second).

Files (:func:`save_stone_field`, :func:`load_stone_field`): JSON, documented in docs/formats.md.
A bad field (a stone off the corridor, two overlapping stones, a path going backwards, NaN) is
refused with a :class:`~lipmpcc.exceptions.TerrainError` naming the stone or the value.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .exceptions import InvalidInputError, TerrainError
from .obstacles import Obstacle
from .terrain import MAX_STONE_SIZE, STEP_WIDTH, STONE_SIZE, Stone, entry_foothold
from .validation import count, finite_array, number_in, read_text_file

__all__ = [
    "FIELD_FORMAT",
    "PEDESTRIAN_RADIUS",
    "StoneField",
    "make_stone_field",
    "save_stone_field",
    "load_stone_field",
    "field_to_dict",
    "field_from_dict",
]

#: the ``format`` tag of a stone-field JSON file
FIELD_FORMAT = "lipmpcc-stone-field"
#: radius of a generated pedestrian [m] (a person's shoulders)
PEDESTRIAN_RADIUS = 0.25
#: the least clearance between two generated stones [m]
_STONE_CLEARANCE = 0.05
#: the lateral distance between consecutive backbone stones [m] (within the kinematic 0.1-0.5 m, with a margin)
_BACKBONE_DY = (0.16, 0.42)
#: the walking speed a generated pedestrian is timed against [m/s], and the approach's duration [s]
_TIMING_SPEED, _APPROACH_TIME = 0.6, 3.0


def _rects_overlap(c1: np.ndarray, s1: np.ndarray, c2: np.ndarray, s2: np.ndarray, gap: float = 0.0) -> bool:
    """True when two axis-aligned rectangles come closer than ``gap`` [m] (touching at gap 0 is not overlap)."""
    d = np.abs(c1 - c2) - 0.5 * (s1 + s2)
    return bool(np.all(d < gap - 1e-12))


@dataclass(frozen=True)
class StoneField:
    """A field of stones around a path (see the module docstring).

    Attributes:
        centers: (n, 2) stone centres [m].
        sizes: (n, 2) full stone sizes (size_x, size_y) [m], each in (0, 10].
        path: (m, 2) waypoints [m], m >= 2, x strictly increasing.
        corridor_width: full width of the corridor around the path [m]; every stone centre lies in it.
        goal_center, goal_size: the goal rectangle (solid ground at the path's end) [m].
        pedestrians: moving circles (constant velocity) [m, m/s].
        seed: the generator's seed (None for a hand-made field).
        name: a label.
    """

    centers: np.ndarray
    sizes: np.ndarray
    path: np.ndarray
    corridor_width: float
    goal_center: tuple[float, float]
    goal_size: tuple[float, float]
    pedestrians: tuple[Obstacle, ...] = ()
    seed: int | None = None
    name: str = "stone field"
    meta: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        c = finite_array("centers", self.centers, (None, 2), "m", error=TerrainError, what="(n, 2) stone centres")
        s = finite_array("sizes", self.sizes, (None, 2), "m", error=TerrainError, what="(n, 2) stone sizes")
        if len(c) != len(s) or len(c) == 0:
            raise TerrainError("sizes", (len(c), len(s)), "one size per stone and at least one stone")
        bad = np.flatnonzero(np.any((s <= 0) | (s > MAX_STONE_SIZE), axis=1))
        if bad.size:
            raise TerrainError(f"stone {int(bad[0])} size", s[bad[0]].tolist(), f"sizes > 0 and <= {MAX_STONE_SIZE:g} [m]")
        p = finite_array("path", self.path, (None, 2), "m", error=TerrainError, what="(m, 2) waypoints")
        if len(p) < 2 or np.any(np.diff(p[:, 0]) <= 0):
            raise TerrainError("path", p.tolist(), "at least 2 waypoints [m] with x strictly increasing")
        width = number_in("corridor_width", self.corridor_width, 0.0, 20.0, "m", lo_open=True, error=TerrainError)
        gc = finite_array("goal_center", self.goal_center, (2,), "m", error=TerrainError)
        gs = finite_array("goal_size", self.goal_size, (2,), "m", error=TerrainError)
        if np.any(gs <= 0) or np.any(gs > MAX_STONE_SIZE):
            raise TerrainError("goal_size", gs.tolist(), f"sizes > 0 and <= {MAX_STONE_SIZE:g} [m]")
        peds = tuple(self.pedestrians)
        for i, ob in enumerate(peds):
            if not isinstance(ob, Obstacle) or not ob.is_circle or ob.path is not None:
                raise TerrainError(f"pedestrians[{i}]", ob, "a circular Obstacle moving with a constant velocity")
        if self.seed is not None:
            count("seed", self.seed, 0, error=TerrainError)
        for name, value in (("centers", c), ("sizes", s), ("path", p)):
            value = np.array(value, dtype=float)
            value.flags.writeable = False
            object.__setattr__(self, name, value)
        object.__setattr__(self, "corridor_width", width)
        object.__setattr__(self, "goal_center", (float(gc[0]), float(gc[1])))
        object.__setattr__(self, "goal_size", (float(gs[0]), float(gs[1])))
        object.__setattr__(self, "pedestrians", peds)
        self._check_layout()

    def _check_layout(self) -> None:
        """Every stone in the corridor, no two stones overlapping, none overlapping the goal."""
        d = self.lateral_offset(self.centers)
        off = np.flatnonzero(np.abs(d) > 0.5 * self.corridor_width + 1e-9)
        if off.size:
            i = int(off[0])
            raise TerrainError(f"stone {i}", self.centers[i].tolist(),
                               f"a centre within the corridor, |offset from the path| <= {0.5 * self.corridor_width:g} m",
                               f"it is {abs(d[i]):.3f} m off the path")
        c, s = self.centers, self.sizes
        for i in range(len(c)):
            near = np.flatnonzero(np.all(np.abs(c[i + 1:] - c[i]) - 0.5 * (s[i + 1:] + s[i]) < -1e-9, axis=1))
            if near.size:
                j = i + 1 + int(near[0])
                raise TerrainError(f"stone {j}", c[j].tolist(), f"a stone apart from stone {i} at {c[i].tolist()}",
                                   "the two stones overlap")
            if _rects_overlap(c[i], s[i], np.asarray(self.goal_center), np.asarray(self.goal_size)):
                raise TerrainError(f"stone {i}", c[i].tolist(), "a stone outside the goal rectangle")

    # ---- geometry ------------------------------------------------------------------------------
    @property
    def n_stones(self) -> int:
        """Number of stones."""
        return len(self.centers)

    @property
    def goal(self) -> Stone:
        """The goal rectangle as a :class:`~lipmpcc.terrain.Stone`."""
        return Stone(self.goal_center, self.goal_size)

    def stone(self, i: int) -> Stone:
        """Stone ``i`` as a :class:`~lipmpcc.terrain.Stone`."""
        return Stone(tuple(self.centers[i]), tuple(self.sizes[i]))  # type: ignore[arg-type]

    @property
    def path_length(self) -> float:
        """Arc length of the path [m]."""
        return float(np.sum(np.linalg.norm(np.diff(self.path, axis=0), axis=1)))

    def path_y(self, x: float | np.ndarray) -> np.ndarray:
        """The path's y at ``x`` [m] (held constant beyond its ends)."""
        return np.interp(x, self.path[:, 0], self.path[:, 1])

    def lateral_offset(self, points: np.ndarray) -> np.ndarray:
        """Signed distance [m] of points (n, 2) from the path polyline (positive to its left)."""
        q = np.atleast_2d(np.asarray(points, dtype=float))
        a, b = self.path[:-1], self.path[1:]
        ab = b - a
        t = np.clip(np.einsum("nsk,sk->ns", q[:, None, :] - a[None], ab) / np.sum(ab * ab, axis=1), 0.0, 1.0)
        foot = a[None] + t[..., None] * ab[None]
        dist = np.linalg.norm(q[:, None, :] - foot, axis=2)
        k = np.argmin(dist, axis=1)
        rel = q - foot[np.arange(len(q)), k]
        cross = ab[k, 0] * rel[:, 1] - ab[k, 1] * rel[:, 0]
        return np.where(cross >= 0, 1.0, -1.0) * dist[np.arange(len(q)), k]

    def stone_at(self, p: Sequence[float], tol: float = 1e-6) -> int | None:
        """Index of the stone holding the point ``p`` [m] (None when there is none)."""
        q = np.asarray(p, dtype=float)
        inside = np.all(np.abs(self.centers - q) <= 0.5 * self.sizes + tol, axis=1)
        hits = np.flatnonzero(inside)
        return int(hits[0]) if hits.size else None

    def in_goal(self, p: Sequence[float], tol: float = 1e-6) -> bool:
        """True when the point ``p`` [m] is in the goal rectangle."""
        return self.goal.contains(p, tol)


# ----------------------------------------------------------------------------- generator
def _check_generator_args(length: float, corridor_width: float, stone_size: Sequence[float], max_gap: float,
                          density: float, bend: float, pedestrian_speed: float | None) -> tuple[float, ...]:
    L = number_in("length", length, 1.0, 50.0, "m", error=InvalidInputError)
    W = number_in("corridor_width", corridor_width, 0.6, 10.0, "m", error=InvalidInputError)
    sz = finite_array("stone_size", stone_size, (2,), "m", error=InvalidInputError, what="(size_x, size_y)")
    if not (0.05 <= sz[0] <= 0.5 and 0.05 <= sz[1] <= 0.5):
        raise InvalidInputError("stone_size", tuple(stone_size), "(size_x, size_y) each in [0.05, 0.5] m")
    g = number_in("max_gap", max_gap, 0.0, 0.6 - sz[0], "m", error=InvalidInputError,
                  detail="a step is size_x + gap and the kinematic limit is 0.6 m")
    rho = number_in("density", density, 0.0, 20.0, "stones/m²", error=InvalidInputError)
    b = number_in("bend", bend, 0.0, 0.2 * L, "m", error=InvalidInputError, detail="at most a fifth of the length")
    v = math.nan if pedestrian_speed is None else number_in(
        "pedestrian_speed", pedestrian_speed, 0.0, 3.0, "m/s", lo_open=True, error=InvalidInputError)
    return L, W, float(sz[0]), float(sz[1]), g, rho, b, v


def make_stone_field(
    seed: int = 0,
    length: float = 4.0,
    corridor_width: float = 1.5,
    stone_size: Sequence[float] = STONE_SIZE,
    max_gap: float = 0.3,
    density: float = 4.0,
    bend: float = 0.3,
    pedestrian_speed: float | None = None,
    w: float = STEP_WIDTH,
) -> StoneField:
    """A seeded random stone field (see the module docstring); the same arguments give the same field.

    Args:
        seed: random seed (an integer >= 0).
        length: length of the field along x [m].
        corridor_width: full width of the corridor [m].
        stone_size: (size_x, size_y) of every stone [m] (issue 29: 0.2 x 0.1).
        max_gap: largest gap between consecutive backbone stones along the path [m].
        density: stones per m² of the corridor, backbone included (the distractors fill up to it).
        bend: largest lateral offset of the path's middle waypoint [m] (the end's is half of it).
        pedestrian_speed: speed of a pedestrian crossing the corridor [m/s]; None: no pedestrian.
        w: nominal step width [m].

    Raises:
        InvalidInputError: an argument out of its range (the message names it and the range).
    """
    seed = count("seed", seed, 0)
    L, W, sx, sy, gmax, rho, b, v = _check_generator_args(length, corridor_width, stone_size, max_gap, density,
                                                          bend, pedestrian_speed)
    rng = np.random.default_rng(seed)
    x0, y0 = entry_foothold(w)
    y0 = 0.0  # the path starts between the feet
    path = np.array([[x0, y0], [x0 + 0.5 * L, rng.uniform(-b, b)], [x0 + L, rng.uniform(-0.5 * b, 0.5 * b)]])
    centers: list[np.ndarray] = []
    x, side = x0, -1  # the approach ends on the left foot: the right foot enters the field
    y_prev = float(entry_foothold(w)[1])
    while True:
        x_next = x + sx + rng.uniform(0.0, gmax)
        if x_next + 0.5 * sx > x0 + L:
            break
        y = float(np.interp(x_next, path[:, 0], path[:, 1])) + side * 0.5 * w + rng.uniform(-0.05, 0.05)
        lo, hi = sorted((y_prev + side * _BACKBONE_DY[0], y_prev + side * _BACKBONE_DY[1]))
        y = min(max(y, lo), hi)  # a step across the feet's comfortable range, whatever the bend
        centers.append(np.array([x_next, y]))
        x, y_prev, side = x_next, y, -side
    n_backbone = len(centers)
    x_goal = x + 0.5 * sx + rng.uniform(0.05, max(gmax, 0.05))
    goal_size = (0.6, W)
    goal_center = (x_goal + 0.3, float(np.interp(x_goal, path[:, 0], path[:, 1])))
    path[-1] = [x_goal, goal_center[1]]
    if path[1, 0] >= path[2, 0]:
        path = path[[0, 2]]
    size = np.array([sx, sy])
    n_total = int(round(rho * (x_goal - x0) * W))
    tries = 0
    while len(centers) < n_total and tries < 200 * max(n_total, 1):
        tries += 1
        cx = rng.uniform(x0 + 0.5 * sx, x_goal - 0.5 * sx)
        cy = float(np.interp(cx, path[:, 0], path[:, 1])) + rng.uniform(-0.5 * W, 0.5 * W)
        c = np.array([cx, cy])
        if abs(cy - float(np.interp(cx, path[:, 0], path[:, 1]))) > 0.5 * W * 0.98:
            continue
        if all(not _rects_overlap(c, size, q, size, _STONE_CLEARANCE) for q in centers):
            centers.append(c)
    peds: tuple[Obstacle, ...] = ()
    meta: dict[str, Any] = {"length": L, "max_gap": gmax, "density": rho, "n_backbone": n_backbone}
    if not math.isnan(v):
        xc = rng.uniform(x0 + 0.25 * L, x0 + 0.75 * L)
        yc = float(np.interp(xc, path[:, 0], path[:, 1]))
        t_meet = _APPROACH_TIME + (xc - x0) / _TIMING_SPEED + rng.uniform(-1.0, 1.0)
        direction = 1.0 if rng.uniform() < 0.5 else -1.0
        start = (float(xc), float(yc - direction * v * t_meet))
        peds = (Obstacle.circle(PEDESTRIAN_RADIUS, position=start, velocity=(0.0, float(direction * v))),)
        meta.update({"pedestrian_crossing_x": float(xc), "pedestrian_meet_time": float(t_meet)})
    arr = np.array(centers)
    fld = StoneField(arr, np.tile(size, (len(arr), 1)), path, W, goal_center, goal_size, peds, seed,
                     f"stone field seed {seed}" + ("" if math.isnan(v) else f", pedestrian {v:.2f} m/s"), meta)
    return fld


# ----------------------------------------------------------------------------- files
def field_to_dict(fld: StoneField) -> dict[str, Any]:
    """The JSON object of a field (docs/formats.md, "Stone-field JSON")."""
    return {
        "format": FIELD_FORMAT,
        "version": 1,
        "name": fld.name,
        "seed": fld.seed,
        "corridor_width": fld.corridor_width,
        "path": fld.path.tolist(),
        "goal": {"center": list(fld.goal_center), "size": list(fld.goal_size)},
        "stones": [[*c, *s] for c, s in zip(fld.centers.tolist(), fld.sizes.tolist())],
        "pedestrians": [{"position": list(p.position), "velocity": list(p.velocity), "radius": p.axes[0]}
                        for p in fld.pedestrians],
    }


def _item(d: dict, key: str, where: str) -> Any:
    if key not in d:
        raise TerrainError(f"{where}.{key}", None, f"a '{key}' entry (docs/formats.md, stone-field JSON)")
    return d[key]


def field_from_dict(d: object, where: str = "field") -> StoneField:
    """A :class:`StoneField` from its JSON object; a bad entry raises TerrainError naming it."""
    if not isinstance(d, dict) or d.get("format") != FIELD_FORMAT:
        raise TerrainError(f"{where}.format", d.get("format") if isinstance(d, dict) else d, f"'{FIELD_FORMAT}'")
    if d.get("version") != 1:
        raise TerrainError(f"{where}.version", d.get("version"), "1")
    rows = _item(d, "stones", where)
    if not isinstance(rows, list) or not rows or not all(isinstance(r, list) and len(r) == 4 for r in rows):
        raise TerrainError(f"{where}.stones", rows, "a non-empty list of [x, y, size_x, size_y] [m]")
    a = finite_array(f"{where}.stones", rows, (None, 4), "m", error=TerrainError)
    goal = _item(d, "goal", where)
    if not isinstance(goal, dict):
        raise TerrainError(f"{where}.goal", goal, "{'center': [x, y], 'size': [size_x, size_y]} [m]")
    peds = []
    for i, p in enumerate(d.get("pedestrians", [])):
        if not isinstance(p, dict):
            raise TerrainError(f"{where}.pedestrians[{i}]", p, "{'position': [x, y], 'velocity': [vx, vy], 'radius': r}")
        try:
            peds.append(Obstacle.circle(_item(p, "radius", f"{where}.pedestrians[{i}]"),
                                        position=_item(p, "position", f"{where}.pedestrians[{i}]"),
                                        velocity=_item(p, "velocity", f"{where}.pedestrians[{i}]")))
        except TerrainError:
            raise
        except InvalidInputError as exc:
            raise TerrainError(f"{where}.pedestrians[{i}].{exc.name}", exc.value, exc.expected) from None
    seed = d.get("seed")
    return StoneField(a[:, :2], a[:, 2:], _item(d, "path", where), _item(d, "corridor_width", where),
                      _item(goal, "center", f"{where}.goal"), _item(goal, "size", f"{where}.goal"), tuple(peds),
                      seed, str(d.get("name", "stone field")))


def save_stone_field(fld: StoneField, path: str | Path) -> Path:
    """Write ``fld`` as JSON to ``path`` (parent folders created); returns the path."""
    if not isinstance(fld, StoneField):
        raise InvalidInputError("field", fld, "a lipmpcc.stone_field.StoneField")
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(json.dumps(field_to_dict(fld), indent=1) + "\n")
    return p


def load_stone_field(path: str | Path) -> StoneField:
    """Read a stone-field JSON file (docs/formats.md); a bad file raises TerrainError naming the entry."""
    text = read_text_file("stone field", path, "a stone-field JSON file", error=TerrainError)
    try:
        d = json.loads(text)
    except json.JSONDecodeError as exc:
        raise TerrainError(f"{Path(path).name} line {exc.lineno}", exc.msg, "valid JSON") from None
    return field_from_dict(d, Path(path).name)
