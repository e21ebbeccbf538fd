"""Shared pytest fixtures."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# The tests build many one-off MPCC problems (each path and slot count its own function) and run them for
# seconds: a background C compile of the large ones (lipmpcc.solvers.casadi_buffer) would rarely finish in
# time to pay for the core it takes from the other tests. Results are the same to the bit either way
# (tests/solvers/test_casadi_buffer.py checks the swap and switches it on for itself).
os.environ.setdefault("LIPMPCC_BACKGROUND_JIT", "0")

REPO = Path(__file__).resolve().parents[1]
#: the environment variable naming the optional Digit v3 MJCF (osudrl/roadrunner's digit-v3.xml)
DIGIT_V3_ENV = "LIPMPCC_DIGIT_V3"
#: where the Digit v3 model is looked for when the variable is unset: beside the repository
DEFAULT_SHARED_DIGIT = REPO.parent / "shared" / "models" / "digit-v3" / "digit-v3.xml"


def shared_digit_path() -> Path:
    """The Digit v3 MJCF the tests use: ``$LIPMPCC_DIGIT_V3`` when set (and not empty), else
    ``../shared/models/digit-v3/digit-v3.xml`` beside the repository. The tests that need it skip
    when the file does not exist."""
    env = os.environ.get(DIGIT_V3_ENV, "").strip()
    return Path(env).expanduser().resolve() if env else DEFAULT_SHARED_DIGIT


SHARED_DIGIT = shared_digit_path()


@pytest.fixture
def shared_digit_xml() -> Path:
    """Path of the reference Digit v3 MJCF (:func:`shared_digit_path`); skips when it is absent."""
    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT} (set {DIGIT_V3_ENV} to its path)")
    return SHARED_DIGIT


@pytest.fixture(scope="session")
def shared_digit():
    """The reference Digit v3 described once (:func:`lipmpcc.robots.load_robot`); skips when ../shared is absent."""
    if not SHARED_DIGIT.exists():
        pytest.skip(f"reference model not found at {SHARED_DIGIT}")
    from lipmpcc.robots import load_robot

    return load_robot(SHARED_DIGIT)


def _xdist_group(item: pytest.Item) -> str:
    """The worker group of a test under ``pytest-xdist`` (``--dist loadgroup``): the notebooks and the site's
    tests run in one worker, in collection order (the site renders the executed copies nbval writes), every
    other test file in one worker (its module-scoped runs are made once)."""
    path = Path(str(item.fspath)).resolve()
    try:
        rel = path.relative_to(REPO)
    except ValueError:
        return str(path)
    if rel.parts[0] == "notebooks" or rel.parts[:2] == ("tests", "docs"):
        return "book"
    return rel.as_posix()


@pytest.hookimpl(tryfirst=True)  # before xdist's own, which turns the marks into work units
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Group the tests for ``pytest-xdist`` (:func:`_xdist_group`); a no-op in a serial run."""
    if not config.pluginmanager.hasplugin("xdist"):
        return
    for item in items:
        item.add_marker(pytest.mark.xdist_group(_xdist_group(item)))


def package_env(base: dict[str, str] | None = None) -> dict[str, str]:
    """The environment (``os.environ`` or ``base``) for a subprocess that must import the lipmpcc these tests
    import: the installed package in CI (whose compiled modules the source tree lacks), the source tree in
    development (``PYTHONPATH=python``)."""
    import lipmpcc

    root = str(Path(lipmpcc.__file__).resolve().parents[1])
    env = dict(os.environ if base is None else base)
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def default_sigint() -> None:
    """``preexec_fn`` of a subprocess that a test interrupts: SIGINT at its default, whatever the test runner
    inherited (a shell's background job ignores SIGINT, and an ignored signal stays ignored across exec)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)


#: the Menagerie humanoids beside the repository (unedited; ``<position>`` servos, no sole sites)
SHARED_HUMANOIDS = {
    "g1": REPO.parent / "shared" / "models" / "unitree-g1" / "g1.xml",
    "t1": REPO.parent / "shared" / "models" / "booster-t1" / "t1.xml",
}


def _humanoid(name: str, tmp_path_factory):
    """(MJCF, layout file written by ``robot init`` into a temporary folder) of a shared humanoid; skips when absent."""
    path = SHARED_HUMANOIDS[name]
    if not path.exists():
        pytest.skip(f"reference model not found at {path}")
    from lipmpcc.robots.autolayout import write_layout

    out = tmp_path_factory.mktemp(f"{name}_layout") / f"{name}.lipmpcc.toml"
    write_layout(path, out)
    return path, out


@pytest.fixture(scope="session")
def shared_g1(tmp_path_factory):
    """Unitree G1 (Menagerie) described with the layout ``lipmpcc robot init`` writes; skips when absent."""
    from lipmpcc.robots import load_robot

    path, layout = _humanoid("g1", tmp_path_factory)
    return load_robot(path, layout=layout)


@pytest.fixture(scope="session")
def shared_t1(tmp_path_factory):
    """Booster T1 (Menagerie) described with the layout ``lipmpcc robot init`` writes; skips when absent."""
    from lipmpcc.robots import load_robot

    path, layout = _humanoid("t1", tmp_path_factory)
    return load_robot(path, layout=layout)
