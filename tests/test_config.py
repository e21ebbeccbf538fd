"""lipmpcc.config: fast mode (environment and override), run horizons, helper threads."""

from __future__ import annotations

import pytest

from lipmpcc import config


@pytest.fixture(autouse=True)
def _no_override():
    config.set_fast_mode(None)
    yield
    config.set_fast_mode(None)


@pytest.mark.parametrize("value, fast", [("1", True), ("true", True), (" Yes ", True), ("on", True),
                                         ("0", False), ("", False), ("no", False), ("2", False)])
def test_fast_mode_reads_the_environment(monkeypatch: pytest.MonkeyPatch, value: str, fast: bool) -> None:
    monkeypatch.setenv("LIPMPCC_FAST", value)
    assert config.fast_mode() is fast
    assert config.horizon(100, 10) == (10 if fast else 100)


def test_fast_mode_is_off_without_the_variable(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("LIPMPCC_FAST", raising=False)
    assert config.fast_mode() is False and config.horizon(44.0, 6.0) == 44.0


def test_set_fast_mode_overrides_the_environment_until_reset(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("LIPMPCC_FAST", "1")
    config.set_fast_mode(False)
    assert not config.fast_mode() and config.horizon(3, 1) == 3
    monkeypatch.setenv("LIPMPCC_FAST", "0")
    config.set_fast_mode(True)
    assert config.fast_mode() and config.horizon(3, 1) == 1
    config.set_fast_mode(None)
    assert not config.fast_mode()


def test_threads_need_two_cpus_and_the_variable_not_zero(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(config.os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    monkeypatch.delenv("LIPMPCC_TEST_THREAD", raising=False)
    assert config.threads_enabled("LIPMPCC_TEST_THREAD")
    monkeypatch.setenv("LIPMPCC_TEST_THREAD", "0")
    assert not config.threads_enabled("LIPMPCC_TEST_THREAD")
    monkeypatch.setenv("LIPMPCC_TEST_THREAD", "1")
    monkeypatch.setattr(config.os, "sched_getaffinity", lambda pid: {0}, raising=False)
    assert not config.threads_enabled("LIPMPCC_TEST_THREAD")  # one CPU: never


def test_fast_mode_as_sets_it_within_a_block_and_restores_it(monkeypatch) -> None:
    monkeypatch.setenv("LIPMPCC_FAST", "0")
    config.set_fast_mode(None)
    with config.fast_mode_as(True):
        assert config.fast_mode() and config.horizon(10, 3) == 3
    assert not config.fast_mode()  # back to the environment, not left forced
    config.set_fast_mode(False)
    try:
        with pytest.raises(KeyError):
            with config.fast_mode_as(True):
                raise KeyError("x")
        assert config.fast_mode() is False
    finally:
        config.set_fast_mode(None)


def test_scoped_env_sets_and_restores_each_variable(monkeypatch) -> None:
    import os

    from lipmpcc.config import scoped_env

    monkeypatch.setenv("LIPMPCC_PROBE_SET", "before")
    monkeypatch.delenv("LIPMPCC_PROBE_UNSET", raising=False)
    with scoped_env({"LIPMPCC_PROBE_SET": "inside", "LIPMPCC_PROBE_UNSET": "inside"}):
        assert os.environ["LIPMPCC_PROBE_SET"] == os.environ["LIPMPCC_PROBE_UNSET"] == "inside"
    assert os.environ["LIPMPCC_PROBE_SET"] == "before" and "LIPMPCC_PROBE_UNSET" not in os.environ
