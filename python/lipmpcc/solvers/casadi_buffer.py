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
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Sequence

import casadi as ca
import numpy as np

__all__ = ["BufferedFunction", "jit_available", "cache_dir", "MAX_JIT_INSTRUCTIONS"]

_log = logging.getLogger(__name__)
_JIT_CACHE: dict[str, tuple[ca.Function, Path]] = {}
_JIT_BROKEN = False
_WARNED_DAMAGED = False
#: larger functions (e.g. long spline paths, whose piecewise coefficients grow the expression)
#: stay interpreted: their C compile would take tens of seconds (``LIPMPCC_JIT_MAX_INSTRUCTIONS`` in the
#: environment replaces this limit: the timed MPCC's terms function has 12 000–17 500 instructions with 0–2
#: obstacle slots, about 12 s of gcc for 17 500 on a loaded 2-core machine, once per cache)
MAX_JIT_INSTRUCTIONS = 12000


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
        subprocess.run(
            [_compiler(), "-O2", "-fPIC", "-shared", str(src), "-o", str(out), "-lm"],
            check=True, capture_output=True, timeout=300,
        )
        os.replace(out, so)  # atomic: concurrent processes never see half a library
    _write_sidecar(so)


def _jit(fun: ca.Function) -> ca.Function:
    """Compile ``fun`` to a shared library with the system C compiler and load it (see :func:`_jit_library`)."""
    return _jit_library(fun)[0]


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
    key = hashlib.sha1(fun.serialize().encode()).hexdigest()[:20]
    if key in _JIT_CACHE:
        return _JIT_CACHE[key]
    name = f"lipmpcc_{key}"
    try:
        d = cache_dir()
        d.mkdir(parents=True, exist_ok=True)
        so = d / f"{name}.so"
        if not _verified(so):  # missing or damaged: build it (the new library replaces a damaged one)
            _compile(fun, name, d, so)
        compiled = ca.external(name, str(so))
    except Exception as exc:  # no working compiler: stay interpreted
        _JIT_BROKEN = True
        _log.warning("CasADi code generation unavailable (%s); using interpreted functions", str(exc).splitlines()[0][:120])
        return fun, None
    _JIT_CACHE[key] = (compiled, so)
    return compiled, so


class BufferedFunction:
    """Wrap ``name(inputs) -> outputs`` (CasADi expressions) for fast repeated calls.

    Args:
        name: function name.
        inputs: symbolic inputs (column vectors).
        outputs: expressions; they are densified.
        jit: compile to machine code when a C compiler is available (~25× faster evaluation).

    Attributes:
        function: the CasADi function evaluated (the loaded library's, when compiled).
        so: the compiled library's path (its C symbol is :attr:`symbol`; CasADi's C interface), or None
            when the function is interpreted (``jit`` off, no compiler, or too large).
        symbol: the C name of the compiled function in :attr:`so`, or None.
    """

    def __init__(self, name: str, inputs: Sequence[ca.SX], outputs: Sequence[ca.SX], jit: bool = False) -> None:
        self.function = ca.Function(name, list(inputs), [ca.densify(o) for o in outputs])
        self.so: Path | None = None
        self.symbol: str | None = None
        if jit:
            self.function, self.so = _jit_library(self.function)
            self.symbol = self.function.name() if self.so is not None else None
        self._buf, self._eval = self.function.buffer()
        self._args = []
        for i, x in enumerate(inputs):
            a = np.zeros(int(x.numel()))
            self._buf.set_arg(i, memoryview(a))
            self._args.append(a)
        self._res = []
        self._views = []
        for j, o in enumerate(outputs):
            r = np.zeros(int(o.numel()))
            self._buf.set_res(j, memoryview(r))
            self._res.append(r)
            shape = (int(o.shape[0]), int(o.shape[1]))
            if shape[1] == 1:
                self._views.append(r)
            else:
                self._views.append(r.reshape(shape, order="F"))

    def __call__(self, *args: np.ndarray) -> list[np.ndarray]:
        """Evaluate; returns views into internal buffers (copy them to keep them)."""
        for dst, src in zip(self._args, args):
            np.copyto(dst, np.ravel(src), casting="unsafe")
        self._eval()
        return self._views

    def set_arg(self, i: int, value: np.ndarray) -> None:
        """Bind the value of input ``i`` for the following :meth:`evaluate` calls (as ``__call__`` does)."""
        np.copyto(self._args[i], np.ravel(value), casting="unsafe")

    def evaluate(self, *first: np.ndarray) -> list[np.ndarray]:
        """Evaluate with new values of the first ``len(first)`` inputs and the others as last set (by
        :meth:`set_arg` or a call); returns views into internal buffers, as ``__call__``."""
        for dst, src in zip(self._args, first):
            np.copyto(dst, src, casting="unsafe")
        self._eval()
        return self._views
