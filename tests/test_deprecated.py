"""lipmpcc._deprecated.forward: the old import paths hand out the new objects with a DeprecationWarning."""

from __future__ import annotations

import warnings

import pytest

from lipmpcc import metrics, rotations
from lipmpcc._deprecated import REMOVED_IN, forward

OLD = "lipmpcc.old_place"


@pytest.fixture
def shim():
    return forward(OLD, "lipmpcc.metrics", renames={"root_mean_square": "rms", "wrap": "lipmpcc.rotations:wrap_angle"})


def test_a_forwarded_name_warns_and_is_the_same_object(shim) -> None:
    getattr_, _ = shim
    with pytest.warns(DeprecationWarning, match=rf"{OLD}\.rms moved to lipmpcc\.metrics\.rms; .* lipmpcc {REMOVED_IN}"):
        assert getattr_("rms") is metrics.rms
    with pytest.warns(DeprecationWarning):  # every read warns (Python's filters show it once per call site)
        getattr_("rms")


def test_renames_within_the_new_module_and_to_another_module(shim) -> None:
    getattr_, _ = shim
    with pytest.warns(DeprecationWarning, match=r"root_mean_square moved to lipmpcc\.metrics\.rms"):
        assert getattr_("root_mean_square") is metrics.rms
    with pytest.warns(DeprecationWarning, match=r"wrap moved to lipmpcc\.rotations\.wrap_angle"):
        assert getattr_("wrap") is rotations.wrap_angle


def test_unknown_and_dunder_names_raise_attribute_error_without_a_warning(shim) -> None:
    getattr_, _ = shim
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(AttributeError, match=rf"module '{OLD}' has no attribute 'no_such_name'"):
            getattr_("no_such_name")
        with pytest.raises(AttributeError):
            getattr_("__path__")  # import machinery probes dunders: never forwarded


def test_dir_lists_the_new_module_and_the_old_names(shim) -> None:
    _, dir_ = shim
    names = dir_()
    assert names == sorted(names)
    assert {"rms", "max_abs", "timing_stats_ms", "root_mean_square", "wrap"} <= set(names)


def test_a_real_shim_module_forwards() -> None:
    import lipmpcc.trajectory as old
    from lipmpcc.models.phase import PhaseClock

    with pytest.warns(DeprecationWarning, match=r"lipmpcc\.trajectory\.PhaseClock moved to lipmpcc\.models\.phase"):
        assert old.PhaseClock is PhaseClock
    assert "PhaseClock" in dir(old)


def test_moved_names_warn_when_read_from_the_old_module_but_not_inside_it() -> None:
    import lipmpcc.studies.path_following as pf
    from lipmpcc.studies import path_params

    with pytest.warns(DeprecationWarning, match=r"path_following\.fullbody_params moved to lipmpcc\.studies\.path_params"):
        assert pf.fullbody_params is path_params.fullbody_params
    import lipmpcc.studies.stepping_stones as ss
    from lipmpcc.studies import stone_course, stone_metrics

    with pytest.warns(DeprecationWarning, match=r"stepping_stones\.make_course moved to lipmpcc\.studies\.stone_course"):
        assert ss.make_course is stone_course.make_course
    with pytest.warns(DeprecationWarning, match=r"stone_metrics\.full_body_stones_log"):
        from lipmpcc.studies.stepping_stones import full_body_stones_log
    assert full_body_stones_log is stone_metrics.full_body_stones_log
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert pf.simulate_lip is not None and ss.run_case is not None  # names they keep
        assert pf.PLANNERS == ("mpcc", "cartesian") and ss.PLANNERS == ("alip-mpc", "alip-qp")  # its own
        from lipmpcc.studies.path_following import run_circle  # noqa: F401
