"""A first layout of a humanoid from its MJCF alone (``lipmpcc robot init``).

:func:`guess_layout` reads a compiled model and guesses what a layout file states
(:mod:`lipmpcc.robots.layouts`):

- the floating base (the body of the free joint) as the torso;
- the feet: the two bodies (one each side of the base) that hold the robot's lowest colliding geoms
  in the reference pose (the first keyframe, else ``qpos0``), and their sole rectangle (the bottom
  face of those geoms' bounding boxes), as ``sole_offset`` in the foot body frame;
- the joint groups from the kinematic tree: the joints on the path from the base to each foot are
  the legs, the joints shared by both legs' or both arms' paths are the waist, the paths to the other
  leaves are the arms (a leaf beside the base) or the head (a leaf on the middle plane);
- a standing pose with the knees bent (:func:`crouched_pose`): the base lowered until the hip-to-sole
  height is :data:`CROUCH_RATIO` of the straight leg's, the feet kept flat where they were, solved by
  damped least squares on MuJoCo's Jacobians; the robot then stands on the ground (soles at z = 0);
- the derived sizes: the fall height (0.55 of the standing torso height), the LIP height (the
  standing COM height), the step duration (Digit's 0.4 s scaled with the pendulum time √(h/g)), the
  step width (the standing feet spacing), the forward reach (Digit's 0.55 m per 1.08 m of leg) and
  the smallest lateral step (three quarters of half the standing feet spacing).

Each guess comes with a note and how sure it is (:class:`LayoutGuess`); :func:`layout_toml` writes
the commented file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..exceptions import InvalidInputError, RobotDescriptionError
from .mjcf import compile_mjcf, names, torque_drive

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

__all__ = [
    "CROUCH_RATIO",
    "CROUCH_RANGE",
    "JOINT_LIMIT_HORIZON",
    "COP_SAFETY_FACTOR",
    "TORSION_CONE",
    "LayoutGuess",
    "guess_layout",
    "crouched_pose",
    "layout_toml",
    "write_layout",
]

#: Hip-to-sole height of the standing pose as a fraction of the straight leg's: the knees bent so
#: that the LIP height leaves leg travel (Digit-class robots stand at about 0.9).
CROUCH_RATIO = 0.9

#: The ``--crouch`` ratios ``robot init`` accepts (a joint's range may stop a deep crouch first: the
#: standing_qpos note's pose error then grows and the guess is marked ``[check]``).
CROUCH_RANGE = (0.6, 0.99)

#: The whole-body QP's joint-limit horizon [s] a new layout sets (``wbc_overrides``; the paper
#: studies' layouts leave the rows out).
JOINT_LIMIT_HORIZON = 0.1

#: The whole-body QP's CoP margin a new layout sets (``wbc_overrides``): the centre of pressure within
#: this fraction of the sole rectangle guessed from the collision geoms (the controller's default,
#: 0.9, is for a measured sole such as Digit's).
COP_SAFETY_FACTOR = 0.6

#: The whole-body QP on a new layout (``wbc_overrides``, every run): the centroidal angular momentum task's
#: weight and the posture joints' (arms, waist, head) task weight. A guessed sole's CoP box cannot absorb the
#: swing leg's angular momentum on G1 or T1 (the CoP sat at its edge in 88-94 % of G1's single-support ticks on
#: the stones, the COM 1-3 cm behind the ALIP's; on T1's circle the stance foot rolled onto a corner and spun);
#: with the posture joints free and the momentum damped, the upper body takes it (docs/design.md, "Paper B on
#: smaller humanoids", and docs/add_a_robot.md, Appendix B, session 41). Paper B's runs only until session 41 (an
#: ``alip_wbc_overrides`` table); in every run since: T1's circle completes with them. Digit's layouts state none.
ANGULAR_MOMENTUM_WEIGHT = 1.0
UPPER_BODY_POSTURE_WEIGHT = 0.01

#: Whether a new layout turns on the whole-body QP's torsion cone (``wbc_overrides``; written either way, so
#: that a student sees the switch): a foot's yaw moment shrinks with its CoP's distance to the sole's edges.
#: Off: with it T1's MPCC runs last twice as long (circle 10.0 s against 4.8 s) but its stones get worse (5
#: stones against 12; docs/add_a_robot.md, Appendix B).
TORSION_CONE = False

#: Fraction of the standing torso height above the soles below which a robot counts as fallen
#: (digit_like: 0.55 m of 1.0 m).
_FALL_FRACTION = 0.55

#: digit_like's step duration [s] and standing COM height [m]: other robots' step durations scale
#: with the pendulum time √(h/g).
_DIGIT_STEP = (0.4, 0.953)

#: digit_like's forward reach per step (the capture-point walker's 0.55 m) over its straight leg
#: (1.08 m, hip to foot): other robots' reach scales with their legs.
_REACH_PER_LEG = 0.55 / 1.082
#: Digit v3's ALIP-MPC centre-of-pressure box (0.04, 0.015) m as fractions of its 0.235 x 0.08 m sole
_DIGIT_COP_FRACTION = (0.04 / 0.235, 0.015 / 0.08)


@dataclass
class LayoutGuess:
    """A guessed layout and what was guessed.

    Attributes:
        model_path: the MJCF.
        layout: the layout keys (as :func:`~lipmpcc.robots.layouts.read_layout_file` reads them).
        notes: (key, note, confidence) for every guess; confidence is ``"sure"``, ``"likely"`` or
            ``"check"`` (look at it before trusting a run).
        sizes: derived sizes for the comments [m] (leg length, hip spacing, COM height, ...).
    """

    model_path: Path
    layout: dict[str, Any]
    notes: list[tuple[str, str, str]] = field(default_factory=list)
    sizes: dict[str, float] = field(default_factory=dict)

    def note(self, key: str, text: str, confidence: str = "sure") -> None:
        """Record a guess about ``key``."""
        self.notes.append((key, text, confidence))

    def summary(self) -> str:
        """One line per guess: ``[confidence] key: note``."""
        return "\n".join(f"[{c}] {k}: {t}" for k, t, c in self.notes)


# ------------------------------------------------------------------------------------------------
# the tree
# ------------------------------------------------------------------------------------------------
def _free_root(m: "mujoco.MjModel", path: Path) -> tuple[int, int]:
    """(free joint id, its body) of the model's floating base."""
    import mujoco

    free = [j for j in range(m.njnt) if int(m.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE)]
    if len(free) != 1:
        raise RobotDescriptionError(str(path), [f"one floating base (a free joint; the model has {len(free)})"])
    return free[0], int(m.jnt_bodyid[free[0]])


def _path_joints(m: "mujoco.MjModel", body: int, root: int) -> list[int]:
    """The 1-DoF joints on the path from ``root`` (excluded) down to ``body``, root first."""
    chain = []
    b = body
    while b not in (root, 0):
        chain.append(b)
        b = int(m.body_parentid[b])
    joints: list[int] = []
    for c in reversed(chain):
        joints += [j for j in range(m.njnt) if int(m.jnt_bodyid[j]) == c and int(m.jnt_type[j]) in (2, 3)]
    return joints


def _colliding(m: "mujoco.MjModel", g: int) -> bool:
    return bool(m.geom_contype[g] or m.geom_conaffinity[g])


def _geom_corners(m: "mujoco.MjModel", d: "mujoco.MjData", g: int) -> np.ndarray:
    """The 8 world-frame corners of geom ``g``'s bounding box (8, 3); for a sphere, 8 times its lowest
    point (a sphere supports the foot at that point only)."""
    c, h = m.geom_aabb[g, :3], m.geom_aabb[g, 3:]
    if int(m.geom_type[g]) == 2:  # sphere: it touches the ground at one point, under its centre
        r = float(m.geom_size[g, 0])
        return np.repeat((d.geom_xpos[g] - np.array([0.0, 0.0, r]))[None, :], 8, axis=0)
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    local = c + signs * h
    R = d.geom_xmat[g].reshape(3, 3)
    return d.geom_xpos[g] + local @ R.T


def _subtree(m: "mujoco.MjModel", body: int) -> list[int]:
    out = []
    for b in range(m.nbody):
        a = b
        while a > 0 and a != body:
            a = int(m.body_parentid[a])
        if a == body:
            out.append(b)
    return out


def _find_feet(m: "mujoco.MjModel", d: "mujoco.MjData", root: int, path: Path) -> tuple[int, int]:
    """(left, right) foot bodies: the lowest colliding body on each side of the base."""
    lowest: dict[int, float] = {}
    for g in range(m.ngeom):
        b = int(m.geom_bodyid[g])
        if b == 0 or not _colliding(m, g):
            continue
        z = float(_geom_corners(m, d, g)[:, 2].min())
        lowest[b] = min(lowest.get(b, math.inf), z)
    if not lowest:
        raise RobotDescriptionError(str(path), ["colliding geoms on the robot (none collide)"])
    R0 = d.xmat[root].reshape(3, 3)
    feet = []
    for sign in (1.0, -1.0):
        side = [b for b in lowest if sign * float(R0[:, 1] @ (d.xpos[b] - d.xpos[root])) > 0.02]
        if not side:
            raise RobotDescriptionError(str(path), ["colliding bodies on both sides of the base (no foot found)"])
        feet.append(min(side, key=lambda b: lowest[b]))
    return feet[0], feet[1]


def _sole(m: "mujoco.MjModel", d: "mujoco.MjData", foot: int) -> tuple[np.ndarray, float, float, float]:
    """(sole centre in the foot body frame, length, width, flatness) of ``foot``: the rectangle of
    the bottom corners (within 1 cm of the lowest) of its colliding geoms' boxes, world x/y aligned;
    flatness: the angle between the foot body's z axis and the vertical [rad]."""
    pts = np.vstack([_geom_corners(m, d, g) for g in range(m.ngeom)
                     if int(m.geom_bodyid[g]) == foot and _colliding(m, g)])
    zmin = float(pts[:, 2].min())
    bottom = pts[pts[:, 2] < zmin + 0.01]
    lo, hi = bottom[:, :2].min(axis=0), bottom[:, :2].max(axis=0)
    centre = np.array([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), zmin])
    R = d.xmat[foot].reshape(3, 3)
    offset = R.T @ (centre - d.xpos[foot])
    tilt = math.acos(max(-1.0, min(1.0, float(R[2, 2]))))
    return offset, float(hi[0] - lo[0]), float(hi[1] - lo[1]), tilt


def _leaves(m: "mujoco.MjModel", root: int) -> list[int]:
    children = {int(m.body_parentid[b]) for b in range(1, m.nbody)}
    return [b for b in _subtree(m, root) if b not in children and b != root]


def _groups(m: "mujoco.MjModel", d: "mujoco.MjData", root: int, feet: tuple[int, int]) -> dict[str, list[int]]:
    """Leg (left then right), waist, arm (left then right) and head joints (ids, tree order)."""
    legs = [_path_joints(m, f, root) for f in feet]
    waist = [j for j in legs[0] if j in legs[1]]
    R0 = d.xmat[root].reshape(3, 3)
    arms: dict[str, list[int]] = {"left": [], "right": [], "head": []}
    for leaf in _leaves(m, root):
        if leaf in feet or any(leaf in _subtree(m, f) for f in feet):
            continue
        y = float(R0[:, 1] @ (d.xpos[leaf] - d.xpos[root]))
        key = "head" if abs(y) < 0.05 else ("left" if y > 0 else "right")
        arms[key].append(leaf)
    arm_paths = {k: [j for leaf in v for j in _path_joints(m, leaf, root)] for k, v in arms.items()}
    waist += [j for j in arm_paths["left"] if j in arm_paths["right"] and j not in waist]
    out = {
        "leg": [j for j in legs[0] if j not in waist] + [j for j in legs[1] if j not in waist],
        "waist": sorted(waist),
        "arm": [j for side in ("left", "right") for j in dict.fromkeys(arm_paths[side]) if j not in waist],
        "head": [j for j in dict.fromkeys(arm_paths["head"]) if j not in waist],
    }
    return out


# ------------------------------------------------------------------------------------------------
# the crouch
# ------------------------------------------------------------------------------------------------
def _knee(m: "mujoco.MjModel", d: "mujoco.MjData", leg: list[int], foot: int) -> int:
    """The leg joint with a lateral axis farthest from both the hip and the foot (the knee)."""
    hip, sole = d.xanchor[leg[0]], d.xpos[foot]
    lateral = [j for j in leg if abs(float(d.xaxis[j][1])) > 0.8]
    pool = lateral or leg
    return max(pool, key=lambda j: min(np.linalg.norm(d.xanchor[j] - hip), np.linalg.norm(d.xanchor[j] - sole)))


def _solve_leg(m: "mujoco.MjModel", d: "mujoco.MjData", leg: list[int], foot: int,
               target_pos: np.ndarray, target_rot: np.ndarray, iters: int = 200) -> float:
    """Damped least squares on ``leg``'s joints until ``foot`` has the target pose; the final error."""
    import mujoco

    dofs = [int(m.jnt_dofadr[j]) for j in leg]
    adrs = [int(m.jnt_qposadr[j]) for j in leg]
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    err = math.inf
    for _ in range(iters):
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        ep = target_pos - d.xpos[foot]
        Re = target_rot @ d.xmat[foot].reshape(3, 3).T
        q = np.zeros(4)
        mujoco.mju_mat2Quat(q, Re.ravel())
        er = np.zeros(3)
        mujoco.mju_quat2Vel(er, q, 1.0)
        e = np.concatenate([ep, er])
        err = float(np.linalg.norm(e))
        if err < 1e-8:
            break
        mujoco.mj_jacBody(m, d, jp, jr, foot)
        J = np.vstack([jp, jr])[:, dofs]
        dq = J.T @ np.linalg.solve(J @ J.T + 1e-6 * np.eye(6), e)
        for k, j in enumerate(leg):
            lo, hi = m.jnt_range[j] if m.jnt_limited[j] else (-math.inf, math.inf)
            d.qpos[adrs[k]] = float(np.clip(d.qpos[adrs[k]] + dq[k], lo, hi))
    return err


def crouched_pose(m: "mujoco.MjModel", qpos: np.ndarray, root_joint: int, legs: tuple[list[int], list[int]],
                  feet: tuple[int, int], ratio: float = CROUCH_RATIO) -> tuple[np.ndarray, float, float]:
    """A standing ``qpos`` with bent knees: the base lowered until the hip-to-sole height is ``ratio``
    of the straight leg's, the feet at their poses of ``qpos``; then the whole robot moved so that its
    lowest colliding point is at z = 0.

    Returns:
        (qpos, straight leg length [m], largest foot pose error [m or rad]).
    """
    import mujoco

    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    mujoco.mj_kinematics(m, d)
    targets = [(d.xpos[f].copy(), d.xmat[f].reshape(3, 3).copy()) for f in feet]
    # the straight leg: every leg joint at zero, the hip-to-foot distance
    straight = mujoco.MjData(m)
    straight.qpos[:] = qpos
    for leg in legs:
        for j in leg:
            straight.qpos[m.jnt_qposadr[j]] = 0.0
    mujoco.mj_kinematics(m, straight)
    length = float(np.mean([straight.xanchor[leg[0]][2] - straight.xpos[f][2] for leg, f in zip(legs, feet)]))
    height = float(np.mean([d.xanchor[leg[0]][2] - d.xpos[f][2] for leg, f in zip(legs, feet)]))
    base = int(m.jnt_qposadr[root_joint])
    d.qpos[base + 2] -= max(0.0, height - ratio * length)
    err = 0.0
    for leg, f, (p, R) in zip(legs, feet, targets):
        k = _knee(m, d, leg, f)
        lo, hi = m.jnt_range[k] if m.jnt_limited[k] else (-1.0, 1.0)
        bend = 0.3 if (lo + hi) >= 0 else -0.3
        adr = int(m.jnt_qposadr[k])
        if abs(d.qpos[adr]) < 0.25:
            d.qpos[adr] = bend  # off the straight-knee singularity, towards the knee's range
        err = max(err, _solve_leg(m, d, leg, f, p, R))
    mujoco.mj_kinematics(m, d)
    zmin = min(float(_geom_corners(m, d, g)[:, 2].min()) for g in range(m.ngeom)
               if int(m.geom_bodyid[g]) in feet and _colliding(m, g))
    d.qpos[base + 2] -= zmin
    return d.qpos.copy(), length, err


# ------------------------------------------------------------------------------------------------
# the guess
# ------------------------------------------------------------------------------------------------
def _names(m: "mujoco.MjModel", ids: list[int]) -> list[str]:
    import mujoco

    return [mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j) or "" for j in ids]


def _reference(m: "mujoco.MjModel", guess: LayoutGuess) -> np.ndarray:
    import mujoco

    if m.nkey > 0:
        key = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_KEY, 0) or "keyframe 0"
        guess.note("standing_qpos", f"started from the keyframe '{key}' (arms and head kept as it has them)")
        return np.array(m.key_qpos[0], dtype=float)
    guess.note("standing_qpos", "started from qpos0 (the model has no keyframe)", "likely")
    return np.array(m.qpos0, dtype=float)


def _feet_part(m: "mujoco.MjModel", d: "mujoco.MjData", feet: tuple[int, int], guess: LayoutGuess) -> None:
    import mujoco

    lay = guess.layout
    soles = [_sole(m, d, f) for f in feet]
    off, length, width, tilt = soles[0]
    lay["left_foot_body"] = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, feet[0])
    lay["right_foot_body"] = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, feet[1])
    lay["sole_offset"] = [round(float(x), 5) for x in off]
    lay["foot_length"] = round(min(s[1] for s in soles), 4)
    lay["foot_width"] = round(min(s[2] for s in soles), 4)
    sure = "sure" if max(s[3] for s in soles) < 0.02 and abs(off[1]) < 0.01 else "check"
    guess.note("feet", f"'{lay['left_foot_body']}' / '{lay['right_foot_body']}': the lowest colliding body on each "
               "side", "sure")
    guess.note("sole", f"{lay['foot_length']:.3f} x {lay['foot_width']:.3f} m, the bottom of the foot geoms' boxes "
               f"(foot frame tilted {math.degrees(max(s[3] for s in soles)):.1f} deg from flat)", sure)


def _check_crouch(crouch: float) -> float:
    """``crouch`` as a float in [:data:`CROUCH_RANGE`] (the ``--crouch`` of ``robot init``)."""
    lo, hi = CROUCH_RANGE
    ok = isinstance(crouch, (int, float)) and not isinstance(crouch, bool) and math.isfinite(crouch)
    if not ok or not lo <= float(crouch) <= hi:
        raise InvalidInputError("--crouch", crouch, f"a hip-to-sole height ratio in [{lo}, {hi}] "
                                f"(the straight leg is 1; default {CROUCH_RATIO})")
    return float(crouch)


def guess_layout(path: str | Path, crouch: float = CROUCH_RATIO) -> LayoutGuess:
    """Guess a layout for the humanoid MJCF ``path`` (see the module doc); ``crouch``: the standing pose's
    hip-to-sole height as a fraction of the straight leg's (:data:`CROUCH_RATIO`; lower bends the knees more).

    Raises:
        InvalidInputError: ``crouch`` outside :data:`CROUCH_RANGE`.
        ModelFileError: the file cannot be loaded.
        RobotDescriptionError: no single free joint, no colliding geoms, no body on one side.
    """
    import mujoco

    crouch = _check_crouch(crouch)
    path = Path(path)
    m = compile_mjcf(path)
    notes = torque_drive(m)
    guess = LayoutGuess(model_path=path, layout={"name": path.stem})
    for n in notes:
        guess.note("actuators", n)
    free, root = _free_root(m, path)
    d = mujoco.MjData(m)
    d.qpos[:] = _reference(m, guess)
    mujoco.mj_forward(m, d)
    feet = _find_feet(m, d, root, path)
    _feet_part(m, d, feet, guess)
    lay = guess.layout
    lay["torso_body"] = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, root)
    free_name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, free)
    if free_name:
        lay["base_joint"] = free_name
    guess.note("torso_body", f"'{lay['torso_body']}', the body of the free joint", "sure")
    groups = _groups(m, d, root, feet)
    for key, ids in groups.items():
        lay[f"{key}_joints"] = _names(m, ids)
    n_leg = len(groups["leg"])
    guess.note("leg_joints", f"{n_leg} joints on the paths from the base to the feet",
               "sure" if n_leg % 2 == 0 and n_leg >= 10 else "check")
    guess.note("waist/arm/head", f"{len(groups['waist'])} waist, {len(groups['arm'])} arm, {len(groups['head'])} head "
               "joints from the tree's leaves", "likely")
    legs = (_path_joints(m, feet[0], root), _path_joints(m, feet[1], root))
    legs = ([j for j in legs[0] if j not in groups["waist"]], [j for j in legs[1] if j not in groups["waist"]])
    qpos, leg_length, err = crouched_pose(m, d.qpos.copy(), free, legs, feet, ratio=crouch)
    lay["standing_qpos"] = [round(float(x), 6) for x in qpos]
    guess.note("standing_qpos", f"knees bent: hip-to-sole height {crouch:g} x the straight leg "
               f"({leg_length:.3f} m), feet flat (pose error {err:.1e})", "sure" if err < 1e-4 else "check")
    _derived(m, qpos, root, feet, leg_length, guess)
    return guess


def _derived(m: "mujoco.MjModel", qpos: np.ndarray, root: int, feet: tuple[int, int], leg_length: float,
             guess: LayoutGuess) -> None:
    """Fall height, LIP height, step duration, step width, reach and smallest lateral step from the
    standing pose and the straight leg length [m]."""
    import mujoco

    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    mujoco.mj_forward(m, d)
    off = np.asarray(guess.layout["sole_offset"], dtype=float)
    soles = [d.xpos[f] + d.xmat[f].reshape(3, 3) @ off for f in feet]
    torso_h = float(d.xpos[root][2] - min(s[2] for s in soles))
    com_h = float(d.subtree_com[root][2] - min(s[2] for s in soles))
    spacing = float(abs(soles[0][1] - soles[1][1]))
    lay = guess.layout
    lay["fall_height"] = round(_FALL_FRACTION * torso_h, 3)
    lay["step_duration"] = round(min(1.0, max(0.2, _DIGIT_STEP[0] * math.sqrt(com_h / _DIGIT_STEP[1]))), 3)
    lay["min_lateral_step"] = round(0.75 * 0.5 * spacing, 3)
    lay["lip_height"] = round(com_h, 4)
    lay["step_width"] = round(spacing, 3)
    lay["max_step_length"] = round(_REACH_PER_LEG * leg_length, 3)
    lay["touchdown_timing"] = "loop"
    sole = (float(lay["foot_length"]), float(lay["foot_width"]))
    lay["alip_cop_range"] = [round(f * x, 3) for f, x in zip(_DIGIT_COP_FRACTION, sole)]
    guess.sizes.update(torso_height=torso_h, com_height=com_h, feet_spacing=spacing,
                       mass=float(np.sum(m.body_mass)))
    guess.note("fall_height", f"{_FALL_FRACTION:g} x the standing torso height ({torso_h:.3f} m)", "sure")
    guess.note("step_duration", f"Digit's {_DIGIT_STEP[0]} s scaled by sqrt(COM height {com_h:.3f} m / "
               f"{_DIGIT_STEP[1]} m)", "likely")
    guess.note("min_lateral_step", f"3/4 of half the standing feet spacing ({spacing:.3f} m)", "likely")
    guess.note("lip_height", "the standing COM height above the soles", "sure")
    guess.note("step_width", "the standing feet spacing (Digit: 0.26 m)", "likely")
    guess.note("max_step_length", f"Digit's reach per leg length ({_REACH_PER_LEG:.3f}) x the straight leg "
               f"({leg_length:.3f} m)", "likely")
    guess.note("alip_cop_range", f"paper B's centre-of-pressure box (ankle strategy) in the same fractions of the "
               f"{sole[0]:.3f} x {sole[1]:.3f} m sole as Digit v3's (0.04, 0.015) m of its 0.235 x 0.08 m", "likely")
    guess.note("touchdown_timing", "the loop lands each foot at its planned time (\"planner\": at the first "
               "contact after 60 % of the swing, which a robot whose swing foot grazes the ground ends early)", "likely")


# ------------------------------------------------------------------------------------------------
# the file
# ------------------------------------------------------------------------------------------------
def _toml_value(v: Any) -> str:
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        items = [_toml_value(x) for x in v]
        text = "[" + ", ".join(items) + "]"
        if len(text) <= 100:
            return text
        lines, line = [], ""
        for it in items:
            if len(line) + len(it) > 96:
                lines.append(line.rstrip())
                line = ""
            line += it + ", "
        lines.append(line.rstrip())
        return "[\n  " + "\n  ".join(lines) + "\n]"
    if isinstance(v, float):
        return repr(float(v))
    return str(v)


_ORDER = ("name", "left_foot_body", "right_foot_body", "sole_offset", "foot_length", "foot_width", "torso_body",
          "base_joint", "leg_joints", "waist_joints", "arm_joints", "head_joints", "standing_qpos", "fall_height",
          "lip_height", "step_duration", "step_width", "max_step_length", "min_lateral_step",
          "touchdown_timing", "alip_cop_range")


def layout_toml(guess: LayoutGuess) -> str:
    """The commented TOML text of ``guess`` (read back by :func:`~lipmpcc.robots.layouts.read_layout_file`)."""
    by_key: dict[str, list[str]] = {}
    for key, text, conf in guess.notes:
        by_key.setdefault(key, []).append(f"# [{conf}] {text}")
    group_notes = {"left_foot_body": "feet", "sole_offset": "sole", "leg_joints": "leg_joints",
                   "waist_joints": "waist/arm/head", "torso_body": "torso_body", "standing_qpos": "standing_qpos",
                   "fall_height": "fall_height", "step_duration": "step_duration",
                   "min_lateral_step": "min_lateral_step", "lip_height": "lip_height", "step_width": "step_width",
                   "max_step_length": "max_step_length", "touchdown_timing": "touchdown_timing",
                   "alip_cop_range": "alip_cop_range"}
    out = [f"# Layout of {guess.model_path.name}, written by `lipmpcc robot init` from the MJCF alone.",
           "# Each guess says how sure it is: [sure], [likely] or [check] (look before trusting a run).",
           "# Keys: lipmpcc.robots.layouts.LAYOUT_KEYS; docs/add_a_robot.md explains each one."]
    out += [f"# [{c}] {t}" for k, t, c in guess.notes if k == "actuators"]
    for key in _ORDER:
        if key not in guess.layout:
            continue
        note_key = group_notes.get(key)
        if note_key:
            out += by_key.get(note_key, [])
        out.append(f"{key} = {_toml_value(guess.layout[key])}")
    out += ["# the whole-body QP keeps every actuated joint in its range over this horizon [s], the centre",
            "# of pressure within this fraction of the guessed sole (an upper bound of the real support) and",
            "# (torsion_cone = true) each stance foot's yaw moment within what its CoP leaves, the sole's contact",
            "# wrench cone: paper A's runs on T1 last longer, paper B's stones got worse (docs/add_a_robot.md)",
            "[wbc_overrides]", f"joint_limit_horizon = {JOINT_LIMIT_HORIZON}",
            f"cop_safety_factor = {COP_SAFETY_FACTOR}", f"torsion_cone = {'true' if TORSION_CONE else 'false'}",
            "# the upper body takes the swing leg's angular momentum the sole cannot (the QP damps the centroidal",
            "# angular momentum; the arm, waist and head postures yield): every run (paper B's only before session 41)",
            f"angular_momentum_weight = {ANGULAR_MOMENTUM_WEIGHT}",
            f"arm_posture = {{weight = {UPPER_BODY_POSTURE_WEIGHT}, kp = 100.0, kd = 20.0}}"]
    return "\n".join(out) + "\n"


def write_layout(path: str | Path, out: str | Path | None = None, *, overwrite: bool = False,
                 crouch: float = CROUCH_RATIO) -> tuple[Path, LayoutGuess]:
    """Guess the layout of the MJCF ``path`` (standing at ``crouch`` of the straight leg, :func:`guess_layout`)
    and write it to ``out`` (default: ``<model>.lipmpcc.toml`` next to the model); the file written and the guess.

    Raises:
        InvalidInputError: ``out`` exists and ``overwrite`` is false, or its folder is not writable; ``crouch``
            outside :data:`CROUCH_RANGE`.
        ModelFileError / RobotDescriptionError: as :func:`guess_layout`.
    """
    path = Path(path)
    target = Path(out) if out is not None else path.with_name(path.stem + ".lipmpcc.toml")
    if target.exists() and not overwrite:
        if out is not None:
            raise InvalidInputError("--out", str(target), "a file that does not exist yet (or pass --force to replace it)")
        raise InvalidInputError("layout", str(target), "no layout beside the model yet (pass --force to replace it, "
                                "or --out FILE to write another)")
    guess = guess_layout(path, crouch=crouch)
    try:
        target.write_text(layout_toml(guess))
    except OSError as err:
        raise InvalidInputError("--out", str(target), f"a writable file ({err.strerror}; pass --out PATH)") from None
    return target, guess
