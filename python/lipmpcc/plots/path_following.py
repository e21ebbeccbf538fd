"""Figures of paper A (Figs. 5 and 6) from a :class:`~lipmpcc.plots.logs.PathFollowingLog` (a LIP or a
full-body run), plus frames of a full-body run (:func:`figure_frames`) and the receding horizon of a LIP
run, drawn at one step (:func:`plot_receding_horizon`) or animated (:func:`animate_receding_horizon`)."""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Protocol, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..obstacles import Obstacle
from ..paths import Path
from .logs import PathFollowingLog

if TYPE_CHECKING:  # matplotlib is imported when a figure is drawn (importing it takes ~0.5 s)
    from matplotlib.animation import FuncAnimation
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "EVENT_MARKERS",
    "REGION_MARGIN",
    "REGION_NEAR",
    "REGION_MIN_ASPECT",
    "path_region",
    "plot_path",
    "plot_errors",
    "plot_footsteps",
    "plot_vavg",
    "plot_contouring_fullbody",
    "figure_circle",
    "figure_circle_fullbody",
    "figure_overtake",
    "figure_follow_path",
    "figure_frames",
    "PlannedSteps",
    "plot_receding_horizon",
    "animate_receding_horizon",
]

RIGHT = "tab:blue"
LEFT = "tab:red"


def _check_log(log: object) -> PathFollowingLog:
    if not isinstance(log, PathFollowingLog):
        raise InvalidInputError(
            "log", type(log).__name__,
            "a PathFollowingLog (a LIP run's LipLog gives one: lipmpcc.studies.path_metrics.lip_path_log(log))",
        )
    return log


#: the markers of a run's events (:func:`plot_path`), in order
EVENT_MARKERS = ("X", "D", "P", "v")
#: [m] the margin around the robot's region (:func:`path_region`)
REGION_MARGIN = 0.5
#: [m] an obstacle's positions this near the robot (at the same instant) belong to the robot's region
REGION_NEAR = 2.0
#: the least span of the region along y, as a fraction of its span along x, and its least span [m]
REGION_MIN_ASPECT = 0.25
REGION_MIN_SPAN = 2.4


def path_region(log: PathFollowingLog, path: Path, extent: float | None = None,
                obstacles: Sequence[Obstacle] = ()) -> tuple[float, float, float, float]:
    """The robot's region of a run, (x0, x1, y0, y1) [m]: the COM's trace, the footholds, the path up to arc
    length ``extent`` [m] (None: all of it), the ``obstacles`` where they came within :data:`REGION_NEAR` of
    the COM at the same instant, and :data:`REGION_MARGIN` around; at least :data:`REGION_MIN_SPAN` wide and
    high. An obstacle's trajectory far from the robot does not widen it (the figures clip it)."""
    log = _check_log(log)
    L = float(path.length) if extent is None else float(min(max(extent, 0.0), path.length))
    pts = [np.asarray(path.position(np.linspace(0.0, L, 200)), dtype=float).reshape(-1, 2)]
    if len(log.com):
        pts.append(np.asarray(log.com)[:, [0, 2]])
    if len(log.footholds):
        pts.append(np.asarray(log.footholds)[:, :2])
    obs = np.asarray(log.obstacles, dtype=float)
    if obs.size and len(log.com):
        com = np.asarray(log.com)[:, [0, 2]]
        for j in range(obs.shape[0]):
            r = float(max(obstacles[j].axes)) if j < len(obstacles) else 0.0
            near = np.linalg.norm(obs[j] - com, axis=1) <= REGION_NEAR + r
            if np.any(near):
                c = obs[j][near]
                pts.append(np.vstack([c - r, c + r]))
    allp = np.vstack(pts)
    lo, hi = allp.min(axis=0) - REGION_MARGIN, allp.max(axis=0) + REGION_MARGIN
    for k in range(2):
        if hi[k] - lo[k] < REGION_MIN_SPAN:
            mid = 0.5 * (lo[k] + hi[k])
            lo[k], hi[k] = mid - REGION_MIN_SPAN / 2, mid + REGION_MIN_SPAN / 2
    return float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1])


class _Labels:
    """Text labels that do not overlap and stay in the axes: each is tried right and left of its point, above
    and below it, then further; when no place is free, it is joined to the label in the way."""

    OFFSETS = tuple((dx, dy, ha) for dy in (6, -12, 18, -24, 30, -36) for dx, ha in ((3, "left"), (-3, "right")))

    def __init__(self, ax: Axes) -> None:
        self.ax = ax
        self.placed: list[object] = []

    def _in_the_way(self, artist: object, renderer: object) -> tuple[bool, object | None]:
        box = artist.get_window_extent(renderer)  # type: ignore[attr-defined]
        frame = self.ax.get_window_extent(renderer)
        inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
        for other in self.placed:
            if box.overlaps(other.get_window_extent(renderer)):  # type: ignore[attr-defined]
                return inside, other
        return inside, None

    def add(self, text: str, xy: Sequence[float], **kw: object) -> None:
        kw.setdefault("fontsize", 7)
        renderer = self.ax.figure.canvas.get_renderer()  # type: ignore[attr-defined]
        first, outside = None, None
        for dx, dy, ha in self.OFFSETS:
            artist = self.ax.annotate(text, (float(xy[0]), float(xy[1])), xytext=(dx, dy), textcoords="offset points",
                                      ha=ha, **kw)
            inside, hit = self._in_the_way(artist, renderer)
            if hit is None and inside:
                self.placed.append(artist)
                return
            if hit is None and outside is None:
                outside = (dx, dy, ha)
            first = first or hit
            artist.remove()
        if first is not None:  # no free place in the axes: joined to the label in the way
            first.set_text(f"{first.get_text()}, {text}")  # type: ignore[union-attr]
            return
        dx, dy, ha = outside  # free only across the frame: better than hiding it
        self.placed.append(self.ax.annotate(text, (float(xy[0]), float(xy[1])), xytext=(dx, dy),
                                            textcoords="offset points", ha=ha, **kw))


def _inside(p: np.ndarray, region: tuple[float, float, float, float]) -> np.ndarray:
    return (p[:, 0] >= region[0]) & (p[:, 0] <= region[1]) & (p[:, 1] >= region[2]) & (p[:, 1] <= region[3])


def _draw_obstacle_tracks(ax: Axes, log: PathFollowingLog, obstacles: Sequence[Obstacle],
                          region: tuple[float, float, float, float], labels: _Labels) -> None:
    """Each moving obstacle's trajectory (dotted, clipped to ``region``), with an arrow at the last point it
    has in the region showing where it goes, and its number where it enters (a static one: where it stands;
    with more than four obstacles, the number alone)."""
    n = min(len(obstacles), np.asarray(log.obstacles).shape[0])
    name = "obstacle {}" if n <= 4 else "{}"
    for j in range(n):
        c = np.asarray(log.obstacles[j], dtype=float)
        if len(c) < 2 or np.allclose(c, c[0]):  # beside the obstacle's upper right edge, off its patch
            at = (c[0] if len(c) else np.asarray(obstacles[j].center(0.0))) + 0.7 * max(obstacles[j].axes)
            labels.add(name.format(j), at, color="dimgray")
            continue
        ax.plot(c[:, 0], c[:, 1], ":", color="gray", lw=1.0, label="obstacle track" if j == 0 else None)
        idx = np.flatnonzero(_inside(c, region))
        if not idx.size:
            continue
        labels.add(name.format(j), c[idx[0]], color="dimgray")
        i1 = int(idx[-1])
        i0 = max(0, i1 - max(1, len(c) // 50))
        if np.linalg.norm(c[i1] - c[i0]) > 1e-9:
            ax.annotate("", xy=tuple(c[i1]), xytext=tuple(c[i0]),
                        arrowprops=dict(arrowstyle="-|>", color="dimgray", lw=1.2, mutation_scale=14))


def _frame(ax: Axes, region: tuple[float, float, float, float], to_scale: bool) -> None:
    """Limit ``ax`` to ``region``: to scale (equal axes, y widened to :data:`REGION_MIN_ASPECT` of x), or with
    y stretched (a long straight run: the detour stays visible)."""
    x0, x1, y0, y1 = region
    ax.set_xlim(x0, x1)
    if to_scale:
        half = max(y1 - y0, REGION_MIN_ASPECT * (x1 - x0)) / 2
        ax.set_ylim(0.5 * (y0 + y1) - half, 0.5 * (y0 + y1) + half)
        ax.set_aspect("equal", adjustable="box")
        ax.apply_aspect()  # the box the labels are placed in
    else:
        ax.set_ylim(y0, y1)
        ax.set_aspect("auto")
        ax.set_title("y stretched (axes not to scale)", fontsize=8, loc="right")


def plot_path(ax: Axes, log: PathFollowingLog, path: Path, obstacles: Sequence[Obstacle] = (), snapshots: int = 4,
              events: Sequence[tuple[str, Sequence[float]]] = (), extent: float | None = None,
              to_scale: bool = False) -> None:
    """Reference path (red), COM path (blue), footholds, obstacles at a few instants, framed on the robot's
    region (:func:`path_region`, with obstacles: the path up to ``extent`` [m], None: all of it), each
    obstacle's trajectory clipped to it with an arrow where it goes; ``events``: (label, (x, y)) marked
    with a red marker each (:data:`EVENT_MARKERS`), named in the legend with where (where the run stalled,
    where it fell). With obstacles the y axis is stretched, unless ``to_scale`` (equal axes, at least
    :data:`REGION_MIN_ASPECT` as high as wide)."""
    from matplotlib.patches import Circle, Ellipse

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
    region = path_region(log, path, extent, obstacles) if len(obstacles) else None
    if region is not None:  # set first: the labels are placed (and kept apart) in these limits
        _frame(ax, region, to_scale)
    labels = _Labels(ax)
    if len(obstacles) and len(log.tc):
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
            labels.add(f"{log.tc[i]:.0f} s", (log.com[i, 0], log.com[i, 2]))
        _draw_obstacle_tracks(ax, log, obstacles, region, labels)
    for k, (text, xy) in enumerate(events):  # named in the legend: no label on the crowded spot
        ax.plot(float(xy[0]), float(xy[1]), EVENT_MARKERS[k % len(EVENT_MARKERS)], color="crimson", ms=10, mec="k",
                zorder=5, label=f"{text} ({round(float(xy[0]), 2) + 0.0:.2f}, {round(float(xy[1]), 2) + 0.0:.2f}) m")
    if region is None:
        ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)


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


def figure_circle(log: PathFollowingLog, path: Path, title: str = "", settle_time: float | None = None,
                  obstacles: Sequence[Obstacle] = (), events: Sequence[tuple[str, Sequence[float]]] = ()) -> Figure:
    """Paper A Fig. 5 (a, b) or (c, d): path (COM, footholds, pushes, and the ``obstacles`` of
    ``--obstacles`` if any, at a few instants; ``events``: see :func:`plot_path`) and contouring error.

    The error panel shows the continuous error of the COM and the error at the touch-downs when the log
    has the continuous one (a full-body run, with a line at ``settle_time`` [s] after the start), else the
    error at the step instants."""
    log = _check_log(log)
    import matplotlib.pyplot as plt
    fig, axs = plt.subplots(1, 2, figsize=(10, 4.2))
    plot_path(axs[0], log, path, obstacles, events=events)
    if log.e_contouring_c is not None:
        plot_contouring_fullbody(axs[1], log, settle_time)
    else:
        plot_errors(axs[1], log, "contouring")
    fig.suptitle(title or "MPCC on a circle of radius 2 m")
    fig.tight_layout()
    return fig


def figure_overtake(log: PathFollowingLog, path: Path, obstacles: Sequence[Obstacle], cartesian: bool, title: str = "",
                    events: Sequence[tuple[str, Sequence[float]]] = ()) -> Figure:
    """Paper A Fig. 6 (a–d) for the Cartesian MPC or (e–h) for the MPCC: the path framed on the part the
    robot walked (its progress and :data:`REGION_NEAR` ahead; ``events``: see :func:`plot_path`)."""
    log = _check_log(log)
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(11, 6.5))
    gs = fig.add_gridspec(2, 3, height_ratios=[1.0, 1.1])
    ax0 = fig.add_subplot(gs[0, :])
    plot_path(ax0, log, path, obstacles, events=events, extent=float(log.progress) + REGION_NEAR)
    plot_errors(fig.add_subplot(gs[1, 0]), log, "cartesian" if cartesian else "contouring+lag", pushes=False)
    plot_footsteps(fig.add_subplot(gs[1, 1]), log)
    plot_vavg(fig.add_subplot(gs[1, 2]), log)
    fig.suptitle(title or ("Cartesian MPC trailing the obstacle" if cartesian else "MPCC overtaking the obstacle"))
    fig.tight_layout()
    return fig


def figure_follow_path(log: PathFollowingLog, path: Path, obstacles: Sequence[Obstacle] = (), title: str = "",
                       settle_time: float | None = None, events: Sequence[tuple[str, Sequence[float]]] = ()) -> Figure:
    """A path-following run (``lipmpcc run follow-path``): the whole path, the COM, the footholds and the
    obstacles (if any, at a few instants, their trajectories clipped to the robot's region,
    :func:`path_region`, to scale, at least :data:`REGION_MIN_ASPECT` as high as wide), ``events`` (see
    :func:`plot_path`) above; the contouring error (a full-body run: continuous and at the touch-downs, with
    a line at ``settle_time`` [s]) and the path progress per step below."""
    log = _check_log(log)
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(11, 7.0))
    gs = fig.add_gridspec(2, 2, height_ratios=[1.3, 1.0])
    ax0 = fig.add_subplot(gs[0, :])
    plot_path(ax0, log, path, obstacles, events=events, to_scale=True)  # the bends to scale
    ax1 = fig.add_subplot(gs[1, 0])
    if log.e_contouring_c is not None:
        plot_contouring_fullbody(ax1, log, settle_time)
    else:
        plot_errors(ax1, log, "contouring")
    t0 = float(log.tc[0]) if len(log.tc) else 0.0
    judged = log.e_contouring[log.t - t0 >= (settle_time or 0.0)]
    if len(judged):
        after = f" after {settle_time:g} s" if settle_time else ""
        ax1.set_title(f"max |contouring error|{after}: {np.nanmax(np.abs(judged)):.3f} m", fontsize=9)
    plot_vavg(fig.add_subplot(gs[1, 1]), log)
    fig.suptitle(title or "Path following")
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
    import matplotlib.pyplot as plt
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


class PlannedSteps(Protocol):
    """One solve's plan as :func:`plot_receding_horizon` reads it (an
    :class:`~lipmpcc.planners.mpcc.MpccResult` is one): ``states`` (N+1, ≥3) predicted LIP states
    [x, ẋ, y, ...] at the step instants [m, m/s], ``footsteps`` (N, ≥2) predicted footholds [x, y, ...] [m]."""

    states: np.ndarray
    footsteps: np.ndarray


def _check_plans(log: PathFollowingLog, plans: Sequence[PlannedSteps]) -> None:
    n = len(log.footholds)
    if len(plans) != n or n == 0:
        raise InvalidInputError("plans", f"{len(plans)} plans", f"one plan per step of the log ({n} steps, at least 1)")
    for i, pl in enumerate(plans):
        if not (hasattr(pl, "states") and hasattr(pl, "footsteps")):
            raise InvalidInputError(f"plans[{i}]", type(pl).__name__, "a plan with .states and .footsteps (an MpccResult)")


def _draw_obstacles_at(ax: Axes, obstacles: Sequence[Obstacle], t: float) -> None:
    from matplotlib.patches import Circle, Ellipse

    for j, ob in enumerate(obstacles):
        c = ob.center(t)
        ang = np.degrees(float(ob.heading(t)))
        patch = Circle(c, ob.axes[0]) if ob.is_circle else Ellipse(c, 2 * ob.axes[0], 2 * ob.axes[1], angle=ang)
        patch.set(color="gray", alpha=0.5, label="obstacle now" if j == 0 else None)
        ax.add_patch(patch)


def plot_receding_horizon(ax: Axes, log: PathFollowingLog, plans: Sequence[PlannedSteps], path: Path, k: int,
                          obstacles: Sequence[Obstacle] = (), window: float | None = None,
                          limits: tuple[tuple[float, float], tuple[float, float]] | None = None) -> None:
    """The receding horizon at the support exchange that starts step ``k`` of a LIP run: the path, the COM
    walked so far and the footholds placed so far (solid), the plan of solve ``k`` (dashed: the predicted
    COM at the next N exchanges and the N predicted footholds; only its first foothold is executed) and the
    obstacles at that instant.

    Args:
        ax: the axes (cleared first).
        log: the run (:func:`lipmpcc.studies.path_metrics.lip_path_log` of a LIP run).
        plans: one plan per step (a LIP run's ``LipLog.plans``).
        path: the reference path.
        k: the step, 0 ≤ k < number of steps.
        obstacles: the run's obstacles.
        window: when given, the x axis follows the COM over this width [m] (for a long straight path).
        limits: ((xmin, xmax), (ymin, ymax)) [m]; default: the whole run and its plans.
    """
    log = _check_log(log)
    _check_plans(log, plans)
    if not isinstance(k, (int, np.integer)) or not 0 <= k < len(plans):
        raise InvalidInputError("k", k, f"a step index in [0, {len(plans) - 1}]")
    tk = float(log.t[k])
    ax.clear()
    ref = path.sample(400)
    ax.plot(ref[:, 0], ref[:, 1], color="tab:red", lw=1.0, alpha=0.6, label="reference path")
    walked = log.tc <= tk + 1e-9
    ax.plot(log.com[walked, 0], log.com[walked, 2], color="tab:blue", lw=1.2, label="COM walked")
    f, s = log.footholds[:k], log.sides[:k]
    ax.plot(f[s == 1, 0], f[s == 1, 1], "o", ms=4, color=LEFT, label="left feet placed")
    ax.plot(f[s != 1, 0], f[s != 1, 1], "o", ms=4, color=RIGHT, label="right feet placed")
    plan = plans[k]
    pc, pf = np.asarray(plan.states)[:, [0, 2]], np.asarray(plan.footsteps)[:, :2]
    ax.plot(pc[:, 0], pc[:, 1], "--", color="tab:purple", marker=".", lw=1.2, label=f"plan of step {k}: COM")
    ax.plot(pf[:, 0], pf[:, 1], "--", color="tab:green", marker="x", ms=6, lw=0.8, label="plan: footholds")
    ax.plot(*pf[0], "o", mfc="none", mec="k", ms=9, label="executed now (u₀)")
    _draw_obstacles_at(ax, obstacles, tk)
    if limits is None:
        allp = np.vstack([log.com[:, [0, 2]], *(np.asarray(p.states)[:, [0, 2]] for p in plans)])
        limits = ((allp[:, 0].min() - 0.5, allp[:, 0].max() + 0.5), (allp[:, 1].min() - 0.5, allp[:, 1].max() + 0.5))
    (x0, x1), (y0, y1) = limits
    if window is not None:
        x0 = float(log.com[walked, 0][-1]) - window / 3
        x1 = x0 + window
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"t = {tk:.1f} s, step {k}", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))


@lru_cache(maxsize=1)
def _frames_animation() -> type:
    """The class ``_FramesAnimation``, defined on first use (it subclasses matplotlib's FuncAnimation)."""
    from matplotlib.animation import FuncAnimation

    class _FramesAnimation(FuncAnimation):
        """A :class:`~matplotlib.animation.FuncAnimation` that skips the canvas redraw after each frame while
        it is saved (``to_jshtml``, ``save``): the writer's ``savefig`` draws the frame anyway, so saving
        draws each frame once instead of twice. Shown live, it behaves as a FuncAnimation."""

        def _post_draw(self, framedata: object, blit: bool) -> None:
            if not self._fig.canvas.is_saving():
                super()._post_draw(framedata, blit)

    return _FramesAnimation


def animate_receding_horizon(log: PathFollowingLog, plans: Sequence[PlannedSteps], path: Path,
                             obstacles: Sequence[Obstacle] = (), frames: int = 40, window: float | None = None,
                             figsize: tuple[float, float] = (8.0, 4.5), dpi: int = 60, interval: int = 250,
                             title: str = "") -> FuncAnimation:
    """:func:`plot_receding_horizon` at up to ``frames`` steps spread evenly over the run (the last step
    included), as a matplotlib animation. Embed it in a notebook with ``HTML(anim.to_jshtml())``; its figure
    is ``anim._fig`` (closed by the caller once embedded).

    Args:
        frames: most frames (≥ 1); ``dpi`` and ``figsize`` [in] keep an embedded animation small.
        interval: time between frames when played [ms].
        window, obstacles: as in :func:`plot_receding_horizon`.
    """
    log = _check_log(log)
    _check_plans(log, plans)
    if not isinstance(frames, (int, np.integer)) or frames < 1:
        raise InvalidInputError("frames", frames, "a number of frames ≥ 1")
    steps = np.unique(np.linspace(0, len(plans) - 1, min(int(frames), len(plans))).round().astype(int))
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    fig.subplots_adjust(left=0.09, right=0.74, bottom=0.14, top=0.86)  # fixed: a layout engine re-measures every frame
    if title:
        fig.suptitle(title, fontsize=10)
    allp = np.vstack([log.com[:, [0, 2]], *(np.asarray(p.states)[:, [0, 2]] for p in plans)])
    limits = ((allp[:, 0].min() - 0.5, allp[:, 0].max() + 0.5), (allp[:, 1].min() - 0.5, allp[:, 1].max() + 0.5))

    def draw(i: int) -> list:
        plot_receding_horizon(ax, log, plans, path, int(steps[i]), obstacles, window, limits)
        return []

    return _frames_animation()(fig, draw, frames=len(steps), interval=interval, blit=False)
