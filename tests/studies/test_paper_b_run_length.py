"""circle-push --push-set paper-b: the default run reaches three footsteps past the last push on every robot
(fast mode's 10 s full-body default ended before footstep 28 and the study failed with an IndexError)."""

from __future__ import annotations

import pytest

from lipmpcc.studies.circle_pushes import _reaching_the_last_push
from lipmpcc.studies.options import RunOptions


def _opts(**kw) -> RunOptions:
    return RunOptions("circle-push", planner="mpcc", out="results", push_set="paper-b", **kw)


def test_a_short_full_body_default_is_lengthened_to_the_last_push(monkeypatch) -> None:
    monkeypatch.setenv("LIPMPCC_FAST", "1")
    assert _reaching_the_last_push(_opts(robot="digit_like"), 28).steps == 31
    timed = _opts(robot="digit_like", step_duration_range=(0.3, 0.5))
    assert _reaching_the_last_push(timed, 28).steps == 31


def test_a_default_that_reaches_it_and_the_users_length_are_kept(monkeypatch) -> None:
    monkeypatch.delenv("LIPMPCC_FAST", raising=False)
    full = _opts(robot="digit_like")
    assert _reaching_the_last_push(full, 56) is full  # 45 s: about 105 footsteps of 0.4 s
    monkeypatch.setenv("LIPMPCC_FAST", "1")
    for given in (_opts(robot="digit_like", steps=40), _opts(robot="digit_like", duration=20.0), _opts(robot="lip")):
        assert _reaching_the_last_push(given, 28) is given
