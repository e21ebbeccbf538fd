"""The MuJoCo plant: the robot model stepped and measured, pushes, terrain, falls, rendering.

- :mod:`~lipmpcc.sim.robot_sim`: :class:`RobotSim` (step, measure, push, fall);
- :mod:`~lipmpcc.sim.types`: :class:`Measurement`, :class:`FramePose`, :class:`FallCriterion`, :class:`SimLog`;
- :mod:`~lipmpcc.sim.stones_scene`: stepping stones as terrain (:class:`StonesRobotSim`);
- :mod:`~lipmpcc.sim.render`: offscreen video (:class:`VideoRecorder`, :func:`write_video`).

The closed loops that drive the plant are in :mod:`lipmpcc.loops`. The names below are imported on
first use (MuJoCo is imported then, after the OpenGL backend is chosen).
"""

from __future__ import annotations

from .._lazy import lazy_exports

__all__ = [
    "RobotSim",
    "Measurement",
    "FramePose",
    "FallCriterion",
    "SimLog",
    "StonesRobotSim",
    "StonesSceneParams",
    "SceneBox",
    "scene_boxes",
    "stones_scene_editor",
    "VideoRecorder",
    "VideoSettings",
    "write_video",
]

_HOME = {
    "RobotSim": "robot_sim",
    **dict.fromkeys(("Measurement", "FramePose", "FallCriterion", "SimLog"), "types"),
    **dict.fromkeys(("StonesRobotSim", "StonesSceneParams", "SceneBox", "scene_boxes", "stones_scene_editor"),
                    "stones_scene"),
    **dict.fromkeys(("VideoRecorder", "VideoSettings", "write_video"), "render"),
}


__getattr__, __dir__ = lazy_exports(__name__, _HOME, globals())
