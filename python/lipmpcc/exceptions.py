"""Exception hierarchy of lipmpcc.

Every error raised on purpose by the package derives from :class:`LipmpccError`
and carries the offending data as attributes, so that callers can react to it
programmatically and the CLI can print one readable line.

Input-validation errors also derive from :class:`ValueError`, so that
``except ValueError`` keeps working for users who do not import this module.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "LipmpccError",
    "InvalidInputError",
    "PathError",
    "ParameterError",
    "StateError",
    "TerrainError",
    "ModelFileError",
    "RobotDescriptionError",
    "SolverError",
    "NoFallbackPlanError",
    "RenderUnavailableError",
    "ConcurrentUseError",
    "OutputFolderError",
    "OutputBusyError",
    "RunTooLongError",
    "ObstacleError",
    "LayoutError",
]


class LipmpccError(Exception):
    """Base class of every error raised by lipmpcc on purpose."""


class InvalidInputError(LipmpccError, ValueError):
    """An argument has a bad value.

    Attributes:
        name: name of the argument or field.
        value: the value that was received.
        expected: human-readable description of what was expected.
    """

    def __init__(self, name: str, value: Any, expected: str, detail: str = "") -> None:
        self.name = name
        self.value = value
        self.expected = expected
        self.detail = detail
        shown = repr(value)
        if len(shown) > 120:
            shown = shown[:117] + "..."
        msg = f"{name} = {shown}: expected {expected}"
        if detail:
            msg += f" ({detail})"
        super().__init__(msg)


class PathError(InvalidInputError):
    """A path is malformed (too few points, NaN, zero length, radius <= 0, ...)."""


class ParameterError(InvalidInputError):
    """A planner, model or scenario parameter is impossible (e.g. T <= 0, lb > ub)."""


class StateError(InvalidInputError):
    """A state passed to a planner or model is malformed (wrong shape, NaN, inf)."""


class TerrainError(InvalidInputError):
    """A stepping-stone file or profile is unusable (empty, NaN, impossibly spaced)."""


class ModelFileError(LipmpccError, FileNotFoundError):
    """A robot model file is missing or cannot be parsed.

    Attributes:
        path: the file that was asked for.
        reason: what went wrong.
    """

    def __init__(self, path: str, reason: str) -> None:
        self.path = str(path)
        self.reason = reason
        super().__init__(f"robot model {self.path!s}: {reason}")


class RobotDescriptionError(LipmpccError, ValueError):
    """A robot model lacks something the stack needs (a foot body, a motor, ...).

    Attributes:
        path: model file.
        missing: list of missing items.
    """

    def __init__(self, path: str, missing: list[str]) -> None:
        self.path = str(path)
        self.missing = list(missing)
        super().__init__(f"robot model {self.path}: missing {', '.join(self.missing)}")


class SolverError(LipmpccError, RuntimeError):
    """An optimisation solver failed and no safe fallback exists.

    Attributes:
        solver: solver name.
        status: the solver's return status.
        iterations: iterations performed.
    """

    def __init__(self, solver: str, status: str, iterations: int = -1, detail: str = "") -> None:
        self.solver = solver
        self.status = status
        self.iterations = iterations
        msg = f"{solver} failed with status {status!r} after {iterations} iterations"
        if detail:
            msg += f": {detail}"
        super().__init__(msg)


class NoFallbackPlanError(SolverError):
    """The planner failed on its first solve, so there is no previous plan to execute."""


class RenderUnavailableError(LipmpccError, RuntimeError):
    """Rendering or viewing cannot work here (no OpenGL backend, no display, no video encoder).

    Attributes:
        what: what was asked for (``"offscreen rendering"``, ``"viewer"``, ``"MP4 video"``, ...).
        reason: why it cannot be done, with the remedy when there is one.
    """

    def __init__(self, what: str, reason: str) -> None:
        self.what = what
        self.reason = reason
        super().__init__(f"{what} unavailable: {reason}")


class ConcurrentUseError(LipmpccError, RuntimeError):
    """An object that holds a single native workspace was used from two threads at once.

    Attributes:
        obj: a description of the object (its class and id).
        method: the method that found the object busy.
        kind: what the object is, in the advice (``"controller"``: "use one controller per thread").
    """

    def __init__(self, obj: str, method: str, kind: str = "object") -> None:
        self.obj = obj
        self.method = method
        super().__init__(
            f"{obj}.{method}() called while another thread is inside a call on the same {kind}: it holds one "
            f"native workspace and cannot be used from two threads at once; use one {kind} per thread"
        )


class OutputFolderError(InvalidInputError):
    """An output folder (``--out``) cannot take the run: an empty path, an existing file, a folder that
    holds something else (without ``--replace``), or a place that cannot be created or written.
    ``name`` is the option (``"--out"``), ``value`` the path given."""


class OutputBusyError(LipmpccError, RuntimeError):
    """Another run is writing to the same output folder (its lock file exists and is held).

    Attributes:
        path: the output folder.
        lock: the lock file (``OUT.lock`` beside the folder).
        holder: what the lock file says of its holder (``"pid 123 since 2026-12-02T07:00:00+00:00"``) or ``""``.
    """

    def __init__(self, path: str, lock: str, holder: str = "") -> None:
        self.path = str(path)
        self.lock = str(lock)
        self.holder = holder
        who = f" ({holder})" if holder else ""
        super().__init__(f"--out {self.path}: another lipmpcc run{who} is writing to this folder (lock {self.lock}); "
                         "wait for it to end or choose another --out")


class RunTooLongError(InvalidInputError):
    """A run whose estimated wall time is over the bound (``lipmpcc run --allow-long`` runs it anyway).

    Attributes (besides ``name``, ``value``, ``expected``, ``detail``):
        wall_s: the estimated wall time [s].
        bound_s: the bound [s].
    """

    def __init__(self, name: str, value: Any, expected: str, detail: str = "", wall_s: float = float("nan"),
                 bound_s: float = float("nan")) -> None:
        super().__init__(name, value, expected, detail)
        self.wall_s = wall_s
        self.bound_s = bound_s
class ObstacleError(InvalidInputError):
    """An obstacle is malformed or absurd (semi-axes, speed, position out of range, a bad obstacle file)."""


class LayoutError(RobotDescriptionError):
    """A robot layout (a layout file, or keyword overrides of ``load_robot``) has a key of the wrong
    type or shape (e.g. ``leg_joints = 5``, ``sole_offset = [1.0]``).

    Attributes:
        path: the layout file (or the model when the layout came as overrides).
        missing: what each bad key should be, with the value received.
    """

    def __init__(self, path: str, problems: list[str]) -> None:
        super().__init__(path, problems)
        Exception.__init__(self, f"robot layout {self.path}: expected {'; '.join(self.missing)}")
