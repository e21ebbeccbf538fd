"""Loop-closure watch for runs on the reference Digit v3 (its ``<equality connect>`` loops are soft in
MuJoCo): shared by the Digit v3 loop and study tests."""

from __future__ import annotations

import numpy as np

LOOP_TOLERANCE = 1e-3  # [m] anchor distance of any <equality connect>, over every run


class LoopWatch:
    """Wraps ``sim.step`` to record the largest loop-closure error (MuJoCo's anchor distance) [m]
    after every controller tick."""

    def __init__(self, sim) -> None:
        from lipmpcc.robots import loop_closure_errors

        self.max = 0.0
        step = sim.step

        def watched(ctrl, n=1, **kw):
            step(ctrl, n, **kw)
            self.max = max(self.max, float(np.max(loop_closure_errors(sim.model, sim.data))))

        sim.step = watched
