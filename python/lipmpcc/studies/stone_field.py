"""The stone-field study (issue 29): cross seeded stone fields, with and without a pedestrian, on the ALIP.

Each run: the robot stands at the origin, walks paper B's approach (6 steps, driven by a shared
ALIP-MPC, so every planner starts from the same state) and then crosses the field
(:mod:`lipmpcc.stone_field`) with the planner under test (:mod:`lipmpcc.planners.stone_field`: the
cost-to-go stone choice, or a baseline). The ALIP loop (:mod:`lipmpcc.loops.alip`) walks it; the
field's footholds are free regions for the loop, and this module judges the run against the field:

- ``completed``: a foothold reached the goal (the end of the path), every field foothold before it on
  a stone, no contact with a pedestrian, no fall (the loop's kinematic and DCM-viability checks, up to
  the start of the step after the goal foothold);
- ``collided``: the body disk (``robot_radius`` about the COM) or the stance foot touched a pedestrian
  before the goal;
- ``fell``: a field foothold off every stone, or the loop's fall;
- ``stalled``: the planner found no reachable stone or no way to the goal (it names the step);
- ``incomplete``: the step budget ran out first.

:func:`field_table` sweeps seeds × {no pedestrian, a pedestrian at 0.3–0.6 m/s} × planners and reports
success rates with Wilson intervals and the planners' plan-time distribution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..loops.alip import AlipLoopConfig, AlipLoopLog, run_alip_loop
from ..metrics import timing_stats_ms, wilson_interval
from ..planners.alip_mpc import AlipMpc, AlipMpcParams
from ..planners.stone_field import CHOOSERS, StoneFieldParams, StoneFieldPlanner
from ..planners.stone_milp import MilpStoneFieldPlanner
from ..push import Push
from ..stone_field import StoneField, make_stone_field
from ..terrain import N_APPROACH, StoneSequence, approach_footholds
from ..validation import count
from .options import RunOptions, RunResult
from .paper import push_test

__all__ = ["PLANNERS", "judge_log", "FIELD_OUTCOMES", "FIELD_PUSH_STEPS", "field_pushes", "FieldRun", "field_course", "run_field", "field_cases", "field_table", "study_field",
           "field_summary", "run_stone_field"]

#: ``--planner`` of ``lipmpcc run stone-field`` (and a sweep's planners): the planner, the two baselines, and the
#: planner with the mixed-integer stone choice (:class:`~lipmpcc.planners.stone_milp.MilpStoneFieldPlanner`)
PLANNERS = ("stone-field", "greedy-stone", "path-agnostic-alip-mpc", "stone-field-milp")
_CHOOSER = {"stone-field": "cost-to-go", "greedy-stone": "greedy", "path-agnostic-alip-mpc": "nominal",
            "stone-field-milp": "cost-to-go"}
#: a field run's outcomes, most severe first
FIELD_OUTCOMES = ("collided", "fell", "stalled", "incomplete", "completed")
#: the field footholds whose swings paper B's four pushes hit (``--push-set paper-b``): every second one, so that all
#: four land on a 4 m field of 10-18 steps (paper B's row pushes every fifth stone of 22)
FIELD_PUSH_STEPS = (2, 4, 6, 8)


def field_pushes(scale: float = 1.0) -> tuple[Push, ...]:
    """Paper B's four pushes (+150 N forward, -150 N backward, +75 N left, -75 N right, world frame, 0.1-0.2 s into
    the swing), forces times ``scale``, on the swings towards field footholds :data:`FIELD_PUSH_STEPS` (the
    approach's 6 footsteps counted: footstep ``N_APPROACH + j - 1``)."""
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not math.isfinite(scale) or scale < 0:
        raise InvalidInputError("push_scale", scale, "a finite number >= 0")
    test = push_test()
    a, b = test.window
    return tuple(Push.between((scale * p.force[0], scale * p.force[1]), a, b, step=N_APPROACH + j - 1)
                 for p, j in zip(test.pushes, FIELD_PUSH_STEPS))


@dataclass
class FieldRun:
    """How one run across a field ended.

    Attributes:
        outcome: one of :data:`FIELD_OUTCOMES`; reached_end: a foothold reached the goal.
        planner: the planner's name; seed: the field's seed; pedestrian_speed: [m/s] (None: none).
        field_steps: footholds on the field up to the goal (or the end of the run).
        waits: field footholds back on the stone that foot left (marching in place: waiting).
        min_clearance_m: the least clearance to a pedestrian before the goal [m] (None: no pedestrian).
        reason: why the run failed ("" when it completed).
        plan_times: wall time of every planner call on the field [s] (the choice included).
        log: the ALIP loop's log.
    """

    outcome: str
    reached_end: bool
    planner: str
    seed: int | None
    pedestrian_speed: float | None
    field_steps: int
    waits: int
    min_clearance_m: float | None
    reason: str
    plan_times: np.ndarray
    log: AlipLoopLog | None = field(default=None, repr=False)

    @property
    def success(self) -> bool:
        """True when the run completed."""
        return self.outcome == "completed"

    def summary(self) -> dict[str, Any]:
        """The run's fields for a summary.json (no arrays)."""
        return {"outcome": self.outcome, "reached_end": self.reached_end, "planner": self.planner, "seed": self.seed,
                "pedestrian_speed": self.pedestrian_speed, "field_steps": self.field_steps, "waits": self.waits,
                "min_clearance_m": self.min_clearance_m, "reason": self.reason,
                "plan_ms": timing_stats_ms(self.plan_times)}


def field_course(stone_field: StoneField, budget: int) -> StoneSequence:
    """Paper B's approach, then ``budget`` free footholds (the loop's course; the field planner chooses
    its own footholds, the free ones only preview a straight walk for the approach planner)."""
    app = approach_footholds()
    last = app.centers[-1]
    sides = np.array([-1 if k % 2 == 0 else 1 for k in range(budget)])
    centers = np.column_stack([last[0] + 0.3 * np.arange(1, budget + 1), 0.14 * sides])
    free = StoneSequence(centers, np.full((budget, 2), np.inf), sides, np.zeros(budget, bool), stone_field.name)
    return app + free


def _clearance(stone_field: StoneField, log: AlipLoopLog, t_end: float, prm: StoneFieldParams) -> float | None:
    """The least clearance [m] of the body disk and the stance foot to the pedestrians up to ``t_end``."""
    if not stone_field.pedestrians:
        return None
    keep = log.t <= t_end + 1e-9
    t, com = log.t[keep], log.com[keep]
    feet = np.vstack([log.start_stance[None], log.footholds])
    k = np.searchsorted(log.td_times, t, side="right")  # touch-downs so far
    stance = feet[k]
    best = math.inf
    for ped in stone_field.pedestrians:
        c = ped.center(t)
        r = ped.axes[0]
        best = min(best, float(np.min(np.linalg.norm(com - c, axis=1) - r - prm.robot_radius)),
                   float(np.min(np.linalg.norm(stance - c, axis=1) - r - prm.foot_radius)))
    return best


def _judge(stone_field: StoneField, log: AlipLoopLog) -> tuple[str, bool, int, float, str]:
    """(outcome before the clearance check, reached_end, field steps, end time [s], reason)."""
    for k in range(N_APPROACH, log.n_steps):
        f = log.footholds[k]
        if stone_field.in_goal(f):
            if log.fell and log.fall_index is not None and log.fall_index <= k + 1:
                return "fell", False, k - N_APPROACH + 1, float(log.fall_time or log.td_times[k]), log.fall_reason
            return "completed", True, k - N_APPROACH + 1, float(log.td_times[k]), ""
        if stone_field.stone_at(f) is None:
            return ("fell", False, k - N_APPROACH + 1, float(log.td_times[k]),
                    f"field foothold {k - N_APPROACH + 1} at {np.round(f, 3).tolist()} m is on no stone")
    steps = max(log.n_steps - N_APPROACH, 0)
    end = float(log.t[-1]) if log.t.size else 0.0
    if log.fell:
        reason = log.fall_reason
        stalled = "no reachable stone" in reason or "no way to the goal" in reason
        return ("stalled" if stalled else "fell"), False, steps, float(log.fall_time or end), reason
    return "incomplete", False, steps, end, "the step budget ran out before the goal"


def run_field(
    stone_field: StoneField, chooser: str = "cost-to-go", params: StoneFieldParams | None = None, budget: int | None = None,
    planner: StoneFieldPlanner | None = None, pushes: Sequence[Push] = (),
) -> FieldRun:
    """Cross ``stone_field`` on the ALIP with the planner's ``chooser`` (see the module docstring).

    Args:
        stone_field: the field.
        chooser: "cost-to-go" (the planner), "greedy" or "nominal" (the baselines).
        params: the planner's parameters (None: the defaults with ``chooser``).
        budget: the most footsteps on the field (None: enough for a 0.2 m stride plus 16 steps of waiting).
        planner: the planner to run (None: a :class:`StoneFieldPlanner` of ``params``; given, ``chooser`` and
            ``params`` are its own), e.g. :class:`~lipmpcc.planners.stone_milp.MilpStoneFieldPlanner`.
        pushes: forces on the COM (:class:`~lipmpcc.push.Push`; a push's ``step`` counts the approach's 6 steps).
    """
    if not isinstance(stone_field, StoneField):
        raise InvalidInputError("stone_field", stone_field, "a lipmpcc.stone_field.StoneField")
    if chooser not in CHOOSERS:
        raise InvalidInputError("chooser", chooser, f"one of {', '.join(CHOOSERS)}")
    if planner is not None and not isinstance(planner, StoneFieldPlanner):
        raise InvalidInputError("planner", planner, "a lipmpcc.planners.stone_field.StoneFieldPlanner")
    if planner is not None and planner.field is not stone_field:
        raise InvalidInputError("planner", planner.name, "a planner of this stone field")
    pushes = tuple(pushes)
    if not all(isinstance(q, Push) for q in pushes):
        raise InvalidInputError("pushes", pushes, "a sequence of lipmpcc.push.Push")
    prm = StoneFieldParams(chooser=chooser) if params is None else params
    n = int(math.ceil(stone_field.path_length / 0.2)) + 16 if budget is None else count("budget", budget, 1)
    planner = StoneFieldPlanner(stone_field, prm) if planner is None else planner
    prm = planner.params
    approach = AlipMpc(AlipMpcParams.paper(alip=prm.mpc.alip))
    log = run_alip_loop(planner, field_course(stone_field, n), config=AlipLoopConfig(alip=prm.mpc.alip, pushes=pushes),
                        approach_planner=approach, approach_steps=N_APPROACH, progress=False)
    on_field = log.plan_step >= N_APPROACH
    return judge_log(stone_field, log, planner.name, planner.params, log.plan_time[on_field])


def judge_log(stone_field: StoneField, log: AlipLoopLog, planner_name: str, params: StoneFieldParams,
              plan_times: np.ndarray) -> FieldRun:
    """The :class:`FieldRun` of a walk across ``stone_field`` recorded in ``log`` (the ALIP loop's, or a full body's
    in the same record, on the pedestrians' clock): the module docstring's outcomes."""
    outcome, reached, steps, t_end, reason = _judge(stone_field, log)
    clear = _clearance(stone_field, log, t_end, params)
    if clear is not None and clear < 0:
        outcome, reached, reason = "collided", False, f"a pedestrian touched the robot (clearance {clear:.3f} m)"
    speed = float(np.hypot(*stone_field.pedestrians[0].velocity)) if stone_field.pedestrians else None
    on = [stone_field.stone_at(f) for f in log.footholds[N_APPROACH:N_APPROACH + steps]]
    waits = sum(1 for k in range(2, len(on)) if on[k] is not None and on[k] == on[k - 2])
    return FieldRun(outcome, reached, planner_name, stone_field.seed, speed, steps, waits, clear, reason,
                    np.asarray(plan_times, float), log)


def field_cases(seeds: Sequence[int], speeds: tuple[float, float] = (0.3, 0.6)) -> list[StoneField]:
    """The study's fields: for each seed, without a pedestrian for even seeds and with one for odd seeds
    (its speed drawn from ``speeds`` [m/s] by the seed), the issue's geometry (0.2 x 0.1 m stones, gaps up
    to 0.3 m, a 1.5 m corridor)."""
    out = []
    for s in seeds:
        s = count("seed", s, 0)
        v = None if s % 2 == 0 else float(np.random.default_rng(10_000 + s).uniform(*speeds))
        out.append(make_stone_field(s, pedestrian_speed=v))
    return out


def _rate(runs: Sequence[FieldRun]) -> dict[str, Any]:
    k, n = sum(r.success for r in runs), len(runs)
    lo, hi = wilson_interval(k, n)
    return {"success": k, "n": n, "rate": k / n if n else math.nan, "wilson95": [lo, hi]}


def field_table(seeds: Sequence[int], choosers: Sequence[str] = CHOOSERS, mpc: AlipMpcParams | None = None,
                robot: str = "alip", push_scale: float | None = None) -> dict[str, Any]:
    """Success rates (Wilson 95 % intervals) and plan times of ``choosers`` on :func:`field_cases` of ``seeds``,
    overall and without / with a pedestrian, with the outcomes' counts; ``mpc``: the placement's parameters
    for every chooser (None: paper B's). ``robot``: ``"alip"``, or a full body (``"digit_like"``, a PATH.xml: its
    own ALIP constants and CoP box, ``mpc`` not read); ``push_scale``: paper B's four pushes (:func:`field_pushes`)
    at that scale (None: no push)."""
    fields = field_cases(seeds)
    pushes = () if push_scale is None else field_pushes(push_scale)
    desc = None
    if robot != "alip":
        from ..robots import load_robot

        desc = load_robot(robot)
    table: dict[str, Any] = {}
    for ch in choosers:
        if desc is None:
            prm = StoneFieldParams(chooser=ch) if mpc is None else StoneFieldParams(chooser=ch, mpc=mpc)
            runs = [run_field(f, ch, prm, pushes=pushes) for f in fields]
        else:
            runs = [_judged_full_body(desc, f, ch, pushes) for f in fields]
        times = np.concatenate([r.plan_times for r in runs]) if runs else np.zeros(0)
        outcomes = {o: sum(r.outcome == o for r in runs) for o in FIELD_OUTCOMES}
        table[runs[0].planner if runs else ch] = {
            "all": _rate(runs),
            "no_pedestrian": _rate([r for r in runs if r.pedestrian_speed is None]),
            "pedestrian": _rate([r for r in runs if r.pedestrian_speed is not None]),
            "outcomes": outcomes,
            "plan_ms": timing_stats_ms(times),
            "failed_seeds": [r.seed for r in runs if not r.success],
        }
    return table


def _judged_full_body(robot: Any, stone_field: StoneField, chooser: str, pushes: Sequence[Push] = ()) -> FieldRun:
    """One full-body run across ``stone_field`` (:func:`lipmpcc.studies.stone_field_full_body.run_field_full_body`),
    judged by :func:`judge_log`."""
    from .stone_field_full_body import run_field_full_body

    fb = run_field_full_body(robot, stone_field, pushes=pushes, chooser=chooser)
    return judge_log(fb.field, fb.log, fb.planner.name, fb.planner.params, fb.plan_times)


# ----------------------------------------------------------------------------- lipmpcc run stone-field
def study_field(seed: int, pedestrian_speed: float | None = None) -> StoneField:
    """The field of ``lipmpcc run stone-field``: :func:`field_cases`'s field of ``seed`` (a pedestrian for odd
    seeds), or with a pedestrian at ``pedestrian_speed`` [m/s] when it is given."""
    if pedestrian_speed is None:
        return field_cases([seed])[0]
    return make_stone_field(count("seed", seed, 0), pedestrian_speed=pedestrian_speed)


def field_summary(run: FieldRun, stone_field: StoneField) -> dict[str, Any]:
    """The ``summary.json`` of a field run: the study's own fields and the outcome fields every study has
    (:mod:`lipmpcc.studies.outcome`: ``outcome``, ``collided``, ``fell``, ``stopped_early``, ``reached_end``...)."""
    log = run.log
    s = {"scenario": "stone-field", "robot": "alip", **run.summary()}
    s.update({
        "n_stones": stone_field.n_stones,
        "path_length_m": stone_field.path_length,
        "goal": "end",
        "field": {"seed": stone_field.seed, "name": stone_field.name, "corridor_width_m": stone_field.corridor_width},
        "fell": run.outcome == "fell",
        "collided": run.outcome == "collided",
        "stopped_early": None,
        "stall": {"step": run.field_steps, "reason": run.reason} if run.outcome == "stalled" else None,
        "solver_failures": int(log.solver_failures) if log is not None else 0,
        "relaxed_solves": 0,
        "min_body_clearance_m": None,
        "warnings": [],
        "expected_outcome": None,
    })
    return s


def _field_figure(run: FieldRun, stone_field: StoneField) -> Any:
    """The field (stones, goal, path), the footholds and the pedestrian's track over the run."""
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    fig, ax = plt.subplots(figsize=(9, 4))
    for c, sz in zip(stone_field.centers, stone_field.sizes):
        ax.add_patch(Rectangle(tuple(c - 0.5 * sz), sz[0], sz[1], color="0.6"))
    g = stone_field.goal
    ax.add_patch(Rectangle(tuple(g.lower), g.size[0], g.size[1], color="tab:green", alpha=0.3))
    ax.plot(*stone_field.path.T, "k--", lw=0.8, label="path")
    if run.log is not None:
        f = run.log.footholds
        ax.plot(f[:, 0], f[:, 1], "o-", ms=3, lw=0.6, color="tab:blue", label=f"footholds ({run.outcome})")
        t = run.log.t
        for ped in stone_field.pedestrians:
            c = ped.center(t)
            ax.plot(c[:, 0], c[:, 1], color="tab:red", lw=0.8, label="pedestrian")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_ylim(-2.0, 2.0)
    ax.legend(loc="upper left", fontsize=7)
    ax.set_title(stone_field.name)
    return fig


def _run_pushes(opts: RunOptions) -> tuple[tuple[Push, ...], str | None]:
    """The run's pushes and their label: a sweep's own (``extra["pushes"]``, "given"), paper B's four
    (``--push-set paper-b``, or a sweep's ``extra["push_scale"]``: :func:`field_pushes`), or none."""
    given = opts.extra.get("pushes")
    if given is not None:
        if opts.push_set is not None:
            raise InvalidInputError("pushes", "given", "either --push-set paper-b or pushes of one's own, not both")
        return tuple(given), "given"
    if opts.push_set == "paper-b" or "push_scale" in opts.extra:
        return field_pushes(float(opts.extra.get("push_scale", 1.0))), "paper-b"
    return (), None


def run_stone_field(opts: RunOptions) -> RunResult:
    """``lipmpcc run stone-field``: ``--planner`` (:data:`PLANNERS`, default the stone-field planner) across the field
    of ``--seed`` (odd seeds: a pedestrian, ``--obstacle-speed`` sets its speed) on the ALIP (``--cop-range``: its
    ALIP-MPC with a foot; ``--push-set paper-b``: paper B's four pushes, :func:`field_pushes`), or on a full body
    (``--robot digit_like``: :mod:`lipmpcc.studies.stone_field_full_body`; the robot's CoP box by default)."""
    if opts.robot in ("lip",):
        raise InvalidInputError("--robot", opts.robot, "alip (the reduced model), digit_like or a PATH.xml")
    if opts.push_set not in (None, "paper-b"):
        raise InvalidInputError("--push-set", opts.push_set, "paper-b (paper B's four pushes) for stone-field")
    name = opts.planner or "stone-field"
    if name not in PLANNERS:
        raise InvalidInputError("--planner", name, f"one of {', '.join(PLANNERS)} for stone-field")
    stone_field = study_field(opts.rng_seed, opts.obstacle_speed)
    pushes, label = _run_pushes(opts)
    files, replay = [], None
    if opts.robot not in (None, "", "alip"):
        run, stone_field, extra, files, replay = _full_body(opts, name, stone_field, pushes)
    else:
        mpc = AlipMpcParams() if opts.cop_range is None else AlipMpcParams.paper(cop_range=tuple(opts.cop_range))
        prm = StoneFieldParams(chooser=_CHOOSER[name], mpc=mpc)
        planner = MilpStoneFieldPlanner(stone_field, prm) if name == "stone-field-milp" else StoneFieldPlanner(stone_field, prm)
        run, extra = run_field(stone_field, planner=planner, pushes=pushes), {}
    summary = field_summary(run, stone_field)
    summary.update(extra)
    summary["push_set"] = label
    summary["pushes"] = [{"field_step": (p.step or 0) - N_APPROACH + 1, "force_N": list(p.force[:2]),
                          "window_s": [p.t_start, p.t_end]} for p in pushes]
    summary["pushes_before_goal"] = sum(1 for p in pushes if p.step is not None
                                        and p.step - N_APPROACH + 1 <= run.field_steps)
    return RunResult(summary, {"field": _field_figure(run, stone_field)}, run.log, files=list(files), replay=replay)


def _full_body(opts: RunOptions, name: str, stone_field: StoneField, pushes: tuple[Push, ...]
               ) -> tuple[FieldRun, StoneField, dict[str, Any], list[Any], Any]:
    """The run on a full body: (the judged run, the field as placed in the scene, the summary's extra fields, the
    files written (``--video``), the run's replay)."""
    from ..robots import load_robot
    from . import replay as _replay
    from .stone_field_full_body import run_field_full_body

    if name == "stone-field-milp":
        raise InvalidInputError("--planner", name, "stone-field, greedy-stone or path-agnostic-alip-mpc on a full body")
    robot = load_robot(opts.robot)
    fb = run_field_full_body(robot, stone_field, opts.cop_range, pushes, chooser=_CHOOSER[name], record_video=True)
    run = judge_log(fb.field, fb.log, fb.planner.name, fb.planner.params, fb.plan_times)
    extra = {"robot": str(opts.robot), "cop_range": list(fb.planner.params.mpc.cop_range), **fb.result.summary()}
    for key in ("fell", "steps", "fall_reason", "collided"):  # the study's own
        extra.pop(key, None)
    windows = [(p.t_start, p.t_end, tuple(p.force[:2])) for p in fb.result.pushes]
    rep, files = _replay.run_outputs(opts, robot, fb.loop.sim.model, fb.result, obstacles=fb.field.pedestrians,
                                     pushes=windows, fps=fb.loop.params.video_fps)
    return run, fb.field, extra, files, rep
