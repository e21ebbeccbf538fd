"""A push: the one external disturbance of every loop (LIP, ALIP, full body) and of the plant.

A :class:`Push` is a constant force [N] over a time window. On the reduced models it acts on the
point mass (its horizontal part); in MuJoCo on a body (default: the torso), at the body's centre of
mass. The window is either absolute run time or, with ``step``, relative to the touch-down that
starts footstep ``step`` (paper B's "0.1 to 0.2 s into step 5").
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .exceptions import InvalidInputError
from .validation import count, finite_array, non_negative_number, positive_number

__all__ = ["Push"]


def _time(name: str, value: object) -> float:
    return non_negative_number(name, value, "s", what="a finite time")


@dataclass(frozen=True)
class Push:
    """A constant force over ``t_start <= t < t_end``.

    Attributes:
        force: (F_x, F_y) or (F_x, F_y, F_z), world frame [N].
        t_start: start of the window [s] (absolute, or after the touch-down of footstep ``step``).
        duration: length of the window [s] (> 0).
        step: None (absolute times) or the 0-based index of the footstep whose touch-down the
            window is measured from.
        body: the MuJoCo body pushed (None: the robot's torso); ignored by the reduced models.
        t_end: end of the window [s]: ``t_start + duration``, or exactly the end given to
            :meth:`between`.
    """

    force: tuple[float, ...]
    t_start: float
    duration: float = 0.1
    step: int | None = None
    body: str | None = None
    t_end: float = field(init=False, compare=False)

    def __post_init__(self) -> None:
        f = finite_array("force", self.force, None, "N", what="(F_x, F_y) or (F_x, F_y, F_z), finite numbers").reshape(-1)
        if f.shape not in ((2,), (3,)):
            raise InvalidInputError("force", self.force, "(F_x, F_y) or (F_x, F_y, F_z), finite [N]")
        object.__setattr__(self, "force", tuple(float(x) for x in f))
        object.__setattr__(self, "t_start", _time("t_start", self.t_start))
        object.__setattr__(self, "duration", positive_number("duration", self.duration, "s", what="a finite duration"))
        if self.step is not None:
            count("step", self.step, 0, what="None or a footstep index")
        if self.body is not None and not (isinstance(self.body, str) and self.body):
            raise InvalidInputError("body", self.body, "None or the name of a body of the model")
        object.__setattr__(self, "t_end", self.t_start + self.duration)

    @classmethod
    def between(cls, force: tuple[float, ...], t_start: float, t_end: float, step: int | None = None,
                body: str | None = None) -> "Push":
        """A push over ``[t_start, t_end)`` [s]; ``t_end`` is kept exactly as given."""
        a, b = _time("t_start", t_start), _time("t_end", t_end)
        if not b > a:
            raise InvalidInputError("t_start, t_end", (t_start, t_end), "t_start < t_end [s]")
        push = cls(force, a, b - a, step, body)
        object.__setattr__(push, "t_end", b)
        return push

    @property
    def force_xy(self) -> tuple[float, float]:
        """The horizontal part (F_x, F_y) [N]."""
        return (self.force[0], self.force[1])

    @property
    def force_xyz(self) -> tuple[float, float, float]:
        """The force as a 3-vector (F_z = 0 for a planar push) [N]."""
        return (self.force[0], self.force[1], self.force[2] if len(self.force) == 3 else 0.0)

    def active(self, t: float) -> bool:
        """True while the push acts at (absolute or step-relative) time ``t`` [s]."""
        return self.t_start <= t < self.t_end
