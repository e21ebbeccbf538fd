"""Every public name of lipmpcc 0.1 still resolves in 0.2, from its old module; the ones that moved
warn with a DeprecationWarning that names the new place (CHANGELOG.md lists them; removed in 0.3).

``tests/data/api_0_1.json`` is the public surface of 0.1 (commit 8ec1328): every top-level name of
every module that does not start with an underscore.
"""

from __future__ import annotations

import importlib
import json
import warnings
from pathlib import Path

import pytest

API_0_1: dict[str, list[str]] = json.loads((Path(__file__).parent / "data" / "api_0_1.json").read_text())
CASES = [(mod, name) for mod, names in sorted(API_0_1.items()) for name in names]


def _get(mod: str, name: str) -> tuple[object, list[warnings.WarningMessage]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(mod)
        value = getattr(module, name)
    return value, [w for w in caught if issubclass(w.category, DeprecationWarning)]


@pytest.mark.parametrize("mod, name", CASES, ids=[f"{m}.{n}" for m, n in CASES])
def test_every_0_1_name_resolves(mod: str, name: str) -> None:
    value, warned = _get(mod, name)
    assert value is not None or name in ("com_height",)
    for w in warned:  # a warning names the old path and where to go
        text = str(w.message)
        assert name in text and ("lipmpcc." in text) and ("0.3" in text), text


def test_moved_modules_warn_and_hand_out_the_new_objects() -> None:
    cases = {
        ("lipmpcc.sim.fullbody_loop", "FullBodyLoop"): ("lipmpcc.loops.fullbody", "FullBodyLoop"),
        ("lipmpcc.sim.lip_loop", "simulate"): ("lipmpcc.loops.lip", "simulate"),
        ("lipmpcc.sim.alip_loop", "run_alip_loop"): ("lipmpcc.loops.alip", "run_alip_loop"),
        ("lipmpcc.robot", "load_robot"): ("lipmpcc.robots", "load_robot"),
        ("lipmpcc.wbc", "WholeBodyController"): ("lipmpcc.control.wbc", "WholeBodyController"),
        ("lipmpcc.trajectory", "StepTrajectory"): ("lipmpcc.control.references", "StepTrajectory"),
        ("lipmpcc.planners.mpcc_source", "MpccFootstepSource"): ("lipmpcc.planners.sources.mpcc", "MpccFootstepSource"),
        ("lipmpcc.planners.alip_source", "AlipFootstepSource"): ("lipmpcc.planners.sources.alip", "AlipFootstepSource"),
        ("lipmpcc.scenarios", "RunOptions"): ("lipmpcc.studies", "RunOptions"),
        ("lipmpcc.sim.fullbody_loop", "StepPlan"): ("lipmpcc.planners.base", "StepPlan"),
    }
    for (old, name), (new, new_name) in cases.items():
        value, warned = _get(old, name)
        assert value is getattr(importlib.import_module(new), new_name), (old, name)
        assert warned and new in str(warned[0].message), (old, name, [str(w.message) for w in warned])


def test_the_package_itself_uses_no_old_path() -> None:
    """Importing every non-deprecated module raises no DeprecationWarning of lipmpcc's."""
    root = Path(importlib.import_module("lipmpcc").__file__).parent
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for p in sorted(root.rglob("*.py")):
            text = p.read_text()
            if p.name == "__main__.py" or text.lstrip().startswith('"""Deprecated:'):
                continue
            mod = ".".join(p.relative_to(root.parent).with_suffix("").parts).removesuffix(".__init__")
            importlib.import_module(mod)
    ours = [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning) and "lipmpcc" in str(w.message)]
    assert not ours, ours
