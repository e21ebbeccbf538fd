"""Waypoint CSVs: an optional header, blank lines and ``#`` comments, as the stone reader accepts
them; the errors still name the file, the line and the bad value. Stone files: the same."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lipmpcc.exceptions import PathError, TerrainError
from lipmpcc.paths import load_path_csv, load_waypoints_csv
from lipmpcc.terrain import load_stones

WAYPOINTS = np.array([[0.0, 0.0], [1.0, 0.5], [2.0, 0.0]])


def _write(tmp_path: Path, text: str, name: str = "wp.csv") -> Path:
    f = tmp_path / name
    f.write_text(text)
    return f


@pytest.mark.parametrize(
    "text",
    [
        "x,y\n0,0\n1,0.5\n2,0\n",  # the header, as before
        "0,0\n1,0.5\n2,0\n",  # no header
        "# an S\n# frame: world [m]\nx,y\n0,0\n\n1,0.5\n# a comment between rows\n2,0\n\n",
        "# no header, comments and blank lines\n\n0,0\n1,0.5\n\n# end\n2,0\n",
        " X , Y \n 0 , 0 \n1,0.5\n2,0\n",  # header in capitals, spaces around the cells
        "y,x,name\n0,0,start\n0.5,1,top\n0,2,end\n",  # columns taken by name, others ignored
        "   # an indented comment\n0,0\n1,0.5\n2,0\n",
    ],
)
def test_every_accepted_layout_reads_the_same_waypoints(tmp_path: Path, text: str) -> None:
    w = load_waypoints_csv(_write(tmp_path, text))
    assert w.shape == (3, 2)
    assert np.array_equal(w, WAYPOINTS)


def test_a_headerless_file_makes_the_same_path_as_with_a_header(tmp_path: Path) -> None:
    a = load_path_csv(_write(tmp_path, "x,y\n0,0\n1,0.5\n2,0\n3,1\n", "a.csv"))
    b = load_path_csv(_write(tmp_path, "# comment\n0,0\n1,0.5\n\n2,0\n3,1\n", "b.csv"))
    assert a.length == b.length
    assert np.array_equal(a.sample(50), b.sample(50))


@pytest.mark.parametrize(
    ("text", "line", "value", "expected"),
    [
        ("# header next\nx,y\n0,0\nfoo,1\n", "line 4", "foo", "two numbers"),
        ("0,0\n\n# c\n1,bar\n", "line 4", "bar", "two numbers"),
        ("x,y\n0,0\n# c\nnan,1\n", "line 4", "nan", "finite"),
        ("0,0\n1,2,3\n", "line 2", "1,2,3", "two numbers x,y"),
        ("0,0\n1\n", "line 2", "1", "two numbers x,y"),
        ("x,y\n0,0\n1\n", "line 3", "None", "two numbers"),
        ("0,0\ninf,1\n", "line 2", "inf", "finite"),
    ],
)
def test_errors_name_the_file_the_line_and_the_value(tmp_path: Path, text: str, line: str, value: str, expected: str) -> None:
    f = _write(tmp_path, text, "bad_path.csv")
    with pytest.raises(PathError) as err:
        load_waypoints_csv(f)
    msg = str(err.value)
    assert f"bad_path.csv {line}" in msg
    assert value in msg and expected in msg


def test_a_header_without_x_and_y_is_refused_with_its_line(tmp_path: Path) -> None:
    with pytest.raises(PathError, match=r"columns x,y.*bad\.csv line 2: found columns \['a', 'b'\]"):
        load_waypoints_csv(_write(tmp_path, "# c\na,b\n0,0\n1,1\n", "bad.csv"))


@pytest.mark.parametrize("text", ["# only comments\n\n", "x,y\n", "# c\nx,y\n0,0\n", "0,0\n# c\n\n"])
def test_fewer_than_two_waypoints_are_refused(tmp_path: Path, text: str) -> None:
    with pytest.raises(PathError, match="at least two waypoints"):
        load_waypoints_csv(_write(tmp_path, text))


def test_stone_files_accept_comments_blank_lines_and_an_optional_header(tmp_path: Path) -> None:
    rows = "1.45,-0.14\n1.85,0.14,0.3,0.2\n"
    plain = load_stones(_write(tmp_path, rows, "plain.csv"))
    commented = load_stones(_write(tmp_path, f"# my stones\n\nx,y,size_x,size_y\n# first: right foot\n{rows}\n", "c.csv"))
    for seq in (plain, commented):
        assert np.array_equal(seq.centers, [[1.45, -0.14], [1.85, 0.14]])
        assert np.array_equal(seq.sizes, [[0.2, 0.1], [0.3, 0.2]])


def test_stone_errors_name_the_file_the_line_and_the_value(tmp_path: Path) -> None:
    f = _write(tmp_path, "# c\nx,y\n1.45,-0.14\n\n1.85,oops\n", "bad_stones.csv")
    with pytest.raises(TerrainError, match=r"bad_stones\.csv line 5.*1\.85,oops"):
        load_stones(f)


def test_a_degenerate_or_reversing_waypoint_file_is_named(tmp_path) -> None:
    import pytest

    from lipmpcc.exceptions import PathError
    from lipmpcc.paths import load_path_csv

    short = tmp_path / "short.csv"
    short.write_text("x,y\n0,0\n2e-9,0\n")
    with pytest.raises(PathError, match=r"short.csv: waypoints = .*degenerate"):
        load_path_csv(short)
    back = tmp_path / "back.csv"
    back.write_text("x,y\n0,0\n1,0\n0.5,0\n")
    with pytest.raises(PathError, match=r"back.csv: waypoints = .*turns back by 180 deg at waypoint 1"):
        load_path_csv(back)
    hairpin = tmp_path / "hairpin.csv"  # a U-turn over three waypoints is a path
    hairpin.write_text("x,y\n0,0\n1,0\n1.2,0.2\n1,0.4\n0,0.4\n")
    assert load_path_csv(hairpin).length > 2.0
