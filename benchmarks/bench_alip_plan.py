"""Benchmark: the ALIP planners' ``plan()`` against their solver call, on recorded planner calls.

One closed-loop run per case (ALIP loop, approach + the profile's stones) records every
:class:`~lipmpcc.planners.base.PlannerInput` the loop hands the planner under test; the inputs are then
replayed ``--rounds`` times into a freshly reset planner (the same calls in the same order, hence the
same warm starts and the same plans: the replay checks every foothold and duration bit for bit against
the recording). Per call it times

- ``input``: building the ``PlannerInput`` from its fields (the loop does it every call; its checks);
- ``plan()``: the planner contract's call, ``planner.plan(inp) -> StepPlan``, wall time;
- ``solver``: the solver call inside it (``StepPlan.solve_time``: CasADi's packed ``sqpmethod`` for the
  ALIP-MPC, ProxQP's ``init`` + ``solve`` for the ALIP-QP);

and prints the medians and ``plan() / solver``, the overhead the planner adds around its solver. Each
worker prints a SHA-256 of every recorded foothold and duration (``repr``, all digits): equal digests
mean the two trees planned the same runs to the bit.

``--against DIR`` compares with another checkout's code in the same run: two worker processes (this
tree's ``python/`` and ``DIR``'s, e.g. a ``git worktree`` of the previous commit) replay alternately,
round by round, so both see the same machine load; the table shows both side by side::

    git worktree add /tmp/lipmpcc-prev HEAD~1
    PYTHONPATH=python python benchmarks/bench_alip_plan.py --against /tmp/lipmpcc-prev --rounds 9

The script uses only public APIs (``AlipMpc``, ``AlipQp``, ``run_alip_loop``, ``PlannerInput``), so the
other checkout needs nothing from this one. On a loaded machine, read the medians; compare figures of
one run only.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

PLANNERS = ("alip-mpc", "alip-mpc-foot", "alip-qp")


def _make(name: str):
    from lipmpcc.planners.alip_mpc import AlipMpc, AlipMpcParams
    from lipmpcc.planners.alip_qp import AlipQp

    if name == "alip-mpc":
        return AlipMpc()
    if name == "alip-mpc-foot":
        return AlipMpc(AlipMpcParams.paper(cop_range=(0.06, 0.025)))
    return AlipQp()


class _Recorder:
    """A planner of the contract that records every input it is given."""

    def __init__(self, planner) -> None:
        self.planner = planner
        self.name = planner.name
        self.inputs: list = []
        self.plans: list[tuple[tuple[float, ...], float]] = []

    @property
    def rate_hz(self) -> float:
        return self.planner.rate_hz

    def reset(self) -> None:
        self.planner.reset()

    def plan(self, inp):
        self.inputs.append(inp)
        plan = self.planner.plan(inp)
        self.plans.append((tuple(float(v) for v in plan.foothold), float(plan.duration)))
        return plan


def record(cases: list[str]) -> dict[str, list]:
    """Per planner: the (PlannerInput, (foothold, duration)) of every call of one run per case."""
    from lipmpcc.loops.alip import run_alip_loop
    from lipmpcc.terrain import approach_footholds, make_profile

    out: dict[str, list] = {}
    for name in PLANNERS:
        calls = []
        for c in cases:
            prof, seed = c.split(":")
            rec = _Recorder(_make(name))
            run_alip_loop(rec, approach_footholds() + make_profile(prof, int(seed)), progress=False)
            calls.append(list(zip(rec.inputs, rec.plans)))
        out[name] = calls
    return out


def replay(planners: dict[str, object], recorded: dict[str, list]) -> dict[str, dict[str, list[float]]]:
    """One round: every recorded run replayed into its reset planner; per-call times [s]."""
    from lipmpcc.planners.base import PlannerInput

    fields = [f.name for f in dataclasses.fields(PlannerInput)]
    perf = time.perf_counter
    out = {}
    for name, runs in recorded.items():
        planner = planners[name]
        t_in, t_plan, t_solve = [], [], []
        for calls in runs:
            planner.reset()
            for inp, (foot, dur) in calls:
                kw = {f: getattr(inp, f) for f in fields}
                t0 = perf()
                inp2 = PlannerInput(**kw)
                t1 = perf()
                plan = planner.plan(inp2)
                t2 = perf()
                if tuple(float(v) for v in plan.foothold) != foot or float(plan.duration) != dur:
                    raise SystemExit(f"{name}: the replay's plan differs from the recorded one")
                t_in.append(t1 - t0)
                t_plan.append(t2 - t1)
                t_solve.append(float(plan.solve_time))
        out[name] = {"input": t_in, "plan": t_plan, "solver": t_solve}
    return out


def worker(cases: list[str]) -> None:
    """Record, then answer each line on stdin with one replay round as a JSON line."""
    recorded = record(cases)
    planners = {name: _make(name) for name in recorded}
    replay(planners, recorded)  # warm-up round
    plans = [(foot, dur) for runs in recorded.values() for calls in runs for _, (foot, dur) in calls]
    digest = hashlib.sha256(repr(plans).encode()).hexdigest()[:16]
    print(json.dumps({"ready": {k: sum(len(c) for c in v) for k, v in recorded.items()}, "plans": digest}), flush=True)
    for line in sys.stdin:
        if line.strip() != "round":
            break
        print(json.dumps(replay(planners, recorded)), flush=True)


def _spawn(python_dir: Path, here: Path, cases: list[str]) -> subprocess.Popen:
    """A worker importing ``lipmpcc`` from ``python_dir`` (PYTHONPATH's other entries kept, ``here`` dropped)."""
    env = dict(os.environ)
    rest = [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p and Path(p).resolve() != here]
    env["PYTHONPATH"] = os.pathsep.join(rest + [str(python_dir)])
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", "--cases", *cases]
    return subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env)


def _ask(p: subprocess.Popen) -> dict:
    p.stdin.write("round\n")
    p.stdin.flush()
    return json.loads(p.stdout.readline())


def _med_us(x: list[float]) -> float:
    return 1e6 * statistics.median(x)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", default=["I:0", "III:1"], help="PROFILE:SEED")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--against", help="another checkout (its python/ is imported by the second worker)")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--json", help="write the per-round medians to this file")
    args = ap.parse_args()
    if args.worker:
        worker(args.cases)
        return
    here = Path(__file__).resolve().parents[1] / "python"
    trees = {"this": here}
    if args.against:
        trees["other"] = Path(args.against).resolve() / "python"
    procs = {k: _spawn(d, here, args.cases) for k, d in trees.items()}
    digests = {}
    for k, p in procs.items():
        msg = json.loads(p.stdout.readline())
        digests[k] = msg["plans"]
        print(f"{k}: {trees[k]} ({', '.join(f'{n} {c} calls' for n, c in msg['ready'].items())}; "
              f"plans' SHA-256 {msg['plans']})")
    if len(set(digests.values())) > 1:
        print("the trees' plans DIFFER (footholds or durations of the recorded runs)")
    # per tree, planner, kind: one median per round (rounds alternate between the trees)
    med: dict = {k: {} for k in trees}
    order = list(trees)
    for r in range(args.rounds):
        for k in (order if r % 2 == 0 else order[::-1]):
            res = _ask(procs[k])
            for name, kinds in res.items():
                for kind, xs in kinds.items():
                    med[k].setdefault(name, {}).setdefault(kind, []).append(_med_us(xs))
    for p in procs.values():
        p.stdin.write("stop\n")
        p.stdin.close()
        p.wait()
    print(f"\nmedian over {args.rounds} rounds of the per-round median per call [µs] (cases {' '.join(args.cases)})")
    head = f"{'planner':15s}" + "".join(f" {k + ' ' + c:>17s}" for k in trees for c in ("input", "plan()", "solver", "plan/solver"))
    print(head)
    summary = {}
    for name in PLANNERS:
        row = f"{name:15s}"
        for k in trees:
            m = {kind: statistics.median(v) for kind, v in med[k][name].items()}
            summary.setdefault(k, {})[name] = m
            row += f" {m['input']:17.1f} {m['plan']:17.1f} {m['solver']:17.1f} {m['plan'] / m['solver']:17.2f}"
        print(row)
    if "other" in trees:
        print("\nplan() this / other: " + ", ".join(
            f"{n} {summary['this'][n]['plan'] / summary['other'][n]['plan']:.2f}" for n in PLANNERS))
    if args.json:
        Path(args.json).write_text(json.dumps({"rounds": med, "median": summary}, indent=2))


if __name__ == "__main__":
    main()
