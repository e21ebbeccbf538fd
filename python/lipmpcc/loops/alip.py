"""Reduced-order closed loop: the ALIP walking over a foothold sequence with a planner.

Each step the ALIP is integrated exactly (closed form, piecewise-constant push forces).
The planner (ALIP-MPC or ALIP-QP, anything with the same ``plan`` method) is called at
touch-down and then every ``replan_period`` (25 Hz) during the swing; the swing foot
lands on the latest planned foothold at the latest planned duration (variable). There is
no swing-leg dynamics: the foot goes where the last plan says.

Failure criterion (the run stops, ``fell = True``), checked at every planner tick and at
every touch-down:

1. a foothold outside its stone rectangle (tolerance ``tol``);
2. a foothold outside the kinematic limits relative to the stance foot
   (``|x| <= 0.6``, ``0.1 <= |y| <= 0.5`` m on the swing side);
3. the DCM leaving the viable set: the initial DCM of the current step (measured DCM
   projected back to the touch-down, paper B eq. 10) outside the intervals of
   :func:`lipmpcc.models.alip.viability_bounds` (``T >= T_min``). Outside them no
   admissible step sequence, stones or not, can stop the DCM from diverging;
4. the planner failing with no plan to fall back on.

``fall_index`` is the index in the sequence of the footstep during which the failure is
found: for 1–2 the footstep that landed badly; for 3 the step that starts (or is under
way) with a non-viable DCM, like paper B's "fails at the 14th step because the 13th foot
placement yields an initial condition that cannot lead to viable states".
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from ..exceptions import InvalidInputError, NoFallbackPlanError, ParameterError
from ..models.alip import (
    AlipParams,
    KinematicLimits,
    alip_flow,
    alip_from_com,
    com_velocity_from_alip,
    dcm_from_alip,
    parse_side,
    viability_bounds,
)
from ..terrain import STEP_WIDTH, StoneSequence, initial_feet

__all__ = [
    "Push",
    "AlipLoopConfig",
    "AlipInitialState",
    "AlipLoopLog",
    "FootPlanner",
    "run_alip_loop",
    "loop_metrics",
]


class FootPlanner(Protocol):
    """What the loop needs from a planner (ALIP-MPC and ALIP-QP provide it)."""

    stones_needed: int
    failures: int

    def plan(self, dcm_world: Any, stance_world: Any, stance_side: int | str, t_since_touchdown: float, stones: Any) -> Any: ...

    def reset(self) -> None: ...


@dataclass(frozen=True)
class Push:
    """A horizontal force on the COM.

    Attributes:
        force: (F_x, F_y) world frame [N].
        t_start, t_end: window [s]; relative to the touch-down that starts footstep
            ``step`` when ``step`` is given, else absolute run time.
        step: index (0-based) in the loop's foothold sequence of the footstep whose swing
            phase is pushed, or None.
    """

    force: tuple[float, float]
    t_start: float
    t_end: float
    step: int | None = None

    def __post_init__(self) -> None:
        try:
            f = np.asarray(self.force, dtype=float)
        except (TypeError, ValueError):
            raise InvalidInputError("force", self.force, "(F_x, F_y) finite [N]") from None
        if f.shape != (2,) or not np.all(np.isfinite(f)):
            raise InvalidInputError("force", self.force, "(F_x, F_y) finite [N]")
        object.__setattr__(self, "force", (float(f[0]), float(f[1])))
        for name in ("t_start", "t_end"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise InvalidInputError(name, v, "a finite time >= 0 [s]")
        if self.t_end <= self.t_start:
            raise InvalidInputError("t_start, t_end", (self.t_start, self.t_end), "t_start < t_end [s]")
        if self.step is not None and (not isinstance(self.step, (int, np.integer)) or self.step < 0):
            raise InvalidInputError("step", self.step, "None or a footstep index >= 0")


@dataclass(frozen=True)
class AlipLoopConfig:
    """Loop settings.

    Attributes:
        alip: ALIP constants (must match the planner's).
        limits: kinematic limits used by the failure criterion [m].
        T_min: shortest step [s] in the viability bounds.
        replan_period: planner period [s] (paper B: 40 ms).
        pushes: forces on the COM.
        log_period: sampling period of the logged trajectories [s].
        tol: tolerance of the stone / kinematic / viability checks [m].
    """

    alip: AlipParams = field(default_factory=AlipParams)
    limits: KinematicLimits = field(default_factory=KinematicLimits)
    T_min: float = 0.35
    replan_period: float = 0.04
    pushes: tuple[Push, ...] = ()
    log_period: float = 0.01
    tol: float = 1e-6

    def __post_init__(self) -> None:
        for name in ("T_min", "replan_period", "log_period", "tol"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ParameterError(name, v, "a finite number > 0")
        if not all(isinstance(p, Push) for p in self.pushes):
            raise ParameterError("pushes", self.pushes, "a tuple of Push")
        object.__setattr__(self, "pushes", tuple(self.pushes))


@dataclass(frozen=True)
class AlipInitialState:
    """Start of a run: stance foot, COM and COM velocity in the world frame [m, m/s]."""

    stance: tuple[float, float]
    stance_side: int
    com: tuple[float, float]
    com_vel: tuple[float, float] = (0.0, 0.0)
    swing_foot: tuple[float, float] | None = None

    @classmethod
    def standing(cls, w: float = STEP_WIDTH, alip: AlipParams | None = None, T_nom: float = 0.5) -> "AlipInitialState":
        """Standing still on the left foot (the right foot swings first), feet at
        ``(0, +-w/2)``. The COM is at rest, shifted from the midpoint of the feet towards
        the stance foot to the in-place-stepping initial DCM ``-w/(e^{lambda T_nom} + 1)``
        (eq. 5 with L = W = 0): the ALIP has no double support in which to shift the
        weight, so the run starts where that shift ends. Starting at the midpoint would
        put the DCM 0.14 m out, on the edge of the viable set."""
        left, right = initial_feet(w)
        lam = (AlipParams() if alip is None else alip).lam
        y = left[1] - w / (math.exp(lam * T_nom) + 1.0)
        return cls(tuple(left), +1, (0.0, float(y)), (0.0, 0.0), tuple(right))  # type: ignore[arg-type]


@dataclass
class AlipLoopLog:
    """Everything a run produced (arrays indexed by sample, step or planner tick)."""

    sequence: StoneSequence
    t: np.ndarray
    com: np.ndarray
    com_vel: np.ndarray
    dcm: np.ndarray
    sample_step: np.ndarray
    footholds: np.ndarray
    step_index: np.ndarray
    step_sides: np.ndarray
    durations: np.ndarray
    td_times: np.ndarray
    z_initial: np.ndarray
    in_stone: np.ndarray
    kin_ok: np.ndarray
    plan_t: np.ndarray
    plan_step: np.ndarray
    plan_t_step: np.ndarray
    plan_T: np.ndarray
    plan_foothold: np.ndarray
    solve_time: np.ndarray
    plan_time: np.ndarray
    plan_fallback: np.ndarray
    plan_status: list[str]
    start_stance: np.ndarray
    start_swing: np.ndarray | None
    fell: bool
    fall_index: int | None
    fall_reason: str
    fall_time: float | None
    completed: bool
    solver_failures: int
    pushes: tuple[Push, ...]
    push_windows: list[tuple[float, float, tuple[float, float]]]
    dcm_bounds: Any
    lam: float

    @property
    def n_steps(self) -> int:
        return len(self.footholds)


def _check_state(init: AlipInitialState) -> None:
    for name in ("stance", "com", "com_vel"):
        v = np.asarray(getattr(init, name), dtype=float)
        if v.shape != (2,) or not np.all(np.isfinite(v)):
            raise InvalidInputError(f"initial.{name}", getattr(init, name), "(x, y) finite [m]")
    parse_side(init.stance_side)


def run_alip_loop(
    planner: FootPlanner,
    sequence: StoneSequence,
    initial: AlipInitialState | None = None,
    config: AlipLoopConfig | None = None,
    approach_planner: FootPlanner | None = None,
    approach_steps: int = 0,
) -> AlipLoopLog:
    """Walk the ALIP over ``sequence`` with ``planner`` until the last foothold or a failure.

    Args:
        planner: ALIP-MPC, ALIP-QP or equivalent (reset at the start of the run).
        sequence: footholds in order (approach + stones); ``sequence.sides[0]`` must be
            the foot opposite to the initial stance.
        initial: start state (default: standing, left stance).
        config: loop settings.
        approach_planner: planner for the first ``approach_steps`` footsteps (None: use
            ``planner`` throughout). Like any planner it previews the footholds ahead,
            stones included. Sharing one approach planner gives every planner under test
            the same state when it takes over (paper B: "we try to ensure consistent
            initial conditions in each comparison test").
        approach_steps: number of footsteps driven by ``approach_planner``.

    Returns:
        :class:`AlipLoopLog`.
    """
    cfg = AlipLoopConfig() if config is None else config
    if not isinstance(cfg, AlipLoopConfig):
        raise ParameterError("config", config, "an AlipLoopConfig")
    init = AlipInitialState.standing(alip=cfg.alip) if initial is None else initial
    if not isinstance(init, AlipInitialState):
        raise InvalidInputError("initial", initial, "an AlipInitialState")
    if not isinstance(sequence, StoneSequence) or len(sequence) == 0:
        raise InvalidInputError("sequence", sequence, "a non-empty StoneSequence")
    if not callable(getattr(planner, "plan", None)):
        raise InvalidInputError("planner", planner, "an object with a plan(...) method (AlipMpc, AlipQp)")
    _check_state(init)
    if int(sequence.sides[0]) != -parse_side(init.stance_side):
        raise InvalidInputError("sequence.sides[0]", int(sequence.sides[0]), "the foot opposite to the initial stance foot")
    prm = cfg.alip
    pl_alip = getattr(getattr(planner, "params", None), "alip", None)
    if pl_alip is not None and pl_alip != prm:
        raise ParameterError("config.alip", prm, f"the planner's ALIP constants {pl_alip}")
    lam = prm.lam
    bounds = viability_bounds(lam, cfg.T_min, cfg.limits)
    if approach_planner is not None and not callable(getattr(approach_planner, "plan", None)):
        raise InvalidInputError("approach_planner", approach_planner, "None or an object with a plan(...) method")
    if not isinstance(approach_steps, (int, np.integer)) or not 0 <= approach_steps <= len(sequence):
        raise InvalidInputError("approach_steps", approach_steps, f"an integer in [0, {len(sequence)}]")
    if approach_planner is None:
        approach_steps = 0

    def stones_needed(p: Any) -> int:
        return max(int(getattr(p, "stones_needed", getattr(p, "horizon", 1))), 1)

    planner.reset()
    if approach_planner is not None:
        approach_planner.reset()

    stance = np.asarray(init.stance, float).copy()
    side = parse_side(init.stance_side)
    s = alip_from_com(np.asarray(init.com, float) - stance, init.com_vel, prm)
    k = 0
    t_glob = 0.0
    t_step = 0.0
    step_start = 0.0
    tol = cfg.tol
    # logs
    T_, C_, V_, D_, K_ = [], [], [], [], []
    F_, SI_, SS_, DU_, TD_, IS_, KO_ = [], [], [], [], [], [], []
    Z_ = [dcm_from_alip(s, prm)]
    PT_, PK_, PTS_, PTT_, PF_, ST_, PLT_, PFB_, PS_ = [], [], [], [], [], [], [], [], []
    windows: list[tuple[float, float, tuple[float, float]]] = [
        (p.t_start, p.t_end, p.force) for p in cfg.pushes if p.step is None
    ]
    fell, fall_index, fall_reason, fall_time, completed = False, None, "", None, False

    def log_sample() -> None:
        T_.append(t_glob)
        C_.append(stance + s[0:2])
        V_.append(com_velocity_from_alip(s, prm))
        D_.append(stance + dcm_from_alip(s, prm))
        K_.append(k)

    def force_at(tg: float) -> np.ndarray:
        f = np.zeros(2)
        for a, b, fv in windows:
            if a <= tg < b:
                f += fv
        return f

    def register_pushes(step: int, start: float) -> None:
        for p in cfg.pushes:
            if p.step is not None and p.step == step:
                windows.append((start + p.t_start, start + p.t_end, p.force))

    log_sample()
    register_pushes(0, 0.0)
    max_time = 2.0 * len(sequence) + 5.0
    while True:
        # ------------------------------------------------------------- plan
        dcm_w = stance + dcm_from_alip(s, prm)
        z0 = (dcm_w - stance) * math.exp(-lam * t_step)
        if not bounds.contains(z0, -side, tol):
            fell, fall_index, fall_time = True, k, t_glob
            fall_reason = f"DCM left the viable set (initial DCM {np.round(z0, 4).tolist()} m) during footstep {k}"
            break
        active = approach_planner if k < approach_steps else planner
        H = stones_needed(active)
        upcoming = [sequence[j] for j in range(k, min(k + H, len(sequence)))]
        try:
            res = active.plan(dcm_w, stance, side, t_step, upcoming)  # type: ignore[union-attr]
        except NoFallbackPlanError as exc:
            fell, fall_index, fall_reason, fall_time = True, k, f"planner failed with no fallback plan: {exc}", t_glob
            break
        PT_.append(t_glob)
        PK_.append(k)
        PTS_.append(t_step)
        PTT_.append(res.step_duration)
        PF_.append(np.asarray(res.next_foothold, float))
        ST_.append(res.solve_time)
        PLT_.append(res.plan_time)
        PFB_.append(bool(res.fallback))
        PS_.append(res.status)
        # ------------------------------------------------------------- integrate
        T_td = float(res.step_duration)
        t_next = t_step + cfg.replan_period
        touchdown = T_td <= t_next + 1e-12
        t_target = max(T_td, t_step) if touchdown else t_next
        t_end_glob = t_glob + (t_target - t_step)
        cuts = {t_end_glob}
        for a, b, _ in windows:
            for c in (a, b):
                if t_glob < c < t_end_glob:
                    cuts.add(c)
        g = math.floor(t_glob / cfg.log_period + 1e-9) + 1
        while g * cfg.log_period < t_end_glob - 1e-12:
            cuts.add(g * cfg.log_period)
            g += 1
        # a planned centre-of-pressure offset (planner with a foot): the ALIP about the shifted pivot;
        # at constant height the angular momentum about it is the same (L_xy = m z_c (v_y, -v_x))
        cop = getattr(res, "cop_offset", None)
        shifted = cop is not None and bool(np.any(cop))
        for c in sorted(cuts):
            dt = c - t_glob
            if dt > 0:
                if shifted:
                    s = s.copy()
                    s[0:2] -= cop
                    s = alip_flow(s, dt, prm, force_at(t_glob + 0.5 * dt))
                    s[0:2] += cop
                else:
                    s = alip_flow(s, dt, prm, force_at(t_glob + 0.5 * dt))
                t_glob = c
            log_sample()
        t_step = t_target
        if t_glob > max_time:
            fell, fall_index, fall_time, fall_reason = True, k, t_glob, "time limit reached"
            break
        if not touchdown:
            continue
        # ------------------------------------------------------------- touch-down
        foothold = np.asarray(res.next_foothold, float).copy()
        u = foothold - stance
        swing_side = -side
        st = sequence[k]
        in_stone = (not bool(sequence.is_stone[k])) or st.contains(foothold, tol)
        kin_ok = cfg.limits.contains(u, swing_side, tol)
        F_.append(foothold)
        SI_.append(k)
        SS_.append(swing_side)
        DU_.append(t_step)
        TD_.append(t_glob)
        IS_.append(in_stone)
        KO_.append(kin_ok)
        s = s.copy()
        s[0:2] -= u
        stance = foothold
        side = swing_side
        t_step = 0.0
        step_start = t_glob
        k += 1
        register_pushes(k, step_start)
        Z_.append(dcm_from_alip(s, prm))
        if not in_stone or not kin_ok:
            fell, fall_index, fall_time = True, k - 1, t_glob
            fall_reason = (
                f"foothold {np.round(foothold, 4).tolist()} of footstep {k - 1} "
                + ("outside its stone" if not in_stone else "outside the kinematic limits")
            )
            break
        if not bounds.contains(Z_[-1], -side, tol):
            fell, fall_index, fall_time = True, k, t_glob
            fall_reason = f"DCM left the viable set (initial DCM {np.round(Z_[-1], 4).tolist()} m) at the start of footstep {k}"
            break
        if k >= len(sequence):
            completed = True
            break

    def arr(x: list, shape: tuple[int, ...], dtype: Any = float) -> np.ndarray:
        return np.array(x, dtype=dtype) if x else np.zeros(shape, dtype=dtype)

    return AlipLoopLog(
        sequence=sequence,
        t=arr(T_, (0,)),
        com=arr(C_, (0, 2)),
        com_vel=arr(V_, (0, 2)),
        dcm=arr(D_, (0, 2)),
        sample_step=arr(K_, (0,), int),
        footholds=arr(F_, (0, 2)),
        step_index=arr(SI_, (0,), int),
        step_sides=arr(SS_, (0,), int),
        durations=arr(DU_, (0,)),
        td_times=arr(TD_, (0,)),
        z_initial=np.array(Z_),
        in_stone=arr(IS_, (0,), bool),
        kin_ok=arr(KO_, (0,), bool),
        plan_t=arr(PT_, (0,)),
        plan_step=arr(PK_, (0,), int),
        plan_t_step=arr(PTS_, (0,)),
        plan_T=arr(PTT_, (0,)),
        plan_foothold=arr(PF_, (0, 2)),
        solve_time=arr(ST_, (0,)),
        plan_time=arr(PLT_, (0,)),
        plan_fallback=arr(PFB_, (0,), bool),
        plan_status=PS_,
        start_stance=np.asarray(init.stance, float),
        start_swing=None if init.swing_foot is None else np.asarray(init.swing_foot, float),
        fell=fell,
        fall_index=fall_index,
        fall_reason=fall_reason,
        fall_time=fall_time,
        completed=completed,
        solver_failures=int(getattr(planner, "failures", 0)),
        pushes=cfg.pushes,
        push_windows=windows,
        dcm_bounds=bounds,
        lam=lam,
    )


def loop_metrics(log: AlipLoopLog) -> dict[str, Any]:
    """Stone metrics of a run: landed stones, RMSE to the stone centres [m], stones
    violated, step durations on the stones [s], planner timing [ms]."""
    from ..metrics import timing_stats_ms

    seq = log.sequence
    on = np.array([bool(seq.is_stone[i]) for i in log.step_index], dtype=bool)
    idx = log.step_index[on]
    errs = np.linalg.norm(log.footholds[on] - seq.centers[idx], axis=1) if idx.size else np.zeros(0)
    n_stones = int(np.sum(seq.is_stone))
    first_stone = int(np.argmax(seq.is_stone)) if n_stones else 0
    landed_ok = int(np.sum(log.in_stone[on] & log.kin_ok[on])) if idx.size else 0
    d = log.durations[on]
    fall_step = None
    if log.fell and log.fall_index is not None:
        fall_step = int(log.fall_index - first_stone + 1)
    return {
        "n_stones": n_stones,
        "steps_completed": landed_ok if not log.fell else int(max(0, min(landed_ok, (fall_step or 1) - 1))),
        "step_rmse_m": float(np.sqrt(np.mean(errs**2))) if errs.size else float("nan"),
        "step_error_max_m": float(np.max(errs)) if errs.size else float("nan"),
        "stones_violated": int(np.sum(~log.in_stone[on])) if idx.size else 0,
        "step_duration_min_s": float(np.min(d)) if d.size else float("nan"),
        "step_duration_max_s": float(np.max(d)) if d.size else float("nan"),
        "solve_ms": timing_stats_ms(log.solve_time),
        "plan_ms": timing_stats_ms(log.plan_time),
        "solver_failures": int(log.solver_failures),
        "fallback_ticks": int(np.sum(log.plan_fallback)),
        "fell": bool(log.fell),
        "fall_step": fall_step,
        "fall_reason": log.fall_reason,
        "completed": bool(log.completed),
    }
