"""Fuzz cases of the files lipmpcc reads: path CSV, obstacle JSON, stone CSV (through the CLI, in-process),
robot layouts (TOML) and robot MJCF models (through ``load_robot`` and ``--robot PATH.xml``)."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from .cases_cli import cli
from .harness import REPO, Case

BINARY = bytes(range(256)) * 8  # NULs, control bytes, invalid UTF-8
UTF16 = "x,y\n0,0\n1,0\n2,0\n".encode("utf-16")


# ---- path CSV (--path) ----------------------------------------------------------------------------
def path_case(cid: str, text: Any, names: tuple, **kw: Any) -> Case:
    return cli(f"path-{cid}", "run circle --robot lip --steps 2 --path {tmp}/p.csv", names, category="path-csv",
               files={"p.csv": text}, **kw)


PATH_CSV = [
    path_case("empty", "", ("p.csv",)),
    path_case("header-only", "x,y\n", ("p.csv",)),
    path_case("one-waypoint", "x,y\n0,0\n", ("p.csv", "two")),
    path_case("header-without-xy", "a,b\n0,0\n1,0\n", ("p.csv", "x")),
    path_case("word-in-row", "x,y\n0,0\n1,oops\n2,0\n", ("line 3", "oops")),
    path_case("nan-row", "x,y\n0,0\nnan,1\n2,0\n", ("line 3", "nan")),
    path_case("inf-row", "x,y\n0,0\n1,inf\n2,0\n", ("line 3", "inf")),
    path_case("three-columns-no-header", "0,0,0\n1,0,0\n2,0,0\n", ("line 1",)),
    path_case("same-waypoint-4x", "x,y\n1,1\n1,1\n1,1\n1,1\n", ("p.csv", ("same", "duplicate", "distinct"))),
    path_case("two-waypoints-2e-9", "x,y\n0,0\n2e-9,0\n", ("p.csv", ("2e-09", "2e-9", "length", "apart")),
              question="the issue asks for a refusal of 2 waypoints 2e-9 m apart (a degenerate path)"),
    path_case("binary", BINARY, ("p.csv", ("binary", "text", "utf", "decode"))),
    path_case("utf16", UTF16, ("p.csv",), question="a UTF-16 CSV: refused naming the file (decoding it is also fine)"),
    path_case("huge-coordinates", "x,y\n0,0\n1e300,0\n2e300,1e300\n", (("1e+300", "1e300"),),
              question="coordinates of 1e300 m are absurd: expected refused naming the value"),
    path_case("semicolons", "x;y\n0;0\n1;0\n2;0\n", ("p.csv",)),
    path_case("zigzag-backtrack", "x,y\n0,0\n1,0\n0,0\n1,0\n", ("p.csv",),
              question="a path that doubles back on itself: expected refused (its tangent flips); judgment call"),
]


# ---- obstacle JSON (--obstacles) ------------------------------------------------------------------
def obs_case(cid: str, obj: Any, names: tuple, **kw: Any) -> Case:
    text = obj if isinstance(obj, (str, bytes)) else json.dumps(obj)
    return cli(f"obstacles-{cid}", "run overtake --robot lip --steps 2 --obstacles {tmp}/o.json", names,
               category="obstacles-json", files={"o.json": text}, **kw)


C = {"shape": "circle", "radius": 0.2, "position": [5.0, 0.5]}
OBSTACLES_JSON = [
    obs_case("invalid-json", "[{'shape': 'circle'}]", ("o.json", "line 1")),
    obs_case("trailing-comma", '[{"shape": "circle", "radius": 0.2, "position": [5, 0]},]', ("line",)),
    obs_case("not-a-list", {"shape": "circle", "radius": 0.2}, ("list",)),
    obs_case("item-number", [5], ("obstacles[0]",)),
    obs_case("missing-shape", [{"radius": 0.2, "position": [5, 0]}], ("obstacles[0].shape",)),
    obs_case("shape-square", [{**C, "shape": "square"}], ("square",)),
    obs_case("radius-negative", [{**C, "radius": -0.2}], ("-0.2",)),
    obs_case("radius-word", [{**C, "radius": "big"}], ("big",)),
    obs_case("radius-bool", [{**C, "radius": True}], ("radius", "true"),
             question="JSON true as a radius: float(True) = 1 is taken today; expected refused"),
    obs_case("radius-1e6", [{**C, "radius": 1e6}], ("1000000",),
             question="the issue: a 1e6 m obstacle 'accepted without a word'; expected refused as absurd"),
    obs_case("axes-one", [{"shape": "ellipse", "axes": [1.0], "position": [5, 0]}], ("axes",)),
    obs_case("axes-negative", [{"shape": "ellipse", "axes": [0.4, -1.0], "position": [5, 0]}], ("-1.0",)),
    obs_case("position-one", [{**C, "position": [1.0]}], ("position",)),
    obs_case("position-nan", '[{"shape": "circle", "radius": 0.2, "position": [NaN, 0]}]', ("nan",)),
    obs_case("velocity-word", [{**C, "velocity": "fast"}], ("fast",)),
    obs_case("speed-1e308", [{"shape": "circle", "radius": 0.2, "s0": 5.0, "speed": 1e308}],
             (("1e+308", "1e308"), "speed"), question="the issue's vague message: must name the speed"),
    obs_case("s0-beyond-path", [{"shape": "circle", "radius": 0.2, "s0": 1e6, "speed": 0.1}], ("1000000",)),
    obs_case("orientation-word", [{"shape": "ellipse", "axes": [0.4, 0.2], "position": [5, 0], "orientation": "x"}],
             ("orientation",)),
    obs_case("no-motion", [{"shape": "circle", "radius": 0.2}], ("obstacles[0]",)),
    obs_case("binary", BINARY, ("o.json",)),
    obs_case("nested-list", [[C]], ("obstacles[0]",)),
    obs_case("position-huge", [{**C, "position": [1e300, 0]}], (("1e+300", "1e300"),),
             question="an obstacle at 1e300 m: expected refused as absurd (dropping it as irrelevant is also fine)",
             ),
]


# ---- stone CSV (--stones) -------------------------------------------------------------------------
def stones_case(cid: str, text: Any, names: tuple, **kw: Any) -> Case:
    return cli(f"stones-{cid}", "run stones --stones {tmp}/s.csv", names, category="stones-csv",
               files={"s.csv": text}, **kw)


STONES_CSV = [
    stones_case("empty", "", ("s.csv",)),
    stones_case("header-only", "x,y,size_x,size_y\n", ("s.csv",)),
    stones_case("three-numbers", "1.4,-0.14,0.2\n", ("line 1",)),
    stones_case("word", "1.4,abc\n", ("abc",)),
    stones_case("nan", "1.4,nan\n", ("nan",)),
    stones_case("size-zero", "1.4,-0.14,0,0.1\n", ("line 1",)),
    stones_case("size-negative", "1.4,-0.14,0.2,-0.1\n", ("-0.1",)),
    stones_case("unreachable-first", "10,-0.14\n", ("10",)),
    stones_case("same-spot-twice", "1.40,-0.14\n1.70,0.16\n1.70,0.16\n", (("line 3", "stone 3", "stones[2]", "1.7"),),
                question="the issue: two stones on the same spot accepted without a word"),
    stones_case("binary", BINARY, ("s.csv",)),
    stones_case("huge-size", "1.4,-0.14,1e9,1e9\n", (("1e+09", "1e9", "1000000000"),),
                question="a stone of 1e9 m: expected refused as absurd"),
    stones_case("wrong-side", "1.40,0.14\n", ("1.4",),
                question="the first stone is for the right foot; on the left it is unreachable (0.0 m across)"),
]


# ---- robot layouts (TOML) through load_robot(xml, layout=...) -----------------------------------------
DIGIT_XML = REPO / "data" / "models" / "digit_like" / "digit_like.xml"
DIGIT_TOML = (REPO / "data" / "layouts" / "digit_like.toml").read_text()


def _set_key(text: str, key: str, value: str) -> str:
    """The layout with ``key = value`` (a TOML value) in place of its line, or appended."""
    pat = re.compile(rf"^{re.escape(key)}\s*=.*?(?=^\w|\Z|^\[)", re.S | re.M)
    line = f"{key} = {value}\n"
    if pat.search(text):
        return pat.sub(line, text, count=1)
    head, sep, tail = text.partition("[wbc_overrides]")
    return head + line + sep + tail


def _drop_key(text: str, key: str) -> str:
    pat = re.compile(rf"^{re.escape(key)}\s*=.*?(?=^\w|\Z|^\[)", re.S | re.M)
    return pat.sub("", text, count=1)


def _load(layout: str = "layout.toml"):
    def call(tmp: Path):
        from lipmpcc.robots import load_robot

        return load_robot(DIGIT_XML, layout=tmp / layout)
    return call


def _wbc_params(layout: str = "layout.toml"):
    """Load, then build the controller's parameters: ``[wbc_overrides]`` are fields of
    lipmpcc.control.WbcParams, which the robots layer below it cannot read; they are checked when a
    controller is made from the description, before any run."""
    def call(tmp: Path):
        from lipmpcc.control.wbc_types import WbcParams
        from lipmpcc.robots import load_robot

        return WbcParams.for_robot(load_robot(DIGIT_XML, layout=tmp / layout))
    return call


def layout_case(cid: str, text: Any, names: tuple, expect: str = "error", **kw: Any) -> Case:
    name = kw.pop("filename", "layout.toml")
    func = kw.pop("func", None) or _load(name)
    return Case(f"layout-{cid}", "layout", "api", expect, files={name: text}, func=func, names=names, **kw)


LAYOUTS = [
    layout_case("leg-joints-int", _set_key(DIGIT_TOML, "leg_joints", "5"), ("leg_joints", "5")),
    layout_case("sole-offset-1", _set_key(DIGIT_TOML, "sole_offset", "[1.0]"), ("sole_offset",)),
    layout_case("leg-joint-missing", _set_key(DIGIT_TOML, "leg_joints", '["left_hip_roll", "no_such_joint"]'),
                ("no_such_joint",)),
    layout_case("arm-joints-str", _set_key(DIGIT_TOML, "arm_joints", '"left_elbow"'), ("arm_joints",)),
    layout_case("name-int", _set_key(DIGIT_TOML, "name", "5"), ("name",)),
    layout_case("foot-length-negative", _set_key(DIGIT_TOML, "foot_length", "-1.0"), ("foot_length",)),
    layout_case("foot-width-nan", _set_key(DIGIT_TOML, "foot_width", "nan"), ("foot_width",)),
    layout_case("foot-length-str", _set_key(DIGIT_TOML, "foot_length", '"long"'), ("foot_length",)),
    layout_case("step-duration-5", _set_key(DIGIT_TOML, "step_duration", "5.0"), ("step_duration",)),
    layout_case("min-lateral-nan", _set_key(DIGIT_TOML, "min_lateral_step", "nan"), ("min_lateral_step",)),
    layout_case("keyframe-missing", _set_key(DIGIT_TOML, "standing_keyframe", '"nope"'), ("nope",)),
    layout_case("standing-qpos-short", _set_key(DIGIT_TOML, "standing_qpos", "[1.0, 2.0]"), ("standing_qpos",)),
    layout_case("cop-range-huge", _set_key(DIGIT_TOML, "alip_cop_range", "[1.0, 1.0]"), ("alip_cop_range",)),
    layout_case("com-gains-negative", _set_key(DIGIT_TOML, "alip_com_gains", "[-1.0, 8.0]"), ("alip_com_gains",)),
    layout_case("wbc-override-unknown", DIGIT_TOML + "\n[wbc_overrides]\nno_such_field = 1\n", ("no_such_field",),
                func=_wbc_params()),
    layout_case("wbc-override-bad-value", DIGIT_TOML + "\n[wbc_overrides]\ncop_safety_factor = -3\n",
                ("cop_safety_factor",), func=_wbc_params()),
    layout_case("unknown-key", DIGIT_TOML + "\nleft_foot = 1\n", ("left_foot",)),
    layout_case("missing-torso", _drop_key(DIGIT_TOML, "torso_body"), ("torso_body",)),
    layout_case("torso-missing-body", _set_key(DIGIT_TOML, "torso_body", '"no_torso"'), ("no_torso",)),
    layout_case("toml-syntax", "name = \n[[[", ("layout.toml",)),
    layout_case("binary", BINARY, ("layout.toml",)),
    layout_case("json-list", "[1, 2]", ("layout.json",), filename="layout.json"),
    layout_case("base-joint-int", _set_key(DIGIT_TOML, "base_joint", "3"), ("base_joint",)),
    layout_case("sole-site-missing", _set_key(DIGIT_TOML, "left_sole_site", '"no_site"'), ("no_site",)),
    layout_case("valid-copy", DIGIT_TOML, (), "ok"),
]


# ---- robot MJCF models: --robot PATH.xml (CLI) and load_robot ------------------------------------------
DIGIT_MJCF = DIGIT_XML.read_text()


def mjcf_case(cid: str, xml: Any, names: tuple, sidecar: bool = True, **kw: Any) -> Case:
    files: dict[str, Any] = {"r.xml": xml}
    if sidecar:
        files["r.lipmpcc.toml"] = DIGIT_TOML
    return cli(f"mjcf-{cid}", "run stand --robot {tmp}/r.xml --duration 0.2", names, category="mjcf",
               files=files, timeout=60, **kw)


def _motor_joint(xml: str, motor: str, joint: str) -> str:
    return xml.replace(f'<motor name="{motor}" joint="{motor}"', f'<motor name="{motor}" joint="{joint}"', 1)


MJCF = [
    mjcf_case("empty", "", ("r.xml",)),
    mjcf_case("not-xml", "this is not xml\n", ("r.xml",)),
    mjcf_case("binary", BINARY, ("r.xml",)),
    mjcf_case("html", "<html><body>hi</body></html>", ("r.xml",)),
    mjcf_case("truncated", DIGIT_MJCF[: len(DIGIT_MJCF) // 2], ("r.xml",)),
    mjcf_case("no-layout-unknown-bodies", "<mujoco><worldbody><body name='b'><freejoint/><geom size='0.1'/>"
              "</body></worldbody></mujoco>", ("r.xml",), sidecar=False),
    mjcf_case("motor-on-missing-joint", _motor_joint(DIGIT_MJCF, "left_hip_roll", "no_such_joint"),
              ("no_such_joint",)),
    mjcf_case("joint-renamed", DIGIT_MJCF.replace('joint name="left_knee"', 'joint name="left_knee_x"').replace(
        'joint="left_knee"', 'joint="left_knee_x"'), ("left_knee",),
        question="a joint of the layout missing from the model: the issue lists it as a vague message"),
    mjcf_case("weld-equality", DIGIT_MJCF.replace("</mujoco>", "<equality><weld body1='torso'/></equality></mujoco>"),
              ("weld",)),
]

CASES: list[Case] = PATH_CSV + OBSTACLES_JSON + STONES_CSV + LAYOUTS + MJCF
