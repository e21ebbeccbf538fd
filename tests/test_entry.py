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


@pytest.mark.parametrize("delay", [0.15, 0.4, 0.8, 1.5])
def test_a_ctrl_c_at_any_moment_is_one_line_and_130(delay: float, tmp_path: Path) -> None:
    argv = [sys.executable, "-m", "lipmpcc", "run", "circle", "--robot", "lip", "--steps", "3000",
            "--path", str(_line_path(tmp_path)), "--out", str(tmp_path / "out")]
    p = subprocess.Popen(argv, preexec_fn=default_sigint, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=package_env())
    time.sleep(delay)
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
