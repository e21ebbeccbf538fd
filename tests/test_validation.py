"""lipmpcc.validation: the shared input checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, PathError
from lipmpcc.validation import (
    choice,
    count,
    finite_array,
    finite_number,
    finite_vector,
    flag,
    non_negative_number,
    number_in,
    ordered_pair,
    positive_number,
    read_text_file,
)


@pytest.mark.parametrize("value, expected", [(1, 1.0), (-2.5, -2.5), (np.float32(0.5), 0.5), (np.int64(3), 3.0)])
def test_numbers_pass_as_floats(value: object, expected: float) -> None:
    v = finite_number("x", value)
    assert v == expected and type(v) is float


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, "abc", "4", None, [1.0], object(), True, np.bool_(False)])
def test_anything_else_is_named(value: object) -> None:
    with pytest.raises(InvalidInputError, match=r"com_height.*a finite number"):
        finite_number("com_height", value)


def test_the_error_class_and_unit_are_chosen_by_the_caller() -> None:
    with pytest.raises(PathError, match=r"radius = 'big': expected a finite number > 0 \[m\]"):
        positive_number("radius", "big", "m", error=PathError)


def test_ranges() -> None:
    assert number_in("g", 0.5, 0.0, 1.0, lo_open=True) == 0.5
    assert non_negative_number("w", 0) == 0.0
    with pytest.raises(InvalidInputError, match=r"> 0 and <= 100 \[m\]"):
        positive_number("r", 1e6, "m", hi=100.0)
    with pytest.raises(InvalidInputError, match=r">= 0"):
        non_negative_number("w", -1)
    with pytest.raises(InvalidInputError, match=r"< 1"):
        number_in("gamma", 1.0, 0.0, 1.0, lo_open=True, hi_open=True)


def test_counts_accept_numpy_integers_only() -> None:
    assert count("N", np.int64(5), 1) == 5 and type(count("N", np.int64(5), 1)) is int
    for bad in (5.0, True, "5", 0, None):
        with pytest.raises(InvalidInputError, match=r"N = .*an integer >= 1"):
            count("N", bad, 1)
    with pytest.raises(InvalidInputError, match="<= 10"):
        count("N", 11, 1, 10)


def test_flags_and_choices() -> None:
    assert flag("jit", np.bool_(True)) is True
    with pytest.raises(InvalidInputError, match="True or False"):
        flag("jit", 1)
    assert choice("solver", "sqp", ("sqp", "ipopt")) == "sqp"
    with pytest.raises(InvalidInputError, match=r"solver = 'SQP': expected one of 'sqp', 'ipopt'"):
        choice("solver", "SQP", ("sqp", "ipopt"))


def test_arrays() -> None:
    a = finite_array("x0", [1, 2, 3, 4, 5], (5,))
    assert a.dtype == float and a.shape == (5,)
    assert finite_array("w", np.zeros((7, 2)), (None, 2)).shape == (7, 2)
    with pytest.raises(InvalidInputError, match=r"shape \(5,\).*got shape \(3,\)"):
        finite_array("x0", [1, 2, 3], (5,))
    with pytest.raises(InvalidInputError, match="NaN or inf"):
        finite_array("x0", [1, np.nan], (2,))
    for bad in ("abc", [[1], [1, 2]], True, np.array([True, False]), None):
        with pytest.raises(InvalidInputError, match="x0"):
            finite_array("x0", bad, (2,))
    assert finite_vector("axes", (1, np.float32(2)), 2) == (1.0, 2.0)
    with pytest.raises(InvalidInputError, match="a list of two finite numbers"):
        finite_vector("axes", (1,), 2)
    assert ordered_pair("lateral", (0.05, 0.35)) == (0.05, 0.35)
    with pytest.raises(InvalidInputError, match="lower <= upper"):
        ordered_pair("lateral", (0.35, 0.05))


def test_text_files(tmp_path) -> None:
    f = tmp_path / "a.csv"
    f.write_text("x,y\n0,0\n")
    assert read_text_file("path", f, "CSV file") == "x,y\n0,0\n"
    b = tmp_path / "b.csv"
    b.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    with pytest.raises(PathError, match=r"path = .*b.csv.*a CSV file \(UTF-8 text\) \(the file is binary\)"):
        read_text_file("path", b, "CSV file", error=PathError)
    with pytest.raises(InvalidInputError, match="an existing CSV file.*no such file"):
        read_text_file("path", tmp_path / "none.csv", "CSV file")
    with pytest.raises(InvalidInputError, match="a folder"):
        read_text_file("path", tmp_path, "CSV file")
    with pytest.raises(InvalidInputError, match="the path of"):
        read_text_file("path", 3, "CSV file")


def test_is_finite_number() -> None:
    from lipmpcc.validation import is_finite_number

    assert is_finite_number(np.float32(1.5)) and is_finite_number(3)
    assert not any(is_finite_number(v) for v in (True, "1", None, math.nan, math.inf, [1.0]))


def test_check_field_types_names_the_field() -> None:
    from dataclasses import dataclass

    from lipmpcc.exceptions import ParameterError
    from lipmpcc.validation import check_field_types

    @dataclass
    class P:
        gain: float = 1.0
        n: int = 3
        on: bool = True
        label: str = "x"

        def __post_init__(self) -> None:
            check_field_types(self, error=ParameterError)

    P(gain=np.float32(2.0), n=np.int64(4), on=np.bool_(False))
    for kw, match in (({"gain": None}, r"gain = None: expected a finite number"), ({"n": 2.5}, r"n = 2.5: expected an integer"),
                      ({"on": "yes"}, r"on = 'yes': expected True or False"), ({"gain": math.nan}, r"gain = nan")):
        with pytest.raises(ParameterError, match=match):
            P(**kw)
    P(label=3)  # other annotations are left to the dataclass
