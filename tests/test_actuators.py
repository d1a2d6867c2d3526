"""MuJoCo's actuators: the report's ctrl layout, its findings, ``--to mujoco-ctrl`` and the
diff, held to MuJoCo itself on the models the test extras install.

MuJoCo is the oracle: ``actuator_trnid`` (what each actuator drives), ``actuator_gear``,
``actuator_ctrlrange``, and ``mj_step``: a stiff position actuator given the ctrl cspace
converts from a configuration holds its joint at that configuration's value (gravity
and contacts off).
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
from lxml import etree

import cspace
from cspace.errors import JointMatchError

from conftest import REPO, run_cli

HERE = REPO / "tests" / "actuators"
SERVO = HERE / "servo_arm.xml"
CTRLRANGE = HERE / "ctrlrange.xml"


def _package(name: str) -> Path:
    spec = importlib.util.find_spec(name)
    assert spec is not None and spec.submodule_search_locations, name
    return Path(next(iter(spec.submodule_search_locations)))


KITCHEN = (
    _package("gymnasium_robotics")
    / "envs/assets/kitchen_franka/kitchen_assets/kitchen_env_model.xml"
)
"""Franka's arm and gripper, nine position actuators, in a kitchen of joints none drives."""

REAL = [
    KITCHEN,
    _package("gymnasium_robotics") / "envs/assets/hand/manipulate_block.xml",
    _package("gymnasium_robotics") / "envs/assets/fetch/pick_and_place.xml",
    _package("dm_control") / "suite/fish.xml",
    _package("gymnasium") / "envs/mujoco/assets/ant.xml",
    _package("robosuite") / "models/assets/robots/spot/robot.xml",
]
"""Position actuators on joints and on a tendon (fish), motors (ant, spot)."""

_OBJECTS = {
    "joint": mujoco.mjtObj.mjOBJ_JOINT,
    "jointinparent": mujoco.mjtObj.mjOBJ_JOINT,
    "tendon": mujoco.mjtObj.mjOBJ_TENDON,
    "body": mujoco.mjtObj.mjOBJ_BODY,
    "site": mujoco.mjtObj.mjOBJ_SITE,
    "slidercrank": mujoco.mjtObj.mjOBJ_SITE,
}


@pytest.mark.parametrize("path", REAL, ids=[p.name for p in REAL])
def test_the_ctrl_layout_is_mujocos(path: Path) -> None:
    """Each actuator in ctrl order: its name, what it drives (actuator_trnid), its gear
    and ctrlrange are the compiled model's; a position actuator is one by its gain and
    bias (kp > 0, bias (0, -kp, -kv))."""
    model = mujoco.MjModel.from_xml_path(str(path))
    report = cspace.inspect(path)
    assert len(report.actuators) == model.nu > 0
    for a, actuator in enumerate(report.actuators):
        assert actuator.name == (mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a) or None)
        trnid = int(model.actuator_trnid[a][0])
        target = mujoco.mj_id2name(model, _OBJECTS[actuator.transmission], trnid)
        assert actuator.target == target, (actuator, target)
        assert actuator.gear == float(model.actuator_gear[a][0])
        limited = bool(model.actuator_ctrllimited[a])
        assert actuator.ctrlrange == (tuple(model.actuator_ctrlrange[a]) if limited else None)
        kp, bias = model.actuator_gainprm[a][0], model.actuator_biasprm[a][:3]
        servo = model.actuator_biastype[a] == mujoco.mjtBias.mjBIAS_AFFINE and bias[1] == -kp
        assert (actuator.kind == "position") == bool(servo and kp > 0 and bias[0] == 0)


@pytest.mark.parametrize("name", ["fish.xml", "ant.xml"])
def test_each_kind_is_the_element_the_file_writes(name: str) -> None:
    """Where the file writes its actuators itself, each kind is its element's tag."""
    path = next(p for p in REAL if p.name == name)
    tags = [e.tag for e in etree.parse(str(path)).getroot().iterfind("actuator/*")]
    assert [a.kind for a in cspace.inspect(path).actuators] == tags


def test_inspect_shows_the_layout_and_its_findings_at_their_lines() -> None:
    run = run_cli("inspect", str(CTRLRANGE), "--format", "json")
    document = json.loads(run.stdout)
    assert [a["line"] for a in document["actuators"]] == [18, 19, 20]
    found = {(d["code"], d["joint"], d["line"]) for d in document["diagnostics"]}
    assert found == {
        ("actuator-ctrlrange-exceeds", "hip", 18),
        ("actuator-joint-unlimited", "knee", 19),
    }  # the ankle's ctrlrange, pi/4 written rounded, is within its range
    exceeds = next(d for d in document["diagnostics"] if d["line"] == 18)["message"]
    assert "[-3.2, 3.2]" in exceeds and "(line 5)" in exceeds and "gear 2" in exceeds
    assert "[-3.1415927, 3.1415927] in ctrl units" in exceeds
    text = run_cli("inspect", str(SERVO)).stdout
    assert "actuators (MuJoCo's ctrl, 6 entries)" in text
    assert "1     shoulder_servo  position  joint shoulder  2     [-3, 3]" in text
    assert "actuator-order (line 25)" in text
    markdown = run_cli("inspect", str(SERVO), "--format", "markdown").stdout
    assert "| 4 | `spin_speed` | velocity | `joint spin` | 1 | - |" in markdown


def test_a_report_without_actuators_has_no_actuators_part() -> None:
    document = json.loads(
        run_cli("inspect", "robots/mjcf_every_joint.xml", "--format", "json").stdout
    )
    assert "actuators" not in document


def test_a_saved_report_reads_back_the_same(tmp_path: Path) -> None:
    saved = tmp_path / "servo.json"
    saved.write_text(run_cli("inspect", str(SERVO), "--format", "json").stdout)
    back = cspace.Report.from_dict(json.loads(saved.read_text()))
    assert back.actuators == cspace.inspect(SERVO).actuators
    run = run_cli("diff", str(saved), str(SERVO))
    assert run.code == 0, run.stdout


def test_convert_to_ctrl_and_back_on_the_command_line(tmp_path: Path) -> None:
    """ctrl = gear * qpos for each position actuator, 0 for the velocity servo and the
    motor; back, every joint (each one driven) as it was."""
    rows = [[0.5, -1.0, 0.1, 2.0], [-0.7, 1.9, 0.0, -3.0]]
    (tmp_path / "x.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    run = run_cli(
        "convert", str(SERVO), "x.jsonl", "--from", "canonical", "--to", "mujoco-ctrl", cwd=tmp_path
    )
    assert run.code == 0, run.stderr
    ctrl = [json.loads(line) for line in run.stdout.splitlines()]
    assert ctrl == [[-1.0, 1.0, 0.1, 2.0, 0.0, 0.0], [1.9, -1.4, 0.0, -3.0, 0.0, 0.0]]
    (tmp_path / "u.jsonl").write_text(run.stdout)
    back = run_cli(
        "convert", str(SERVO), "u.jsonl", "--from", "mujoco-ctrl", "--to", "canonical", cwd=tmp_path
    )
    np.testing.assert_allclose([json.loads(line) for line in back.stdout.splitlines()], rows)


def test_joints_no_position_actuator_drives_come_back_neutral() -> None:
    space = cspace.load(KITCHEN)
    conventions = space.conventions()
    unbounded = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower)}
    x = space.sample(3, np.random.default_rng(5), bounds=unbounded)
    back = conventions.from_mujoco_ctrl(conventions.to_mujoco_ctrl(x))
    driven = {a.target for a in space.mujoco.actuators}
    neutral = np.array([c.neutral for c in space.coordinates])
    for k, coordinate in enumerate(space.coordinates):
        expected = x[:, k] if coordinate.joint in driven else np.full(3, neutral[k])
        np.testing.assert_allclose(back[:, k], expected, atol=1e-12, err_msg=coordinate.name)
    assert conventions.names("mujoco-ctrl")[:2] == ("panda0_joint1", "panda0_joint2")


def test_a_position_actuator_on_a_tendon_is_refused_in_one_line(tmp_path: Path) -> None:
    fish = next(p for p in REAL if p.name == "fish.xml")
    (tmp_path / "x.jsonl").write_text(json.dumps([0.0] * 11) + "\n")
    run = run_cli(
        "convert", str(fish), "x.jsonl", "--from", "mujoco", "--to", "mujoco-ctrl", cwd=tmp_path
    )
    assert run.code == 2 and run.stdout == "" and run.stderr.count("\n") == 1, run.stderr
    assert "position actuator 'fins_flap' drives tendon 'fins_flap'" in run.stderr, run.stderr
    with pytest.raises(JointMatchError, match="tendon"):
        cspace.load(fish).conventions().to_mujoco_ctrl(np.zeros(11))


def test_a_robot_without_actuators_has_no_ctrl() -> None:
    with pytest.raises(JointMatchError, match="no MuJoCo actuators"):
        cspace.load(REPO / "robots" / "mjcf_every_joint.xml").conventions().names("mujoco-ctrl")


def _held(model: mujoco.MjModel, ctrl: np.ndarray, steps: int) -> np.ndarray:
    """qpos after ``steps`` steps of ``ctrl``, from qpos0, gravity and contacts off."""
    model.opt.gravity[:] = 0
    model.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    data = mujoco.MjData(model)
    data.ctrl[:] = ctrl
    mujoco.mj_step(model, data, nstep=steps)
    return np.array(data.qpos)


@pytest.mark.parametrize(
    ("path", "steps"), [(SERVO, 4000), (KITCHEN, 3000)], ids=["servo", "franka"]
)
def test_mj_step_brings_each_position_actuator_to_the_converted_target(
    path: Path, steps: int
) -> None:
    """A configuration within the actuators' ctrlranges, converted to ctrl by cspace, is
    where MuJoCo's position actuators bring their joints (to 1e-6)."""
    space = cspace.load(path)
    conventions = space.conventions(mujoco=mujoco.MjModel.from_xml_path(str(path)))
    rng = np.random.default_rng(11)
    ranges = {
        a.target: sorted(x / a.gear for x in a.ctrlrange)
        for a in space.mujoco.actuators
        if a.kind == "position" and a.ctrlrange is not None
    }
    bounds = {}
    for c in space.coordinates:  # within the joint's limits and its actuator's ctrlrange
        low, high = ranges.get(c.joint, (-2.0, 2.0))
        low, high = max(low, c.lower, -2.0), min(high, c.upper, 2.0)
        if c.factor in ("R^1", "S^1"):
            bounds[c.name] = (0.8 * low + 0.2 * high, 0.2 * low + 0.8 * high)
    x = space.sample(1, rng, bounds=bounds)[0]
    ctrl = conventions.to_mujoco_ctrl(x)
    qpos = _held(mujoco.MjModel.from_xml_path(str(path)), ctrl, steps)
    want = conventions.to_mujoco(x)
    model = mujoco.MjModel.from_xml_path(str(path))
    for a in range(model.nu):
        if space.mujoco.actuators[a].kind != "position":
            continue
        adr = int(model.jnt_qposadr[model.actuator_trnid[a][0]])
        assert qpos[adr] == pytest.approx(want[adr], abs=1e-6), space.mujoco.actuators[a].name
        assert ctrl[a] == pytest.approx(model.actuator_gear[a][0] * want[adr])


def test_a_mujoco_model_given_in_python_brings_its_actuators() -> None:
    space = cspace.load(SERVO)
    given = space.conventions(mujoco=mujoco.MjModel.from_xml_path(str(SERVO)))
    own = space.conventions()
    x = np.array([0.3, -0.2, 0.05, 1.0])
    np.testing.assert_array_equal(given.to_mujoco_ctrl(x), own.to_mujoco_ctrl(x))
    assert given.names("mujoco-ctrl") == own.names("mujoco-ctrl")


def test_diff_compares_the_actuators_order_target_gear_and_ctrlrange(tmp_path: Path) -> None:
    text = SERVO.read_text()
    (tmp_path / "old.xml").write_text(text)
    lines = text.splitlines(keepends=True)
    first = next(i for i, line in enumerate(lines) if "elbow_servo" in line)
    moved = [*lines[:first], *lines[first + 1 : first + 3], lines[first], *lines[first + 3 :]]
    (tmp_path / "moved.xml").write_text("".join(moved))
    (tmp_path / "geared.xml").write_text(
        text.replace('gear="2" ctrlrange="-3 3"', 'gear="3" ctrlrange="-3 3"')
    )
    same = run_cli("diff", "old.xml", "old.xml", cwd=tmp_path)
    assert same.code == 0, same.stdout
    run = run_cli("diff", "old.xml", "moved.xml", "--format", "json", cwd=tmp_path)
    changes = json.loads(run.stdout)["changes"]
    assert run.code == 1 and [c["kind"] for c in changes] == ["actuators"], changes
    assert changes[0]["before"].startswith("ctrl elbow_servo, shoulder_servo, extend_servo")
    assert changes[0]["after"].startswith("ctrl shoulder_servo, extend_servo, elbow_servo")
    run = run_cli("diff", "old.xml", "geared.xml", cwd=tmp_path)
    assert run.code == 1 and "MuJoCo ctrl  shoulder" in run.stdout, run.stdout
    assert "gear 2, ctrlrange [-3, 3]" in run.stdout and "gear 3, ctrlrange [-3, 3]" in run.stdout


def test_a_report_saved_before_actuators_were_listed_still_matches(tmp_path: Path) -> None:
    """A saved report (a baseline) that lists no actuators, as earlier versions wrote,
    is not a change: the diff notes that one side lists them, and passes."""
    document = json.loads(run_cli("inspect", str(SERVO), "--format", "json").stdout)
    del document["actuators"]
    saved = tmp_path / "old.json"
    saved.write_text(json.dumps(document))
    run = run_cli("diff", str(saved), str(SERVO), "--format", "json")
    assert run.code == 0, run.stdout
    notes = json.loads(run.stdout)["notes"]
    assert [(n["kind"], n["before"], n["after"]) for n in notes] == [
        ("actuators-listed", "none listed", "6 actuators")
    ]


_TWO_JOINTS = """<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="b">
      <joint name="h" type="hinge" range="-1 1"/>
      <geom size="0.1" mass="1"/>
      <body name="c" pos="0 0 1">
        <joint name="s" type="slide" range="-0.5 0.5"/>
        <geom size="0.1" mass="1"/>
      </body>
    </body>
  </worldbody>
  {actuators}
</mujoco>
"""


def test_a_robot_whose_actuators_are_all_removed_fails_the_diff(tmp_path: Path) -> None:
    """The new robot has no actuators where the old had some: each is a removal (not the
    note of a baseline saved before actuators were listed), in diff and check --baseline."""
    servos = '<actuator><position name="lift" joint="h" kp="10" ctrlrange="-1 1"/></actuator>'
    (tmp_path / "old.xml").write_text(_TWO_JOINTS.format(actuators=servos))
    (tmp_path / "new.xml").write_text(_TWO_JOINTS.format(actuators=""))
    run = run_cli("diff", "old.xml", "new.xml", "--format", "json", cwd=tmp_path)
    changes = json.loads(run.stdout)["changes"]
    assert run.code == 1 and [(c["kind"], c["after"]) for c in changes] == [("actuators", "-")]
    assert changes[0]["before"] == "lift: position on joint 'h', gear 1, ctrlrange [-1, 1]"
    (tmp_path / "robot.xml").write_text(_TWO_JOINTS.format(actuators=servos))
    saved = run_cli("inspect", "--format", "jsonl", "robot.xml", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(saved.stdout)
    (tmp_path / "robot.xml").write_text(_TWO_JOINTS.format(actuators=""))
    run = run_cli("check", "--baseline", "baseline.jsonl", "robot.xml", cwd=tmp_path)
    assert run.code == 1 and run.stdout.startswith("differs: robot.xml"), run.stdout


def test_an_actuator_named_as_an_entry_is_not_paired_with_an_unnamed_one(tmp_path: Path) -> None:
    """An actuator named ``#1`` and the unnamed one at entry 1 are two actuators: a change
    to either is seen."""
    actuators = (
        '<actuator><position name="#1" joint="h" kp="10" gear="{gear}" ctrlrange="-1 1"/>'
        '<motor joint="s"/></actuator>'
    )
    (tmp_path / "old.xml").write_text(_TWO_JOINTS.format(actuators=actuators.format(gear=-2)))
    (tmp_path / "new.xml").write_text(_TWO_JOINTS.format(actuators=actuators.format(gear=5)))
    run = run_cli("diff", "old.xml", "new.xml", "--format", "json", cwd=tmp_path)
    changes = json.loads(run.stdout)["changes"]
    assert run.code == 1 and [(c["kind"], c["joint"]) for c in changes] == [("actuators", "h")]
    assert "gear -2" in changes[0]["before"] and "gear 5" in changes[0]["after"], changes


def test_a_general_servo_behind_a_filter_is_a_position_actuator(tmp_path: Path) -> None:
    """``<general>`` with a servo's gain and bias behind ``filter`` dynamics (as
    ``<position timeconst>`` is behind ``filterexact``) holds its joint where ctrl equals
    ``gear * qpos``: a position actuator, whose ctrl mujoco-ctrl converts (MuJoCo is the
    oracle)."""
    servos = (
        '<actuator><general name="filtered" joint="s" gear="-2" dyntype="filter" dynprm="0.05"'
        ' biastype="affine" gainprm="400" biasprm="0 -400 -40"/>'
        '<position name="exact" joint="h" kp="1" kv="0.1" timeconst="0.05"/></actuator>'
    )
    path = tmp_path / "filtered.xml"
    path.write_text(_TWO_JOINTS.format(actuators=servos))
    space = cspace.load(path)
    assert [a.kind for a in space.mujoco.actuators] == ["position", "position"]
    conventions = space.conventions()
    x = np.array([0.3, -0.2])  # h, s
    ctrl = conventions.to_mujoco_ctrl(x)
    np.testing.assert_allclose(ctrl, [-2 * -0.2, 0.3])
    qpos = _held(mujoco.MjModel.from_xml_path(str(path)), ctrl, 4000)
    np.testing.assert_allclose(qpos, conventions.to_mujoco(x), atol=1e-6)


def test_convert_warns_of_the_ctrl_mujoco_clamps(tmp_path: Path) -> None:
    """A target within the joint's range but beyond a narrower ctrlrange: the ctrl is
    written (gear * qpos), MuJoCo clamps it and the joint stops at the range's end; one
    warning per actuator says so, at the first vector's line, with how many."""
    narrow = (REPO / "docs" / "examples" / "servo.xml").read_text()
    narrow = narrow.replace('ctrlrange="-2.5 2.5"', 'ctrlrange="-1 1"')
    (tmp_path / "arm.xml").write_text(narrow)
    (tmp_path / "x.csv").write_text("shoulder,elbow\n0.1,0.2\n0.5,-1.5\n0.2,1.2\n")
    args = ("convert", "arm.xml", "x.csv", "--from", "canonical", "--to", "mujoco-ctrl")
    run = run_cli(*args, cwd=tmp_path)
    assert run.code == 0 and run.stdout.splitlines()[2] == "-1.5,1.0,0.0", run.stdout
    assert run.stderr.splitlines() == [
        "cspace: warning: x.csv:3: ctrl[0] of actuator 'elbow_servo' is outside its ctrlrange "
        "[-1, 1] in 2 vectors (the first here): MuJoCo clamps it, and the joint stops where "
        "the range ends"
    ]
    model = mujoco.MjModel.from_xml_string(narrow)
    data = mujoco.MjData(model)
    data.qpos[:] = [0.5, -1.5]  # the second vector: shoulder, elbow
    data.ctrl[:] = [-1.5, 1.0, 0.0]
    mujoco.mj_forward(model, data)  # at its target the elbow is still pulled: kp * 0.5
    assert data.actuator_force[:2] == pytest.approx([400 * 0.5, 0.0])
    wide = run_cli(
        "convert", str(REPO / "docs" / "examples" / "servo.xml"), *args[2:], cwd=tmp_path
    )
    assert wide.code == 0 and wide.stderr == ""  # within every ctrlrange: nothing said


def test_ctrl_clamping_disabled_leaves_no_ctrlrange(tmp_path: Path) -> None:
    """``<flag clampctrl="disable"/>``: MuJoCo applies a ctrl beyond its ctrlrange, so no
    actuator has one, convert warns of no clamp, and a baseline with them differs."""
    text = SERVO.read_text().replace(
        'joint="elbow" kp="400" kv="20" ctrlrange="-2 2"',
        ('joint="elbow" kp="400" kv="20" ctrlrange="-1 1"'),
    )
    (tmp_path / "arm.xml").write_text(text)
    (tmp_path / "x.jsonl").write_text("[0, 1.5, 0, 0]\n")  # the elbow beyond its ctrlrange
    args = ("convert", "arm.xml", "x.jsonl", "--from", "canonical", "--to", "mujoco-ctrl")
    assert "MuJoCo clamps it" in run_cli(*args, cwd=tmp_path).stderr
    baseline = run_cli("inspect", "arm.xml", "--format", "jsonl", cwd=tmp_path)
    (tmp_path / "base.jsonl").write_text(baseline.stdout)
    unclamped = text.replace("<actuator>", '<option><flag clampctrl="disable"/></option><actuator>')
    (tmp_path / "arm.xml").write_text(unclamped)
    model = mujoco.MjModel.from_xml_string(unclamped)
    data = mujoco.MjData(model)
    data.ctrl[0] = 1.5  # elbow_servo: kp 400
    mujoco.mj_forward(model, data)
    assert data.actuator_force[0] == pytest.approx(400 * 1.5)  # not clamped to 1
    report = cspace.inspect(tmp_path / "arm.xml")
    assert [a.ctrlrange for a in report.actuators] == [None] * len(report.actuators)
    run = run_cli(*args, cwd=tmp_path)
    assert run.code == 0 and json.loads(run.stdout)[0] == 1.5 and run.stderr == ""
    check = run_cli("check", "--baseline", "base.jsonl", "arm.xml", cwd=tmp_path)
    assert check.code == 1 and "MuJoCo ctrl differs" in check.stdout, check.stdout


def _thrusters(site: str) -> str:
    """A thruster on a site and a slider-crank (its crank site first), MuJoCo's two site
    transmissions."""
    return f"""<mujoco><worldbody><body name="b"><joint name="h"/><geom size=".1"/>
  <site name="left" pos="0 .1 0"/><site name="right" pos="0 -.1 0"/></body>
  <body name="c" pos="1 0 0"><joint name="s" type="slide"/><geom size=".1"/>
  <site name="slider"/></body></worldbody>
  <actuator><motor name="thrust" site="{site}" gear="0 0 1 0 0 0"/>
  <general name="crank" cranksite="right" slidersite="slider" cranklength="1"/></actuator>
</mujoco>
"""


def test_a_site_actuator_names_its_site_and_moving_it_is_a_change(tmp_path: Path) -> None:
    """The site a thruster or a slider-crank drives (actuator_trnid's first object, as
    MuJoCo compiles it) is its target, from the file and from an MjModel; a thruster moved
    to another site fails the diff."""
    (tmp_path / "left.xml").write_text(_thrusters("left"))
    (tmp_path / "right.xml").write_text(_thrusters("right"))
    model = mujoco.MjModel.from_xml_path(str(tmp_path / "left.xml"))
    names = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, int(model.actuator_trnid[a][0]))
        for a in range(model.nu)
    ]
    assert names == ["left", "right"]
    report = cspace.inspect(tmp_path / "left.xml")
    assert [(a.transmission, a.target) for a in report.actuators] == [
        ("site", "left"),
        ("slidercrank", "right"),
    ]
    given = cspace.load(tmp_path / "left.xml").conventions(mujoco=model)
    assert [a.target for a in given.mujoco.actuators] == names
    run = run_cli("diff", "left.xml", "right.xml", "--format", "json", cwd=tmp_path)
    changes = json.loads(run.stdout)["changes"]
    assert run.code == 1 and [c["kind"] for c in changes] == ["actuators"], run.stdout


def test_a_gear_number_after_the_first_that_moves_the_robot_is_a_change(tmp_path: Path) -> None:
    """A thruster's gear is a force along the site's axes (all six numbers count): turned
    from +z to -z it pushes the other way, a change; a hinge reads the first number only,
    so a second written there is none. A saved report reads back byte for byte."""
    text = _thrusters("left")
    (tmp_path / "up.xml").write_text(text)
    (tmp_path / "down.xml").write_text(text.replace('gear="0 0 1 0 0 0"', 'gear="0 0 -1 0 0 0"'))
    for name, z in (("up.xml", 1.0), ("down.xml", -1.0)):  # MuJoCo keeps all six
        model = mujoco.MjModel.from_xml_path(str(tmp_path / name))
        assert list(model.actuator_gear[0]) == [0, 0, z, 0, 0, 0]
    run = run_cli("diff", "up.xml", "down.xml", "--format", "json", cwd=tmp_path)
    changes = json.loads(run.stdout)["changes"]
    assert run.code == 1 and [c["kind"] for c in changes] == ["actuators"], run.stdout
    assert "gear [0, 0, 1, 0, 0, 0]" in changes[0]["before"], changes
    assert "gear [0, 0, -1, 0, 0, 0]" in changes[0]["after"], changes
    saved = run_cli("inspect", "up.xml", "--format", "json", cwd=tmp_path).stdout
    (tmp_path / "up.json").write_text(saved)
    assert run_cli("diff", "up.json", "up.xml", cwd=tmp_path).code == 0
    back = cspace.Report.from_dict(json.loads(saved))
    own = cspace.inspect(tmp_path / "up.xml").actuators
    assert back.actuators == own and own[0].gears == (0, 0, 1, 0, 0, 0)
    assert back.to_json() == saved.rstrip("\n")
    servo = SERVO.read_text()
    (tmp_path / "servo.xml").write_text(servo)
    (tmp_path / "servo2.xml").write_text(servo.replace('gear="2"', 'gear="2 7"', 1))
    assert 'gear="2"' in servo
    assert run_cli("diff", "servo.xml", "servo2.xml", cwd=tmp_path).code == 0


@pytest.mark.parametrize(("joint", "read"), [("ball", 3), ("free", 6), ("hinge", 1)])
def test_the_gear_numbers_listed_are_those_mujoco_reads(
    tmp_path: Path, joint: str, read: int
) -> None:
    """A gear number past those listed moves nothing in MuJoCo (qfrc_actuator); each
    listed one does."""

    def run(gear: list[float]) -> tuple[np.ndarray, cspace.Report]:
        xml = (
            f'<mujoco><worldbody><body><joint name="j" type="{joint}"/><geom size=".1"/>'
            f'</body></worldbody><actuator><motor joint="j" gear="{" ".join(map(str, gear))}"/>'
            "</actuator></mujoco>"
        )
        model = mujoco.MjModel.from_xml_string(xml)
        data = mujoco.MjData(model)
        data.ctrl[0] = 1.0
        mujoco.mj_forward(model, data)
        (tmp_path / "m.xml").write_text(xml)
        return data.qfrc_actuator.copy(), cspace.inspect(tmp_path / "m.xml")

    base, report = run([1, 0, 0, 0, 0, 0])
    assert report.actuators[0].gears == ((1.0,) + (0.0,) * (read - 1) if read > 1 else ())
    for k in range(1, 6):
        moved, _ = run([1.0 if i in (0, k) else 0.0 for i in range(6)])
        assert (not np.array_equal(moved, base)) == (k < read), k
