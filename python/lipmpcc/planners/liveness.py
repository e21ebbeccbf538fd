"""Liveness of the MPCC planners: notice a stall from the measured progress along the path (issue 31).

The MPCC's progress reward −ρ v² has zero slope at v = 0, so "stand still" is a local minimum, and the
warm start (the shifted previous plan) keeps a planner in it long after the reason has gone. Measured on
a straight 14 m path with one pedestrian crossing 3.3 m ahead (``follow-path``, paper A's ``circle``
weights, the LIP): the robot stops in front of the crossing, and every later solve returns the plan
v = (0, 0, 0, 0, v_max), a slow backward gait (the distance-per-step bound δ_min forbids standing still
and the barrier forbids stepping towards the pedestrian); the closest point ϑ_init follows the COM
backwards. The plan's *mean* v is v_max / N = 0.2 v_max, above the old restart test (mean v < v_max / 10),
so no restart was tried; a cold multi-start from the very same state finds a plan that walks on and costs
less (0.97 against 1.15). The cause is the solver's basin, not the cost.

:class:`ProgressMonitor` watches the measured path parameter ϑ_init of each solve against time and says
when the robot has gained less than ``min_progress`` [m] (:func:`stall_progress`) over the last ``window`` [s]: the planners then
solve again from their cold starts (march along the path, v = 0 and v = v_max, and for the SQP the
interior-point solution of the lifted problem) and keep the cheapest converged plan — the same cost, so
a robot that waits for a good reason (the barrier of an obstacle still on the path) keeps waiting, and
one that was only stuck walks on. When that does not help for :data:`DETOUR_AFTER` windows (the robot is
held by an obstacle that will not clear: standing beside or on the path, or coming towards the robot), the
planner solves with the detour weights (:data:`DETOUR_FIELDS`, paper A's overtaking preset, contouring
weight 1: the path may be left) until it has gained the plan's reach past the stall, and then returns to its
own weights (and to the path). Measured: with paper A's ``circle`` weights the contouring term (300 per m²)
makes the way around a static obstacle 0.3 m from the path dearer than standing still, for any start of the
solver; with the overtaking weights every such scene was passed (issue 31's 20 scenes).

Both rules engage only on a stall, so runs that never stall (paper A's studies) are unchanged bit for bit.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..exceptions import ParameterError
from ..obstacles import Obstacle
from ..paths import ExtendedPath, Path
from ..validation import finite_number, positive_number
from .presets import MPCC_PRESET_FIELDS

__all__ = ["ProgressMonitor", "stall_window", "stall_progress", "DETOUR_FIELDS", "detour_fields", "DETOUR_AFTER",
           "detour_pace", "problem_path", "end_mode", "approach_mode", "end_frame", "barred_by", "hold_inputs", "RETURN_STEPS",
           "RETURN_ERROR", "return_fields", "return_level", "passing", "trailed"]

#: the weights of the detour mode: paper A's overtaking preset (contouring weight 1, lag 1000, ρ = 50)
DETOUR_FIELDS: dict[str, object] = dict(MPCC_PRESET_FIELDS["overtake"])
#: how many stall windows without progress (the cold restarts tried at each solve) before the detour mode
DETOUR_AFTER = 2


def detour_fields(params: object) -> dict[str, object] | None:
    """The fields a planner with parameters ``params`` (an MpccParams) changes in its detour mode, or None
    when its weights already are the detour's (no detour mode)."""
    if all(getattr(params, k) == v for k, v in DETOUR_FIELDS.items()):
        return None
    return dict(DETOUR_FIELDS)


def detour_pace(params: object) -> dict[str, object]:
    """The fields a timed MPCC with varying step durations (``params``: a TimedMpccParams) changes in its detour
    and on the return from it, besides the weights (:func:`detour_fields`): no reward on the path speed
    (``reward_speed`` off: the progress reward is paper A's −ρ v² per step), so the durations stay near the
    nominal T (the duration cost α_σ) and the pace near v_max / T_nom [m/s], the fixed-T MPCC's.

    Why (issue 31, ``digit_like``, timed 0.3–0.5 s, follow-path, random scene 2): with the overtaking weights
    (ρ = 50) the speed reward −ρ (v T_nom / T)² made every detour plan T = T_min = 0.3 s at v = v_max, a body
    speed of 0.9–1.2 m/s (fixed T's detour: 0.75 m/s); the detour ended while the robot crossed the path at that
    speed, the own weights' first plan stood still, and the body fell with footholds 0.65 and 0.94 m apart."""
    return {"reward_speed": False} if getattr(params, "reward_speed", False) else {}


#: the return from the detour: the weights' fractions s of the way from the detour's to the planner's own
#: (geometric: w = w_detour^(1 − s) w_own^s), taken in turn after the detour ends (then s = 1: its own)
RETURN_STEPS = (1.0 / 3.0, 2.0 / 3.0)
#: [m] the return takes the next fraction once that fraction's contouring weight charges the measured contouring
#: error no more than the planner's own weight charges this error
RETURN_ERROR = 0.1


def _between(a: float, b: float, s: float) -> float:
    """``a``^(1 − s) ``b``^s (geometric), or linear when either is not positive."""
    a, b = float(a), float(b)
    return a ** (1.0 - s) * b ** s if a > 0.0 and b > 0.0 else (1.0 - s) * a + s * b


def return_fields(params: object, s: float) -> dict[str, object]:
    """The detour fields (:data:`DETOUR_FIELDS`) a fraction ``s`` in [0, 1] of the way from the detour's
    values (s = 0) back to those of ``params`` (an MpccParams; s = 1), geometrically per weight."""
    out: dict[str, object] = {}
    for k, d in DETOUR_FIELDS.items():
        own = getattr(params, k)
        if isinstance(d, tuple):
            out[k] = tuple(_between(a, b, s) for a, b in zip(d, own))
        else:
            out[k] = _between(d, own, s)  # type: ignore[arg-type]
    return out


def return_level(level: int, error: float, params: object, tolerance: float = RETURN_ERROR) -> int | None:
    """The return's step (an index into :data:`RETURN_STEPS`; None: the planner's own weights, the return is
    over) for a solve whose COM is ``error`` [m] from the path, after step ``level`` (it never goes back).

    Why: the detour (contouring weight 1) can leave the robot a metre beside the path when it ends. The own
    weights (``follow-path``: 300) then plan the way back at once, the reachability's largest steps and a hard
    stop: on issue 31's random scenes on ``digit_like`` the robot fell within two steps of every detour's end
    (seeds 1 and 9: 0.65 and 1.3 m from the path, footholds 0.46–0.7 m apart, COM velocity reversed). The
    return steps up through :data:`RETURN_STEPS` while the next step's contouring weight charges ``error``
    no more than the own weight charges ``tolerance``: the pull back to the path grows as the robot nears it."""
    cw = float(params.Q_bar[0])  # type: ignore[attr-defined]
    budget = cw * tolerance ** 2
    while True:
        nxt = level + 1
        w = return_fields(params, RETURN_STEPS[nxt])["Q_bar"][0] if nxt < len(RETURN_STEPS) else cw  # type: ignore[index]
        if w * error ** 2 > budget:
            return level
        if nxt >= len(RETURN_STEPS):
            return None
        level = nxt


def passing(theta: float, error: float, obstacles: Sequence[Obstacle], t: float, inflation: float, reach: float,
            tolerance: float = RETURN_ERROR) -> int | None:
    """The obstacle moving forward along the path that a robot ``error`` [m] off the path (more than
    ``tolerance``; the driver hands the lesser of the robot's and its last plan's end's distance from the path,
    so that a robot drifting off while its plans lead back, e.g. Digit v3 tracking paper A's Cartesian
    reference 0.10 m aside, is not taken as going around) at path parameter ``theta`` [m] and time ``t`` [s]
    is going around — its centre along the
    path between its own size grown by ``inflation`` [m] behind ϑ and ``reach`` [m] ahead of it (the nearest
    such, by index in ``obstacles``) — or None.

    Why: behind an obstacle slower than itself, paper A's path-following weights (contouring weight 300) do
    not keep trailing: the barrier holds the robot at the obstacle's pace, and the plans slide it sideways
    around the barrier a few centimetres per step, beside the obstacle at its pace, for 40 s and more
    (measured on issue 31's random scenes, LIP, obstacles at 0.054–0.066 m/s: the robot 0.08 → 0.63 m off
    the path from 60 s to 100 s, the obstacle 0.5 → 0.0 m ahead along the path, the run ending mid-pass;
    on ``digit_like`` one such creep ended in a fall). Once the plans have left the path to go around such an
    obstacle the planner has chosen to pass it: the driver then passes it in the detour mode (the overtaking
    weights, a few steps) and returns to the path by :func:`return_level`; a robot that stays on the path
    keeps trailing."""
    if not error > tolerance:
        return None
    best, gap = None, math.inf
    for j, ob in enumerate(obstacles):
        if ob.path is None or not ob.speed > 0.0:
            continue
        along = float(ob.s0 + ob.speed * t) - float(theta)
        if -(max(ob.axes) + inflation) <= along <= reach and abs(along) < gap:
            best, gap = j, abs(along)
    return best


def trailed(theta: float, position: Sequence[float], obstacles: Sequence[Obstacle], t: float, min_speed: float,
            reach: float) -> int | None:
    """The obstacle that holds a robot at path parameter ``theta`` [m] and COM ``position`` (x, y) [m] at time ``t``
    [s] while moving on along the path at ``min_speed`` [m/s] or faster (the speed of a robot that is not stalled,
    :func:`stall_progress` over :func:`stall_window`): the nearest obstacle to the robot (least clearance), if it
    moves forward along the path that fast with its centre ahead of ϑ by at most ``reach`` [m] (the plan's reach);
    else None. A robot held so is trailing, not stalled: the stall's detour does not start behind it
    (:meth:`ProgressMonitor.detour`); the planner still passes it when its own plans go around (:func:`passing`).

    Why (issue 31, LIP seed 64, the timed MPCC, follow-path weights): the robot trailed an obstacle moving at
    0.065 m/s on the path, 0.25 m of clearance behind it, for 38 s, gaining 0.026 m a step. Behind an obstacle
    that slow the progress reward −ρv² of trailing is all but nil, so a plan that stands still costs about the
    same; at 97.6 s the plans became v = (0, 0, 0, 0, v_max), the stand-still's restarts found nothing cheaper
    (the barrier holds it), and paper A's least COM step δ_min walked the robot back 0.11 m in three steps. Its
    gain over two stall windows fell to 0.13 m (< 0.15 m), the detour started a pass 6.2 s before the run's 258
    steps ran out, and the run ended mid-pass, neither at the end nor trailing (``incomplete`` at 16.64 m of
    19 m). Without the timed stand-still rule the same drift had come 4 s after the robot caught up, and the
    pass finished in time: whether the robot trailed or passed was the chance of such a drift. Such an obstacle
    clears the way at its own pace (issue 31: the robot waits for an obstacle that will clear the path, and the
    follow-path weights trail a slower one); the detour is for those that will not (static, oncoming)."""
    if not obstacles:
        return None
    pt = np.asarray(position, dtype=float).reshape(1, 2)
    clear = [float(ob.clearance(pt, float(t))[0]) for ob in obstacles]
    j = int(np.argmin(clear))
    ob = obstacles[j]
    if ob.path is None or not ob.speed >= min_speed:
        return None
    along = float(ob.s0 + ob.speed * t) - float(theta)
    return j if 0.0 < along <= reach else None


def problem_path(path: Path, past_end: bool, reach: float) -> Path:
    """The path an MPCC builds its problem on: ``path`` itself, or with ``past_end`` the path continued
    straight along its end tangent for ``reach`` [m] (:class:`~lipmpcc.paths.ExtendedPath`; the plan's
    reach, N v_max, so that ϑ_N is never capped by the end).

    Why: with ϑ ≤ ϑ_T the progress reward −ρ v² is the same whether the last metre is walked now or later,
    so within N v_max of the end the plans walk it at δ_min per step or slower, and a barrier nearby (an
    obstacle beside the path, a pedestrian crossing) then wins: the robot stalls short of the end or yields
    backwards (issue 31's end approach: 17 of 20 random scenes with the overtaking weights ended 0.4–1 m short).
    Past the end the path is a straight line, so the plan's last stages aim along the end tangent; the
    loops stop at the end (ϑ_1 ≥ ϑ_T) and the measured ϑ_init stays within [0, ϑ_T]."""
    if not past_end:
        return path
    return ExtendedPath(path, reach)


def end_mode(at_end: bool, theta: float, length: float, past_end: bool, leave_margin: float) -> bool:
    """Whether a planner solves in the end mode (on the path itself, ϑ ≤ ϑ_T: the plans stop at the end) for a
    solve from the measured ``theta`` [m] on a path of ``length`` [m], given whether the previous solve did
    (``at_end``). Only with ``past_end`` (else the problem is on the path itself anyway).

    The mode is entered once ϑ is the end (the robot there or past it) and left only when ϑ falls more than
    ``leave_margin`` [m] (one step's largest progress, v_max) short of the end: a hysteresis. Without it a
    full body standing at the end chattered between the two problems (measured on issue 31's random scenes
    on ``digit_like``): its sway or a step back put ϑ a few centimetres short of the end, the next plan on the
    extended path led it on along the end tangent by a step, the end mode's brought it back, and after some
    of these 0.5 m steps to and fro it fell (seeds 4 and 5, 8–12 s after reaching the end)."""
    if not past_end:
        return False
    if at_end:
        return bool(theta >= length - leave_margin)
    return bool(theta >= length - 1e-9)


def approach_mode(arriving: bool, theta: float, length: float, reach: float, past_end: bool,
                  leave_margin: float) -> bool:
    """Whether a planner solves in the approach to the end (the problem on the extended path with the arrival
    row, :func:`~lipmpcc.planners.mpcc.build_problem`) for a solve from the measured ``theta`` [m] on a path of
    ``length`` [m], given whether the previous solve did (``arriving``): once the plan's ``reach`` [m] (how far
    past the end the extended path runs, N v_max) takes ϑ to the end, and left as :func:`end_mode` is, only
    ``leave_margin`` [m] further back (a hysteresis). Only with ``past_end``."""
    return end_mode(arriving, theta, length - reach, past_end, leave_margin)


def end_frame(path: Path, past: float = 0.0) -> tuple[float, float, float, float]:
    """The point ``past`` [m] beyond the end of ``path`` along its end tangent, and that unit tangent:
    (pˣ, pʸ, tˣ, tʸ) [m, -] (the arrival row's bound, :func:`~lipmpcc.planners.mpcc.build_problem`)."""
    L = float(path.length)
    p, t = path.position(L), path.tangent(L)
    return float(p[0] + past * t[0]), float(p[1] + past * t[1]), float(t[0]), float(t[1])


def barred_by(points: np.ndarray, times: np.ndarray, obstacles: Sequence[Obstacle], radius: float) -> list[int]:
    """The obstacles a plan would walk into: the indices j (in ``obstacles``) of those whose clearance to a disk
    of ``radius`` [m] (the barrier's inflation) about a planned COM ``points[k]`` [m] at ``times[k]`` [s], k ≥ 1,
    falls below zero and below the clearance at ``points[0]`` (a robot already inside the grown obstacle may
    step out of it).

    Used on the solver's fallback (the previous plan replayed from the current state): where there is no way
    out (a ring of obstacles, a wall across a narrow passage), the replayed plan walks on into an obstacle the
    failed solve was avoiding; the planner then holds in place (:func:`hold_inputs`) instead."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    tt = np.asarray(times, dtype=float).reshape(-1)
    out = []
    for j, ob in enumerate(obstacles):
        c = ob.clearance(pts, tt, radius)
        if len(c) > 1 and float(np.min(c[1:])) < min(0.0, float(c[0])):
            out.append(j)
    return out


def hold_inputs(x0: np.ndarray, side: int, n: int, omega: float, T: float, lateral: tuple[float, float],
                forward: tuple[float, float] = (-math.inf, math.inf)) -> np.ndarray:
    """Stage inputs (n, 3) [uˣ, uʸ, u^θ] that step in place from LIP state ``x0`` = [x, ẋ, y, ẏ, heading]:
    each foot lands on the divergent component of motion ξ = c + ċ/ω [m] shifted sideways to its side by
    2a/(σ + 1) (σ = e^{ωT}, a = the middle of ``lateral`` [m]: the offset of the in-place gait whose feet are
    2a apart), so the COM comes to rest over the feet and the feet alternate sides. The offset from the COM is
    kept within the reachability rectangle's ``forward`` and ``lateral`` bounds [m] (in the heading frame,
    lateral to ``side``: +1 left, −1 right). Steps take T [s]; the heading does not change.
    """
    x = [float(v) for v in np.asarray(x0, dtype=float).reshape(-1)[:5]]
    c, s = math.cos(x[4]), math.sin(x[4])
    ch, sh = math.cosh(omega * T), math.sinh(omega * T)
    b = (lateral[0] + lateral[1]) / (math.exp(omega * T) + 1.0)
    U = np.zeros((int(n), 3))
    for k in range(int(n)):
        dx, dy = x[1] / omega, x[3] / omega  # foot at the DCM ...
        fwd, lat = c * dx + s * dy, -s * dx + c * dy + side * b  # ... shifted to its side (heading frame)
        lo, hi = sorted((side * lateral[0], side * lateral[1]))
        fwd, lat = min(max(fwd, forward[0]), forward[1]), min(max(lat, lo), hi)
        ux, uy = c * fwd - s * lat, s * fwd + c * lat
        U[k] = (ux, uy, 0.0)
        for i, u in ((0, ux), (2, uy)):  # the LIP about the foot for T
            p, v = x[i], x[i + 1]
            x[i], x[i + 1] = p + u - u * ch + v * sh / omega, -u * omega * sh + v * ch
        side = -side
    return U


def stall_window(N: int, T: float) -> float:
    """The time over which a planner judges its progress [s]: its horizon, N steps of T [s]."""
    return float(N) * float(T)


def stall_progress(N: int, v_max: float) -> float:
    """The least progress over :func:`stall_window` that is not a stall [m]: v_max / 20 [m] per step over N
    steps (0.0375 m/s for paper A's v_max = 0.3 m, T = 0.4 s: a robot trailing an obstacle at 0.05 m/s or
    faster, the slowest ``ahead`` obstacle of :mod:`lipmpcc.course.scenes`, is not stalled)."""
    return 0.05 * float(v_max) * float(N)


@dataclass
class ProgressMonitor:
    """The measured path parameter of each solve against time, and whether the robot has stalled.

    Attributes:
        window: how far back progress is judged [s].
        min_progress: the least gain of ϑ over ``window`` that is not a stall [m].
        history: (t [s], ϑ [m]) of the solves in the last :data:`DETOUR_AFTER` windows (and the one before).
        detour_until: ϑ at which the detour mode ends [m] (None: not in it).
    """

    window: float
    min_progress: float
    history: deque = field(default_factory=deque)
    detour_until: float | None = None

    def __post_init__(self) -> None:
        self.window = positive_number("window", self.window, "s", error=ParameterError)
        self.min_progress = positive_number("min_progress", self.min_progress, "m", error=ParameterError)

    def reset(self) -> None:
        """Forget the history and the detour (a new run)."""
        self.history.clear()
        self.detour_until = None

    def record(self, t: float, theta: float) -> None:
        """Add the solve at time ``t`` [s] from path parameter ``theta`` [m]; a time before the last one
        (a new run on the same planner) starts the history again."""
        t = finite_number("t", t, "s", error=ParameterError)
        theta = finite_number("theta", theta, "m", error=ParameterError)
        if self.history and t < self.history[-1][0]:
            self.reset()
        self.history.append((t, theta))
        # keep one record at or before t - DETOUR_AFTER windows (the reference of the longest judgement)
        while len(self.history) > 2 and self.history[1][0] <= t - DETOUR_AFTER * self.window:
            self.history.popleft()

    def stalled(self, windows: int = 1) -> bool:
        """The last record gained less than ``windows`` × ``min_progress`` over the ``windows`` × ``window``
        before it (False until the history spans that time)."""
        if len(self.history) < 2:
            return False
        t1, th1 = self.history[-1]
        span = windows * self.window - 1e-9
        ref = [th for t, th in self.history if t <= t1 - span]
        return bool(ref) and th1 - ref[-1] < windows * self.min_progress

    def start_detour(self, until: float) -> None:
        """Enter the detour mode now, until ϑ reaches ``until`` [m] (no change when already in it)."""
        if self.detour_until is None:
            self.detour_until = finite_number("until", until, "m", error=ParameterError)

    def detour(self, theta: float, reach: float, trailing: bool = False) -> bool:
        """Whether the solve at path parameter ``theta`` [m] (the last :meth:`record`) uses the detour mode: it
        starts after :data:`DETOUR_AFTER` windows stalled, unless the robot is ``trailing`` an obstacle that moves
        on along the path (:func:`trailed`), and lasts until ϑ has gained ``reach`` [m] (the plan's reach: past
        what blocked it); the history starts again when it ends."""
        if self.detour_until is None and not trailing and self.stalled(DETOUR_AFTER):
            self.detour_until = theta + reach
        if self.detour_until is not None and theta >= self.detour_until:
            self.detour_until = None
            last = self.history[-1]
            self.history.clear()
            self.history.append(last)
        return self.detour_until is not None
