"""Low-overhead evaluation of CasADi functions from Python.

A plain ``casadi.Function`` call from Python converts every argument to a DM and costs
20–80 µs; :class:`BufferedFunction` binds preallocated numpy arrays to the function's
inputs and outputs once (``Function.buffer``) so that an evaluation costs well under 1 µs
plus the numerical work. Outputs are dense; matrices come back as numpy arrays in
column-major layout, reshaped to their 2-D shape.
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np


class BufferedFunction:
    """Wrap ``name(inputs) -> outputs`` (CasADi expressions) for fast repeated calls.

    Args:
        name: function name.
        inputs: symbolic inputs (column vectors).
        outputs: expressions; they are densified.
    """

    def __init__(self, name: str, inputs: Sequence, outputs: Sequence) -> None:
        self.function = ca.Function(name, list(inputs), [ca.densify(o) for o in outputs])
        self._buf, self._eval = self.function.buffer()
        self._args = []
        for i, x in enumerate(inputs):
            a = np.zeros(int(x.numel()))
            self._buf.set_arg(i, memoryview(a))
            self._args.append(a)
        self._res = []
        self._views = []
        for j, o in enumerate(outputs):
            r = np.zeros(int(o.numel()))
            self._buf.set_res(j, memoryview(r))
            self._res.append(r)
            shape = (int(o.shape[0]), int(o.shape[1]))
            if shape[1] == 1:
                self._views.append(r)
            else:
                self._views.append(r.reshape(shape, order="F"))

    def __call__(self, *args: np.ndarray) -> list[np.ndarray]:
        """Evaluate; returns views into internal buffers (copy them to keep them)."""
        for dst, src in zip(self._args, args):
            np.copyto(dst, np.ravel(src), casting="unsafe")
        self._eval()
        return self._views
