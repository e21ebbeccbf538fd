"""lipmpcc.loops.fullbody.params.LoopParams: defaults, validation and the helper-thread choice."""

from __future__ import annotations

import pytest

from lipmpcc.conventions import LEFT, RIGHT
from lipmpcc.exceptions import ParameterError
from lipmpcc.loops.fullbody.params import LoopParams


def test_defaults() -> None:
    p = LoopParams()
    assert p.sim_steps_per_wbc == 5 and p.first_stance == RIGHT and p.com_height is None
    assert LoopParams(first_stance="left").first_stance == LEFT


@pytest.mark.parametrize(
    "kw, name",
    [
        ({"sim_steps_per_wbc": 0}, "sim_steps_per_wbc"),
        ({"sim_steps_per_wbc": 2.5}, "sim_steps_per_wbc"),
        ({"com_height": 0.0}, "com_height"),
        ({"initial_shift": -0.1}, "initial_shift"),
        ({"double_support": float("nan")}, "double_support"),
        ({"load_ramp": float("inf")}, "load_ramp"),
        ({"landing_depth": -0.01}, "landing_depth"),
        ({"initial_shift_fraction": 1.5}, "initial_shift_fraction"),
        ({"touchdown_min_phase": 0.0}, "touchdown_min_phase"),
        ({"first_stance": "middle"}, "first_stance"),
        ({"video_fps": 0.0}, "video_fps"),
        ({"helper_thread": "yes"}, "helper_thread"),
    ],
)
def test_bad_values_are_named(kw: dict, name: str) -> None:
    with pytest.raises(ParameterError, match=name):
        LoopParams(**kw)


def test_the_helper_thread_follows_the_flag_or_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    assert LoopParams(helper_thread=True).resolved_helper_thread() is True
    assert LoopParams(helper_thread=False).resolved_helper_thread() is False
    monkeypatch.setenv("LIPMPCC_LOOP_THREAD", "0")
    assert LoopParams().resolved_helper_thread() is False
    monkeypatch.setattr("lipmpcc.loops.fullbody.params.threads_enabled", lambda env: env == "LIPMPCC_LOOP_THREAD")
    assert LoopParams().resolved_helper_thread() is True


# ---- issue 14: parameters of the wrong type are named ------------------------------------------
def test_bad_loop_params_are_named():
    import math

    import pytest

    from lipmpcc.exceptions import ParameterError
    from lipmpcc.loops.fullbody.params import LoopParams

    cases = (({"com_height": "x"}, r"com_height = 'x'"), ({"swing": "high"}, r"swing = 'high': expected a lipmpcc"),
             ({"initial_shift": None}, r"initial_shift = None"), ({"video_fps": math.nan}, r"video_fps = nan"),
             ({"com_resync_on_plan": "yes"}, r"com_resync_on_plan = 'yes'"),
             ({"sim_steps_per_wbc": 5.0}, r"sim_steps_per_wbc = 5.0"))
    for kw, match in cases:
        with pytest.raises(ParameterError, match=match):
            LoopParams(**kw)
