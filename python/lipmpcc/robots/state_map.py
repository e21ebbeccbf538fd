"""The one map between MuJoCo's state (qpos, qvel) and Pinocchio's (q, v) for a model both load.

Pinocchio's ``buildModelFromMJCF`` keeps MuJoCo's joint order (the MJCF tree order), turns a free
joint into a free-flyer and a ball joint into a spherical joint; nq and nv are equal. Per joint:

- free: position copied; quaternion (w, x, y, z) → (x, y, z, w); linear velocity rotated from the
  world frame (MuJoCo) into the body frame (Pinocchio); angular velocity in the body frame in both;
- ball: quaternion reordered; angular velocity (body frame in both) copied;
- hinge, slide: copied.

:class:`StateMap` is used by the simulator (:class:`~lipmpcc.sim.robot_sim.RobotSim`) and by the
whole-body controller's model reading (:mod:`lipmpcc.robots.wbc_model`).
:func:`mujoco_to_pinocchio` / :func:`pinocchio_to_mujoco` do the same for a model whose only
multi-DoF joint is a free joint first, without a model at hand.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..exceptions import StateError
from ..rotations import quat_wxyz_to_rot

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

__all__ = ["StateMap", "mujoco_to_pinocchio", "pinocchio_to_mujoco"]


class StateMap:
    """Converts MuJoCo (qpos, qvel) to Pinocchio (q, v) and back for a model loaded by both.

    Args:
        model: the ``mujoco.MjModel`` (only its joint layout is read).
    """

    def __init__(self, model: "mujoco.MjModel") -> None:
        import mujoco

        self.nq = int(model.nq)
        self.nv = int(model.nv)
        self._free: list[tuple[int, int]] = []
        self._ball: list[int] = []
        for j in range(model.njnt):
            t = model.jnt_type[j]
            if t == mujoco.mjtJoint.mjJNT_FREE:
                self._free.append((int(model.jnt_qposadr[j]), int(model.jnt_dofadr[j])))
            elif t == mujoco.mjtJoint.mjJNT_BALL:
                self._ball.append(int(model.jnt_qposadr[j]))
        # q_pinocchio = qpos[_perm]: every quaternion (w, x, y, z) -> (x, y, z, w), the rest copied
        perm = np.arange(self.nq)
        for a in [a + 3 for a, _ in self._free] + self._ball:
            perm[a : a + 4] = (a + 1, a + 2, a + 3, a)
        self._perm = perm
        self._free_quat = [(a + 3, b) for a, b in self._free]  # (qpos address of w, dof address)

    @property
    def permutation(self) -> np.ndarray:
        """``q = qpos[permutation]`` (nq,): the quaternion reorder (a copy)."""
        return self._perm.copy()

    @property
    def free_quaternions(self) -> list[tuple[int, int]]:
        """(qpos address of the quaternion's w, dof address) of every free joint."""
        return list(self._free_quat)

    def check(self, a: np.ndarray, n: int, name: str) -> np.ndarray:
        """``a`` as a float array of shape (n,) with finite entries.

        Raises:
            StateError: another shape, or NaN/inf entries (``name`` in the message).
        """
        a = np.asarray(a, dtype=float)
        if a.shape != (n,):
            raise StateError(name, f"array of shape {a.shape}", f"shape ({n},)")
        if not np.all(np.isfinite(a)):
            raise StateError(name, "non-finite values", "finite numbers")
        return a


    def configuration_to_pinocchio(self, qpos: np.ndarray) -> np.ndarray:
        """Pinocchio's q for MuJoCo's qpos (every free/ball quaternion reordered), a new array."""
        return np.asarray(qpos, dtype=float).take(self._perm)

    def to_pinocchio(self, qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, v) in Pinocchio's convention from MuJoCo's (qpos, qvel).

        Raises:
            StateError: wrong shapes or non-finite values.
        """
        q = self.check(qpos, self.nq, "qpos").copy()
        v = self.check(qvel, self.nv, "qvel").copy()
        return self._convert_to_pinocchio(q, v)

    def _convert_to_pinocchio(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """In-place conversion of copies ``q``, ``v`` (no validation)."""
        q[:] = q[self._perm]
        self._rotate_free_velocities(q, v)
        return q, v

    def pinocchio_copy(self, qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """New (q, v) arrays in Pinocchio's convention from MuJoCo's float64 arrays (no validation:
        the simulator's per-tick path)."""
        q = qpos.take(self._perm)
        v = qvel.copy()
        self._rotate_free_velocities(q, v)
        return q, v


    def _rotate_free_velocities(self, q: np.ndarray, v: np.ndarray) -> None:
        """Free joints: linear velocity world -> base frame (``q`` already in Pinocchio order)."""
        for a, b in self._free_quat:
            x, y, z, w = q[a : a + 4].tolist()
            R = quat_wxyz_to_rot(w, x, y, z)
            v[b : b + 3] = R.T @ v[b : b + 3]

    def to_mujoco(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(qpos, qvel) in MuJoCo's convention from Pinocchio's (q, v).

        Raises:
            StateError: wrong shapes or non-finite values.
        """
        qpos = self.check(q, self.nq, "q").copy()
        qvel = self.check(v, self.nv, "v").copy()
        for a, b in self._free:
            x, y, z, w = qpos[a + 3 : a + 7]
            R = quat_wxyz_to_rot(w, x, y, z)
            qpos[a + 3 : a + 7] = (w, x, y, z)
            qvel[b : b + 3] = R @ qvel[b : b + 3]
        for a in self._ball:
            x, y, z, w = qpos[a : a + 4]
            qpos[a : a + 4] = (w, x, y, z)
        return qpos, qvel


def mujoco_to_pinocchio(qpos: np.ndarray, qvel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) for Pinocchio from a MuJoCo state whose first joint is a free joint, the rest 1-DoF.

    Quaternion (w, x, y, z) → (x, y, z, w); base linear velocity world → body frame.

    Raises:
        StateError: shapes that do not fit a free-joint base, or non-finite values.
    """
    qpos = np.asarray(qpos, dtype=float)
    qvel = np.asarray(qvel, dtype=float)
    if qpos.ndim != 1 or qvel.ndim != 1 or qpos.size < 7 or qvel.size != qpos.size - 1:
        raise StateError(
            "qpos/qvel", f"shapes {qpos.shape}/{qvel.shape}", "(7 + n,) and (6 + n,) for a free-joint base"
        )
    if not (np.all(np.isfinite(qpos)) and np.all(np.isfinite(qvel))):
        raise StateError("qpos/qvel", "non-finite values", "finite numbers")
    R = quat_wxyz_to_rot(*qpos[3:7])
    q = np.concatenate([qpos[:3], qpos[4:7], qpos[3:4], qpos[7:]])
    v = np.concatenate([R.T @ qvel[:3], qvel[3:]])
    return q, v


def pinocchio_to_mujoco(q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`mujoco_to_pinocchio`.

    Raises:
        StateError: shapes that do not fit a free-flyer base, or non-finite values.
    """
    q = np.asarray(q, dtype=float)
    v = np.asarray(v, dtype=float)
    if q.ndim != 1 or v.ndim != 1 or q.size < 7 or v.size != q.size - 1:
        raise StateError("q/v", f"shapes {q.shape}/{v.shape}", "(7 + n,) and (6 + n,) for a free-flyer base")
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
        raise StateError("q/v", "non-finite values", "finite numbers")
    R = quat_wxyz_to_rot(q[6], q[3], q[4], q[5])
    qpos = np.concatenate([q[:3], q[6:7], q[3:6], q[7:]])
    qvel = np.concatenate([R @ v[:3], v[3:]])
    return qpos, qvel
