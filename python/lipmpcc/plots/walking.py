"""Figures of full-body runs (``lipmpcc run walk|stand``): paths, tracking, timing.

They read a :class:`~lipmpcc.plots.logs.FullBodyRunResult` (the full-body loop's result has its fields)."""

from __future__ import annotations

from typing import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from ..push import Push
from .logs import FullBodyRunResult

__all__ = ["top_view", "tracking", "timing", "stand_view"]


def top_view(result: FullBodyRunResult, title: str = "Top view") -> Figure:
    """COM and DCM paths with the planned and actual footholds (world frame, [m])."""
    log = result.log
    fig, ax = plt.subplots(figsize=(7.0, 5.5))
    ax.plot(log.com[:, 0], log.com[:, 1], color="C0", lw=1.5, label="COM")
    ax.plot(log.dcm[:, 0], log.dcm[:, 1], color="C0", lw=0.7, alpha=0.5, ls="--", label="DCM")
    for side, color in (("left", "C2"), ("right", "C3")):
        tds = [td for td in result.touchdowns if td.side == side]
        if tds:
            ax.scatter([td.pos[0] for td in tds], [td.pos[1] for td in tds], s=22, color=color, label=f"{side} foot")
            ax.scatter(
                [td.planned[0] for td in tds],
                [td.planned[1] for td in tds],
                s=30,
                facecolors="none",
                edgecolors=color,
                label=f"{side} planned",
            )
    ax.scatter(
        [log.left_foot[0, 0], log.right_foot[0, 0]],
        [log.left_foot[0, 1], log.right_foot[0, 1]],
        marker="s",
        s=30,
        color=["C2", "C3"],
        label="initial feet",
    )
    ax.plot(log.com[0, 0], log.com[0, 1], "k^", label="start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    return fig


def tracking(result: FullBodyRunResult, pushes: Sequence[Push] = ()) -> Figure:
    """COM tracking, speed, base height / torso tilt and swing-foot error over time."""
    log = result.log
    t = log.t
    fig, axs = plt.subplots(4, 1, figsize=(8.0, 9.0), sharex=True)
    ax = axs[0]
    for i, name in enumerate("xy"):
        ax.plot(t, log.com[:, i], color=f"C{i}", label=f"COM {name}")
        ax.plot(t, log.com_ref[:, i], color=f"C{i}", ls="--", lw=0.8, label=f"ref {name}")
    ax.set_ylabel("COM [m]")
    ax.legend(fontsize=7, ncol=4)
    ax = axs[1]
    speed = np.linalg.norm(log.com_vel[:, :2], axis=1)
    ax.plot(t, speed, color="C0", label="|COM velocity|")
    if len(t) > 1 and result.touchdowns:
        tds = np.array([td.t for td in result.touchdowns])
        pos = np.array([td.pos[:2] for td in result.touchdowns])
        if len(tds) > 2:
            step_speed = np.linalg.norm(np.diff(pos[::2], axis=0), axis=1) / np.diff(tds[::2])
            ax.step(tds[::2][1:], step_speed, where="pre", color="C1", label="stride speed")
    ax.set_ylabel("speed [m/s]")
    ax.legend(fontsize=7)
    ax = axs[2]
    ax.plot(t, log.base_height, color="C0", label="base height [m]")
    ax.plot(t, log.com[:, 2], color="C1", label="COM height [m]")
    ax2 = ax.twinx()
    ax2.plot(t, np.degrees(log.torso_tilt), color="C3", lw=0.8, label="torso tilt [deg]")
    ax2.set_ylabel("tilt [deg]")
    ax.set_ylabel("height [m]")
    ax.legend(fontsize=7, loc="lower left")
    ax2.legend(fontsize=7, loc="lower right")
    ax = axs[3]
    ax.plot(t, log.swing_err * 1e3, color="C0", lw=0.8, label="swing-foot error [mm]")
    ax.set_ylabel("error [mm]")
    ax.set_xlabel("t [s]")
    ax.legend(fontsize=7)
    for a in axs:
        a.grid(alpha=0.3)
        for k, p in enumerate(pushes):
            a.axvspan(p.t_start, p.t_start + p.duration, color="k", alpha=0.12, label="pushes" if k == 0 else None)
    fell_at = _fall_time(result)
    if fell_at is not None:  # the fall, with its reason
        reason = getattr(result, "fall_reason", None) or "fell"
        for a in axs:
            a.axvline(fell_at, color="C3", lw=1.2, ls=":")
        axs[0].set_title(f"fell at t = {fell_at:.2f} s: {reason}", fontsize=8, color="C3")
    if pushes:  # the push bands in the first panel's legend
        axs[0].legend(fontsize=7, ncol=5)
    fig.tight_layout()
    return fig


def _fall_time(result: FullBodyRunResult) -> float | None:
    """The time of the run's fall [s], or None (no fall, or a result without one)."""
    t = getattr(result, "fall_time", None)
    if not getattr(result, "fell", False) or t is None or not np.isfinite(t):
        return None
    return float(t)


def timing(result: FullBodyRunResult) -> Figure:
    """Histogram of the WBC tick time, with the real-time budget of one tick."""
    fig, ax = plt.subplots(figsize=(6.0, 3.5))
    ms = result.log.wbc_time * 1e3
    ax.hist(ms, bins=60, color="C0", alpha=0.8)
    budget = 1e3 / result.wbc_rate_hz
    ax.axvline(budget, color="C3", ls="--", label=f"tick period {budget:.2f} ms")
    ax.set_xlabel("WBC time per tick [ms]")
    ax.set_ylabel("ticks")
    ax.set_title(
        f"WBC median {result.wbc_ms['median']:.3f} ms, p90 {result.wbc_ms['p90']:.3f} ms; "
        f"RTF {result.real_time_factor:.1f}×"
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def stand_view(result: FullBodyRunResult, pushes: Sequence[Push] = ()) -> Figure:
    """Standing under pushes: horizontal COM excursion and the feet's support polygon."""
    log = result.log
    fig, axs = plt.subplots(1, 2, figsize=(10.0, 4.0))
    ax = axs[0]
    c0 = log.com[0, :2]
    ax.plot(log.t, (log.com[:, 0] - c0[0]) * 1e3, label="COM x − x0")
    ax.plot(log.t, (log.com[:, 1] - c0[1]) * 1e3, label="COM y − y0")
    for k, p in enumerate(pushes):
        ax.axvspan(p.t_start, p.t_start + p.duration, color="k", alpha=0.12, label="push (force [N] beside it)" if k == 0 else None)
        ax.annotate(
            f"{np.asarray(p.force)[:2].round(0).tolist()} N",
            (p.t_start, 0),
            fontsize=7,
            rotation=90,
            va="bottom",
        )
    ax.set_xlabel("t [s]")
    ax.set_ylabel("[mm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax = axs[1]
    ax.plot(log.com[:, 0], log.com[:, 1], label="COM")
    ax.plot(log.dcm[:, 0], log.dcm[:, 1], ls="--", lw=0.8, label="DCM")
    ax.scatter(log.left_foot[0, 0], log.left_foot[0, 1], color="C2", label="left sole")
    ax.scatter(log.right_foot[0, 0], log.right_foot[0, 1], color="C3", label="right sole")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig
