"""Fuzz cases of the command line: options that do not apply, bad and absurd values, output folders,
``reproduce``, and runs whose outcome must not be reported as a success (in-process, through
:func:`lipmpcc.cli.main`)."""

from __future__ import annotations

import json
import shlex
from pathlib import Path
from typing import Any, Callable

from .harness import RC_COLLIDED, RC_FELL, RC_OK, RC_STOPPED, Case, Ran, outcome_problem

WAYPOINTS = "x,y\n0,0\n1,0\n2,0\n3,0.4\n"
STONES = "x,y\n1.40,-0.14\n1.70,0.16\n2.05,-0.10\n"


def cli(cid: str, args: str, names: tuple = (), expect: str = "error", category: str = "cli",
        files: dict[str, Any] | None = None, **kw: Any) -> Case:
    """A CLI case; ``args`` is split like a shell would; ``--out {tmp}/out`` is added to ``run`` and
    ``reproduce`` when not given (nothing silently accepted may write into the working directory)."""
    argv = shlex.split(args)
    kw_out = kw.pop("default_out", False)
    if argv and argv[0] in ("run", "reproduce") and "--out" not in argv and not kw_out:
        argv += ["--out", "{tmp}/out"]
    return Case(cid, category, "cli", expect, argv=argv, files=files or {}, names=names, **kw)


def ran_ok(extra: Callable[[Ran], str | None] | None = None) -> Callable[[Ran], str | None]:
    """The shared outcome contract, then ``extra``."""
    def check(ran: Ran) -> str | None:
        return outcome_problem(ran) or (extra(ran) if extra else None)
    return check


def no_solver_failures(ran: Ran) -> str | None:
    s = ran.summary() or {}
    n = s.get("solver_failures")
    return None if n == 0 else f"solver_failures = {n} (expected 0: the input is legitimate)"


# ---- options that do not apply (issue 14, first class) -------------------------------------------
NOT_APPLYING = [
    cli("opt-obstacle-speed-circle", "run circle --obstacle-speed 0.3", ("--obstacle-speed", "circle"), "usage"),
    cli("opt-obstacle-speed-circle-push", "run circle-push --obstacle-speed 0.3", ("--obstacle-speed",), "usage"),
    cli("opt-profile-overtake", "run overtake --profile II", ("--profile", "overtake"), "usage"),
    cli("opt-cop-range-circle", "run circle --cop-range 0.05 0.02", ("--cop-range", "circle"), "usage"),
    cli("opt-video-lip", "run circle --robot lip --video", ("--video",), "usage"),
    cli("opt-video-alip", "run stones --robot alip --video", ("--video",), "usage"),
    cli("opt-duration-lip", "run circle --robot lip --duration 5", ("--duration",), "usage"),
    cli("opt-duration-alip-stones", "run stones --duration 5", ("--duration",), "usage"),
    cli("opt-duration-fullbody-stones", "run stones --robot digit_like --duration 5", ("--duration",), "usage"),
    cli("opt-stones-circle", "run circle --stones {tmp}/s.csv", ("--stones",), "usage", files={"s.csv": STONES}),
    cli("opt-speed-stand", "run stand --speed 0.3", ("--speed", "stand"), "usage"),
    cli("opt-steps-stand", "run stand --steps 3", ("--steps", "stand"), "usage"),
    cli("opt-planner-stand", "run stand --planner mpcc", ("--planner",), "usage"),
    cli("opt-seed-circle", "run circle --seed 3", ("--seed", "circle"), "usage"),
    cli("opt-seed-overtake", "run overtake --seed 3", ("--seed",), "usage"),
    cli("opt-seed-stones-profile-I", "run stones --seed 2", ("--seed",), "usage"),
    cli("opt-seed-stones-file", "run stones --stones {tmp}/s.csv --seed 2", ("--seed",), "usage", files={"s.csv": STONES}),
    cli("opt-profile-with-stones-file", "run stones --stones {tmp}/s.csv --profile II", ("--profile",), "usage",
        files={"s.csv": STONES}),
    cli("opt-L-profile-II", "run stones --profile II --L 0.4", ("--L",), "usage"),
    cli("opt-W-circle-push", "run circle-push --W 0.1", ("--W",), "usage"),
    cli("opt-yaw-rate-push", "run push --yaw-rate 0.2", ("--yaw-rate",), "usage"),
    cli("opt-speed-stones", "run stones --speed 0.5", ("--speed",), "usage"),
    cli("opt-path-stones", "run stones --path {tmp}/p.csv", ("--path",), "usage", files={"p.csv": WAYPOINTS}),
    cli("opt-obstacles-walk", "run walk --obstacles {tmp}/o.json", ("--obstacles",), "usage", files={"o.json": "[]"}),
    cli("opt-obstacle-speed-with-file", "run overtake --obstacles {tmp}/o.json --obstacle-speed 0.2",
        ("--obstacle-speed",), "usage",
        files={"o.json": '[{"shape": "circle", "radius": 0.2, "position": [5, 0]}]'}),
]

# ---- bad option values ----------------------------------------------------------------------------
BAD_VALUES = [
    cli("val-steps-zero", "run circle --steps 0", ("0",), "usage"),
    cli("val-steps-negative", "run circle --steps -3", ("-3",), "usage"),
    cli("val-steps-word", "run circle --steps two", ("two",), "usage"),
    cli("val-steps-float", "run circle --steps 1.5", ("1.5",), "usage"),
    cli("val-seed-negative", "run circle-push --seed -1", ("-1",), "usage"),
    cli("val-speed-nan", "run walk --speed nan", ("nan",), "usage"),
    cli("val-obstacle-speed-inf", "run overtake --obstacle-speed inf", ("inf",), "usage"),
    cli("val-L-word", "run stones --L long", ("long",), "usage"),
    cli("val-cop-range-one", "run stones --cop-range 0.05", ("--cop-range",), "usage"),
    cli("val-scenario-unknown", "run marathon", ("marathon",), "usage"),
    cli("val-option-unknown", "run circle --no-such-option", ("--no-such-option",), "usage"),
    cli("val-no-command", "", ("command",), "usage"),
    cli("val-run-no-scenario", "run", ("scenario",), "usage"),
    cli("val-obstacle-speed-1e308", "run overtake --obstacle-speed 1e308", (("1e+308", "1e308"), "obstacle"),
        question="the issue calls today's message vague (a path-parameter array); rc 1 or 2 both accepted"),
    cli("val-obstacle-speed-absurd", "run overtake --obstacle-speed -50", ("-50",),
        question="is -50 m/s refused or a legitimate (if silly) head-on obstacle? expected refused as absurd"),
    cli("val-planner-unknown", "run circle --planner nonsense", ("nonsense",)),
    cli("val-planner-wrong-study", "run circle --planner alip-mpc", ("alip-mpc",)),
    cli("val-robot-unknown", "run circle --robot nonsense", ("nonsense",)),
    cli("val-robot-missing-xml", "run stand --robot {tmp}/none.xml", ("none.xml",)),
    cli("val-robot-empty", "run circle --robot ''", ("--robot",),
        question="--robot '' is taken as the default robot today; expected refused like --out ''"),
    cli("val-robot-lip-walk", "run walk --robot lip", ("lip",)),
    cli("val-robot-alip-circle", "run circle --robot alip", ("alip",)),
    cli("val-profile-unknown", "run stones --profile V", ("V",)),
    cli("val-L-negative", "run stones --L -1", ("-1",)),
    cli("val-L-huge", "run stones --L 100", ("100",)),
    cli("val-W-huge", "run stones --W 5", ("5",)),
    cli("val-cop-range-negative", "run stones --cop-range -0.1 0.02", ("-0.1",)),
    cli("val-cop-range-huge", "run push --cop-range 5 5", ("5",)),
    cli("val-speed-absurd", "run walk --speed 100", ("100",)),
    cli("val-yaw-rate-absurd", "run walk --yaw-rate 50", ("50",)),
    cli("val-duration-negative", "run walk --duration -1", ("-1",)),
    cli("val-duration-zero", "run stand --duration 0", ("0",)),
    cli("val-steps-absurd-circle", "run circle --steps 100000000000", ("100000000000",),
        question="absurd sizes: expected refused up front (or a warning of the time it takes); a run that "
                 "starts is a hang here"),
    cli("val-steps-absurd-stones", "run stones --steps 1000000", ("1000000",),
        question="as above; 1e6 ALIP steps may also be refused as more than the course"),
    cli("val-duration-absurd-walk", "run walk --duration 1e9", (("1e+09", "1e9", "1000000000"),),
        question="absurd sizes: expected refused up front"),
    cli("val-duration-absurd-stand", "run stand --duration 1e7", (("1e+07", "1e7", "10000000"),),
        question="absurd sizes: expected refused up front"),
    cli("val-path-missing", "run circle --path {tmp}/none.csv", ("none.csv",)),
    cli("val-obstacles-missing", "run overtake --obstacles {tmp}/none.json", ("none.json",)),
    cli("val-stones-missing", "run stones --stones {tmp}/none.csv", ("none.csv",)),
    cli("val-path-is-dir", "run circle --path {tmp}", ("path",)),
    cli("val-stones-is-dir", "run stones --stones {tmp}", ("stones",)),
    cli("val-reproduce-only-nomatch", "reproduce --only nomatch", ("nomatch",), "usage"),
    cli("val-reproduce-only-empty", "reproduce --only ''", ("--only",), "usage",
        question="--only '' matches every study today (a full reproduce); expected refused as empty"),
    cli("val-reproduce-out-empty", "reproduce --only lip-circle --out ''", ("--out",)),
]


# ---- output folders -------------------------------------------------------------------------------
def _foreign_run(tmp: Path) -> None:
    d = tmp / "out"
    d.mkdir()
    (d / "summary.json").write_text(json.dumps({"scenario": "stones", "fell": False}))
    (d / "footprints.png").write_bytes(b"\x89PNG\r\n\x1a\n")


def _foreign_untouched(ran: Ran) -> str | None:
    d = ran.tmp / "out"
    s = json.loads((d / "summary.json").read_text()) if (d / "summary.json").is_file() else {}
    if s.get("scenario") != "stones" or not (d / "footprints.png").is_file():
        return "the other run's results in --out were changed"
    return None


EARLIER = json.dumps({"scenario": "circle", "planner": "mpcc", "robot": "lip", "steps": 120, "fell": False,
                      "solver_failures": 0})


def _earlier_success(tmp: Path) -> None:
    d = tmp / "out"
    d.mkdir()
    (d / "summary.json").write_text(EARLIER)
    (d / "circle.png").write_bytes(b"\x89PNG\r\n\x1a\n")


def _earlier_kept_or_gone(ran: Ran) -> str | None:
    p = ran.tmp / "out" / "summary.json"
    if p.is_file() and p.read_text() != EARLIER:
        return "the failed run wrote a new summary.json"
    return None


def _png_is_dir(tmp: Path) -> None:
    (tmp / "out" / "circle.png").mkdir(parents=True)


def _no_summary(ran: Ran) -> str | None:
    return "a failed run left summary.json in --out" if (ran.tmp / "out" / "summary.json").exists() else None


def _per_run_default(ran: Ran) -> str | None:
    if (ran.tmp / "results" / "summary.json").exists():
        return "the default --out put summary.json straight into results/ (expected a folder per run)"
    found = list(ran.tmp.rglob("summary.json"))
    return None if found else "no summary.json anywhere under the working directory"


OUTPUTS = [
    cli("out-empty", "run circle --robot lip --steps 2 --out ''", ("--out",), category="outputs"),
    cli("out-is-file", "run circle --robot lip --steps 2 --out {tmp}/f.txt", ("f.txt", ("folder", "directory")),
        category="outputs",
        files={"f.txt": "a file\n"}),
    cli("out-under-file", "run circle --robot lip --steps 2 --out {tmp}/f.txt/sub", ("f.txt",), category="outputs",
        files={"f.txt": "a file\n"}),
    cli("out-holds-other-run", "run circle --robot lip --steps 2 --out {tmp}/out", ("out",), category="outputs",
        setup=_foreign_run, check=_foreign_untouched,
        question="expected refused (rc 1 or 2) unless a replace option is given; its name is the CLI part's"),
    cli("out-failed-run-over-success", "run circle --robot lip --steps 2 --obstacles {tmp}/o.json --out {tmp}/out",
        (("out",), ("earlier run", "--replace")), category="outputs", files={"o.json": "[{oops"}, setup=_earlier_success, check=_earlier_kept_or_gone,
        question="the failing run is refused; the earlier run's own summary.json may stay (it is that run's) but no "
                 "new one may appear"),
    cli("out-figure-unwritable", "run circle --robot lip --steps 2 --out {tmp}/out", (("circle.png", "out"),),
        category="outputs", setup=_png_is_dir, check=_no_summary),
    cli("out-default-per-run", "run circle --robot lip --steps 2", (), "ok", category="outputs", default_out=True,
        check=ran_ok(_per_run_default),
        question="'the default --out is a folder per run': checked as no summary.json directly in ./results"),
]


# ---- runs: failures must not be reported as success; legitimate input must run -------------------
def _circle(x: float, y: float, r: float = 0.2) -> dict:
    return {"shape": "circle", "radius": r, "position": [x, y]}


def _json(obj: object) -> str:
    return json.dumps(obj)


HEAD_ON = _json([{"shape": "circle", "radius": 0.5, "s0": 5.0, "speed": -0.4}])
#: a 40 m wide wall coming at 1 m/s: faster than the LIP can walk back (v_max 0.3 m per 0.4 s step)
WALL = _json([{"shape": "ellipse", "axes": [0.3, 20.0], "position": [4.0, 0.0], "velocity": [-1.5, 0.0]}])  # faster than the LIP can back away
FAR_30 = _json([_circle(0.0, 30.0)])
FAR_60 = _json([_circle(20.0, 60.0)])
MANY_200 = _json([_circle(0.2 * (i // 2) + 0.2, 3.0 if i % 2 else -3.0) for i in range(200)])


def _stones_rows(n: int) -> str:
    rows = ["x,y"] + [f"{1.05 + 0.3 * (k + 1):.3f},{-0.14 if k % 2 == 0 else 0.14}" for k in range(n)]
    return "\n".join(rows) + "\n"


def _fullbody_clearance(ran: Ran) -> str | None:
    s = ran.summary() or {}
    if not isinstance(s.get("min_body_clearance_m"), (int, float)):
        return f"min_body_clearance_m = {s.get('min_body_clearance_m')!r} on a full-body run with an obstacle"
    return no_solver_failures(ran)


def _all_stones(ran: Ran) -> str | None:
    s = ran.summary() or {}
    total, reached = s.get("stones_total"), s.get("stones_reached")
    if total != 40:
        return f"stones_total = {total!r} (the file has 40)"
    if reached != 40 and not s.get("stopped_early"):
        return f"stones_reached = {reached!r} of 40 and no stopped_early reason"
    return None


def _start_hint(ran: Ran) -> str | None:
    if ran.rc in (1, 2):
        lines = [ln for ln in ran.err.splitlines() if ln.startswith("lipmpcc: error:")]
        ok = len(lines) == 1 and "start" in lines[0].lower()
        return None if ok else f"refused without one error line naming the path's start: {ran.err.strip()[-200:]!r}"
    s = ran.summary() or {}
    if s.get("solver_failures") or s.get("fell"):
        return f"fell = {s.get('fell')}, solver_failures = {s.get('solver_failures')} with no refusal or hint"
    return None


RUNS = [
    cli("run-head-on-obstacle-lip", "run overtake --robot lip --steps 40 --obstacles {tmp}/o.json", (), "outcome",
        category="outcomes", files={"o.json": HEAD_ON}, rcs=(RC_OK, RC_COLLIDED, RC_STOPPED), check=ran_ok(),
        timeout=60, question="either the robot avoids it (rc 0, clearance >= 0) or the collision is reported (rc 4)"),
    cli("run-unavoidable-wall-lip", "run overtake --robot lip --steps 20 --obstacles {tmp}/o.json", (), "outcome",
        category="outcomes", files={"o.json": WALL}, rcs=(RC_COLLIDED, RC_STOPPED), check=ran_ok(), timeout=60,
        question="the wall sweeps through the start faster than the robot can retreat: a collision (rc 4), or a "
                 "stop reported before it (rc 5); today rc 0 with min_clearance_m > 0 (clearance only at step instants)"),
    cli("run-far-obstacle-30m", "run overtake --robot lip --steps 6 --obstacles {tmp}/o.json", (), "ok",
        category="outcomes", files={"o.json": FAR_30}, check=ran_ok(no_solver_failures), timeout=60),
    cli("run-far-obstacle-60m", "run circle --robot lip --steps 6 --obstacles {tmp}/o.json", (), "ok",
        category="outcomes", files={"o.json": FAR_60}, check=ran_ok(no_solver_failures), timeout=60),
    cli("run-200-obstacles", "run overtake --robot lip --steps 3 --obstacles {tmp}/o.json", (), "ok",
        category="outcomes", files={"o.json": MANY_200}, check=ran_ok(no_solver_failures), timeout=90),
    cli("run-40-stones-no-steps", "run stones --stones {tmp}/s.csv", (), "outcome", category="outcomes",
        files={"s.csv": _stones_rows(40)}, rcs=(RC_OK, RC_FELL, RC_STOPPED), check=ran_ok(_all_stones), timeout=90,
        question="40 stones stands in for the issue's 1000 (cost); every stone walked, or the stop reported"),
    cli("run-empty-obstacle-list", "run overtake --robot lip --steps 4 --obstacles {tmp}/o.json", (), "ok",
        category="outcomes", files={"o.json": "[]"}, check=ran_ok(),
        question="an empty obstacle list is taken as legitimate (no obstacle); refusing it would also be defensible"),
    cli("run-short-lip-circle", "run circle --robot lip --steps 3", (), "ok", category="outcomes", check=ran_ok()),
    cli("run-fullbody-path-not-at-robot",
        "run circle --robot digit_like --duration 2.5 --path {tmp}/p.csv", ("start",), "outcome", category="outcomes",
        files={"p.csv": "x,y\n3,3\n4,3\n5,3.5\n6,4\n"}, rcs=(RC_OK, 1, 2), check=_start_hint, timeout=120,
        question="refused with a message naming the start (rc 1/2), or run from the path's start without failures"),
    cli("run-fullbody-far-obstacle", "run overtake --robot digit_like --duration 1.5 --obstacles {tmp}/o.json", (),
        "ok", category="outcomes", files={"o.json": FAR_60}, check=ran_ok(_fullbody_clearance), timeout=120),
    cli("version", "--version", (), "ok", category="cli", rcs=(RC_OK,),
        check=lambda r: None if "lipmpcc" in r.out else f"--version printed {r.out!r}"),
]

CASES: list[Case] = NOT_APPLYING + BAD_VALUES + OUTPUTS + RUNS
