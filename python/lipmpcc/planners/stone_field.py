"""Across a stone field with a pedestrian: choose the stones, then place each foot with paper B's ALIP-MPC.

Beyond both papers (issue 29). The field (:class:`~lipmpcc.stone_field.StoneField`) has more stones
than steps; the planner chooses which stone each foot lands on, and when to wait, in two layers:

1. **The stone choice** (at every touch-down, with the pedestrians' predicted positions): a dynamic
   programme over the next ``horizon_choice`` steps on the stone graph. A node is a stone (or the
   goal); an edge i -> j for a swing foot of side s exists when stone j's centre lies within the
   planning limits of stone i's (``|dx| <= step_x_max``, ``step_y_min <= s dy <= step_y_max`` [m]),
   the first step from the actual stance point into the stone shrunk by ``edge_margin``, and the first
   step must also keep the initial DCM of the next step viable for some duration in [T_min, T_max]
   (paper B eq. 6, :func:`~lipmpcc.models.alip.viability_bounds`). Stepping back onto the stone the
   swing foot left is an edge like any other: that is how the robot **waits** (marching on two
   stones). Each step costs 1 plus ``w_offset`` times the squared lateral offset of its stone beyond
   ``offset_free`` from the path, plus ``w_collision`` times the pedestrian clearance missing at its
   predicted time (the stone under the foot from its touch-down for two steps, the COM near the two
   feet around the touch-down, each needing the pedestrian's radius, the foot's or the body's radius
   and ``margin``); the last step adds the **cost-to-go** to the goal (the fewest steps over the
   static graph, Dijkstra over (stone, foot side), computed once per field). The choice is exact on
   this model: a DP over the graph, O(horizon x n²) per touch-down with n stones.
2. **The placement**: paper B's :class:`~lipmpcc.planners.alip_mpc.AlipMpc` with the chosen stones
   as its regions (the goal clipped to a nominal step from the region before), adaptive durations,
   re-solved at 25 Hz during the swing. With a foot (``mpc.cop_range`` > 0) each stone is shrunk by the
   centre-of-pressure box, so that any centre of pressure the MPC plans about the foothold is on the stone. The goal is solid ground: once a foot is on it the regions
   are the goal.

Two baselines share the placement (issue 29): ``chooser="greedy"`` takes the nearest reachable stone
ahead of the stance foot, step after step, with a fixed step duration (T in [0.49, 0.51] s);
``chooser="nominal"`` (path-agnostic) takes the reachable stone nearest a nominal step (0.35 m ahead,
``w`` across) with paper B's adaptive durations, ignoring the path and the pedestrian.

When no stone is reachable, or no way leads to the goal, the planner raises
:class:`~lipmpcc.exceptions.NoFallbackPlanError` naming the step and the stance foot (the loop stops
and reports it; the stone-field study calls that outcome ``stalled``): never a hang.
"""

from __future__ import annotations

import heapq
import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..exceptions import InvalidInputError, NoFallbackPlanError, ParameterError
from ..models.alip import AlipParams, parse_side
from ..stone_field import StoneField
from ..terrain import Stone
from ..validation import check_field_types, count, non_negative_number, positive_number
from .alip_common import AlipPlanResult, to_step_plan
from .alip_mpc import AlipMpc, AlipMpcParams
from .base import PlannerInput, StepPlan

__all__ = ["CHOOSERS", "StoneFieldParams", "StoneChoice", "StoneFieldPlanner", "cost_to_go"]

#: the stone choosers: the planner's, and the two baselines
CHOOSERS = ("cost-to-go", "greedy", "nominal")
_NAMES = {"cost-to-go": "stone-field", "greedy": "greedy-stone", "nominal": "path-agnostic-alip-mpc"}


@dataclass(frozen=True)
class StoneFieldParams:
    """Parameters of the stone choice (the placement's are ``mpc``, paper B's by default).

    Attributes:
        chooser: "cost-to-go" (the planner), "greedy" or "nominal" (the baselines).
        horizon_choice: steps the choice looks ahead (>= the MPC's horizon + 1).
        step_x_max, step_y_min, step_y_max: planning limits on a step between stone centres [m].
        edge_margin: how far inside a stone the first foothold must be reachable [m].
        robot_radius, foot_radius: the body disk about the COM and the foot disk [m].
        margin: clearance kept from a pedestrian beyond those radii [m].
        w_collision: cost per metre of missing clearance [1/m].
        w_offset, offset_free: cost [1/m²] on a stone's lateral offset from the path beyond ``offset_free`` [m].
        L_nominal: the nominal step length [m] of the "nominal" chooser and of the ``w_length`` term.
        w_length: cost [1/m²] on a step's length along x away from ``L_nominal`` (0: off).
        viability_margin: the first step keeps the next initial DCM this far inside the viable set [m].
        probes: the most trial solves of the ALIP-MPC that check a choice at a touch-down (1: none).
        cold_retry: when the warm-started MPC fails, solve again from a cold start (and keep that MPC).
        mpc: the ALIP-MPC's parameters.
    """

    chooser: str = "cost-to-go"
    horizon_choice: int = 6
    step_x_max: float = 0.55
    step_y_min: float = 0.12
    step_y_max: float = 0.45
    edge_margin: float = 0.01
    robot_radius: float = 0.2
    foot_radius: float = 0.05
    margin: float = 0.1
    w_collision: float = 1000.0
    w_offset: float = 2.0
    offset_free: float = 0.3
    L_nominal: float = 0.35
    w_length: float = 0.0
    viability_margin: float = 0.01
    probes: int = 5
    cold_retry: bool = True
    mpc: AlipMpcParams = field(default_factory=AlipMpcParams)

    def __post_init__(self) -> None:
        check_field_types(self, error=ParameterError)
        if self.chooser not in CHOOSERS:
            raise ParameterError("chooser", self.chooser, f"one of {', '.join(CHOOSERS)}")
        count("horizon_choice", self.horizon_choice, self.mpc.horizon + 1, 30, error=ParameterError)
        count("probes", self.probes, 1, 10, error=ParameterError)
        for name in ("step_x_max", "step_y_max", "robot_radius", "L_nominal"):
            positive_number(name, getattr(self, name), "m", error=ParameterError)
        for name in ("step_y_min", "edge_margin", "foot_radius", "margin", "w_collision", "w_offset", "offset_free",
                     "viability_margin", "w_length"):
            non_negative_number(name, getattr(self, name), error=ParameterError)
        if self.step_y_min >= self.step_y_max:
            raise ParameterError("step_y_min, step_y_max", (self.step_y_min, self.step_y_max), "step_y_min < step_y_max [m]")

    @property
    def alip(self) -> AlipParams:
        """The ALIP constants (the MPC's): a loop checks that they match its own."""
        return self.mpc.alip


@dataclass
class StoneChoice:
    """One stone choice, made at a touch-down.

    Attributes:
        step: the loop's step index; t: its time [s].
        nodes: the chosen nodes, next first (stone indices; ``n_stones`` is the goal).
        cost: the choice's cost (inf: no way to the goal); waits: steps back onto a stone just left.
        choice_time: wall time of the choice [s].
    """

    step: int
    t: float
    nodes: list[int]
    cost: float
    waits: int
    choice_time: float


def _adjacency(c: np.ndarray, goal: Stone, prm: StoneFieldParams) -> dict[int, np.ndarray]:
    """Static edges between the nodes (stones, then the goal) for a swing foot of each side."""
    n = len(c)
    d = c[None, :, :] - c[:, None, :]  # d[i, j] = c_j - c_i
    adj = {}
    lo_g, hi_g = goal.lower, goal.upper
    for s in (1, -1):
        a = np.zeros((n + 1, n + 1), bool)
        a[:n, :n] = (np.abs(d[..., 0]) <= prm.step_x_max) & (s * d[..., 1] >= prm.step_y_min) & (s * d[..., 1] <= prm.step_y_max)
        np.fill_diagonal(a, False)
        ylo = np.where(s > 0, c[:, 1] + prm.step_y_min, c[:, 1] - prm.step_y_max)
        yhi = np.where(s > 0, c[:, 1] + prm.step_y_max, c[:, 1] - prm.step_y_min)
        a[:n, n] = ((c[:, 0] + prm.step_x_max >= lo_g[0] + 0.05) & (c[:, 0] - prm.step_x_max <= hi_g[0])
                    & (yhi >= lo_g[1]) & (ylo <= hi_g[1]))
        a[n, n] = True
        adj[s] = a
    return adj


def cost_to_go(adj: dict[int, np.ndarray], node_cost: np.ndarray) -> dict[int, np.ndarray]:
    """The least cost to the goal node (the last) from each (node, side of the foot on it): each step
    costs 1 + ``node_cost`` of its stone (Dijkstra backwards); inf where no way leads to the goal."""
    n1 = len(node_cost)
    ctg = {1: np.full(n1, np.inf), -1: np.full(n1, np.inf)}
    heap = [(0.0, n1 - 1, 1), (0.0, n1 - 1, -1)]
    ctg[1][n1 - 1] = ctg[-1][n1 - 1] = 0.0
    while heap:
        v, j, g = heapq.heappop(heap)
        if v > ctg[g][j]:
            continue
        # a swing foot of side g landed on j from a stance i whose foot has side -g
        for i in np.flatnonzero(adj[g][:, j]):
            nv = v + 1.0 + node_cost[j]
            if nv < ctg[-g][i]:
                ctg[-g][i] = nv
                heapq.heappush(heap, (nv, int(i), -g))
    return ctg


class StoneFieldPlanner:
    """Chooses the stones across a :class:`~lipmpcc.stone_field.StoneField` and places each foot with
    paper B's ALIP-MPC (see the module docstring). Implements the planner contract
    (:mod:`lipmpcc.planners.base`); the field, its pedestrians included, is given here (the loop's
    ``course`` is not read).

    Attributes:
        field: the stone field; params: the parameters; mpc: the placement.
        choices: the stone choices of the run, one per touch-down (:class:`StoneChoice`).
    """

    def __init__(self, stone_field: StoneField, params: StoneFieldParams | None = None) -> None:
        if not isinstance(stone_field, StoneField):
            raise InvalidInputError("stone_field", stone_field, "a lipmpcc.stone_field.StoneField")
        prm = StoneFieldParams() if params is None else params
        if not isinstance(prm, StoneFieldParams):
            raise ParameterError("params", params, "a StoneFieldParams")
        if prm.chooser == "greedy":  # the baseline's fixed step duration
            prm = replace(prm, mpc=replace(prm.mpc, T_min=0.49, T_nom=0.5, T_max=0.51))
        self.field, self.params = stone_field, prm
        self.name = _NAMES[prm.chooser]
        self.mpc = AlipMpc(prm.mpc)
        self._probe = AlipMpc(prm.mpc)
        self.probe_failures = 0
        self.cold_retries = 0
        self.rechoices = 0
        c = stone_field.centers
        self._nodes = np.vstack([c, np.asarray(stone_field.goal_center)[None]])
        self._goal = stone_field.goal
        self._adj = _adjacency(c, self._goal, prm)
        off = np.abs(stone_field.lateral_offset(c))
        self._node_cost = np.r_[prm.w_offset * np.maximum(off - prm.offset_free, 0.0) ** 2, 0.0]
        self._ctg = cost_to_go(self._adj, self._node_cost)
        b = prm.mpc.dcm_bounds
        self._viable = {s: (b.lower(s) + prm.viability_margin, b.upper(s) - prm.viability_margin) for s in (1, -1)}
        self.choices: list[StoneChoice] = []
        self._stance: np.ndarray | None = None
        self._regions: list[Stone] = []

    @property
    def rate_hz(self) -> float:
        """Re-planning rate [Hz] (the MPC's, paper B: 25 Hz)."""
        return self.mpc.rate_hz

    def reset(self) -> None:
        """Forget the run (choices, the MPC's warm start)."""
        self.mpc.reset()
        self.probe_failures = 0
        self.cold_retries = 0
        self.rechoices = 0
        self.choices = []
        self._stance = None
        self._regions = []

    # ---- the contract ----------------------------------------------------------------------------
    def plan(self, inp: PlannerInput) -> StepPlan:
        """The next foothold and duration: the stones are chosen at each touch-down, the MPC re-solves
        at every call. Raises NoFallbackPlanError when no stone is reachable or no way leads to the goal."""
        if not isinstance(inp, PlannerInput):
            raise InvalidInputError("inp", inp, "a lipmpcc.planners.base.PlannerInput")
        res = self.solve_step(inp)
        return to_step_plan(res, float(inp.stance_yaw), self.mpc.has_foot)

    def solve_step(self, inp: PlannerInput) -> AlipPlanResult:
        """:meth:`plan`'s answer as the ALIP-MPC's result (footholds, durations, CoP offset), for an adapter that
        wants it (the full-body source); ``inp`` needs ``stance_pos``, ``stance_side``, ``dcm``, ``t``,
        ``time_since_touchdown`` and ``step_index``."""
        p = np.asarray(inp.stance_pos, float)[:2]
        side0 = parse_side(inp.stance_side)
        t0 = time.perf_counter()
        if self._stance is None or float(np.max(np.abs(p - self._stance))) > 1e-9:
            self._choose(inp, p, side0)
            self._stance = p.copy()
        choice_time = time.perf_counter() - t0
        res = self.mpc.solve(inp.dcm, p, side0, inp.time_since_touchdown, self._regions)
        if not res.success and self.params.cold_retry:
            # paper B's relative stone boxes are centred on the previous plan's footholds, which a new choice
            # of stones leaves behind: a cold start (boxes on the stones' centres) may solve where the warm one
            # cannot; it then carries on as the planner's MPC
            retry = self._cold_solve(inp, p, side0, self._regions)
            if retry is None and self.params.chooser == "cost-to-go" and not self.field.in_goal(p):
                self._choose(inp, p, side0)  # the stones chosen at touch-down are out of reach now: choose again
                retry = self._cold_solve(inp, p, side0, self._regions)
                self.rechoices += 1
            if retry is not None:
                retry.plan_time += res.plan_time
                self.mpc, self._probe, res = self._probe, self.mpc, retry
                self.cold_retries += 1
        res.plan_time += choice_time
        return res

    # ---- the choice ------------------------------------------------------------------------------
    def _choose(self, inp: PlannerInput, p: np.ndarray, side0: int) -> None:
        t0 = time.perf_counter()
        n = self.field.n_stones
        if self.field.in_goal(p):
            nodes, cost = [n] * self.params.horizon_choice, 0.0
        else:
            reach = self._first_reachable(p, -side0)
            if not np.any(reach):
                raise NoFallbackPlanError(self.name, "no reachable stone", -1,
                                          f"step {inp.step_index}: no stone is reachable from the stance foot at "
                                          f"{np.round(p, 3).tolist()} m")
            chooser = self.params.chooser
            if chooser == "cost-to-go":
                nodes, cost = self._checked_dp(inp, p, side0, reach & self._dynamic_ok(inp, p, side0))
                if not nodes:
                    nodes, cost = self._dp(inp, p, side0, reach)  # none viable: the best the MPC may still save
                if not nodes:
                    raise NoFallbackPlanError(self.name, "no way to the goal", -1,
                                              f"step {inp.step_index}: no reachable stone from the stance foot at "
                                              f"{np.round(p, 3).tolist()} m leads to the goal")
            else:
                nodes, cost = self._chain(p, side0, reach, chooser), math.nan
                if not nodes:
                    raise NoFallbackPlanError(self.name, "no reachable stone", -1,
                                              f"step {inp.step_index}: no stone ahead is reachable from the stance "
                                              f"foot at {np.round(p, 3).tolist()} m")
        self._regions = self._regions_of(p, side0, nodes)
        waits = sum(1 for k in range(2, len(nodes)) if nodes[k] == nodes[k - 2] and nodes[k] != n)
        self.choices.append(StoneChoice(int(inp.step_index), float(inp.t), [int(x) for x in nodes], float(cost), waits,
                                        time.perf_counter() - t0))

    def _first_reachable(self, p: np.ndarray, s: int) -> np.ndarray:
        """The nodes the swing foot of side ``s`` can reach from the stance point ``p`` (planning limits)."""
        prm = self.params
        lo_box = p + np.array([-prm.step_x_max, prm.step_y_min if s > 0 else -prm.step_y_max])
        hi_box = p + np.array([prm.step_x_max, prm.step_y_max if s > 0 else -prm.step_y_min])
        sizes = np.vstack([self.field.sizes, np.asarray(self._goal.size)[None]])
        half = np.maximum(0.5 * sizes - prm.edge_margin, 0.0)
        lo, hi = self._nodes - half, self._nodes + half
        return np.all((hi >= lo_box) & (lo <= hi_box), axis=1)

    def _dynamic_ok(self, inp: PlannerInput, p: np.ndarray, side0: int) -> np.ndarray:
        """The nodes where the first foothold can land, for some duration in [max(t, T_min), T_max], with the
        next step's initial DCM viable (paper B eq. 6; the point foot's DCM flow)."""
        mp = self.params.mpc
        t = float(inp.time_since_touchdown)
        lo_v, hi_v = self._viable[side0]
        sizes = np.vstack([self.field.sizes, np.asarray(self._goal.size)[None]])
        half = 0.5 * sizes
        ok = np.zeros(len(self._nodes), bool)
        xi = np.asarray(inp.dcm, float)
        for T in np.linspace(max(t, mp.T_min), max(mp.T_max, t), 7):
            xi_T = p + (xi - p) * math.exp(mp.lam * (T - t))
            lo = np.maximum(self._nodes - half, xi_T - hi_v)
            hi = np.minimum(self._nodes + half, xi_T - lo_v)
            ok |= np.all(lo <= hi, axis=1)
        return ok

    def _pedestrian_cost(self, a: np.ndarray, b: np.ndarray, t_td: float) -> np.ndarray:
        """Missing clearance [m] (summed) of the step from stance points ``a`` (m, 2) to nodes ``b`` (n, 2)
        landing at ``t_td``: the foot on b over two steps, the COM near a, (a + b)/2 and b."""
        prm = self.params
        T = prm.mpc.T_nom
        out = np.zeros((len(a), len(b)))
        for ped in self.field.pedestrians:
            r = ped.axes[0]
            for dt in (0.0, T, 2 * T):
                out += np.maximum(r + prm.foot_radius + prm.margin - np.linalg.norm(b - ped.center(t_td + dt), axis=1), 0.0)[None]
            need = r + prm.robot_radius + prm.margin
            out += np.maximum(need - np.linalg.norm(a - ped.center(t_td - 0.5 * T), axis=1), 0.0)[:, None]
            mid = 0.5 * (a[:, None, :] + b[None, :, :])
            out += np.maximum(need - np.linalg.norm(mid - ped.center(t_td), axis=2), 0.0)
            out += np.maximum(need - np.linalg.norm(b - ped.center(t_td + 0.5 * T), axis=1), 0.0)[None]
        return out

    def _checked_dp(self, inp: PlannerInput, p: np.ndarray, side0: int, first: np.ndarray) -> tuple[list[int], float]:
        """The DP's choice, checked by a trial solve of the ALIP-MPC (cold start) on its first regions: when the
        trial fails, the choice's first two stones are barred, then its first stone, and the DP chooses again
        (at most ``probes`` trials; the first choice is kept when every trial fails)."""
        first = first.copy()
        barred: set[tuple[int, int]] = set()
        best: tuple[list[int], float] = ([], math.inf)
        for trial in range(self.params.probes):
            nodes, cost = self._dp(inp, p, side0, first, barred)
            if not nodes:
                break
            if not best[0]:
                best = (nodes, cost)
            if self.params.probes == 1 or self._probe_ok(inp, p, side0, nodes):
                return nodes, cost
            self.probe_failures += 1
            if (nodes[0], nodes[1]) not in barred:
                barred.add((nodes[0], nodes[1]))
            else:
                first[nodes[0]] = False
        return best

    def _probe_ok(self, inp: PlannerInput, p: np.ndarray, side0: int, nodes: list[int]) -> bool:
        """True when the ALIP-MPC (a cold-started copy) solves with these nodes as its regions."""
        return self._cold_solve(inp, p, side0, self._regions_of(p, side0, nodes)) is not None

    def _cold_solve(self, inp: PlannerInput, p: np.ndarray, side0: int, regions: list[Stone]) -> AlipPlanResult | None:
        """The second ALIP-MPC's solve from a cold start (None when it fails)."""
        self._probe.reset()
        try:
            res = self._probe.solve(inp.dcm, p, side0, inp.time_since_touchdown, regions)
        except NoFallbackPlanError:
            return None
        return res if res.success else None

    def _dp(self, inp: PlannerInput, p: np.ndarray, side0: int, first: np.ndarray,
            barred: set[tuple[int, int]] = frozenset()) -> tuple[list[int], float]:  # type: ignore[assignment]
        """The least-cost node sequence over ``horizon_choice`` steps ([] when every sequence costs inf); the
        ``barred`` pairs may not be its first two nodes."""
        prm = self.params
        K, T = prm.horizon_choice, prm.mpc.T_nom
        t1 = inp.t + max(T - float(inp.time_since_touchdown), 0.05)
        nodes, nc = self._nodes, self._node_cost
        dx = nodes[None, :, 0] - nodes[:, None, 0]
        step_len = prm.w_length * (dx - prm.L_nominal) ** 2  # [i, j]: a step of stone i to stone j
        with np.errstate(invalid="ignore"):
            V = np.where(first, 1.0 + nc + prm.w_length * (nodes[:, 0] - p[0] - prm.L_nominal) ** 2
                         + prm.w_collision * self._pedestrian_cost(p[None], nodes, t1)[0], np.inf)
        back = []
        s = -side0
        for k in range(1, K):
            s = -s
            C = 1.0 + nc[None, :] + step_len + prm.w_collision * self._pedestrian_cost(nodes, nodes, t1 + k * T)
            C[-1, -1] = 0.0  # on the goal: arrived
            tot = np.where(self._adj[s], V[:, None] + C, np.inf)
            if k == 1:
                for a, b in barred:
                    tot[a, b] = np.inf
            arg = np.argmin(tot, axis=0)
            back.append(arg)
            V = tot[arg, np.arange(len(nodes))]
        final = V + self._ctg[s] - 1e-3 * nodes[:, 0]
        j = int(np.argmin(final))
        if not np.isfinite(final[j]):
            return [], math.inf
        seq = [j]
        for arg in reversed(back):
            seq.append(int(arg[seq[-1]]))
        return seq[::-1], float(final[j])

    def _chain(self, p: np.ndarray, side0: int, reach: np.ndarray, chooser: str) -> list[int]:
        """The baselines' chains: the nearest reachable node ahead ("greedy"), or the one nearest a nominal
        step ("nominal"), step after step (shorter when a node has no successor)."""
        prm = self.params
        out: list[int] = []
        prev, ok, s = p, reach, -side0
        for _ in range(prm.mpc.horizon + 1):
            d = self._nodes - prev
            if chooser == "greedy":
                score = np.where(ok & (d[:, 0] > 0.05), np.linalg.norm(d, axis=1), np.inf)
            else:
                target = prev + np.array([prm.L_nominal, s * prm.mpc.w])
                score = np.where(ok, np.linalg.norm(self._nodes - target, axis=1), np.inf)
            j = int(np.argmin(score))
            if not np.isfinite(score[j]):
                break
            out.append(j)
            prev, s = self._nodes[j], -s
            ok = self._adj[s][j]
        return out

    def _regions_of(self, p: np.ndarray, side0: int, nodes: list[int]) -> list[Stone]:
        """The MPC's regions for the chosen nodes (the goal clipped to a nominal step from the region before)."""
        n = self.field.n_stones
        out: list[Stone] = []
        prev, s = p, -side0
        w = self.params.mpc.w
        for j in nodes:
            if j == n:
                g_lo, g_hi = self._goal.lower, self._goal.upper
                box_lo = prev + np.array([0.0, 0.6 * w if s > 0 else -1.4 * w])
                box_hi = prev + np.array([0.4, 1.4 * w if s > 0 else -0.6 * w])
                lo, hi = np.maximum(g_lo, box_lo), np.minimum(g_hi, box_hi)
                if np.any(lo >= hi):
                    lo, hi = g_lo, g_hi
                st = Stone(tuple(0.5 * (lo + hi)), tuple(hi - lo))  # type: ignore[arg-type]
            else:
                st = self.field.stone(j)
                if self.params.mpc.uses_cop:  # with a foot the centre of pressure must stay on the stone too
                    size = np.maximum(np.asarray(st.size) - 2.0 * np.asarray(self.params.mpc.cop_range), 0.01)
                    st = Stone(st.center, tuple(size))  # type: ignore[arg-type]
            out.append(st)
            prev, s = np.asarray(st.center), -s
        return out
