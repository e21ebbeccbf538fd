"""``lipmpcc sweep``: grid and Monte-Carlo campaigns over a study (pushes, obstacle speeds, stones, robots),
on local processes or a Dask cluster, resumable, with survival statistics.

Modules::

    spec   -- the TOML specification, validated up front and expanded into plain, seeded cases
    worker -- one case in a worker, through :func:`lipmpcc.studies.run` (the code path of ``lipmpcc run``)
    processes -- the local pool's processes die with the sweep; orphans of a killed sweep are stopped
    store  -- the SQLite results store (one row per finished case, one transaction each)
    runner -- the local process pool, any ``concurrent.futures.Executor`` (Dask), resuming, Ctrl-C
    report -- ``report.md`` and the figures: survival against impulse (Wilson intervals), the largest
              recoverable impulse per direction, overtaking success against obstacle speed
"""

from __future__ import annotations

from .report import wilson_interval, write_report
from .runner import SweepInterrupted, SweepStats, available_cpus, dask_executor, local_pool, run_sweep
from .spec import AXES, SweepSize, SweepSpec, load_spec, parse_spec, sweep_size
from .store import STORE_NAME, ResultStore, SweepSpecChangedError, SweepStoreError

__all__ = [
    "AXES",
    "STORE_NAME",
    "ResultStore",
    "SweepInterrupted",
    "SweepSpec",
    "SweepSize",
    "SweepSpecChangedError",
    "SweepStoreError",
    "SweepStats",
    "available_cpus",
    "dask_executor",
    "load_spec",
    "local_pool",
    "parse_spec",
    "run_sweep",
    "sweep_size",
    "wilson_interval",
    "write_report",
]
