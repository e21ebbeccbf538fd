"""The old ``lipmpcc.scenarios`` paths keep working for one release, with a DeprecationWarning, and give
the new objects; the package's own imports raise none."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

OLD_TO_NEW = [
    ("lipmpcc.scenarios", "RunOptions", "lipmpcc.studies", "RunOptions"),
    ("lipmpcc.scenarios", "run", "lipmpcc.studies", "run"),
    ("lipmpcc.scenarios.path_following", "PAPER_SPEED", "lipmpcc.studies.path_following", "PAPER_SPEED"),
    ("lipmpcc.scenarios.path_following", "SETTLE_TIME", "lipmpcc.studies.path_following", "SETTLE_TIME"),
    ("lipmpcc.scenarios.fullbody_path_following", "simulate", "lipmpcc.studies.path_following", "simulate_full_body"),
    ("lipmpcc.scenarios.fullbody_path_following", "FullBodyPathLog", "lipmpcc.plots.logs", "PathFollowingLog"),
    ("lipmpcc.scenarios.fullbody_path_following", "SETTLE_TIME", "lipmpcc.studies.path_following", "FULLBODY_SETTLE_TIME"),
    ("lipmpcc.scenarios.fullbody_path_following", "render_frames", "lipmpcc.studies.path_following", "render_frames"),
    ("lipmpcc.scenarios.stepping_stones", "run_case", "lipmpcc.studies.stepping_stones", "run_case"),
    ("lipmpcc.scenarios.stepping_stones", "paper_cases", "lipmpcc.terrain", "paper_cases"),
    ("lipmpcc.scenarios.stepping_stones", "table_markdown", "lipmpcc.report", "table_markdown"),
    ("lipmpcc.scenarios.stepping_stones", "sweep_markdown", "lipmpcc.report", "sweep_markdown"),
    ("lipmpcc.scenarios.fullbody_stepping_stones", "simulate", "lipmpcc.studies.stepping_stones", "simulate_full_body"),
    ("lipmpcc.scenarios.fullbody_stepping_stones", "study_table", "lipmpcc.studies.stepping_stones", "study_table_full_body"),
    ("lipmpcc.scenarios.fullbody_stepping_stones", "to_alip_log", "lipmpcc.studies.stepping_stones", "full_body_stones_log"),
    ("lipmpcc.scenarios.fullbody_stepping_stones", "paper_cases_fullbody", "lipmpcc.studies.paper", "table_ii_cases"),
    ("lipmpcc.scenarios.fullbody_stepping_stones", "FullBodyStonesParams", "lipmpcc.studies.stepping_stones", "FullBodyStonesParams"),
    ("lipmpcc.scenarios.walking", "stand_pushes", "lipmpcc.studies.walking", "stand_pushes"),
]


@pytest.mark.parametrize("old, name, new, new_name", OLD_TO_NEW)
def test_old_path_warns_and_gives_the_new_object(old, name, new, new_name) -> None:
    mod = importlib.import_module(old)
    with pytest.warns(DeprecationWarning, match="removed in lipmpcc"):
        obj = getattr(mod, name)
    assert obj is getattr(importlib.import_module(new), new_name)


def test_paper_constants_warn_and_come_from_the_reference_file() -> None:
    mod = importlib.import_module("lipmpcc.scenarios.stepping_stones")
    with pytest.warns(DeprecationWarning, match="paper_results.json"):
        table = mod.PAPER_TABLE_II  # the numbers are in lipmpcc.studies.paper
    assert table["I L=0.4 W=+0.15"] == {"alip-mpc": 0.020, "alip-qp": 0.029} and table["II"]["alip-qp"] is None
    with pytest.warns(DeprecationWarning):
        assert mod.PAPER_PUSHES[1] == (10, (-150.0, 0.0)) and mod.PUSH_WINDOW == (0.1, 0.2)
    assert "table_markdown" in dir(mod) and "run_case" in dir(mod) and "PAPER_TABLE_II" in dir(mod)


def test_cli_write_outputs_is_deprecated(tmp_path) -> None:
    from lipmpcc import cli
    from lipmpcc.studies import RunResult

    with pytest.warns(DeprecationWarning, match="RunResult.save"):
        path = cli.write_outputs(RunResult(summary={"a": 1}), tmp_path)
    assert path.read_text().strip().startswith("{")


def test_the_package_imports_no_old_path() -> None:
    code = (
        "import warnings; warnings.simplefilter('error', DeprecationWarning)\n"
        "import lipmpcc.cli, lipmpcc.reproduce, lipmpcc.report\n"
        "import lipmpcc.studies.path_following, lipmpcc.studies.stepping_stones, lipmpcc.studies.walking\n"
        "from lipmpcc.reproduce import all_studies; assert len(all_studies()) == 52\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
