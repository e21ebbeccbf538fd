"""Bit-check: run every study of ``lipmpcc reproduce --fast`` (plus a short Digit v3 walk when the
model is beside the repository) and print one SHA-256 per study over its ``summary.json`` with the
wall-clock fields removed, and one over all of them.

Two commits give the same hashes exactly when every deterministic summary number is equal to the
bit (floats are hashed by their ``repr``, i.e. all 17 significant digits). Used to show that a
refactoring changes no result::

    python tools/bitcheck.py --out /tmp/bc_new > new.txt   # then diff against the old commit's
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import subprocess
import sys
from pathlib import Path

#: summary keys that measure the machine, not the run
_TIMING = re.compile(r"(_ms$|wall|real_time_factor|solve_time|elapsed)")


def _strip(obj):
    if isinstance(obj, dict):
        return {k: _strip(v) for k, v in obj.items() if not _TIMING.search(str(k))}
    if isinstance(obj, list):
        return [_strip(v) for v in obj]
    return obj


def digest(summary_path: Path) -> str:
    data = _strip(json.loads(summary_path.read_text()))
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="/tmp/lipmpcc_bitcheck")
    ap.add_argument("--only", default=None, help="reproduce --only PREFIX")
    ap.add_argument("--no-run", action="store_true", help="hash an existing --out")
    ns = ap.parse_args()
    out = Path(ns.out)
    if not ns.no_run:
        cmd = [sys.executable, "-m", "lipmpcc", "reproduce", "--fast", "--out", str(out / "reproduce")]
        if ns.only:
            cmd += ["--only", ns.only]
        rc = subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode
        if rc not in (0, 1):  # 1: a study missed its criterion (hashed all the same)
            raise SystemExit(f"bitcheck: lipmpcc reproduce exited {rc}")
        v3 = Path(__file__).resolve().parents[2] / "shared" / "models" / "digit-v3" / "digit-v3.xml"
        if v3.is_file() and not ns.only:
            subprocess.run([sys.executable, "-m", "lipmpcc", "run", "walk", "--robot", str(v3), "--duration", "3",
                            "--out", str(out / "digit-v3-walk"), "--replace"], check=False, stdout=subprocess.DEVNULL)
    total = hashlib.sha256()
    for s in sorted(out.rglob("summary.json")):
        h = digest(s)
        total.update(h.encode())
        print(f"{h[:16]}  {s.parent.relative_to(out)}")
    print(f"{total.hexdigest()[:16]}  ALL")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
