"""Adapters that make the reduced-model planners walk a full-body robot (planner contract of
:mod:`lipmpcc.planners.base`).

- :mod:`lipmpcc.planners.sources.mpcc`: paper A's MPCC (:class:`MpccFootstepSource`): predicts the
  state at the coming support exchange, re-plans at 15 Hz, learns the touch-down timing; and the timed
  MPCC (:class:`TimedMpccFootstepSource`), paper A's MPCC with each step's duration a decision variable,
  re-planned at 25 Hz within the step (``sources.mpcc_timed``: its deprecated old path);
- :mod:`lipmpcc.planners.sources.alip`: paper B's ALIP-MPC and ALIP-QP (:class:`AlipFootstepSource`):
  the DCM from the angular momentum about the contact point, contact-phase and landing models,
  relaxed re-solves on failure.
"""

__all__ = ["mpcc", "mpcc_timed", "alip"]
