"""Paper B's studies on the ALIP: ``stones`` (profiles I–IV or a stone file) and ``push``.

Set-up (documented in notebook 05):

- The robot starts standing (left foot in stance), walks the 6 approach steps of
  :func:`lipmpcc.terrain.approach_footholds` and enters the stones with a right swing.
  The approach is driven by ALIP-MPC for every planner under test, so ALIP-MPC and
  ALIP-QP take over in the same state at the first stone (paper B: "we try to ensure
  consistent initial conditions in each comparison test"); it previews the stones ahead
  like any planner.
- ``stones``: ``--profile I|II|III|IV`` (default I), ``--L/--W`` for profile I
  (default 0.4 / +0.15), ``--seed`` for II–IV, or ``--stones FILE.csv``; 32 stones
  (16 in fast mode), ``--steps`` to walk fewer.
- ``push``: 24 stones of (L, W) = (0.4, 0) (22 in fast mode); pushes on the COM from 0.1 to
  0.2 s into the swing towards stone 5 (F_x = +150 N), 10 (-150 N), 15 (F_y = +75 N) and
  20 (-75 N).
- ``--planner alip-mpc`` (default) or ``alip-qp``; ``--robot alip`` (default, the reduced
  model) or a full-body robot, ``--robot digit_like`` or ``--robot PATH.xml``: the same studies in
  MuJoCo with the whole-body controller, :mod:`lipmpcc.scenarios.fullbody_stepping_stones`.

On the ALIP the failure criterion is :mod:`lipmpcc.loops.alip`'s; on a full-body robot, the
simulator's (a fall, or a foot in the pit between the stones).
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from .. import config
from ..exceptions import InvalidInputError
from ..models.alip import AlipParams
from ..planners.alip_mpc import AlipMpc, AlipMpcParams
from ..planners.alip_qp import AlipQp, AlipQpParams
from ..loops.alip import AlipLoopConfig, AlipLoopLog, Push, loop_metrics, run_alip_loop
from ..terrain import (
    N_APPROACH,
    N_STONES,
    StoneSequence,
    approach_footholds,
    load_stones,
    make_profile,
    paper_cases,
    stones_from_steps,
)
from . import RunOptions, RunResult

__all__ = [
    "PLANNERS",
    "PAPER_TABLE_II",
    "PAPER_PUSHES",
    "make_planner",
    "paper_pushes",
    "push_stones",
    "push_sweep",
    "run_case",
    "study_table",
    "sweep_markdown",
    "table_markdown",
    "run_stones",
    "run_push",
]

PLANNERS = ("alip-mpc", "alip-qp")
PUSH_STEPS = 24
PUSH_LW = (0.4, 0.0)
# (stone index 1-based, (F_x, F_y) [N]); window 0.1-0.2 s into that swing (paper B §V-B)
PAPER_PUSHES: tuple[tuple[int, tuple[float, float]], ...] = (
    (5, (150.0, 0.0)),
    (10, (-150.0, 0.0)),
    (15, (0.0, 75.0)),
    (20, (0.0, -75.0)),
)
PUSH_WINDOW = (0.1, 0.2)  # [s]

# Paper B Table II and §V-A: step-position RMSE [m] (None = the planner fails).
PAPER_TABLE_II: dict[str, dict[str, float | None]] = {
    "I L=0.2 W=+0.15": {"alip-mpc": 0.036, "alip-qp": 0.040},
    "I L=0.4 W=+0.15": {"alip-mpc": 0.020, "alip-qp": 0.029},
    "I L=0.55 W=+0.15": {"alip-mpc": 0.028, "alip-qp": None},
    "I L=0.2 W=-0.15": {"alip-mpc": 0.039, "alip-qp": 0.042},
    "I L=0.4 W=-0.15": {"alip-mpc": 0.019, "alip-qp": 0.024},
    "I L=0.55 W=-0.15": {"alip-mpc": 0.022, "alip-qp": None},
    "II": {"alip-mpc": 0.023, "alip-qp": None},
    "III": {"alip-mpc": 0.027, "alip-qp": None},
    "IV": {"alip-mpc": 0.024, "alip-qp": None},
}


def case_label(profile: str, L: float | None = None, W: float | None = None, seed: int | None = None) -> str:
    """Row label: ``"I L=0.4 W=+0.15"`` or ``"II seed 3"``."""
    if profile == "I":
        return f"I L={L:g} W={W:+.2f}"
    return f"{profile} seed {seed}"


def make_planner(
    name: str, alip: AlipParams | None = None, solver: str | None = None, cop_range: tuple[float, float] = (0.0, 0.0)
) -> AlipMpc | AlipQp:
    """``"alip-mpc"`` (paper B's preset; with a foot, ``cop_range`` [m], see
    :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`) or ``"alip-qp"`` (Khadiv's QP on stones)."""
    a = AlipParams() if alip is None else alip
    if name == "alip-mpc":
        return AlipMpc(AlipMpcParams.paper(alip=a, cop_range=tuple(cop_range)), solver=solver)
    if name == "alip-qp":
        if solver not in (None, "proxqp"):
            raise InvalidInputError("solver", solver, "None or 'proxqp' for alip-qp")
        return AlipQp(AlipQpParams.paper(alip=a))
    raise InvalidInputError("--planner", name, "'alip-mpc' or 'alip-qp'")


def paper_pushes(scale: float = 1.0, n_approach: int = N_APPROACH) -> tuple[Push, ...]:
    """Paper B's four pushes, forces multiplied by ``scale``, as loop pushes."""
    if not isinstance(scale, (int, float)) or not math.isfinite(scale) or scale < 0:
        raise InvalidInputError("scale", scale, "a finite number >= 0")
    a, b = PUSH_WINDOW
    return tuple(
        Push((scale * f[0], scale * f[1]), a, b, step=n_approach + j - 1) for j, f in PAPER_PUSHES
    )


def run_case(
    planner: str,
    stones: StoneSequence,
    pushes: Sequence[Push] = (),
    alip: AlipParams | None = None,
    shared_approach: bool = True,
    solver: str | None = None,
    cop_range: tuple[float, float] = (0.0, 0.0),
) -> tuple[AlipLoopLog, dict[str, Any]]:
    """Approach + ``stones`` with one planner; returns the log and :func:`loop_metrics`.

    Args:
        planner: "alip-mpc" or "alip-qp".
        stones: the stones (without the approach).
        pushes: COM pushes (step indices count the approach).
        alip: ALIP constants.
        shared_approach: drive the approach with ALIP-MPC whatever ``planner`` is
            (False: ``planner`` walks its own approach).
        solver: ALIP-MPC solver ("sqp" or "ipopt").
        cop_range: the ALIP-MPC's centre-of-pressure box (x, y) [m] (a foot; (0, 0): paper B's point
            foot), for the planner under test and the approach; the loop then turns the ALIP about
            the planned centre of pressure.
    """
    if not isinstance(stones, StoneSequence):
        raise InvalidInputError("stones", stones, "a StoneSequence")
    a = AlipParams() if alip is None else alip
    seq = approach_footholds() + stones
    pl = make_planner(planner, a, solver, cop_range=cop_range)
    app = make_planner("alip-mpc", a, cop_range=cop_range) if shared_approach else None
    log = run_alip_loop(
        pl,
        seq,
        config=AlipLoopConfig(alip=a, pushes=tuple(pushes)),
        approach_planner=app,
        approach_steps=N_APPROACH if shared_approach else 0,
    )
    return log, loop_metrics(log)


def study_table(
    n_stones: int = N_STONES,
    planners: Sequence[str] = PLANNERS,
    cases: Sequence[dict] | None = None,
    alip: AlipParams | None = None,
) -> list[dict[str, Any]]:
    """Table II on the ALIP: one row per case and planner with the run metrics and the
    paper's RMSE for that case."""
    rows: list[dict[str, Any]] = []
    for case in paper_cases() if cases is None else cases:
        stones = make_profile(case["profile"], case["seed"], case["L"], case["W"]).head(n_stones)
        label = case_label(case["profile"], case["L"], case["W"], case["seed"])
        paper_key = label if case["profile"] == "I" else case["profile"]
        for name in planners:
            _, m = run_case(name, stones, alip=alip)
            rows.append({"case": label, "planner": name, "paper_rmse_m": PAPER_TABLE_II[paper_key][name], **m})
    return rows


def push_stones(n: int = PUSH_STEPS) -> StoneSequence:
    """The push test's stones: ``n`` stones of (L, W) = (0.4, 0)."""
    return stones_from_steps(np.full(n, PUSH_LW[0]), np.full(n, PUSH_LW[1]), name="push (L, W) = (0.4, 0)")


def push_sweep(
    scales: Sequence[float] = (1.0, 0.75, 0.5),
    planners: Sequence[str] = PLANNERS,
    n_stones: int = PUSH_STEPS,
    alip: AlipParams | None = None,
) -> list[dict[str, Any]]:
    """Each of paper B's four pushes alone, with its force scaled: one row per
    (push, scale, planner) with ``fell`` and ``fall_step``."""
    rows = []
    stones = push_stones(n_stones)
    for i, (stone, force) in enumerate(PAPER_PUSHES):
        if stone > n_stones:
            continue
        for sc in scales:
            p = paper_pushes(sc)[i]
            for name in planners:
                _, m = run_case(name, stones, pushes=(p,), alip=alip)
                rows.append(
                    {"push": f"stone {stone}: F = {tuple(force)} N", "scale": sc, "planner": name, "fell": m["fell"], "fall_step": m["fall_step"]}
                )
    return rows


def sweep_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """Markdown table of :func:`push_sweep`: for each push and scale, each planner's outcome."""
    planners = list(dict.fromkeys(r["planner"] for r in rows))
    keys = list(dict.fromkeys((r["push"], r["scale"]) for r in rows))
    lines = ["| push | scale | " + " | ".join(planners) + " |", "|---|---|" + "---|" * len(planners)]
    for push, sc in keys:
        cells = []
        for p in planners:
            r = next(r for r in rows if r["push"] == push and r["scale"] == sc and r["planner"] == p)
            cells.append(f"falls at stone {r['fall_step']}" if r["fell"] else "survives")
        lines.append(f"| {push} | {sc:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def table_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """Markdown table: ALIP-MPC and ALIP-QP side by side with the paper's numbers."""
    by_case: dict[str, dict[str, dict]] = {}
    for r in rows:
        by_case.setdefault(r["case"], {})[r["planner"]] = r

    def cell(r: dict | None) -> str:
        if r is None:
            return "–"
        if r["fell"]:
            return f"falls at stone {r['fall_step']}"
        return f"{r['step_rmse_m']:.3f}"

    def paper(r: dict | None) -> str:
        if r is None:
            return "–"
        v = r["paper_rmse_m"]
        return "fails" if v is None else f"{v:.3f}"

    lines = [
        "| case | ALIP-MPC RMSE [m] | paper | ALIP-QP RMSE [m] | paper | MPC solver failures |",
        "|---|---|---|---|---|---|",
    ]
    for case, d in by_case.items():
        m, q = d.get("alip-mpc"), d.get("alip-qp")
        fails = "–" if m is None else str(m["solver_failures"])
        lines.append(f"| {case} | {cell(m)} | {paper(m)} | {cell(q)} | {paper(q)} | {fails} |")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- CLI
def _planner_name(opts: RunOptions) -> str:
    name = opts.planner or "alip-mpc"
    if name not in PLANNERS:
        raise InvalidInputError("--planner", name, "'alip-mpc' or 'alip-qp' for this scenario")
    return name


def _check_robot(opts: RunOptions) -> str:
    robot = opts.robot or "alip"
    if robot in ("lip", ""):
        raise InvalidInputError("--robot", robot, "'alip' (the reduced model), 'digit_like' or a PATH.xml (full body)")
    return robot


def _full_body(opts: RunOptions) -> bool:
    """True when ``--robot`` names a full-body robot (anything but ``alip``)."""
    return _check_robot(opts) != "alip"


def _cop_range(opts: RunOptions, planner: str) -> tuple[float, float] | None:
    """``--cop-range`` checked: None (not given) or two numbers in [0, 0.2) m, with alip-mpc only."""
    from ..robot import MAX_ALIP_COP_RANGE

    c = opts.cop_range
    if c is None:
        return None
    expected = f"two half-extents DX DY in [0, {MAX_ALIP_COP_RANGE:g}) m"
    try:
        d = tuple(float(x) for x in c)
    except (TypeError, ValueError):
        raise InvalidInputError("--cop-range", c, expected) from None
    if len(d) != 2 or not all(math.isfinite(x) and 0.0 <= x < MAX_ALIP_COP_RANGE for x in d):
        raise InvalidInputError("--cop-range", c, expected)
    if planner != "alip-mpc" and max(d) > 0.0:
        raise InvalidInputError("--cop-range", c, "0 0 with --planner alip-qp (only the ALIP-MPC plans the centre of pressure)")
    return d  # type: ignore[return-value]


def _n_stones(opts: RunOptions, available: int, full: int, fast: int) -> int:
    n = int(config.horizon(full, fast))
    if opts.steps is not None:
        if not isinstance(opts.steps, int) or opts.steps < 1:
            raise InvalidInputError("--steps", opts.steps, "a positive integer")
        if opts.steps > available:
            raise InvalidInputError("--steps", opts.steps, f"at most {available} (the number of stones)")
        n = opts.steps
    return min(n, available)


def _stones_from_options(opts: RunOptions) -> tuple[StoneSequence, dict[str, Any]]:
    if opts.stones is not None:
        if opts.profile is not None or opts.L is not None or opts.W is not None:
            raise InvalidInputError("--stones", opts.stones, "either --stones FILE or --profile/--L/--W, not both")
        seq = load_stones(opts.stones)
        return seq, {"profile": None, "stones_file": str(opts.stones), "L": None, "W": None, "seed": None}
    profile = (opts.profile or "I").strip().upper()
    if profile not in ("I", "II", "III", "IV"):
        raise InvalidInputError("--profile", opts.profile, "one of I, II, III, IV")
    if profile != "I" and (opts.L is not None or opts.W is not None):
        raise InvalidInputError("--L/--W", (opts.L, opts.W), "only with --profile I")
    L = W = None
    if profile == "I":
        L = 0.4 if opts.L is None else float(opts.L)
        W = 0.15 if opts.W is None else float(opts.W)
        if not 0.0 < L <= 0.6:
            raise InvalidInputError("--L", L, "a step length in (0, 0.6] [m]")
        if not -0.2 <= W <= 0.2:
            raise InvalidInputError("--W", W, "a lateral offset in [-0.2, 0.2] [m]")
    seq = make_profile(profile, opts.seed, L, W)
    return seq, {"profile": profile, "stones_file": None, "L": L, "W": W, "seed": opts.seed if profile != "I" else None}


def _summary(
    scenario: str, planner: str, robot: str, log: AlipLoopLog, m: dict[str, Any], alip: AlipParams, extra: dict[str, Any]
) -> dict[str, Any]:
    s: dict[str, Any] = {"scenario": scenario, "planner": planner, "robot": robot}
    s.update(extra)
    s.update(
        {
            "n_stones": m["n_stones"],
            "fell": m["fell"],
            "fall_step": m["fall_step"],
            "fall_reason": m["fall_reason"],
            "steps_completed": m["steps_completed"],
            "step_rmse_m": m["step_rmse_m"],
            "step_error_max_m": m["step_error_max_m"],
            "stones_violated": m["stones_violated"],
            "step_duration_min_s": m["step_duration_min_s"],
            "step_duration_max_s": m["step_duration_max_s"],
            "solve_ms": {k: m["solve_ms"][k] for k in ("median", "p90", "max", "n")},
            "plan_ms": {k: m["plan_ms"][k] for k in ("median", "p90", "max", "n")},
            "solver_failures": m["solver_failures"],
            "fallback_ticks": m["fallback_ticks"],
            "solver": "sqpmethod+qrqp" if planner == "alip-mpc" else "proxqp",
            "approach": f"{N_APPROACH} steps driven by alip-mpc",
            "model": {"mass_kg": alip.mass, "z_c_m": alip.z_c, "g": alip.g},
            "fast_mode": config.fast_mode(),
        }
    )
    return s


def run_stones(opts: RunOptions) -> RunResult:
    """``lipmpcc run stones``: one stepping-stone course with one planner."""
    from ..plots import stepping_stones as plots

    if _full_body(opts):
        from .fullbody_stepping_stones import run_stones as run_full_body

        return run_full_body(opts)
    planner = _planner_name(opts)
    robot = _check_robot(opts)
    seq, info = _stones_from_options(opts)
    n = _n_stones(opts, len(seq), N_STONES, 16)
    stones = seq.head(n)
    alip = AlipParams()
    cop = _cop_range(opts, planner) or (0.0, 0.0)
    log, m = run_case(planner, stones, alip=alip, cop_range=cop)
    key = None
    if info["profile"] == "I":
        key = case_label("I", info["L"], info["W"])
    elif info["profile"] is not None:
        key = info["profile"]
    paper = PAPER_TABLE_II.get(key, {}).get(planner) if key else None
    extra = {**info, "paper_rmse_m": paper, "paper_case": key}
    summary = _summary("stones", planner, robot, log, m, alip, extra)
    summary["model"]["cop_range_m"] = list(cop)
    title = f"{planner}, {stones.name}"
    figures = {
        "footprints": plots.plot_footprints(log, title=title),
        "durations_dcm": plots.plot_durations_and_dcm(log, title=title),
    }
    return RunResult(summary=summary, figures=figures, log=log)


def run_push(opts: RunOptions) -> RunResult:
    """``lipmpcc run push``: paper B's perturbation test on (L, W) = (0.4, 0) stones."""
    from ..plots import stepping_stones as plots

    if _full_body(opts):
        from .fullbody_stepping_stones import run_push as run_full_body

        return run_full_body(opts)
    planner = _planner_name(opts)
    robot = _check_robot(opts)
    if opts.stones is not None or opts.profile is not None or opts.L is not None or opts.W is not None:
        raise InvalidInputError("--stones/--profile/--L/--W", opts.profile or opts.stones, "none: the push test uses (L, W) = (0.4, 0) stones")
    n = _n_stones(opts, PUSH_STEPS, PUSH_STEPS, 22)
    stones = push_stones(n)
    alip = AlipParams()
    pushes = paper_pushes()
    cop = _cop_range(opts, planner) or (0.0, 0.0)
    log, m = run_case(planner, stones, pushes=pushes, alip=alip, cop_range=cop)
    extra = {
        "profile": None,
        "L": PUSH_LW[0],
        "W": PUSH_LW[1],
        "pushes": [
            {"stone": j, "force_N": list(f), "window_s": list(PUSH_WINDOW)} for j, f in PAPER_PUSHES
        ],
    }
    summary = _summary("push", planner, robot, log, m, alip, extra)
    summary["model"]["cop_range_m"] = list(cop)
    title = f"{planner}, push test" + (f" with a foot ({cop[0]:g} x {cop[1]:g} m)" if max(cop) > 0 else "")
    figures = {
        "push_response": plots.plot_push_response(log, title=title),
        "footprints": plots.plot_footprints(log, title=title),
    }
    return RunResult(summary=summary, figures=figures, log=log)
