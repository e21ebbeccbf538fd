"""Output folders that never mix and never lie: what ``lipmpcc run`` and ``lipmpcc reproduce`` write.

- :func:`check_folder_path` / :func:`check_out`: ``--out`` is a folder path that can be created and
  written; a run's ``--out`` is new or empty, or (with ``--replace``) the folder of an earlier run.
- :class:`OutputLock`: ``OUT.lock`` beside the folder, held (``fcntl.flock``) while a command writes;
  a second command on the same folder gets :class:`~lipmpcc.exceptions.OutputBusyError` at once.
- :class:`StagedFolder`: the run writes into a fresh hidden folder beside the target
  (``.NAME.partial-XXXX``), moved into place only when everything is written. A failure replaces the
  target by a folder holding only ``failed.json`` (:data:`FAILED_FILE`: the error, the options, the
  time); an interrupt (``KeyboardInterrupt``) removes the staging folder and leaves the target as it was.
- :func:`write_text_atomic`: a file written beside its target and renamed over it.
- :func:`deferred_interrupt`: Ctrl-C held back while a folder is moved into place.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import threading
import uuid
from datetime import datetime, timezone
from pathlib import Path
from types import TracebackType
from typing import Any, Iterator

from ..exceptions import OutputBusyError, OutputFolderError
from .applicability import SCENARIO_ROBOTS
from .options import jsonable

try:  # POSIX
    import fcntl
except ImportError:  # pragma: no cover - Windows: the lock is the file's existence
    fcntl = None  # type: ignore[assignment]

__all__ = [
    "SUMMARY_FILE",
    "FAILED_FILE",
    "LOCK_SUFFIX",
    "RUN_MARKERS",
    "DEFAULT_ROOT",
    "default_out",
    "check_folder_path",
    "check_out",
    "lock_path",
    "OutputLock",
    "StagedFolder",
    "move_into_place",
    "failure_record",
    "write_text_atomic",
    "deferred_interrupt",
    "is_interrupt",
    "in_finalizer",
]

SUMMARY_FILE = "summary.json"
FAILED_FILE = "failed.json"
LOCK_SUFFIX = ".lock"
#: files that mark a folder as a lipmpcc run's output (a run's or a failed run's)
RUN_MARKERS = (SUMMARY_FILE, FAILED_FILE)
DEFAULT_ROOT = "results"  # the default runs go to results/SCENARIO-ROBOT-YYYYmmdd-HHMMSS
_EXPECTED = "a folder path that can be created and written"


def _robot_label(scenario: str, robot: str | None) -> str:
    if robot and robot.lower().endswith(".xml"):
        return Path(robot).stem or "robot"
    if robot:
        return robot
    reduced = SCENARIO_ROBOTS.get(scenario, (None, None))[1]
    return reduced or "digit_like"


def default_out(scenario: str, robot: str | None = None, root: str | Path = DEFAULT_ROOT,
                now: datetime | None = None) -> Path:
    """A new folder for one run: ``ROOT/SCENARIO-ROBOT-YYYYmmdd-HHMMSS`` (local time; ``-2``, ``-3``, ...
    appended when that name or its lock is taken). ``robot`` None is the scenario's default robot; a
    ``PATH.xml`` is named by its stem."""
    stamp = (now or datetime.now()).strftime("%Y%m%d-%H%M%S")
    base = Path(root) / f"{scenario}-{_robot_label(scenario, robot)}-{stamp}"
    out, k = base, 1
    while out.exists() or lock_path(out).exists():
        k += 1
        out = base.with_name(f"{base.name}-{k}")
    return out


def _as_path(out: object, option: str) -> Path:
    if isinstance(out, Path):
        text = str(out)
    elif isinstance(out, str):
        text = out
    else:
        raise OutputFolderError(option, out, _EXPECTED, f"a {type(out).__name__} is not a path")
    if not text.strip():
        raise OutputFolderError(option, out, _EXPECTED, "an empty path names no folder")
    if "\0" in text:
        raise OutputFolderError(option, out, _EXPECTED, "a path cannot hold a NUL character")
    return Path(text)


def check_folder_path(out: str | Path, option: str = "--out") -> Path:
    """``out`` as a Path, after checking that it can be the output folder: not empty, not an existing
    file, and its nearest existing ancestor a folder that can be written (nothing is created).

    Raises:
        OutputFolderError: one line naming ``out`` and what was expected.
    """
    p = _as_path(out, option)
    try:
        p.resolve()
    except (RuntimeError, OSError):  # a symbolic link loop on the way (RuntimeError before Python 3.13)
        raise OutputFolderError(option, str(out), _EXPECTED, "a symbolic link on it loops") from None
    if p.is_symlink() and not p.exists():
        raise OutputFolderError(option, str(out), _EXPECTED, "it is a symbolic link that leads nowhere (a loop, or a "
                                "missing target)")
    if p.exists() and not p.is_dir():
        raise OutputFolderError(option, str(out), _EXPECTED, "it is an existing file, not a folder")
    probe = p.parent  # where the staging folder and the lock file go
    while not probe.exists() and probe != probe.parent:
        probe = probe.parent
    if not probe.is_dir():
        raise OutputFolderError(option, str(out), _EXPECTED, f"{probe} is a file, not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise OutputFolderError(option, str(out), _EXPECTED,
                                f"{probe} is not writable: the run is written beside the folder, then moved into place")
    return p


def _describe(entries: list[str]) -> str:
    markers = [m for m in RUN_MARKERS if m in entries]
    if markers:
        more = len(entries) - 1
        return f"an earlier run: {markers[0]}" + (f" and {more} other entr{'y' if more == 1 else 'ies'}" if more else "")
    shown = ", ".join(sorted(entries)[:3]) + (", ..." if len(entries) > 3 else "")
    return f"{len(entries)} entr{'y' if len(entries) == 1 else 'ies'}: {shown}"


def check_out(out: str | Path, replace: bool = False, option: str = "--out") -> Path:
    """``out`` checked as a run's output folder (:func:`check_folder_path`) that is new or empty, or,
    with ``replace``, the folder of an earlier run (it holds ``summary.json`` or ``failed.json`` and no
    sub-folder, and is not the working folder or one of its parents) that the run replaces whole.

    Raises:
        OutputFolderError: one line naming ``out``, what it holds and what was expected.
    """
    p = check_folder_path(out, option)
    if not p.is_dir():
        return p
    entries = [e.name for e in p.iterdir()]
    if not entries:
        return p
    if not replace:
        raise OutputFolderError(option, str(out), "a new or empty folder",
                                f"it holds {_describe(entries)}; pass --replace to replace it whole")
    cwd = Path.cwd().resolve()
    target = p.resolve()
    if target == cwd or target in cwd.parents:
        raise OutputFolderError(option, str(out), "a folder of an earlier run to replace",
                                "it is the working folder or one of its parents: nothing is deleted")
    has_dirs = any((p / e).is_dir() and not (p / e).is_symlink() for e in entries)
    if not any(m in entries for m in RUN_MARKERS) or has_dirs:
        raise OutputFolderError(option, str(out), "a folder of an earlier run to replace (summary.json or failed.json, "
                                "no sub-folder)", f"it holds {_describe(entries)}: nothing is deleted")
    return p


def lock_path(out: str | Path) -> Path:
    """The lock file of the output folder ``out``: ``OUT.lock`` beside it."""
    p = Path(out)
    return p.with_name(p.name + LOCK_SUFFIX)


class OutputLock:
    """``OUT.lock`` beside the output folder ``out``, held while a command writes to ``out``.

    ``with OutputLock(out):`` creates the parent folder if needed, takes the lock at once or raises
    :class:`~lipmpcc.exceptions.OutputBusyError`, and removes the lock file on the way out. A lock file
    left by a killed process is not held, and is taken over.
    """

    def __init__(self, out: str | Path) -> None:
        self.out = Path(out)
        self.path = lock_path(self.out)
        self._fd: int | None = None

    def _holder(self) -> str:
        try:
            return self.path.read_text().strip()
        except OSError:
            return ""

    def _open(self) -> int:
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            flags = os.O_RDWR | os.O_CREAT | (os.O_EXCL if fcntl is None else 0)
            return os.open(self.path, flags, 0o644)
        except FileExistsError:  # pragma: no cover - without fcntl
            raise OutputBusyError(str(self.out), str(self.path), self._holder()) from None
        except OSError as exc:
            raise OutputFolderError("--out", str(self.out), _EXPECTED, f"{exc.strerror or exc}: {exc.filename or self.path}") from None

    def acquire(self) -> None:
        """Take the lock (see the class doc)."""
        for _ in range(20):
            fd = self._open()
            if fcntl is not None:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except OSError:
                    os.close(fd)
                    raise OutputBusyError(str(self.out), str(self.path), self._holder()) from None
                try:
                    same = os.path.samestat(os.fstat(fd), os.stat(self.path))
                except FileNotFoundError:
                    same = False
                if not same:  # the holder removed the file between our open and our lock: again
                    os.close(fd)
                    continue
            stamp = datetime.now(timezone.utc).isoformat(timespec="seconds")
            os.ftruncate(fd, 0)
            os.write(fd, f"pid {os.getpid()} since {stamp}\n".encode())
            self._fd = fd
            return
        raise OutputBusyError(str(self.out), str(self.path), self._holder())  # pragma: no cover

    def release(self) -> None:
        """Remove the lock file and let the lock go (nothing when not held)."""
        if self._fd is None:
            return
        with contextlib.suppress(OSError):
            self.path.unlink()
        os.close(self._fd)
        self._fd = None

    def __enter__(self) -> OutputLock:
        self.acquire()
        return self

    def __exit__(self, et: type[BaseException] | None, ev: BaseException | None, tb: TracebackType | None) -> None:
        self.release()


def is_interrupt(exc: BaseException | None) -> bool:
    """True when ``exc`` is a ``KeyboardInterrupt`` or was raised from or while handling one (a Ctrl-C
    that a library turned into another error: ``SystemError: ... returned a result with an exception
    set``, a helper thread's ``RuntimeError``)."""
    seen: set[int] = set()
    e = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


def in_finalizer(frame: Any) -> bool:
    """True when ``frame`` (a signal handler's) or one of its callers is a ``__del__``: an exception raised
    there is only printed ("Exception ignored in ...") and the code goes on, so a handler that means to stop
    the code must not raise there (it fires again a moment later instead)."""
    while frame is not None:
        if frame.f_code.co_name == "__del__":
            return True
        frame = frame.f_back
    return False


@contextlib.contextmanager
def deferred_interrupt() -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) back during the block and raise ``KeyboardInterrupt`` after it if one came
    (in the main thread only; elsewhere the block runs as is)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got: list[int] = []
    try:
        previous = signal.signal(signal.SIGINT, lambda signum, frame: got.append(signum))
    except ValueError:  # pragma: no cover - no signals here
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if got:
        raise KeyboardInterrupt


def _remove(path: Path) -> None:
    if path.is_symlink():  # an --out that was a link: the link goes, not what it points to
        with contextlib.suppress(OSError):
            path.unlink()
        return
    shutil.rmtree(path, ignore_errors=True)


def move_into_place(src: Path, target: Path) -> None:
    """Rename the folder ``src`` to ``target``, replacing ``target`` whole when it exists (it is moved
    aside first, then removed; put back if the rename fails)."""
    old = None
    if target.exists():
        old = target.with_name(f".{target.name}.old-{uuid.uuid4().hex[:8]}")
        os.rename(target, old)
    try:
        os.rename(src, target)
    except OSError:
        if old is not None:
            os.rename(old, target)
        raise
    if old is not None:
        _remove(old)


def failure_record(exc: BaseException, options: dict[str, Any] | None = None) -> dict[str, Any]:
    """The content of ``failed.json``: the error (type and message), the options and the time (UTC)."""
    from .. import __version__

    return {
        "failed": True,
        "error": f"{type(exc).__name__}: {exc}",
        "error_type": type(exc).__name__,
        "message": str(exc),
        "options": jsonable(options or {}),
        "time": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "lipmpcc": __version__,
    }


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a file beside it renamed over it (a reader sees the old file
    or the new one, never half of one)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:12]}.tmp")
    try:
        with open(tmp, "x") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return path


class StagedFolder:
    """``with StagedFolder(target, options) as stage:`` write the run's files into ``stage.tmp``.

    On a normal exit the staging folder replaces ``target`` whole (:func:`move_into_place`). On an
    exception the staging folder is removed and ``target`` is replaced by a folder holding only
    ``failed.json`` (:func:`failure_record`), then the exception goes on. On ``KeyboardInterrupt`` (or
    an error raised from one, :func:`is_interrupt`, or any other ``BaseException``) the staging folder is
    removed and ``target`` is left as it was.
    The caller checks ``target`` (:func:`check_out`) and holds its lock (:class:`OutputLock`).
    """

    def __init__(self, target: str | Path, options: dict[str, Any] | None = None) -> None:
        self.target = Path(target)
        self.options = options
        self.tmp = self.target  # set on entering
        self.failed: Path | None = None  # failed.json when the block raised

    def _mkdtemp(self) -> Path:
        try:
            self.target.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.target.with_name(f".{self.target.name}.partial-{uuid.uuid4().hex[:12]}")
            tmp.mkdir()  # the user's umask, as the target would have (mkdtemp: 0o700)
            return tmp
        except OSError as exc:
            raise OutputFolderError("--out", str(self.target), _EXPECTED, f"{exc.strerror or exc}: {exc.filename or self.target.parent}") from None

    def __enter__(self) -> StagedFolder:
        self.tmp = self._mkdtemp()
        return self

    def _write_failed(self, exc: BaseException) -> None:
        tmp = self._mkdtemp()
        try:
            (tmp / FAILED_FILE).write_text(json.dumps(failure_record(exc, self.options), indent=2, default=str))
            with deferred_interrupt():
                move_into_place(tmp, self.target)
            self.failed = self.target / FAILED_FILE
        finally:
            _remove(tmp)

    def __exit__(self, et: type[BaseException] | None, ev: BaseException | None, tb: TracebackType | None) -> None:
        if et is None:
            try:
                with deferred_interrupt():
                    move_into_place(self.tmp, self.target)
            except Exception as exc:  # the folder could not be moved into place: the run failed
                _remove(self.tmp)
                with contextlib.suppress(Exception):
                    self._write_failed(exc)
                raise
            return
        with deferred_interrupt():
            _remove(self.tmp)
        if isinstance(ev, Exception) and not is_interrupt(ev):
            with contextlib.suppress(Exception):  # the run's own error is the one to report
                self._write_failed(ev)
