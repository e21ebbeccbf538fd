"""lipmpcc.robots.autolayout: the layout ``lipmpcc robot init`` guesses from an MJCF alone, on the
Menagerie G1 and T1 (skipped when ../shared is absent) and on the packaged digit_like."""

from __future__ import annotations

import math
import tomllib

import mujoco
import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError
from lipmpcc.robots import load_robot
from lipmpcc.robots.autolayout import guess_layout, layout_toml, write_layout
from lipmpcc.robots.loading import digit_like_paths

from ..conftest import SHARED_HUMANOIDS


def _standing(desc):
    m = desc.scene_model
    d = mujoco.MjData(m)
    d.qpos[:] = desc.standing_qpos
    mujoco.mj_forward(m, d)
    return m, d


@pytest.mark.parametrize("name", ["g1", "t1"])
def test_menagerie_humanoids_get_feet_groups_and_a_crouch(name, tmp_path):
    path = SHARED_HUMANOIDS[name]
    if not path.exists():
        pytest.skip(f"reference model not found at {path}")
    out, guess = write_layout(path, tmp_path / f"{name}.lipmpcc.toml")
    text = out.read_text()
    assert text.startswith("#") and "[sure]" in text and tomllib.loads(text)["name"] == name
    with pytest.raises(InvalidInputError, match="--out"):
        write_layout(path, out)  # not overwritten
    desc = load_robot(path, layout=out)
    assert len(desc.leg_joints) == 12 and desc.actuator_notes
    # every actuated joint but the legs gets a posture task
    assert set(desc.posture_joints) | set(desc.leg_joints) == set(desc.motor_joints)
    assert len(desc.waist_joints) >= 1
    m, d = _standing(desc)
    feet = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in (desc.left_foot_body, desc.right_foot_body)]
    for f in feet:  # flat, on the ground
        assert d.xmat[f].reshape(3, 3)[2, 2] > 1 - 1e-6
    lowest = min(float(d.geom_xpos[g][2] - m.geom_rbound[g]) for g in range(m.ngeom) if m.geom_bodyid[g] in feet)
    assert lowest < 0.01
    # knees bent: every leg joint inside its range, the leg shorter than straight
    for j in desc.leg_joints:
        jid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j)
        lo, hi = m.jnt_range[jid]
        assert lo - 1e-9 <= d.qpos[m.jnt_qposadr[jid]] <= hi + 1e-9
    assert "0.9 x the straight leg" in guess.summary()
    knees = [max(abs(d.qpos[m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j)]]) for j in leg)
             for leg in (desc.leg_joints[:6], desc.leg_joints[6:])]
    assert all(0.6 < k < 1.4 for k in knees)
    assert 0.2 < desc.fall_height < 0.6 and 0.2 <= desc.step_duration < 0.4
    # paper B's centre-of-pressure box: inside the sole, in Digit v3's fractions of it
    cx, cy = desc.alip_cop_range
    assert 0 < cx < 0.25 * desc.foot_length and 0 < cy < 0.25 * desc.foot_width
    assert desc.alip_touchdown_timing == desc.touchdown_timing == "loop"


def test_digit_like_guess_matches_its_layout():
    """On the packaged biped the guess finds the layout's feet, torso and leg joints."""
    mjcf, _ = digit_like_paths()
    guess = guess_layout(mjcf)
    shipped = load_robot("digit_like")
    lay = guess.layout
    assert (lay["left_foot_body"], lay["right_foot_body"], lay["torso_body"]) == (
        shipped.left_foot_body, shipped.right_foot_body, shipped.torso_body)
    assert set(lay["leg_joints"]) == set(shipped.leg_joints) and set(lay["arm_joints"]) == set(shipped.arm_joints)
    assert math.isclose(lay["foot_length"], shipped.foot_length, abs_tol=0.03)
    assert tomllib.loads(layout_toml(guess))["leg_joints"] == lay["leg_joints"]
    assert np.all(np.isfinite(lay["standing_qpos"]))


def test_crouch_sets_the_standing_knee_bend_and_bad_ratios_are_refused(tmp_path):
    """``robot init --crouch RATIO``: the standing pose's hip-to-sole height as a fraction of the straight
    leg's (no source edit needed); a deeper crouch stands lower (torso, LIP height, fall height) and the
    note says which ratio was used; a ratio outside CROUCH_RANGE is one InvalidInputError naming --crouch."""
    mjcf, _ = digit_like_paths()
    default, deep = guess_layout(mjcf), guess_layout(mjcf, crouch=0.8)
    assert "0.8 x the straight leg" in deep.summary() and "0.9 x the straight leg" in default.summary()
    assert deep.sizes["torso_height"] < default.sizes["torso_height"] - 0.03
    assert deep.layout["lip_height"] < default.layout["lip_height"]
    assert deep.layout["fall_height"] < default.layout["fall_height"]
    path, guess = write_layout(mjcf, tmp_path / "deep.lipmpcc.toml", crouch=0.8)
    assert tomllib.loads(path.read_text())["standing_qpos"] == guess.layout["standing_qpos"]
    for bad in (0.3, 1.2, float("nan"), True):
        with pytest.raises(InvalidInputError, match="--crouch"):
            guess_layout(mjcf, crouch=bad)


def test_an_existing_layout_beside_the_model_is_named_as_such(tmp_path):
    """`robot init MODEL.xml` without --out, a layout already beside the model: the error names that file and
    both ways on (--force, --out), not an --out the student never passed."""
    mjcf, _ = digit_like_paths()
    model = tmp_path / "bot.xml"
    model.symlink_to(mjcf)
    (tmp_path / "bot.lipmpcc.toml").write_text("# mine\n")
    with pytest.raises(InvalidInputError) as err:
        write_layout(model)
    text = str(err.value)
    assert "bot.lipmpcc.toml" in text and "--force" in text and "--out FILE" in text and "--out =" not in text
    assert (tmp_path / "bot.lipmpcc.toml").read_text() == "# mine\n"


def test_every_key_robot_init_writes_is_explained_in_the_guide():
    """docs/add_a_robot.md's table "Every key `robot init` writes" has a row for each key the guess writes
    (and the [wbc_overrides] it adds), so a student never meets an unexplained key."""
    from pathlib import Path

    mjcf, _ = digit_like_paths()
    text = (Path(__file__).resolve().parents[2] / "docs" / "add_a_robot.md").read_text()
    table = text.split("### Every key `robot init` writes", 1)[1].split("\n## ", 1)[0]
    rows = [line.split("|")[1] for line in table.splitlines() if line.startswith("| `")]
    written = tomllib.loads(layout_toml(guess_layout(mjcf)))
    top = [f"`{k}`" for k in written if k != "wbc_overrides"]
    wbc = [f"`[wbc_overrides] {k}`" for k in written["wbc_overrides"]]
    missing = [k for k in top + wbc if not any(k in r for r in rows)]
    # session 41: the upper body's momentum keys moved from paper B's [alip_wbc_overrides] to every run's table
    assert len(wbc) == 5 and "alip_wbc_overrides" not in written and not missing, missing
