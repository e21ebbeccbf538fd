"""lipmpcc.studies.run_cache: a full-body run made once, loaded by the next reader with what it reads."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.robots import load_robot
from lipmpcc.studies import run_cache
from lipmpcc.studies.path_following import render_frames

OPTS = {"obstacle_speed": 0.6, "duration": 3.5, "record_video": True}


@pytest.fixture(scope="module")
def robot():
    return load_robot("digit_like")


@pytest.fixture(scope="module")
def stored(robot, tmp_path_factory):
    """(folder, the run made, the same run loaded)."""
    folder = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv(run_cache.CACHE_ENV, str(folder))
        made, loaded_first = run_cache.cached_full_body(robot, "overtake", "mpcc", **OPTS)
        again, loaded_second = run_cache.cached_full_body(robot, "overtake", "mpcc", **OPTS)
    assert (loaded_first, loaded_second) == (False, True)
    return folder, made, again


def test_a_loaded_run_holds_what_the_readers_read(stored) -> None:
    _, made, again = stored
    assert json.dumps(again.summary, sort_keys=True, default=repr) == json.dumps(made.summary, sort_keys=True, default=repr)
    assert again.summary["steps"] > 0 and np.isfinite(again.summary["contouring_error_max_m"])
    np.testing.assert_array_equal(again.log.e_contouring_c, made.log.e_contouring_c)
    steps, mism = made.source.exchange_mismatches()
    steps2, mism2 = again.source.exchange_mismatches()
    assert len(steps) > 0 and steps.tolist() == steps2.tolist() and np.array_equal(mism, mism2)
    assert isinstance(again.source, run_cache.StoredMpccSource) and again.source.params.robot_radius == made.source.params.robot_radius
    assert len(again.result.frames) == len(made.result.frames) > 0 and len(again.source.records) == len(made.source.records)


def test_a_loaded_run_renders_its_frames(stored) -> None:
    _, made, again = stored
    try:
        images, shown = render_frames(again, [1.0], size=(64, 48))
    except Exception as exc:  # noqa: BLE001 - no OpenGL context on this machine
        pytest.skip(f"offscreen rendering unavailable: {exc}")
    assert len(images) == 1 and images[0].shape[:2] == (48, 64) and images[0].std() > 0


def test_the_key_changes_with_the_options_and_refuses_what_it_cannot_hold(robot, stored, monkeypatch) -> None:
    folder, _, _ = stored
    monkeypatch.setenv(run_cache.CACHE_ENV, str(folder))
    k = run_cache.run_key(robot, "overtake", "mpcc", OPTS)
    assert k != run_cache.run_key(robot, "overtake", "mpcc", {**OPTS, "obstacle_speed": 0.5})
    assert k != run_cache.run_key(robot, "overtake", "cartesian", OPTS)
    monkeypatch.setenv("LIPMPCC_SQP_CONVEXIFICATION", "modified_cholesky")  # other SQP iterates: another run
    assert k != run_cache.run_key(robot, "overtake", "mpcc", OPTS)
    monkeypatch.delenv("LIPMPCC_SQP_CONVEXIFICATION")
    assert (folder / "runs" / f"{k}.pkl").is_file()
    with pytest.raises(InvalidInputError, match="pushes"):
        run_cache.cached_full_body(robot, "overtake", "mpcc", pushes=[], **OPTS)


def test_a_torn_entry_is_run_again(robot, tmp_path, monkeypatch) -> None:
    monkeypatch.setenv(run_cache.CACHE_ENV, str(tmp_path))
    opts = {**OPTS, "duration": 0.5, "record_video": False}
    entry = tmp_path / "runs" / f"{run_cache.run_key(robot, 'overtake', 'mpcc', opts)}.pkl"
    entry.parent.mkdir(parents=True)
    entry.write_bytes(b"\x80\x05torn")
    run, loaded = run_cache.cached_full_body(robot, "overtake", "mpcc", **opts)
    assert not loaded and run.summary["duration_s"] > 0 and entry.stat().st_size > 100


def _cached_call(notebook) -> str:
    """The source of ``notebook``'s ``run_cache.cached_full_body(...)`` call, its names' constants substituted."""
    import ast

    cells = [c for c in json.loads(notebook.read_text(encoding="utf-8"))["cells"] if c["cell_type"] == "code"]
    src = next("".join(c["source"]) for c in cells if "run_cache.cached_full_body(" in "".join(c["source"]))
    tree = ast.parse(src)
    consts = {t.id: ast.unparse(n.value) for n in tree.body if isinstance(n, ast.Assign) for t in n.targets
              if isinstance(t, ast.Name) and isinstance(n.value, ast.Constant)}
    call = next(n for n in ast.walk(tree) if isinstance(n, ast.Call) and ast.unparse(n.func).endswith("cached_full_body"))
    args = [ast.unparse(a) for a in call.args] + sorted(f"{k.arg}={consts.get(ast.unparse(k.value), ast.unparse(k.value))}"
                                                        for k in call.keywords)
    return ", ".join(args)


def test_notebook_09b_asks_for_the_very_run_of_09() -> None:
    """09b reads 09's overtaking run from the cache only if it asks with the same arguments (else CI simulates it twice)."""
    from pathlib import Path

    nbs = Path(__file__).resolve().parents[2] / "notebooks"
    if not nbs.is_dir():
        pytest.skip("needs the source tree's notebooks/")
    core, deep = _cached_call(nbs / "09_digit_paper_a.ipynb"), _cached_call(nbs / "09b_digit_paper_a_deep_dive.ipynb")
    assert core == deep and "duration=30.0" in core and "record_video=True" in core, (core, deep)
