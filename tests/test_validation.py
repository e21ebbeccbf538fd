"""lipmpcc.validation: the shared input checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.validation import finite_number


@pytest.mark.parametrize("value, expected", [(1, 1.0), (-2.5, -2.5), (np.float32(0.5), 0.5), (np.int64(3), 3.0), ("4", 4.0)])
def test_numbers_pass_as_floats(value: object, expected: float) -> None:
    v = finite_number("x", value)
    assert v == expected and type(v) is float


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, "abc", None, [1.0], object()])
def test_anything_else_is_named(value: object) -> None:
    with pytest.raises(InvalidInputError, match=r"com_height.*a finite number"):
        finite_number("com_height", value)
