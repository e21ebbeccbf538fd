"""Full-body runs kept on disk, keyed by everything that makes them: a second reader loads the run instead of
simulating it again.

Notebook 09's core lesson runs paper A's 30 s overtaking on ``digit_like`` and its deep dive (09b) reads the
same run (the whole-body clearance, the model mismatch of each step): :func:`cached_full_body` runs it once
and stores what can be stored, the other notebook loads it. The key (:func:`run_key`) is a digest of the
study's arguments, the robot (its description and its MJCF and scene files), fast mode and the package itself
(every ``.py`` source and the compiled modules of ``lipmpcc``): a changed line of the library makes a new run.
Two processes asking for the same run at once: the second waits for the first's (a lock file beside the
entry) and loads it.

Stored: the run's log, summary, path, obstacles, parameters, pushes and the loop's
:class:`~lipmpcc.loops.fullbody.loop.LoopResult` (the recorded configurations included), and of the footstep
source its name, parameters and plan records (:class:`StoredMpccSource`; the source itself holds the CasADi
solver, which does not pickle). A loaded run's ``loop`` is the loop passed in (or a new one for the robot):
its simulator's model renders the recorded frames (:func:`lipmpcc.studies.path_following.render_frames`).

Where: ``$LIPMPCC_CACHE_DIR/runs`` when the variable is set, else ``$XDG_CACHE_HOME/lipmpcc/runs`` (default
``~/.cache/lipmpcc/runs``). The entries are Python pickles: keep the folder your own (a pickle from
elsewhere can run code when loaded). Deleting the folder is always safe.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import pickle
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path as FsPath
from typing import TYPE_CHECKING, Any, Iterator

import numpy as np

from .. import config
from ..exceptions import InvalidInputError
from ..planners.sources.mpcc import MpccPlanRecord, exchange_mismatches

if TYPE_CHECKING:
    from ..loops.fullbody.loop import FullBodyLoop
    from ..planners.mpcc import MpccParams
    from ..robots import RobotDescription
    from .path_following import FullBodyPathRun

__all__ = ["StoredMpccSource", "cache_dir", "run_key", "cached_full_body", "CACHE_ENV", "STORED_OPTIONS"]

#: the environment variable naming the cache's folder (its ``runs/`` subfolder holds the runs)
CACHE_ENV = "LIPMPCC_CACHE_DIR"
#: the options of :func:`~lipmpcc.studies.path_following.simulate_full_body` a cached run may set (plain
#: values that the key can hold; pushes, settings, viewers are not cached)
STORED_OPTIONS = ("obstacle_speed", "duration", "n_steps", "record_video", "settle_time")
#: the format of an entry: changes when what is stored changes
_FORMAT = "fullbody-path-run-1"


@dataclass
class StoredMpccSource:
    """What a run's MPCC footstep source leaves for the reader: its name, parameters, re-planning rate [Hz] and
    the record of every solve (:class:`~lipmpcc.planners.sources.mpcc.MpccPlanRecord`)."""

    name: str
    params: MpccParams
    rate_hz: float
    records: list[MpccPlanRecord]

    def exchange_mismatches(self) -> tuple[np.ndarray, np.ndarray]:
        """As :meth:`lipmpcc.planners.sources.mpcc.MpccFootstepSource.exchange_mismatches`: the steps (n,) and
        each step's state at the exchange minus what the executed plan predicted (n, 5) [m, m/s, rad]."""
        return exchange_mismatches(self.records)


def cache_dir() -> FsPath:
    """The folder of the stored runs (:data:`CACHE_ENV`, else the XDG cache folder), not created here."""
    root = os.environ.get(CACHE_ENV, "").strip()
    if root:
        return FsPath(root).expanduser() / "runs"
    xdg = os.environ.get("XDG_CACHE_HOME", "").strip()
    return (FsPath(xdg).expanduser() if xdg else FsPath.home() / ".cache") / "lipmpcc" / "runs"


def _package_digest() -> str:
    """A digest of the installed/imported ``lipmpcc``: every ``.py`` source and the compiled modules."""
    pkg = FsPath(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(p for p in pkg.rglob("*") if p.suffix in (".py", ".so", ".pyd") and "__pycache__" not in p.parts):
        h.update(str(path.relative_to(pkg)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def run_key(robot: RobotDescription, scenario: str, planner: str, options: dict[str, Any]) -> str:
    """The hex digest that names a stored run: the study's arguments, the robot (description, MJCF and scene
    files), fast mode, the whole-body QP's default solver (``$LIPMPCC_WBC_QP_SOLVER``), the SQP's default
    convexification (``$LIPMPCC_SQP_CONVEXIFICATION``, ``$LIPMPCC_SQP_PARTIAL_EIGEN``), the entry format and the package's sources."""
    from ..control.wbc_types import default_qp_solver
    from ..solvers.convexify import requested_convexification, requested_partial_eigen

    h = hashlib.sha256()
    h.update(json.dumps({"format": _FORMAT, "scenario": scenario, "planner": planner, "fast": config.fast_mode(),
                         "qp_solver": default_qp_solver(),
                         "options": {k: options[k] for k in sorted(options)}}, sort_keys=True, default=repr).encode())
    h.update(repr(robot).encode())
    h.update(requested_convexification(None).encode())  # the MPCC's SQP (another convexification: other runs)
    if requested_partial_eigen(None):  # the partial eigenvalue clip (rounding-level differences move chaotic runs)
        h.update(b"partial_eigen")
    for path in (robot.mjcf_path, robot.scene_path):
        if path is not None and FsPath(path).is_file():
            h.update(FsPath(path).read_bytes())
    h.update(_package_digest().encode())
    return h.hexdigest()


@contextmanager
def _locked(path: FsPath) -> Iterator[None]:
    """Hold ``path`` (a lock file) exclusively: a second process asking for the same run waits here."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a") as fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh.fileno(), fcntl.LOCK_UN)


def _store(run: FullBodyPathRun, entry: FsPath) -> None:
    src = run.source
    stored = {"format": _FORMAT, "log": run.log, "summary": run.summary, "path": run.path, "obstacles": run.obstacles,
              "params": run.params, "pushes": run.pushes, "settle_time": run.settle_time, "result": run.result,
              "source": StoredMpccSource(src.name, src.params, float(src.rate_hz), list(src.records))}
    tmp = entry.with_suffix(".part")
    with open(tmp, "wb") as fh:
        pickle.dump(stored, fh, protocol=pickle.HIGHEST_PROTOCOL)
    tmp.replace(entry)  # whole or not at all


def _load(entry: FsPath, robot: RobotDescription, loop: FullBodyLoop | None) -> FullBodyPathRun | None:
    from ..loops.fullbody.loop import FullBodyLoop
    from .path_following import FullBodyPathRun

    try:
        with open(entry, "rb") as fh:
            d = pickle.load(fh)  # noqa: S301 - the user's own cache folder (module docstring)
    except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ImportError):
        return None  # absent, torn or from an older package: run again
    if not isinstance(d, dict) or d.get("format") != _FORMAT:
        return None
    loop = loop if loop is not None else FullBodyLoop(robot, planner=None)
    return FullBodyPathRun(d["log"], d["summary"], d["path"], d["obstacles"], d["params"], d["pushes"],
                           d["settle_time"], d["result"], d["source"], loop)


def cached_full_body(robot: RobotDescription, scenario: str, planner: str = "mpcc", *,
                     loop: FullBodyLoop | None = None, **options: Any) -> tuple[FullBodyPathRun, bool]:
    """:func:`~lipmpcc.studies.path_following.simulate_full_body` once per key: the stored run when there is
    one, else the run made now and stored.

    Args:
        robot: the robot (:func:`lipmpcc.robots.load_robot`).
        scenario: ``"circle"``, ``"circle-push"`` or ``"overtake"``; planner: ``"mpcc"`` or ``"cartesian"``.
        loop: a loop whose simulator and whole-body controller a new run reuses, and which a loaded run gets
            as its ``loop`` (None: a new one).
        **options: any of :data:`STORED_OPTIONS` (e.g. ``obstacle_speed=0.6, duration=30.0``).

    Returns:
        ``(run, loaded)``: the run and whether it was loaded from the cache (True) or simulated now. A loaded
        run's ``source`` is a :class:`StoredMpccSource`.
    """
    from .path_following import simulate_full_body

    unknown = sorted(set(options) - set(STORED_OPTIONS))
    if unknown:
        raise InvalidInputError("options", unknown, f"only {', '.join(STORED_OPTIONS)} (plain values the key can hold)")
    entry = cache_dir() / f"{run_key(robot, scenario, planner, options)}.pkl"
    with _locked(entry.with_suffix(".lock")):
        run = _load(entry, robot, loop)
        if run is not None:
            return run, True
        run = simulate_full_body(robot, scenario, planner, loop=loop, **options)
        _store(run, entry)
    return run, False
