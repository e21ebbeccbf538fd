"""The compiled control tick ``lipmpcc._mjtick``: whether it can be used, and building one.

:class:`~lipmpcc.sim.robot_sim.RobotSim` runs its MuJoCo calls, pushes, contact sums and state map
in C++ when the private module ``lipmpcc._mjtick`` is built against the running MuJoCo and
reproduces the Python path's arithmetic to the bit (:func:`check_tick_module`); otherwise, or with
``LIPMPCC_PYTHON_TICK=1``, it runs them in Python with identical results. :data:`TICK` is the
module and its rotation mode, or None.
"""

from __future__ import annotations

import os
from types import ModuleType
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from . import render as _render  # noqa: F401  (chooses a headless GL backend before mujoco is imported)
import mujoco  # noqa: E402

from ..robots.state_map import StateMap
from ..rotations import quat_wxyz_to_rot

if TYPE_CHECKING:  # pragma: no cover
    from .. import _mjtick

__all__ = ["TICK", "TickViews", "check_tick_module", "load_tick_module", "build_tick"]


def check_tick_module(mod: ModuleType) -> tuple[ModuleType, bool] | None:
    """(module, fma_rotation) when ``mod`` (``lipmpcc._mjtick``) can stand in for the Python tick, else None.

    It must be built against the MuJoCo that runs (headers and linked library: ``mj_version()``),
    have this package's measurement layout (the substep contact peaks), and reproduce
    :class:`~lipmpcc.robots.state_map.StateMap`'s base velocity rotation (numpy's
    ``R.T @ v``, whose BLAS kernel may or may not fuse multiply-adds) bit for bit on probe values;
    either mode is tried.
    """
    try:
        running = int(mujoco.mj_version())
        if int(mod.mujoco_version) != running or int(mod.linked_mujoco_version()) != running:
            return None
        if "peak" not in mod.layout(7, 6):  # a build older than the substep contact peaks
            return None
        rng = np.random.default_rng(12345)
        probes = [(rng.normal(size=4), rng.normal(size=3) * 10.0 ** rng.integers(-3, 3)) for _ in range(64)]
        for fma in (True, False):
            if all(
                np.array_equal(mod.rotate_transposed(*qt.tolist(), v, fma), quat_wxyz_to_rot(*qt.tolist()).T @ v)
                for qt, v in probes
            ):
                return mod, fma
    except Exception:  # an incompatible or broken build: keep the Python path
        return None
    return None


def load_tick_module() -> tuple[ModuleType, bool] | None:
    """The compiled tick, if it is installed and usable (see :func:`check_tick_module`).

    ``LIPMPCC_PYTHON_TICK=1`` in the environment keeps the Python path (identical results).
    """
    if os.environ.get("LIPMPCC_PYTHON_TICK", "") not in ("", "0"):
        return None
    try:
        from .. import _mjtick
    except ImportError:
        return None
    return check_tick_module(_mjtick)


#: the usable compiled tick (module, fma_rotation), or None (RobotSim reads it when it is built)
TICK = load_tick_module()


class TickViews(NamedTuple):
    """Views of a tick's measurement buffer (they change with every tick call)."""

    q: np.ndarray
    v: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    torso_pos: np.ndarray
    torso_rot: np.ndarray
    left_pos: np.ndarray
    left_rot: np.ndarray
    right_pos: np.ndarray
    right_rot: np.ndarray
    left_force: np.ndarray
    right_force: np.ndarray
    peak: np.ndarray  # (left, right) largest vertical foot force since the previous measurement [N]


def build_tick(
    tick_module: tuple[ModuleType, bool],
    model: mujoco.MjModel,
    data: mujoco.MjData,
    state_map: StateMap,
    torso: int,
    sole_sites: tuple[int, int],
    geom_side: list[int],
    geom_robot: list[bool],
    split: bool,
) -> tuple["_mjtick.Tick", np.ndarray, int, TickViews]:
    """A ``_mjtick.Tick`` on ``model``/``data``, its measurement buffer, the buffer index of the
    "non-foot contact" flag, and the views of the buffer's fields.

    Args:
        tick_module: :data:`TICK` (not None).
        model, data: the simulator's MuJoCo model and data (the tick keeps their addresses).
        state_map: the simulator's state map (its permutation and free-joint addresses).
        torso: body id of the torso; sole_sites: (left, right) site ids.
        geom_side: per geom 0 (left foot), 1 (right foot) or -1; geom_robot: per geom, a robot geom.
        split: whether a step may start with ``mj_step2`` (every integrator but RK4).
    """
    mod, fma = tick_module
    cfg = mod.TickConfig()
    cfg.torso = torso
    cfg.sole_site = sole_sites
    cfg.geom_side = geom_side
    cfg.geom_robot = [int(r) for r in geom_robot]
    cfg.perm = state_map.permutation.tolist()
    cfg.free_quat = state_map.free_quaternions
    cfg.split = split
    cfg.fma_rotation = fma
    lay = mod.layout(state_map.nq, state_map.nv)
    buf = np.zeros(lay["size"])
    tick = mod.Tick(model._address, data._address, cfg, buf)

    def vec(a: int, n: int) -> np.ndarray:
        return buf[a : a + n]

    def mat(a: int) -> np.ndarray:
        return buf[a : a + 9].reshape(3, 3)

    views = TickViews(
        vec(lay["q"], state_map.nq), vec(lay["v"], state_map.nv), vec(lay["com"], 3), vec(lay["com_vel"], 3),
        vec(lay["torso_pos"], 3), mat(lay["torso_rot"]),
        vec(lay["foot_pos"][0], 3), mat(lay["foot_rot"][0]), vec(lay["foot_pos"][1], 3), mat(lay["foot_rot"][1]),
        vec(lay["force"][0], 3), vec(lay["force"][1], 3), vec(lay["peak"][0], 2),
    )
    if lay["peak"][1] != lay["peak"][0] + 1:  # pragma: no cover (a module of another layout)
        raise RuntimeError("lipmpcc._mjtick: the contact peaks are not adjacent")
    return tick, buf, int(lay["other"]), views
