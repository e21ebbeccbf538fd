"""lipmpcc.solvers.casadi_buffer.BufferedFunction: a buffered CasADi function equals the direct call."""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from ..conftest import package_env

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.solvers import casadi_buffer
from lipmpcc.solvers.casadi_buffer import BufferedFunction


def _tiny() -> tuple[list[ca.SX], list[ca.SX]]:
    x = ca.SX.sym("x", 3)
    y = ca.SX.sym("y", 2)
    vec = ca.vertcat(x[0] * y[0], ca.sin(x[1]) + y[1], x[2] ** 2)
    mat = ca.horzcat(x[:2], y, x[1:] * y[0])  # 2 x 3: comes back column-major, reshaped
    sparse = ca.diag(x)  # densified
    return [x, y], [vec, mat, sparse]


def test_buffered_evaluation_equals_the_direct_call() -> None:
    inputs, outputs = _tiny()
    f = BufferedFunction("tiny", inputs, outputs)
    direct = ca.Function("direct", inputs, outputs)
    x, y = np.array([0.3, -1.2, 2.0]), np.array([[4.0], [0.5]])  # any shape: raveled
    vec, mat, sparse = f(x, y)
    want = [np.asarray(ca.DM(w)) for w in direct(x, y.ravel())]
    assert vec.shape == (3,) and mat.shape == (2, 3) and sparse.shape == (3, 3)
    np.testing.assert_array_equal(vec, want[0].ravel())
    np.testing.assert_array_equal(mat, want[1])
    np.testing.assert_array_equal(sparse, np.diag(x))
    # the results are views into the buffers: the next call overwrites them
    first = vec.copy()
    again = f(2 * x, y)
    assert again[0] is vec and not np.array_equal(vec, first)


def test_jit_compiled_function_gives_the_same_values(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    if not casadi_buffer.jit_available():
        pytest.skip("no C compiler on the PATH")
    monkeypatch.setenv("LIPMPCC_CACHE_DIR", str(tmp_path))
    assert casadi_buffer.cache_dir() == tmp_path
    inputs, outputs = _tiny()
    plain, fast = BufferedFunction("tiny", inputs, outputs), BufferedFunction("tiny", inputs, outputs, jit=True)
    x, y = np.array([0.3, -1.2, 2.0]), np.array([4.0, 0.5])
    for a, b in zip(plain(x, y), fast(x, y)):
        np.testing.assert_allclose(a, b, rtol=1e-15, atol=0.0)
    assert list(tmp_path.glob("lipmpcc_*.so")), "the compiled library is cached on disk"


_JIT_SCRIPT = """
import casadi as ca, numpy as np
from lipmpcc.solvers.casadi_buffer import BufferedFunction
x = ca.SX.sym("x", 3); y = ca.SX.sym("y", 2)
f = BufferedFunction("tiny", [x, y], [ca.vertcat(x[0] * y[0], ca.sin(x[1]) + y[1], x[2] ** 2)], jit=True)
print(repr(f(np.array([0.3, -1.2, 2.0]), np.array([4.0, 0.5]))[0].tolist()))
"""


def _run_jit(cache: Path) -> "subprocess.CompletedProcess[str]":
    import os
    import subprocess
    import sys

    env = {**package_env(), "LIPMPCC_CACHE_DIR": str(cache)}
    return subprocess.run([sys.executable, "-c", _JIT_SCRIPT], capture_output=True, text=True, timeout=300, env=env)


def _truncate(so: Path) -> None:
    so.write_bytes(so.read_bytes()[:3000])


def _flip_a_byte(so: Path) -> None:
    data = bytearray(so.read_bytes())
    data[len(data) // 2] ^= 0xFF
    so.write_bytes(bytes(data))


@pytest.mark.parametrize("damage", [_truncate, _flip_a_byte])
def test_a_damaged_cached_library_is_compiled_again(tmp_path: Path, damage) -> None:
    """A truncated cached library killed the process with a bus error (rc 135) when loaded; a corrupted
    one of the right size could run wrong code. Each cached library is checked against its recorded
    size and SHA-256 first: a damaged one is compiled again (one warning) and gives the same values."""
    if not casadi_buffer.jit_available():
        pytest.skip("no C compiler on the PATH")
    first = _run_jit(tmp_path)
    assert first.returncode == 0, first.stderr
    (so,) = tmp_path.glob("lipmpcc_*.so")
    assert so.with_name(so.name + ".sha256").is_file()
    again = _run_jit(tmp_path)  # a sound library: loaded as is, no message
    assert again.returncode == 0 and again.stdout == first.stdout and "compiled again" not in again.stderr
    damage(so)
    third = _run_jit(tmp_path)
    assert third.returncode == 0, third.stderr[-2000:]
    assert third.stdout == first.stdout
    assert third.stderr.count("compiled again") == 1 and "does not match its record" in third.stderr
    fourth = _run_jit(tmp_path)  # the rebuilt library is sound again
    assert fourth.returncode == 0 and fourth.stdout == first.stdout and "compiled again" not in fourth.stderr


def test_a_cached_library_without_its_record_is_not_loaded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                            caplog: pytest.LogCaptureFixture) -> None:
    """A library without a size/SHA-256 record (an older cache, an interrupted build) cannot be checked:
    it is compiled again (an info message, not a warning) rather than loaded."""
    so = tmp_path / "lipmpcc_0123.so"
    so.write_bytes(b"\x7fELF truncated")
    with caplog.at_level("INFO", logger=casadi_buffer.__name__):
        assert not casadi_buffer._verified(so)
    assert [r.levelname for r in caplog.records] == ["INFO"] and "no size/SHA-256 record" in caplog.text
    casadi_buffer._write_sidecar(so)
    assert casadi_buffer._verified(so)
    so.write_bytes(b"\x7fELF changed!!")  # same size, other bytes
    monkeypatch.setattr(casadi_buffer, "_WARNED_DAMAGED", False)
    caplog.clear()
    with caplog.at_level("DEBUG", logger=casadi_buffer.__name__):
        assert not casadi_buffer._verified(so) and not casadi_buffer._verified(so)
    assert [r.levelname for r in caplog.records] == ["WARNING", "DEBUG"], "one warning per process"


def _chain(n: int) -> tuple[list[ca.SX], list[ca.SX]]:
    """A function of a few hundred instructions (enough to be above a lowered size limit)."""
    x = ca.SX.sym("x", 4)
    y = x
    for k in range(n):
        y = ca.vertcat(ca.sin(y[1]) * y[0] + k, y[2] * y[3], ca.cos(y[0]) - y[2], y[0] + 0.5 * y[3])
    return [x], [y, ca.jacobian(y, x)]


def test_a_large_function_is_compiled_in_the_background_and_swapped_in_unchanged(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Above MAX_JIT_INSTRUCTIONS the function starts interpreted, a background thread compiles it, and the
    next evaluation after the compile uses the compiled code: the same numbers to the bit."""
    if not casadi_buffer.jit_available():
        pytest.skip("no C compiler on the PATH")
    monkeypatch.setenv("LIPMPCC_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("LIPMPCC_BACKGROUND_JIT", "1")
    monkeypatch.setattr(casadi_buffer, "MAX_JIT_INSTRUCTIONS", 10)
    inputs, outputs = _chain(30)
    f = BufferedFunction("chain", inputs, outputs, jit=True)
    assert not f.compiled and f.pending is not None
    x = np.array([0.3, -0.2, 0.7, 1.1])
    before = [v.copy() for v in f(x)]
    assert f.pending.result(timeout=120) is not None
    after = f(x)
    assert f.compiled and f.pending is None
    for a, b in zip(before, after):
        np.testing.assert_array_equal(a, b)
    again = BufferedFunction("chain", inputs, outputs, jit=True)  # now in the cache: compiled at once
    assert again.compiled and again.pending is None


def test_background_compiles_can_be_switched_off_and_size_bounded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("LIPMPCC_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(casadi_buffer, "MAX_JIT_INSTRUCTIONS", 10)
    inputs, outputs = _chain(3)
    monkeypatch.setenv("LIPMPCC_BACKGROUND_JIT", "0")
    off = BufferedFunction("chain", inputs, outputs, jit=True)
    assert not off.compiled and off.pending is None
    monkeypatch.setenv("LIPMPCC_BACKGROUND_JIT", "1")
    monkeypatch.setattr(casadi_buffer, "MAX_BACKGROUND_JIT_INSTRUCTIONS", 11)
    too_big = BufferedFunction("chain", inputs, outputs, jit=True)
    assert not too_big.compiled and too_big.pending is None


def test_a_running_compile_is_stopped_at_exit() -> None:
    """The process's exit kills a background compile and the passes it started (not left running)."""
    import subprocess
    import threading
    import time

    failed: list[BaseException] = []

    def run() -> None:
        try:
            casadi_buffer._run_compiler(["sh", "-c", "sleep 60 & wait"])
        except subprocess.CalledProcessError as exc:
            failed.append(exc)

    t = threading.Thread(target=run)
    t.start()
    time.sleep(0.3)
    t0 = time.monotonic()
    casadi_buffer._stop_compilers()
    t.join(timeout=10)
    assert not t.is_alive() and failed and time.monotonic() - t0 < 10


def test_compiled_library_is_named_and_the_size_limit_can_be_set(monkeypatch) -> None:
    """A JIT-compiled function names its library and C symbol (the C++ SQP loads them); an interpreted one
    names none; LIPMPCC_JIT_MAX_INSTRUCTIONS replaces the size limit (a bad value is named)."""
    inputs, outputs = _tiny()
    assert BufferedFunction("tiny_interp", inputs, outputs).so is None
    if not casadi_buffer.jit_available():
        pytest.skip("no C compiler")
    f = BufferedFunction("tiny_named", inputs, outputs, jit=True)
    assert f.so is not None and f.so.is_file() and f.symbol == f.so.stem
    monkeypatch.setenv("LIPMPCC_JIT_MAX_INSTRUCTIONS", "1")  # smaller than the function: interpreted
    assert BufferedFunction("tiny_limited", inputs, outputs, jit=True).so is None
    monkeypatch.setenv("LIPMPCC_JIT_MAX_INSTRUCTIONS", "many")
    with pytest.raises(InvalidInputError, match="LIPMPCC_JIT_MAX_INSTRUCTIONS"):
        BufferedFunction("tiny_bad", inputs, outputs, jit=True)


def test_the_timed_mpcc_on_a_circle_fits_the_synchronous_jit():
    """The timed MPCC on a circle without obstacles (12 092 instructions) is compiled before its first evaluation,
    so that it runs on the C++ SQP (issue 28; larger ones, with obstacle slots, go to the background compile)."""
    from lipmpcc.paths import ArcPath
    from lipmpcc.planners.liveness import problem_path
    from lipmpcc.planners.mpcc import MpccParams, build_sqp
    from lipmpcc.planners.mpcc_timed import TimedMpccParams

    prm = TimedMpccParams(mpcc=MpccParams.circle(jit=False), T_min=0.3, T_max=0.5)
    path = problem_path(ArcPath.circle(2.0, turns=1.25), True, prm.mpcc.N * prm.mpcc.v_max)
    sizes = [build_sqp(path, prm, n).f_all.function.n_instructions() for n in (0, 1)]
    assert sizes[0] <= casadi_buffer.MAX_JIT_INSTRUCTIONS < sizes[1]
