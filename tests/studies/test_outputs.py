"""lipmpcc.studies.outputs: output folders written whole or not at all, refused when they hold something,
locked against a second writer, with failed.json when the run fails (issue 14)."""

from __future__ import annotations

import json
import os
import signal
from datetime import datetime
from pathlib import Path

import pytest

from lipmpcc.exceptions import InvalidInputError, OutputBusyError, OutputFolderError
from lipmpcc.studies import outputs
from lipmpcc.studies.outputs import (
    FAILED_FILE,
    OutputLock,
    StagedFolder,
    check_folder_path,
    check_out,
    default_out,
    deferred_interrupt,
    lock_path,
    move_into_place,
    write_text_atomic,
)


def _leftovers(folder: Path) -> list[str]:
    """Hidden staging folders, old folders, temporary files and locks left in ``folder``."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") or p.name.endswith(".lock"))


def _earlier_run(folder: Path) -> Path:
    folder.mkdir(parents=True)
    (folder / "summary.json").write_text('{"fell": false}')
    (folder / "old.png").write_bytes(b"png")
    return folder


@pytest.mark.parametrize("bad, words", [
    ("", "an empty path names no folder"),
    ("   ", "an empty path names no folder"),
    (3, "a int is not a path"),
    ("a\0b", "NUL"),
])
def test_a_path_that_names_no_folder_is_refused(bad: object, words: str) -> None:
    with pytest.raises(OutputFolderError, match=words) as e:
        check_folder_path(bad)  # type: ignore[arg-type]
    assert isinstance(e.value, InvalidInputError) and e.value.name == "--out"
    assert "expected a folder path that can be created and written" in str(e.value)


def test_a_file_or_a_path_under_a_file_is_refused(tmp_path: Path) -> None:
    f = tmp_path / "f.txt"
    f.write_text("x")
    with pytest.raises(OutputFolderError, match="it is an existing file, not a folder"):
        check_out(f)
    with pytest.raises(OutputFolderError, match=r"f.txt is a file, not a folder"):
        check_out(f / "sub" / "out")


def test_a_folder_that_cannot_be_written_is_refused(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(outputs.os, "access", lambda path, mode: False)  # as root, chmod would not stop us
    with pytest.raises(OutputFolderError, match="is not writable") as e:
        check_out(tmp_path / "new")
    assert str(tmp_path) in str(e.value) and "a folder path that can be created and written" in str(e.value)


def test_a_new_or_empty_folder_is_accepted_and_one_holding_anything_is_refused(tmp_path: Path) -> None:
    assert check_out(tmp_path / "a" / "b") == tmp_path / "a" / "b"  # nothing is created
    assert not (tmp_path / "a").exists()
    (tmp_path / "empty").mkdir()
    assert check_out(tmp_path / "empty") == tmp_path / "empty"
    run = _earlier_run(tmp_path / "run")
    with pytest.raises(OutputFolderError, match="it holds an earlier run: summary.json and 1 other entry; pass --replace"):
        check_out(run)
    other = tmp_path / "notes"
    other.mkdir()
    (other / "todo.txt").write_text("mine")
    with pytest.raises(OutputFolderError, match="it holds 1 entry: todo.txt; pass --replace"):
        check_out(other)


def test_replace_takes_only_an_earlier_runs_folder(tmp_path: Path, monkeypatch) -> None:
    run = _earlier_run(tmp_path / "run")
    assert check_out(run, replace=True) == run
    failed = tmp_path / "failed"
    failed.mkdir()
    (failed / FAILED_FILE).write_text("{}")
    assert check_out(failed, replace=True) == failed
    other = tmp_path / "notes"
    other.mkdir()
    (other / "todo.txt").write_text("mine")
    with pytest.raises(OutputFolderError, match="nothing is deleted"):
        check_out(other, replace=True)
    (run / "sub").mkdir()  # a reproduce folder, say: not a run's
    with pytest.raises(OutputFolderError, match="no sub-folder"):
        check_out(run, replace=True)
    monkeypatch.chdir(failed)
    with pytest.raises(OutputFolderError, match="working folder"):
        check_out(".", replace=True)


def test_the_default_folder_is_new_per_run(tmp_path: Path) -> None:
    now = datetime(2026, 12, 2, 7, 8, 9)
    a = default_out("circle", None, tmp_path, now)
    assert a == tmp_path / "circle-lip-20261202-070809"
    assert default_out("stones", None, tmp_path, now).name == "stones-alip-20261202-070809"
    assert default_out("walk", None, tmp_path, now).name == "walk-digit_like-20261202-070809"
    assert default_out("overtake", "models/my_bot.xml", tmp_path, now).name == "overtake-my_bot-20261202-070809"
    a.mkdir()
    b = default_out("circle", "lip", tmp_path, now)
    assert b.name == "circle-lip-20261202-070809-2"
    lock_path(b).write_text("")  # another run is starting there
    assert default_out("circle", "lip", tmp_path, now).name == "circle-lip-20261202-070809-3"


def test_a_second_writer_is_refused_while_the_lock_is_held(tmp_path: Path) -> None:
    out = tmp_path / "sub" / "run"
    with OutputLock(out) as lock:
        assert lock.path == tmp_path / "sub" / "run.lock" and lock.path.exists()
        assert lock.path.read_text().startswith(f"pid {os.getpid()} since ")
        with pytest.raises(OutputBusyError) as e:
            OutputLock(out).acquire()
        msg = str(e.value)
        assert msg.startswith(f"--out {out}: another lipmpcc run (pid {os.getpid()} since") and "run.lock" in msg
        assert "\n" not in msg and e.value.path == str(out)
    assert not lock.path.exists()
    with OutputLock(out):  # free again
        pass


def test_a_lock_file_left_by_a_killed_run_is_taken_over(tmp_path: Path) -> None:
    out = tmp_path / "run"
    lock_path(out).write_text("pid 999999 since 2026-01-01T00:00:00+00:00\n")
    with OutputLock(out) as lock:
        assert lock.path.read_text().startswith(f"pid {os.getpid()}")
    assert not lock_path(out).exists()


def test_a_staged_folder_appears_whole_and_replaces_an_earlier_run_whole(tmp_path: Path) -> None:
    target = _earlier_run(tmp_path / "run")
    with StagedFolder(target) as stage:
        assert stage.tmp.parent == tmp_path and stage.tmp.name.startswith(".run.partial-")
        (stage.tmp / "summary.json").write_text('{"new": true}')
        assert json.loads((target / "summary.json").read_text()) == {"fell": False}  # not yet
    assert sorted(p.name for p in target.iterdir()) == ["summary.json"]  # old.png is gone: never mixed
    assert json.loads((target / "summary.json").read_text()) == {"new": True}
    assert _leftovers(tmp_path) == []
    assert oct(target.stat().st_mode & 0o777) == oct(0o777 & ~_umask())  # as mkdir would make it


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def test_a_failed_run_leaves_only_failed_json(tmp_path: Path) -> None:
    target = _earlier_run(tmp_path / "run")
    stage = StagedFolder(target, {"scenario": "circle", "steps": 3})
    with pytest.raises(OSError, match="disk full"):
        with stage:
            (stage.tmp / "summary.json").write_text("{}")
            raise OSError("disk full")
    assert [p.name for p in target.iterdir()] == [FAILED_FILE] and stage.failed == target / FAILED_FILE
    rec = json.loads(stage.failed.read_text())
    assert rec["failed"] is True and rec["error"] == "OSError: disk full" and rec["error_type"] == "OSError"
    assert rec["options"] == {"scenario": "circle", "steps": 3} and rec["time"].endswith("+00:00") and rec["lipmpcc"]
    assert _leftovers(tmp_path) == []


def test_an_interrupted_run_leaves_nothing_and_the_target_as_it_was(tmp_path: Path) -> None:
    target = _earlier_run(tmp_path / "run")
    with pytest.raises(KeyboardInterrupt):
        with StagedFolder(target) as stage:
            (stage.tmp / "summary.json").write_text("{}")
            raise KeyboardInterrupt
    assert sorted(p.name for p in target.iterdir()) == ["old.png", "summary.json"]
    with pytest.raises(KeyboardInterrupt):
        with StagedFolder(tmp_path / "new"):
            raise KeyboardInterrupt
    assert not (tmp_path / "new").exists() and _leftovers(tmp_path) == []


def test_move_into_place_puts_the_old_folder_back_when_the_rename_fails(tmp_path: Path, monkeypatch) -> None:
    target = _earlier_run(tmp_path / "run")
    src = tmp_path / "src"
    src.mkdir()
    real = os.rename

    def rename(a, b):
        if Path(a) == src:
            raise OSError("no")
        return real(a, b)

    monkeypatch.setattr(outputs.os, "rename", rename)
    with pytest.raises(OSError):
        move_into_place(src, target)
    assert (target / "summary.json").exists() and not any(p.name.startswith(".run.old") for p in tmp_path.iterdir())


def test_write_text_atomic_leaves_no_temporary_file(tmp_path: Path) -> None:
    p = tmp_path / "report.md"
    p.write_text("old")
    assert write_text_atomic(p, "new") == p and p.read_text() == "new"
    assert [x.name for x in tmp_path.iterdir()] == ["report.md"]


def test_deferred_interrupt_holds_ctrl_c_until_the_block_ends() -> None:
    done = []
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt():
            os.kill(os.getpid(), signal.SIGINT)
            done.append("the block ran to its end")
    assert done == ["the block ran to its end"]
    with deferred_interrupt():  # no Ctrl-C: nothing raised
        pass


def test_is_interrupt_follows_the_chain_of_an_error() -> None:
    from lipmpcc.studies.outputs import is_interrupt

    assert is_interrupt(KeyboardInterrupt()) and not is_interrupt(None) and not is_interrupt(ValueError("x"))
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt:
            raise RuntimeError("release unlocked lock")  # raised while handling it
    except RuntimeError as exc:
        assert is_interrupt(exc)
    err = SystemError("returned a result with an exception set")
    err.__cause__ = KeyboardInterrupt()
    assert is_interrupt(err)
    loop = ValueError("a")
    loop.__context__ = ValueError("b")
    loop.__context__.__context__ = loop  # a cycle ends the walk
    assert not is_interrupt(loop)


def test_in_finalizer_sees_a_del_anywhere_up_the_stack() -> None:
    import sys

    from lipmpcc.studies.outputs import in_finalizer

    seen: list[bool] = []

    def probe() -> None:
        seen.append(in_finalizer(sys._getframe()))

    class Finalized:
        def __del__(self) -> None:
            probe()

    probe()
    Finalized()
    assert seen == [False, True]
