"""Figures of paper A (Figs. 5 and 6) from a :class:`~lipmpcc.plots.logs.PathFollowingLog` (a LIP or a
full-body run), plus frames of a full-body run (:func:`figure_frames`)."""

from __future__ import annotations

from typing import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Ellipse

from ..exceptions import InvalidInputError
from ..obstacles import Obstacle
from ..paths import Path
from .logs import PathFollowingLog

__all__ = [
    "plot_path",
    "plot_errors",
    "plot_footsteps",
    "plot_vavg",
    "plot_contouring_fullbody",
    "figure_circle",
    "figure_circle_fullbody",
    "figure_overtake",
    "figure_frames",
]

RIGHT = "tab:blue"
LEFT = "tab:red"


def _check_log(log: object) -> PathFollowingLog:
    if not isinstance(log, PathFollowingLog):
        raise InvalidInputError(
            "log", type(log).__name__,
            "a PathFollowingLog (a LIP run's LipLog gives one: lipmpcc.studies.path_following.lip_path_log(log))",
        )
    return log


def plot_path(ax: Axes, log: PathFollowingLog, path: Path, obstacles: Sequence[Obstacle] = (), snapshots: int = 4) -> None:
    """Reference path (red), COM path (blue), footholds, obstacles at a few instants."""
    log = _check_log(log)
    ref = path.sample(400)
    ax.plot(ref[:, 0], ref[:, 1], color="tab:red", lw=1.5, label="reference path")
    ax.plot(log.com[:, 0], log.com[:, 2], color="tab:blue", lw=1.0, label="COM")
    f = log.footholds
    left = log.sides == 1
    ax.plot(f[left, 0], f[left, 1], "o", ms=3, color=LEFT, alpha=0.6, label="left foot")
    ax.plot(f[~left, 0], f[~left, 1], "o", ms=3, color=RIGHT, alpha=0.6, label="right foot")
    for pu in log.pushes:
        i = int(np.searchsorted(log.tc, pu.t_start))
        if i < len(log.tc):
            p = log.com[i]
            fx, fy = pu.force[0], pu.force[1]
            ax.annotate(
                "", xy=(p[0] + fx / 250, p[2] + fy / 250), xytext=(p[0], p[2]),
                arrowprops=dict(arrowstyle="->", color="k", lw=1.2),
            )
    if len(obstacles):
        idx = np.linspace(0, len(log.tc) - 1, snapshots).astype(int)
        for n, i in enumerate(idx):
            a = 0.15 + 0.6 * n / max(1, snapshots - 1)
            for ob in obstacles:
                c = ob.center(log.tc[i])
                w, h = 2 * ob.axes[0], 2 * ob.axes[1]
                ang = np.degrees(float(ob.heading(log.tc[i])))
                patch = Circle(c, ob.axes[0]) if ob.is_circle else Ellipse(c, w, h, angle=ang)
                patch.set(color="gray", alpha=a)
                ax.add_patch(patch)
            ax.plot(log.com[i, 0], log.com[i, 2], "s", color="tab:blue", alpha=a, ms=6)
            ax.annotate(f"{log.tc[i]:.0f} s", (log.com[i, 0], log.com[i, 2]), fontsize=7, xytext=(2, 6), textcoords="offset points")
    if len(obstacles):  # zoom on the part of the path the robot walked
        lo = min(log.com[:, 0].min(), log.obstacles[:, :, 0].min()) - 1.0
        hi = max(log.com[:, 0].max(), log.obstacles[:, :, 0].max()) + 1.0
        ax.set_xlim(lo, hi)
        ax.set_ylim(min(-1.2, log.com[:, 2].min() - 0.4), max(1.2, log.com[:, 2].max() + 0.4))
        ax.set_aspect("auto")  # a long straight run: stretch y so the detour is visible
        ax.set_title("y stretched (axes not to scale)", fontsize=8, loc="right")
    else:
        ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="best")


def plot_errors(ax: Axes, log: PathFollowingLog, kind: str = "contouring", pushes: bool = True) -> None:
    """Errors at the step instants: ``contouring``, ``contouring+lag`` or ``cartesian``."""
    log = _check_log(log)
    t = log.t
    if kind == "cartesian":
        ax.plot(t, log.e_cartesian, color="tab:blue", label="‖e‖ Cartesian")
    else:
        ax.plot(t, log.e_contouring, color="tab:blue", label="ē_c contouring")
        if kind == "contouring+lag":
            ax.plot(t, log.e_lag, color="tab:red", label="ē_l lag")
    if pushes:
        for k, pu in enumerate(log.pushes):
            ax.axvspan(pu.t_start, pu.t_start + pu.duration, color="orange", alpha=0.4, lw=0, label="pushes" if k == 0 else None)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("error [m]")
    ax.legend(fontsize=7)


def plot_footsteps(ax: Axes, log: PathFollowingLog) -> None:
    """Step sizes uˣ, uʸ of the right (blue) and left (red) feet, per step (paper A Fig. 6c/g).

    ``log.step_offsets``: the planned u_0 of each solve on the LIP; on the full body the realised
    offset of the landed foot from the measured COM at touch-down."""
    u = np.asarray(_check_log(log).step_offsets)
    t = log.t[: len(u)]
    left = log.sides == 1
    ax.plot(t[left], u[left, 0], "o-", ms=3, color=LEFT, label="uˣ left")
    ax.plot(t[~left], u[~left, 0], "o-", ms=3, color=RIGHT, label="uˣ right")
    ax.plot(t[left], u[left, 1], "^", ms=3, color=LEFT, alpha=0.5, label="uʸ left")
    ax.plot(t[~left], u[~left, 1], "^", ms=3, color=RIGHT, alpha=0.5, label="uʸ right")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("foot offset [m]")
    ax.legend(fontsize=7, ncol=2)


def plot_vavg(ax: Axes, log: PathFollowingLog) -> None:
    """v_avg = (1/N) Σ v per MPC solve (blue) and v_max (red) (paper A Fig. 6d/h)."""
    log = _check_log(log)
    ax.plot(log.v_avg_t, log.v_avg, color="tab:blue", label="v_avg")
    ax.axhline(log.v_max, color="tab:red", label="v_max")
    ax.set_ylim(0, 1.15 * log.v_max)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("path update [m/step]")
    ax.legend(fontsize=7)


def figure_circle(log: PathFollowingLog, path: Path, title: str = "", settle_time: float | None = None) -> Figure:
    """Paper A Fig. 5 (a, b) or (c, d): path (COM, footholds, pushes) and contouring error.

    The error panel shows the continuous error of the COM and the error at the touch-downs when the log
    has the continuous one (a full-body run, with a line at ``settle_time`` [s] after the start), else the
    error at the step instants."""
    log = _check_log(log)
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.2))
    plot_path(axs[0], log, path)
    if log.e_contouring_c is not None:
        plot_contouring_fullbody(axs[1], log, settle_time)
    else:
        plot_errors(axs[1], log, "contouring")
    fig.suptitle(title or "MPCC on a circle of radius 2 m")
    fig.tight_layout()
    return fig


def figure_overtake(log: PathFollowingLog, path: Path, obstacles: Sequence[Obstacle], cartesian: bool, title: str = "") -> Figure:
    """Paper A Fig. 6 (a–d) for the Cartesian MPC or (e–h) for the MPCC."""
    log = _check_log(log)
    fig = plt.figure(figsize=(11, 6.5))
    gs = fig.add_gridspec(2, 3, height_ratios=[1.0, 1.1])
    ax0 = fig.add_subplot(gs[0, :])
    plot_path(ax0, log, path, obstacles)
    plot_errors(fig.add_subplot(gs[1, 0]), log, "cartesian" if cartesian else "contouring+lag", pushes=False)
    plot_footsteps(fig.add_subplot(gs[1, 1]), log)
    plot_vavg(fig.add_subplot(gs[1, 2]), log)
    fig.suptitle(title or ("Cartesian MPC trailing the obstacle" if cartesian else "MPCC overtaking the obstacle"))
    fig.tight_layout()
    return fig


def plot_contouring_fullbody(ax: Axes, log: PathFollowingLog, settle_time: float | None = None) -> None:
    """Contouring error of a full-body run: continuous COM error (light, every WBC tick) and at
    touch-downs (dots); a dotted line ``settle_time`` [s] after the start."""
    log = _check_log(log)
    ax.plot(log.tc, log.e_contouring_c, color="tab:blue", lw=0.7, alpha=0.45, label="ē_c of the COM (400 Hz)")
    ax.plot(log.t, log.e_contouring, "o-", ms=2.5, lw=1.0, color="tab:blue", label="ē_c at touch-downs")
    for k, pu in enumerate(log.pushes):
        ax.axvspan(pu.t_start, pu.t_start + pu.duration, color="orange", alpha=0.4, lw=0, label="pushes" if k == 0 else None)
    if settle_time is not None and len(log.tc):
        ax.axvline(log.tc[0] + settle_time, color="gray", ls=":", lw=1.0, label="settle time")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("contouring error [m]")
    ax.legend(fontsize=7)


def figure_circle_fullbody(log: PathFollowingLog, path: Path, title: str = "", settle_time: float | None = 3.0) -> Figure:
    """:func:`figure_circle` of a full-body run (the settle line at 3 s by default)."""
    return figure_circle(log, path, title or "MPCC on the full-body robot: circle of radius 2 m", settle_time)


def figure_frames(images: Sequence[np.ndarray], times: Sequence[float], title: str = "", ncols: int = 4) -> Figure:
    """A row (or grid) of rendered frames with their times [s]."""
    n = len(images)
    ncols = max(1, min(ncols, n))
    nrows = max(1, -(-n // ncols))
    fig, axs = plt.subplots(nrows, ncols, figsize=(3.2 * ncols, 2.5 * nrows), squeeze=False)
    for ax in axs.ravel():
        ax.axis("off")
    for ax, img, t in zip(axs.ravel(), images, times):
        ax.imshow(img)
        ax.set_title(f"t = {t:.1f} s", fontsize=9)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return fig
