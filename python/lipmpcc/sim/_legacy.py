"""Deprecated names of :mod:`lipmpcc.sim.robot_sim` kept for one release (see CHANGELOG.md).

:class:`Rates` was never used by the package (the loops take their rates from their own
parameters); it is reached through ``lipmpcc.sim.robot_sim.Rates`` with a DeprecationWarning and
removed in lipmpcc 0.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..exceptions import ParameterError

__all__ = ["Rates"]


@dataclass(frozen=True)
class Rates:
    """Loop rates [Hz]: simulation, whole-body control (a divisor of it), planner (its own rate).

    Attributes:
        sim_hz: MuJoCo rate (2000 Hz: 0.5 ms steps).
        wbc_hz: whole-body QP rate (400 Hz default; up to ``sim_hz``).
        planner_hz: footstep planner rate (e.g. 15 Hz for paper A, 25 Hz for paper B); rounded to
            whole controller ticks by the loop.
    """

    sim_hz: float = 2000.0
    wbc_hz: float = 400.0
    planner_hz: float = 15.0

    def __post_init__(self) -> None:
        for name in ("sim_hz", "wbc_hz", "planner_hz"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ParameterError(name, v, "a positive rate [Hz]")
        if self.wbc_hz > self.sim_hz:
            raise ParameterError("wbc_hz", self.wbc_hz, f"at most sim_hz = {self.sim_hz:g} Hz")
        ratio = self.sim_hz / self.wbc_hz
        if abs(ratio - round(ratio)) > 1e-9:
            raise ParameterError(
                "wbc_hz", self.wbc_hz, f"a divisor of sim_hz = {self.sim_hz:g} Hz (e.g. 400, 500, 1000)"
            )
        if self.planner_hz > self.wbc_hz:
            raise ParameterError("planner_hz", self.planner_hz, f"at most wbc_hz = {self.wbc_hz:g} Hz")

    @property
    def timestep(self) -> float:
        """Simulation time step [s]."""
        return 1.0 / self.sim_hz

    @property
    def sim_steps_per_wbc(self) -> int:
        """Simulation steps per controller tick (5 at 2 kHz / 400 Hz)."""
        return int(round(self.sim_hz / self.wbc_hz))

    @property
    def wbc_ticks_per_plan(self) -> int:
        """Controller ticks per planner update (rounded, at least 1)."""
        return max(1, int(round(self.wbc_hz / self.planner_hz)))
