"""lipmpcc._lazy: names of a package loaded from their module on first use."""

from __future__ import annotations

import subprocess
import sys

import pytest

from lipmpcc._lazy import lazy_exports


def test_loads_caches_and_lists() -> None:
    ns: dict[str, object] = {}
    getattr_, dir_ = lazy_exports("lipmpcc", {"Push": "push", "GRAVITY": "conventions"}, ns)
    from lipmpcc.push import Push

    assert getattr_("Push") is Push and ns["Push"] is Push  # cached in the package namespace
    assert getattr_("GRAVITY") == 9.81
    assert dir_() == ["GRAVITY", "Push"]
    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        getattr_("Nope")


def test_importing_the_package_loads_no_heavy_dependency() -> None:
    code = "import sys, lipmpcc; print(sorted(m for m in ('casadi', 'mujoco', 'pinocchio') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_every_public_name_of_the_root_resolves() -> None:
    import lipmpcc

    for name in lipmpcc.__all__:
        assert getattr(lipmpcc, name) is not None, name
