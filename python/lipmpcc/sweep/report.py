"""A sweep's statistics: ``OUT/report.md`` and its figures, read from the store alone (``lipmpcc sweep
--report OUT``, and at the end of every run).

- Survival per planner (a case survives when it neither fell nor collided; errors and dead workers are
  counted apart), with Wilson score intervals at 95 % (:func:`wilson_interval`).
- When the cases carry a push: survival against the push's impulse [N·s] per planner
  (``survival_vs_impulse.png``; for ``push_scale`` sweeps, the impulse of the largest scaled push).
- When ``direction`` is an axis with 3 values or more: the largest recoverable impulse per direction and
  planner (the largest impulse at and below which every case of that direction survived), as a polar plot
  (``recoverable_impulse_polar.png``).
- For paper B's push test on the ALIP with a point-foot ALIP-MPC: the analytic largest backward impulse
  the point foot can survive (:func:`point_foot_bound`), beside the measured boundary (a dashed line on
  both figures, a line in the report).
- When ``obstacle_speed`` is an axis: overtaking success (overtook, neither fell nor collided) against the
  speed per planner (``overtaking_vs_speed.png``); for a study whose summaries have no ``overtook`` (stone-field),
  the success rate (the outcome's) against the speed (``success_vs_speed.png``).
- When the cases follow a path (their summaries have ``path_length_m``): how the runs ended per planner
  (``completed``, ``trailing``, ``stalled``, ``incomplete``, ``fell``, ``collided``, ``stopped_early``, any
  other outcome), the success rate (completed or trailing, :data:`lipmpcc.studies.outcome.SUCCESS_OUTCOMES`)
  with its interval, and the stalled cases with what bound them.
- When ``profile`` or ``seed`` is an axis: the error RMSE (``rmse_m``) as mean ± std and the fall rate per
  planner (and profile, or push scale): Table II over seeds.
"""

from __future__ import annotations

import math
import sqlite3
from collections import defaultdict
from pathlib import Path
from typing import Any, Iterable

from ..exceptions import InvalidInputError
from ..metrics import Z95, wilson_interval  # one definition (the sweeps' and the scene benchmark's)
from .store import STORE_NAME

__all__ = ["Z95", "BOUND_LABEL", "wilson_interval", "load_rows", "survival_by", "recoverable_impulse", "point_foot_bound",
           "point_foot_bounds", "write_report"]

BOUND_LABEL = "point-foot bound (analytic)"  # the dashed line of :func:`point_foot_bound`


def load_rows(out: str | Path) -> tuple[dict[str, str], list[dict[str, Any]]]:
    """The store's ``meta`` and its ``cases`` rows (by case index)."""
    path = Path(out) / STORE_NAME
    if not path.is_file():
        raise InvalidInputError("--report", str(out), f"a sweep's output folder (with {STORE_NAME})")
    db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        meta = dict(db.execute("SELECT key, value FROM meta").fetchall())
        cur = db.execute("SELECT * FROM cases ORDER BY idx")
        names = [d[0] for d in cur.description]
        rows = [dict(zip(names, r)) for r in cur.fetchall()]
    finally:
        db.close()
    return meta, rows


def survival_by(rows: Iterable[dict[str, Any]], key: str, ok: str = "survived") -> dict[tuple[str, Any], tuple[int, int]]:
    """(planner, value of column ``key``) -> (cases where column ``ok`` is 1, cases that ran) over the
    ``done`` rows with a value."""
    acc: dict[tuple[str, Any], list[int]] = defaultdict(lambda: [0, 0])
    for r in rows:
        if r["status"] != "done" or r.get(key) is None:
            continue
        v = round(r[key], 9) if isinstance(r[key], float) else r[key]
        acc[(r["planner"], v)][0] += int(bool(r.get(ok)))
        acc[(r["planner"], v)][1] += 1
    return {k: (a[0], a[1]) for k, a in sorted(acc.items(), key=lambda kv: (kv[0][0], kv[0][1]))}


def recoverable_impulse(rows: Iterable[dict[str, Any]]) -> dict[tuple[str, float], float]:
    """(planner, direction [rad]) -> the largest impulse [N·s] at and below which every ``done`` case of that
    direction survived (0 when the smallest failed)."""
    by: dict[tuple[str, float], dict[float, bool]] = defaultdict(dict)
    for r in rows:
        if r["status"] != "done" or r.get("impulse_Ns") is None or r.get("p_direction") is None:
            continue
        cell = by[(r["planner"], round(r["p_direction"], 9))]
        imp = round(r["impulse_Ns"], 9)
        cell[imp] = cell.get(imp, True) and bool(r["survived"])
    out = {}
    for key, cell in sorted(by.items()):
        best = 0.0
        for imp in sorted(cell):
            if not cell[imp]:
                break
            best = imp
        out[key] = best
    return out


def point_foot_bound(onset_s: float, duration_s: float, push_step: int, n_stones: int, mass: float = 47.9,
                     z_c: float = 0.9, g: float = 9.81) -> float:
    """The largest backward impulse [N·s] the point-foot ALIP can survive in paper B's push test (analytic).

    The push test walks (L, W) = (0.4, 0) stones along +x; a push of impulse ``J`` [N·s], force
    ``F = J / Δt`` [N] held for ``Δt = duration_s`` [s], starts ``t_p = onset_s`` [s] after the touch-down
    that starts footstep ``push_step`` (the stance foot is then on stone ``j = push_step − N_APPROACH``,
    1-based; the swing goes towards stone j + 1).

    1. *Nominal state.* On equal stones the ALIP-MPC walks the periodic gait of its nominal duration
       ``T_nom`` [s]: the step-to-step ALIP (paper B eq. 8) ``z⁺ = σ z − L`` with ``σ = e^{λ T_nom}`` has
       the fixed point ``z⁰_nom = L / (σ − 1)`` [m], the DCM ahead of the stance foot at the step's start
       (λ = √(g/z_c) [1/s]). (0.095 m for L = 0.4 m, T_nom = 0.5 s; the runs' ``z_initial`` on the
       stones agrees to 1 mm.)
    2. *The push.* With a point foot the DCM obeys ``ξ̇ = λ(ξ − p) + F/(mλ)`` [m/s]: linear, so the push adds
       to the unpushed motion a DCM offset whatever the footholds, and its effect equals a shift of the
       step's initial DCM ``z⁰`` (eq. 10: ``z⁰ = z(t) e^{−λt}``) by
       ``Δz⁰ = −(J cos θ)/(mλ) · e^{−λ t_p} · (1 − e^{−λΔt})/(λΔt)`` [m] (θ the push's direction, 0 = +x;
       an instantaneous push, Δt → 0, gives the DCM jump J/(mλ) at t_p).
    3. *Reachability.* :func:`lipmpcc.models.alip.min_forward_dcm_on_stones` gives the least ``z⁰`` from
       which the stones ahead can still be reached with the longest steps ``T_max`` onto their near edges:
       ``z_req`` [m]. Below it every planner with a point foot falls.

    Hence a backward push (θ = 180°) of ``J > J_max = (z⁰_nom − z_req) · mλ · e^{λ t_p} · λΔt / (1 − e^{−λΔt})``
    cannot be survived; a push at θ with cos θ < 0 cannot when ``−J cos θ > J_max``. It is a necessary
    condition only: lateral motion, the kinematic limits and the planner may fail sooner. ``T_nom`` and
    ``T_max`` are paper B's (0.5 s, 0.65 s; :class:`lipmpcc.planners.alip_mpc.AlipMpcParams`).

    Args:
        onset_s: push start after the touch-down of ``push_step`` [s].
        duration_s: push duration Δt [s] (> 0).
        push_step: the footstep pushed (0-based, approach included); its stance must be on a stone.
        n_stones: stones of the course (the stones ahead of the stance up to it count).
        mass: m [kg]; z_c: COM height [m]; g: gravity [m/s²].
    Returns: J_max [N·s] (0 when the nominal state is already below ``z_req``).
    """
    from ..models.alip import min_forward_dcm_on_stones
    from ..planners.alip_mpc import AlipMpcParams
    from ..studies import paper
    from ..studies.stone_course import push_stones
    from ..terrain import N_APPROACH

    j = int(push_step) - N_APPROACH
    if not 1 <= j < int(n_stones):
        raise InvalidInputError("push_step", push_step, f"a footstep whose stance is on a stone with a stone ahead "
                                                         f"({N_APPROACH + 1}..{N_APPROACH + int(n_stones) - 1})")
    if not (math.isfinite(duration_s) and duration_s > 0 and math.isfinite(onset_s) and onset_s >= 0):
        raise InvalidInputError("onset_s/duration_s", (onset_s, duration_s), "onset >= 0 and duration > 0 [s]")
    lam = math.sqrt(g / z_c)
    prm = AlipMpcParams.paper()
    z_nom = paper.push_test().L / (math.exp(lam * prm.T_nom) - 1.0)
    stones = push_stones(int(n_stones))
    near = [float(stones.centers[i][0] - 0.5 * stones.sizes[i][0]) for i in range(j, int(n_stones))]
    z_req = min_forward_dcm_on_stones(float(stones.centers[j - 1][0]), near, lam, prm.T_max)
    x = lam * duration_s
    return max(0.0, (z_nom - z_req) * mass * lam * math.exp(lam * onset_s) * x / (1.0 - math.exp(-x)))


def point_foot_bounds(meta: dict[str, str], rows: Iterable[dict[str, Any]]) -> dict[str, float]:
    """planner label -> :func:`point_foot_bound` [N·s] for the point-foot ALIP-MPC cases of a ``push`` sweep on the
    ALIP (one value per planner: only when its cases share the push's timing and footstep, on a stone, and
    the planner keeps paper B's settings (no ``preset``/``set``); none otherwise)."""
    import json

    from .spec import parse_spec
    from .worker import case_pushes

    if meta.get("study") != "push" or "spec" not in meta:
        return {}
    spec = parse_spec(json.loads(meta["spec"]))
    units = {a.name: a.unit for a in spec.axes}
    tuned = {pl.label for pl in spec.planners  # --preset / --set may move T_nom, T_max: the bound's are paper B's
             if {**spec.options, **pl.options}.get("preset") or {**spec.options, **pl.options}.get("set")}
    found: dict[str, set[float]] = defaultdict(set)
    for r in rows:
        s = json.loads(r["summary"]) if r["status"] == "done" and r.get("summary") else {}
        model = s.get("model", {})
        if (s.get("robot") != "alip" or s.get("planner") != "alip-mpc" or any(model.get("cop_range_m", [1.0]))
                or r["planner"] in tuned):
            continue
        pushes, _ = case_pushes({"study": "push", "robot": "alip", "planner_name": "alip-mpc", "units": units,
                                 "params": json.loads(r["params"])})
        if not pushes or pushes[0].step is None:
            continue
        p = pushes[0]
        try:
            found[r["planner"]].add(round(point_foot_bound(p.t_start, p.t_end - p.t_start, p.step, s["stones_total"],
                                                           model["mass_kg"], model["z_c_m"], model["g"]), 9))
        except InvalidInputError:  # a push while the stance is on the approach: no bound (the gait is not periodic)
            found[r["planner"]].add(math.nan)
    return {k: next(iter(v)) for k, v in sorted(found.items()) if len(v) == 1 and not math.isnan(next(iter(v)))}


def _fmt_rate(k: int, n: int) -> str:
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n} = {100.0 * k / n:.0f} % [{100 * lo:.0f}, {100 * hi:.0f}]" if n else "-"


def _rate_table(title: str, col: str, table: dict[tuple[str, Any], tuple[int, int]], unit: str) -> list[str]:
    planners = sorted({p for p, _ in table})
    values = sorted({v for _, v in table})
    lines = [f"### {title}", "", f"| {col} [{unit}] | " + " | ".join(planners) + " |",
             "|---|" + "---|" * len(planners)]
    for v in values:
        cells = [_fmt_rate(*table[(p, v)]) if (p, v) in table else "-" for p in planners]
        lines.append(f"| {v:g} | " + " | ".join(cells) + " |" if isinstance(v, (int, float)) else f"| {v} | " + " | ".join(cells) + " |")
    return lines + [""]


def _plot_rates(table: dict[tuple[str, Any], tuple[int, int]], xlabel: str, ylabel: str, path: Path,
                bound: float | None = None) -> None:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for planner in sorted({p for p, _ in table}):
        xs = sorted(v for p, v in table if p == planner)
        rate = [table[(planner, x)][0] / table[(planner, x)][1] for x in xs]
        ci = [wilson_interval(*table[(planner, x)]) for x in xs]
        err = [[max(0.0, r - c[0]) for r, c in zip(rate, ci)], [max(0.0, c[1] - r) for r, c in zip(rate, ci)]]
        ax.errorbar(xs, rate, yerr=err, marker="o", capsize=3, label=planner)
    if bound is not None:
        ax.axvline(bound, color="k", ls="--", lw=1.2, label=f"{BOUND_LABEL}: backward, {bound:.1f} N s")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_ylim(-0.05, 1.05)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def _plot_polar(best: dict[tuple[str, float], float], path: Path, bound: float | None = None) -> None:
    import matplotlib.pyplot as plt
    import numpy as np

    fig = plt.figure(figsize=(5.5, 5.5))
    ax = fig.add_subplot(projection="polar")
    for planner in sorted({p for p, _ in best}):
        dirs = sorted(d for p, d in best if p == planner)
        r = [best[(planner, d)] for d in dirs]
        ax.plot(dirs + dirs[:1], r + r[:1], marker="o", label=planner)
    if bound is not None:  # -J cos(theta) = J_max: the line x = -J_max in the plane of the plot
        rmax = max([*best.values(), bound]) * 1.1
        th = np.linspace(math.pi / 2, 3 * math.pi / 2, 181)[1:-1]
        r = -bound / np.cos(th)
        keep = r <= rmax
        ax.plot(th[keep], r[keep], "k--", lw=1.2, label=f"{BOUND_LABEL}: -J cos(dir) = {bound:.1f} N s")
        ax.set_rmax(rmax)
    ax.set_title("largest recoverable impulse [N s] by push direction (0 = +x)")
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, -0.15))
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def _recoverable_lines(best: dict[tuple[str, float], float], bounds: dict[str, float] | None = None) -> list[str]:
    """The largest recoverable impulse [N s]: one row per direction, one column per planner (and the
    point-foot bound, :func:`point_foot_bound`, where it applies)."""
    planners = sorted({p for p, _ in best})
    lines = ["### Largest recoverable impulse [N s] by push direction", "",
             "(the largest impulse at and below which every case of that direction survived)", "",
             "| direction [deg] | " + " | ".join(planners) + " |", "|---|" + "---|" * len(planners)]
    for d in sorted({d for _, d in best}):
        lines.append(f"| {math.degrees(d):.0f} | " + " | ".join(f"{best[(p, d)]:g}" if (p, d) in best else "-"
                                                              for p in planners) + " |")
    return lines + ["", *_bound_lines(bounds or {}), "![recoverable impulse](recoverable_impulse_polar.png)", ""]


def _bound_lines(bounds: dict[str, float]) -> list[str]:
    """One line per point-foot planner: the analytic bound on the backward impulse."""
    return [f"{BOUND_LABEL} for `{p}`: a backward push of more than {b:.2f} N s (its component against the walking "
            "direction, -J cos(direction)) cannot be survived with a point foot (the nominal DCM minus the push's "
            "shift falls below the least DCM from which the stones ahead are reachable; a necessary condition)."
            for p, b in bounds.items()] + ([""] if bounds else [])


def _summary_lines(meta: dict[str, str], rows: list[dict[str, Any]]) -> list[str]:
    status: dict[str, int] = defaultdict(int)
    for r in rows:
        status[r["status"]] += 1
    total = int(meta["n_cases"]) if "n_cases" in meta else None
    wall = [r["wall_s"] for r in rows if r.get("wall_s") is not None]
    lines = [f"# Sweep: {meta.get('name', '')}", "",
             f"Study `{meta.get('study')}`, spec hash `{meta.get('spec_hash')}`, lipmpcc {meta.get('lipmpcc_version')}, "
             f"fast mode {meta.get('fast_mode')}.", "",
             f"Cases recorded: {len(rows)}{'' if total is None else f' of {total}'} "
             f"(done {status['done']}, errors {status['error']}, timed out {status['timeout']}, worker died {status['died']}); "
             f"mean wall time per case {sum(wall) / len(wall) if wall else math.nan:.2f} s.", "",
             "Survival = neither fell nor collided; rates with 95 % Wilson intervals.", "",
             "| planner | survived | fell | collided | errors | timed out | died |", "|---|---|---|---|---|---|---|"]
    for planner in sorted({r["planner"] for r in rows}):
        mine = [r for r in rows if r["planner"] == planner]
        done = [r for r in mine if r["status"] == "done"]
        k = sum(int(bool(r["survived"])) for r in done)
        lines.append(f"| {planner} | {_fmt_rate(k, len(done))} | {sum(int(bool(r['fell'])) for r in done)} | "
                     f"{sum(int(bool(r['collided'])) for r in done)} | {sum(r['status'] == 'error' for r in mine)} | "
                     f"{sum(r['status'] == 'timeout' for r in mine)} | "
                     f"{sum(r['status'] == 'died' for r in mine)} |")
    errors = sorted({r["error"] for r in rows if r["status"] in ("error", "timeout") and r.get("error")})
    if errors:
        lines += ["", "Errors (distinct messages):", *(f"- `{e}`" for e in errors[:10])]
    return lines + [""]


def _rmse_lines(rows: list[dict[str, Any]], group: str | None) -> list[str]:
    import numpy as np

    acc: dict[tuple[str, Any], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        if r["status"] == "done":
            acc[(r["planner"], r.get(group) if group else "")].append(r)
    lines = ["### Error RMSE over the cases (mean ± std) and fall rate", "",
             f"| planner | {(group or '').removeprefix('p_').replace('_', ' ')} | cases | RMSE [m] | fall rate |",
             "|---|---|---|---|---|"]
    for (planner, g), rs in sorted(acc.items(), key=lambda kv: (kv[0][0], str(kv[0][1]))):
        e = np.array([r["rmse_m"] for r in rs if r.get("rmse_m") is not None], dtype=float)
        m = f"{e.mean():.4f} ± {e.std(ddof=1) if len(e) > 1 else 0.0:.4f}" if len(e) else "-"
        lines.append(f"| {planner} | {g if g is not None else ''} | {len(rs)} | {m} | {_fmt_rate(sum(int(bool(r['fell'])) for r in rs), len(rs))} |")
    return lines + [""]


def _outcome_lines(rows: list[dict[str, Any]]) -> list[str]:
    """How the path-following cases ended, per planner (see the module doc)."""
    from ..studies.outcome import OUTCOMES, SUCCESS_OUTCOMES

    done = [r for r in rows if r["status"] == "done" and r.get("path_length_m") is not None]
    if not done:
        return []
    seen = [o for o in OUTCOMES if any(r.get("outcome") == o for r in done)]
    other = sorted({str(r.get("outcome")) for r in done} - set(OUTCOMES))
    cols = seen + other
    lines = ["### How the runs ended along their path", "",
             "Success = completed (the end reached, or a set-length study run through) or trailing a slower "
             "obstacle along the path (the preset's choice); an outcome not listed here is not a success.", "",
             "| planner | success | " + " | ".join(c.replace("_", " ") for c in cols) + " |",
             "|---|---|" + "---|" * len(cols)]
    for planner in sorted({r["planner"] for r in done}):
        mine = [r for r in done if r["planner"] == planner]
        k = sum(r.get("outcome") in SUCCESS_OUTCOMES for r in mine)
        lines.append(f"| {planner} | {_fmt_rate(k, len(mine))} | "
                     + " | ".join(str(sum(r.get("outcome") == c for r in mine)) for c in cols) + " |")
    stalled = [r for r in done if r.get("outcome") == "stalled"]
    if stalled:
        lines += ["", "Stalled cases:", *(f"- `{r['case_id']}` ({r['planner']}): {r.get('progress_m') or 0.0:.2f} of "
                                          f"{r['path_length_m']:.2f} m; {r.get('stall_binding') or ''}" for r in stalled[:20])]
    return lines + [""]


def write_report(out: str | Path) -> Path:
    """Write ``OUT/report.md`` and its figures from ``OUT/results.sqlite``; returns the report's path."""
    out = Path(out)
    meta, rows = load_rows(out)
    lines = _summary_lines(meta, rows)
    lines += _outcome_lines(rows)
    if any(r.get("impulse_Ns") is not None for r in rows):
        table = survival_by(rows, "impulse_Ns")
        bounds = point_foot_bounds(meta, rows)
        bound = min(bounds.values()) if len(set(bounds.values())) == 1 else None
        _plot_rates(table, "push impulse [N s]", "survival rate", out / "survival_vs_impulse.png", bound=bound)
        lines += _rate_table("Survival against push impulse", "impulse", table, "N s")
        lines += ["![survival vs impulse](survival_vs_impulse.png)", ""]
    dirs = {round(r["p_direction"], 9) for r in rows if r.get("p_direction") is not None}
    if len(dirs) >= 3 and any(r.get("impulse_Ns") is not None for r in rows):
        best = recoverable_impulse(rows)
        _plot_polar(best, out / "recoverable_impulse_polar.png", bound=bound)
        lines += _recoverable_lines(best, bounds)
    elif any(r.get("impulse_Ns") is not None for r in rows):
        lines += _bound_lines(bounds)
    if any(r.get("p_obstacle_speed") is not None for r in rows):
        if any(r.get("overtook") is not None for r in rows):
            for r in rows:
                r["overtake_ok"] = int(bool(r.get("overtook")) and bool(r.get("survived")))
            what, ok, png = "Overtaking success", "overtake_ok", "overtaking_vs_speed.png"
        else:  # a study with no overtaking (stone-field: a pedestrian crossing): its success
            from ..studies.outcome import SUCCESS_OUTCOMES

            for r in rows:
                r["speed_ok"] = int(r.get("outcome") in SUCCESS_OUTCOMES)
            what, ok, png = "Success", "speed_ok", "success_vs_speed.png"
        table = survival_by(rows, "p_obstacle_speed", ok=ok)
        _plot_rates(table, "obstacle speed [m/s]", what.lower(), out / png)
        lines += _rate_table(f"{what} against obstacle speed", "speed", table, "m/s")
        lines += [f"![{what.lower()} vs speed]({png})", ""]
    if any(r.get("p_profile") is not None or r.get("p_seed") is not None for r in rows):
        group = next((g for g in ("p_profile", "p_push_scale") if any(r.get(g) is not None for r in rows)), None)
        lines += _rmse_lines(rows, group)
    path = out / "report.md"
    path.write_text("\n".join(lines))
    return path
