"""Low-overhead evaluation of CasADi functions from Python.

A plain ``casadi.Function`` call from Python converts every argument to a DM and costs
20–80 µs; :class:`BufferedFunction` binds preallocated numpy arrays to the function's
inputs and outputs once (``Function.buffer``) so that an evaluation costs well under 1 µs
plus the numerical work. Outputs are dense; matrices come back as numpy arrays in
column-major layout, reshaped to their 2-D shape.

The compiled-code cache (:func:`cache_dir`): each library ``lipmpcc_<key>.so`` has a sidecar
``lipmpcc_<key>.so.sha256`` (its size and SHA-256, written atomically after the library). A library
is loaded only when it matches its sidecar: a truncated or corrupted library (which would kill the
process with a bus error when loaded) or one without a sidecar is compiled again and replaces it
atomically (a warning, once per process, for a damaged library).

Compiling takes about a second per 5000 instructions of the function. Functions up to
:data:`MAX_JIT_INSTRUCTIONS` are compiled before their first evaluation. Larger ones up to
:data:`MAX_BACKGROUND_JIT_INSTRUCTIONS` (the MPCC with four or eight obstacle slots, the timed MPCC with
two or more) would keep a first run waiting 5–30 s: they are compiled by one background thread of the
process while the interpreted function serves the evaluations, and :class:`BufferedFunction` swaps the
compiled one in at its next evaluation once the library is ready (``LIPMPCC_BACKGROUND_JIT=0``: those
stay interpreted). The swap does not change any result: the generated C performs the interpreted
function's operations in the same order, so both give the same numbers to the bit (a test checks it).
A library already in the cache is loaded at once, whatever its size. The C++ SQP asked for explicitly
(``backend="cpp"``) evaluates a function that is not compiled yet through :meth:`BufferedFunction.eval_into` (a
callback) and the library once it is ready: the same numbers either way, so its results depend neither on the
cache nor on when the compile ends.
"""

from __future__ import annotations

import atexit
import hashlib
import json
import logging
import os
import shutil
import subprocess
import tempfile
import queue
import threading
from concurrent.futures import Future
from pathlib import Path
from typing import Sequence

import casadi as ca
import numpy as np

__all__ = ["BufferedFunction", "jit_available", "cache_dir", "MAX_JIT_INSTRUCTIONS", "MAX_BACKGROUND_JIT_INSTRUCTIONS"]

_log = logging.getLogger(__name__)
_JIT_CACHE: dict[str, tuple[ca.Function, Path]] = {}
_JIT_BROKEN = False
_WARNED_DAMAGED = False
#: functions up to this size are compiled before their first evaluation (a few seconds at most: 13 000 takes about
#: 3 s of gcc, once per problem and cache; the timed MPCC on a circle, 12 092, so runs on the C++ SQP, about five
#: times faster per solve than the Python one; ``LIPMPCC_JIT_MAX_INSTRUCTIONS`` in the environment replaces it)
MAX_JIT_INSTRUCTIONS = 13000
#: larger ones up to this size are compiled in the background (see the module's docstring); still larger
#: ones (e.g. very long spline paths, whose piecewise coefficients grow the expression) stay interpreted
MAX_BACKGROUND_JIT_INSTRUCTIONS = 80000
_PENDING: dict[str, "Future[tuple[ca.Function, Path] | None]"] = {}
_COMPILER_PROCS: set[subprocess.Popen] = set()
_LOCK = threading.Lock()
_QUEUE: "queue.Queue[tuple[Future, ca.Function, str]] | None" = None


def _max_instructions() -> int:
    """The JIT's size limit: ``LIPMPCC_JIT_MAX_INSTRUCTIONS`` when set (an integer), else :data:`MAX_JIT_INSTRUCTIONS`."""
    raw = os.environ.get("LIPMPCC_JIT_MAX_INSTRUCTIONS", "").strip()
    if not raw:
        return MAX_JIT_INSTRUCTIONS
    try:
        return int(raw)
    except ValueError:
        from ..exceptions import InvalidInputError

        raise InvalidInputError("LIPMPCC_JIT_MAX_INSTRUCTIONS", raw, "an integer (environment variable)") from None


def _compiler() -> str | None:
    return shutil.which("gcc") or shutil.which("cc")


def jit_available() -> bool:
    """True when a C compiler is on the PATH and no compilation has failed so far."""
    return not _JIT_BROKEN and _compiler() is not None


def cache_dir() -> Path:
    """Where compiled CasADi functions are kept (``LIPMPCC_CACHE_DIR``, default ~/.cache/lipmpcc)."""
    return Path(os.environ.get("LIPMPCC_CACHE_DIR", Path.home() / ".cache" / "lipmpcc"))


def _sidecar(so: Path) -> Path:
    """The file holding the size and SHA-256 of the cached library ``so``."""
    return so.with_name(so.name + ".sha256")


def _fingerprint(path: Path) -> dict[str, object]:
    """{"size": bytes, "sha256": hex digest} of a file."""
    data = path.read_bytes()
    return {"size": len(data), "sha256": hashlib.sha256(data).hexdigest()}


def _write_sidecar(so: Path) -> None:
    """Record ``so``'s fingerprint beside it (atomically: a reader sees the old sidecar, the new one or none)."""
    side = _sidecar(so)
    fd, tmp = tempfile.mkstemp(dir=so.parent, prefix=side.name, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        json.dump(_fingerprint(so), f)
    os.replace(tmp, side)


def _verified(so: Path) -> bool:
    """Whether the cached library ``so`` exists and matches its sidecar (then it may be loaded).

    A library that does not (truncated, corrupted, an unreadable record: a warning, once per process;
    no record, from an older cache or an interrupted build: an info message) must be compiled again;
    the new library replaces it atomically, so that another process never finds it missing.
    """
    global _WARNED_DAMAGED
    if not so.exists():
        return False
    level = logging.WARNING
    try:
        ok = json.loads(_sidecar(so).read_text()) == _fingerprint(so)
        why = "its size or SHA-256 does not match its record (truncated or corrupted)"
    except FileNotFoundError:
        ok, why, level = False, "it has no size/SHA-256 record (an older cache or an interrupted build)", logging.INFO
    except (OSError, ValueError):
        ok, why = False, "its size/SHA-256 record is unreadable"
    if ok:
        return True
    if level == logging.WARNING:
        level = logging.DEBUG if _WARNED_DAMAGED else level
        _WARNED_DAMAGED = True
    _log.log(level, "compiled-code cache: %s is not loaded because %s; it is compiled again", so, why)
    return False


def _compile(fun: ca.Function, name: str, d: Path, so: Path) -> None:
    """Generate C for ``fun`` as ``name``, compile it into ``so`` (atomic replace) and record its fingerprint."""
    with tempfile.TemporaryDirectory(dir=d) as tmp:
        src = Path(tmp) / f"{name}.c"
        cg = ca.CodeGenerator(f"{name}.c", {"with_header": False})
        cg.add(ca.Function(name, fun.sx_in(), fun.call(fun.sx_in())))
        cg.generate(tmp + os.sep)
        out = Path(tmp) / f"{name}.so"
        _run_compiler([_compiler(), "-O2", "-fPIC", "-shared", str(src), "-o", str(out), "-lm"])
        os.replace(out, so)  # atomic: concurrent processes never see half a library
    _write_sidecar(so)


def _run_compiler(cmd: list[str]) -> None:
    """Run the C compiler (at most 300 s); it is stopped if the process exits first (:func:`_stop_compilers`)."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    with _LOCK:
        _COMPILER_PROCS.add(proc)
    try:
        _, err = proc.communicate(timeout=300)
    except subprocess.TimeoutExpired:
        _kill(proc)
        proc.communicate()
        raise
    finally:
        with _LOCK:
            _COMPILER_PROCS.discard(proc)
    if proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, cmd, stderr=err)


@atexit.register
def _stop_compilers() -> None:
    """At exit, stop background compiles still running (their temporary files go with them; a later
    process compiles the function again)."""
    with _LOCK:
        procs = list(_COMPILER_PROCS)
    for proc in procs:
        _kill(proc)


def _kill(proc: subprocess.Popen) -> None:
    """Kill the compiler and the passes it started (its own process group: ``cc1`` outlives a killed ``gcc``)."""
    try:
        os.killpg(proc.pid, 9)
    except (ProcessLookupError, PermissionError):
        pass


def _key(fun: ca.Function) -> str:
    """The cache key of ``fun``: a hash of its serialised form."""
    return hashlib.sha1(fun.serialize().encode()).hexdigest()[:20]


def _background(fun: ca.Function) -> "Future[tuple[ca.Function, Path] | None] | None":
    """The pending background compile of ``fun`` (started now if none is), or None when ``fun`` is
    not to be compiled in the background (too small or too large, no compiler, switched off)."""
    global _QUEUE
    n = fun.n_instructions()
    if (not jit_available() or not _max_instructions() < n <= MAX_BACKGROUND_JIT_INSTRUCTIONS
            or os.environ.get("LIPMPCC_BACKGROUND_JIT", "1") == "0"):
        return None
    key = _key(fun)
    with _LOCK:
        if key not in _PENDING:
            if _QUEUE is None:  # one compile at a time (a C compile takes a whole core), on a daemon
                _QUEUE = queue.Queue()  # thread: the process's exit does not wait for it
                threading.Thread(target=_compile_worker, args=(_QUEUE,), name="lipmpcc-jit", daemon=True).start()
            _PENDING[key] = Future()
            _QUEUE.put((_PENDING[key], fun, key))
        return _PENDING[key]


def _after_fork() -> None:
    """In a forked child: no compile thread yet (the parent's does not exist here)."""
    global _QUEUE, _LOCK
    _QUEUE, _LOCK = None, threading.Lock()
    _PENDING.clear()
    _COMPILER_PROCS.clear()


os.register_at_fork(after_in_child=_after_fork)


def _compile_worker(jobs: "queue.Queue[tuple[Future, ca.Function, str]]") -> None:
    """The background thread: compile the queued functions one after the other."""
    while True:
        done, fun, key = jobs.get()
        if done.set_running_or_notify_cancel():
            done.set_result(_compile_quietly(fun, key))


def _compile_quietly(fun: ca.Function, key: str) -> tuple[ca.Function, Path] | None:
    """:func:`_load_or_compile` for a background thread: (the compiled function, its library), or None (and a
    warning) when it fails."""
    try:
        return _load_or_compile(fun, key)
    except Exception as exc:  # noqa: BLE001 - the interpreted function keeps serving
        _log.warning("background compile of a CasADi function failed (%s); it stays interpreted",
                     str(exc).splitlines()[0][:120] if str(exc) else type(exc).__name__)
        return None


def _load_or_compile(fun: ca.Function, key: str) -> tuple[ca.Function, Path]:
    """The compiled ``fun`` and its library: from the in-memory cache, the disk cache, or compiled now."""
    if key in _JIT_CACHE:
        return _JIT_CACHE[key]
    name = f"lipmpcc_{key}"
    d = cache_dir()
    d.mkdir(parents=True, exist_ok=True)
    so = d / f"{name}.so"
    if not _verified(so):  # missing or damaged: build it (the new library replaces a damaged one)
        _compile(fun, name, d, so)
    compiled = ca.external(name, str(so))
    _JIT_CACHE[key] = (compiled, so)
    return compiled, so


def _cached(fun: ca.Function) -> tuple[ca.Function, Path] | None:
    """The compiled ``fun`` and its library when it is in the in-memory or the disk cache (no compile), else None."""
    if not jit_available():
        return None
    key = _key(fun)
    if key in _JIT_CACHE:
        return _JIT_CACHE[key]
    so = cache_dir() / f"lipmpcc_{key}.so"
    if not _verified(so):
        return None
    try:
        return _load_or_compile(fun, key)
    except Exception:  # noqa: BLE001 - an unloadable library: compiled again later
        return None


def _jit(fun: ca.Function) -> tuple[ca.Function, Path | None, bool]:
    """Compile ``fun`` to a shared library with the system C compiler and load it (see :func:`_jit_library`);
    a function above the size limit: its compiled library when the cache has one, else ``fun`` (and None).
    Returns (the function, its library or None, whether it was compiled because it is within the size limit)."""
    compiled, so = _jit_library(fun)
    if so is None and jit_available() and fun.n_instructions() > _max_instructions():
        cached = _cached(fun)
        return (fun, None, False) if cached is None else (*cached, False)
    return compiled, so, so is not None


def _jit_library(fun: ca.Function) -> tuple[ca.Function, Path | None]:
    """Compile ``fun`` to a shared library with the system C compiler and load it: (the loaded function, the
    library's path; its C symbol is the function's name), or (``fun``, None) when it stays interpreted.

    The library is cached on disk by a hash of the function's serialised form (so a later
    process reuses it, after checking it against its recorded size and SHA-256) and in memory
    (so planners for the same problem share it). Falls back to the interpreted ``fun`` when no
    compiler works or the function is larger than :data:`MAX_JIT_INSTRUCTIONS` (or its override)."""
    global _JIT_BROKEN
    if not jit_available() or fun.n_instructions() > _max_instructions():
        return fun, None
    try:
        return _load_or_compile(fun, _key(fun))
    except Exception as exc:  # no working compiler: stay interpreted
        _JIT_BROKEN = True
        _log.warning("CasADi code generation unavailable (%s); using interpreted functions", str(exc).splitlines()[0][:120])
        return fun, None


class BufferedFunction:
    """Wrap ``name(inputs) -> outputs`` (CasADi expressions) for fast repeated calls.

    Args:
        name: function name.
        inputs: symbolic inputs (column vectors).
        outputs: expressions; they are densified.
        jit: compile to machine code when a C compiler is available (~25× faster evaluation).

    Attributes:
        function: the CasADi function evaluated (the loaded library's, when compiled).
        jit: whether compiled code was asked for (``jit``).
        eager: compiled before its first evaluation because it is within the JIT's size limit (whatever the cache
            holds; a larger function may be compiled too, from the cache or in the background, depending on the
            cache and on timing): the C++ SQP's backend ``"auto"`` takes only such functions, so that which
            backend runs a problem never depends on either.
        so: the compiled library's path (its C symbol is :attr:`symbol`; CasADi's C interface), or None
            while the function is interpreted (``jit`` off, no compiler, or above the size limit and not in the
            cache: then compiled in the background, see :attr:`pending`, and set once swapped in).
        pending: a background compile that will replace :attr:`function`, or None.
        symbol: the C name of the compiled function in :attr:`so`, or None.
        in_sizes, out_shapes: the inputs' sizes and the outputs' (rows, columns).
    """

    def __init__(self, name: str, inputs: Sequence[ca.SX], outputs: Sequence[ca.SX], jit: bool = False) -> None:
        self.function = ca.Function(name, list(inputs), [ca.densify(o) for o in outputs])
        self.pending: "Future[tuple[ca.Function, Path] | None] | None" = None
        self.so: Path | None = None
        self.symbol: str | None = None
        self.jit = bool(jit)
        self.eager = False
        self.in_sizes = [int(x.numel()) for x in inputs]
        self.out_shapes = [(int(o.shape[0]), int(o.shape[1])) for o in outputs]
        if jit:
            self.function, self.so, self.eager = _jit(self.function)  # a large one: from the cache, if it is there
            self.symbol = self.function.name() if self.so is not None else None
            if not self.compiled:
                self.pending = _background(self.function)
        self._args = [np.zeros(int(x.numel())) for x in inputs]
        self._res = [np.zeros(int(o.numel())) for o in outputs]
        self._views = [r if int(o.shape[1]) == 1 else r.reshape((int(o.shape[0]), int(o.shape[1])), order="F")
                       for r, o in zip(self._res, outputs)]
        self._bind()

    @property
    def compiled(self) -> bool:
        """Whether the function evaluates as compiled machine code (not interpreted)."""
        return self.function.class_name() == "External"

    def _bind(self) -> None:
        """Bind the argument and result arrays to a buffer of ``function``."""
        self._buf, self._eval = self.function.buffer()
        for i, a in enumerate(self._args):
            self._buf.set_arg(i, memoryview(a))
        for j, r in enumerate(self._res):
            self._buf.set_res(j, memoryview(r))

    def poll(self) -> bool:
        """Take a finished background compile (as the next evaluation would); whether the function is compiled."""
        if self.pending is not None:
            self._swap()
        return self.compiled

    def _swap(self) -> None:
        """Take the background compile's result when it is ready (the same numbers to the bit, faster)."""
        pending = self.pending
        if pending is not None and pending.done():
            self.pending = None
            compiled = pending.result()
            if compiled is not None:
                self.function, self.so = compiled
                self.symbol = self.function.name()
                self._bind()

    def __call__(self, *args: np.ndarray) -> list[np.ndarray]:
        """Evaluate; returns views into internal buffers (copy them to keep them)."""
        for dst, src in zip(self._args, args):
            np.copyto(dst, np.ravel(src), casting="unsafe")
        if self.pending is not None:
            self._swap()
        self._eval()
        return self._views

    def eval_into(self, args: Sequence[np.ndarray], res: Sequence[np.ndarray | None]) -> None:
        """Evaluate with ``args`` (flat, one per input) into ``res`` (flat column-major arrays, one per output; None:
        not wanted): the C++ SQP's callback while the function is interpreted. Takes a finished background
        compile (the same numbers) as ``__call__`` does."""
        for dst, src in zip(self._args, args):
            np.copyto(dst, src)
        if self.pending is not None:
            self._swap()
        self._eval()
        for dst, src in zip(res, self._res):
            if dst is not None:
                np.copyto(dst, src)

    def set_arg(self, i: int, value: np.ndarray) -> None:
        """Bind the value of input ``i`` for the following :meth:`evaluate` calls (as ``__call__`` does)."""
        np.copyto(self._args[i], np.ravel(value), casting="unsafe")

    def evaluate(self, *first: np.ndarray) -> list[np.ndarray]:
        """Evaluate with new values of the first ``len(first)`` inputs and the others as last set (by
        :meth:`set_arg` or a call); returns views into internal buffers, as ``__call__``."""
        for dst, src in zip(self._args, first):
            np.copyto(dst, src, casting="unsafe")
        if self.pending is not None:
            self._swap()
        self._eval()
        return self._views
