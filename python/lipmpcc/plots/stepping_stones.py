"""Figures of paper B's studies (footprints, step durations, initial DCM, pushes).

The figures read a :class:`~lipmpcc.plots.logs.SteppingStonesLog`: an ALIP run's log, or a full-body
run recorded in the same log by the stepping-stone study (measured soles, times from the first lift-off).
:func:`plot_frames` shows snapshots of a recorded full-body run, :func:`plot_timing_errors` and
:func:`plot_cop_offsets` what the full-body footstep source planned.
"""

from __future__ import annotations

from types import ModuleType
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from .logs import SteppingStonesLog

if TYPE_CHECKING:  # pragma: no cover
    import mujoco
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..planners.sources.alip import AlipFootstepSource

__all__ = [
    "plot_footprints",
    "plot_durations_and_dcm",
    "plot_push_response",
    "plot_table_bars",
    "plot_frames",
    "plot_timing_errors",
    "plot_cop_offsets",
]

FOOT_SIZE = (0.18, 0.08)  # [m] drawn foot outline (illustration only)


def _plt() -> ModuleType:
    import matplotlib.pyplot as plt

    return plt


def _check_log(log: object) -> SteppingStonesLog:
    from ..exceptions import InvalidInputError

    if not isinstance(log, SteppingStonesLog):
        raise InvalidInputError("log", type(log).__name__, "a stepping-stone log (an SteppingStonesLog of run_alip_loop or of a full-body run)")
    return log


def plot_footprints(log: SteppingStonesLog, ax: Axes | None = None, title: str | None = None, show_approach: bool = True) -> Figure:
    """Stones, footholds, COM and DCM paths in the world frame (paper B Figs. 4 and 6).

    Green rectangles: the step-position bounds (the stones); black dots and frames: the
    footholds; red: the footstep where the run failed. Returns the figure.
    """
    from matplotlib.patches import Rectangle

    plt = _plt()
    log = _check_log(log)
    seq = log.sequence
    if ax is None:
        x_span = float(np.ptp(seq.centers[:, 0])) + 1.0 if len(seq) else 4.0
        fig, ax = plt.subplots(figsize=(min(max(6.0, 1.2 * x_span), 16.0), 3.6))
    else:
        fig = ax.figure
    for i in range(len(seq)):
        if not seq.is_stone[i]:
            continue
        st = seq[i]
        lo = st.lower
        ax.add_patch(Rectangle((lo[0] - 0.03, lo[1] - 0.03), st.size[0] + 0.06, st.size[1] + 0.06, color="0.85", zorder=0))
        ax.add_patch(Rectangle(tuple(lo), st.size[0], st.size[1], fill=False, edgecolor="tab:green", lw=1.2, zorder=1))
    fh = log.footholds
    stone_mask = np.array([bool(seq.is_stone[i]) for i in log.step_index], dtype=bool)
    bad = ~(log.in_stone & log.kin_ok) if fh.size else np.zeros(0, bool)
    for j, p in enumerate(fh):
        if not show_approach and not stone_mask[j]:
            continue
        color = "tab:red" if bad[j] else "k"
        ax.add_patch(
            Rectangle((p[0] - FOOT_SIZE[0] / 2, p[1] - FOOT_SIZE[1] / 2), *FOOT_SIZE, fill=False, edgecolor=color, lw=0.8, zorder=3)
        )
    if fh.size:
        sel = stone_mask if not show_approach else np.ones(len(fh), bool)
        ax.plot(fh[sel & ~bad, 0], fh[sel & ~bad, 1], "k.", ms=5, zorder=4, label="footholds")
        if np.any(bad):
            ax.plot(fh[bad, 0], fh[bad, 1], "x", color="tab:red", ms=8, zorder=5, label="failed footstep")
    if show_approach:
        ax.plot(*log.start_stance, "ko", mfc="none", ms=5)
        if log.start_swing is not None:
            ax.plot(*log.start_swing, "ko", mfc="none", ms=5)
    ax.plot(log.com[:, 0], log.com[:, 1], color="tab:blue", lw=1.0, label="COM")
    ax.plot(log.dcm[:, 0], log.dcm[:, 1], color="tab:orange", lw=0.8, alpha=0.8, label="DCM")
    if log.fell and log.fall_time is not None:
        i = int(np.searchsorted(log.t, log.fall_time))
        i = min(i, len(log.t) - 1)
        ax.plot(log.com[i, 0], log.com[i, 1], "v", color="tab:red", ms=9, label="fall detected")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(loc="upper left", fontsize=7, ncol=5)
    ax.autoscale_view()
    status = "falls at stone %s" % _stone_number(log) if log.fell else "completes the course"
    ax.set_title((title + ": " if title else "") + status, fontsize=9)
    fig.tight_layout()
    return fig


def _stone_number(log: SteppingStonesLog) -> str:
    seq = log.sequence
    first = int(np.argmax(seq.is_stone)) if np.any(seq.is_stone) else 0
    if log.fall_index is None:
        return "?"
    return str(int(log.fall_index - first + 1))


def _clip_to_bounds(ax: Axes, lo: float, hi: float) -> None:
    """Keep the viable interval in view even when a fall sends the DCM far away."""
    span = hi - lo
    y0, y1 = ax.get_ylim()
    ax.set_ylim(max(y0, lo - 0.6 * span), min(y1, hi + 0.6 * span))


def _td_lines(ax: Axes, log: SteppingStonesLog) -> None:
    for t in log.td_times:
        ax.axvline(t, color="0.85", lw=0.6, zorder=0)


def plot_durations_and_dcm(log: SteppingStonesLog, title: str | None = None, axes: Sequence[Axes] | None = None) -> Figure:
    """Step durations and initial DCM of each step vs time (paper B Fig. 5).

    Grey lines: touch-downs. Dashed: the viable intervals of the initial DCM.
    """
    plt = _plt()
    log = _check_log(log)
    if axes is None:
        fig, axes = plt.subplots(3, 1, figsize=(8, 6.0), sharex=True)
    else:
        fig = axes[0].figure
    ax_T, ax_x, ax_y = axes
    starts = np.concatenate([[0.0], log.td_times])
    z = log.z_initial
    for ax in axes:
        _td_lines(ax, log)
    if log.durations.size:
        ax_T.step(log.td_times, log.durations, where="pre", color="k", lw=1.2, label="actual")
    ax_T.plot(log.plan_t, log.plan_T, ".", ms=2, color="tab:blue", label="planned (each tick)")
    ax_T.set_ylabel("step duration [s]")
    ax_T.legend(fontsize=7, loc="upper right")
    b = log.dcm_bounds
    n = min(len(starts), len(z))
    sides = [-int(s) for s in _stance_sides(log)][:n]
    ax_x.plot(starts[:n], z[:n, 0], "o-", ms=3, color="tab:orange")
    ax_x.axhline(b.x[0], ls="--", color="0.5", lw=0.8)
    ax_x.axhline(b.x[1], ls="--", color="0.5", lw=0.8)
    ax_x.set_ylabel("initial DCM x [m]")
    _clip_to_bounds(ax_x, *b.x)
    ax_y.plot(starts[:n], z[:n, 1], "o-", ms=3, color="tab:orange")
    lo = [b.y(s)[0] for s in sides]
    hi = [b.y(s)[1] for s in sides]
    ax_y.step(starts[:n], lo, where="post", ls="--", color="0.5", lw=0.8)
    ax_y.step(starts[:n], hi, where="post", ls="--", color="0.5", lw=0.8)
    ax_y.set_ylabel("initial DCM y [m]")
    _clip_to_bounds(ax_y, b.y_right[0], b.y_left[1])
    ax_y.set_xlabel("time [s]")
    if title:
        ax_T.set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


def _stance_sides(log: SteppingStonesLog) -> list[int]:
    """Stance side at the start of each step (the first from the sequence)."""
    first_stance = -int(log.sequence.sides[0])
    return [first_stance] + [int(s) for s in log.step_sides]


def plot_push_response(log: SteppingStonesLog, title: str | None = None) -> Figure:
    """COM velocity, step durations and initial DCM around the pushes (paper B Fig. 7)."""
    plt = _plt()
    log = _check_log(log)
    fig, axes = plt.subplots(2, 2, figsize=(10, 5.5), sharex=True)
    (a_v, a_T), (a_x, a_y) = axes
    colors = ["tab:red", "gold", "tab:green", "tab:purple"]
    for ax in axes.ravel():
        _td_lines(ax, log)
        for i, (t0, t1, _f) in enumerate(log.push_windows):
            ax.axvspan(t0, t1, color=colors[i % 4], alpha=0.35, lw=0)
    a_v.plot(log.t, log.com_vel[:, 0], label="v_x", color="tab:blue")
    a_v.plot(log.t, log.com_vel[:, 1], label="v_y", color="tab:orange")
    a_v.set_ylabel("COM velocity [m/s]")
    a_v.set_ylim(max(a_v.get_ylim()[0], -1.5), min(a_v.get_ylim()[1], 2.0))
    a_v.legend(fontsize=7)
    if log.durations.size:
        a_T.step(log.td_times, log.durations, where="pre", color="k")
    a_T.set_ylabel("step duration [s]")
    starts = np.concatenate([[0.0], log.td_times])
    n = min(len(starts), len(log.z_initial))
    b = log.dcm_bounds
    a_x.plot(starts[:n], log.z_initial[:n, 0], "o-", ms=3, color="tab:orange")
    a_x.axhline(b.x[0], ls="--", color="0.5", lw=0.8)
    a_x.axhline(b.x[1], ls="--", color="0.5", lw=0.8)
    a_x.set_ylabel("initial DCM x [m]")
    _clip_to_bounds(a_x, *b.x)
    a_x.set_xlabel("time [s]")
    sides = [-s for s in _stance_sides(log)][:n]
    a_y.plot(starts[:n], log.z_initial[:n, 1], "o-", ms=3, color="tab:orange")
    a_y.step(starts[:n], [b.y(s)[0] for s in sides], where="post", ls="--", color="0.5", lw=0.8)
    a_y.step(starts[:n], [b.y(s)[1] for s in sides], where="post", ls="--", color="0.5", lw=0.8)
    a_y.set_ylabel("initial DCM y [m]")
    _clip_to_bounds(a_y, b.y_right[0], b.y_left[1])
    a_y.set_xlabel("time [s]")
    status = f"falls at stone {_stone_number(log)}" if log.fell else "survives"
    fig.suptitle((title + ": " if title else "") + status, fontsize=9)
    fig.tight_layout()
    return fig


def plot_table_bars(rows: Sequence[dict[str, Any]], title: str = "") -> Figure:
    """Bar chart of the step RMSE per case for each planner; a cross marks a fall."""
    plt = _plt()
    cases = list(dict.fromkeys(r["case"] for r in rows))
    planners = list(dict.fromkeys(r["planner"] for r in rows))
    fig, ax = plt.subplots(figsize=(max(6.0, 0.45 * len(cases) + 2), 3.2))
    width = 0.8 / max(len(planners), 1)
    for j, p in enumerate(planners):
        for i, c in enumerate(cases):
            r = next((r for r in rows if r["case"] == c and r["planner"] == p), None)
            if r is None:
                continue
            x = i + (j - (len(planners) - 1) / 2) * width
            if r["fell"]:
                ax.plot(x, 0.005, "x", color="tab:red", ms=8)
            else:
                ax.bar(x, r["step_rmse_m"], width=width, color=f"C{j}", label=p if i == 0 else None)
    ax.plot([], [], "x", color="tab:red", label="falls")
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels(cases, rotation=60, ha="right", fontsize=7)
    ax.set_ylabel("step RMSE [m]")
    ax.legend(fontsize=7)
    if title:
        ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


# ----------------------------------------------------------------------------- full-body helpers
def plot_frames(
    model: mujoco.MjModel,
    frames: np.ndarray,
    times: np.ndarray,
    n: int = 4,
    title: str | None = None,
    width: int = 480,
    height: int = 360,
    track_body: str | None = None,
) -> Figure:
    """``n`` evenly spaced snapshots of a recorded full-body run (MuJoCo configurations ``frames`` at
    ``times`` [s], e.g. ``LoopResult.frames``/``frame_times``), rendered offscreen, side by side."""
    import mujoco

    from ..exceptions import InvalidInputError
    from ..sim.render import VideoRecorder, VideoSettings

    q = np.asarray(frames, dtype=float)
    if q.ndim != 2 or q.shape[0] == 0 or q.shape[1] != model.nq:
        raise InvalidInputError("frames", getattr(q, "shape", None), f"a (k >= 1, nq = {model.nq}) array of configurations")
    if not isinstance(n, int) or n < 1:
        raise InvalidInputError("n", n, "a positive number of snapshots")
    idx = np.unique(np.linspace(0, len(q) - 1, n).round().astype(int))
    data = mujoco.MjData(model)
    images = []
    settings = VideoSettings(width=width, height=height, track_body=track_body, distance=3.5, azimuth=135.0)
    with VideoRecorder(model, settings) as rec:
        for i in idx:
            data.qpos[:] = q[i]
            mujoco.mj_forward(model, data)
            images.append(rec.render(data))
    plt = _plt()
    fig, axes = plt.subplots(1, len(images), figsize=(3.2 * len(images), 2.6))
    axes = np.atleast_1d(axes)
    for ax, img, i in zip(axes, images, idx):
        ax.imshow(img)
        ax.set_axis_off()
        ax.set_title(f"t = {float(times[i]):.1f} s", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    return fig


def plot_timing_errors(log: SteppingStonesLog, source: AlipFootstepSource, title: str | None = None) -> Figure:
    """Full-body step timing: the last planned duration of each step against the measured one
    (touch-down detected from contact), and the contact phase τ_c of each touch-down."""
    plt = _plt()
    log = _check_log(log)
    last: dict[int, float] = {}
    for r in source.records:
        last[r.step_index] = r.planned_duration
    n = len(log.durations)
    planned = np.array([last.get(k, np.nan) for k in range(n)])
    fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.0))
    a.plot(np.arange(n), 1e3 * (log.durations - planned), "o-", ms=3)
    a.axhline(0.0, color="0.5", lw=0.8)
    a.set_xlabel("footstep")
    a.set_ylabel("measured − planned duration [ms]")
    tc = np.asarray(getattr(source, "contact_phases", []), dtype=float)
    b.plot(np.arange(len(tc)), tc, "o-", ms=3, color="tab:green")
    b.set_xlabel("footstep")
    b.set_ylabel("phase at contact τ_c [-]")
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    return fig


def plot_cop_offsets(
    source: AlipFootstepSource,
    push_windows: Sequence[tuple[float, float, tuple[float, float]]] = (),
    t0: float = 0.0,
    title: str | None = None,
) -> Figure:
    """The centre-of-pressure offset d [m] the ALIP-MPC planned at each call (x and y, from the
    stance contact point), with the pushes shaded and the planner's box dashed (a planner with a foot,
    :attr:`~lipmpcc.planners.alip_mpc.AlipMpcParams.cop_range`).

    Args:
        source: an :class:`~lipmpcc.planners.sources.alip.AlipFootstepSource` after a run.
        push_windows: (t_start, t_end, force) of the pushes [s] in simulation time (a full-body run's
            :attr:`~lipmpcc.studies.stepping_stones.FullBodyStonesRun.push_windows`).
        t0: subtracted from every time on the axis [s] (the records and the windows carry simulation
            time).
        title: figure title.
    """
    from ..exceptions import InvalidInputError

    plt = _plt()
    recs = [r for r in getattr(source, "records", []) if r.result is not None]
    if not recs:
        raise InvalidInputError("source", source, "a footstep source with at least one successful plan")
    t = np.array([r.t for r in recs]) - float(t0)
    d = np.array([np.asarray(getattr(r.result, "cop_offset", np.zeros(2)), dtype=float) for r in recs])
    box = getattr(getattr(getattr(source, "planner", None), "params", None), "cop_range", None)
    fig, axes = plt.subplots(2, 1, figsize=(10, 3.6), sharex=True)
    colors = ["tab:red", "gold", "tab:green", "tab:purple"]
    for i, (ax, name) in enumerate(zip(axes, ("x (along)", "y (across)"))):
        for j, (a, b, _f) in enumerate(push_windows):
            ax.axvspan(a - t0, b - t0, color=colors[j % 4], alpha=0.35, lw=0)
        ax.step(t, 1e2 * d[:, i], where="post", color="tab:blue", lw=1.0)
        if box is not None and box[i] > 0:
            for sgn in (-1, 1):
                ax.axhline(1e2 * sgn * box[i], ls="--", color="0.5", lw=0.8)
        ax.axhline(0.0, color="0.7", lw=0.6)
        ax.set_ylabel(f"CoP offset {name} [cm]", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    if title:
        fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    return fig
