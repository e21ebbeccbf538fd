"""lipmpcc: bipedal footstep planning, reproduced and taught.

Paper A: model predictive contouring control (MPCC) on the 3D-LIP, path following and overtaking.
Paper B: ALIP/DCM multi-step MPC with adaptive step duration on stepping stones.

The public API is importable from here; each name is loaded on first use, so ``import lipmpcc``
stays fast (the planners import CasADi, the plant MuJoCo). The layers, bottom to top (see
``docs/architecture.md``): core (:mod:`~lipmpcc.conventions`, :mod:`~lipmpcc.push`, ...), geometry
and models (:mod:`~lipmpcc.paths`, :mod:`~lipmpcc.terrain`, :mod:`~lipmpcc.models`),
:mod:`~lipmpcc.robots`, then :mod:`~lipmpcc.planners` / :mod:`~lipmpcc.control` /
:mod:`~lipmpcc.sim`, :mod:`~lipmpcc.loops`, :mod:`~lipmpcc.plots`, :mod:`~lipmpcc.studies`,
:mod:`~lipmpcc.reproduce` and the command line (:mod:`~lipmpcc.cli`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from . import exceptions
from ._lazy import lazy_exports
from .config import fast_mode, set_fast_mode

__version__ = "0.2.0.dev0"

#: public name -> the module that defines it
_EXPORTS: dict[str, str] = {
    # core
    "Side": "conventions", "LEFT": "conventions", "RIGHT": "conventions", "GRAVITY": "conventions",
    "Push": "push",
    # geometry and models
    "LinePath": "paths", "ArcPath": "paths", "SplinePath": "paths", "CompositePath": "paths",
    "load_path_csv": "paths", "Obstacle": "obstacles", "obstacles_from_json": "obstacles",
    "Stone": "terrain", "StoneSequence": "terrain", "make_profile": "terrain", "load_stones": "terrain",
    "Lip3dModel": "models.lip3d", "AlipParams": "models.alip",
    # robots
    "RobotDescription": "robots", "load_robot": "robots",
    # planners, control, plant
    "PlannerInput": "planners.base", "StepPlan": "planners.base", "FootstepSource": "planners.base",
    "MpccParams": "planners.mpcc", "MpccPlanner": "planners.mpcc",
    "AlipMpc": "planners.alip_mpc", "AlipMpcParams": "planners.alip_mpc",
    "AlipQp": "planners.alip_qp", "AlipQpParams": "planners.alip_qp",
    "CapturePointPlanner": "planners.capture_point", "CapturePointParams": "planners.capture_point",
    "MpccFootstepSource": "planners.sources.mpcc", "AlipFootstepSource": "planners.sources.alip",
    "WholeBodyController": "control.wbc", "WbcParams": "control.wbc_types",
    "RobotSim": "sim.robot_sim",
    # loops
    "run_lip_loop": "loops.lip", "run_alip_loop": "loops.alip",
    "FullBodyLoop": "loops.fullbody", "LoopParams": "loops.fullbody", "LoopResult": "loops.fullbody",
    "Course": "loops.base", "PushSchedule": "loops.base", "RunRecord": "loops.base",
    # studies
    "RunOptions": "studies", "RunResult": "studies", "run": "studies",
}

__all__ = ["__version__", "exceptions", "fast_mode", "set_fast_mode", *_EXPORTS]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


if TYPE_CHECKING:  # the names as static type checkers see them
    from .control.wbc import WholeBodyController
    from .control.wbc_types import WbcParams
    from .conventions import GRAVITY, LEFT, RIGHT, Side
    from .loops.alip import run_alip_loop
    from .loops.base import Course, PushSchedule, RunRecord
    from .loops.fullbody import FullBodyLoop, LoopParams, LoopResult
    from .loops.lip import run_lip_loop
    from .models.alip import AlipParams
    from .models.lip3d import Lip3dModel
    from .obstacles import Obstacle, obstacles_from_json
    from .paths import ArcPath, CompositePath, LinePath, SplinePath, load_path_csv
    from .planners.alip_mpc import AlipMpc, AlipMpcParams
    from .planners.alip_qp import AlipQp, AlipQpParams
    from .planners.base import FootstepSource, PlannerInput, StepPlan
    from .planners.capture_point import CapturePointParams, CapturePointPlanner
    from .planners.mpcc import MpccParams, MpccPlanner
    from .planners.sources.alip import AlipFootstepSource
    from .planners.sources.mpcc import MpccFootstepSource
    from .push import Push
    from .robots import RobotDescription, load_robot
    from .sim.robot_sim import RobotSim
    from .studies import RunOptions, RunResult, run
    from .terrain import Stone, StoneSequence, load_stones, make_profile
