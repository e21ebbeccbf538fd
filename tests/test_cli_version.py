"""`lipmpcc --version`, and `lipmpcc reproduce --only` matching no study (issue 14)."""

from __future__ import annotations

import subprocess
import sys

import pytest

import lipmpcc
from lipmpcc.cli import EXIT_USAGE, main
from lipmpcc.exceptions import InvalidInputError
from lipmpcc.reproduce import all_studies, reproduce, select_studies


def test_version_prints_the_package_version_and_exits_0(capsys) -> None:
    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0
    assert capsys.readouterr().out == f"lipmpcc {lipmpcc.__version__}\n"
    assert lipmpcc.__version__ == "0.2.0.dev0"


def test_version_from_the_command_line() -> None:
    r = subprocess.run([sys.executable, "-m", "lipmpcc", "--version"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and r.stdout.strip() == "lipmpcc 0.2.0.dev0" and r.stderr == ""


def test_reproduce_only_matching_no_study_exits_2_with_one_line(tmp_path, capsys) -> None:
    out = tmp_path / "report"
    assert main(["reproduce", "--fast", "--only", "nomatch", "--out", str(out)]) == EXIT_USAGE
    captured = capsys.readouterr()
    lines = [ln for ln in captured.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("lipmpcc: error: --only = 'nomatch'")
    assert "matches no study" in lines[0]
    for prefix in ("lip-", "alip-", "digit-"):
        assert prefix in lines[0]
    assert captured.out == "" and not out.exists()  # nothing run, no report written


def test_select_studies_and_reproduce_refuse_a_prefix_matching_nothing(tmp_path) -> None:
    names = [st.name for st in select_studies("lip-")]
    assert names == ["lip-circle", "lip-circle-push", "lip-overtake-cartesian", "lip-overtake-mpcc"]
    assert len(select_studies(None)) == len(all_studies())
    with pytest.raises(InvalidInputError, match="--only = ''"):
        select_studies("")  # not "every study": an empty prefix is a mistake
    with pytest.raises(InvalidInputError, match="matches no study"):
        select_studies("LIP-")  # case counts
    with pytest.raises(InvalidInputError, match="--only"):
        reproduce(tmp_path / "r", only="zzz")
    assert not (tmp_path / "r").exists()
