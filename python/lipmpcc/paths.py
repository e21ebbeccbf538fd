"""Reference paths parametrised by arc length.

A path is a smooth planar curve y_d(θ) = [x_d(θ), y_d(θ)] with θ ∈ [0, θ_T] the
arc length [m] (paper A eq. 3). Every path gives, numerically (vectorised over θ)
and as CasADi expressions for the planners:

- :meth:`Path.position`  y_d(θ) [m]
- :meth:`Path.tangent`   unit tangent ∂y_d/∂θ
- :meth:`Path.slope`     φ_d(θ) = atan2(∂y_d/∂θ, ∂x_d/∂θ) [rad] (paper A eq. 4)
- :meth:`Path.curvature` κ(θ) [1/m], signed (positive turning left)

Kinds: :class:`LinePath`, :class:`ArcPath` (circles are full arcs), :class:`SplinePath`
(a C² cubic spline through waypoints, re-parametrised by arc length) and
:class:`CompositePath` (a concatenation); :class:`ExtendedPath` continues a path straight past its
end (the MPCC's problem, so that its progress reward does not vanish there). :meth:`Path.closest_point` implements
θ_init of paper A eq. (19) as a *local* search around the previous θ, so that a
path that comes back near itself does not make θ jump.
"""

from __future__ import annotations

import csv
import io
import math
from abc import ABC, abstractmethod
from pathlib import Path as FsPath
from typing import Sequence

import casadi as ca
import numpy as np

from .exceptions import PathError
from .validation import (
    count,
    finite_array,
    finite_number,
    non_negative_number,
    number_in,
    positive_number,
    read_text_file,
)

__all__ = [
    "Path",
    "LinePath",
    "ArcPath",
    "SplinePath",
    "CompositePath",
    "ExtendedPath",
    "load_waypoints_csv",
    "path_from_waypoints",
    "load_path_csv",
    "MIN_PATH_LENGTH",
    "MAX_PATH_COORDINATE",
    "MAX_SPLINE_SAMPLES",
    "MAX_WAYPOINT_TURN",
    "CLOSEST_POINT_WINDOW",
    "check_loops",
]

#: Shortest path accepted [m]: a shorter one is degenerate (its tangent is numerical noise).
MIN_PATH_LENGTH = 1e-3
#: Largest coordinate of a path point accepted [m] (|x|, |y|); beyond it a value is taken for a mistake
#: (10 km: about six hours of walking at 0.5 m/s).
MAX_PATH_COORDINATE = 1e4
#: Most samples a :class:`SplinePath` takes to re-parametrise its curve (length / ds x 20).
MAX_SPLINE_SAMPLES = 10_000_000

ArrayLike = float | np.ndarray | Sequence[float]


def _as_point(name: str, p: ArrayLike) -> np.ndarray:
    a = finite_array(name, p, (2,), "m", error=PathError, what="a 2-vector [x, y]")
    _check_coordinates(name, a)
    return a


def _check_coordinates(name: str, a: np.ndarray) -> None:
    """PathError unless every coordinate of ``a`` is within ±:data:`MAX_PATH_COORDINATE`."""
    if a.size and float(np.max(np.abs(a))) > MAX_PATH_COORDINATE:
        raise PathError(name, a.tolist(), f"coordinates within +-{MAX_PATH_COORDINATE:g} m")


def _check_length(name: str, value: object, length: float) -> None:
    """PathError unless the path's ``length`` [m] is at least :data:`MIN_PATH_LENGTH`."""
    if not length >= MIN_PATH_LENGTH:
        raise PathError(name, value, f"a path at least {MIN_PATH_LENGTH:g} m long",
                        f"this one is {length:.3g} m long: degenerate")


class Path(ABC):
    """A planar path parametrised by arc length θ ∈ [0, length]."""

    #: total arc length θ_T [m]
    length: float

    # ---- numeric -------------------------------------------------------------------------
    @abstractmethod
    def _eval(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position (n,2), first derivative (n,2) and second derivative (n,2) at clipped s."""

    def _prepare(self, theta: ArrayLike) -> tuple[np.ndarray, bool]:
        t = finite_array("theta", theta, None, "m", error=PathError, what="path parameter values")
        scalar = t.ndim == 0
        t = np.atleast_1d(t)
        return np.clip(t, 0.0, self.length), scalar

    def position(self, theta: ArrayLike) -> np.ndarray:
        """y_d(θ) [m]; shape (2,) for scalar θ, (n, 2) otherwise. θ is clipped to [0, θ_T]."""
        s, scalar = self._prepare(theta)
        p, _, _ = self._eval(s)
        return p[0] if scalar else p

    def tangent(self, theta: ArrayLike) -> np.ndarray:
        """Unit tangent at θ; shape (2,) or (n, 2)."""
        s, scalar = self._prepare(theta)
        _, d, _ = self._eval(s)
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        return d[0] if scalar else d

    def slope(self, theta: ArrayLike) -> np.ndarray | float:
        """φ_d(θ) = atan2(ẏ_d, ẋ_d) [rad] (paper A eq. 4)."""
        s, scalar = self._prepare(theta)
        _, d, _ = self._eval(s)
        phi = np.arctan2(d[:, 1], d[:, 0])
        return float(phi[0]) if scalar else phi

    def _frame(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(y_d(θ) (n, 2) [m], φ_d(θ) (n,) [rad]) of a float array θ (n,) [m], clipped to [0, θ_T], in one
        evaluation and without the argument checks (a planner's own finite arrays, in its inner loop): the same
        numbers as :meth:`position` and :meth:`slope`."""
        p, d, _ = self._eval(np.clip(theta, 0.0, self.length))
        return p, np.arctan2(d[:, 1], d[:, 0])

    def curvature(self, theta: ArrayLike) -> np.ndarray | float:
        """Signed curvature κ(θ) [1/m], positive when the path turns left."""
        s, scalar = self._prepare(theta)
        _, d, dd = self._eval(s)
        num = d[:, 0] * dd[:, 1] - d[:, 1] * dd[:, 0]
        k = num / np.linalg.norm(d, axis=1) ** 3
        return float(k[0]) if scalar else k

    def sample(self, n: int = 200) -> np.ndarray:
        """``n`` points equally spaced in arc length, shape (n, 2)."""
        n = count("n", n, 2, error=PathError)
        return self.position(np.linspace(0.0, self.length, n))

    # ---- CasADi --------------------------------------------------------------------------
    @abstractmethod
    def casadi_derivs(self, theta: ca.SX | ca.MX) -> tuple[ca.SX, ca.SX]:
        """CasADi expressions of (y_d(θ), ∂y_d/∂θ), each a 2-vector. θ is not clipped."""

    def casadi_position(self, theta: ca.SX | ca.MX) -> ca.SX:
        """y_d(θ) as a CasADi 2-vector."""
        return self.casadi_derivs(theta)[0]

    def casadi_tangent(self, theta: ca.SX | ca.MX) -> ca.SX:
        """Unit tangent as a CasADi 2-vector."""
        d = self.casadi_derivs(theta)[1]
        return d / ca.norm_2(d)

    def casadi_slope(self, theta: ca.SX | ca.MX) -> ca.SX:
        """φ_d(θ) [rad] as a CasADi scalar."""
        d = self.casadi_derivs(theta)[1]
        return ca.atan2(d[1], d[0])

    def casadi_curvature(self, theta: ca.SX | ca.MX) -> ca.SX:
        """Signed curvature [1/m] as a CasADi scalar (by automatic differentiation)."""
        if not isinstance(theta, (ca.SX, ca.MX)) or not theta.is_symbolic():
            s = ca.SX.sym("s")
            f = ca.Function("kappa", [s], [self.casadi_curvature(s)])
            return f(theta)
        d = self.casadi_derivs(theta)[1]
        dd = ca.jacobian(d, theta)
        return (d[0] * dd[1] - d[1] * dd[0]) / ca.norm_2(d) ** 3

    # ---- closest point (paper A eq. 19) ---------------------------------------------------
    def closest_point(
        self,
        point: ArrayLike,
        theta_prev: float | None = None,
        window: tuple[float, float] = (1.0, 2.0),
        resolution: float = 0.02,
    ) -> float:
        """θ_init = argmin_θ ‖point − y_d(θ)‖² (paper A eq. 19).

        Args:
            point: robot position [x, y] [m].
            theta_prev: previous θ [m]. When given, only θ ∈ [θ_prev − window[0],
                θ_prev + window[1]] is searched, so that a path passing near itself
                does not make θ jump. ``None`` searches the whole path.
            window: how far back and ahead of ``theta_prev`` to search [m].
            resolution: spacing of the coarse search grid [m], refined afterwards.

        Returns:
            θ_init [m], in [0, θ_T].
        """
        p = _as_point("point", point)
        resolution = positive_number("resolution", resolution, "m", error=PathError)
        if theta_prev is None:
            lo, hi = 0.0, self.length
        else:
            theta_prev = finite_number("theta_prev", theta_prev, "m", error=PathError)
            w = finite_array("window", window, (2,), "m", error=PathError, what="(back, ahead) distances")
            if w[0] < 0 or w[1] < 0:
                raise PathError("window", window, "non-negative (back, ahead) distances [m]")
            lo, hi = self._window(theta_prev, window)
        return self._closest_in(p, lo, hi, resolution)

    def _closest_near(self, p: np.ndarray, theta_prev: float | None) -> float:
        """:meth:`closest_point` of a checked (2,) float point and a finite ``theta_prev`` (or None) with the
        default window and resolution, without the argument checks (a planner's inner loop); a point out of
        range (or not finite) goes through them, for the same error."""
        if not (abs(p[0]) <= MAX_PATH_COORDINATE and abs(p[1]) <= MAX_PATH_COORDINATE):
            return self.closest_point(p, theta_prev)
        lo, hi = (0.0, self.length) if theta_prev is None else self._window(theta_prev, (1.0, 2.0))
        return self._closest_in(p, lo, hi, 0.02)

    def _window(self, theta_prev: float, window: Sequence[float]) -> tuple[float, float]:
        """The searched interval [lo, hi] about ``theta_prev`` [m]."""
        lo = max(0.0, theta_prev - window[0])
        hi = min(self.length, theta_prev + window[1])
        if hi < lo:
            lo = hi = min(max(theta_prev, 0.0), self.length)
        return lo, hi

    def _closest_in(self, p: np.ndarray, lo: float, hi: float, resolution: float) -> float:
        """argmin over θ ∈ [lo, hi] of ‖p − y_d(θ)‖²: closed form, or a grid refined by Newton steps."""
        exact = self._closest_exact(p, lo, hi)
        if exact is not None:
            return exact
        n = max(3, int(math.ceil((hi - lo) / resolution)) + 1)
        grid = np.linspace(lo, hi, n)
        pts, _, _ = self._eval(grid)
        d2 = np.sum((pts - p) ** 2, axis=1)
        i = int(np.argmin(d2))
        # Newton refinement of f(s) = ½‖y_d(s) − p‖² inside the bracketing cells
        a = grid[max(i - 1, 0)]
        b = grid[min(i + 1, n - 1)]
        s = np.array([grid[i]])
        for _ in range(8):
            y, d, dd = self._eval(s)
            r = y[0] - p
            f1 = float(r @ d[0])
            f2 = float(d[0] @ d[0] + r @ dd[0])
            step = -f1 / f2 if f2 > 1e-12 else -f1
            s_new = min(max(s[0] + step, a), b)
            if abs(s_new - s[0]) < 1e-10:
                s[0] = s_new
                break
            s[0] = s_new
        y, _, _ = self._eval(s)
        return float(s[0]) if float(np.sum((y[0] - p) ** 2)) <= d2[i] else float(grid[i])


    def _closest_exact(self, p: np.ndarray, lo: float, hi: float) -> float | None:
        """Closed-form closest point in [lo, hi], or None when the kind has none."""
        return None


# ----------------------------------------------------------------------------------------------
class LinePath(Path):
    """Straight segment from ``start`` to ``end`` [m]."""

    def __init__(self, start: ArrayLike, end: ArrayLike) -> None:
        self.start = _as_point("start", start)
        self.end = _as_point("end", end)
        self.length = float(np.linalg.norm(self.end - self.start))
        if self.length < MIN_PATH_LENGTH:
            raise PathError("end", self.end.tolist(), f"a point at least {MIN_PATH_LENGTH:g} m from start {self.start.tolist()}",
                            "the line has zero length" if self.length == 0.0
                            else f"the line would be {self.length:.3g} m long: degenerate")
        self.direction = (self.end - self.start) / self.length

    def _eval(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        p = self.start + s[:, None] * self.direction
        d = np.empty_like(p)
        d[:] = self.direction
        return p, d, np.zeros(p.shape)

    def _closest_exact(self, p: np.ndarray, lo: float, hi: float) -> float | None:
        return float(min(max(float((p - self.start) @ self.direction), lo), hi))

    def casadi_derivs(self, theta: ca.SX | ca.MX) -> tuple[ca.SX, ca.SX]:
        p = ca.vertcat(self.start[0] + theta * self.direction[0], self.start[1] + theta * self.direction[1])
        d = ca.vertcat(self.direction[0] + 0 * theta, self.direction[1] + 0 * theta)
        return p, d

    def __repr__(self) -> str:
        return f"LinePath(start={self.start.tolist()}, end={self.end.tolist()})"


class ArcPath(Path):
    """Circular arc of ``radius`` [m] about ``center``, from polar angle ``start_angle``
    [rad] sweeping ``sweep`` [rad] (positive: counter-clockwise)."""

    def __init__(self, center: ArrayLike, radius: float, start_angle: float = 0.0, sweep: float = 2 * math.pi) -> None:
        self.center = _as_point("center", center)
        radius = positive_number("radius", radius, "m", hi=MAX_PATH_COORDINATE, error=PathError, what="a finite radius")
        start_angle = finite_number("start_angle", start_angle, "rad", error=PathError)
        sweep = finite_number("sweep", sweep, "rad", error=PathError)
        if abs(sweep) < 1e-9:
            raise PathError("sweep", sweep, "a finite, non-zero sweep angle [rad] (the arc has zero length)")
        self.radius = float(radius)
        self.start_angle = float(start_angle)
        self.sweep = float(sweep)
        self.sign = 1.0 if sweep > 0 else -1.0
        self.length = self.radius * abs(self.sweep)
        _check_length("radius", radius, self.length)

    @classmethod
    def circle(cls, radius: float, start: ArrayLike = (0.0, 0.0), heading: float = 0.0, turns: float = 1.0) -> "ArcPath":
        """A full counter-clockwise circle of ``radius`` starting at ``start`` with the
        initial direction ``heading`` [rad]."""
        radius = positive_number("radius", radius, "m", hi=MAX_PATH_COORDINATE, error=PathError, what="a finite radius")
        heading = finite_number("heading", heading, "rad", error=PathError)
        turns = number_in("turns", turns, -100.0, 100.0, error=PathError)
        st = _as_point("start", start)
        center = st + radius * np.array([-math.sin(heading), math.cos(heading)])
        return cls(center, radius, start_angle=heading - math.pi / 2, sweep=2 * math.pi * turns)

    def _angle(self, s):
        return self.start_angle + self.sign * s / self.radius

    def _eval(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a = self._angle(s)
        c, sn = np.cos(a), np.sin(a)
        cs = np.empty((len(s), 2))  # [cos, sin] (np.stack's numbers, built without its overhead: planners' loops)
        cs[:, 0], cs[:, 1] = c, sn
        p = self.center + self.radius * cs
        d = np.empty_like(cs)
        d[:, 0], d[:, 1] = -sn, c
        d *= self.sign
        return p, d, -cs / self.radius

    def _closest_exact(self, p: np.ndarray, lo: float, hi: float) -> float | None:
        d = p - self.center
        if float(d @ d) < 1e-18:  # at the centre every point is closest: stay at lo
            return lo
        ang = math.atan2(d[1], d[0])
        # arc length of the polar angle, unwrapped into [lo - period, hi + period]
        period = 2 * math.pi * self.radius
        s0 = self.sign * (ang - self.start_angle) * self.radius
        mid = 0.5 * (lo + hi)
        s0 = s0 + period * round((mid - s0) / period)
        best, best_d = lo, math.inf
        seen = []
        for cand in (s0 - period, s0, s0 + period, lo, hi):
            c = min(max(cand, lo), hi)
            if c in seen:  # the same distance again: never strictly better
                continue
            seen.append(c)
            a = self._angle(c)
            d = self.center + self.radius * np.array([math.cos(a), math.sin(a)]) - p
            dist = float(d @ d)
            if dist < best_d - 1e-15:
                best, best_d = c, dist
        return float(best)

    def casadi_derivs(self, theta: ca.SX | ca.MX) -> tuple[ca.SX, ca.SX]:
        a = self._angle(theta)
        p = ca.vertcat(self.center[0] + self.radius * ca.cos(a), self.center[1] + self.radius * ca.sin(a))
        d = ca.vertcat(-self.sign * ca.sin(a), self.sign * ca.cos(a))
        return p, d

    def __repr__(self) -> str:
        return (
            f"ArcPath(center={self.center.tolist()}, radius={self.radius}, "
            f"start_angle={self.start_angle:.4f}, sweep={self.sweep:.4f})"
        )


class SplinePath(Path):
    """C² cubic spline through waypoints, re-parametrised by arc length.

    The waypoints are first interpolated by a natural cubic spline in the chord-length
    parameter; that curve is sampled every ``ds`` metres of arc length and a second cubic
    spline x(θ), y(θ) is fitted through those samples, so that θ is arc length to within
    ~1e-4 relative (checked in the tests). Both the numeric and the CasADi evaluations
    use the same piecewise-cubic coefficients.
    """

    def __init__(self, waypoints: ArrayLike, ds: float = 0.1) -> None:
        w = _waypoint_array(waypoints)
        # drop consecutive duplicates
        keep = np.ones(len(w), dtype=bool)
        keep[1:] = np.linalg.norm(np.diff(w, axis=0), axis=1) > 1e-9
        w = w[keep]
        if len(w) < 2:
            raise PathError("waypoints", waypoints, "at least two distinct points",
                            f"all {keep.size} waypoints are the point {w[0].tolist()}")
        ds = positive_number("ds", ds, "m", error=PathError)
        self.waypoints = w
        chord = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(w, axis=0), axis=1))])
        if chord[-1] / ds * 20 > MAX_SPLINE_SAMPLES:
            raise PathError("ds", ds, f"a resampling step >= {chord[-1] * 20 / MAX_SPLINE_SAMPLES:.3g} m for a path "
                            f"of {chord[-1]:.4g} m (at most {MAX_SPLINE_SAMPLES:g} samples)")
        from scipy.interpolate import CubicSpline  # here: importing scipy.interpolate takes ~0.4 s

        if len(w) == 2:
            raw = CubicSpline(chord, w, bc_type=((1, (w[1] - w[0]) / chord[-1]), (1, (w[1] - w[0]) / chord[-1])))
        else:
            raw = CubicSpline(chord, w, bc_type="natural")
        # arc length of the raw curve by dense trapezoidal quadrature
        u = np.linspace(0.0, chord[-1], max(200, int(chord[-1] / ds * 20)))
        speed = np.linalg.norm(raw(u, 1), axis=1)
        s_of_u = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(u))])
        total = float(s_of_u[-1])
        _check_length("waypoints", waypoints, total)
        n = max(4, int(math.ceil(total / ds)) + 1)
        s_grid = np.linspace(0.0, total, n)
        u_grid = np.interp(s_grid, s_of_u, u)
        pts = raw(u_grid)
        d0 = raw(0.0, 1)
        d1 = raw(chord[-1], 1)
        self._spline = CubicSpline(
            s_grid,
            pts,
            bc_type=((1, d0 / np.linalg.norm(d0)), (1, d1 / np.linalg.norm(d1))),
        )
        self.length = total
        self._knots = s_grid
        # coefficient table for CasADi: c[k, i, dim], highest power first
        self._coef = self._spline.c

    def _eval(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self._spline(s), self._spline(s, 1), self._spline(s, 2)

    def casadi_derivs(self, theta: ca.SX | ca.MX) -> tuple[ca.SX, ca.SX]:
        if not isinstance(theta, ca.SX):  # MX (Opti) or numbers: go through an SX function
            if getattr(self, "_sx_fun", None) is None:
                s = ca.SX.sym("s")
                self._sx_fun = ca.Function("spline", [s], list(self.casadi_derivs(s)))
            out = self._sx_fun(theta)
            return out[0], out[1]
        inner = ca.DM(self._knots[1:-1])
        k0 = ca.pw_const(theta, inner, ca.DM(self._knots[:-1]))
        h = theta - k0
        out_p, out_d = [], []
        for dim in range(2):
            a3, a2, a1, a0 = (ca.pw_const(theta, inner, ca.DM(self._coef[k, :, dim])) for k in range(4))
            out_p.append(((a3 * h + a2) * h + a1) * h + a0)
            out_d.append((3 * a3 * h + 2 * a2) * h + a1)
        return ca.vertcat(*out_p), ca.vertcat(*out_d)

    def __repr__(self) -> str:
        return f"SplinePath({len(self.waypoints)} waypoints, length={self.length:.3f} m)"


def _waypoint_array(waypoints: ArrayLike) -> np.ndarray:
    """Waypoints as an (n, 2) float array of finite coordinates within ±:data:`MAX_PATH_COORDINATE`."""
    if isinstance(waypoints, (str, bytes)):
        raise PathError("waypoints", waypoints, "an (n, 2) array of [x, y] points [m]")
    try:
        w = np.asarray(waypoints, dtype=float)
    except (TypeError, ValueError):
        raise PathError("waypoints", waypoints, "an (n, 2) array of [x, y] points [m]") from None
    if w.ndim != 2 or w.shape[1] != 2 or len(w) == 0:
        raise PathError("waypoints", waypoints, "an (n, 2) array of [x, y] points [m]")
    if not np.all(np.isfinite(w)):
        bad = int(np.argwhere(~np.isfinite(w))[0][0])
        raise PathError("waypoints", w[bad].tolist(), f"finite coordinates (row {bad} has NaN or inf)")
    _check_coordinates("waypoints", w)
    return w


class CompositePath(Path):
    """Concatenation of paths; θ runs through the pieces in order.

    Consecutive pieces must join (end of one = start of the next, within ``tol``)."""

    def __init__(self, pieces: Sequence[Path], tol: float = 1e-6) -> None:
        if isinstance(pieces, (str, bytes, Path)) or not isinstance(pieces, Sequence) or len(pieces) == 0:
            raise PathError("pieces", pieces, "a list of at least one path")
        tol = non_negative_number("tol", tol, "m", error=PathError)
        for i, p in enumerate(pieces):
            if not isinstance(p, Path):
                raise PathError(f"pieces[{i}]", p, "a lipmpcc.paths.Path")
        for i in range(len(pieces) - 1):
            gap = float(np.linalg.norm(pieces[i].position(pieces[i].length) - pieces[i + 1].position(0.0)))
            if gap > tol:
                raise PathError(f"pieces[{i + 1}]", pieces[i + 1], f"to start where piece {i} ends (gap {gap:.3g} m)")
        self.pieces = list(pieces)
        self.offsets = np.concatenate([[0.0], np.cumsum([p.length for p in pieces])])
        self.length = float(self.offsets[-1])

    def _eval(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        idx = np.clip(np.searchsorted(self.offsets, s, side="right") - 1, 0, len(self.pieces) - 1)
        p = np.empty((len(s), 2))
        d = np.empty((len(s), 2))
        dd = np.empty((len(s), 2))
        for i, piece in enumerate(self.pieces):
            m = idx == i
            if np.any(m):
                p[m], d[m], dd[m] = piece._eval(np.clip(s[m] - self.offsets[i], 0.0, piece.length))
        return p, d, dd

    def casadi_derivs(self, theta: ca.SX | ca.MX) -> tuple[ca.SX, ca.SX]:
        p, d = self.pieces[-1].casadi_derivs(theta - self.offsets[-2])
        for i in range(len(self.pieces) - 2, -1, -1):
            pi, di = self.pieces[i].casadi_derivs(theta - self.offsets[i])
            c = theta < self.offsets[i + 1]
            p = ca.if_else(c, pi, p)
            d = ca.if_else(c, di, d)
        return p, d

    def __repr__(self) -> str:
        return f"CompositePath({self.pieces!r})"


class ExtendedPath(Path):
    """A path continued straight along its end tangent for ``extra`` [m] past its end.

    θ ∈ [0, base.length] is the base path; θ ∈ (base.length, base.length + extra] is the straight line
    y_d(θ_T) + (θ − θ_T) t(θ_T), with t the unit end tangent (zero curvature). ``length`` is the extended
    length. The MPCC builds its problem on it (:func:`lipmpcc.planners.liveness.problem_path`): with ϑ
    capped at the end, the progress reward −ρ v² vanishes within N v_max of it and the plans crawl the last
    metre (issue 31's end approach).

    Args:
        base: the path to extend.
        extra: how far past the end θ may run [m] (> 0).
    """

    def __init__(self, base: Path, extra: float) -> None:
        if not isinstance(base, Path):
            raise PathError("base", base, "a lipmpcc.paths.Path")
        self.base = base
        self.extra = positive_number("extra", extra, "m", error=PathError)
        self.end_length = float(base.length)
        self.length = self.end_length + self.extra
        self._end_p, d, _ = (a[0] for a in base._eval(np.array([self.end_length])))
        self._end_t = d / np.linalg.norm(d)

    def _eval(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        past = s > self.end_length
        p, d, dd = self.base._eval(np.minimum(s, self.end_length))
        if past.any():
            p, d, dd = p.copy(), d.copy(), dd.copy()
            p[past] = self._end_p + (s[past] - self.end_length)[:, None] * self._end_t
            d[past] = self._end_t
            dd[past] = 0.0
        return p, d, dd

    def casadi_derivs(self, theta: ca.SX | ca.MX) -> tuple[ca.SX, ca.SX]:
        p, d = self.base.casadi_derivs(theta)
        past = theta > self.end_length
        run = theta - self.end_length
        pe = ca.vertcat(self._end_p[0] + run * self._end_t[0], self._end_p[1] + run * self._end_t[1])
        de = ca.vertcat(self._end_t[0] + 0 * theta, self._end_t[1] + 0 * theta)
        return ca.if_else(past, pe, p), ca.if_else(past, de, d)

    def __repr__(self) -> str:
        return f"ExtendedPath({self.base!r}, extra={self.extra:.3f} m)"


# ----------------------------------------------------------------------------------------------
def _is_number(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _header_columns(fp: FsPath, path: str | FsPath, lineno: int, cells: list[str]) -> tuple[int, int] | None:
    """Column indices of x and y when ``cells`` is a header row, None when it is a data row.

    Raises:
        PathError: a header without the columns x and y.
    """
    if all(_is_number(c) for c in cells):
        return None
    cols = [c.lower() for c in cells]
    if "x" in cols and "y" in cols:
        return cols.index("x"), cols.index("y")
    if any(_is_number(c) for c in cells):
        return None  # a data row with a bad value: reported by the row parser with its line
    raise PathError("path", str(path), "a CSV header with columns x,y", f"{fp.name} line {lineno}: found columns {cols}")


def _waypoint(fp: FsPath, lineno: int, cells: list[str], ix: int, iy: int, header: bool) -> tuple[float, float]:
    """(x, y) [m] of one data row; the error names the file, the line and the bad value."""
    where = f"{fp.name} line {lineno}"
    if not header and len(cells) != 2:
        raise PathError(where, ",".join(cells), "two numbers x,y (or a header row naming the columns x,y)")
    cx, cy = (cells[i] if i < len(cells) else None for i in (ix, iy))
    try:
        x, y = float(cx), float(cy)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise PathError(where, [cx, cy], "two numbers x,y") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise PathError(where, [x, y], "finite coordinates (no NaN or inf)")
    return x, y


def load_waypoints_csv(path: str | FsPath) -> np.ndarray:
    """Read waypoints [m] from a CSV file, one ``x,y`` row per waypoint, in the world frame.

    Blank lines and lines starting with ``#`` are skipped. A header row is optional: when the first
    row is ``x,y`` (any case, in any order, other columns ignored) the columns are taken by name,
    otherwise every row is exactly two numbers ``x,y``. Format: docs/formats.md.

    Raises:
        PathError: missing file, a header without x,y, non-numeric or NaN entries (naming the file,
            the line and the value), fewer than two rows.
    """
    text = read_text_file("path", path, "CSV file of waypoints with columns x,y", error=PathError)
    fp = FsPath(path)
    rows: list[tuple[float, float]] = []
    columns: tuple[int, int] | None = None
    first = True
    with io.StringIO(text, newline="") as f:
        reader = csv.reader(f)
        for row in reader:
            cells = [c.strip() for c in row]
            if not cells or all(c == "" for c in cells) or cells[0].startswith("#"):
                continue
            if first:
                first = False
                columns = _header_columns(fp, path, reader.line_num, cells)
                if columns is not None:
                    continue
            ix, iy = columns if columns is not None else (0, 1)
            rows.append(_waypoint(fp, reader.line_num, cells, ix, iy, columns is not None))
    if len(rows) < 2:
        raise PathError("path", str(path), "at least two waypoints", f"found {len(rows)}")
    if len(set(rows)) == 1:
        raise PathError("path", str(path), "at least two distinct points",
                        f"all {len(rows)} rows are the point ({rows[0][0]:g}, {rows[0][1]:g})")
    return np.asarray(rows)


#: (back, ahead) arc length [m] the closest-point search looks about the previous closest point
#: (:meth:`Path.closest_point`'s default window)
CLOSEST_POINT_WINDOW = (1.0, 2.0)


def _crossings(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray) -> np.ndarray:
    """Whether segments a0→a1 and b0→b1 (arrays of (n, 2)) properly cross each other."""
    def cross(o: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
        return (p[:, 0] - o[:, 0]) * (q[:, 1] - o[:, 1]) - (p[:, 1] - o[:, 1]) * (q[:, 0] - o[:, 0])

    d1, d2 = cross(b0, b1, a0), cross(b0, b1, a1)
    d3, d4 = cross(a0, a1, b0), cross(a0, a1, b1)
    return (d1 * d2 < 0.0) & (d3 * d4 < 0.0)


def check_loops(path: Path, name: str = "path") -> None:
    """Refuse a path that crosses itself with a loop no longer than the closest-point search's window
    (:data:`CLOSEST_POINT_WINDOW`, 3 m in all): there the search, which looks about the previous closest
    point, cannot tell the two passes apart and the path parameter may jump across the loop. A path that
    crosses itself with a longer loop (a figure eight, paper A's 1.25 turns of circle) is accepted: the
    local search follows it in order (paper A eq. 19).

    Raises:
        PathError: naming where the path crosses itself (the two arc lengths) and the loop's length.
    """
    L = float(path.length)
    span = float(sum(CLOSEST_POINT_WINDOW))
    ds = max(0.05, L / 20_000)
    n = int(math.ceil(L / ds))
    if n < 3:
        return
    th = np.linspace(0.0, L, n + 1)
    pts = np.asarray(path.position(th), dtype=float)
    a0, a1 = pts[:-1], pts[1:]
    for k in range(2, int(math.ceil(span / ds)) + 2):
        if k >= n:
            break
        hit = np.flatnonzero(_crossings(a0[:-k], a1[:-k], a0[k:], a1[k:]))
        if hit.size:
            i = int(hit[0])
            raise PathError(name, f"a path crossing itself at arc lengths {th[i]:.2f} and {th[i + k]:.2f} m",
                            f"a path whose loops are longer than {span:g} m (the closest-point search's window)",
                            f"its loop is {th[i + k] - th[i]:.2f} m long: the robot's progress along it is ambiguous; "
                            "widen the loop or split the path")


def path_from_waypoints(waypoints: ArrayLike) -> Path:
    """A :class:`LinePath` for two waypoints, a :class:`SplinePath` otherwise.

    Raises:
        PathError: not an (n, 2) array of finite points, fewer than two distinct points, or a path
            shorter than :data:`MIN_PATH_LENGTH`.
    """
    w = _waypoint_array(waypoints)
    seg = np.diff(w, axis=0)
    lengths = np.hypot(seg[:, 0], seg[:, 1])
    if float(np.sum(lengths)) < MIN_PATH_LENGTH:
        raise PathError("waypoints", w.tolist(), f"waypoints spanning at least {MIN_PATH_LENGTH} m",
                        f"they span {float(np.sum(lengths)):.3g} m: a degenerate path")
    _check_no_reversal(w, seg, lengths)
    if w.shape == (2, 2):
        return LinePath(w[0], w[1])
    return SplinePath(w)


#: sharpest turn at a waypoint [rad] a path may take: beyond it the path doubles back on itself (a cusp)
MAX_WAYPOINT_TURN = math.radians(170.0)


def _check_no_reversal(w: np.ndarray, seg: np.ndarray, lengths: np.ndarray) -> None:
    """Refuse waypoints along which the path turns back on itself (a turn over :data:`MAX_WAYPOINT_TURN`)."""
    keep = lengths > 0.0
    d, idx = seg[keep] / lengths[keep, None], np.flatnonzero(keep)
    for j in range(len(d) - 1):
        turn = math.acos(max(-1.0, min(1.0, float(d[j] @ d[j + 1]))))
        if turn > MAX_WAYPOINT_TURN:
            k = int(idx[j + 1])
            raise PathError("waypoints", w.tolist(), f"a path that never turns back (turns under "
                            f"{math.degrees(MAX_WAYPOINT_TURN):.0f} deg at a waypoint)",
                            f"it turns back by {math.degrees(turn):.0f} deg at waypoint {k} {w[k].tolist()}")


def load_path_csv(path: str | FsPath) -> Path:
    """Load a waypoint CSV (columns ``x,y`` [m]) as an arc-length parametrised path.

    Raises:
        PathError: the file cannot be read, or its waypoints make no path, or it crosses itself with a loop
            too short to follow (:func:`check_loops`; the message names the file).
    """
    waypoints = load_waypoints_csv(path)
    try:
        out = path_from_waypoints(waypoints)
        check_loops(out)
        return out
    except PathError as exc:
        raise PathError(f"{FsPath(path).name}: {exc.name}", exc.value, exc.expected, exc.detail) from None
