"""Stepping stones as MuJoCo terrain for the full-body robot (paper B §V on Digit).

:func:`stones_scene_editor` returns a scene editor for :class:`~lipmpcc.sim.robot_sim.RobotSim`
(``RobotSim(robot, scene_editor=...)``): it edits the ``mujoco.MjSpec`` of the scene before it is
compiled so that

- every stone of a :class:`~lipmpcc.terrain.StoneSequence` is a static box whose top is at
  ``top`` (z = 0, the standing robot's sole height) and ``depth`` deep (0.3 m);
- the floor plane is lowered by ``pit_depth`` (0.6 m): between the stones there is a pit, so a foot
  that misses its stone really falls (no hidden floor catches it);
- the approach walk (the free footholds before the first stone) is on a solid platform at z = 0
  from behind the standing robot to ``approach_margin`` past the last approach foothold;
- an exit platform starts at the far edge of the last stone, so that the run can take a couple of
  steps after the course (a fall after the last stone is still seen).

**Stone size.** Paper B's stone rectangle (0.2 × 0.1 m, :data:`lipmpcc.terrain.STONE_SIZE`) bounds the
*foot centre* (the green rectangles of its Fig. 4, drawn on larger grey stones). The physical box is
that rectangle grown by the foot's length and width (``foot_margin``, default the robot's
``foot_length × foot_width``, 0.235 × 0.08 m for digit_like: 0.435 × 0.18 m boxes), so every foot whose
centre is inside the bounds is fully supported and a foot starts to overhang as soon as its centre
leaves them. Neighbouring boxes may overlap on the short profiles; that changes nothing for the feet.

**Contacts stay cheap.** The new geoms are static world geoms with the contype/conaffinity of the scene's
own floor (``0 / 1`` for the project's floor, 127 for Digit v3's): they touch the feet and nothing else,
MuJoCo never tests world geoms against each other, and the broad phase prunes the stones far from the
feet (the step time grows by a few %).

:class:`StonesRobotSim` is the simulator on such a course; its fall criterion adds "a sole more than
``pit_tolerance`` below the stone tops" (a foot in the pit) to the simulator's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from . import render as _render  # noqa: F401  (chooses a headless GL backend before mujoco is imported)
import mujoco  # noqa: E402

from ..exceptions import InvalidInputError, ParameterError
from ..robots.description import RobotDescription
from ..robots.loading import load_robot
from ..terrain import StoneSequence
from .robot_sim import RobotSim
from .types import FallCriterion

__all__ = ["StonesSceneParams", "SceneBox", "scene_boxes", "stones_scene_editor", "StonesRobotSim"]

_PLANE_TYPES = ("mjGEOM_PLANE", "mjGEOM_HFIELD")


@dataclass(frozen=True)
class StonesSceneParams:
    """Geometry of the stepping-stone scene (lengths [m], world frame; the course runs along +x).

    Attributes:
        top: height of the stone tops and of the platforms (the standing soles' height) [m].
        depth: height of the stone boxes below ``top`` [m].
        pit_depth: how far below ``top`` the floor plane is moved [m] (> depth: a pit between stones).
        foot_margin: (x, y) added to each stone's foot-centre rectangle to get the physical box [m];
            None: the robot's foot length and width.
        approach_back: the approach platform starts this far behind the first standing foot [m].
        approach_margin: the approach platform ends this far past the last approach foothold [m].
        exit_length: length of the exit platform after the last stone [m].
        platform_half_width: half width of both platforms about their footholds' mean y [m].
        pit_tolerance: a sole this far below ``top`` is in the pit (a fall) [m].
        rgba: colour of the stones (the platforms are slightly darker).
    """

    top: float = 0.0
    depth: float = 0.3
    pit_depth: float = 0.6
    foot_margin: tuple[float, float] | None = None
    approach_back: float = 0.6
    approach_margin: float = 0.15
    exit_length: float = 2.0
    platform_half_width: float = 1.0
    pit_tolerance: float = 0.08
    rgba: tuple[float, float, float, float] = (0.62, 0.6, 0.56, 1.0)

    def __post_init__(self) -> None:
        if not math.isfinite(self.top):
            raise ParameterError("top", self.top, "a finite height [m]")
        for name in ("depth", "pit_depth", "approach_back", "approach_margin", "exit_length",
                     "platform_half_width", "pit_tolerance"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0.0):
                raise ParameterError(name, v, "a positive length [m]")
        if self.pit_depth <= self.depth:
            raise ParameterError("pit_depth", self.pit_depth, f"deeper than the stones (depth = {self.depth} m)")
        if self.foot_margin is not None:
            fm = np.asarray(self.foot_margin, dtype=float)
            if fm.shape != (2,) or not np.all(np.isfinite(fm)) or np.any(fm < 0):
                raise ParameterError("foot_margin", self.foot_margin, "None or (x, y) >= 0 [m]")
            object.__setattr__(self, "foot_margin", (float(fm[0]), float(fm[1])))


@dataclass(frozen=True)
class SceneBox:
    """One static box of the scene: ``center`` (3,) and ``half_size`` (3,) [m]; ``kind`` is
    ``"stone"``, ``"approach"`` or ``"exit"``; ``index`` the stone's index in the sequence (-1 for
    platforms)."""

    name: str
    kind: str
    center: tuple[float, float, float]
    half_size: tuple[float, float, float]
    index: int = -1

    def contains_xy(self, p: np.ndarray, tol: float = 0.0) -> bool:
        """True if the horizontal point ``p`` [m] is on the box's top face."""
        q = np.asarray(p, dtype=float)[:2]
        c = np.asarray(self.center[:2])
        h = np.asarray(self.half_size[:2])
        return bool(np.all(np.abs(q - c) <= h + tol))


def scene_boxes(
    sequence: StoneSequence,
    params: StonesSceneParams | None = None,
    foot_size: tuple[float, float] = (0.235, 0.08),
    standing_feet: np.ndarray | None = None,
) -> list[SceneBox]:
    """The boxes :func:`stones_scene_editor` adds: the approach platform, one per stone, the exit platform.

    Args:
        sequence: approach footholds (``is_stone`` False) followed by the stones, world frame.
        params: :class:`StonesSceneParams`.
        foot_size: the robot's foot (length, width) [m] (the default ``foot_margin``).
        standing_feet: (2, 2) standing sole positions (the platform starts behind them); None: the
            first foothold's x minus ``approach_back``.
    """
    p = params or StonesSceneParams()
    if not isinstance(sequence, StoneSequence) or len(sequence) == 0:
        raise InvalidInputError("sequence", sequence, "a non-empty StoneSequence")
    if not np.any(sequence.is_stone):
        raise InvalidInputError("sequence", sequence.name, "a sequence with at least one stone")
    margin = np.asarray(p.foot_margin if p.foot_margin is not None else foot_size, dtype=float)
    h = 0.5 * p.depth
    zc = p.top - h
    boxes: list[SceneBox] = []
    free = ~sequence.is_stone
    pts = [sequence.centers[free]] if np.any(free) else []
    if standing_feet is not None:
        pts.append(np.asarray(standing_feet, dtype=float).reshape(-1, 2))
    if pts:
        P = np.vstack(pts)
        x0 = float(np.min(P[:, 0])) - p.approach_back
        x1 = float(np.max(P[:, 0])) + p.approach_margin
        y = float(np.mean(P[:, 1]))
    else:
        c0 = sequence.centers[0]
        x0, x1, y = float(c0[0]) - p.approach_back - 0.5, float(c0[0]) - 0.3, float(c0[1])
    boxes.append(SceneBox("lipmpcc_approach", "approach", (0.5 * (x0 + x1), y, zc),
                          (0.5 * (x1 - x0), p.platform_half_width, h)))
    last = -1
    for i in range(len(sequence)):
        if not sequence.is_stone[i]:
            continue
        size = np.asarray(sequence.sizes[i], dtype=float)
        if not np.all(np.isfinite(size)):
            raise InvalidInputError(f"stone {i}", size.tolist(), "a finite stone size [m]")
        half = 0.5 * (size + margin)
        c = sequence.centers[i]
        boxes.append(SceneBox(f"lipmpcc_stone_{i}", "stone", (float(c[0]), float(c[1]), zc),
                              (float(half[0]), float(half[1]), h), i))
        last = i
    c = sequence.centers[last]
    half_x = 0.5 * (float(sequence.sizes[last][0]) + float(margin[0]))
    if last > 0 and float(c[0]) - float(sequence.centers[last - 1][0]) - 0.5 * float(margin[0]) < half_x:
        # a free step as long as the last one (the planner's after the course) would leave the sole's heel over
        # the pit (short steps on a robot-scaled course): the exit reaches back to the last stone's centre
        half_x = 0.0
    xe0 = float(c[0]) + half_x
    boxes.append(SceneBox("lipmpcc_exit", "exit", (xe0 + 0.5 * p.exit_length, float(c[1]), zc),
                          (0.5 * p.exit_length, p.platform_half_width, h)))
    return boxes


def stones_scene_editor(
    sequence: StoneSequence,
    params: StonesSceneParams | None = None,
    foot_size: tuple[float, float] = (0.235, 0.08),
    standing_feet: np.ndarray | None = None,
) -> Callable[[mujoco.MjSpec], None]:
    """A ``scene_editor`` for :class:`~lipmpcc.sim.robot_sim.RobotSim` that builds the course.

    It lowers every ground plane (or height field) of the world body by ``pit_depth`` (adding one at
    that depth when the scene has none, so the simulator does not add its own floor at z = 0) and adds
    the boxes of :func:`scene_boxes`, with the floor's friction.
    """
    p = params or StonesSceneParams()
    boxes = scene_boxes(sequence, p, foot_size, standing_feet)

    def edit(spec: mujoco.MjSpec) -> None:
        plane_types = {getattr(mujoco.mjtGeom, t) for t in _PLANE_TYPES}
        friction = None
        found = False
        contype, conaffinity = 0, 1  # the project's floor: touches geoms of contype 1 (the feet)
        for g in spec.worldbody.geoms:
            if g.type in plane_types:
                pos = np.array(g.pos, dtype=float)
                pos[2] = p.top - p.pit_depth
                g.pos = pos
                if friction is None:
                    friction = np.array(g.friction, dtype=float)
                    # collide like the scene's own floor (Digit v3's: conaffinity 127, its right leg
                    # has contype 4 and would fall through stones with conaffinity 1)
                    contype, conaffinity = int(g.contype), int(g.conaffinity)
                found = True
        if not found:
            spec.worldbody.add_geom(
                name="lipmpcc_pit_floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.0, 0.0, 0.05],
                pos=[0.0, 0.0, p.top - p.pit_depth], contype=0, conaffinity=1, condim=3,
                rgba=[0.25, 0.28, 0.32, 1.0],
            )
        if friction is None:
            friction = np.array([1.0, 0.005, 0.0001])
        for b in boxes:
            rgba = list(p.rgba) if b.kind == "stone" else [0.8 * c for c in p.rgba[:3]] + [1.0]
            spec.worldbody.add_geom(
                name=b.name, type=mujoco.mjtGeom.mjGEOM_BOX, pos=list(b.center), size=list(b.half_size),
                contype=contype, conaffinity=conaffinity, condim=3, friction=list(friction), rgba=rgba,
            )

    edit.boxes = boxes  # type: ignore[attr-defined]
    return edit


class StonesRobotSim(RobotSim):
    """A :class:`~lipmpcc.sim.robot_sim.RobotSim` of a robot on a stepping-stone course.

    The scene is the robot's with :func:`stones_scene_editor` applied; the fall criterion adds "a sole
    more than ``pit_tolerance`` below the stone tops" (a foot in the pit) to the simulator's.

    Args:
        robot: a :class:`~lipmpcc.robots.RobotDescription`, ``"digit_like"`` or an MJCF path.
        sequence: approach footholds + stones, world frame (:class:`~lipmpcc.terrain.StoneSequence`).
        params: :class:`StonesSceneParams`.
        standing_feet: (2, 2) standing sole positions [m] (where the approach platform starts);
            None: the description's :attr:`~lipmpcc.robots.RobotDescription.standing` soles.
        timestep, fall, log_every, contact_threshold: as for :class:`~lipmpcc.sim.robot_sim.RobotSim`.

    Attributes:
        scene_boxes: the added boxes (:class:`SceneBox`).
        scene_params: the :class:`StonesSceneParams` used.
    """

    def __init__(
        self,
        robot: RobotDescription | str | Path,
        sequence: StoneSequence,
        params: StonesSceneParams | None = None,
        standing_feet: np.ndarray | None = None,
        *,
        timestep: float = 0.0005,
        fall: FallCriterion | None = None,
        log_every: int | None = None,
        contact_threshold: float = 1.0,
    ) -> None:
        desc = robot if isinstance(robot, RobotDescription) else load_robot(robot)
        p = params or StonesSceneParams()
        if not isinstance(p, StonesSceneParams):
            raise ParameterError("params", params, "a StonesSceneParams")
        if standing_feet is None:
            standing_feet = desc.standing.feet_xy
        editor = stones_scene_editor(sequence, p, (float(desc.foot_length), float(desc.foot_width)), standing_feet)
        self.scene_boxes: list[SceneBox] = editor.boxes  # type: ignore[attr-defined]
        self.scene_params = p
        self._pit_z = p.top - p.pit_tolerance
        super().__init__(desc, timestep, fall=fall, scene_editor=editor, log_every=log_every,
                         contact_threshold=contact_threshold)

    def fall_detail(self) -> dict[str, str] | None:
        """Why the robot counts as fallen: a sole in the pit (kind ``"pit"``), or the simulator's
        criterion; None if not."""
        (pl, _), (pr, _) = self.foot_poses()
        z = min(float(pl[2]), float(pr[2]))
        if z < self._pit_z:
            foot = self.description.left_foot_body if float(pl[2]) <= float(pr[2]) else self.description.right_foot_body
            return {"reason": f"a foot fell into the pit between the stones (sole at z = {z:.3f} m)", "kind": "pit",
                    "body": foot, "contact": ""}
        return super().fall_detail()
