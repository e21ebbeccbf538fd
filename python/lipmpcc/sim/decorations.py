"""Scene decorations of a full-body run: the reference path, the obstacles, the footholds (planned and
landed) and the push, drawn into a MuJoCo scene (``mujoco.MjvScene``) from plain arrays.

One function, :func:`draw_decorations`, serves the live viewer (``viewer.user_scn``), the replay and
the videos (the offscreen renderer's scene after ``update_scene``): the three show the same things.
The model has none of them; they are drawn as extra geoms, up to the scene's ``maxgeom``.

Colours: the path red on the floor, obstacles grey cylinders (circles) or ellipsoids, landed footholds
blue (left) and orange (right), the current planned foothold green and its preview pale green, the push
a yellow arrow at the torso pointing along the force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InvalidInputError

__all__ = ["SceneDecorations", "draw_decorations", "PATH_RADIUS", "NEAR_RADIUS", "PATH_SAMPLE_M"]

#: spacing of the points a path is drawn through (and saved with, in a replay) [m]
PATH_SAMPLE_M = 0.1
#: half-width of the path's capsules [m]
PATH_RADIUS = 0.012
#: only path segments within this distance of the robot are drawn [m] (keeps the geom count low)
NEAR_RADIUS = 4.0

_RED = np.array([0.85, 0.1, 0.1, 1.0], dtype=np.float32)
_GREY = np.array([0.45, 0.45, 0.5, 0.75], dtype=np.float32)
_LEFT = np.array([0.15, 0.35, 0.9, 0.9], dtype=np.float32)
_RIGHT = np.array([0.95, 0.55, 0.1, 0.9], dtype=np.float32)
_PLAN = np.array([0.1, 0.8, 0.2, 0.9], dtype=np.float32)
_PREVIEW = np.array([0.55, 0.9, 0.55, 0.6], dtype=np.float32)
_PUSH = np.array([1.0, 0.85, 0.0, 1.0], dtype=np.float32)
_EYE = np.eye(3).reshape(-1)


def _rows(name: str, value: object, width: int) -> np.ndarray:
    """``value`` as a finite (k, width) float array ((0, width) for None)."""
    arr = np.zeros((0, width)) if value is None else np.asarray(value, dtype=float)
    if arr.size == 0:
        return np.zeros((0, width))
    if arr.ndim != 2 or arr.shape[1] != width or not np.all(np.isfinite(arr)):
        raise InvalidInputError(name, f"array of shape {arr.shape}", f"a finite (k, {width}) array")
    return arr


@dataclass(frozen=True)
class SceneDecorations:
    """What to draw at one moment, in the world frame.

    Attributes:
        path_xy: (k, 2) points of the reference path [m] (drawn as a polyline on the floor).
        obstacles: (n, 6) rows (x, y, semi-axis a, semi-axis b, heading, is_circle) [m, m, m, m, rad, -].
        landed: (k, 3) rows (x, y, side) of the touch-downs so far [m, m, -] (side 0 left, 1 right).
        planned: (k, 2) the planned footholds [m]: the current plan first, then its preview.
        push: None, or (6,) (x, y, z of the point pushed [m], F_x, F_y, F_z [N]) while a push acts.
        ground_z: height of the floor the marks are drawn on [m].
        near_xy: draw only path segments within :data:`NEAR_RADIUS` of this point [m] (None: all).
    """

    path_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    obstacles: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))
    landed: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    planned: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    push: np.ndarray | None = None
    ground_z: float = 0.0
    near_xy: np.ndarray | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "path_xy", _rows("path_xy", self.path_xy, 2))
        object.__setattr__(self, "obstacles", _rows("obstacles", self.obstacles, 6))
        object.__setattr__(self, "landed", _rows("landed", self.landed, 3))
        object.__setattr__(self, "planned", _rows("planned", self.planned, 2))
        if self.push is not None:
            object.__setattr__(self, "push", _rows("push", np.reshape(self.push, (1, -1)), 6)[0])
        if self.near_xy is not None:
            object.__setattr__(self, "near_xy", _rows("near_xy", np.reshape(self.near_xy, (1, -1))[:, :2], 2)[0])


def _room(scene: object) -> bool:
    return scene.ngeom < scene.maxgeom  # type: ignore[attr-defined]


def _add(scene: object, kind: int, size: np.ndarray, pos: np.ndarray, mat: np.ndarray, rgba: np.ndarray) -> object:
    import mujoco

    g = scene.geoms[scene.ngeom]  # type: ignore[attr-defined]
    mujoco.mjv_initGeom(g, kind, np.asarray(size, dtype=float), np.asarray(pos, dtype=float), mat, rgba)
    scene.ngeom += 1  # type: ignore[attr-defined]
    return g


def _connector(scene: object, kind: int, width: float, a: np.ndarray, b: np.ndarray, rgba: np.ndarray) -> None:
    import mujoco

    g = scene.geoms[scene.ngeom]  # type: ignore[attr-defined]
    mujoco.mjv_initGeom(g, kind, np.zeros(3), np.zeros(3), _EYE, rgba)
    mujoco.mjv_connector(g, kind, width, np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    scene.ngeom += 1  # type: ignore[attr-defined]


def _draw_path(scene: object, deco: SceneDecorations) -> None:
    import mujoco

    pts = deco.path_xy
    if len(pts) < 2:
        return
    near = np.ones(len(pts), dtype=bool) if deco.near_xy is None else np.linalg.norm(pts - deco.near_xy, axis=1) < NEAR_RADIUS
    z = deco.ground_z + 0.005
    for a, b, ok in zip(pts[:-1], pts[1:], near[:-1] & near[1:]):
        if ok and _room(scene):
            _connector(scene, mujoco.mjtGeom.mjGEOM_CAPSULE, PATH_RADIUS, np.r_[a, z], np.r_[b, z], _RED)


def _draw_obstacles(scene: object, deco: SceneDecorations) -> None:
    import mujoco

    for x, y, a, b, psi, circle in deco.obstacles:
        if not _room(scene):
            return
        c, s = math.cos(psi), math.sin(psi)
        mat = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).reshape(-1)
        if circle:  # a cylinder's size: (radius, half-height, -)
            _add(scene, mujoco.mjtGeom.mjGEOM_CYLINDER, np.array([a, 0.5, 0.0]), np.array([x, y, deco.ground_z + 0.5]),
                 mat, _GREY)
        else:  # an ellipsoid's: its three semi-axes
            _add(scene, mujoco.mjtGeom.mjGEOM_ELLIPSOID, np.array([a, b, 0.5]), np.array([x, y, deco.ground_z + 0.5]),
                 mat, _GREY)


def _draw_footholds(scene: object, deco: SceneDecorations) -> None:
    import mujoco

    disc = mujoco.mjtGeom.mjGEOM_CYLINDER
    z = deco.ground_z + 0.004
    for x, y, side in deco.landed:
        if _room(scene):
            _add(scene, disc, np.array([0.05, 0.003, 0.0]), np.array([x, y, z]), _EYE, _LEFT if side < 0.5 else _RIGHT)
    for i, (x, y) in enumerate(deco.planned):
        if _room(scene):
            size = np.array([0.07, 0.004, 0.0]) if i == 0 else np.array([0.04, 0.004, 0.0])  # (radius, half-height)
            _add(scene, disc, size, np.array([x, y, z + 0.002]), _EYE, _PLAN if i == 0 else _PREVIEW)


def _draw_push(scene: object, deco: SceneDecorations) -> None:
    import mujoco

    if deco.push is None or not _room(scene):
        return
    at, force = deco.push[:3], deco.push[3:]
    norm = float(np.linalg.norm(force))
    if norm <= 0.0:
        return
    length = min(0.8, 0.2 + norm / 200.0)  # [m]: 50 N -> 0.45 m
    tail = at - force / norm * length
    _connector(scene, mujoco.mjtGeom.mjGEOM_ARROW, 0.03, tail, at, _PUSH)


def draw_decorations(scene: object, deco: SceneDecorations) -> int:
    """Append ``deco``'s geoms to ``scene`` (a ``mujoco.MjvScene``: the live viewer's ``user_scn``,
    cleared by the caller, or a renderer's scene after ``update_scene``), up to its ``maxgeom``.

    Returns:
        The number of geoms added.
    """
    if not isinstance(deco, SceneDecorations):
        raise InvalidInputError("deco", deco, "a lipmpcc.sim.decorations.SceneDecorations")
    n0 = int(scene.ngeom)  # type: ignore[attr-defined]
    _draw_path(scene, deco)
    _draw_obstacles(scene, deco)
    _draw_footholds(scene, deco)
    _draw_push(scene, deco)
    return int(scene.ngeom) - n0  # type: ignore[attr-defined]
