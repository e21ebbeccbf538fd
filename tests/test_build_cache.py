"""The content-addressed cache of the compiled modules (cmake/module_cache.cmake): the README's second
command, run after the first, reuses the modules the first compiled instead of compiling them again.

Checked in CMake's script mode on a scratch source tree: the key is stable, changes with any file
under cpp/ or with the toolchain strings, and only a complete cache entry (a MANIFEST whose files all
exist) is reused."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
MODULE_CACHE = ROOT / "cmake" / "module_cache.cmake"

pytestmark = pytest.mark.skipif(shutil.which("cmake") is None or not MODULE_CACHE.is_file(),
                                reason="needs cmake and the source tree's cmake/module_cache.cmake")


def _cmake(script: str, tmp_path: Path) -> str:
    f = tmp_path / "probe.cmake"
    f.write_text(f'include("{MODULE_CACHE.as_posix()}")\n{script}\n')
    r = subprocess.run(["cmake", "-P", str(f)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return r.stderr.strip()  # message() writes to stderr


def _key(src: Path, tmp_path: Path, *extra: str) -> str:
    args = " ".join(f'"{e}"' for e in extra)
    return _cmake(f'lipmpcc_module_cache_key(k "{src.as_posix()}" {args})\nmessage("${{k}}")', tmp_path)


@pytest.fixture()
def src(tmp_path: Path) -> Path:
    s = tmp_path / "src"
    (s / "cpp" / "wbc" / "src").mkdir(parents=True)
    (s / "cpp" / "wbc" / "src" / "a.cpp").write_text("int a() { return 1; }\n")
    (s / "CMakeLists.txt").write_text("project(x)\n")
    (s / "python").mkdir()
    (s / "python" / "x.py").write_text("x = 1\n")
    return s


def test_the_key_is_stable_and_follows_every_input(src: Path, tmp_path: Path) -> None:
    k0 = _key(src, tmp_path, "GNU 12.2.0", "pin 4.1.0")
    assert len(k0) == 64 and k0 == _key(src, tmp_path, "GNU 12.2.0", "pin 4.1.0")
    (src / "python" / "x.py").write_text("x = 2\n")  # Python sources do not go into the modules
    assert _key(src, tmp_path, "GNU 12.2.0", "pin 4.1.0") == k0
    assert _key(src, tmp_path, "GNU 13.1.0", "pin 4.1.0") != k0  # another compiler
    assert _key(src, tmp_path, "GNU 12.2.0", "pin 4.2.0") != k0  # another pinocchio
    (src / "cpp" / "wbc" / "src" / "a.cpp").write_text("int a() { return 2; }\n")
    k1 = _key(src, tmp_path, "GNU 12.2.0", "pin 4.1.0")
    assert k1 != k0
    (src / "cpp" / "wbc" / "src" / "b.hpp").write_text("// new header\n")
    assert _key(src, tmp_path, "GNU 12.2.0", "pin 4.1.0") != k1


def test_only_a_complete_entry_is_reused(tmp_path: Path) -> None:
    entry = tmp_path / "cache" / "KEY"
    probe = f'lipmpcc_cached_modules(m "{entry.as_posix()}")\nmessage("[${{m}}]")'
    assert _cmake(probe, tmp_path) == "[]"  # no entry
    entry.mkdir(parents=True)
    (entry / "_wbc.so").write_bytes(b"\x7fELF")
    assert _cmake(probe, tmp_path) == "[]"  # no MANIFEST: an interrupted store
    (entry / "MANIFEST").write_text("_wbc.so\n_mjtick.so\n")
    assert _cmake(probe, tmp_path) == "[]"  # a listed file is missing
    (entry / "_mjtick.so").write_bytes(b"\x7fELF")
    found = _cmake(probe, tmp_path).strip("[]").split(";")
    assert [Path(f).name for f in found] == ["_wbc.so", "_mjtick.so"]


def test_the_top_level_build_uses_the_cache() -> None:
    text = (ROOT / "CMakeLists.txt").read_text()
    assert "include(cmake/module_cache.cmake)" in text
    assert "lipmpcc_store_modules" in text and "lipmpcc_cached_modules" in text
