"""lipmpcc.conventions: one Side, one gravity."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lipmpcc.conventions import GRAVITY, LEFT, RIGHT, Side, other_side, parse_side
from lipmpcc.exceptions import InvalidInputError


def test_side_is_its_string() -> None:
    assert LEFT == "left" and RIGHT == "right"
    assert str(LEFT) == "left" and f"{RIGHT}" == "right"
    assert {"left": 0}[LEFT] == 0  # dictionaries keyed by the strings accept a Side
    assert json.dumps({"side": RIGHT}) == '{"side": "right"}'


def test_side_sign_index_other() -> None:
    assert (LEFT.sign, RIGHT.sign) == (1, -1)
    assert (LEFT.index, RIGHT.index) == (0, 1)
    assert LEFT.other is RIGHT and RIGHT.other is LEFT
    assert other_side("left") is RIGHT and other_side(RIGHT) is LEFT


@pytest.mark.parametrize(
    "value, side",
    [("left", LEFT), (" L ", LEFT), ("Right", RIGHT), ("r", RIGHT), (1, LEFT), (-1, RIGHT),
     (np.int64(-1), RIGHT), (LEFT, LEFT)],
)
def test_parse_side_accepts_every_spelling(value: object, side: Side) -> None:
    assert parse_side(value) is side


@pytest.mark.parametrize("value", ["up", "", 0, 2, True, 1.0, None, [1]])
def test_parse_side_names_the_bad_value(value: object) -> None:
    with pytest.raises(InvalidInputError, match="side"):
        parse_side(value)


def test_gravity_is_the_papers() -> None:
    assert GRAVITY == 9.81
