"""Closed-loop experiments: a footstep planner driving a model, step after step.

- :mod:`lipmpcc.loops.lip`: the 3D-LIP point mass (paper A on the reduced model);
- :mod:`lipmpcc.loops.alip`: the ALIP over stepping stones (paper B on the reduced model);
- :mod:`lipmpcc.loops.fullbody`: the full body in MuJoCo under the whole-body QP.

Every loop calls its planner through the one contract of :mod:`lipmpcc.planners.base`, so a planner
written once runs in all three; and every run follows the one run contract of :mod:`lipmpcc.loops.base`
(a :class:`~lipmpcc.loops.base.Course` and a :class:`~lipmpcc.loops.base.PushSchedule` in, a
:class:`~lipmpcc.loops.base.RunRecord` out).
"""

from __future__ import annotations

__all__ = ["base", "lip", "alip", "fullbody"]
