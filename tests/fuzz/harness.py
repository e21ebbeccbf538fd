"""The fuzz harness: what a case is, how it is run and how its outcome is classified.

A :class:`Case` states the clean behaviour it expects (``expect``) and the harness runs it one of
three ways (``kind``):

- ``"cli"``: in this process, through :func:`lipmpcc.cli.main` (argparse's ``SystemExit`` is the
  exit code; stderr and stdout are captured; a wall-clock alarm bounds it);
- ``"api"``: a Python call ``func(tmp)`` in this process, bounded the same way;
- ``"proc"``: a subprocess (``python -m lipmpcc ARGV`` or ``python -c SCRIPT``), for crashes, the
  compiled-code cache, threads and interrupts, with a timeout (and SIGINTs sent on a schedule).

Every outcome is classified into one of :data:`CLASSES`:

========== ===========================================================================================
ok         the expected clean behaviour
traceback  a non-lipmpcc exception escaped, or "Traceback" on stderr
crash      the process died (rc < 0 or >= 128, but 130 after a SIGINT)
hang       the case did not end within its time limit
silent     an error (or a failure outcome) was required and none came: exit 0 / no exception
refused    legitimate input was refused with an error
vague      the error came, but not as one ``lipmpcc: error:`` line naming the bad value, or with the
           wrong exit code
wrong      it ran, but the result contradicts what it must say (e.g. summary without ``outcome``,
           clearance < 0 reported as completed, an interrupt that did not exit 130)
========== ===========================================================================================
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from ..conftest import package_env, default_sigint

REPO = Path(__file__).resolve().parents[2]

CLASSES = ("ok", "traceback", "crash", "hang", "silent", "refused", "vague", "wrong")

#: the exit codes of lipmpcc.cli (shared contract of issue 14)
RC_OK, RC_ERROR, RC_USAGE, RC_FELL, RC_COLLIDED, RC_STOPPED, RC_INTERRUPTED = 0, 1, 2, 3, 4, 5, 130
OUTCOME_RC = {"completed": RC_OK, "fell": RC_FELL, "collided": RC_COLLIDED, "stopped_early": RC_STOPPED}

Token = str | tuple[str, ...]  # a word the message must contain, or alternatives of which one must


@dataclass
class Case:
    """One bad input or fault and the clean behaviour expected from it.

    Attributes:
        id: unique, stable name (the pytest id).
        category: the group in the tally (cli, outputs, path-csv, obstacles-json, stones-csv, layout,
            mjcf, api-params, api-geometry, api-planners, api-wbc, api-loops, cache, threads, interrupts).
        kind: ``"cli"``, ``"api"`` or ``"proc"``.
        expect: ``"error"`` (rc 1 or 2 / a LipmpccError naming ``names``), ``"usage"`` (rc 2),
            ``"ok"`` (runs: rc 0 / returns), ``"outcome"`` (a run whose rc is in ``rcs``),
            ``"interrupt"`` (rc 130, ``lipmpcc: interrupted``), ``"survive"`` (a fault: rc 0, or rc 1
            with one ``lipmpcc: error:`` line; never a crash or a traceback).
        argv: CLI arguments (``cli`` kind, or ``proc`` kind without ``script``); ``{tmp}`` is the
            case's folder.
        files: files written into the case's folder first: name -> text, bytes, or a callable
            ``f(tmp) -> text | bytes``.
        setup: called with the case's folder after the files are written (prepare a cache, ...).
        func: ``api`` kind: the call, ``func(tmp)``; its return value goes to ``check``.
        script: ``proc`` kind: Python source run with ``python -c`` (``{tmp}`` substituted).
        env: extra environment of a ``proc`` case (``{tmp}`` substituted in values).
        cwd: ``"tmp"`` (default) runs the case with its folder as the working directory (a silently
            accepted ``--out ''`` must not write into the repository); None: the caller's.
        names: words the error message must contain (case-insensitive); a tuple item is a set of
            alternatives.
        rcs: allowed exit codes (default by ``expect``).
        check: extra check of a run that ended as expected: ``check(ctx)`` returns a problem (str)
            or None; ``ctx`` is a :class:`Ran`.
        sigint_after: ``proc`` kind: seconds after start when SIGINT is sent (then every
            ``sigint_every`` s, ``sigint_count`` times).
        timeout: wall-clock limit [s] (a ``proc`` case after its SIGINT: ``interrupt_grace``).
        question: why the expected behaviour is a judgment call ("" when it is not).
    """

    id: str
    category: str
    kind: str
    expect: str
    argv: Sequence[str] = ()
    files: dict[str, Any] = field(default_factory=dict)
    setup: Callable[[Path], None] | None = None
    func: Callable[[Path], Any] | None = None
    script: str | None = None
    env: dict[str, str] = field(default_factory=dict)
    cwd: str | None = "tmp"
    names: Sequence[Token] = ()
    rcs: Sequence[int] | None = None
    check: Callable[["Ran"], str | None] | None = None
    sigint_after: float | None = None
    sigint_every: float = 0.3
    sigint_count: int = 1
    interrupt_grace: float = 5.0
    timeout: float = 25.0
    question: str = ""

    def allowed_rcs(self) -> set[int]:
        if self.rcs is not None:
            return set(self.rcs)
        return {"error": {RC_ERROR, RC_USAGE}, "usage": {RC_USAGE}, "ok": {RC_OK},
                "interrupt": {RC_INTERRUPTED}, "survive": {RC_OK, RC_ERROR}}.get(self.expect, {RC_OK})


@dataclass
class Ran:
    """What running a case gave (the input of the classification and of ``Case.check``)."""

    case: Case
    tmp: Path
    rc: int | None = None  # exit code (cli/proc); None for api or a hang
    out: str = ""
    err: str = ""
    value: Any = None  # api: the returned value
    exc: BaseException | None = None  # api/cli: the exception that escaped
    hung: bool = False
    seconds: float = 0.0

    def summary(self) -> dict | None:
        """The summary.json of the run's ``--out`` (None when there is none)."""
        out = _out_arg(self.case.argv, self.tmp)
        if out is None:  # the default --out, under the case's working directory
            found = sorted(self.tmp.rglob("summary.json"))
            p = found[0] if found else self.tmp / "summary.json"
        else:
            p = out / "summary.json"
        if not p.is_file():
            return None
        try:
            return json.loads(p.read_text())
        except ValueError:
            return None


@dataclass
class Outcome:
    """The classification of one case."""

    case_id: str
    category: str
    cls: str
    detail: str
    seconds: float
    question: str = ""


# ---- helpers used by the cases --------------------------------------------------------------------
def fmt(text: str, tmp: Path) -> str:
    return text.replace("{tmp}", str(tmp))


def _out_arg(argv: Sequence[str], tmp: Path) -> Path | None:
    argv = list(argv)
    for i, a in enumerate(argv):
        if a == "--out" and i + 1 < len(argv):
            return Path(fmt(argv[i + 1], tmp))
    return None


#: ``lipmpcc: error:``, or argparse's ``lipmpcc run: error:`` / ``lipmpcc reproduce: error:`` (usage errors)
_ERROR_LINE = re.compile(r"^lipmpcc(?: run| reproduce)?: error:")


def error_lines(err: str) -> list[str]:
    return [ln for ln in err.splitlines() if _ERROR_LINE.match(ln)]


def missing_names(text: str, names: Sequence[Token]) -> list[str]:
    low = text.lower()
    miss = []
    for tok in names:
        alts = (tok,) if isinstance(tok, str) else tuple(tok)
        if not any(a.lower() in low for a in alts):
            miss.append("|".join(alts))
    return miss


def outcome_problem(ran: Ran) -> str | None:
    """The shared contract on a run that wrote summary.json: ``outcome`` present and matching the exit
    code, a negative clearance reported as a collision, a fall as a fall."""
    s = ran.summary()
    if s is None:
        return "no summary.json in --out after a run that exited %s" % ran.rc
    oc = s.get("outcome")
    if oc not in OUTCOME_RC:
        return f"summary.json outcome = {oc!r}: expected one of {sorted(OUTCOME_RC)}"
    if ran.rc is not None and OUTCOME_RC[oc] != ran.rc:
        return f"outcome {oc!r} but exit code {ran.rc} (expected {OUTCOME_RC[oc]})"
    for key in ("min_clearance_m", "min_body_clearance_m"):
        c = s.get(key)
        if isinstance(c, (int, float)) and c < 0 and oc != "collided":
            return f"{key} = {c} < 0 but outcome {oc!r}"
    if s.get("collided") and oc != "collided":
        return f"collided = true but outcome {oc!r}"
    if s.get("fell") and oc not in ("fell", "collided"):
        return f"fell = true but outcome {oc!r}"
    for key in ("collided", "relaxed_solves", "stopped_early", "warnings", "solver_failures"):
        if key not in s:
            return f"summary.json has no {key!r} field"
    return None


# ---- running ---------------------------------------------------------------------------------------
class FuzzTimeout(BaseException):
    """Raised by the alarm in an in-process case that ran past its time limit."""


class _Alarm:
    fired = False


@contextlib.contextmanager
def _alarm(seconds: float):
    """Raise :class:`FuzzTimeout` in the main thread after ``seconds``; ``_Alarm.fired`` tells whether it
    fired (the code under test may turn the exception into another one, e.g. while releasing a lock)."""
    _Alarm.fired = False
    if not hasattr(signal, "setitimer") or sys.platform == "win32":
        yield
        return

    def _fire(signum, frame):  # noqa: ARG001
        _Alarm.fired = True
        raise FuzzTimeout()

    old = signal.signal(signal.SIGALRM, _fire)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _write_files(case: Case, tmp: Path) -> None:
    for name, content in case.files.items():
        p = tmp / name
        p.parent.mkdir(parents=True, exist_ok=True)
        if callable(content):
            content = content(tmp)
        if isinstance(content, bytes):
            p.write_bytes(content)
        else:
            p.write_text(fmt(content, tmp))
    if case.setup is not None:
        case.setup(tmp)


@contextlib.contextmanager
def _cwd(path: Path | None):
    if path is None:
        yield
        return
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


def _run_cli(case: Case, tmp: Path) -> Ran:
    from lipmpcc.cli import main

    ran = Ran(case, tmp)
    argv = [fmt(a, tmp) for a in case.argv]
    out, err = io.StringIO(), io.StringIO()
    debug = os.environ.pop("LIPMPCC_DEBUG", None)
    t0 = time.perf_counter()
    try:
        with _cwd(tmp if case.cwd == "tmp" else None), contextlib.redirect_stdout(out), \
                contextlib.redirect_stderr(err), _alarm(case.timeout):
            ran.rc = main(argv)
    except SystemExit as exc:
        code = exc.code
        ran.rc = code if isinstance(code, int) else (0 if code is None else 1)
        if isinstance(code, str):
            err.write(code + "\n")
    except FuzzTimeout:
        ran.hung = True
    except KeyboardInterrupt:
        raise
    except BaseException as exc:  # noqa: BLE001 - every escape is a finding
        ran.exc = exc
    finally:
        if debug is not None:
            os.environ["LIPMPCC_DEBUG"] = debug
        _close_figures()
    ran.hung = ran.hung or _Alarm.fired
    ran.seconds = time.perf_counter() - t0
    ran.out, ran.err = out.getvalue(), err.getvalue()
    return ran


def _close_figures() -> None:
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")


def _run_api(case: Case, tmp: Path) -> Ran:
    ran = Ran(case, tmp)
    t0 = time.perf_counter()
    err = io.StringIO()
    try:
        with _cwd(tmp if case.cwd == "tmp" else None), contextlib.redirect_stderr(err), _alarm(case.timeout):
            ran.value = case.func(tmp)
    except FuzzTimeout:
        ran.hung = True
    except KeyboardInterrupt:
        raise
    except BaseException as exc:  # noqa: BLE001
        ran.exc = exc
    finally:
        _close_figures()
    ran.hung = ran.hung or _Alarm.fired
    ran.seconds = time.perf_counter() - t0
    ran.err = err.getvalue()
    return ran


def proc_env(extra: dict[str, str], tmp: Path) -> dict[str, str]:
    env = package_env()  # the lipmpcc these cases import: the installed one in CI
    env.pop("LIPMPCC_DEBUG", None)
    env.setdefault("MPLBACKEND", "Agg")
    env.update({k: fmt(v, tmp) for k, v in extra.items()})
    return env


def _run_proc(case: Case, tmp: Path) -> Ran:
    ran = Ran(case, tmp)
    if case.script is not None:
        cmd = [sys.executable, "-c", fmt(case.script, tmp)]
    else:
        cmd = [sys.executable, "-m", "lipmpcc", *[fmt(a, tmp) for a in case.argv]]
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, preexec_fn=default_sigint, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=proc_env(case.env, tmp), cwd=str(tmp) if case.cwd == "tmp" else None)
    try:
        if case.sigint_after is None:
            ran.out, ran.err = p.communicate(timeout=case.timeout)
        else:
            ran.out, ran.err = _interrupt(p, case)
        ran.rc = p.returncode
    except subprocess.TimeoutExpired:
        ran.hung = True
        p.kill()
        ran.out, ran.err = p.communicate()
    ran.seconds = time.perf_counter() - t0
    return ran


def _interrupt(p: subprocess.Popen, case: Case) -> tuple[str, str]:
    """Send SIGINT(s) on the case's schedule; the process must then end within ``interrupt_grace``."""
    try:
        return p.communicate(timeout=case.sigint_after)  # ended before the interrupt
    except subprocess.TimeoutExpired:
        pass
    for i in range(case.sigint_count):
        p.send_signal(signal.SIGINT)
        if i + 1 < case.sigint_count:
            try:
                return p.communicate(timeout=case.sigint_every)
            except subprocess.TimeoutExpired:
                pass
    return p.communicate(timeout=case.interrupt_grace)


# ---- classification --------------------------------------------------------------------------------
def _short(text: str, n: int = 160) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= n else text[: n - 3] + "..."


def traceback_detail(err: str) -> str:
    """What a failure report needs of a traceback on stderr: its last frames and the exception it ended
    with (the first unindented line after ``Traceback``), not the last line of stderr, which may be the
    program's own answer printed after it."""
    lines = err[err.find("Traceback"):].splitlines()
    end = next((i for i, ln in enumerate(lines[1:], 1) if ln and not ln[0].isspace()), len(lines) - 1)
    frames = [ln.strip() for ln in lines[max(1, end - 6):end]]
    before = err[:err.find("Traceback")].strip().splitlines()[-1:]  # e.g. "Exception ignored in: ..."
    return " | ".join(before + frames + lines[end:end + 1])


def _classify_exception(case: Case, ran: Ran) -> tuple[str, str]:
    from lipmpcc.exceptions import LipmpccError

    exc = ran.exc
    msg = f"{type(exc).__name__}: {_short(exc)}"
    if not isinstance(exc, LipmpccError):
        return "traceback", msg
    if case.kind == "cli":
        return "traceback", "escaped lipmpcc.cli.main: " + msg
    if case.expect != "error":
        return "refused", msg
    miss = missing_names(str(exc), case.names)
    if miss:
        return "vague", f"{msg} (does not name {', '.join(miss)})"
    return "ok", msg


def _classify_api(case: Case, ran: Ran) -> tuple[str, str]:
    if ran.exc is not None:
        return _classify_exception(case, ran)
    if "Traceback" in ran.err:
        return "traceback", _short(ran.err[ran.err.find("Traceback"):])
    if case.expect == "error":
        return "silent", f"no error; returned {_short(repr(ran.value), 100)}"
    problem = case.check(ran) if case.check is not None else None
    return ("wrong", problem) if problem else ("ok", _short(repr(ran.value), 100))


def _classify_rc(case: Case, ran: Ran) -> tuple[str, str]:
    rc, err = ran.rc, ran.err
    last = _short(err.strip().splitlines()[-1]) if err.strip() else ""
    if "Traceback" in err:
        return "traceback", traceback_detail(err)
    if rc is not None and (rc < 0 or (rc >= 128 and not (rc == RC_INTERRUPTED and case.sigint_after is not None))):
        return "crash", f"rc {rc}; stderr: {last}"
    allowed = case.allowed_rcs()
    if case.expect == "interrupt":
        return _classify_interrupt(case, ran, allowed, last)
    if case.expect in ("error", "usage"):
        if rc in (RC_OK, RC_FELL, RC_COLLIDED, RC_STOPPED):
            return "silent", f"rc {rc}; stdout: {_short(ran.out)}"
        lines = error_lines(err)
        if rc not in allowed:
            return "vague", f"rc {rc} (expected {sorted(allowed)}); stderr: {last}"
        if len(lines) != 1:
            return "vague", f"{len(lines)} 'lipmpcc: error:' lines; stderr: {last}"
        miss = missing_names(lines[0], case.names)
        if miss:
            return "vague", f"does not name {', '.join(miss)}: {_short(lines[0])}"
        problem = case.check(ran) if case.check is not None else None
        return ("wrong", problem) if problem else ("ok", _short(lines[0]))
    if case.expect == "survive" and rc == RC_ERROR and len(error_lines(err)) != 1:
        return "vague", f"rc 1 without one 'lipmpcc: error:' line; stderr: {last}"
    if rc not in allowed:
        if rc in (RC_ERROR, RC_USAGE) and case.expect == "ok":
            return "refused", f"rc {rc}: {last}"
        if rc == RC_OK:
            return "silent", f"rc 0, expected {sorted(allowed)}; stdout: {_short(ran.out)}"
        return "wrong", f"rc {rc}, expected {sorted(allowed)}; stderr: {last}"
    problem = case.check(ran) if case.check is not None else None
    return ("wrong", problem) if problem else ("ok", f"rc {rc}")


def _classify_interrupt(case: Case, ran: Ran, allowed: set[int], last: str) -> tuple[str, str]:
    lines = [ln for ln in ran.err.splitlines() if ln.startswith("lipmpcc: interrupted")]
    if ran.rc not in allowed:
        return "wrong", f"rc {ran.rc} after SIGINT (expected 130); stderr: {last}"
    if len(lines) != 1:
        return "vague", f"no single 'lipmpcc: interrupted' line; stderr: {last}"
    problem = case.check(ran) if case.check is not None else None
    return ("wrong", problem) if problem else ("ok", lines[0])


def classify(ran: Ran) -> Outcome:
    case = ran.case
    if ran.hung:
        cls, detail = "hang", f"no end within {case.timeout:g} s"
    elif case.kind == "api":
        cls, detail = _classify_api(case, ran)
    elif ran.exc is not None:
        cls, detail = _classify_exception(case, ran)
    else:
        cls, detail = _classify_rc(case, ran)
    return Outcome(case.id, case.category, cls, detail, ran.seconds, case.question)


def run_case(case: Case, tmp: Path | None = None) -> Outcome:
    """Run ``case`` in ``tmp`` (a fresh temporary folder when None) and classify it."""
    own = tmp is None
    if own:
        tmp = Path(tempfile.mkdtemp(prefix=f"fuzz_{case.id[:40]}_"))
    tmp.mkdir(parents=True, exist_ok=True)
    try:
        _write_files(case, tmp)
    except Exception as exc:  # noqa: BLE001 - a setup error is the harness's, shown as such
        return Outcome(case.id, case.category, "traceback", f"harness setup failed: {type(exc).__name__}: {exc}", 0.0)
    runner = {"cli": _run_cli, "api": _run_api, "proc": _run_proc}[case.kind]
    ran = runner(case, tmp)
    out = classify(ran)
    if own:
        import shutil

        shutil.rmtree(tmp, ignore_errors=True)
    return out


def finite(x: Any) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)
