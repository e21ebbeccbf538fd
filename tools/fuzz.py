"""Run the issue-14 fuzz (tests/fuzz) and print the tally of outcomes by class and category.

    PYTHONPATH=python python3 tools/fuzz.py                 # every case
    PYTHONPATH=python python3 tools/fuzz.py --only cache    # cases whose id or category starts with 'cache'
    PYTHONPATH=python python3 tools/fuzz.py --json out.json # also write every outcome

Exit 0 when every case is "ok", 1 otherwise. Classes: see tests/fuzz/harness.py.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter, defaultdict
from dataclasses import asdict
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(1, str(REPO / "python"))

from tests.fuzz import CLASSES, all_cases, run_case  # noqa: E402


def _table(outcomes: list) -> str:
    cats: dict[str, Counter] = defaultdict(Counter)
    for o in outcomes:
        cats[o.category][o.cls] += 1
    head = f"{'category':<16}" + "".join(f"{c:>10}" for c in CLASSES) + f"{'total':>8}"
    lines = [head, "-" * len(head)]
    total: Counter = Counter()
    for cat, cnt in cats.items():
        total.update(cnt)
        lines.append(f"{cat:<16}" + "".join(f"{cnt.get(c, 0):>10}" for c in CLASSES) + f"{sum(cnt.values()):>8}")
    lines.append("-" * len(head))
    lines.append(f"{'all':<16}" + "".join(f"{total.get(c, 0):>10}" for c in CLASSES) + f"{sum(total.values()):>8}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="run the cases whose id or category starts with this")
    ap.add_argument("--json", help="write every outcome to this JSON file")
    ap.add_argument("--quiet", action="store_true", help="print only the failures and the table")
    ns = ap.parse_args(argv)
    cases = [c for c in all_cases() if not ns.only or c.id.startswith(ns.only) or c.category.startswith(ns.only)]
    t0 = time.perf_counter()
    outcomes = []
    for case in cases:
        o = run_case(case)
        outcomes.append(o)
        if not ns.quiet or o.cls != "ok":
            q = "  [?]" if o.question else ""
            print(f"{o.cls:<9} {o.seconds:6.1f}s  {o.category:<15} {o.case_id}: {o.detail}{q}", flush=True)
    wall = time.perf_counter() - t0
    print()
    print(_table(outcomes))
    print(f"\n{len(outcomes)} cases in {wall:.0f} s; {sum(o.cls == 'ok' for o in outcomes)} ok")
    if ns.json:
        Path(ns.json).write_text(json.dumps([asdict(o) for o in outcomes], indent=1))
    return 0 if all(o.cls == "ok" for o in outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
