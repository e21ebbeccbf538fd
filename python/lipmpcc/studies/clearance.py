"""The whole robot's clearance to the obstacles, from its MuJoCo geometry.

The planners keep a body disk around the COM and disks around the feet clear of the obstacles; the
robot's arms, thighs and torso corners are not in those disks. :class:`BodyClearance` measures the
least distance between every geom of the robot (collision and visual geoms alike: every geom on a
robot body) and every obstacle, each a vertical prism standing on the floor (:data:`OBSTACLE_HEIGHT`
tall: the planners' obstacles are planar, so they are as tall as the robot and more): a cylinder for a
circle, a convex prism over the ellipse (a circumscribed polygon of :data:`ELLIPSE_SIDES` sides, so the
distance is never over-estimated) for an ellipse, at the obstacle's position and heading at each
sampled time. MuJoCo computes each distance (``mj_geomDistance``; negative: penetration depth) on a
copy of the robot's scene with the obstacles added as mocap bodies that collide with nothing; the
simulator's model is left alone.

It is cheap: bounding shapes (a capsule's or a cylinder's axis grown by its radius, any other geom's
bounding sphere ``geom_rbound``) give a lower bound of every (time, geom, obstacle) horizontal distance, and MuJoCo is asked only for those pairs whose bound is below the least distance found so far,
in increasing order of the bound.

:func:`swept_body` derives, from the same geometry, what the robot covers about its COM during a step (the
legs swept about the hips): the radius of the body disk the MPCC keeps clear of the obstacles on a full body
(:func:`lipmpcc.studies.path_params.body_clearance_params`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..obstacles import Obstacle

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

    from ..robots import RobotDescription

__all__ = ["OBSTACLE_HEIGHT", "ELLIPSE_SIDES", "BodyClearanceResult", "BodyClearance", "SweptBody", "swept_body",
           "arm_reach", "standing_body_radius"]

OBSTACLE_HEIGHT = 3.0  # [m] the obstacles' prisms reach from 0.5 m below the floor to this height
ELLIPSE_SIDES = 64  # sides of the prism of an elliptic obstacle
_PREFIX = "lipmpcc_obstacle_"


@dataclass(frozen=True)
class BodyClearanceResult:
    """The least clearance of a run.

    Attributes:
        min_clearance: least distance between the robot's geometry and an obstacle [m] (negative:
            penetration); +inf without obstacles or samples.
        time: when [s] (NaN without).
        geom: the robot's geom there (its name, or its body's name and index), "" without.
        obstacle: the obstacle's index (-1 without).
        queries: distances MuJoCo computed; samples: configurations examined; cost: wall time [s].
    """

    min_clearance: float
    time: float
    geom: str
    obstacle: int
    queries: int
    samples: int
    cost: float


def _add_obstacle(spec: "mujoco.MjSpec", j: int, ob: Obstacle) -> None:
    """Obstacle ``j`` as a mocap body with one geom that collides with nothing."""
    import mujoco

    half = 0.5 * (OBSTACLE_HEIGHT + 0.5)
    body = spec.worldbody.add_body(name=f"{_PREFIX}{j}", mocap=True, pos=[0.0, 0.0, 0.0])
    kw = {"contype": 0, "conaffinity": 0, "group": 5, "pos": [0.0, 0.0, OBSTACLE_HEIGHT - half]}
    if ob.is_circle:
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[ob.axes[0], half, 0.0], **kw)
        return
    n = ELLIPSE_SIDES
    grow = 1.0 / math.cos(math.pi / n)  # the polygon circumscribes the ellipse
    ang = 2.0 * math.pi * np.arange(n) / n
    xy = np.column_stack([grow * ob.axes[0] * np.cos(ang), grow * ob.axes[1] * np.sin(ang)])
    verts = np.vstack([np.column_stack([xy, np.full(n, -half)]), np.column_stack([xy, np.full(n, half)])])
    spec.add_mesh(name=f"{_PREFIX}mesh_{j}", uservert=verts.reshape(-1).tolist())
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"{_PREFIX}mesh_{j}", **kw)


class BodyClearance:
    """Distances between a robot's MuJoCo geometry and planar obstacles (module doc).

    Args:
        robot: the robot (its ``scene_path`` is compiled again, with the obstacles added).
        obstacles: the obstacles (moving ones are placed at each sample's time).

    Raises:
        InvalidInputError: an obstacle that is not a :class:`~lipmpcc.obstacles.Obstacle`.
    """

    def __init__(self, robot: RobotDescription, obstacles: Sequence[Obstacle]) -> None:
        import mujoco

        from ..robots.mjcf import compile_scene

        self.obstacles = list(obstacles)
        for i, ob in enumerate(self.obstacles):
            if not isinstance(ob, Obstacle):
                raise InvalidInputError(f"obstacles[{i}]", ob, "a lipmpcc.obstacles.Obstacle")

        def add_all(spec: "mujoco.MjSpec") -> None:
            for j, ob in enumerate(self.obstacles):
                _add_obstacle(spec, j, ob)

        self.model = compile_scene(Path(robot.scene_path), add_all)
        self.data = mujoco.MjData(self.model)
        m = self.model
        obstacle_bodies = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"{_PREFIX}{j}") for j in range(len(self.obstacles))}
        self.obstacle_geoms = np.array([int(np.flatnonzero(m.geom_bodyid == b)[0]) for b in
                                        [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"{_PREFIX}{j}")
                                         for j in range(len(self.obstacles))]], dtype=int)
        skip = (mujoco.mjtGeom.mjGEOM_PLANE, mujoco.mjtGeom.mjGEOM_HFIELD)
        self.robot_geoms = np.array([g for g in range(m.ngeom) if m.geom_bodyid[g] != 0
                                     and int(m.geom_bodyid[g]) not in obstacle_bodies and m.geom_type[g] not in skip],
                                    dtype=int)
        self.mocap = np.array([m.body_mocapid[m.geom_bodyid[g]] for g in self.obstacle_geoms], dtype=int)
        self.nq = int(robot.scene_model.nq)
        if self.nq != m.nq:  # pragma: no cover - mocap bodies add no coordinates
            raise InvalidInputError("robot", robot.name, "a scene whose coordinates the obstacles leave unchanged")

    def geom_name(self, g: int) -> str:
        """A robot geom's name, or ``body[index]`` for an unnamed geom."""
        import mujoco

        m = self.model
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, int(g))
        return name or f"{mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[g]))}[{int(g)}]"

    def _poses(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The obstacles' centres (k, n, 2) [m] and headings (k, n) [rad] at ``times`` (k,) [s]."""
        k, n = len(times), len(self.obstacles)
        centers, headings = np.zeros((k, n, 2)), np.zeros((k, n))
        for j, ob in enumerate(self.obstacles):
            centers[:, j] = np.atleast_2d(np.asarray(ob.center(times), dtype=float))
            headings[:, j] = np.broadcast_to(np.asarray(ob.heading(times), dtype=float), (k,))
        return centers, headings

    def _place(self, qpos: np.ndarray, centers: np.ndarray, headings: np.ndarray) -> None:
        """The robot at ``qpos``, the obstacles at ``centers`` (n, 2) [m] and ``headings`` (n,) [rad];
        kinematics computed."""
        import mujoco

        d = self.data
        d.qpos[:] = qpos
        d.mocap_pos[self.mocap, :2] = centers
        d.mocap_pos[self.mocap, 2] = 0.0
        d.mocap_quat[self.mocap] = np.column_stack([np.cos(0.5 * headings), np.zeros((len(headings), 2)),
                                                    np.sin(0.5 * headings)])
        mujoco.mj_kinematics(self.model, d)

    def _query(self, geom: int, obstacle: int, distmax: float) -> float:
        import mujoco

        return float(mujoco.mj_geomDistance(self.model, self.data, int(geom), int(self.obstacle_geoms[obstacle]),
                                            float(distmax), None))

    def distance(self, qpos: np.ndarray, t: float, geom: int, obstacle: int, distmax: float = 10.0) -> float:
        """The distance [m] between robot geom ``geom`` at ``qpos`` and obstacle ``obstacle`` at time ``t`` [s]
        (at most ``distmax``; negative: penetration)."""
        centers, headings = self._poses(np.array([float(t)]))
        self._place(np.asarray(qpos, dtype=float), centers[0], headings[0])
        return self._query(geom, obstacle, distmax)

    def _bounds(self, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Each geom's horizontal bound at each configuration: its axis ends (k, G, 2, 2) [m] and radius
        (G,) [m] — a capsule's or a cylinder's axis grown by its radius, any other geom's bounding sphere."""
        import mujoco

        m, d = self.model, self.data
        geoms = self.robot_geoms
        axial = np.isin(m.geom_type[geoms], (int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER)))
        half = np.where(axial, m.geom_size[geoms, 1], 0.0)
        radius = np.where(axial, m.geom_size[geoms, 0], m.geom_rbound[geoms])
        ends = np.empty((len(qpos), len(geoms), 2, 2))
        for i in range(len(qpos)):
            d.qpos[:] = qpos[i]
            mujoco.mj_kinematics(m, d)
            axis = d.geom_xmat[geoms].reshape(-1, 3, 3)[:, :2, 2] * half[:, None]
            ends[i, :, 0] = d.geom_xpos[geoms, :2] - axis
            ends[i, :, 1] = d.geom_xpos[geoms, :2] + axis
        return ends, radius

    def _sizes(self, which: np.ndarray) -> np.ndarray:
        """The bounding radii [m] of obstacles ``which`` (an ellipse's prism circumscribes it)."""
        grow = 1.0 / math.cos(math.pi / ELLIPSE_SIDES)
        return np.array([max(self.obstacles[j].axes) * (1.0 if self.obstacles[j].is_circle else grow) for j in which])

    @staticmethod
    def _segment_gaps(ends: np.ndarray, radius: np.ndarray, centers: np.ndarray, sizes: np.ndarray) -> np.ndarray:
        """Lower bounds (k, G, n) [m]: the gap between each geom's bound (``ends`` (k, G, 2, 2), ``radius``
        (G,)) and each obstacle's bounding circle (``centers`` (k, n, 2), ``sizes`` (n,))."""
        a, ab = ends[:, :, None, 0], (ends[:, :, 1] - ends[:, :, 0])[:, :, None]
        ac = centers[:, None, :, :] - a
        den = np.maximum(np.sum(ab * ab, axis=3), 1e-18)
        t = np.clip(np.sum(ac * ab, axis=3) / den, 0.0, 1.0)
        return np.linalg.norm(ac - t[..., None] * ab, axis=3) - radius[None, :, None] - sizes[None, None, :]

    def _lower_bounds(self, qpos: np.ndarray, centers: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lower bounds (k, G, n') [m] of the distances to the obstacles that can hold the least one, and
        their indices (n',): a disk around the whole robot prunes the obstacles farther than the nearest
        obstacle's farthest bound first."""
        ends, radius = self._bounds(qpos)
        sizes = self._sizes(np.arange(len(self.obstacles)))
        mid = 0.5 * (ends[:, :, 0] + ends[:, :, 1])  # (k, G, 2)
        hub = np.mean(mid, axis=1)  # (k, 2)
        reach = np.max(np.linalg.norm(ends - hub[:, None, None, :], axis=3).max(axis=2) + radius[None, :], axis=1)  # (k,)
        dist = np.linalg.norm(centers - hub[:, None, :], axis=2)  # (k, n)
        coarse_lo = dist - reach[:, None] - sizes[None, :]
        coarse_hi = dist + reach[:, None] + sizes[None, :]  # no robot point is farther from an obstacle's centre
        keep = np.flatnonzero(coarse_lo.min(axis=0) <= coarse_hi.min())
        return self._segment_gaps(ends, radius, centers[:, keep], sizes[keep]), keep

    def measure(self, qpos: np.ndarray, times: np.ndarray) -> BodyClearanceResult:
        """The least clearance over the configurations ``qpos`` (k, nq) at ``times`` (k,) [s] (configurations
        that are not finite, e.g. of a diverged simulation, are left out)."""
        w0 = time.perf_counter()
        qpos = np.atleast_2d(np.asarray(qpos, dtype=float))
        times = np.asarray(times, dtype=float).reshape(-1)
        if qpos.shape != (len(times), self.nq):
            raise InvalidInputError("qpos", qpos.shape, f"({len(times)}, {self.nq}): one configuration per time")
        finite = np.all(np.isfinite(qpos), axis=1) & np.isfinite(times)  # a diverged simulation's last states
        qpos, times = qpos[finite], times[finite]
        if not self.obstacles or not len(times):
            return BodyClearanceResult(math.inf, math.nan, "", -1, 0, len(times), time.perf_counter() - w0)
        centers, headings = self._poses(times)
        lb, keep = self._lower_bounds(qpos, centers)
        flat_lb = lb.reshape(-1)
        placed = -1

        def query(flat: int, distmax: float) -> tuple[float, tuple[int, int, int]]:
            nonlocal placed
            i, g, jj = np.unravel_index(flat, lb.shape)
            if i != placed:
                self._place(qpos[i], centers[i], headings[i])
                placed = int(i)
            geom, j = int(self.robot_geoms[g]), int(keep[jj])
            return self._query(geom, j, distmax), (int(i), geom, j)

        # the pair with the least bound first (the bound is within ~1 m of its distance), then, in increasing
        # order of their bounds, the pairs it does not already beat
        first = int(np.argmin(flat_lb))
        best, where = query(first, float(flat_lb[first]) + 10.0)
        queries = 1
        rest = np.flatnonzero(flat_lb < best)
        rest = rest[rest != first]
        for flat in rest[np.argsort(flat_lb[rest], kind="stable")]:
            if flat_lb[flat] >= best:
                break
            dist, at = query(int(flat), best)
            queries += 1
            if dist < best:
                best, where = dist, at
        i, g, j = where
        return BodyClearanceResult(best, float(times[i]), self.geom_name(g) if j >= 0 else "", j, queries, len(times),
                                   time.perf_counter() - w0)


#: the horizontal outline of a geom: points (k, 3) [m] in the world frame and a radius [m] around them
_Outline = tuple[np.ndarray, float]


def _geom_outline(m: "mujoco.MjModel", d: "mujoco.MjData", g: int) -> _Outline:
    """Geom ``g``'s outline at ``d``'s kinematics: a capsule's or a cylinder's axis ends and its radius, any
    other geom's bounding-box corners in its own frame (exact for a box, never an under-estimate) and 0."""
    import mujoco

    rot = d.geom_xmat[g].reshape(3, 3)
    if int(m.geom_type[g]) in (int(mujoco.mjtGeom.mjGEOM_CAPSULE), int(mujoco.mjtGeom.mjGEOM_CYLINDER)):
        return d.geom_xpos[g] + np.outer([-1.0, 1.0], rot[:, 2] * m.geom_size[g, 1]), float(m.geom_size[g, 0])
    box = m.geom_aabb[g, :3] + _CORNERS * m.geom_aabb[g, 3:]
    return d.geom_xpos[g] + box @ rot.T, 0.0


_CORNERS = np.array([[sx, sy, sz] for sx in (-1.0, 1.0) for sy in (-1.0, 1.0) for sz in (-1.0, 1.0)])


def _leg_pivots(robot: RobotDescription, m: "mujoco.MjModel", d: "mujoco.MjData") -> dict[int, tuple[float, float]]:
    """The bodies of each leg (the subtree of the torso's child that holds a foot body) mapped to the leg's
    pivot height (its first body's, the hip) and its sole height [m], at ``d``'s kinematics."""
    import mujoco

    torso = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, robot.torso_body)
    out: dict[int, tuple[float, float]] = {}
    for side in ("left", "right"):
        foot = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, robot.foot_body(side))
        root = foot
        while root > 0 and int(m.body_parentid[root]) != torso:
            root = int(m.body_parentid[root])
        if root <= 0:
            raise InvalidInputError("robot", robot.name, f"a {side} foot body below the torso body {robot.torso_body!r}")
        sole_z = float(robot.standing.sole(side)[2])
        for b in range(m.nbody):
            a = b
            while a > 0 and a != root:
                a = int(m.body_parentid[a])
            if a == root:
                out[b] = (float(d.xpos[root, 2]), sole_z)
    return out


@dataclass(frozen=True)
class SweptBody:
    """The horizontal extent of a robot about its COM over a step, in the heading frame (x forward, y left).

    Attributes:
        radius: the largest horizontal distance [m] from the COM of any point of the robot's geometry over
            the step: the radius of the body disk about the COM that holds the whole robot.
        front, back: how far the geometry reaches ahead of and behind the COM along the heading [m].
        half_width: how far it reaches to either side of the COM [m] (the larger side).
        stride: the legs' sweep it was computed for [m] (0: standing).
        part: the body whose geometry sets ``radius``.
    """

    radius: float
    front: float
    back: float
    half_width: float
    stride: float
    part: str


def swept_body(robot: RobotDescription, stride: float = 0.0) -> SweptBody:
    """What the robot's geometry covers about its COM during a step, from its MJCF geoms (every geom on a
    robot body; a capsule's or a cylinder's axis grown by its radius, any other geom's bounding box), in
    the standing configuration's heading frame.

    The trunk and the arms keep their standing place about the COM. Each leg pivots about its hip: over a
    step its foot moves from ``stride`` behind to ``stride`` ahead of the COM along the heading (the stance
    foot from ahead to behind, the swing foot from the previous foothold to the next), so a point of the
    leg at height z moves by ±``stride`` × (z_hip − z) / (z_hip − z_sole) (clipped to [0, 1]): the foot
    by the whole stride, the thigh by part of it, the hip not at all. Both ends of the sweep are taken, so
    the trailing leg's extent behind the COM is in ``back``.

    Args:
        robot: the robot description.
        stride: the foot's largest distance ahead of or behind the COM along the heading during a step [m]
            (0: the standing geometry; the MPCC: half its largest COM distance per step, ``delta_max`` / 2).

    Raises:
        InvalidInputError: a negative or non-finite stride, or a robot without geometry.
    """
    import mujoco

    if isinstance(stride, bool) or not isinstance(stride, (int, float)) or not (math.isfinite(stride) and stride >= 0.0):
        raise InvalidInputError("stride", stride, "a non-negative leg sweep [m]")
    m = robot.scene_model
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing.qpos
    mujoco.mj_kinematics(m, d)
    yaw = float(robot.standing.torso_yaw)
    heading = np.array([[math.cos(yaw), math.sin(yaw)], [-math.sin(yaw), math.cos(yaw)]])  # world -> heading frame
    com = np.asarray(robot.standing.com, dtype=float)[:2]
    pivots = _leg_pivots(robot, m, d)
    skip = (int(mujoco.mjtGeom.mjGEOM_PLANE), int(mujoco.mjtGeom.mjGEOM_HFIELD))
    best = (-math.inf, "")
    front = back = half = -math.inf
    for g in range(m.ngeom):
        b = int(m.geom_bodyid[g])
        if b == 0 or int(m.geom_type[g]) in skip:
            continue
        pts, rad = _geom_outline(m, d, g)
        xy = (pts[:, :2] - com) @ heading.T
        if b in pivots:
            hip_z, sole_z = pivots[b]
            lam = np.clip((hip_z - pts[:, 2]) / max(hip_z - sole_z, 1e-9), 0.0, 1.0)
            shift = np.column_stack([stride * lam, np.zeros(len(lam))])
            xy = np.vstack([xy - shift, xy + shift])
        front = max(front, float(np.max(xy[:, 0])) + rad)
        back = max(back, float(np.max(-xy[:, 0])) + rad)
        half = max(half, float(np.max(np.abs(xy[:, 1]))) + rad)
        far = float(np.max(np.linalg.norm(xy, axis=1))) + rad
        if far > best[0]:
            best = (far, mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b) or f"body {b}")
    if not math.isfinite(best[0]):
        raise InvalidInputError("robot", robot.name, "a robot with geometry (no geom on a robot body)")
    return SweptBody(best[0], front, back, half, float(stride), best[1])


def arm_reach(robot: RobotDescription) -> float:
    """How far from the standing COM (horizontally) [m] an arm that swings freely can reach: for each of the
    layout's ``arm_joints``, its anchor's horizontal distance from the COM plus the farthest point of any geom
    it moves (the joint's subtree, a capsule's axis grown by its radius, any other geom's bounding box) from
    that anchor, in the standing configuration; the largest over the joints (0 without arm joints). A bound
    on what the arms cover whatever their angles (an arm on its stops reaches less)."""
    import mujoco

    m = robot.scene_model
    d = mujoco.MjData(m)
    d.qpos[:] = robot.standing.qpos
    mujoco.mj_kinematics(m, d)
    com = np.asarray(robot.standing.com, dtype=float)[:2]
    best = 0.0
    for name in robot.arm_joints:
        j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name)
        if j < 0:
            continue
        root, anchor = int(m.jnt_bodyid[j]), np.asarray(d.xanchor[j], dtype=float)
        far = 0.0
        for g in range(m.ngeom):
            b = int(m.geom_bodyid[g])
            while b > root:  # a body's parent has a smaller id: walk up to the joint's body or past it
                b = int(m.body_parentid[b])
            if b != root:
                continue
            pts, rad = _geom_outline(m, d, g)
            far = max(far, float(np.max(np.linalg.norm(pts - anchor, axis=1))) + rad)
        if far > 0.0:
            best = max(best, float(np.linalg.norm(anchor[:2] - com)) + far)
    return best


def standing_body_radius(robot: RobotDescription) -> float:
    """The horizontal radius [m] of the robot's standing geometry about its standing COM: the largest
    horizontal distance from the COM's (x, y) of any point of a robot geom (a capsule's or a cylinder's axis
    grown by its radius, the corners of any other geom's bounding box in its own frame: exact for a box,
    never an under-estimate), in the standing configuration (:func:`swept_body` with no stride).

    The planners keep a disk of ``robot_radius`` around the COM clear of the obstacles; this is the disk
    that holds the whole standing robot, arms included (``digit_like``: 0.415 m, its forearms, against
    the library's default 0.2 m; paper A's barrier has no robot radius).
    """
    return swept_body(robot, 0.0).radius
