"""lipmpcc.robots.layouts: bring your own robot. The robot's layout (feet, sole sites, torso, arms,
standing pose, controller overrides) is a small description: shipped for digit_like and the Digit v3
layout, readable from a TOML/JSON file, found next to the model as ``<model>.lipmpcc.toml``; on the
reference Digit v3 (../shared; skipped when absent), its shipped standing pose. (The controller on
Digit v3: tests/control/test_wbc_digit_v3.py.)
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ModelFileError, RobotDescriptionError
from lipmpcc.robots import LAYOUT_KEYS, load_robot, loop_closure_errors, read_layout_file
from lipmpcc.robots.layouts import DIGIT_V3_STANDING_QPOS

MINI = Path(__file__).resolve().parents[1] / "control" / "data" / "mini_biped.xml"


# ------------------------------------------------------------------------------------------------
# Layout files (no shared model needed)
# ------------------------------------------------------------------------------------------------
POGO_LAYOUT = """
name = "pogo"
left_foot_body = "l_foot"
right_foot_body = "r_foot"
left_sole_site = "l_sole"
right_sole_site = "r_sole"
foot_length = 0.2
foot_width = 0.1
torso_body = "pelvis"
base_joint = "root"
leg_joints = ["left_hip_yaw", "left_knee", "right_hip_yaw", "right_knee"]
arm_joints = ["left_shoulder_pitch", "right_shoulder_pitch"]
standing_keyframe = "stand"

[wbc_overrides]
cop_safety_factor = 0.7
"""


def _pogo(tmp_path: Path) -> Path:
    """The test biped with names no shipped layout knows."""
    text = MINI.read_text()
    for old, new in (('"left_foot"', '"l_foot"'), ('"right_foot"', '"r_foot"'), ('"left_sole"', '"l_sole"'),
                     ('"right_sole"', '"r_sole"'), ('"torso"', '"pelvis"'), ('name="base"', 'name="root"')):
        text = text.replace(old, new)
    path = tmp_path / "pogo.xml"
    path.write_text(text)
    return path


def test_an_unknown_model_names_what_it_lacks(tmp_path: Path) -> None:
    with pytest.raises(RobotDescriptionError, match=r"no layout found .*pogo\.lipmpcc\.toml.*lipmpcc robot init"):
        load_robot(_pogo(tmp_path))
    with pytest.raises(RobotDescriptionError) as err:  # parts named: checked against the model
        load_robot(_pogo(tmp_path), left_foot_body="l_foot", right_foot_body="r_foot", torso_body="chest")
    missing = " ".join(err.value.missing)
    assert "chest" in missing


def test_a_misspelt_key_names_the_nearest_one(tmp_path: Path) -> None:
    layout = tmp_path / "typo.toml"
    layout.write_text("foot_lenght = 0.2\n" + POGO_LAYOUT)
    with pytest.raises(RobotDescriptionError, match="unknown key 'foot_lenght' .did you mean 'foot_length'") as err:
        read_layout_file(layout)
    assert "missing no" not in str(err.value)


def test_a_layout_file_describes_a_users_robot(tmp_path: Path) -> None:
    from lipmpcc.control.wbc import WholeBodyController

    model = _pogo(tmp_path)
    layout = tmp_path / "pogo_layout.toml"
    layout.write_text(POGO_LAYOUT)
    desc = load_robot(model, layout=layout)
    assert desc.name == "pogo" and desc.torso_body == "pelvis" and desc.left_sole_site == "l_sole"
    assert desc.layout_file == layout and dict(desc.wbc_overrides) == {"cop_safety_factor": 0.7}
    assert desc.standing_reset == "stand"
    wbc = WholeBodyController(desc)
    assert wbc.params.cop_safety_factor == pytest.approx(0.7)  # the layout's controller override
    assert wbc.model.base_kind == "free joint" and wbc.n_loops == 0
    # the same file next to the model is found on its own (so `--robot pogo.xml` works)
    (tmp_path / "pogo.lipmpcc.toml").write_text(POGO_LAYOUT)
    assert load_robot(model).name == "pogo"
    # JSON works too
    import json
    import tomllib

    js = tmp_path / "pogo.json"
    js.write_text(json.dumps(tomllib.loads(POGO_LAYOUT)))
    assert load_robot(model, layout=js).torso_body == "pelvis"
    assert desc.min_lateral_step == pytest.approx(0.10)  # the default
    (tmp_path / "wide.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "min_lateral_step = 0.18\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "wide.toml").min_lateral_step == pytest.approx(0.18)
    assert desc.step_duration == pytest.approx(0.4)  # the default
    (tmp_path / "quick.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "step_duration = 0.35\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "quick.toml").step_duration == pytest.approx(0.35)
    assert desc.alip_com_gains is None  # the default: the controller's own COM gains
    (tmp_path / "soft.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "alip_com_gains = [20, 9]\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "soft.toml").alip_com_gains == (20.0, 9.0)
    assert desc.alip_cop_range is None  # the default: paper B's point foot
    (tmp_path / "foot.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "alip_cop_range = [0.05, 0.02]\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "foot.toml").alip_cop_range == (0.05, 0.02)
    assert desc.alip_dcm_settle_time == 0.0  # the default: the bias is learned at the touch-down
    (tmp_path / "settle.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "alip_dcm_settle_time = 0.08\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "settle.toml").alip_dcm_settle_time == pytest.approx(0.08)
    assert desc.touchdown_timing is None  # the default: the loop decides by the planner
    (tmp_path / "clock.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", 'touchdown_timing = "loop"\n[wbc_overrides]'))
    clocked = load_robot(model, layout=tmp_path / "clock.toml")
    assert clocked.touchdown_timing == "loop"
    assert clocked.alip_touchdown_timing == "loop"  # paper B's runs follow it when no alip_touchdown_timing is stated
    from lipmpcc.loops.fullbody import FullBodyLoop, LoopParams

    assert LoopParams().touchdown_timing == "auto"  # the robot's layout, else by the planner
    assert FullBodyLoop(clocked).params.touchdown_timing == "loop"
    assert FullBodyLoop(clocked, params=LoopParams(touchdown_timing="planner")).params.touchdown_timing == "planner"
    assert FullBodyLoop(desc).params.touchdown_timing == "auto"
    # landing_depth: read for paper A's MPCC runs (tests/studies/test_robot_check.py); 0 without it
    assert desc.landing_depth == 0.0
    (tmp_path / "deep.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "landing_depth = 0.02\n[wbc_overrides]"))
    deep = load_robot(model, layout=tmp_path / "deep.toml")
    assert deep.landing_depth == pytest.approx(0.02)
    assert FullBodyLoop(deep).params.landing_depth == 0.0  # the walk's and the stand's loop: at the ground
    assert desc.steady_heading is False  # paper A's near-free heading
    (tmp_path / "steady.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "steady_heading = true\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "steady.toml").steady_heading is True
    (tmp_path / "wobbly.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "steady_heading = 1\n[wbc_overrides]"))
    with pytest.raises(RobotDescriptionError, match="steady_heading"):
        load_robot(model, layout=tmp_path / "wobbly.toml")
    (tmp_path / "abyss.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "landing_depth = 0.3\n[wbc_overrides]"))
    with pytest.raises(RobotDescriptionError, match="landing_depth"):
        load_robot(model, layout=tmp_path / "abyss.toml")
    assert desc.alip_touchdown_timing == "planner" and desc.alip_com_resync is False  # the defaults
    (tmp_path / "timing.toml").write_text(
        POGO_LAYOUT.replace("[wbc_overrides]", "alip_touchdown_timing = 'loop'\nalip_com_resync = true\n[wbc_overrides]"))
    timed = load_robot(model, layout=tmp_path / "timing.toml")
    assert timed.alip_touchdown_timing == "loop" and timed.alip_com_resync is True
    assert desc.alip_step_reference == "plan" and desc.alip_stone_bounds == "relative"  # paper B's
    (tmp_path / "ref.toml").write_text(
        POGO_LAYOUT.replace("[wbc_overrides]", "alip_step_reference = 'stones'\nalip_stone_bounds = 'world'\n[wbc_overrides]"))
    ref = load_robot(model, layout=tmp_path / "ref.toml")
    assert ref.alip_step_reference == "stones" and ref.alip_stone_bounds == "world"
    assert desc.alip_max_speed == 0.0  # paper B's T_nom for every step
    (tmp_path / "speed.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "alip_max_speed = 0.9\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "speed.toml").alip_max_speed == 0.9
    assert desc.alip_cop_safety_factor is None  # the controller's own in paper B's runs
    (tmp_path / "csf.toml").write_text(POGO_LAYOUT.replace("[wbc_overrides]", "alip_cop_safety_factor = 0.8\n[wbc_overrides]"))
    assert load_robot(model, layout=tmp_path / "csf.toml").alip_cop_safety_factor == 0.8


def test_bad_layout_files_are_named(tmp_path: Path) -> None:
    model = _pogo(tmp_path)
    with pytest.raises(ModelFileError, match="not found"):
        load_robot(model, layout=tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("left_foot_body = 'l_foot'\nright_foot_body = 'r_foot'\nhead = 'x'\n")
    with pytest.raises(RobotDescriptionError) as err:
        read_layout_file(bad)
    assert "head" in str(err.value) and "torso_body" in str(err.value)
    broken = tmp_path / "broken.toml"
    broken.write_text("left_foot_body = \n")
    with pytest.raises(ModelFileError, match="layout"):
        read_layout_file(broken)
    with pytest.raises(InvalidInputError, match="layout"):
        load_robot(model, layout="cassie")
    bad_keys = (  # one bad key per file, and the problem its error must name
        ("min_lateral_step = 0.5", r"min_lateral_step in \[0, 0.4\) m \(got 0.5\)"),
        ("step_duration = 2.0", r"step_duration in \[0.2, 1.0\] s \(got 2.0\)"),
        ("alip_com_gains = [16]", r"alip_com_gains as two positive numbers"),
        ("alip_cop_range = [0.3, -0.01]", r"alip_cop_range as two numbers in \[0, 0.2\) m"),
        ("alip_dcm_settle_time = 0.5", r"alip_dcm_settle_time in \[0, 0.3\] s \(got 0.5\)"),
        ('touchdown_timing = "late"', r"touchdown_timing 'planner' or 'loop' \(got 'late'\)"),
        ("alip_touchdown_timing = 'contact'", r"alip_touchdown_timing 'planner' or 'loop' \(got 'contact'\)"),
        ("alip_com_resync = 1", r"alip_com_resync as true or false \(got 1\)"),
        ("alip_step_reference = 'previous'", r"alip_step_reference 'plan' or 'stones' \(got 'previous'\)"),
        ("alip_stone_bounds = 'box'", r"alip_stone_bounds 'relative' or 'world' \(got 'box'\)"),
        ("alip_max_speed = -1", r"alip_max_speed in \[0, 5\] m/s \(got -1\)"),
        ("alip_cop_safety_factor = 0", r"alip_cop_safety_factor in \(0, 1\] \(got 0\)"),
    )
    for i, (line, message) in enumerate(bad_keys):
        bad_key = tmp_path / f"bad_key_{i}.toml"
        bad_key.write_text(POGO_LAYOUT.replace("[wbc_overrides]", f"{line}\n[wbc_overrides]"))
        with pytest.raises(RobotDescriptionError, match=message):
            load_robot(model, layout=bad_key)
    assert "wbc_overrides" in LAYOUT_KEYS and "step_duration" in LAYOUT_KEYS and "alip_com_gains" in LAYOUT_KEYS
    assert "alip_cop_range" in LAYOUT_KEYS and "alip_dcm_settle_time" in LAYOUT_KEYS


# ------------------------------------------------------------------------------------------------
# The reference Digit v3
# ------------------------------------------------------------------------------------------------
def test_digit_v3_layout_and_standing_pose(shared_digit_xml: Path) -> None:
    desc = load_robot(shared_digit_xml)
    assert desc.name == "digit_v3" and desc.standing_reset == "stand"
    model = mujoco.MjModel.from_xml_path(str(shared_digit_xml))
    data = mujoco.MjData(model)
    data.qpos[:] = DIGIT_V3_STANDING_QPOS
    mujoco.mj_forward(model, data)
    # the loops are closed, the springs carry the weight, the COM is over the foot boxes
    assert np.max(loop_closure_errors(model, data)) < 1e-8
    shin = model.joint("left-leg/shin")
    assert -model.jnt_stiffness[shin.id] * data.qpos[shin.qposadr[0]] > 50.0  # [N m]
    boxes = [data.geom_xpos[model.geom(f"{s}-foot").id] for s in ("left", "right")]
    com = data.subtree_com[model.body("torso/base").id]
    assert np.linalg.norm(com[:2] - 0.5 * (boxes[0][:2] + boxes[1][:2])) < 0.01


# ------------------------------------------------------------------------------------------------
# issue 14: keys of the wrong type, binary files, missing joints
# ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "line, message",
    [
        ("leg_joints = 5", r"expected leg_joints as a list of joint names \(got 5\)"),
        ("sole_offset = [1.0]", r"expected sole_offset as three numbers \[x, y, z\] in metres \(got \[1.0\]\)"),
        ("arm_joints = ['a', 3]", r"arm_joints as a list of joint names"),
        ("foot_length = 'long'", r"foot_length as a number in \(0, 1\] m \(got 'long'\)"),
        ("foot_width = -0.1", r"foot_width as a number in \(0, 1\] m"),
        ("base_joint = 3", r"base_joint as a joint name"),
        ("standing_qpos = [0.0, 'a']", r"standing_qpos as a list of finite numbers"),
        ("wbc_overrides = 3", r"wbc_overrides as a table of WbcParams fields \(got 3\)"),
    ],
)
def test_layout_keys_of_the_wrong_type_are_named(tmp_path: Path, line: str, message: str) -> None:
    from lipmpcc.exceptions import LayoutError

    key = line.split(" =")[0]
    text = "\n".join(ln for ln in POGO_LAYOUT.splitlines() if not ln.startswith(key + " "))
    if key == "wbc_overrides":
        text = text.split("[wbc_overrides]")[0]
    f = tmp_path / "bad_type.toml"
    f.write_text(line + "\n" + text)
    with pytest.raises(LayoutError, match=r"robot layout .*bad_type.toml: .*" + message):
        read_layout_file(f)
    with pytest.raises(RobotDescriptionError, match=message):  # a LayoutError is a RobotDescriptionError
        load_robot(_pogo(tmp_path), layout=f)


def test_overrides_of_the_wrong_type_are_named(tmp_path: Path) -> None:
    from lipmpcc.exceptions import LayoutError

    layout = tmp_path / "pogo_layout.toml"
    layout.write_text(POGO_LAYOUT)
    with pytest.raises(LayoutError, match=r"leg_joints as a list of joint names \(got 5\)"):
        load_robot(_pogo(tmp_path), layout=layout, leg_joints=5)
    desc = load_robot(_pogo(tmp_path), layout=layout)
    with pytest.raises(LayoutError, match=r"torso_body as a body name"):
        load_robot(desc, torso_body=["pelvis"])
    with pytest.raises(InvalidInputError, match=r"overrides = \['head'\]"):
        load_robot(desc, head="x")


def test_a_binary_layout_file_is_named(tmp_path: Path) -> None:
    f = tmp_path / "image.toml"
    f.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    with pytest.raises(ModelFileError, match=r"image.toml: not a valid layout file: the file is binary"):
        read_layout_file(f)


def test_a_missing_joint_is_named_with_its_key(tmp_path: Path) -> None:
    layout = tmp_path / "pogo_layout.toml"
    layout.write_text(POGO_LAYOUT.replace('"left_knee"', '"left_knee_x"'))
    with pytest.raises(RobotDescriptionError, match=r"missing joint 'left_knee_x' \(leg_joints\)"):
        load_robot(_pogo(tmp_path), layout=layout)


def test_a_layout_that_is_not_a_path_is_named() -> None:
    with pytest.raises(InvalidInputError, match=r"layout = 5: expected the path of a .toml/.json layout file"):
        read_layout_file(5)


def test_a_layout_naming_the_same_body_or_site_for_both_feet_is_refused(tmp_path) -> None:
    from lipmpcc.exceptions import LayoutError
    from lipmpcc.robots.layouts import distinct_feet_problems, read_layout_file

    f = tmp_path / "same.toml"
    f.write_text('left_foot_body = "foot"\nright_foot_body = "foot"\ntorso_body = "torso"\n')
    with pytest.raises(LayoutError, match=r"left_foot_body and right_foot_body as two different bodies \(both are 'foot'\)"):
        read_layout_file(f)
    assert distinct_feet_problems({"left_sole_site": "s", "right_sole_site": "s"}) == [
        "left_sole_site and right_sole_site as two different sites (both are 's')"]
    assert distinct_feet_problems({"left_foot_body": "l", "right_foot_body": "r", "left_sole_site": None,
                                   "right_sole_site": None}) == []


def test_use_layout_names_a_layout_kept_away_from_the_model(tmp_path: Path) -> None:
    """A model in a read-only folder: its layout written elsewhere and named for the process (`--layout`), in a
    scene that includes it too; forgotten again with None; a missing or non-layout file is refused."""
    from lipmpcc.robots.layouts import use_layout

    folder, elsewhere = tmp_path / "model", tmp_path / "mine"
    folder.mkdir()
    elsewhere.mkdir()
    model = _pogo(folder)
    layout = elsewhere / "pogo.toml"
    layout.write_text(POGO_LAYOUT)
    with pytest.raises(RobotDescriptionError, match="no layout found"):
        load_robot(model)
    use_layout(model, layout)
    try:
        desc = load_robot(model)
        assert desc.layout_file == layout and desc.torso_body == "pelvis"
        assert load_robot(str(model)).layout_file == layout  # the CLI's str path, the same file
    finally:
        use_layout(model, None)
    with pytest.raises(RobotDescriptionError, match="no layout found"):
        load_robot(model)
    for bad in (elsewhere / "absent.toml", model):
        with pytest.raises(InvalidInputError, match="--layout"):
            use_layout(model, bad)
