"""The stone choice as a mixed-integer program: one binary per (step, stone), big-M or hull rows.

Beyond both papers (issue 29; notebook 13). The footstep problem on a stone field, written the way
Deits & Tedrake and the OSU follow-up to paper B write it: each footstep ``k`` has a foothold
``u_k`` (2,) [m] and a binary ``z_kj`` per stone ``j``; the foot is on exactly one stone,

    sum_j z_kj = 1,    z_kj = 1  =>  |u_k - c_j| <= h_j          (c_j the centre, h_j the half size [m])

and consecutive footholds keep the planning limits (``|dx| <= step_x_max``, ``step_y_min <= s dy <=
step_y_max``, s the swing side). Two ways to write the implication as linear rows:

- **big-M** (:func:`one_stone_rows`): ``±(u - c_j) <= h_j + M (1 - z_j)``; a z_j of 0 relaxes the row by M.
  Few variables, a loose relaxation (fractional z_j spread over the stones);
- **hull** (:func:`hull_rows`): one copy v_j (2,) of the foothold per stone, ``u = sum_j v_j``,
  ``(c_j - h_j) z_j <= v_j <= (c_j + h_j) z_j``: the relaxation is the convex hull of the union of the
  stones, the tightest linear one.

:func:`footstep_milp` builds the program over K steps (cost: a linear cost per (step, stone), the last
step's cost-to-go); :func:`branch_and_bound` solves it with a plain best-first branch-and-bound on LP
relaxations (scipy's HiGHS ``linprog``) and keeps every node it explored, for the notebook's figures;
:func:`solve_milp` hands it to HiGHS's own MILP solver (``scipy.optimize.milp``).

:class:`MilpStoneFieldPlanner` is :class:`~lipmpcc.planners.stone_field.StoneFieldPlanner` with the
stone choice made by this program (on footholds anywhere in the stones, not on the stone graph's
centres) instead of the dynamic programme; the placement, the trial solves and the fallbacks are the
same. ``rows=`` takes another one-stone-per-foot function (notebook 13's exercise).
"""

from __future__ import annotations

import heapq
import math
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from scipy.optimize import Bounds, LinearConstraint, linprog, milp

from ..exceptions import InvalidInputError
from ..stone_field import StoneField
from .base import PlannerInput
from .stone_field import StoneFieldParams, StoneFieldPlanner

__all__ = ["one_stone_rows", "hull_rows", "FootstepMilp", "footstep_milp", "BnbNode", "BnbResult",
           "branch_and_bound", "relax", "solve_milp", "MilpStoneFieldPlanner", "OneStoneRows"]

#: a one-stone-per-foot function: (centers (m, 2), half_sizes (m, 2), big_m) -> (A, b), A @ [u, z] <= b
OneStoneRows = Callable[[np.ndarray, np.ndarray, float], tuple[np.ndarray, np.ndarray]]


def one_stone_rows(centers: np.ndarray, half_sizes: np.ndarray, big_m: float) -> tuple[np.ndarray, np.ndarray]:
    """The big-M rows of one footstep: ``A @ [u_x, u_y, z_1..z_m] <= b`` holds exactly when the binaries pick
    one stone and the foothold ``u`` [m] is on it.

    Rows 4j..4j+3: ``±(u - c_j) <= h_j + M (1 - z_j)`` (x then y, + then −); the last two: ``sum z <= 1`` and
    ``-sum z <= -1``. ``big_m`` [m] must exceed the largest distance of a reachable foothold from a stone."""
    c, h = np.asarray(centers, float), np.asarray(half_sizes, float)
    m = len(c)
    A = np.zeros((4 * m + 2, 2 + m))
    b = np.zeros(4 * m + 2)
    for j in range(m):
        for a in range(2):
            for sgn, r in ((1.0, 4 * j + 2 * a), (-1.0, 4 * j + 2 * a + 1)):
                A[r, a], A[r, 2 + j] = sgn, big_m
                b[r] = sgn * c[j, a] + h[j, a] + big_m
    A[-2, 2:], b[-2] = 1.0, 1.0
    A[-1, 2:], b[-1] = -1.0, -1.0
    return A, b


def hull_rows(centers: np.ndarray, half_sizes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The hull rows of one footstep over ``[u (2), z (m), v (2m)]``: ``A_ub x <= b_ub``, ``A_eq x = b_eq`` with
    ``(c_j - h_j) z_j <= v_j <= (c_j + h_j) z_j``, ``u = sum_j v_j`` and ``sum z = 1``."""
    c, h = np.asarray(centers, float), np.asarray(half_sizes, float)
    m = len(c)
    nv = 2 + 3 * m
    A = np.zeros((4 * m, nv))
    for j in range(m):
        for a in range(2):
            v = 2 + m + 2 * j + a
            A[4 * j + 2 * a, v], A[4 * j + 2 * a, 2 + j] = 1.0, -(c[j, a] + h[j, a])
            A[4 * j + 2 * a + 1, v], A[4 * j + 2 * a + 1, 2 + j] = -1.0, c[j, a] - h[j, a]
    E = np.zeros((3, nv))
    E[0, 0] = E[1, 1] = -1.0
    E[0, 2 + m::2] = 1.0
    E[1, 3 + m::2] = 1.0
    E[2, 2:2 + m] = 1.0
    return A, np.zeros(4 * m), E, np.array([0.0, 0.0, 1.0])


@dataclass
class FootstepMilp:
    """A footstep MILP: ``min c @ x`` s.t. ``A_ub x <= b_ub``, ``A_eq x = b_eq``, ``lb <= x <= ub``,
    ``x[integer]`` in {0, 1}. ``u_index[k]`` are the columns of step k's foothold, ``z_index[k]`` its
    binaries (one per ``candidates[k]`` node, in that order)."""

    c: np.ndarray
    A_ub: np.ndarray
    b_ub: np.ndarray
    A_eq: np.ndarray
    b_eq: np.ndarray
    lb: np.ndarray
    ub: np.ndarray
    integer: np.ndarray
    u_index: list[np.ndarray]
    z_index: list[np.ndarray]
    candidates: list[np.ndarray]
    formulation: str

    @property
    def n_binaries(self) -> int:
        """How many binaries the program has."""
        return int(np.sum(self.integer))

    def decode(self, x: np.ndarray) -> tuple[list[int], np.ndarray]:
        """(chosen node per step, footholds (K, 2) [m]) of a solution ``x``."""
        nodes = [int(cand[int(np.argmax(x[zi]))]) for cand, zi in zip(self.candidates, self.z_index)]
        return nodes, np.array([x[ui] for ui in self.u_index])


def _check_limits(limits: Sequence[float]) -> tuple[float, float, float]:
    if len(limits) != 3 or not all(math.isfinite(float(v)) for v in limits) or not 0 <= limits[1] < limits[2]:
        raise InvalidInputError("limits", tuple(limits), "(step_x_max, step_y_min, step_y_max) [m], 0 <= y_min < y_max")
    return float(limits[0]), float(limits[1]), float(limits[2])


def footstep_milp(
    centers: np.ndarray, half_sizes: np.ndarray, start: Sequence[float], first_side: int,
    costs: Sequence[np.ndarray], candidates: Sequence[np.ndarray], limits: Sequence[float] = (0.55, 0.12, 0.45),
    formulation: str = "big-m", rows: OneStoneRows = one_stone_rows, big_m: float | None = None,
    barred: Sequence[tuple[int, int]] = (),
) -> FootstepMilp:
    """The MILP of K footsteps from the stance point ``start`` [m].

    Args:
        centers, half_sizes: (n, 2) every node's rectangle [m].
        start: the stance foothold [m]; first_side: +1 when the first swing foot is the left one.
        costs: per step k, the cost of each of its ``candidates[k]`` nodes (the last step's includes its cost-to-go).
        candidates: per step k, the node indices it may land on (K = len(candidates) >= 1).
        limits: (step_x_max, step_y_min, step_y_max) [m] between consecutive footholds.
        formulation: "big-m" (``rows``, default :func:`one_stone_rows`) or "hull" (:func:`hull_rows`).
        big_m: the big-M constant [m] (None: the candidates' span plus a step).
        barred: (a, b) node pairs the first two steps may not take together.
    """
    if formulation not in ("big-m", "hull"):
        raise InvalidInputError("formulation", formulation, "'big-m' or 'hull'")
    if len(candidates) < 1 or len(costs) != len(candidates):
        raise InvalidInputError("costs", len(costs), f"one cost vector per step ({len(candidates)})")
    xm, ylo, yhi = _check_limits(limits)
    C, H = np.asarray(centers, float), np.asarray(half_sizes, float)
    p0 = np.asarray(start, float)[:2]
    cand = [np.asarray(cd, int) for cd in candidates]
    allc = np.concatenate(cand)
    lo_box = np.minimum((C[allc] - H[allc]).min(axis=0), p0) - 0.05
    hi_box = np.maximum((C[allc] + H[allc]).max(axis=0), p0) + 0.05
    M = float(np.max(hi_box - lo_box)) + 0.1 if big_m is None else float(big_m)
    blocks_ub, blocks_eq, cols, u_idx, z_idx, cost = [], [], 0, [], [], []
    for k, cd in enumerate(cand):
        m = len(cd)
        if formulation == "big-m":
            A, b = rows(C[cd], H[cd], M)
            A, b = np.asarray(A, float), np.asarray(b, float).ravel()
            if A.shape != (len(b), 2 + m):
                raise InvalidInputError("rows(...)", A.shape, f"(rows, {2 + m}) for {m} stones, with b of one entry per row")
            blocks_ub.append((cols, A, b))
            width = 2 + m
        else:
            A, b, E, e = hull_rows(C[cd], H[cd])
            blocks_ub.append((cols, A, b))
            blocks_eq.append((cols, E, e))
            width = 2 + 3 * m
        u_idx.append(cols + np.arange(2))
        z_idx.append(cols + 2 + np.arange(m))
        cost.append((cols, np.asarray(costs[k], float)))
        cols += width
    n = cols
    c = np.zeros(n)
    for at, cv in cost:
        c[at + 2:at + 2 + len(cv)] = cv
    rows_ub, rhs_ub = [], []
    for at, A, b in blocks_ub:
        R = np.zeros((len(b), n))
        R[:, at:at + A.shape[1]] = A
        rows_ub.append(R)
        rhs_ub.append(b)
    s = first_side
    for k in range(len(cand)):  # the planning limits between consecutive footholds
        R = np.zeros((4, n))
        R[0, u_idx[k][0]], R[1, u_idx[k][0]] = 1.0, -1.0
        R[2, u_idx[k][1]], R[3, u_idx[k][1]] = s, -s
        prev = p0 if k == 0 else None
        if k > 0:
            R[0, u_idx[k - 1][0]], R[1, u_idx[k - 1][0]] = -1.0, 1.0
            R[2, u_idx[k - 1][1]], R[3, u_idx[k - 1][1]] = -s, s
        off = np.zeros(4) if prev is None else np.array([prev[0], -prev[0], s * prev[1], -s * prev[1]])
        rows_ub.append(R)
        rhs_ub.append(np.array([xm, xm, yhi, -ylo]) + off)
        s = -s
    for a, bb in barred:
        if len(cand) > 1 and a in cand[0] and bb in cand[1]:
            R = np.zeros((1, n))
            R[0, z_idx[0][list(cand[0]).index(a)]] = R[0, z_idx[1][list(cand[1]).index(bb)]] = 1.0
            rows_ub.append(R)
            rhs_ub.append(np.array([1.0]))
    A_eq, b_eq = np.zeros((0, n)), np.zeros(0)
    if blocks_eq:
        A_eq = np.vstack([np.pad(E, ((0, 0), (at, n - at - E.shape[1]))) for at, E, _ in blocks_eq])
        b_eq = np.concatenate([e for _, _, e in blocks_eq])
    lb, ub = np.full(n, -np.inf), np.full(n, np.inf)
    integer = np.zeros(n, bool)
    for k, zi in enumerate(z_idx):
        lb[u_idx[k]], ub[u_idx[k]] = lo_box, hi_box
        lb[zi], ub[zi], integer[zi] = 0.0, 1.0, True
        if formulation == "hull":  # the copies v_j live in the box too
            vi = np.arange(zi[-1] + 1, zi[-1] + 1 + 2 * len(zi))
            lb[vi], ub[vi] = np.tile(np.minimum(lo_box, 0.0), len(zi)), np.tile(np.maximum(hi_box, 0.0), len(zi))
    return FootstepMilp(c, np.vstack(rows_ub), np.concatenate(rhs_ub), A_eq, b_eq, lb, ub, integer, u_idx, z_idx,
                        cand, formulation)


@dataclass
class BnbNode:
    """A node of the branch-and-bound: its LP relaxation's ``bound`` (inf: infeasible), its ``depth``, the
    binaries it fixed (column -> 0/1), its ``parent`` (-1 for the root) and what became of it: "branched",
    "pruned" (bound no better than the incumbent), "infeasible" or "integral" (a new incumbent or not)."""

    id: int
    parent: int
    depth: int
    bound: float
    fixed: dict[int, int]
    status: str = ""
    fractional: int = 0


@dataclass
class BnbResult:
    """What :func:`branch_and_bound` found: the best ``x`` (None: infeasible) and its ``cost``, every node
    explored, the root relaxation's bound and the wall time [s]."""

    x: np.ndarray | None
    cost: float
    nodes: list[BnbNode] = field(default_factory=list)
    root_bound: float = math.nan
    seconds: float = 0.0

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)


def relax(prob: FootstepMilp, lb: np.ndarray | None = None, ub: np.ndarray | None = None) -> tuple[float, np.ndarray | None]:
    """The LP relaxation of ``prob`` (binaries in [0, 1]; ``lb``/``ub`` replace its bounds): (cost, x), (inf, None)
    when infeasible."""
    lb = prob.lb if lb is None else lb
    ub = prob.ub if ub is None else ub
    res = linprog(prob.c, A_ub=prob.A_ub, b_ub=prob.b_ub, A_eq=prob.A_eq if len(prob.b_eq) else None,
                  b_eq=prob.b_eq if len(prob.b_eq) else None, bounds=list(zip(lb, ub)), method="highs")
    return (float(res.fun), res.x) if res.status == 0 else (math.inf, None)


def branch_and_bound(prob: FootstepMilp, max_nodes: int = 5000, tol: float = 1e-6) -> BnbResult:
    """Best-first branch-and-bound on LP relaxations: at each node solve the relaxation with the node's binaries
    fixed; prune it when infeasible or no better than the incumbent; keep an integral solution; else branch on
    the most fractional binary (z = 1 first). Stops after ``max_nodes`` nodes (the incumbent then stands)."""
    t0 = time.perf_counter()
    zcols = np.flatnonzero(prob.integer)
    out = BnbResult(None, math.inf)
    heap: list[tuple[float, int]] = []
    pending: dict[int, BnbNode] = {}

    def visit(parent: int, depth: int, fixed: dict[int, int]) -> None:
        lb, ub = prob.lb.copy(), prob.ub.copy()
        for col, v in fixed.items():
            lb[col] = ub[col] = v
        bound, x = relax(prob, lb, ub)
        node = BnbNode(len(out.nodes), parent, depth, bound, dict(fixed))
        out.nodes.append(node)
        if x is None:
            node.status = "infeasible"
            return
        frac = np.abs(x[zcols] - np.round(x[zcols]))
        node.fractional = int(np.sum(frac > tol))
        if bound >= out.cost - tol:
            node.status = "pruned"
        elif node.fractional == 0:
            node.status = "integral"
            out.x, out.cost = x, bound
        else:
            pending[node.id] = node
            node._x = x  # type: ignore[attr-defined]
            heapq.heappush(heap, (bound, node.id))

    visit(-1, 0, {})
    out.root_bound = out.nodes[0].bound
    while heap and len(out.nodes) < max_nodes:
        bound, nid = heapq.heappop(heap)
        node = pending.pop(nid)
        if bound >= out.cost - tol:
            node.status = "pruned"
            continue
        node.status = "branched"
        x = node._x  # type: ignore[attr-defined]
        col = int(zcols[int(np.argmax(np.abs(x[zcols] - np.round(x[zcols]))))])
        for v in (1, 0):
            visit(node.id, node.depth + 1, {**node.fixed, col: v})
    for node in pending.values():
        node.status = node.status or "open"
    out.seconds = time.perf_counter() - t0
    return out


def solve_milp(prob: FootstepMilp, time_limit: float = 1.0) -> tuple[np.ndarray | None, float, int]:
    """HiGHS's MILP solver (``scipy.optimize.milp``): (x or None, cost, branch-and-bound nodes)."""
    cons = [LinearConstraint(prob.A_ub, -np.inf, prob.b_ub)]
    if len(prob.b_eq):
        cons.append(LinearConstraint(prob.A_eq, prob.b_eq, prob.b_eq))
    res = milp(prob.c, constraints=cons, integrality=prob.integer.astype(int), bounds=Bounds(prob.lb, prob.ub),
               options={"time_limit": time_limit})
    nodes = int(getattr(res, "mip_node_count", 0) or 0)
    if res.x is None or res.status not in (0, 1):
        return None, math.inf, nodes
    return np.asarray(res.x), float(res.fun), nodes


class MilpStoneFieldPlanner(StoneFieldPlanner):
    """:class:`~lipmpcc.planners.stone_field.StoneFieldPlanner` whose stone choice is the MILP of
    :func:`footstep_milp` (big-M rows from ``rows``), solved by HiGHS, over ``params.horizon_choice`` steps: each
    (step, node) costs what the dynamic programme's step onto it costs (1, the path offset, the pedestrian's
    missing clearance at its predicted time, the goal 0), the last step adds the cost-to-go. The footholds are
    anywhere in the stones shrunk by ``edge_margin`` (and the CoP box with a foot), within the planning limits of the previous foothold.

    Attributes: ``milp_times`` [s] and ``milp_nodes`` (HiGHS's branch-and-bound nodes), one per MILP solved."""

    def __init__(self, stone_field: StoneField, params: StoneFieldParams | None = None,
                 rows: OneStoneRows = one_stone_rows) -> None:
        super().__init__(stone_field, params)
        if not callable(rows):
            raise InvalidInputError("rows", rows, "a function (centers, half_sizes, big_m) -> (A, b)")
        self.rows = rows
        self.name = "stone-field-milp"
        sizes = np.vstack([stone_field.sizes, np.asarray(self._goal.size)[None]])
        shrink = self.params.edge_margin + (np.asarray(self.params.mpc.cop_range) if self.params.mpc.uses_cop else 0.0)
        self._half = np.maximum(0.5 * sizes - shrink, 0.005)  # as the placement's regions (the CoP box on the stone)
        self.milp_times: list[float] = []
        self.milp_nodes: list[int] = []

    def problem(self, p: Sequence[float], side0: int, t1: float = 0.0, first: np.ndarray | None = None,
                barred: Sequence[tuple[int, int]] = (), formulation: str = "big-m", horizon: int | None = None
                ) -> FootstepMilp | None:
        """The MILP of the next ``horizon`` steps (default ``params.horizon_choice``) from the stance point ``p`` [m]
        of side ``side0`` (+1 left), the first touch-down at ``t1`` [s] (the pedestrians' clock); ``first``: the
        nodes the first step may take (None: all). None when a step has no candidate."""
        prm = self.params
        K, T = (prm.horizon_choice if horizon is None else int(horizon)), prm.mpc.T_nom
        p = np.asarray(p, float)[:2]
        nodes, n = self._nodes, self.field.n_stones
        x = nodes[:, 0]
        cands, costs, s = [], [], -side0
        for k in range(K):
            ok = (x >= p[0] - prm.step_x_max) & (x <= p[0] + (k + 1) * prm.step_x_max + 0.3)
            ok = ok & first if (k == 0 and first is not None) else ok
            cd = np.flatnonzero(ok)
            ped = np.diag(self._pedestrian_cost(nodes[cd], nodes[cd], t1 + k * T)) if self.field.pedestrians else 0.0
            cost = np.where(cd == n, 0.0, 1.0 + self._node_cost[cd] + prm.w_collision * ped)
            if k == K - 1:
                cost = cost + self._ctg[s][cd] - 1e-3 * x[cd]
            keep = np.isfinite(cost)
            if not np.any(keep):
                return None
            cands.append(cd[keep])
            costs.append(cost[keep])
            s = -s
        return footstep_milp(nodes, self._half, p, -side0, costs, cands, (prm.step_x_max, prm.step_y_min, prm.step_y_max),
                             formulation=formulation, rows=self.rows, barred=list(barred))

    def _dp(self, inp: PlannerInput, p: np.ndarray, side0: int, first: np.ndarray,
            barred: set[tuple[int, int]] = frozenset()) -> tuple[list[int], float]:  # type: ignore[assignment]
        """The MILP's choice (same signature as the DP's): [] and inf when it is infeasible."""
        T = self.params.mpc.T_nom
        t1 = inp.t + max(T - float(inp.time_since_touchdown), 0.05)
        t0 = time.perf_counter()
        prob = self.problem(p, side0, t1, first, list(barred))
        if prob is None:
            return [], math.inf
        sol, cost, n_nodes = solve_milp(prob)
        self.milp_times.append(time.perf_counter() - t0)
        self.milp_nodes.append(n_nodes)
        if sol is None:
            return [], math.inf
        return prob.decode(sol)[0], cost
