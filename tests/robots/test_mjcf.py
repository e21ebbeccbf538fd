"""lipmpcc.robots.mjcf: compiling an MJCF (errors on one line), the scene's floor, names, equality checks
and the loop-closure residuals, on small hand-written models."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import ModelFileError, RobotDescriptionError
from lipmpcc.robots import load_robot
from lipmpcc.robots.mjcf import (
    check_equalities,
    compile_mjcf,
    compile_scene,
    connect_residuals,
    connect_residuals_at,
    has_ground,
    loop_closure_errors,
    names,
    torque_drive,
)

#: two hinged links whose tips a <connect> ties to a fixed point (closed at q = 0), and a free box
LOOP = """
<mujoco>
  <worldbody>
    {floor}
    <body name="a" pos="0 0 1">
      <joint name="ha" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.02"/>
      <body name="b" pos="0.5 0 0">
        <joint name="hb" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.5 0 0" size="0.02"/>
      </body>
    </body>
    <body name="anchor" pos="1 0 1"><geom type="sphere" size="0.03"/></body>
  </worldbody>
  <equality>
    <connect name="tie" body1="b" body2="anchor" anchor="0.5 0 0" {extra}/>
  </equality>
</mujoco>
"""


def _write(tmp_path: Path, floor: str = "", extra: str = "", kind: str = "connect") -> Path:
    path = tmp_path / "loop.xml"
    text = LOOP.format(floor=floor, extra=extra)
    if kind != "connect":
        text = text.replace('<connect name="tie" body1="b" body2="anchor" anchor="0.5 0 0"', f'<{kind} name="tie" body1="b" body2="anchor"')
    path.write_text(text)
    return path


def test_compile_mjcf_and_names(tmp_path: Path) -> None:
    model = compile_mjcf(_write(tmp_path))
    assert isinstance(model, mujoco.MjModel) and model.nq == 2
    assert names(model, mujoco.mjtObj.mjOBJ_JOINT, model.njnt) == ["ha", "hb"]
    assert names(model, mujoco.mjtObj.mjOBJ_BODY, model.nbody) == ["world", "a", "b", "anchor"]
    assert names(model, mujoco.mjtObj.mjOBJ_GEOM, model.ngeom) == [""] * model.ngeom  # unnamed
    with pytest.raises(ModelFileError, match="not a regular file"):
        compile_mjcf(tmp_path)


def test_compile_scene_adds_a_floor_only_when_there_is_none(tmp_path: Path) -> None:
    bare = compile_scene(_write(tmp_path))
    assert has_ground(bare) and mujoco.mj_name2id(bare, mujoco.mjtObj.mjOBJ_GEOM, "lipmpcc_floor") >= 0
    floored = compile_scene(_write(tmp_path, floor='<geom name="ground" type="plane" size="5 5 0.1"/>'))
    assert has_ground(floored) and mujoco.mj_name2id(floored, mujoco.mjtObj.mjOBJ_GEOM, "lipmpcc_floor") < 0
    assert not has_ground(compile_mjcf(_write(tmp_path)))

    def raise_box(spec: mujoco.MjSpec) -> None:
        spec.worldbody.add_geom(name="box", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.1, 0.1, 0.1], pos=[0, 0, 2])

    edited = compile_scene(_write(tmp_path), scene_editor=raise_box)
    assert edited.geom("box").pos[2] == pytest.approx(2.0)
    with pytest.raises(ModelFileError, match="file not found"):
        compile_scene(tmp_path / "missing.xml")


def test_loop_closure_residuals_are_the_anchors_distance(tmp_path: Path) -> None:
    model = compile_mjcf(_write(tmp_path))
    closed = connect_residuals_at(model, np.zeros(2))
    np.testing.assert_allclose(closed, 0.0, atol=1e-12)
    # bend the tip link by 90 degrees: its tip moves from (1, 0, 1) to (0.5, 0, 0.5)
    res = connect_residuals_at(model, np.array([0.0, np.pi / 2]))
    np.testing.assert_allclose(res[0], [-0.5, 0.0, -0.5], atol=1e-12)
    data = mujoco.MjData(model)
    data.qpos[:] = [0.0, np.pi / 2]
    mujoco.mj_kinematics(model, data)
    np.testing.assert_array_equal(connect_residuals(model, data), res)
    assert loop_closure_errors(model, data)[0] == pytest.approx(np.sqrt(0.5))
    check_equalities(model, "loop.xml")  # an active body <connect>: accepted


def test_equalities_other_than_active_connects_are_named(tmp_path: Path) -> None:
    weld = compile_mjcf(_write(tmp_path, kind="weld"))
    with pytest.raises(RobotDescriptionError, match="weld"):
        check_equalities(weld, "weld.xml")
    assert np.isnan(loop_closure_errors(weld, mujoco.MjData(weld))[0])  # not a connect: NaN
    off = compile_mjcf(_write(tmp_path, extra='active="false"'))
    with pytest.raises(RobotDescriptionError, match="inactive"):
        check_equalities(off, "off.xml")


def test_missing_file_raises_model_file_error_naming_the_path(tmp_path: Path) -> None:
    missing = tmp_path / "nowhere" / "robot.xml"
    with pytest.raises(ModelFileError) as err:
        load_robot(missing)
    assert str(missing) in str(err.value) and "not found" in str(err.value)
    assert isinstance(err.value, FileNotFoundError)


def test_malformed_xml_raises_model_file_error_with_mujocos_reason_on_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "broken.xml"
    bad.write_text("<mujoco><worldbody><body name='a'></worldbody></mujoco>")
    with pytest.raises(ModelFileError) as err:
        load_robot(bad)
    msg = str(err.value)
    assert str(bad) in msg and "\n" not in msg
    assert "XML" in msg or "Error" in msg  # MuJoCo's own reason is kept


def test_a_binary_model_file_is_named(tmp_path: Path) -> None:
    from lipmpcc.robots.mjcf import compile_mjcf

    f = tmp_path / "robot.xml"
    f.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    with pytest.raises(ModelFileError, match=r"robot.xml: not an MJCF file: expected XML text, the file is binary"):
        compile_mjcf(f)
    with pytest.raises(ModelFileError, match="the file is binary"):
        load_robot(f)


SERVOS = """
<mujoco>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint name="j1" type="hinge" axis="0 1 0" actuatorfrcrange="-30 30"/>
      <joint name="j2" type="hinge" axis="1 0 0"/>
      <joint name="j3" type="hinge" axis="0 0 1"/>
      <geom type="sphere" size="0.1"/>
    </body>
  </worldbody>
  <actuator>
    <position name="p1" joint="j1" kp="50" kv="2" ctrlrange="-1 1"/>
    <general name="g2" joint="j2" gainprm="20" biastype="affine" biasprm="0 -20 -1" forcerange="-5 5" gear="2"/>
    <motor name="m3" joint="j3" gear="3" ctrlrange="-4 4"/>
  </actuator>
</mujoco>
"""


def test_torque_drive_turns_servos_into_torque_sources(tmp_path):
    path = tmp_path / "servos.xml"
    path.write_text(SERVOS)
    m = compile_mjcf(path)
    before = m.actuator_ctrlrange[2].copy(), m.actuator_gainprm[2].copy()
    notes = torque_drive(m)
    assert len(notes) == 2 and any("actuatorfrcrange" in n for n in notes) and any("forcerange" in n for n in notes)
    for a in (0, 1):  # gain 1, no bias: ctrl is the actuator force
        assert m.actuator_gainprm[a, 0] == 1.0 and not m.actuator_biasprm[a].any()
        assert int(m.actuator_biastype[a]) == int(mujoco.mjtBias.mjBIAS_NONE)
    assert tuple(m.actuator_ctrlrange[0]) == (-30.0, 30.0)  # the joint's actuatorfrcrange (gear 1)
    assert tuple(m.actuator_ctrlrange[1]) == (-5.0, 5.0)  # the actuator's forcerange
    assert np.array_equal(m.actuator_ctrlrange[2], before[0]) and np.array_equal(m.actuator_gainprm[2], before[1])
    assert torque_drive(m) == ()  # idempotent
    d = mujoco.MjData(m)
    d.ctrl[:] = [10.0, 3.0, 1.0]
    mujoco.mj_forward(m, d)
    assert np.allclose(d.qfrc_actuator, [10.0, 6.0, 3.0])  # gear x ctrl, no position feedback
    assert compile_scene(path).nlight == 1  # a light for the videos


def test_compile_scene_keeps_a_models_light(tmp_path):
    path = tmp_path / "lit.xml"
    path.write_text(SERVOS.replace("<worldbody>", '<worldbody><light pos="0 0 3"/>'))
    assert compile_scene(path).nlight == 1
