"""The results store of a sweep: one SQLite file (``OUT/results.sqlite``) that analysts open directly.

Table ``cases``: one row per finished case, written in one transaction (a crash or Ctrl-C leaves every
row whole): the case id (hash of its plain spec), its index, the planner's label, ``status`` (``done``: the
study ran; ``error``: the study raised, with the message in ``error``; ``timeout``: stopped at the spec's
``timeout_s``; ``died``: the worker process died while running it, retried once), ``attempts``, the parameters as JSON and as one column ``p_<axis>`` per axis
(SI units), the push (``force_N``, ``impulse_Ns``), the outcome read from summary.json (``outcome``,
``survived``, ``fell``, ``collided``, ``overtook``, ``min_clearance_m``, ``rmse_m``, ``solver_failures``,
``relaxed_solves``, ``stopped_reason``, ``solve_ms_median``), the wall time, the worker, and the whole
summary as JSON. Table ``meta`` holds the specification, its hash and the package version: a store made
for another specification is refused (:class:`SweepSpecChangedError`).

Example: ``sqlite3 OUT/results.sqlite "select planner, avg(survived) from cases group by planner"``.
"""

from __future__ import annotations

import json
import sqlite3
import time
from pathlib import Path
from typing import Any, Iterable

from ..exceptions import InvalidInputError
from .spec import AXES, SweepSpec, canonical_json

__all__ = ["STORE_NAME", "OUTCOME_COLUMNS", "SweepSpecChangedError", "SweepStoreError", "ResultStore", "outcome_columns",
           "remove_store"]

STORE_NAME = "results.sqlite"
#: column -> SQL type, read from the summary by :func:`outcome_columns`
OUTCOME_COLUMNS: dict[str, str] = {
    "outcome": "TEXT", "survived": "INTEGER", "fell": "INTEGER", "collided": "INTEGER", "overtook": "INTEGER",
    "min_clearance_m": "REAL", "rmse_m": "REAL", "solver_failures": "INTEGER", "relaxed_solves": "INTEGER",
    "stopped_reason": "TEXT", "solve_ms_median": "REAL", "stones_reached": "INTEGER",
    # issue 31: how a path-following run ended along its path (None for the other studies)
    "reached_end": "INTEGER", "progress_m": "REAL", "path_length_m": "REAL", "stall_binding": "TEXT",
}
_BASE_COLUMNS = ("case_id TEXT PRIMARY KEY", "idx INTEGER", "planner TEXT", "status TEXT", "attempts INTEGER",
                 "params TEXT", "force_N REAL", "impulse_Ns REAL")
_TAIL_COLUMNS = ("wall_s REAL", "worker TEXT", "error TEXT", "summary TEXT", "finished_at REAL")


class SweepSpecChangedError(InvalidInputError):
    """The store at ``path`` holds another campaign (its specification's hash differs)."""

    def __init__(self, path: str, stored: str, given: str) -> None:
        super().__init__("sweep spec", given, f"the specification of the store {path} (hash {stored})",
                         "the spec changed: use another --out, or pass --replace to start the sweep over")


class SweepStoreError(InvalidInputError):
    """The results store cannot be used: damaged, truncated, not a sweep's store (no ``meta``), or it
    cannot be written (a read-only ``--out``, also one that became read-only during the sweep). The
    message names the store, what is wrong and what to do (``--replace``, or the rows still good)."""

    def __init__(self, path: str | Path, problem: str, advice: str) -> None:
        super().__init__("store", str(path), "a results store of lipmpcc sweep that can be read and written",
                         f"{problem}; {advice}")


def remove_store(path: str | Path) -> None:
    """Delete a store and its SQLite side files (``-journal``, ``-wal``, ``-shm``)."""
    p = Path(path)
    for f in (p, *(p.with_name(p.name + x) for x in ("-journal", "-wal", "-shm"))):
        if f.exists() or f.is_symlink():
            f.unlink()


def _good_rows(path: Path) -> int | None:
    """How many rows of ``cases`` can still be read from a damaged store (None: none can)."""
    try:
        db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
        try:
            return int(db.execute("SELECT count(*) FROM cases").fetchone()[0])
        finally:
            db.close()
    except sqlite3.Error:
        return None


def outcome_columns(summary: dict[str, Any] | None) -> dict[str, Any]:
    """The outcome columns of a summary (missing fields: None). ``survived`` is 1 when the run did not fall
    and did not collide (``collided``: the summary's, else ``min_clearance_m < 0`` when there is one);
    ``rmse_m`` is the contouring RMS error (paper A) or the step RMSE (paper B)."""
    if summary is None:
        return {k: None for k in OUTCOME_COLUMNS}
    fell = bool(summary.get("fell", False))
    collided = summary.get("collided")
    clearance = summary.get("min_clearance_m")
    if collided is None and clearance is not None:  # a summary without the field: the clearance says it
        collided = clearance < 0.0
    outcome = summary.get("outcome") or ("collided" if collided else "fell" if fell else "completed")
    rmse = summary.get("contouring_error_rms_m", summary.get("step_rmse_m"))
    solve = summary.get("solve_ms") or {}

    def b(v: Any) -> int | None:
        return None if v is None else int(bool(v))

    return {"outcome": outcome, "survived": int(not fell and not collided), "fell": int(fell), "collided": b(collided),
            "overtook": b(summary.get("overtook")), "min_clearance_m": summary.get("min_clearance_m"), "rmse_m": rmse,
            "solver_failures": summary.get("solver_failures"), "relaxed_solves": summary.get("relaxed_solves"),
            "stopped_reason": summary.get("stopped_early") or summary.get("stopped_reason"),
            "solve_ms_median": solve.get("median") if isinstance(solve, dict) else None,
            "stones_reached": summary.get("stones_reached", summary.get("steps_completed")),
            "reached_end": b(summary.get("reached_end")), "progress_m": summary.get("progress_m"),
            "path_length_m": summary.get("path_length_m"), "stall_binding": _stall_binding(summary)}


def _stall_binding(summary: dict[str, Any]) -> str | None:
    """The stall's binding obstacle(s) or constraint, in words (None when the run did not stall)."""
    stall = summary.get("stall")
    if not isinstance(stall, dict):
        return None
    binding = stall.get("binding") or {}
    return str(binding.get("text") or binding.get("kind") or "")


class ResultStore:
    """A sweep's SQLite store (see the module's docstring). Only the sweep's main process writes to it.

    Args:
        path: the ``.sqlite`` file (created with its folder).
        spec: the campaign; an existing store of another campaign is refused.
    """

    def __init__(self, path: str | Path, spec: SweepSpec) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.spec = spec
        self.axes = [a.name for a in spec.axes]
        existed = self.path.is_file() and self.path.stat().st_size > 0
        try:
            self.db = sqlite3.connect(str(self.path), isolation_level=None, timeout=30.0)
        except sqlite3.Error as exc:
            raise SweepStoreError(self.path, f"it cannot be opened ({exc})", "check --out, or pass --replace") from None
        try:
            if existed:
                self._check_existing()
            self._init_schema()
        except sqlite3.Error as exc:
            self.db.close()
            raise self._error(exc, existed) from None
        except BaseException:
            self.db.close()
            raise

    def _check_existing(self) -> None:
        """An existing store is an SQLite file that passes ``PRAGMA quick_check`` and holds a sweep's
        ``meta`` (spec_hash) and ``cases`` tables."""
        check = self.db.execute("PRAGMA quick_check").fetchone()
        if check is None or check[0] != "ok":
            raise sqlite3.DatabaseError(f"database disk image is malformed: {check[0] if check else 'no answer'}")
        tables = {r[0] for r in self.db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        if "meta" not in tables or self.db.execute("SELECT value FROM meta WHERE key = 'spec_hash'").fetchone() is None:
            rows = _good_rows(self.path) if "cases" in tables else None
            raise SweepStoreError(self.path, "it holds no sweep specification (no meta table or spec_hash: not a "
                                  "store of lipmpcc sweep, or one whose creation was cut short)",
                                  _advice(rows, self.path))
        if "cases" not in tables:
            raise SweepStoreError(self.path, "it has no cases table (truncated)", _advice(None, self.path))

    def _error(self, exc: sqlite3.Error, existed: bool) -> SweepStoreError:
        text = " ".join(str(exc).split())
        if "readonly" in text or "read-only" in text or "unable to open" in text:
            return SweepStoreError(self.path, f"it cannot be written ({text})",
                                   "make --out writable, or choose another --out")
        rows = _good_rows(self.path) if existed else None
        return SweepStoreError(self.path, f"it is damaged or not an SQLite file ({text})", _advice(rows, self.path))

    def _init_schema(self) -> None:
        from .. import __version__

        with self.transaction():
            self.db.execute("CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT)")
            row = self.db.execute("SELECT value FROM meta WHERE key = 'spec_hash'").fetchone()
            if row is not None and row[0] != self.spec.hash:
                raise SweepSpecChangedError(str(self.path), row[0], self.spec.hash)
            if row is None:
                cols = [*_BASE_COLUMNS, *(f'"p_{a}" {_sql_type(a)}' for a in self.axes),
                        *(f"{k} {t}" for k, t in OUTCOME_COLUMNS.items()), *_TAIL_COLUMNS]
                self.db.execute(f"CREATE TABLE cases ({', '.join(cols)})")
                meta = {"spec_hash": self.spec.hash, "spec": canonical_json(self.spec.raw), "name": self.spec.name,
                        "study": self.spec.study, "fast_mode": str(self.spec.fast), "lipmpcc_version": __version__,
                        "n_cases": str(len(self.spec.cases())),
                        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
                self.db.executemany("INSERT INTO meta VALUES (?, ?)", list(meta.items()))
            else:  # a store of an older lipmpcc: the outcome columns added since
                have = {r[1] for r in self.db.execute("PRAGMA table_info(cases)")}
                for k, t in OUTCOME_COLUMNS.items():
                    if k not in have:
                        self.db.execute(f"ALTER TABLE cases ADD COLUMN {k} {t}")

    def transaction(self) -> "_Transaction":
        """A ``with`` block that commits on success and rolls back on any exception (Ctrl-C included)."""
        return _Transaction(self.db)

    def status(self) -> dict[str, tuple[str, int]]:
        """case id -> (status, attempts) of every recorded case."""
        return {r[0]: (r[1], r[2]) for r in self.db.execute("SELECT case_id, status, attempts FROM cases")}

    def record(self, case: dict[str, Any], result: dict[str, Any] | None, died: str | None = None) -> None:
        """Append (or replace) the row of ``case`` in one transaction: the worker's ``result``
        (:func:`lipmpcc.sweep.worker.run_case`), or, with ``died``, a worker that died running it."""
        prev = self.db.execute("SELECT attempts FROM cases WHERE case_id = ?", (case["id"],)).fetchone()
        attempts = (prev[0] if prev else 0) + 1
        res = result or {}
        summary = res.get("summary")
        push = res.get("push") or {}
        row: dict[str, Any] = {
            "case_id": case["id"], "idx": case["index"], "planner": case["planner"],
            "status": "died" if died is not None else res.get("status", "error"), "attempts": attempts,
            "params": canonical_json({**case["params"], "robot": case["robot"]}),
            "force_N": push.get("force_N"), "impulse_Ns": push.get("impulse_Ns"),
            **{f"p_{a}": (case["robot"] if a == "robot" else case["params"].get(a)) for a in self.axes},
            **outcome_columns(summary),
            "wall_s": res.get("wall_s"), "worker": res.get("worker"), "error": died if died is not None else res.get("error"),
            "summary": None if summary is None else json.dumps(summary), "finished_at": time.time(),
        }
        names = ", ".join(f'"{k}"' for k in row)
        marks = ", ".join("?" for _ in row)
        try:
            with self.transaction():
                self.db.execute(f"INSERT OR REPLACE INTO cases ({names}) VALUES ({marks})", list(row.values()))
        except sqlite3.Error as exc:
            text = " ".join(str(exc).split())
            kept = _good_rows(self.path)
            raise SweepStoreError(self.path, f"case {case['id']} could not be recorded ({text})",
                                  "every case recorded before is kept" + (f" ({kept} rows)" if kept is not None else "")
                                  + ": make --out writable (and its disk not full) and run the same command again "
                                  "to resume") from None

    def rows(self, where: str = "1", params: Iterable[Any] = ()) -> list[dict[str, Any]]:
        """The rows of ``cases`` (``where``: an SQL condition) as dicts, by case index."""
        cur = self.db.execute(f"SELECT * FROM cases WHERE {where} ORDER BY idx", tuple(params))
        names = [d[0] for d in cur.description]
        return [dict(zip(names, r)) for r in cur.fetchall()]

    def close(self) -> None:
        """Close the connection."""
        self.db.close()


def _advice(rows: int | None, path: Path) -> str:
    """What to do with a damaged store: start over, or keep the rows that can still be read."""
    start_over = "pass --replace to start the sweep over (the store is deleted)"
    if rows:
        return (f"{rows} rows of its cases table can still be read (sqlite3 {path} '.recover' saves them); "
                f"move it away to keep them, or {start_over}")
    return f"no row can be read from it: {start_over}"


def _sql_type(axis: str) -> str:
    return {"float": "REAL", "int": "INTEGER", "str": "TEXT"}[AXES[axis].kind]


class _Transaction:
    def __init__(self, db: sqlite3.Connection) -> None:
        self.db = db

    def __enter__(self) -> sqlite3.Connection:
        self.db.execute("BEGIN IMMEDIATE")
        return self.db

    def __exit__(self, exc_type: object, exc: object, tb: object) -> None:
        self.db.execute("COMMIT" if exc_type is None else "ROLLBACK")
