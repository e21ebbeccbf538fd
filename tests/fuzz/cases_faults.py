"""Fuzz cases of faults, in subprocesses: a damaged compiled-code cache (``LIPMPCC_CACHE_DIR``), one
controller or planner used from two threads, Ctrl-C (SIGINT) during ``run`` and ``reproduce``, two runs
into one folder at once, and ``reproduce`` whose studies all fail."""

from __future__ import annotations

import atexit
import functools
import json
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable

from .cases_cli import _stones_rows
from .harness import RC_ERROR, RC_OK, Case, Ran, proc_env

# ---- the compiled-code cache ------------------------------------------------------------------------
CACHE_RUN = ["run", "circle", "--robot", "lip", "--steps", "2", "--out", "{tmp}/out"]


@functools.cache
def seeded_cache() -> Path:
    """A cache folder filled by one short LIP run (built once per process)."""
    base = Path(tempfile.mkdtemp(prefix="fuzz_cache_seed_"))
    atexit.register(shutil.rmtree, base, True)
    env = proc_env({"LIPMPCC_CACHE_DIR": str(base / "cache")}, base)
    subprocess.run([sys.executable, "-m", "lipmpcc", *[a.replace("{tmp}", str(base)) for a in CACHE_RUN]],
                   env=env, capture_output=True, timeout=300, check=False)
    return base / "cache"


def _libraries(cache: Path) -> list[Path]:
    return sorted(cache.glob("*.so"))


def _corrupt(how: str) -> Callable[[Path], None]:
    def setup(tmp: Path) -> None:
        cache = tmp / "cache"
        src = seeded_cache()
        if how == "file":
            cache.write_text("not a folder\n")
            return
        shutil.copytree(src, cache) if src.is_dir() else cache.mkdir()
        libs = _libraries(cache)
        if not libs:
            raise RuntimeError(f"the seeded cache {src} holds no .so (no C compiler?)")
        data = [p.read_bytes() for p in libs]
        for i, p in enumerate(libs[:1]):  # one damaged library (each costs a rebuild)
            if how == "half":
                p.write_bytes(data[i][: len(data[i]) // 2])
            elif how == "header":
                p.write_bytes(data[i][:64])
            elif how == "empty":
                p.write_bytes(b"")
            elif how == "garbage":
                p.write_bytes(bytes(range(256)) * 64)
            elif how == "swapped":
                p.write_bytes(data[(i + 1) % len(data)])
            elif how == "directory":
                p.unlink()
                p.mkdir()
            elif how == "flipped":
                b = bytearray(data[i])
                for k in range(len(b) // 3, len(b) // 3 + 256):
                    b[k] ^= 0xFF
                p.write_bytes(bytes(b))
        (cache / "tmpleftover").mkdir(exist_ok=True)
        (cache / "tmpleftover" / "half.c").write_text("int f(")
    return setup


def _summary_written(ran: Ran) -> str | None:
    if ran.rc == RC_OK and not (ran.tmp / "out" / "summary.json").is_file():
        return "exit 0 without summary.json"
    return None


def cache_case(how: str, question: str = "") -> Case:
    return Case(f"cache-{how}", "cache", "proc", "survive", argv=CACHE_RUN, setup=_corrupt(how),
                env={"LIPMPCC_CACHE_DIR": "{tmp}/cache"}, check=_summary_written, timeout=120, question=question)


CACHE = [
    cache_case("half", "a truncated library: rebuilt (rc 0), or rc 1 naming the cache; never rc 135"),
    cache_case("header"),
    cache_case("empty"),
    cache_case("garbage"),
    cache_case("swapped"),
    cache_case("directory"),
    cache_case("flipped", "bytes flipped inside the code: only a checksum finds it; a crash here is a finding"),
    cache_case("file"),
]


# ---- threads ----------------------------------------------------------------------------------------
PRELUDE = """
import sys, threading, numpy as np
from lipmpcc.exceptions import LipmpccError
def main():
{body}
try:
    main()
except LipmpccError as exc:
    print("lipmpcc: error:", exc, file=sys.stderr)
    sys.exit(1)
"""

WBC_SETUP = """
    import lipmpcc as L
    from lipmpcc.control.wbc_types import WbcReference
    r = L.load_robot('digit_like'); w = L.WholeBodyController(r, threaded={threaded}); m = L.RobotSim(r).measure()
    ref = WbcReference(com_pos=np.asarray(m.com), arm_posture=np.zeros(w.n_arm),
                       foot_pos=np.array([m.feet[0].position, m.feet[1].position]))
    errors = []
    def run(k, what):
        try:
            for i in range(1500):
                q = m.q.copy(); q[0] += 1e-4 * (i + k)
                if what in ('solve', 'both'): w.solve(q, m.v, ref)
                if what in ('prepare', 'both'): w.prepare(q, m.v)
                if what == 'reset': w.reset()
        except LipmpccError as exc:
            errors.append(exc)
    ts = [threading.Thread(target=run, args=(k, what)) for k, what in enumerate({roles})]
    [t.start() for t in ts]; [t.join() for t in ts]
    if errors: raise errors[0]
    print('ok')
"""


def script(body: str) -> str:
    return PRELUDE.format(body=body)


def thread_case(cid: str, roles: tuple[str, ...], threaded: bool, question: str = "") -> Case:
    body = WBC_SETUP.format(threaded=threaded, roles=repr(list(roles)))
    return Case(f"threads-{cid}", "threads", "proc", "survive", script=script(body), timeout=90, question=question)


TWO_WBCS = """
    import lipmpcc as L
    from lipmpcc.control.wbc_types import WbcReference
    r = L.load_robot('digit_like'); m = L.RobotSim(r).measure()
    ws = [L.WholeBodyController(r) for _ in range(2)]
    ref = WbcReference(com_pos=np.asarray(m.com), arm_posture=np.zeros(ws[0].n_arm),
                       foot_pos=np.array([m.feet[0].position, m.feet[1].position]))
    def run(w):
        for i in range(200):
            q = m.q.copy(); q[0] += 1e-4 * i; w.solve(q, m.v, ref)
    ts = [threading.Thread(target=run, args=(w,)) for w in ws]
    [t.start() for t in ts]; [t.join() for t in ts]
    print('ok')
"""

MPCC_THREADS = """
    from lipmpcc.paths import ArcPath
    from lipmpcc.planners.mpcc import MpccParams, MpccPlanner
    p = MpccPlanner(ArcPath.circle(2.0), MpccParams.circle())
    errors = []
    def run(k):
        try:
            for i in range(20):
                p.solve(np.array([0.0, 0.01 * k, 0.0, 0.0, 0.0]), 1 if i % 2 else -1, shift=False)
        except LipmpccError as exc:
            errors.append(exc)
    ts = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    [t.start() for t in ts]; [t.join() for t in ts]
    if errors: raise errors[0]
    print('ok')
"""

SIM_THREADS = """
    import lipmpcc as L
    r = L.load_robot('digit_like'); sim = L.RobotSim(r)
    u = np.zeros(sim.model.nu); errors = []
    def run():
        try:
            for i in range(300): sim.step(u, 1)
        except LipmpccError as exc:
            errors.append(exc)
    ts = [threading.Thread(target=run) for _ in range(2)]
    [t.start() for t in ts]; [t.join() for t in ts]
    if errors: raise errors[0]
    print('ok')
"""

THREADS = [
    thread_case("wbc-solve-solve", ("solve", "solve"), False,
                "one controller from two threads: a clear LipmpccError, or safe; never rc 139"),
    thread_case("wbc-solve-solve-threaded", ("solve", "solve"), True),
    thread_case("wbc-prepare-solve", ("prepare", "solve"), True),
    thread_case("wbc-both-both", ("both", "both"), True),
    thread_case("wbc-solve-reset", ("solve", "reset"), False),
    Case("threads-two-wbcs", "threads", "proc", "ok", script=script(TWO_WBCS), timeout=90,
         check=lambda r: None if "ok" in r.out else "did not finish"),
    Case("threads-mpcc-solve-solve", "threads", "proc", "survive", script=script(MPCC_THREADS), timeout=120,
         question="one MPCC from two threads shares its buffers: refuse or serialise; never a crash"),
    Case("threads-sim-step-step", "threads", "proc", "survive", script=script(SIM_THREADS), timeout=90,
         question="one RobotSim stepped from two threads (the compiled tick releases the GIL)"),
]


# ---- interrupts -------------------------------------------------------------------------------------
LONG_PATH = "x,y\n0,0\n2000,0\n"  # 400 LIP steps take longer than the interrupt's delay


def _nothing_half(ran: Ran) -> str | None:
    """After an interrupt --out holds nothing that reads as a complete result."""
    out = ran.tmp / "out"
    for name in ("summary.json", "results.json", "report.md"):
        p = out / name
        if p.is_file():
            text = p.read_text(errors="replace").lower()
            if "partial" not in text and "interrupted" not in text:
                return f"{name} left in --out after Ctrl-C, not marked partial"
    return None


def _old_report(tmp: Path) -> None:
    out = tmp / "out"
    out.mkdir()
    (out / "report.md").write_text("# lipmpcc report\n\nAll studies met their expectation.\n")


def interrupt_case(cid: str, argv: list[str], after: float, count: int = 1, question: str = "",
                   setup: Callable[[Path], None] | None = None, files: dict[str, Any] | None = None) -> Case:
    return Case(f"interrupt-{cid}", "interrupts", "proc", "interrupt", argv=argv + ["--out", "{tmp}/out"],
                sigint_after=after, sigint_count=count, timeout=after + 10, check=_nothing_half, setup=setup,
                files=files or {}, question=question)


INTERRUPTS = [
    # 3000 LIP steps took 4.5 s in all on the idle 2-core machine (Ctrl-C at 3 s after start-up): 10000
    interrupt_case("lip-run", ["run", "circle", "--robot", "lip", "--steps", "10000", "--path", "{tmp}/long.csv"],
                   3.0, files={"long.csv": LONG_PATH}),
    interrupt_case("lip-startup", ["run", "circle", "--robot", "lip", "--steps", "400", "--path", "{tmp}/long.csv"], 0.3,
                   files={"long.csv": LONG_PATH},
                   question="a Ctrl-C during the imports, before main() runs: still one line and rc 130"),
    interrupt_case("alip-stones", ["run", "stones", "--stones", "{tmp}/s.csv"], 2.5,
                   files={"s.csv": _stones_rows(400)}),  # 150 stones took 5.5 s in all on the idle machine
    # a walk of 120 s simulated: the 30 s one ended in under 6 s on an idle CI machine once the imports got
    # lazier (rc 0 before the late Ctrl-C)
    interrupt_case("fullbody-walk-early", ["run", "walk", "--robot", "digit_like", "--duration", "120"], 3.0),
    interrupt_case("fullbody-walk-late", ["run", "walk", "--robot", "digit_like", "--duration", "120"], 6.0),
    interrupt_case("fullbody-walk-3x", ["run", "walk", "--robot", "digit_like", "--duration", "120"], 4.5, count=3),
    # the reduced models' studies: the ALIP's 21 full runs take about 20 s (the LIP's 4 fast ones ended in under
    # 3 s on an idle CI machine, before the Ctrl-C)
    interrupt_case("reproduce-alip", ["reproduce", "--only", "alip-"], 3.0, setup=_old_report,
                   question="an old report.md must not stay unmarked beside partial results"),
    # a full-body study (25 s simulated): the whole command takes about 6 s on an idle CI machine (after 6 s
    # the Ctrl-C once came after its end), and 3.5 s is past the imports on any machine seen
    interrupt_case("reproduce-fullbody", ["reproduce", "--fast", "--only", "digit-overtake-mpcc"], 3.5, setup=_old_report),
]


# ---- two runs into one folder; reproduce whose studies fail -------------------------------------------------
CONCURRENT = """
import json, os, subprocess, sys
out = sys.argv[1]
cmds = [[sys.executable, '-m', 'lipmpcc', 'run', 'circle', '--robot', 'lip', '--steps', '3', '--out', out],
        [sys.executable, '-m', 'lipmpcc', 'run', 'stones', '--steps', '3', '--out', out]]
ps = [subprocess.Popen(c, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for c in cmds]
res = [p.communicate(timeout=120) + (p.returncode,) for p in ps]
files = sorted(os.listdir(out)) if os.path.isdir(out) else []
s = json.load(open(os.path.join(out, 'summary.json'))) if 'summary.json' in files else None
print(json.dumps({'rcs': [r[2] for r in res], 'errs': [r[1][-300:] for r in res], 'files': files,
                  'scenario': s and s.get('scenario')}))
"""
FIGURES = {"circle": {"circle.png"}, "stones": {"durations_dcm.png", "footprints.png"}}


def _not_interleaved(ran: Ran) -> str | None:
    try:
        r = json.loads(ran.out.strip().splitlines()[-1])
    except (ValueError, IndexError):
        return f"no report from the script: {ran.out[-200:]!r}"
    if any("Traceback" in e for e in r["errs"]):
        return "a traceback in one of the runs: " + " | ".join(r["errs"])
    pngs = {f for f in r["files"] if f.endswith(".png")}
    scen = r["scenario"]
    if scen is None:
        return None if any(rc != 0 for rc in r["rcs"]) else "both runs exit 0 and there is no summary.json"
    if pngs != FIGURES.get(scen, set()):
        return f"summary.json of {scen!r} beside figures {sorted(pngs)} (interleaved)"
    if r["rcs"].count(0) == 2:
        return "both runs exit 0 into one folder: one result was overwritten without a word"
    return None


def _reproduce_failed(ran: Ran) -> str | None:
    if ran.rc != RC_ERROR:
        return f"reproduce exit {ran.rc} when every study failed (expected 1)"
    return None


OUTPUT_FAULTS = [
    Case("outputs-two-runs-one-folder", "outputs", "proc", "ok", script=CONCURRENT.replace("sys.argv[1]", "'{tmp}/out'"),
         check=_not_interleaved, timeout=150,
         question="one run refused (or waiting) and the other complete; both exit 0 counts as a lost result"),
    Case("reproduce-every-study-fails", "cli", "proc", "outcome", argv=["reproduce", "--fast", "--only",
         "lip-overtake-cartesian", "--out", "{tmp}/out"], env={"MPLBACKEND": "bogus"}, rcs=(RC_ERROR,),
         check=_reproduce_failed, timeout=150),
]

CASES: list[Case] = CACHE + THREADS + INTERRUPTS + OUTPUT_FAULTS
