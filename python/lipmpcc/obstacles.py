"""Moving obstacles: circles and ellipses, moving along the path or with a constant velocity.

Each obstacle predicts its centre at any time, which the planners sample at the
horizon's step instants (paper A eq. 17 with p_obs,k known per step). The barrier used
by the planner is

    b(p) = (p − c)ᵀ M (p − c) − 1,   M = R(ψ) diag(1/a², 1/b²) R(ψ)ᵀ

with semi-axes inflated by the robot's footprint radius and a safety margin. For a
circle this is paper A's ‖p − c‖² − r² divided by r², which leaves the CBF inequality
b(x_{k+1}) ≥ (1 − γ) b(x_k) unchanged.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import Sequence

import numpy as np

from .exceptions import ObstacleError
from .paths import MAX_PATH_COORDINATE, Path
from .validation import finite_array, finite_number, finite_vector, non_negative_number, number_in, read_text_file

__all__ = [
    "Obstacle",
    "obstacles_from_json",
    "obstacle_from_dict",
    "barrier_params",
    "MAX_OBSTACLE_SIZE",
    "MAX_OBSTACLE_SPEED",
]

#: Largest semi-axis (radius) of an obstacle [m]: beyond it the value is taken for a mistake.
MAX_OBSTACLE_SIZE = 50.0
#: Largest obstacle speed [m/s] (along the path, or the norm of its velocity): ten times a brisk walk;
#: nothing faster can be planned around by a walking robot.
MAX_OBSTACLE_SPEED = 10.0


def _semi_axis(name: str, value: object) -> float:
    return number_in(name, value, 0.0, MAX_OBSTACLE_SIZE, "m", lo_open=True, error=ObstacleError,
                     what="a radius" if "radius" in name else "a semi-axis")


def _speed(name: str, value: object) -> float:
    return number_in(name, value, -MAX_OBSTACLE_SPEED, MAX_OBSTACLE_SPEED, "m/s", error=ObstacleError,
                     what="a speed")


def _position(name: str, value: object) -> tuple[float, float]:
    p = finite_vector(name, value, 2, "m", error=ObstacleError)
    if max(abs(p[0]), abs(p[1])) > MAX_PATH_COORDINATE:
        raise ObstacleError(name, value, f"coordinates within +-{MAX_PATH_COORDINATE:g} m")
    return p  # type: ignore[return-value]


def _velocity(name: str, value: object) -> tuple[float, float]:
    v = finite_vector(name, value, 2, "m/s", error=ObstacleError)
    if math.hypot(v[0], v[1]) > MAX_OBSTACLE_SPEED:
        raise ObstacleError(name, value, f"a velocity [vx, vy] of norm <= {MAX_OBSTACLE_SPEED:g} m/s")
    return v  # type: ignore[return-value]


@dataclass(frozen=True)
class Obstacle:
    """An elliptical obstacle (a circle when both semi-axes are equal).

    Motion: either along ``path`` starting at arc length ``s0`` [m] with ``speed`` [m/s]
    (its axes stay aligned with the path direction), or from ``position`` [m] with constant
    ``velocity`` [m/s] (axes aligned with ``orientation`` [rad]).

    Attributes:
        axes: semi-axes (a, b) [m]; a along the orientation / path direction.
    """

    axes: tuple[float, float]
    path: Path | None = None
    s0: float = 0.0
    speed: float = 0.0
    position: tuple[float, float] = (0.0, 0.0)
    velocity: tuple[float, float] = (0.0, 0.0)
    orientation: float = 0.0

    def __post_init__(self) -> None:
        a, b = finite_vector("axes", self.axes, 2, "m", error=ObstacleError)
        fields = {
            "axes": (_semi_axis("axes[0]", a), _semi_axis("axes[1]", b)),
            "s0": finite_number("s0", self.s0, "m", error=ObstacleError),
            "speed": _speed("speed", self.speed),
            "position": _position("position", self.position),
            "velocity": _velocity("velocity", self.velocity),
            "orientation": finite_number("orientation", self.orientation, "rad", error=ObstacleError),
        }
        if self.path is not None and not isinstance(self.path, Path):
            raise ObstacleError("path", self.path, "a lipmpcc.paths.Path or None")
        for name, value in fields.items():
            object.__setattr__(self, name, value)

    @classmethod
    def circle(cls, radius: float, **kw) -> "Obstacle":
        """A circular obstacle of ``radius`` [m] (in (0, :data:`MAX_OBSTACLE_SIZE`])."""
        r = _semi_axis("radius", radius)
        return cls(axes=(r, r), **kw)

    @property
    def is_circle(self) -> bool:
        return abs(self.axes[0] - self.axes[1]) < 1e-12

    def center(self, t: float | np.ndarray) -> np.ndarray:
        """Centre at time(s) t [s]; shape (2,) or (n, 2).

        An obstacle moving along the path walks on past either end of it, straight along the end's (or the
        start's) tangent at the same speed: it does not stop on the path's end (issue 31: an ``ahead``
        obstacle that stood on the goal for good made the end unreachable, and a robot trailing it was
        reported neither trailing nor stalled)."""
        t = np.asarray(t, dtype=float)
        if self.path is not None:
            s = self.s0 + self.speed * t
            p = self.path.position(s)
            beyond = np.clip(s, 0.0, self.path.length)
            if np.any(s != beyond):
                p = p + (s - beyond)[..., None] * self.path.tangent(beyond)
            return p
        return np.asarray(self.position) + np.multiply.outer(t, np.asarray(self.velocity))

    def _track(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(centres (n, 2) [m], headings (n,) [rad]) at the times ``t`` (a float array (n,) [s]) in one path
        evaluation and without the argument checks (a planner's inner loop): the numbers of :meth:`center` and
        :meth:`heading`."""
        if self.path is None:
            return np.asarray(self.position) + np.multiply.outer(t, np.asarray(self.velocity)), \
                np.full(np.shape(t), self.orientation)
        s = self.s0 + self.speed * t
        beyond = np.clip(s, 0.0, self.path.length)
        p, d, _ = self.path._eval(beyond)
        if (s != beyond).any():
            p = p + (s - beyond)[..., None] * (d / np.linalg.norm(d, axis=1, keepdims=True))
        return p, np.arctan2(d[:, 1], d[:, 0])

    def heading(self, t: float | np.ndarray) -> np.ndarray | float:
        """Orientation ψ of the first semi-axis at time(s) t [rad] (past an end of its path: the end's)."""
        if self.path is not None:
            return self.path.slope(self.s0 + self.speed * np.asarray(t, dtype=float))
        return np.full(np.shape(t), self.orientation) if np.ndim(t) else self.orientation

    def clearance(self, points: np.ndarray, t: np.ndarray | float, robot_radius: float = 0.0) -> np.ndarray:
        """Distance from disks of ``robot_radius`` [m] centred at ``points`` to the obstacle
        surface at times t [m]; negative means contact.

        Exact for circles; for ellipses, the distance to the ellipse is computed by a
        dense angular search refined by Newton steps on the ellipse parameter.
        """
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        tt = np.broadcast_to(np.asarray(t, dtype=float), (pts.shape[0],))
        c = np.atleast_2d(self.center(tt))
        d = pts - c
        if self.is_circle:
            return np.linalg.norm(d, axis=1) - self.axes[0] - robot_radius
        psi = np.atleast_1d(self.heading(tt))
        cs, sn = np.cos(psi), np.sin(psi)
        local = np.stack([cs * d[:, 0] + sn * d[:, 1], -sn * d[:, 0] + cs * d[:, 1]], axis=1)
        a, b = self.axes
        ang = np.linspace(0, 2 * np.pi, 721)[None, :]
        ex, ey = a * np.cos(ang), b * np.sin(ang)
        dist = np.hypot(local[:, :1] - ex, local[:, 1:] - ey)
        i = np.argmin(dist, axis=1)
        ti = ang[0, i]
        for _ in range(4):  # Newton on f(t) = d/dt |q - e(t)|²/2
            ex1, ey1 = a * np.cos(ti), b * np.sin(ti)
            dx, dy = -a * np.sin(ti), b * np.cos(ti)
            ddx, ddy = -a * np.cos(ti), -b * np.sin(ti)
            rx, ry = ex1 - local[:, 0], ey1 - local[:, 1]
            f1 = rx * dx + ry * dy
            f2 = dx * dx + dy * dy + rx * ddx + ry * ddy
            ti = ti - np.where(np.abs(f2) > 1e-12, f1 / f2, 0.0)
        dmin = np.minimum(np.hypot(local[:, 0] - a * np.cos(ti), local[:, 1] - b * np.sin(ti)), dist.min(axis=1))
        inside = (local[:, 0] / a) ** 2 + (local[:, 1] / b) ** 2 < 1.0
        return np.where(inside, -dmin, dmin) - robot_radius


def obstacles_from_json(path: str | FsPath, reference_path: Path | None) -> list[Obstacle]:
    """Read obstacles from a JSON list.

    Each item is ``{"shape": "circle", "radius": r}`` or ``{"shape": "ellipse", "axes": [a, b]}``,
    with either ``{"s0": s, "speed": v}`` (moving along the reference path) or
    ``{"position": [x, y], "velocity": [vx, vy]}`` (optional ``"orientation"`` [rad]), in the world
    frame [m, m/s]. As in the path and stone files, lines whose first non-blank character is ``#`` are
    comments (blanked before parsing, so a JSON error keeps its line number); a ``#`` elsewhere is JSON's
    (format: docs/formats.md; sample: data/examples/my_obstacles.json).
    """
    if reference_path is not None and not isinstance(reference_path, Path):
        raise ObstacleError("reference_path", reference_path, "a lipmpcc.paths.Path or None")
    text = read_text_file("obstacles", path, "JSON file with a list of obstacles", error=ObstacleError)
    # a whole line can be blanked safely: a JSON string cannot span lines
    text = "\n".join("" if line.lstrip().startswith("#") else line for line in text.split("\n"))
    try:
        items = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ObstacleError("obstacles", str(path), "valid JSON", f"line {exc.lineno}: {exc.msg}") from None
    if not isinstance(items, list):
        raise ObstacleError("obstacles", type(items).__name__, "a JSON list of obstacle objects")
    return [obstacle_from_dict(it, reference_path, where=f"obstacles[{i}]") for i, it in enumerate(items)]


def obstacle_from_dict(item: dict, reference_path: Path | None, where: str = "obstacle") -> Obstacle:
    """Build one :class:`Obstacle` from its JSON description (see :func:`obstacles_from_json`)."""
    if not isinstance(item, dict):
        raise ObstacleError(where, item, "an object with a 'shape' field")
    shape = item.get("shape")
    if shape == "circle":
        r = _semi_axis(f"{where}.radius", item.get("radius"))
        axes = (r, r)
    elif shape == "ellipse":
        a, b = finite_vector(f"{where}.axes", item.get("axes"), 2, "m", error=ObstacleError)
        axes = (_semi_axis(f"{where}.axes[0]", a), _semi_axis(f"{where}.axes[1]", b))
    else:
        raise ObstacleError(f"{where}.shape", shape, "'circle' or 'ellipse'")
    if "s0" in item or "speed" in item:
        if reference_path is None:
            raise ObstacleError(where, item, "position/velocity (no reference path to move along)")
        s0 = number_in(f"{where}.s0", item.get("s0", 0.0), 0.0, reference_path.length, "m", error=ObstacleError,
                       what="an arc length")
        return Obstacle(axes=axes, path=reference_path, s0=s0, speed=_speed(f"{where}.speed", item.get("speed", 0.0)))
    if "position" in item:
        return Obstacle(
            axes=axes,
            position=_position(f"{where}.position", item["position"]),
            velocity=_velocity(f"{where}.velocity", item.get("velocity", [0.0, 0.0])),
            orientation=finite_number(f"{where}.orientation", item.get("orientation", 0.0), "rad", error=ObstacleError),
        )
    raise ObstacleError(where, item, "either {'s0', 'speed'} or {'position', 'velocity'}")


def barrier_params(obstacles: Sequence[Obstacle], times: np.ndarray, inflate: float, inflate_foot: float,
                   check: bool = True) -> np.ndarray:
    """Per-obstacle, per-time parameters of the barriers used by the MPCC.

    For each obstacle j and time t_k: [cx, cy, m11, m12, m22, f11, f12, f22], where
    M = [[m11, m12], [m12, m22]] gives the COM barrier b(p) = (p−c)ᵀM(p−c) − 1 with the
    semi-axes grown by ``inflate`` [m], and F the foothold barrier grown by ``inflate_foot`` [m].

    ``check`` False skips the argument checks, for a planner's inner loop with its own checked obstacles and
    times (as ``check_finite`` in SciPy).

    Returns:
        array (len(obstacles), len(times), 8).
    """
    if check:
        _check_barrier_args(obstacles, times, inflate, inflate_foot)
    out = np.zeros((len(obstacles), len(times), 8))
    for j, ob in enumerate(obstacles):
        if check:
            c = np.atleast_2d(ob.center(times))
            psi = np.atleast_1d(ob.heading(times)) * np.ones(len(times))
        else:  # the same numbers in one evaluation of the obstacle's path (times: a float array (n,))
            c, psi = ob._track(times)
        cs, sn = np.cos(psi), np.sin(psi)
        cc, ss, csn = cs * cs, sn * sn, cs * sn  # the products both inflations share (the same numbers)
        out[j, :, 0:2] = c
        for o, infl in ((2, inflate), (5, inflate_foot)):
            ia, ib = 1.0 / (ob.axes[0] + infl) ** 2, 1.0 / (ob.axes[1] + infl) ** 2
            out[j, :, o] = cc * ia + ss * ib
            out[j, :, o + 1] = csn * (ia - ib)
            out[j, :, o + 2] = ss * ia + cc * ib
    return out


def _check_barrier_args(obstacles: Sequence[Obstacle], times: np.ndarray, inflate: float, inflate_foot: float) -> None:
    """The checks of :func:`barrier_params`' arguments."""
    if isinstance(obstacles, (str, bytes, Obstacle)) or not hasattr(obstacles, "__len__"):
        raise ObstacleError("obstacles", obstacles, "a list of lipmpcc.obstacles.Obstacle")
    for i, ob in enumerate(obstacles):
        if not isinstance(ob, Obstacle):
            raise ObstacleError(f"obstacles[{i}]", ob, "a lipmpcc.obstacles.Obstacle")
    finite_array("times", times, (None,), "s", error=ObstacleError)
    non_negative_number("inflate", inflate, "m", error=ObstacleError)
    non_negative_number("inflate_foot", inflate_foot, "m", error=ObstacleError)
