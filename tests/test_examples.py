"""Every script of ``examples/`` runs, as a student runs it, in fast mode, and writes its figure."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SCRIPTS = sorted(p.name for p in EXAMPLES.glob("*.py") if not p.name.startswith("_") and p.name != "my_planner.py")


def test_every_example_is_listed_in_its_readme() -> None:
    text = (EXAMPLES / "README.md").read_text()
    assert SCRIPTS and all(f"`{name}`" in text for name in SCRIPTS + ["my_planner.py"])


@pytest.mark.parametrize("script", SCRIPTS)
def test_example_runs_and_writes_its_figure(script: str, tmp_path: Path) -> None:
    env = dict(os.environ, LIPMPCC_FAST="1", MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(EXAMPLES / script), "--out", str(tmp_path)], env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert (tmp_path / script.replace(".py", ".png")).is_file()
    assert "fell=True" not in proc.stdout and "Traceback" not in proc.stderr


def test_the_readmes_own_planner_snippet_runs_as_written() -> None:
    # README, "In Python: a planner of your own": the only code block a student copies from the README
    import re

    text = (EXAMPLES.parent / "README.md").read_text()
    (block,) = re.findall(r"```python\n(.*?)```", text, re.S)
    namespace: dict = {}
    exec(compile(block, "README.md", "exec"), namespace)  # noqa: S102 - the README's own code
    result = namespace["result"]
    assert not result.fell and result.n_steps == 20
