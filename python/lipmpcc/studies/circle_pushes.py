"""Paper B's four pushes while following paper A's circle (issue 18, beyond both papers).

Paper B's push test (:func:`lipmpcc.studies.paper.push_test`) pushes the robot +150 N forward, −150 N
backward, +75 N left and −75 N right, each from 0.1 to 0.2 s into a swing, on a straight line of stones.
Here the same four pushes act while the robot follows the 2 m circle of ``circle-push``:

- **Frame.** The forces are given in the walking frame (forward = the robot's heading, left = 90° to it)
  and turned into the world frame with the heading at the touch-down that starts the pushed swing, read
  from a first run of the same planner without pushes (the reference): a push is a fixed world-frame
  force (:class:`~lipmpcc.push.Push`), so its direction is chosen before the run. The pushed run
  reaches the pushed swing in a slightly different place once an earlier push moved it along the path:
  :attr:`CirclePushOutcome.heading_error` measures the angle between the force and the heading of the
  pushed run at the push (a few degrees; a 10° error turns 3 % of a 150 N push sideways).
- **Timing.** Each push is registered at the touch-down of its footstep (``Push.step``; every loop arms
  such pushes, :class:`~lipmpcc.loops.base.PushSchedule`), so it acts 0.1 s into that swing whatever the
  durations before it; :attr:`CirclePushOutcome.phase` is the time since the last touch-down of the pushed
  run at the push's start.
- **Durations.** For each push, the durations [s] of the step before, the pushed step (the swing during
  which the push starts) and the step after, beside the same steps of the reference: paper B's Fig. 7 is
  a shorter step after the forward push and a longer one after the backward push.
- **Which swings.** On the circle the two feet are not symmetric (the unpushed durations alternate): the
  four pushes act in the steps that stand on the inner (left) foot of the counter-clockwise circle (even
  footsteps, :data:`PUSHED_STEPS`), where the timed MPCC answers as Fig. 7; pass ``steps`` for the other
  foot's. docs/design.md shows why on the LIP: the outer foot placed at the end of these steps lies on the
  reachability's inner lateral bound, the inner foot does not.

The pushes reach the study through ``RunOptions.extra["pushes"]`` (the hook of ``lipmpcc sweep``), so a
run here is an ordinary ``lipmpcc run circle-push`` with these pushes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from .. import config
from ..exceptions import InvalidInputError
from ..push import Push
from . import paper
from .options import PAPER_B_PUSHED_STEPS, RunOptions, RunResult, check_paper_b_steps
from .path_following import run_circle_push
from .path_scenarios import PLANNERS

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = [
    "PLANNERS",
    "PUSH_NAMES",
    "PUSHED_STEPS",
    "CirclePushOutcome",
    "CirclePushRun",
    "paper_b_circle_push",
    "paper_b_circle_pushes",
    "paper_b_circle",
    "plot_push_durations",
    "run_circle_push_study",
    "run_paper_b_circle",
]

PUSH_NAMES = ("forward", "backward", "left", "right")  # paper B's four pushes, in its order
PUSHED_STEPS = PAPER_B_PUSHED_STEPS  # the footsteps pushed (0-based, even: one foot): (full, fast)


def paper_b_circle_push(i: int, touchdown: float, heading: float, step: int, by_step: bool = True,
                        scale: float = 1.0) -> Push:
    """Paper B's push number ``i`` (0 forward +150 N, 1 backward −150 N, 2 left +75 N, 3 right −75 N) in
    the walking frame of ``heading`` [rad], as a world-frame push from 0.1 to 0.2 s after the touch-down
    that starts footstep ``step`` (0-based, in the loop's numbering): registered at that touch-down
    (``by_step``) or at the absolute time ``touchdown`` [s] + 0.1 s. ``scale``: the force times this."""
    test = paper.push_test()
    if not (isinstance(i, int) and 0 <= i < len(test.pushes)):
        raise InvalidInputError("i", i, f"a push of paper B's test, 0..{len(test.pushes) - 1}")
    if not (math.isfinite(scale) and scale >= 0.0):
        raise InvalidInputError("scale", scale, "a finite number >= 0")
    if not (math.isfinite(heading) and math.isfinite(touchdown)):
        raise InvalidInputError("heading, touchdown", (heading, touchdown), "finite [rad], [s]")
    a, b = test.window
    c, s = math.cos(heading), math.sin(heading)
    fx, fy = scale * test.pushes[i].force[0], scale * test.pushes[i].force[1]  # forward, left [N]
    force = (c * fx - s * fy, s * fx + c * fy)
    return Push.between(force, a, b, step=int(step)) if by_step else Push.between(force, touchdown + a, touchdown + b)


def paper_b_circle_pushes(touchdowns: Sequence[float], headings: Sequence[float], steps: Sequence[int],
                          by_step: bool = True, scale: float = 1.0) -> list[Push]:
    """Paper B's four pushes (:func:`paper_b_circle_push`) from one run's timeline.

    Args:
        touchdowns: the time [s] of the touch-down that starts each footstep (index = footstep).
        headings: the walking heading [rad] at each of those touch-downs.
        steps: the four footsteps pushed (0-based), in paper B's order: forward, backward, left, right.
        by_step: registered at each footstep's touch-down (every loop arms them), else at absolute times.
        scale: the forces times this.
    """
    steps = [int(k) for k in steps]
    n = min(len(touchdowns), len(headings))
    if len(steps) != len(PUSH_NAMES) or any(k < 0 or k >= n for k in steps):
        raise InvalidInputError("steps", steps, f"{len(PUSH_NAMES)} footsteps within the run's {n} touch-downs")
    return [paper_b_circle_push(i, float(touchdowns[k]), float(headings[k]), k, by_step, scale)
            for i, k in enumerate(steps)]


@dataclass(frozen=True)
class CirclePushOutcome:
    """One of the four pushes in the pushed run.

    Attributes:
        name: ``forward``, ``backward``, ``left`` or ``right``.
        force_walking: (forward, left) force [N]; force_world: (F_x, F_y) [N].
        t_start: the push's start [s]; phase: time since the last touch-down at that instant [s].
        heading_error: angle from the walking heading of the pushed run to the push's direction, minus the
            intended one [rad] (0: exactly forward/backward/left/right).
        durations: (before, pushed, after) step durations of the pushed run [s] (NaN where absent).
        reference: the same steps' durations in the run without pushes [s].
    """

    name: str
    force_walking: tuple[float, float]
    force_world: tuple[float, float]
    t_start: float
    phase: float
    heading_error: float
    durations: tuple[float, float, float]
    reference: tuple[float, float, float]


@dataclass
class CirclePushRun:
    """Paper B's four pushes on the circle: ``survived`` (the pushed run did not fall), the outcome of each
    push, and both runs' summaries (``summary``: pushed; ``reference_summary``: without pushes)."""

    robot: str
    planner: str
    step_duration_range: tuple[float, float] | None
    replan_hz: float | None
    survived: bool
    pushes: list[CirclePushOutcome]
    summary: dict[str, Any]
    reference_summary: dict[str, Any] = field(default_factory=dict)

    def table(self) -> list[dict[str, Any]]:
        """One row per push (JSON-ready): name, phase [s], heading error [deg], durations [s]."""
        return [{"push": o.name, "t_start_s": round(o.t_start, 3), "phase_s": round(o.phase, 3),
                 "heading_error_deg": round(math.degrees(o.heading_error), 1),
                 "before_s": round(o.durations[0], 3), "pushed_s": round(o.durations[1], 3),
                 "after_s": round(o.durations[2], 3),
                 "reference_s": [round(x, 3) for x in o.reference]} for o in self.pushes]


def _timeline(run: Any) -> tuple[np.ndarray, np.ndarray]:
    """(touch-down times [s], headings [rad]) of a circle run: the LIP's exchanges (``lip_log.t``, the
    states' heading) or a full body's touch-downs (their foot yaw)."""
    lip = getattr(run, "lip_log", None)
    if lip is not None:
        return np.asarray(lip.t, dtype=float), np.asarray(lip.states, dtype=float)[:, 4]
    tds = run.result.touchdowns
    return np.array([td.t for td in tds], dtype=float), np.array([td.yaw for td in tds], dtype=float)


def _around(t: np.ndarray, t_push: float) -> tuple[int, tuple[float, float, float]]:
    """The index of the last touch-down at or before ``t_push`` [s] and the (before, pushed, after)
    step durations around it [s] (NaN where the run has no such step)."""
    j = int(np.searchsorted(t, t_push, side="right")) - 1
    d = np.diff(t)

    def get(i: int) -> float:
        return float(d[i]) if 0 <= i < len(d) else math.nan

    return j, (get(j - 1), get(j), get(j + 1))


def _pushes_in_turn(opts: RunOptions, steps: Sequence[int], scale: float) -> tuple[list[Push], Any]:
    """The four pushes, each turned with the heading of the run that carries the pushes before it (the
    runs are deterministic: the run with the first i pushes is the pushed run up to push i + 1), and the
    reference run (no pushes, whole). Returns (pushes, the reference's result). When the run with the first
    i pushes falls before push i + 1's footstep, the pushes end there (fewer than four: the pushed run falls
    the same way before the others).

    Raises:
        InvalidInputError: a run that ends without a fall before a pushed footstep (``steps`` beyond the run).
    """
    # the touch-down t[k] starts the LIP's step k, and the full body's footstep k + 1 (its touch-down k ends
    # footstep k): either loop arms the push there
    offset = 0 if (opts.robot or "lip") == "lip" else 1  # robot None: the LIP (the CLI default)
    ref = run_circle_push(opts)
    pushes: list[Push] = []
    for i, k in enumerate(steps):
        run = ref if i == 0 else run_circle_push(replace(opts, steps=k + 2, extra={"pushes": list(pushes)}))
        t, yaw = _timeline(run.log)
        if run is not ref:
            run.close_figures()  # used for its touch-down times only
        if k >= min(len(t), len(yaw)):
            if i > 0 and run.summary.get("fell"):
                break
            raise InvalidInputError("steps", list(steps), f"footsteps the run reaches (it ends after {len(t) - 1})")
        pushes.append(paper_b_circle_push(i, float(t[k]), float(yaw[k]), k + offset, scale=scale))
    ref.close_figures()  # the reference run is kept for its log and summary
    return pushes, ref


def run_paper_b_circle(robot: str = "lip", planner: str = "mpcc", step_duration_range: Sequence[float] | None = None,
                       replan_hz: float | None = None, steps: Sequence[int] | None = None,
                       scale: float = 1.0) -> CirclePushRun:
    """Follow the circle (``circle-push``) under paper B's four pushes, each turned into the walking frame
    at its footstep's touch-down (:func:`_pushes_in_turn`); every run goes through
    :func:`~lipmpcc.studies.path_following.run_circle_push` (the pushes in ``RunOptions.extra``).
    ``lipmpcc run circle-push --push-set paper-b`` is the same run (:func:`run_circle_push_study`).

    Args:
        robot: ``lip``, ``digit_like`` or a PATH.xml.
        planner: ``mpcc`` or ``cartesian``.
        step_duration_range: (TMIN, TMAX) [s]: the timed MPCC; None: fixed T.
        replan_hz: the LIP's within-step re-planning rate [Hz] (with a range; a full body: always 25 Hz).
        steps: the four footsteps pushed, increasing (None: :data:`PUSHED_STEPS`).
        scale: the forces times this.
    """
    opts = RunOptions("circle-push", planner=planner, robot=robot, out="results",
                      step_duration_range=None if step_duration_range is None else tuple(step_duration_range),
                      replan_hz=replan_hz, extra={"pushes": []})
    return paper_b_circle(opts, steps, scale)[0]


def _pushed_steps(steps: Sequence[int] | None, run_steps: int | None) -> list[int]:
    """The four footsteps pushed, checked: increasing, >= 1, and within ``run_steps`` (the run's ``--steps``)."""
    pushed = [int(k) for k in (steps if steps is not None else config.horizon(*PUSHED_STEPS))]
    if len(pushed) != len(PUSH_NAMES) or sorted(set(pushed)) != pushed or pushed[0] < 1:
        raise InvalidInputError("steps", pushed, f"{len(PUSH_NAMES)} increasing footsteps >= 1")
    if run_steps is not None:
        check_paper_b_steps(run_steps, pushed[-1])
    return pushed


def _reaching_the_last_push(opts: RunOptions, last_pushed: int) -> RunOptions:
    """``opts`` with a run long enough for paper B's pushes: with neither ``--steps`` nor ``--duration``, a
    full body whose default duration ends before footstep ``last_pushed + 3`` (fast mode's 10 s: about 20
    footsteps, against 31 needed) runs that many footsteps instead; a longer default, and the LIP's (40 or
    120 steps, at least 31 and 59), are kept. (The default used to end before the last push, and the report
    then failed with an IndexError.)"""
    if opts.steps is not None or opts.duration is not None or (opts.robot or "lip") == "lip":
        return opts
    from .path_following import _robot
    from .path_scenarios import FULLBODY_SETTLE_TIME, STEP_DURATION, _default_duration

    robot = _robot(opts)
    longest = (opts.step_duration_range[1] if opts.step_duration_range is not None
               else (getattr(robot, "step_duration", None) or STEP_DURATION))
    reached = (_default_duration("circle-push", opts.planner or "mpcc") - FULLBODY_SETTLE_TIME) / float(longest)
    return opts if reached >= last_pushed + 3 else replace(opts, steps=last_pushed + 3)


def paper_b_circle(opts: RunOptions, steps: Sequence[int] | None = None,
                   scale: float = 1.0) -> tuple[CirclePushRun, RunResult]:
    """Paper B's four pushes on the circle, with ``opts`` (a ``circle-push`` run's options: robot, planner,
    step durations, ``--preset``/``--set``, ``--steps``/``--duration``, ``--video``/``--viewer``, which only
    the pushed run gets). Returns the outcome and the pushed run's :class:`RunResult`."""
    pushed_steps = _pushed_steps(steps, opts.steps)
    opts = _reaching_the_last_push(opts, pushed_steps[-1])
    quiet = replace(opts, video=False, video_format=None, viewer=None, push_set=None, extra={"pushes": []})
    pushes, ref = _pushes_in_turn(quiet, pushed_steps, scale)
    res = run_circle_push(replace(opts, extra={"pushes": pushes}))
    t_run, yaw_run = _timeline(res.log)
    t_ref, _ = _timeline(ref.log)
    window = paper.push_test().window
    outcomes = []
    for i, (name, k, p) in enumerate(zip(PUSH_NAMES, pushed_steps, pushes)):
        t_push = (float(t_run[k]) + p.t_start if k < len(t_run) else math.nan) if p.step is not None else p.t_start
        j, durations = _around(t_run, t_push) if math.isfinite(t_push) else (-1, (math.nan,) * 3)
        _, reference = (_around(t_ref, float(t_ref[k]) + window[0]) if k < len(t_ref)
                        else (-1, (math.nan,) * 3))  # a reference that fell before footstep k
        walking = paper.push_test().pushes[i].force
        fwd = (scale * walking[0], scale * walking[1])
        heading = float(yaw_run[j]) if 0 <= j < len(yaw_run) else math.nan
        err = math.remainder(math.atan2(p.force[1], p.force[0]) - heading - math.atan2(walking[1], walking[0]),
                             2 * math.pi)
        phase = t_push - float(t_run[j]) if j >= 0 else math.nan
        outcomes.append(CirclePushOutcome(name, fwd, (p.force[0], p.force[1]), float(t_push), float(phase), float(err),
                                          durations, reference))
    survived = not bool(res.summary.get("fell")) and not bool(res.summary.get("collided"))
    run = CirclePushRun(str(res.summary.get("robot", opts.robot)), str(res.summary.get("planner", opts.planner)),
                        opts.step_duration_range, opts.replan_hz, survived, outcomes, res.summary, ref.summary)
    return run, res


def run_circle_push_study(opts: RunOptions) -> RunResult:
    """``lipmpcc run circle-push``: paper A's random pushes (``--push-set paper-a``, the default:
    :func:`~lipmpcc.studies.path_following.run_circle_push`) or paper B's four pushes in the walking frame
    (``--push-set paper-b``: :func:`paper_b_circle`; a sweep's ``push_scale`` scales their forces). With
    paper B's, the summary gains ``paper_b_pushes`` (one row per push: :meth:`CirclePushRun.table`),
    ``survived``, and the reference run's ``reference_fell``; the figures gain ``push_durations``. A robot that
    falls before a pushed footstep gets only the pushes before it (``pushes`` counts those applied)."""
    if (opts.push_set or "paper-a") == "paper-a":
        res = run_circle_push(opts)
        res.summary["push_set"] = "paper-a" if opts.extra.get("pushes") is None else "given"
        return res
    if opts.extra.get("pushes") is not None:
        raise InvalidInputError("pushes", "given", "either --push-set paper-b or pushes of one's own, not both")
    run, res = paper_b_circle(opts, scale=float(opts.extra.get("push_scale", 1.0)))
    res.summary.update({"push_set": "paper-b", "survived": run.survived, "paper_b_pushes": run.table(),
                        "reference_fell": bool(run.reference_summary.get("fell"))})
    res.figures["push_durations"] = plot_push_durations(run, _timeline(res.log)[0])
    return res


def plot_push_durations(run: CirclePushRun, touchdowns: np.ndarray) -> Figure:
    """Paper B Fig. 7 on the circle: each step's duration [s] against its start [s], the pushed run, with
    the four pushes shaded and each pushed step's reference (unpushed) duration marked."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 3.2))
    t = np.asarray(touchdowns, dtype=float)
    ax.step(t[:-1], np.diff(t), where="post", color="C0", label="step duration, pushed run")
    colours = {"forward": "C3", "backward": "C2", "left": "C1", "right": "C4"}
    a, b = paper.push_test().window  # each push's window after its touch-down [s]
    for o in run.pushes:
        f = math.hypot(*o.force_walking)
        ax.axvspan(o.t_start, o.t_start + (b - a), color=colours[o.name], alpha=0.35, label=f"push {o.name} {f:.0f} N")
        if math.isfinite(o.reference[1]) and math.isfinite(o.phase):
            t0 = o.t_start - o.phase  # the pushed step's start
            ax.hlines(o.reference[1], t0, t0 + o.reference[1], colors="k", lw=2.5)
    ax.plot([], [], "k-", lw=2.5, label="pushed step without the push (reference)")
    ax.set(xlabel="time [s]", ylabel="step duration [s]",
           title=f"paper B's four pushes on the circle: {run.robot}, {run.planner}"
                 + ("" if run.step_duration_range is None else f", T in [{run.step_duration_range[0]:g}, "
                                                                f"{run.step_duration_range[1]:g}] s"))
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig
