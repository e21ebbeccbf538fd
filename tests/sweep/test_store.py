"""lipmpcc.sweep.store: one SQLite row per finished case, one transaction each; another spec is refused."""

from __future__ import annotations

import sqlite3

import pytest

from lipmpcc.sweep.spec import parse_spec
from lipmpcc.sweep.store import ResultStore, SweepSpecChangedError, outcome_columns

RAW = {"study": "circle-push", "planners": ["mpcc"], "options": {"steps": 12},
       "axes": {"force": {"values": [10, 20]}, "direction": {"value": 0}}}


def result(case, fell=False):
    return {"id": case["id"], "status": "done", "summary": {"fell": fell, "solver_failures": 0, "overtook": False,
            "contouring_error_rms_m": 0.02, "solve_ms": {"median": 1.0}}, "push": {"force_N": 10.0, "impulse_Ns": 1.0},
            "error": None, "wall_s": 0.5, "worker": "h:1"}


def test_rows_are_appended_with_flat_parameter_and_outcome_columns(tmp_path) -> None:
    spec = parse_spec(RAW)
    store = ResultStore(tmp_path / "r.sqlite", spec)
    a, b = spec.cases()
    store.record(a, result(a, fell=True))
    store.record(b, None, died="worker process died")
    assert store.status() == {a["id"]: ("done", 1), b["id"]: ("died", 1)}
    row = store.rows(f"case_id = '{a['id']}'")[0]
    assert (row["p_force"], row["fell"], row["survived"], row["rmse_m"], row["impulse_Ns"]) == (10.0, 1, 0, 0.02, 1.0)
    store.record(b, result(b))
    assert store.status()[b["id"]] == ("done", 2)
    store.close()
    db = sqlite3.connect(tmp_path / "r.sqlite")  # analysts open it directly
    assert db.execute("select count(*) from cases").fetchone() == (2,)


def test_another_spec_is_refused_and_the_same_one_reopens(tmp_path) -> None:
    ResultStore(tmp_path / "r.sqlite", parse_spec(RAW)).close()
    ResultStore(tmp_path / "r.sqlite", parse_spec(RAW)).close()
    changed = {**RAW, "options": {"steps": 13}}
    with pytest.raises(SweepSpecChangedError) as err:
        ResultStore(tmp_path / "r.sqlite", parse_spec(changed))
    assert "\n" not in str(err.value) and "changed" in str(err.value)


def test_a_failed_transaction_leaves_no_row(tmp_path) -> None:
    spec = parse_spec(RAW)
    store = ResultStore(tmp_path / "r.sqlite", spec)
    with pytest.raises(KeyboardInterrupt):
        with store.transaction() as db:
            db.execute("INSERT INTO cases (case_id, status) VALUES ('x', 'done')")
            raise KeyboardInterrupt
    assert store.status() == {}


def test_outcome_columns_read_the_summary_contract() -> None:
    cols = outcome_columns({"fell": False, "collided": True, "outcome": "collided", "stopped_early": None,
                            "stopped_reason": "duration", "step_rmse_m": 0.03})
    assert (cols["survived"], cols["collided"], cols["outcome"], cols["rmse_m"], cols["stopped_reason"]) == (
        0, 1, "collided", 0.03, "duration")
    assert outcome_columns(None)["survived"] is None
    assert outcome_columns({"fell": True})["outcome"] == "fell"
    derived = outcome_columns({"fell": False, "min_clearance_m": -0.01})  # no collided field: the clearance says
    assert (derived["collided"], derived["survived"], derived["outcome"]) == (1, 0, "collided")
    assert outcome_columns({"fell": False, "min_clearance_m": 0.2})["collided"] == 0


def _tiny_spec():
    from lipmpcc.sweep.spec import parse_spec

    return parse_spec({"name": "t", "study": "circle-push", "robot": "lip", "planners": ["mpcc"], "options": {"steps": 10},
                       "axes": {"impulse": {"values": [1.0, 2.0, 3.0]}, "push_step": {"value": 4}}})


def _filled(path):
    from lipmpcc.sweep.store import ResultStore

    spec = _tiny_spec()
    store = ResultStore(path, spec)
    for case in spec.cases():
        store.record(case, {"id": case["id"], "status": "error", "error": "x", "summary": None})
    store.close()
    return spec


def test_a_store_that_is_not_sqlite_is_named_with_what_to_do(tmp_path) -> None:
    from lipmpcc.sweep.store import ResultStore, SweepStoreError

    p = tmp_path / "results.sqlite"
    p.write_bytes(b"\x00garbage" * 512)
    with pytest.raises(SweepStoreError, match=r"store = .*results.sqlite.*damaged or not an SQLite file.*--replace"):
        ResultStore(p, _tiny_spec())


def test_a_truncated_store_is_named(tmp_path) -> None:
    from lipmpcc.sweep.store import ResultStore, SweepStoreError

    p = tmp_path / "results.sqlite"
    spec = _filled(p)
    data = p.read_bytes()
    p.write_bytes(data[: len(data) // 2])
    with pytest.raises(SweepStoreError, match="results.sqlite") as err:
        ResultStore(p, spec)
    assert "--replace" in str(err.value) and "\n" not in str(err.value)


def test_a_meta_less_store_is_named_with_the_rows_still_good(tmp_path) -> None:
    import sqlite3

    from lipmpcc.sweep.store import ResultStore, SweepStoreError

    p = tmp_path / "results.sqlite"
    spec = _filled(p)
    con = sqlite3.connect(p)
    con.execute("DROP TABLE meta")
    con.commit()
    con.close()
    with pytest.raises(SweepStoreError, match=r"no sweep specification.*3 rows of its cases table can still be read"):
        ResultStore(p, spec)


def test_remove_store_deletes_it_and_its_side_files(tmp_path) -> None:
    from lipmpcc.sweep.store import remove_store

    p = tmp_path / "results.sqlite"
    _filled(p)
    (tmp_path / "results.sqlite-journal").write_text("")
    remove_store(p)
    assert list(tmp_path.iterdir()) == []


def test_path_outcome_columns_and_an_older_store_gains_them(tmp_path) -> None:
    """issue 31: reached_end, progress_m, path_length_m and the stall's binding are columns; a store made
    before them gets them when it is reopened (resume)."""
    stall = {"t_s": 6.4, "binding": {"kind": "obstacle", "obstacles": [5], "text": "obstacle 5 (0.15 m) blocked the robot"}}
    cols = outcome_columns({"fell": False, "outcome": "stalled", "reached_end": False, "progress_m": 0.6,
                            "path_length_m": 4.0, "stall": stall})
    assert (cols["outcome"], cols["reached_end"], cols["progress_m"], cols["path_length_m"]) == ("stalled", 0, 0.6, 4.0)
    assert cols["stall_binding"] == "obstacle 5 (0.15 m) blocked the robot"
    assert outcome_columns({"fell": False})["reached_end"] is None  # not a path-following study
    spec = parse_spec(RAW)
    ResultStore(tmp_path / "r.sqlite", spec).close()
    db = sqlite3.connect(tmp_path / "r.sqlite")
    db.execute("ALTER TABLE cases DROP COLUMN reached_end")  # as an older lipmpcc made it
    db.commit()
    db.close()
    store = ResultStore(tmp_path / "r.sqlite", spec)
    a = spec.cases()[0]
    store.record(a, {**result(a), "summary": {"fell": False, "outcome": "completed", "reached_end": True,
                                              "progress_m": 4.0, "path_length_m": 4.0}})
    assert store.rows()[0]["reached_end"] == 1
    store.close()
