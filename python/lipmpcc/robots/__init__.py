"""Robots: the description of a robot model, resolved once and handed down to every layer.

- :mod:`~lipmpcc.robots.description`: :class:`RobotDescription` (part names, settings, and — computed
  once — the compiled MuJoCo models and the :class:`StandingPose`);
- :mod:`~lipmpcc.robots.loading`: :func:`load_robot` (``"digit_like"`` or an MJCF path), :func:`describe_model`;
- :mod:`~lipmpcc.robots.layouts`: layout files (the shipped ``digit_like`` and ``digit_v3``, or yours);
- :mod:`~lipmpcc.robots.mjcf`: compiling MJCF files, closed-loop residuals;
- :mod:`~lipmpcc.robots.state_map`: the MuJoCo ↔ Pinocchio state map;
- :mod:`~lipmpcc.robots.wbc_model`: what the whole-body controller reads from the MJCF.

Example::

    from lipmpcc.robots import load_robot

    robot = load_robot("digit_like")
    robot.standing.com_height   # [m], measured once
"""

from .description import DIGIT_PUBLISHED_MASS, RobotDescription, StandingPose
from .layouts import LAYOUT_KEYS, MAX_ALIP_COP_RANGE, SHIPPED_LAYOUTS, read_layout_file
from .loading import describe_model, digit_like_paths, load_robot
from .mjcf import compile_mjcf, compile_scene, loop_closure_errors
from .state_map import StateMap
from .wbc_model import WbcModelData, wbc_model_data

__all__ = [
    "RobotDescription",
    "StandingPose",
    "DIGIT_PUBLISHED_MASS",
    "load_robot",
    "describe_model",
    "digit_like_paths",
    "LAYOUT_KEYS",
    "MAX_ALIP_COP_RANGE",
    "SHIPPED_LAYOUTS",
    "read_layout_file",
    "compile_mjcf",
    "compile_scene",
    "loop_closure_errors",
    "StateMap",
    "WbcModelData",
    "wbc_model_data",
]
