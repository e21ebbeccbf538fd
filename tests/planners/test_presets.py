"""The planners' presets and settable parameters (lipmpcc.planners.presets): the presets are the papers'
values, --set keys change the field they name and nothing else, bad names and values are refused with the
valid ones listed."""

from __future__ import annotations

import dataclasses
import json

import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.planners.alip_mpc import AlipMpcParams
from lipmpcc.planners.alip_qp import AlipQpParams
from lipmpcc.planners.mpcc import MpccParams
from lipmpcc.planners.presets import (
    FAMILIES,
    PLANNER_FAMILY,
    PRESETS,
    SETTABLE,
    PlannerSettings,
    check_preset,
    check_settings,
    get_preset,
    params_dict,
    preset_names,
    presets_help,
)

CLASSES = {"mpcc": MpccParams(), "alip-mpc": AlipMpcParams.paper(), "alip-qp": AlipQpParams.paper()}


def test_mpcc_presets_are_paper_a_classmethods():
    assert PRESETS["circle"].fields["Q_bar"] == (300.0, 3.0) and PRESETS["circle"].fields["rho"] == 10.0
    assert PRESETS["overtake"].fields["Q_bar"] == (1.0, 1000.0) and PRESETS["overtake"].fields["rho"] == 50.0
    assert PRESETS["cartesian"].fields["W_bar"] == (200.0, 200.0)
    for name, method in (("circle", MpccParams.circle), ("overtake", MpccParams.overtake_mpcc),
                         ("cartesian", MpccParams.overtake_cartesian)):
        assert PlannerSettings(name).apply(MpccParams(), "mpcc") == method()


def test_alip_presets_are_the_class_defaults():
    assert PlannerSettings("paper-b").apply(AlipMpcParams.paper(), "alip-mpc") == AlipMpcParams()
    assert PlannerSettings("paper-b-qp").apply(AlipQpParams.paper(), "alip-qp") == AlipQpParams()


def test_families_and_names():
    assert PLANNER_FAMILY["cartesian"] == "mpcc" and set(FAMILIES) == set(SETTABLE)
    assert preset_names("mpcc") == ["circle", "overtake", "cartesian"]
    assert preset_names("alip-mpc") == ["paper-b"]
    assert set(preset_names()) == set(PRESETS)


def test_no_settings_returns_the_same_object():
    prm = MpccParams.circle()
    assert PlannerSettings().apply(prm, "mpcc") is prm
    assert not PlannerSettings().given and PlannerSettings(values={"rho": 1.0}).given


@pytest.mark.parametrize("family", list(SETTABLE))
def test_every_key_sets_its_field_and_only_it(family):
    base = CLASSES[family]
    planner = FAMILIES[family][0]
    for key, s in SETTABLE[family].items():
        value = int(s.lo) + 2 if s.integer else s.lo + 0.37 * (min(s.hi, s.lo + 1.0) - s.lo)  # not a default
        if key in ("T_nom", "T_min", "T_max"):
            value = {"T_nom": 0.45, "T_min": 0.3, "T_max": 0.7}[key]
        if key == "delta_min":
            value = 0.1
        if key == "y_min":
            value = 0.05
        out = PlannerSettings(values={key: value}).apply(base, planner)
        head, _, sub = s.field.partition(".")
        got = getattr(getattr(out, head), sub) if sub else getattr(out, head)
        if s.index is not None:
            assert all(got[i] == pytest.approx(value) for i in s.index), key
            others = [i for i in range(len(got)) if i not in s.index]
            assert all(got[i] == getattr(base, head)[i] for i in others), key
        else:
            assert got == pytest.approx(value), key
        changed = [f.name for f in dataclasses.fields(out) if getattr(out, f.name) != getattr(base, f.name)]
        assert changed == [head], (key, changed)


def test_values_apply_together_after_the_preset():
    out = PlannerSettings("overtake", {"q_c": 50, "delta_min": 0.5, "delta_max": 0.8}).apply(MpccParams.circle(), "mpcc")
    assert out.Q_bar == (50.0, 1000.0) and out.W_bar == (1.0, 1000.0) and out.rho == 50.0
    assert (out.delta_min, out.delta_max) == (0.5, 0.8)  # in one step: 0.5 > the default delta_max 0.4 alone
    assert isinstance(PlannerSettings(values={"N": 7.0}).apply(MpccParams(), "mpcc").N, int)


def test_unknown_key_lists_the_planners_keys():
    with pytest.raises(InvalidInputError) as e:
        check_settings({"q_x": 1.0}, "mpcc")
    assert "q_x" in str(e.value) and all(k in str(e.value) for k in SETTABLE["mpcc"])
    with pytest.raises(InvalidInputError, match="alpha_z_x"):
        check_settings({"q_c": 1.0}, "alip-mpc")


@pytest.mark.parametrize("key,value", [("rho", float("nan")), ("rho", float("inf")), ("rho", -1.0), ("gamma", 1.0),
                                       ("gamma", 0.0), ("N", 2.5), ("N", 0), ("v_max", 0.0), ("q_c", "x"),
                                       ("q_c", True)])
def test_bad_values_name_the_key(key, value):
    with pytest.raises(InvalidInputError, match=f"--set {key}"):
        check_settings({key: value}, "mpcc")


def test_values_the_class_refuses_together():
    with pytest.raises(InvalidInputError, match="delta_max"):
        PlannerSettings(values={"delta_min": 0.5}).apply(MpccParams(), "mpcc")
    with pytest.raises(InvalidInputError, match="T_min"):
        PlannerSettings(values={"T_min": 0.6}).apply(AlipMpcParams.paper(), "alip-mpc")
    with pytest.raises(InvalidInputError, match="y_min"):
        PlannerSettings(values={"y_min": 0.6}).apply(AlipMpcParams.paper(), "alip-mpc")


def test_preset_names_and_families_checked():
    with pytest.raises(InvalidInputError) as e:
        get_preset("bogus")
    assert "bogus" in str(e.value) and all(n in str(e.value) for n in PRESETS)
    with pytest.raises(InvalidInputError, match="paper-b"):
        check_preset("circle", "alip-mpc")
    assert check_preset("cartesian", "mpcc").family == "mpcc"
    with pytest.raises(InvalidInputError, match="--planner"):
        check_preset("circle", "capture-point")


def test_params_dict_is_json_and_complete():
    d = params_dict(MpccParams.circle())
    json.dumps(d)
    assert d["Q_bar"] == [300.0, 3.0] and d["model"]["T"] == 0.4 and d["rectangle"]["forward"] == [-0.35, 0.35]
    assert set(d) == {f.name for f in dataclasses.fields(MpccParams)}
    a = params_dict(AlipMpcParams.paper())
    assert a["limits"]["x_max"] == 0.6 and a["horizon"] == 4


def test_help_lists_presets_and_keys():
    text = presets_help()
    for name, p in PRESETS.items():
        assert name in text and p.source in text
    for keys in SETTABLE.values():
        assert all(k in text for k in keys)
    assert "Q_bar=(300, 3)" in text
