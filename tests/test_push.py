"""lipmpcc.push: the one Push of every loop and of the plant."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.push import Push


def test_planar_and_spatial_forces() -> None:
    p = Push((150.0, 0.0), t_start=0.1, duration=0.1, step=5)
    assert p.force == (150.0, 0.0) and p.force_xy == (150.0, 0.0) and p.force_xyz == (150.0, 0.0, 0.0)
    q = Push(np.array([0.0, 50.0, -5.0]), 2.0)
    assert q.force_xyz == (0.0, 50.0, -5.0) and q.duration == 0.1 and q.step is None and q.body is None
    assert all(isinstance(f, float) for f in q.force)


def test_window() -> None:
    p = Push((1.0, 0.0), t_start=0.5, duration=0.25)
    assert p.t_end == 0.75
    assert p.active(0.5) and p.active(0.7499) and not p.active(0.75) and not p.active(0.49)


def test_between_keeps_the_end_exactly() -> None:
    a, b = 0.04997999222368016, 0.6121283611030989  # a + (b - a) != b in floating point
    assert a + (b - a) != b
    p = Push.between((0.0, -75.0), a, b, step=20)
    assert p.t_end == b and p.t_start == a and p.step == 20
    assert math.isclose(p.duration, b - a)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"force": (1.0,), "t_start": 0.0}, "force"),
        ({"force": (1.0, math.nan), "t_start": 0.0}, "force"),
        ({"force": "big", "t_start": 0.0}, "force"),
        ({"force": (1.0, 0.0), "t_start": -1.0}, "t_start"),
        ({"force": (1.0, 0.0), "t_start": math.inf}, "t_start"),
        ({"force": (1.0, 0.0), "t_start": "soon"}, "t_start"),
        ({"force": (1.0, 0.0), "t_start": 0.0, "duration": 0.0}, "duration"),
        ({"force": (1.0, 0.0), "t_start": 0.0, "duration": math.nan}, "duration"),
        ({"force": (1.0, 0.0), "t_start": 0.0, "step": -1}, "step"),
        ({"force": (1.0, 0.0), "t_start": 0.0, "step": 1.5}, "step"),
        ({"force": (1.0, 0.0), "t_start": 0.0, "body": ""}, "body"),
    ],
)
def test_bad_values_are_named(kwargs: dict, name: str) -> None:
    with pytest.raises(InvalidInputError, match=name):
        Push(**kwargs)


def test_between_refuses_an_empty_window() -> None:
    with pytest.raises(InvalidInputError, match="t_start < t_end"):
        Push.between((1.0, 0.0), 0.2, 0.2)


def test_numpy_scalars_are_numbers() -> None:
    p = Push((np.float32(1.0), np.int64(2)), t_start=np.float64(0.5), duration=np.float32(0.25), step=np.int64(3))
    assert p.force == (1.0, 2.0) and p.t_start == 0.5 and p.step == 3


# ---- issue 14: the shared checks, numpy numbers accepted -----------------------------------------
def test_push_names_bad_values_and_accepts_numpy_numbers():
    import numpy as np
    import pytest

    from lipmpcc.exceptions import InvalidInputError
    from lipmpcc.push import Push

    p = Push(np.array([10.0, 0.0]), np.float32(0.5), np.int64(1), step=np.int64(2))
    assert p.t_end == pytest.approx(1.5) and p.step == 2
    for kw, match in (({"force": "east"}, r"force = 'east'"), ({"force": (1.0, np.nan)}, r"force = .*NaN or inf"),
                      ({"t_start": "now"}, r"t_start = 'now': expected a finite time >= 0 \[s\]"),
                      ({"duration": 0.0}, r"duration = 0.0: expected a finite duration > 0 \[s\]"),
                      ({"step": 1.5}, r"step = 1.5: expected None or a footstep index >= 0")):
        args = {"force": (10.0, 0.0), "t_start": 0.5, **kw}
        with pytest.raises(InvalidInputError, match=match):
            Push(**args)
