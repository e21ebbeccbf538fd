"""What the whole-body controller reads from a robot's MJCF, as plain values.

:func:`wbc_model_data` turns a :class:`~lipmpcc.robots.description.RobotDescription` and its compiled
MuJoCo model into a :class:`WbcModelData`: the frames from the description, and from MuJoCo the
motors (pure motors on hinge/slide joints: gear × gain, control and force ranges), the passive
springs, joint damping and dry friction, gravity, the friction pyramid of the feet, the centre of
each sole's support rectangle and the configuration at which the closed loops are checked. The
whole-body controller (:class:`~lipmpcc.control.wbc.WholeBodyController`) copies it into the C++
``WbcModelSpec``; Pinocchio reads the kinematics and inertias from the same file itself.

Friction: unless given, the pyramid coefficient is the smallest sliding friction of the foot geoms,
halved for MuJoCo's pyramidal cone (whose section is a diamond) or divided by √2 for the elliptic
cone, so that the pyramid lies inside MuJoCo's cone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..exceptions import ParameterError, RobotDescriptionError
from .description import RobotDescription
from .mjcf import check_equalities, connect_residuals_at
from .state_map import StateMap

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

__all__ = [
    "WbcModelData",
    "wbc_model_data",
    "standing_qpos",
    "foot_friction",
    "sole_cop_centers",
    "loop_closure_problems",
    "check_consistency",
]


@dataclass(frozen=True)
class WbcModelData:
    """The whole-body controller's reading of a robot model (the fields of the C++ ``WbcModelSpec``).

    Attributes:
        mjcf_path: the robot MJCF (Pinocchio builds its model from it).
        foot_bodies, sole_sites: (left, right) foot bodies and sole sites (``""``: none).
        sole_offsets: (left, right) sole centre in the foot body frame [m] (3,) (without a sole site).
        torso_body: the floating-base body.
        foot_half_length, foot_half_width: half size of the sole rectangle [m].
        sole_cop_centers: (left, right) centre (x, y) of the sole rectangle in the sole frame [m].
        friction: friction-pyramid coefficient.
        actuator_names: actuators in MuJoCo order.
        actuated_joints: the joint of each actuator.
        actuation_gains: gear × gain of each actuator (generalised force per unit of control).
        u_min, u_max: control bounds of each actuator (from ctrlrange and forcerange; ±inf: none).
        arm_joints: the joints of the posture task (:attr:`RobotDescription.posture_joints`: arms,
            waist, head and every other actuated joint but the legs).
        damping, frictionloss: MuJoCo's per-dof joint damping [N m s/rad] and dry friction [N m].
        gravity: the model's gravity vector [m/s²].
        spring_joints: hinge/slide joints with a stiffness (passive springs), MuJoCo joint order.
        spring_stiffness, spring_reference: their stiffness [N m/rad] and spring reference [rad].
        loop_reference_qpos: MuJoCo configuration at which the loops are checked and their dependent
            coordinates chosen (the standing configuration, else qpos0).
        loop_reference_configuration: the same in Pinocchio's convention.
    """

    mjcf_path: str
    foot_bodies: tuple[str, str]
    sole_sites: tuple[str, str]
    sole_offsets: tuple[np.ndarray, np.ndarray]
    torso_body: str
    foot_half_length: float
    foot_half_width: float
    sole_cop_centers: tuple[np.ndarray, np.ndarray]
    friction: float
    actuator_names: tuple[str, ...]
    actuated_joints: tuple[str, ...]
    actuation_gains: np.ndarray
    u_min: np.ndarray
    u_max: np.ndarray
    arm_joints: tuple[str, ...]
    damping: np.ndarray
    frictionloss: np.ndarray
    gravity: np.ndarray
    spring_joints: tuple[str, ...]
    spring_stiffness: np.ndarray
    spring_reference: np.ndarray
    loop_reference_qpos: np.ndarray
    loop_reference_configuration: np.ndarray


def standing_qpos(desc: RobotDescription, mj: "mujoco.MjModel") -> np.ndarray | None:
    """MuJoCo qpos of the description's standing configuration (keyframe or standing_qpos), or None."""
    import mujoco

    if desc.standing_keyframe:
        k = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_KEY, desc.standing_keyframe)
        if k >= 0:
            return np.array(mj.key_qpos[k], dtype=float)
    if desc.standing_qpos is not None and len(desc.standing_qpos) == mj.nq:
        return np.asarray(desc.standing_qpos, dtype=float)
    return None


def _actuators(desc: RobotDescription, mj: "mujoco.MjModel") -> tuple[list[str], list[str], list[float], list[float], list[float]]:
    """(names, joints, gear × gain, u_min, u_max) of the actuators: pure motors on 1-DoF joints."""
    import mujoco

    hinge_slide = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    names, joints, gains, lo, hi = [], [], [], [], []
    for a in range(mj.nu):
        aname = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_ACTUATOR, a) or f"actuator {a}"
        pure_motor = (
            int(mj.actuator_trntype[a]) == int(mujoco.mjtTrn.mjTRN_JOINT)
            and int(mj.actuator_dyntype[a]) == int(mujoco.mjtDyn.mjDYN_NONE)
            and int(mj.actuator_gaintype[a]) == int(mujoco.mjtGain.mjGAIN_FIXED)
            and int(mj.actuator_biastype[a]) == int(mujoco.mjtBias.mjBIAS_NONE)
        )
        j = int(mj.actuator_trnid[a, 0])
        if not pure_motor or int(mj.jnt_type[j]) not in hinge_slide:
            raise RobotDescriptionError(str(desc.mjcf_path), [f"a motor actuator (joint transmission, fixed gain, "
                                                              f"no bias) on a hinge/slide joint for '{aname}'"])
        gear, gain = float(mj.actuator_gear[a, 0]), float(mj.actuator_gainprm[a, 0])
        u_lo, u_hi = -math.inf, math.inf
        if mj.actuator_ctrllimited[a]:
            u_lo, u_hi = float(mj.actuator_ctrlrange[a, 0]), float(mj.actuator_ctrlrange[a, 1])
        if mj.actuator_forcelimited[a] and gain != 0.0:
            f_lo, f_hi = (float(x) / gain for x in mj.actuator_forcerange[a])
            f_lo, f_hi = min(f_lo, f_hi), max(f_lo, f_hi)
            u_lo, u_hi = max(u_lo, f_lo), min(u_hi, f_hi)
        joints.append(mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_JOINT, j) or "")
        gains.append(gear * gain)
        lo.append(u_lo)
        hi.append(u_hi)
        names.append(aname)
    return names, joints, gains, lo, hi


def _springs(desc: RobotDescription, mj: "mujoco.MjModel") -> tuple[list[str], list[float], list[float]]:
    """(joints, stiffness, reference) of the passive springs, on hinge or slide joints only."""
    import mujoco

    hinge_slide = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    sj, sk, sr = [], [], []
    for j in range(mj.njnt):
        jname = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_JOINT, j) or ""
        if float(mj.jnt_stiffness[j]) != 0.0 and int(mj.jnt_type[j]) not in hinge_slide:
            raise RobotDescriptionError(str(desc.mjcf_path), [f"springs on hinge or slide joints only (joint "
                                                              f"'{jname or f'joint {j}'}' is a ball or free joint "
                                                              "with a stiffness)"])
        if int(mj.jnt_type[j]) in hinge_slide and float(mj.jnt_stiffness[j]) != 0.0:
            sj.append(jname)
            sk.append(float(mj.jnt_stiffness[j]))
            sr.append(float(mj.qpos_spring[mj.jnt_qposadr[j]]))
    return sj, sk, sr


def sole_cop_centers(desc: RobotDescription, mj: "mujoco.MjModel") -> list[np.ndarray]:
    """Centre (x, y) of each sole rectangle in its sole frame [m]: the centre of the foot's colliding
    box when the foot body has exactly one (the Digit v3 sole sites sit 1.5 cm ahead of it), else 0."""
    import mujoco

    d = mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, d)
    out = []
    box = int(mujoco.mjtGeom.mjGEOM_BOX)
    feet = ((desc.left_foot_body, desc.left_sole_site), (desc.right_foot_body, desc.right_sole_site))
    for body_name, site_name in feet:
        b = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, body_name)
        boxes = [g for g in range(mj.ngeom) if int(mj.geom_bodyid[g]) == b and int(mj.geom_type[g]) == box
                 and (mj.geom_contype[g] or mj.geom_conaffinity[g])]
        if len(boxes) != 1 or b < 0:
            out.append(np.zeros(2))
            continue
        if site_name:
            s = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_SITE, site_name)
            origin, R = d.site_xpos[s], d.site_xmat[s].reshape(3, 3)
        else:
            R = d.xmat[b].reshape(3, 3)
            origin = d.xpos[b] + R @ np.asarray(desc.sole_offset, dtype=float)
        out.append(np.asarray(R.T @ (d.geom_xpos[boxes[0]] - origin))[:2].copy())
    return out


def foot_friction(desc: RobotDescription, mj: "mujoco.MjModel") -> float:
    """Pyramid coefficient inside MuJoCo's friction cone for the foot geoms (see the module doc).

    Raises:
        RobotDescriptionError: a foot body without a colliding geom.
    """
    import mujoco

    feet = {
        mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, desc.left_foot_body),
        mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, desc.right_foot_body),
    }
    mus = [
        float(mj.geom_friction[g, 0])
        for g in range(mj.ngeom)
        if int(mj.geom_bodyid[g]) in feet and (mj.geom_contype[g] or mj.geom_conaffinity[g])
    ]
    if not mus:
        raise RobotDescriptionError(str(desc.mjcf_path), ["a colliding geom on each foot body"])
    mu = min(mus)
    pyramidal = int(mj.opt.cone) == int(mujoco.mjtCone.mjCONE_PYRAMIDAL)
    return mu / 2.0 if pyramidal else mu / math.sqrt(2.0)


def _friction(desc: RobotDescription, mj: "mujoco.MjModel", friction: float | None) -> float:
    if friction is None:
        return foot_friction(desc, mj)
    if not (isinstance(friction, (int, float)) and math.isfinite(friction) and friction > 0):
        raise ParameterError("friction", friction, "a positive friction coefficient")
    return float(friction)


def wbc_model_data(
    desc: RobotDescription, mj: "mujoco.MjModel | None" = None, friction: float | None = None
) -> WbcModelData:
    """The :class:`WbcModelData` of ``desc`` (``mj``: its compiled model, None: ``desc.model``).

    Args:
        desc: the robot description.
        mj: the compiled robot MJCF (None: :attr:`RobotDescription.model`).
        friction: friction-pyramid coefficient (None: from the foot geoms).

    Raises:
        RobotDescriptionError: an equality constraint that is not an active body ``connect``, a
            non-positive foot size, an actuator that is not a pure motor on a hinge/slide joint, a
            spring on a ball or free joint, a foot without a colliding geom.
        ParameterError: a bad ``friction``.
    """
    mj = desc.model if mj is None else mj
    path = str(desc.mjcf_path)
    check_equalities(mj, path)
    if not (desc.foot_length > 0 and desc.foot_width > 0):
        raise RobotDescriptionError(path, [f"a positive foot size (got {desc.foot_length} x {desc.foot_width} m)"])
    centers = sole_cop_centers(desc, mj)
    names, joints, gains, lo, hi = _actuators(desc, mj)
    sj, sk, sr = _springs(desc, mj)
    mu = _friction(desc, mj, friction)
    qpos = standing_qpos(desc, mj)
    qpos = np.array(mj.qpos0 if qpos is None else qpos, dtype=float)
    offset = np.asarray(desc.sole_offset, dtype=float)
    return WbcModelData(
        mjcf_path=path,
        foot_bodies=(desc.left_foot_body, desc.right_foot_body),
        sole_sites=(desc.left_sole_site or "", desc.right_sole_site or ""),
        sole_offsets=(offset, offset),
        torso_body=desc.torso_body,
        foot_half_length=0.5 * float(desc.foot_length),
        foot_half_width=0.5 * float(desc.foot_width),
        sole_cop_centers=(centers[0], centers[1]),
        friction=mu,
        actuator_names=tuple(names),
        actuated_joints=tuple(joints),
        actuation_gains=np.asarray(gains),
        u_min=np.asarray(lo),
        u_max=np.asarray(hi),
        arm_joints=desc.posture_joints,
        damping=np.array(mj.dof_damping, dtype=float),  # Pinocchio's reader skips ball joints
        frictionloss=np.array(mj.dof_frictionloss, dtype=float),
        gravity=np.array(mj.opt.gravity, dtype=float),  # 9.80665 in digit_like and Digit v3 (Pinocchio: 9.81)
        spring_joints=tuple(sj),
        spring_stiffness=np.asarray(sk, dtype=float),
        spring_reference=np.asarray(sr, dtype=float),
        loop_reference_qpos=qpos,
        loop_reference_configuration=StateMap(mj).configuration_to_pinocchio(qpos),
    )


def loop_closure_problems(data: WbcModelData, mj: "mujoco.MjModel", n_loops: int,
                          pinocchio_residuals: np.ndarray) -> list[str]:
    """What is wrong with Pinocchio's reading of the loops (empty: nothing): the same count as
    MuJoCo's connects, the same anchor offsets at the reference configuration (1 µm), and closed
    there (1 mm).

    Args:
        data: the model data (its loop reference configuration).
        mj: the compiled robot MJCF.
        n_loops: the loops Pinocchio parsed.
        pinocchio_residuals: Pinocchio's anchor offsets at the reference configuration [m] (3 per loop).
    """
    if n_loops != mj.neq:
        return [f"{mj.neq} loop closures in Pinocchio's reading of the file "
                f"(it parsed {n_loops} of the {mj.neq} <equality connect>)"]
    mj_res = connect_residuals_at(mj, data.loop_reference_qpos)
    pin_res = np.asarray(pinocchio_residuals).reshape(-1, 3)
    if not np.allclose(pin_res, mj_res, atol=1e-6):
        return ["the same loop anchors in Pinocchio and MuJoCo (the <equality connect> "
                f"offsets differ by {np.max(np.abs(pin_res - mj_res)):.2e} m)"]
    worst = float(np.max(np.linalg.norm(mj_res, axis=1)))
    if worst > 1e-3:
        return [f"a standing configuration in which the loops close (the <equality "
                f"connect> anchors are {worst * 1e3:.1f} mm apart)"]
    return []


def check_consistency(data: WbcModelData, mj: "mujoco.MjModel", nq: int, nv: int, damping: np.ndarray) -> None:
    """Pinocchio (``nq``, ``nv``, its ``damping``) and MuJoCo must agree on the velocity layout and
    the joint damping passed on.

    Raises:
        RobotDescriptionError: they do not.
    """
    if int(nv) != int(mj.nv) or int(nq) != int(mj.nq):
        raise RobotDescriptionError(
            data.mjcf_path, [f"the same nq/nv in Pinocchio ({nq}/{nv}) and MuJoCo ({mj.nq}/{mj.nv})"]
        )
    if not np.allclose(np.asarray(damping)[6:], mj.dof_damping[6:], rtol=1e-9, atol=1e-12):
        raise RobotDescriptionError(data.mjcf_path, ["the same joint damping in Pinocchio and MuJoCo"])
