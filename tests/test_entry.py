"""lipmpcc._entry: the program ends a Ctrl-C with one line and exit 130 at any moment — during the
imports, the run, or while the process exits — never with a traceback or killed by SIGINT."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from .conftest import package_env, default_sigint


def _line_path(tmp_path: Path) -> Path:
    f = tmp_path / "line.csv"
    f.write_text("x,y\n" + "".join(f"{x},0\n" for x in range(0, 2000, 10)))
    return f


@pytest.fixture(scope="module")
def startup_s() -> float:
    """How long this machine's interpreter takes to start (``site`` imported, nothing else) [s]: a Ctrl-C
    before that ends inside CPython's own start-up, before any program runs (``Fatal Python error:
    init_import_site``, exit 1), which no program can answer. Under load (e.g. beside pytest-xdist's other
    worker) it can exceed 0.15 s."""
    runs = []
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], env=package_env(), check=True)
        runs.append(time.perf_counter() - t0)
    return max(runs)


@pytest.mark.parametrize("delay", [0.15, 0.4, 0.8, 1.5])
def test_a_ctrl_c_at_any_moment_is_one_line_and_130(delay: float, startup_s: float, tmp_path: Path) -> None:
    """``delay`` after the interpreter's start-up: 0.15 s is during lipmpcc's imports."""
    argv = [sys.executable, "-m", "lipmpcc", "run", "circle", "--robot", "lip", "--steps", "3000",
            "--path", str(_line_path(tmp_path)), "--out", str(tmp_path / "out")]
    p = subprocess.Popen(argv, preexec_fn=default_sigint, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=package_env())
    time.sleep(startup_s + delay)
    p.send_signal(signal.SIGINT)
    t0 = time.perf_counter()
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err[-2000:]
    assert err.splitlines()[-1] == "lipmpcc: interrupted" and "Traceback" not in err
    assert time.perf_counter() - t0 < 5.0
    assert not (tmp_path / "out").exists()  # nothing half written


def test_repeated_ctrl_c_do_not_break_the_clean_up(tmp_path: Path) -> None:
    argv = [sys.executable, "-m", "lipmpcc", "run", "circle", "--robot", "lip", "--steps", "3000",
            "--path", str(_line_path(tmp_path)), "--out", str(tmp_path / "out")]
    p = subprocess.Popen(argv, preexec_fn=default_sigint, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=package_env())
    time.sleep(1.0)
    for _ in range(4):
        p.send_signal(signal.SIGINT)
        time.sleep(0.05)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130 and "Traceback" not in err, err[-2000:]
    assert err.count("lipmpcc: interrupted") == 1


def test_a_ctrl_c_swallowed_during_the_imports_still_interrupts(monkeypatch) -> None:
    """An extension being imported may catch the KeyboardInterrupt; the program still answers it (it ran the
    command to its end, and CPython then killed itself with SIGINT at exit)."""
    import builtins
    import os
    import signal as sig

    from lipmpcc import _entry

    real_import = builtins.__import__

    def swallowing_import(name, *args, **kwargs):  # an import during which Ctrl-C is pressed and swallowed
        if name == "" and args and args[2] == ("cli",):
            try:
                os.kill(os.getpid(), sig.SIGINT)
                time.sleep(0.5)
            except KeyboardInterrupt:
                pass
        return real_import(name, *args, **kwargs)

    exits = []
    monkeypatch.setattr(builtins, "__import__", swallowing_import)
    monkeypatch.setattr(_entry.os, "_exit", lambda code: (exits.append(code), (_ for _ in ()).throw(SystemExit(code))))
    monkeypatch.setattr(_entry, "_EARLY", [])
    previous = sig.getsignal(sig.SIGINT)
    sig.signal(sig.SIGINT, sig.default_int_handler)
    try:
        with pytest.raises(SystemExit):
            _entry._import_cli()
    finally:
        sig.signal(sig.SIGINT, previous)
    assert exits == [130]

