"""``lipmpcc robot init`` and ``lipmpcc robot check``: a new robot's layout, and a one-page verdict on it.

:func:`init_robot` writes the layout :mod:`lipmpcc.robots.autolayout` guesses from the MJCF alone and
returns the report of what it guessed. :func:`check_robot` loads the robot with its layout, stands it
for a while (full-body loop, no planner), then steps in place with the capture-point walker (speed 0),
and returns a :class:`CheckResult` whose :meth:`~CheckResult.report` says what works, what failed
and why, and the fixes to try.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from ..exceptions import InvalidInputError
from ..robots.autolayout import CROUCH_RATIO, write_layout

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.description import RobotDescription

__all__ = ["CheckStage", "CheckResult", "init_robot", "check_robot", "layout_in_use"]


def init_robot(model: str | Path, out: str | Path | None = None, overwrite: bool = False,
               crouch: float = CROUCH_RATIO) -> str:
    """Write the guessed layout of ``model`` (``<model>.lipmpcc.toml`` beside it, or ``out``), standing with the
    hip-to-sole height at ``crouch`` of the straight leg's; the report: the file written, and one line per guess
    with how sure it is.

    Raises:
        InvalidInputError: ``out`` exists (without ``overwrite``) or cannot be written; ``crouch`` outside
            :data:`~lipmpcc.robots.autolayout.CROUCH_RANGE`.
        ModelFileError / RobotDescriptionError: the model cannot be read, or has no floating base or feet.
    """
    target, guess = write_layout(model, out, overwrite=overwrite, crouch=crouch)
    if out is None:
        return f"wrote {target}\n{guess.summary()}\nnext: lipmpcc robot check {model}"
    return (f"wrote {target}\n{guess.summary()}\nnext: lipmpcc robot check {model} --layout {target}, "
            f"then lipmpcc run walk --robot {model} --layout {target}")


@dataclass
class CheckStage:
    """One stage of a check: ``name``, whether it ``passed``, its numbers and its explanation."""

    name: str
    passed: bool
    detail: str
    numbers: dict[str, float] = field(default_factory=dict)


@dataclass
class CheckResult:
    """The verdict of :func:`check_robot`: the robot's name, its notes (actuators), the stages and the
    model file."""

    robot: str
    notes: list[str]
    stages: list[CheckStage]
    model: str = "MODEL.xml"
    layout: str | None = None  # the layout file given (None: the model's sidecar)

    @property
    def passed(self) -> bool:
        """True when every stage passed."""
        return all(s.passed for s in self.stages)

    def report(self) -> str:
        """The one-page verdict (plain text)."""
        lines = [f"robot check: {self.robot}"] + [f"  note: {n}" for n in self.notes]
        for s in self.stages:
            nums = ", ".join(f"{k} {v:.3g}" for k, v in s.numbers.items())
            lines.append(f"  [{'ok' if s.passed else 'FAILED'}] {s.name}: {s.detail}" + (f" ({nums})" if nums else ""))
        given = "" if self.layout is None else f" --layout {self.layout}"
        lines.append("verdict: " + (f"ready: try `lipmpcc run walk --robot {self.model}{given}`" if self.passed else
                                    "not ready: see the fixes above"))
        return "\n".join(lines)


def _size(robot: "RobotDescription", key: str, default: str) -> str:
    """``key`` and its value [m], or ``default`` marked as not in the layout."""
    value = getattr(robot, key)
    return f"{key} {default}, not in the layout)" if value is None else f"{key} {float(value):.3g} m"


def layout_in_use(robot: "RobotDescription") -> list[str]:
    """Lines for the verdict: the layout values the runs use, with units (a key the layout does not state:
    the value used instead), and the joints the posture task holds; ``robot`` a loaded robot."""
    from ..control.wbc_types import WbcParams
    from ..sim.types import FALL_HEIGHT_FRACTION

    cop = float(dict(robot.wbc_overrides).get("cop_safety_factor", WbcParams().cop_safety_factor))
    gait = ", ".join([
        _size(robot, "lip_height", f"{robot.standing.com_height:.3g} m (the standing COM height"),
        f"step_duration {robot.step_duration:.3g} s",
        _size(robot, "step_width", "0.26 m (Digit's"), _size(robot, "max_step_length", "0.55 m (Digit's"),
        f"min_lateral_step {robot.min_lateral_step:.3g} m",
        f"touchdown_timing {robot.touchdown_timing or '(not set: by the planner)'}"])
    fall = _size(robot, "fall_height", f"({FALL_HEIGHT_FRACTION:g} x the standing torso height")
    support = (f"sole {robot.foot_length:.3g} x {robot.foot_width:.3g} m (foot_length x foot_width), the CoP kept "
               f"within {cop:g} of it (cop_safety_factor); a fall: the torso below {fall} above the lower sole, "
               "or tilted over 1 rad")
    named = len(robot.waist_joints) + len(robot.arm_joints) + len(robot.head_joints)
    extra = len(robot.posture_joints) - named
    posture = (f"posture: {len(robot.waist_joints)} waist, {len(robot.arm_joints)} arm, {len(robot.head_joints)} head "
               "joints held at their standing_qpos angles"
               + (f", and {extra} actuated joints in no group of the layout" if extra > 0 else ""))
    return [f"mass {robot.total_mass:.1f} kg: the studies' pushes x {robot.push_scale:.2f}", f"gait: {gait}",
            f"support: {support}", posture]


def _fixes(reason: str | None, qp_failures: int) -> str:
    """What to try for a failed stage."""
    tips = []
    if reason and "above the lower sole" in reason:
        tips.append("the knees may be too straight or too bent: re-run `lipmpcc robot init MODEL.xml --crouch RATIO "
                    "--force` (below 0.9 bends them more), or lower fall_height [m]")
    if reason and "touches" in reason:
        tips.append("a link touched the ground: check the feet (left_foot_body/right_foot_body) and sole_offset")
    if reason and "tilted" in reason:
        tips.append("the torso tipped over: check torso_body, the sole rectangle (foot_length/foot_width) and "
                    "the waist/arm posture joints")
    if qp_failures:
        tips.append(f"{qp_failures} QP failures: torque limits too low for the pose, or a foot rectangle larger "
                    "than the real sole (shrink foot_length/foot_width [m], or cop_safety_factor)")
    return "; ".join(tips) or "look at the run's figures"


def _stage(name: str, result: "object", duration: float) -> CheckStage:
    fell = bool(getattr(result, "fell"))
    qpf = int(getattr(result, "qp_failures"))
    reason = getattr(result, "fall_reason")
    numbers = {"sim_s": float(getattr(result, "sim_time")), "qp_failures": float(qpf),
               "steps": float(getattr(result, "n_steps")), "rtf": float(getattr(result, "real_time_factor"))}
    if fell:
        t = float(getattr(result, "fall_time"))
        return CheckStage(name, False, f"fell at t = {t:.2f} s: {reason}; try: {_fixes(reason, qpf)}", numbers)
    ok_qp = qpf <= 0.02 * duration / 0.002  # at most 2 % of the ticks at 500 Hz
    detail = f"{duration:g} s without falling" + ("" if ok_qp else f"; but {_fixes(None, qpf)}")
    return CheckStage(name, ok_qp, detail, numbers)


def check_robot(model: str | Path, stand_s: float = 2.0, step_s: float = 3.0,
                layout: str | Path | None = None) -> CheckResult:
    """Load ``model`` with its layout (the file ``layout``, else ``<model>.lipmpcc.toml`` beside it), stand it
    ``stand_s`` [s], then step in place ``step_s`` [s].

    Raises:
        ModelFileError / RobotDescriptionError: the model or its layout cannot be used (no layout: the
            message says to run ``lipmpcc robot init``).
        InvalidInputError: ``layout`` is not an existing ``.toml``/``.json`` file.
    """
    from ..loops.fullbody.loop import FullBodyLoop
    from ..planners.capture_point import CapturePointPlanner
    from ..robots import load_robot
    from .walking import capture_point_params

    if layout is not None and not (Path(layout).suffix.lower() in (".toml", ".json") and Path(layout).is_file()):
        raise InvalidInputError("--layout", str(layout), "an existing .toml/.json layout file")
    robot = load_robot(Path(model), layout=None if layout is None else Path(layout))
    notes = list(robot.actuator_notes) + [f"layout: {robot.layout_file or 'recognised from the body names'}"]
    notes += layout_in_use(robot)
    stages = []
    stand = FullBodyLoop(robot, planner=None).run(duration=stand_s)
    stages.append(_stage("stand", stand, stand_s))
    if not stand.fell:
        planner = CapturePointPlanner(capture_point_params(robot), speed=0.0, yaw_rate=0.0)
        steps = FullBodyLoop(robot, planner=planner).run(duration=step_s)
        stage = _stage("step in place", steps, step_s)
        if stage.passed and steps.n_steps < 2:
            stage = CheckStage(stage.name, False, f"only {steps.n_steps} steps in {step_s:g} s", stage.numbers)
        stages.append(stage)
    return CheckResult(robot=robot.name, notes=notes, stages=stages, model=str(model),
                       layout=None if layout is None else str(layout))
