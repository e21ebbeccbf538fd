"""lipmpcc.control.wbc_types: the whole-body controller's gains, parameters (and per-robot overrides),
reference and output records, without the compiled controller."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from lipmpcc.control.wbc_types import PostureGains, TaskGains, WbcParams, WbcReference
from lipmpcc.exceptions import ParameterError
from lipmpcc.robots import load_robot


def test_task_gains_take_a_scalar_or_three_non_negative_numbers() -> None:
    g = TaskGains(weight=2, kp=(1.0, 2.0, 3.0), kd=0.5)
    assert g.weight == (2.0, 2.0, 2.0) and g.kp == (1.0, 2.0, 3.0) and g.kd == (0.5, 0.5, 0.5)
    assert all(type(v) is float for v in g.kp)
    for bad in ((1.0, 2.0), -1.0, float("nan"), (1.0, 2.0, -3.0)):
        with pytest.raises(ParameterError, match="kp"):
            TaskGains(kp=bad)
    with pytest.raises(ParameterError, match="arm_posture.kd"):
        PostureGains(kd=-1.0)


def test_params_are_validated_field_by_field() -> None:
    p = WbcParams()
    assert p.com.kp == (100.0, 100.0, 100.0) and p.cop_safety_factor == 0.9 and p.qp_max_iter == 50
    for field, value in (
        ("qdd_regularization", 0.0),  # strictly positive
        ("cop_safety_factor", 1.5),  # at most 1
        ("min_normal_force", -1.0),
        ("qp_max_iter", 0),
        ("qp_eps_abs", True),  # a flag is no number
        ("com", (1.0, 1.0, 1.0)),  # a TaskGains, not its gains
        ("arm_posture", 1.0),
    ):
        with pytest.raises(ParameterError, match=field):
            dataclasses.replace(p, **{field: value})
    assert dataclasses.replace(p, min_normal_force=0.0, angular_momentum_weight=0.0).angular_momentum_weight == 0.0


def test_robot_overrides_build_nested_gains() -> None:
    desc = load_robot("digit_like", wbc_overrides=(("cop_safety_factor", 0.5), ("torso", {"kp": 50.0}),
                                                   ("arm_posture", {"weight": 2.0})))
    p = WbcParams.for_robot(desc)
    assert p.cop_safety_factor == 0.5 and p.torso == TaskGains(kp=50.0) and p.arm_posture == PostureGains(weight=2.0)
    assert p.com == WbcParams().com  # the rest are the defaults


def test_a_fresh_reference_holds_both_feet_with_unbounded_forces() -> None:
    a, b = WbcReference(), WbcReference()
    assert a.contact == (True, True) and all(math.isinf(f) for f in a.max_normal_force)
    np.testing.assert_array_equal(a.foot_rot, np.stack([np.eye(3)] * 2))
    a.com_pos[2] = 1.0  # mutable per tick, and not shared between references
    assert b.com_pos[2] == 0.0


def test_unknown_controller_override_is_rejected() -> None:
    desc = load_robot("digit_like", wbc_overrides=(("cop_safty_factor", 0.5),))
    with pytest.raises(ParameterError, match="cop_safty_factor"):
        WbcParams.for_robot(desc)
    assert WbcParams.for_robot(load_robot("digit_like")) == WbcParams()


# ---- issue 14: a reference field of the wrong type is named when it is set ---------------------
def test_reference_contact_must_be_two_flags() -> None:
    import numpy as np
    import pytest

    from lipmpcc.control.wbc_types import WbcReference
    from lipmpcc.exceptions import InvalidInputError

    ref = WbcReference()
    with pytest.raises(InvalidInputError, match=r"WbcReference.contact = True: expected two flags \(left, right\)"):
        ref.contact = True
    with pytest.raises(InvalidInputError, match=r"WbcReference.contact = 'lr'"):
        WbcReference(contact="lr")
    with pytest.raises(InvalidInputError, match=r"WbcReference.contact = \(True, 2\)"):
        ref.contact = (True, 2)
    with pytest.raises(InvalidInputError, match=r"WbcReference.com_position = .*one of the fields contact, com_pos"):
        ref.com_position = np.zeros(3)  # a typo is not a silent new attribute
    ref.contact = (True, np.bool_(False))
    ref.contact = [1, 0]
    assert ref.contact == [1, 0]


def test_params_numbers_are_checked_by_the_shared_helpers() -> None:
    import numpy as np
    import pytest

    from lipmpcc.control.wbc_types import PostureGains, WbcParams
    from lipmpcc.exceptions import ParameterError

    with pytest.raises(ParameterError, match=r"cop_safety_factor = 1.5: expected a finite number > 0 and <= 1"):
        WbcParams(cop_safety_factor=1.5)
    with pytest.raises(ParameterError, match=r"qp_max_iter = 2.0: expected an integer >= 1"):
        WbcParams(qp_max_iter=2.0)
    with pytest.raises(ParameterError, match=r"arm_posture.kp = 'x'"):
        PostureGains(kp="x")
    assert WbcParams(qp_max_iter=np.int64(20), min_normal_force=np.float32(1.0)).qp_max_iter == 20


def test_task_gains_of_the_wrong_type_are_named() -> None:
    import pytest

    from lipmpcc.control.wbc_types import TaskGains
    from lipmpcc.exceptions import ParameterError

    with pytest.raises(ParameterError, match=r"kp = 'stiff'"):
        TaskGains(kp="stiff")
    with pytest.raises(ParameterError, match=r"weight = \[1.0, -1.0, 1.0\]"):
        TaskGains(weight=[1.0, -1.0, 1.0])



def test_torsion_cone_from_a_layout_adds_eight_rows_per_stance_foot():
    """``[wbc_overrides] torsion_cone = true`` reaches the C++ QP: 8 more inequality rows per stance foot (the
    yaw rows of the sole's contact wrench cone); off by default; anything but a bool is refused by name."""
    import pinocchio as pin

    from lipmpcc.control.reference_qp import ReferenceWbcQp
    from lipmpcc.control.wbc import WholeBodyController

    rows = {}
    for on in (False, True):
        desc = load_robot("digit_like", wbc_overrides=(("torsion_cone", on),))
        params = WbcParams.for_robot(desc)
        assert params.torsion_cone is on
        wbc = WholeBodyController(desc, params)
        q = pin.neutral(ReferenceWbcQp(wbc.model.spec, params).model)
        q[2] = 1.0
        v = np.zeros(wbc.nv)
        out = wbc.solve(q, v, wbc.hold_reference(q, (True, True)))
        assert out.status == "solved"
        rows[on] = np.asarray(wbc.last_qp()["C"]).shape[0]
    assert rows[True] - rows[False] == 16
    assert WbcParams().torsion_cone is False
    with pytest.raises(ParameterError, match="torsion_cone"):
        WbcParams(torsion_cone="yes")  # type: ignore[arg-type]
