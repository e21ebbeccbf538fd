"""Benchmark: ALIP-MPC (CasADi sqpmethod + qrqp) against the same NLP solved by IPOPT,
in the same closed-loop runs, and ALIP-QP (ProxQP) time per call; then the same comparison for the
ALIP-MPC with a foot (``cop_range``: the centre of pressure as a decision variable) on paper B's push test.

At every 25 Hz planner call of an ALIP-MPC run, the identical problem (same parameter
vector, bounds and warm-start point) is also handed to IPOPT; both are timed and their
first-step decisions compared.

    PYTHONPATH=python python3 benchmarks/bench_alip.py [--cases II:0 III:1 IV:2] [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from lipmpcc.loops.alip import AlipLoopConfig, loop_metrics, run_alip_loop
from lipmpcc.metrics import timing_stats_ms
from lipmpcc.models.alip import parse_side
from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams, _BufferedNlp, _solver
from lipmpcc.planners.base import PlannerInput, StepPlan
from lipmpcc.studies.stepping_stones import paper_pushes, push_stones, run_case
from lipmpcc.terrain import approach_footholds, make_profile


class _Twin:
    """Wraps the SQP planner (a planner of the contract): each call also solves the same NLP with IPOPT."""

    name = "alip-mpc+ipopt"

    def __init__(self, params: AlipMpcParams | None = None) -> None:
        self.mpc = AlipMpc(params, solver="sqp")
        # called as the SQP is (a CasADi FunctionBuffer, no DM conversions)
        self.ipopt = _BufferedNlp(_solver(replace(self.mpc.params, solver="ipopt"), "ipopt"))
        self.t_ipopt: list[float] = []
        self.du: list[float] = []
        self.dT: list[float] = []
        self.ipopt_fail = 0
        self.both_ok = 0

    # the planner contract
    @property
    def rate_hz(self) -> float:
        return self.mpc.rate_hz

    @property
    def params(self) -> AlipMpcParams:
        return self.mpc.params

    def reset(self) -> None:
        self.mpc.reset()

    def plan(self, inp: PlannerInput) -> StepPlan:
        stance = np.asarray(inp.stance_pos, float)[:2]
        data = self.mpc.problem_data(inp.dcm, stance, inp.stance_side, inp.time_since_touchdown, inp.course)
        new_step = self.mpc._is_new_step(stance, parse_side(inp.stance_side))
        x0, lx0, lg0 = self.mpc._warm_start(data, new_step)
        t0 = time.perf_counter()
        sol = self.ipopt(data, x0, lx0, lg0)  # same warm start and call path as the SQP
        self.t_ipopt.append(time.perf_counter() - t0)
        ok_i = bool(self.ipopt.stats()["success"])
        plan = self.mpc.plan(inp)
        res = plan.record
        if not ok_i:
            self.ipopt_fail += 1
        elif res.success:
            x = np.asarray(sol["x"], float).ravel()
            T1 = float(np.log(x[0]) / self.mpc.params.lam)
            self.du.append(float(np.max(np.abs(data["stance"] + x[1:3] - res.next_foothold))))
            self.dT.append(abs(T1 - res.step_duration))
            self.both_ok += 1
        return plan


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", default=["II:0", "III:1", "IV:2"], help="PROFILE:SEED")
    ap.add_argument("--json", help="write the figures to this file")
    args = ap.parse_args()

    sqp_solve, sqp_plan, ipopt = [], [], []
    sqp_td, ipopt_td = [], []
    du, dT = [], []
    fails = {"sqp": 0, "ipopt": 0}
    n_both = 0
    qp_solve, qp_plan = [], []
    for c in args.cases:
        prof, seed = c.split(":")
        stones = make_profile(prof, int(seed))
        twin = _Twin()
        log = run_alip_loop(twin, approach_footholds() + stones)
        td = log.plan_t_step == 0.0  # first call after a touch-down: the problem changed
        sqp_td += list(log.solve_time[td])
        ipopt_td += list(np.asarray(twin.t_ipopt)[td])
        m = loop_metrics(log)
        sqp_solve += list(log.solve_time)
        sqp_plan += list(log.plan_time)
        ipopt += twin.t_ipopt
        du += twin.du
        dT += twin.dT
        fails["sqp"] += m["solver_failures"]
        fails["ipopt"] += twin.ipopt_fail
        n_both += twin.both_ok
        qlog, _ = run_case("alip-qp", stones)
        qp_solve += list(qlog.solve_time)
        qp_plan += list(qlog.plan_time)
        print(f"case {c}: {len(log.plan_t)} planner calls, fell={m['fell']}")

    s, p, i = timing_stats_ms(sqp_solve), timing_stats_ms(sqp_plan), timing_stats_ms(ipopt)
    std, itd = timing_stats_ms(sqp_td), timing_stats_ms(ipopt_td)
    qs, qpp = timing_stats_ms(qp_solve), timing_stats_ms(qp_plan)
    out = {
        "alip_mpc_sqp_solve_ms": s,
        "alip_mpc_sqp_plan_ms": p,
        "alip_mpc_ipopt_solve_ms": i,
        "ratio_median_ipopt_over_sqp": i["median"] / s["median"],
        "ratio_p90_ipopt_over_sqp": i["p90"] / s["p90"],
        "max_foothold_diff_m": max(du) if du else float("nan"),
        "max_duration_diff_s": max(dT) if dT else float("nan"),
        "calls_compared": n_both,
        "failures": fails,
        "at_touchdown": {"sqp_solve_ms": std, "ipopt_solve_ms": itd, "ratio_median": itd["median"] / std["median"]},
        "alip_qp_solve_ms": qs,
        "alip_qp_plan_ms": qpp,
    }
    print()
    print(f"{'':28s} {'median':>8s} {'p90':>8s} {'max':>8s} [ms]  n")
    for name, st in (
        ("ALIP-MPC sqp (solver call)", s),
        ("ALIP-MPC sqp (plan() total)", p),
        ("ALIP-MPC IPOPT (solver call)", i),
        ("  sqp, first call of a step", std),
        ("  IPOPT, first call of a step", itd),
        ("ALIP-QP ProxQP (solve)", qs),
        ("ALIP-QP (plan() total)", qpp),
    ):
        print(f"{name:28s} {st['median']:8.3f} {st['p90']:8.3f} {st['max']:8.3f}       {st['n']}")
    print(
        f"IPOPT / SQP: median x{out['ratio_median_ipopt_over_sqp']:.1f}, p90 x{out['ratio_p90_ipopt_over_sqp']:.1f}; "
        f"first call of a step (new problem, shifted warm start): median x{out['at_touchdown']['ratio_median']:.1f}"
    )
    print(
        f"same problem, both converged ({n_both} calls): max |foothold diff| = {out['max_foothold_diff_m']:.2e} m, "
        f"max |duration diff| = {out['max_duration_diff_s']:.2e} s; failures sqp={fails['sqp']} ipopt={fails['ipopt']}"
    )
    print("paper B: IPOPT, 30-50 ms per solve")

    # the ALIP-MPC with a foot (digit_like's sole: +-6 cm x +-2.5 cm), paper B's push test
    foot = _Twin(AlipMpcParams.paper(cop_range=(0.06, 0.025)))
    flog = run_alip_loop(foot, approach_footholds() + push_stones(), config=AlipLoopConfig(pushes=paper_pushes()))
    fm = loop_metrics(flog)
    fs, fi = timing_stats_ms(list(flog.solve_time)), timing_stats_ms(foot.t_ipopt)
    out["foot_push_test"] = {
        "fell": fm["fell"], "sqp_solve_ms": fs, "ipopt_solve_ms": fi, "ratio_median": fi["median"] / fs["median"],
        "max_foothold_diff_m": max(foot.du) if foot.du else float("nan"), "failures": {"sqp": fm["solver_failures"], "ipopt": foot.ipopt_fail},
    }
    print()
    print(f"ALIP-MPC with a foot, push test ({len(flog.plan_t)} calls, fell={fm['fell']}):")
    for name, st in (("  sqp (solver call)", fs), ("  IPOPT (solver call)", fi)):
        print(f"{name:28s} {st['median']:8.3f} {st['p90']:8.3f} {st['max']:8.3f}       {st['n']}")
    print(f"  IPOPT / SQP: median x{out['foot_push_test']['ratio_median']:.1f}; max |foothold diff| = "
          f"{out['foot_push_test']['max_foothold_diff_m']:.2e} m; failures sqp={fm['solver_failures']} ipopt={foot.ipopt_fail}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
