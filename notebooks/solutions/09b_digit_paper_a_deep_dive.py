"""Solutions of notebook 09b (the deep dive of paper A on the full-body robot)."""

from __future__ import annotations

import numpy as np


def step_mismatch(records):
    """(steps (n,), mismatch (n, 5)): each step's exchange state minus what the executed plan of the previous step predicted."""
    first, last = {}, {}
    for r in records:
        first.setdefault(r.step_index, r)
        if r.result is not None:
            last[r.step_index] = r
    steps = [k for k in sorted(first) if k - 1 in last]
    mismatch = np.array([first[k].x0 - last[k - 1].result.states[1] for k in steps]).reshape(-1, 5)
    return np.array(steps), mismatch
