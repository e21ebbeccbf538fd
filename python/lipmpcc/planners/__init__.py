"""Footstep planners, all behind one contract (:mod:`lipmpcc.planners.base`: :class:`PlannerInput` ->
:class:`StepPlan`, :class:`FootstepSource`), so that each runs in the LIP, ALIP and full-body loops.

=============================  =======================================================================
module                         planner
=============================  =======================================================================
``planners.base``              the contract: what a planner is given, what it returns, how it fails
``planners.mpcc``              paper A's MPCC on the 3D-LIP (:class:`MpccPlanner`)
``planners.mpcc_timed``        the MPCC with step durations as variables, re-planned within steps (:class:`TimedMpccPlanner`)
``planners.alip_mpc``          paper B's ALIP-MPC (:class:`AlipMpc`)
``planners.alip_qp``           paper B's baseline, Khadiv's step-timing QP (:class:`AlipQp`)
``planners.alip_common``       what the two ALIP planners share (result type, stones, parameters)
``planners.capture_point``     capture-point placement for a commanded speed (:class:`CapturePointPlanner`)
``planners.stone_field``       across a stone field: stone choice + ALIP-MPC placement (:class:`StoneFieldPlanner`)
``planners.presets``           the papers' named parameter sets and the parameters ``--set`` changes
``planners.sources.mpcc``      the MPCC on a full-body robot (:class:`MpccFootstepSource`)
``planners.sources.alip``      the ALIP planners on a full-body robot (:class:`AlipFootstepSource`)
=============================  =======================================================================

The names are importable from here too (loaded on first use: the solvers import CasADi).
"""

from __future__ import annotations

from .._lazy import lazy_exports

__all__ = [
    "PlannerInput",
    "StepPlan",
    "FootstepSource",
    "MpccParams",
    "MpccPlanner",
    "MpccResult",
    "TimedMpccParams",
    "TimedMpccPlanner",
    "TimedMpccResult",
    "AlipMpc",
    "AlipMpcParams",
    "AlipQp",
    "AlipQpParams",
    "AlipPlanResult",
    "CapturePointParams",
    "CapturePointPlanner",
    "StoneFieldParams",
    "StoneFieldPlanner",
    "MpccFootstepSource",
    "AlipFootstepSource",
]

_MODULE = {
    "PlannerInput": "base",
    "StepPlan": "base",
    "FootstepSource": "base",
    "MpccParams": "mpcc",
    "MpccPlanner": "mpcc",
    "MpccResult": "mpcc",
    "TimedMpccParams": "mpcc_timed",
    "TimedMpccPlanner": "mpcc_timed",
    "TimedMpccResult": "mpcc_timed",
    "AlipMpc": "alip_mpc",
    "AlipMpcParams": "alip_mpc",
    "AlipQp": "alip_qp",
    "AlipQpParams": "alip_qp",
    "AlipPlanResult": "alip_common",
    "CapturePointParams": "capture_point",
    "CapturePointPlanner": "capture_point",
    "StoneFieldParams": "stone_field",
    "StoneFieldPlanner": "stone_field",
    "MpccFootstepSource": "sources.mpcc",
    "AlipFootstepSource": "sources.alip",
}


__getattr__, __dir__ = lazy_exports(__name__, _MODULE, globals())
