"""The poses an MJCF file stores (keyframes), checked as configurations of its C-space.

MuJoCo is the reader (``<key>`` as compiled, quaternions as written); each finding names
the keyframe, the joint, the value and the bounds at the keyframe's line. A pose outside
the space fails ``cspace check`` but leaves the space defined. Hostile keyframes (NaN,
1e308, thousands of them, the wrong length) are refused or bounded, in one line.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import cspace

from conftest import run_cli

ROBOT = """<mujoco model="arm">
  <compiler angle="radian"/>
  <size nkey="{blank}"/>
  <worldbody>
    <body name="base">
      <joint name="spin" type="hinge" axis="0 0 1"/>
      <geom size="0.1"/>
      <body name="upper">
        <joint name="lift" type="hinge" axis="0 1 0" range="-1 1"/>
        <geom size="0.1"/>
        <body name="hand">
          <joint name="wrist" type="ball" range="0 0.5"/>
          <geom size="0.1"/>
        </body>
      </body>
    </body>
  </worldbody>
  <keyframe>
{keys}
  </keyframe>
</mujoco>
"""


def _write(tmp_path: Path, keys: str, blank: int = 0) -> Path:
    path = tmp_path / "arm.xml"
    path.write_text(ROBOT.format(keys=keys, blank=blank))
    return path


def _poses(path: Path) -> list[tuple[str, str, int | None, str]]:
    report = cspace.inspect(path)
    return [
        (d.severity.value, d.code, d.line, d.message)
        for d in report.diagnostics
        if d.code.startswith("pose")
    ]


def test_a_keyframe_inside_the_space_says_nothing(tmp_path: Path) -> None:
    path = _write(tmp_path, '    <key name="home" qpos="4.0 0.5 0.9999 0.01 0 0"/>')
    assert _poses(path) == []  # spin turns freely: 4 rad is fine; |q| within 1e-3 of 1


def test_each_stored_pose_outside_is_named_with_its_joint_value_bounds_and_line(
    tmp_path: Path,
) -> None:
    path = _write(
        tmp_path,
        '    <key name="home" qpos="0 1.5 1 0 0 0"/>\n    <key qpos="0 0 0.7071 0.7071 0 0"/>',
    )
    assert _poses(path) == [
        ("error", "pose-out-of-limits", 19,
         "keyframe 'home': joint 'lift' is 1.5, outside [-1, 1] rad"),
        ("error", "pose-out-of-limits", None,
         "keyframe 'key1': ball joint 'wrist' is turned 1.5708 rad, more than its range 0.5 rad"),
    ]  # fmt: skip
    space = cspace.load(path)  # the C-space is still defined
    assert space.dimension == 5
    run = run_cli("check", str(path), "--dimension", "5")  # the space is as expected
    assert run.code == 1 and run.stderr == (
        f"cspace: check failed: {path}: keyframe 'home': joint 'lift' is 1.5, outside "
        "[-1, 1] rad [pose-out-of-limits]\n"
    )


def test_blank_keyframes_of_size_nkey_are_not_poses_the_file_stores(tmp_path: Path) -> None:
    """`<size nkey>` makes MuJoCo allocate keyframes at qpos0 (gymnasium's humanoid has
    five, its knees outside their range): not poses anyone wrote."""
    path = _write(tmp_path, '    <key name="home" qpos="0 0.5 1 0 0 0"/>', blank=4)
    path.write_text(path.read_text().replace('range="-1 1"', 'range="0.2 1"'))
    assert _poses(path) == []


@pytest.mark.parametrize(
    ("qpos", "said"),
    [
        ("nan 0 1 0 0 0", "joint 'spin' is nan"),
        ("0 nan 1 0 0 0", "joint 'lift' is nan, outside [-1, 1] rad"),
        ("0 1e308 1 0 0 0", "joint 'lift' is 1e+308, outside [-1, 1] rad"),
        ("0 0 nan 0 0 0", "joint 'wrist' is (nan, 0, 0, 0): not finite"),
    ],
)
def test_values_that_are_no_numbers_of_the_space(tmp_path: Path, qpos: str, said: str) -> None:
    path = _write(tmp_path, f'    <key name="k" qpos="{qpos}"/>')
    run = run_cli("inspect", str(path), "--format", "json")
    assert run.code == 1, run.stderr
    messages = [d["message"] for d in json.loads(run.stdout)["diagnostics"]]
    assert any(said in m for m in messages), messages


def test_a_keyframe_of_the_wrong_length_is_mujocos_refusal_in_one_line(tmp_path: Path) -> None:
    path = _write(tmp_path, '    <key name="short" qpos="0 0 1"/>\n    <key qpos="0 0 1 0 0 0 7"/>')
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert "arm.xml" in run.stderr


def test_thousands_of_keyframes_are_bounded(tmp_path: Path) -> None:
    """The first 5,000 keyframes are checked (MuJoCo's vectors take 50 us each to read);
    the rest are counted, in an info finding."""
    keys = "\n".join(f'    <key qpos="0 {k % 3 - 1} 1 0 0 0"/>' for k in range(12_000))
    path = _write(tmp_path, keys)
    report = cspace.inspect(path)
    codes = [d.code for d in report.diagnostics]
    assert codes.count("poses-not-checked") == 1
    assert codes.count("pose-out-of-limits") == 0  # -1, 0 and 1 are within [-1, 1]
    (note,) = [d.message for d in report.diagnostics if d.code == "poses-not-checked"]
    assert note.startswith("7,000 of 12,000 keyframes not checked")


def test_only_what_a_keyframe_writes_is_checked(tmp_path: Path) -> None:
    """A keyframe of ctrl, mocap or time only takes qpos0, which is no pose the file
    stores (here outside 'lift''s range); one that writes part of qpos is filled from
    qpos0 by MuJoCo without a word: a warning names the joints filled (as MuJoCo's own
    key_qpos shows), and the values it does not write are not checked."""
    import mujoco

    keys = (
        '    <key name="t" time="1"/>\n    <key name="partial" qpos="0 0.5"/>\n'
        '    <key qpos="0 0.5 1 0 0"/>'
    )
    path = _write(tmp_path, keys)
    path.write_text(path.read_text().replace('range="-1 1"', 'range="0.2 1" ref="0.3"'))
    model = mujoco.MjModel.from_xml_path(str(path))
    assert list(model.key_qpos[1][2:]) == list(model.qpos0[2:])  # filled from qpos0
    assert list(model.key_qpos[2][5:]) == list(model.qpos0[5:])
    line = path.read_text().splitlines().index('    <key name="partial" qpos="0 0.5"/>') + 1
    said = "of the model's 6 qpos numbers: MuJoCo fills the rest from qpos0, for"
    assert _poses(path) == [
        ("warning", "pose-partial", line, f"keyframe 'partial': writes 2 {said} 'wrist'"),
        ("warning", "pose-partial", None, f"keyframe 'key2': writes 5 {said} 'wrist'"),
    ]


@pytest.mark.parametrize("value", ["1.00001", "-1.00009"])
def test_a_keyframe_written_rounded_or_saved_from_a_run_is_within(
    tmp_path: Path, value: str
) -> None:
    """Keyframes are written rounded, or saved from a simulation whose limits are soft
    (gymnasium-robotics' franka_kitchen: 1.3e-5 past 0): 1e-4 of slack."""
    path = _write(tmp_path, f'    <key name="k" qpos="0 {value} 1 0 0 0"/>')
    assert _poses(path) == []


def test_each_keyframes_finding_is_shown_on_its_own(tmp_path: Path) -> None:
    """The text report folded findings of several keyframes
    into one line 'and 2 more joints like it'."""
    keys = "\n".join(f'    <key name="k{k}" qpos="0 {1.5 + k} 1 0 0 0"/>' for k in range(4))
    run = run_cli("inspect", str(_write(tmp_path, keys)))
    lines = [line for line in run.stdout.splitlines() if "pose-out-of-limits" in line]
    assert [line.split("keyframe ")[1].split(":")[0] for line in lines] == [
        "'k0'", "'k1'", "'k2'", "'k3'"
    ]  # fmt: skip
    assert "more joints like it" not in run.stdout


def test_an_attached_model_keeps_its_own_angle_unit(tmp_path: Path) -> None:
    """A model attached with <compiler angle="radian"/> of its
    own was said to look like radians in degrees."""
    (tmp_path / "child.xml").write_text(
        '<mujoco model="child"><compiler angle="radian"/><worldbody><body name="c">'
        '<joint name="k" type="hinge" range="-0.05 0.05"/><geom size="0.1"/></body>'
        "</worldbody></mujoco>"
    )
    parent = tmp_path / "parent.xml"
    parent.write_text(
        '<mujoco model="parent"><asset><model name="ch" file="child.xml"/></asset>'
        '<worldbody><body name="p"><attach model="ch" prefix="c_"/></body></worldbody>'
        "</mujoco>"
    )
    report = cspace.inspect(parent)
    assert [d.code for d in report.diagnostics if d.code == "range-looks-like-radians"] == []
    assert report.manifold.notation == "R^1"


def test_check_accepts_poses_it_is_told_to(tmp_path: Path) -> None:
    path = _write(tmp_path, '    <key name="home" qpos="0 1.5 1 0 0 0"/>')
    args = ("check", str(path), "--dimension", "5", "--ignore", "pose-out-of-limits")
    run = run_cli(*args)
    assert run.code == 0 and run.stdout.startswith("ok: ")


def test_a_keyframe_that_breaks_a_mimic_tie_is_named(tmp_path: Path) -> None:
    """A gripper's second finger follows the first (a linear joint equality, which
    cspace reads as a mimic joint): a keyframe that opens one and not the other."""
    path = tmp_path / "grip.xml"
    path.write_text(
        '<mujoco model="grip"><compiler angle="radian"/><worldbody><body name="palm">'
        '<geom size="0.1"/><body name="left"><joint name="l" type="slide" range="0 0.04"/>'
        '<geom size="0.01"/></body><body name="right"><joint name="r" type="slide" '
        'range="0 0.04"/><geom size="0.01"/></body></body></worldbody>'
        '<equality><joint joint1="r" joint2="l" polycoef="0.001 1 0 0 0"/></equality>\n'
        '<keyframe><key name="open" qpos="0.03 0.031"/>\n<key name="skew" qpos="0.04 0.01"/>'
        "</keyframe></mujoco>"
    )
    assert _poses(path) == [
        ("warning", "pose-mimic-inconsistent", 3,
         "keyframe 'skew': joint 'r' is 0.01, but it follows 'l' (1 x 0.04 + 0.001 = 0.041; "
         "MuJoCo's equality pulls it there)"),
    ]  # fmt: skip


def test_a_hostile_keyframe_name_is_escaped_in_every_output(tmp_path: Path) -> None:
    """A keyframe's name reaches the text report, the check line and GitHub's workflow
    commands: a line break, '::error::' and a bidi mark must not start a command there."""
    name = "home&#10;::error file=x::pwned&#8238;"
    path = _write(tmp_path, f'    <key name="{name}" qpos="0 1.5 1 0 0 0"/>')
    github = run_cli("inspect", str(path), "--format", "github")
    assert github.code == 1
    assert not any(line.startswith("::error file=x") for line in github.stdout.splitlines())
    assert "\u202e" not in github.stdout  # the finding's message escapes it, as text:
    assert "keyframe 'home\\n::error file=x::pwned\\u202e'" in github.stdout
    check = run_cli("check", str(path), "--dimension", "5")
    assert check.code == 1 and check.stderr.count("\n") == 1
    assert "\u202e" not in check.stderr and "\n::error" not in check.stderr
    text = run_cli("inspect", str(path))
    assert "\u202e" not in text.stdout and "\n::error" not in text.stdout


SDF = """<?xml version="1.0"?>
<sdf version="1.7">
  <model name="arm">
    <link name="base"/>
    <link name="upper"/>
    <link name="lower"/>
    <link name="hand"/>
    <joint name="fix" type="fixed"><parent>world</parent><child>base</child></joint>
    <joint name="shoulder" type="revolute">
      <parent>base</parent><child>upper</child>
      <axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit>
        <initial_position>{shoulder}</initial_position></axis>
    </joint>
    <joint name="elbow" type="revolute">
      <parent>upper</parent><child>lower</child>
      <axis><xyz>0 1 0</xyz><initial_position>4</initial_position></axis>
    </joint>
    <joint name="wrist" type="universal">
      <parent>lower</parent><child>hand</child>
      <axis><xyz>1 0 0</xyz></axis>
      <axis2><xyz>0 1 0</xyz><initial_position>0.5</initial_position></axis2>
    </joint>
  </model>
</sdf>
"""


def test_sdf_initial_positions_are_a_pose(tmp_path: Path) -> None:
    """SDF's <axis><initial_position> (deprecated in SDFormat 1.8): one pose, checked."""
    robot = tmp_path / "arm.sdf"
    robot.write_text(SDF.format(shoulder=0.25))
    report = cspace.inspect(robot)
    (pose,) = report.poses
    assert (pose.name, pose.source, pose.line) == ("initial_position", "initial_position", 12)
    names = [c.name for c in report.coordinates.entries]
    assert names == ["shoulder", "elbow", "wrist.axis1", "wrist.axis2"]
    assert pose.configuration == pytest.approx((0.25, 4 - 2 * 3.141592653589793, 0, 0.5))
    run = run_cli("convert", f"{robot}#initial_position", "--to", "pinocchio")
    assert run.code == 0 and run.stdout.splitlines()[1].startswith("0.25,")
    saved = tmp_path / "arm.json"  # the report, saved, passes its schema and reads back
    saved.write_text(run_cli("inspect", str(robot), "--format", "json").stdout)
    assert run_cli("diff", str(saved), str(robot)).code == 0
    robot.write_text(SDF.format(shoulder=1.5))
    outside = run_cli("inspect", str(robot))
    assert outside.code == 1 and (
        "pose-out-of-limits (line 12): initial position of joint 'shoulder' is 1.5, outside "
        "[-1, 1] rad" in outside.stdout
    )
    robot.write_text(SDF.format(shoulder="nan"))
    report = cspace.inspect(robot)
    assert [d.message for d in report.diagnostics if d.code == "pose-out-of-limits"] == [
        "initial position of joint 'shoulder' is nan: not a number"
    ]
    assert report.poses[0].configuration is None


MORE = """<mujoco model="more">
  <compiler angle="radian"/>
  <worldbody>
    <body name="target" mocap="true"/>
    <body name="base">
      <joint name="a" type="hinge" range="-1 1" ref="{ref}"/>
      <geom size="0.1"/>
      <body name="b1">
        <joint name="b" type="hinge"/>
        <geom size="0.1"/>
        <body name="c1">
          <joint name="c" type="slide" range="-1 1"/>
          <geom size="0.1"/>
        </body>
      </body>
    </body>
  </worldbody>
  <equality>
    <joint joint1="c" joint2="b" polycoef="0 0 1 0 0"/>
  </equality>
  <keyframe>
    <key name="bad" qpos="0.5 0.3 0.5" qvel="nan 0 0" mpos="nan 0 0" mquat="2 0 0 0"/>
    <key name="zero" qpos="0.5 0.3 0.09" mquat="0 0 0 0"/>
    <key name="fine" qpos="0.5 0.3 0.09" qvel="1 2 3" mpos="1 2 3" mquat="0 1 0 0"/>
  </keyframe>
</mujoco>
"""


def test_keyframe_velocities_mocap_and_polynomial_equalities(tmp_path: Path) -> None:
    robot = tmp_path / "more.xml"
    robot.write_text(MORE.format(ref=2))
    report = cspace.inspect(robot)
    said = [(d.code, d.line, d.message) for d in report.diagnostics if d.code.startswith("pose")]
    assert said == [
        ("pose-out-of-limits", 6, "qpos0 of joint 'a' (its ref, where MuJoCo starts without "
         "a keyframe) is 2, outside [-1, 1] rad"),
        ("pose-out-of-limits", 22, "keyframe 'bad': qvel of joint 'a' is nan: not finite"),
        ("pose-equality-violated", 22, "keyframe 'bad': joint 'c' is +0.41 off its joint "
         "equality 0 (tied to 'b' by a polynomial; MuJoCo's constraint pulls it there)"),
        ("pose-out-of-limits", 22, "keyframe 'bad': mpos of mocap body 'target' is "
         "(nan, 0, 0): not finite"),
        ("pose-not-unit", 22, "keyframe 'bad': mquat of mocap body 'target' is (2, 0, 0, 0) "
         "of norm 2, not 1 (MuJoCo normalises it)"),
        ("pose-out-of-limits", 23, "keyframe 'zero': mquat of mocap body 'target' is "
         "(0, 0, 0, 0): no rotation"),
    ]  # fmt: skip
    # the default ref (0) outside a range is MuJoCo's convention, not a pose the file stores
    robot.write_text(MORE.format(ref=0).replace('range="-1 1" ref', 'range="0.5 1" ref'))
    assert not [d for d in cspace.inspect(robot).diagnostics if "qpos0" in d.message]


def test_a_keyframe_converted_to_mujoco_is_mujocos_own() -> None:
    """``convert ROBOT#KEY --to mujoco`` gives MuJoCo's compiled key_qpos (quaternions
    normalised, as MuJoCo does), for every keyframe of the docs' example."""
    import mujoco

    robot = Path(__file__).parent.parent / "docs" / "examples" / "pendulum_keys.xml"
    model = mujoco.MjModel.from_xml_path(str(robot))
    for k in range(model.nkey):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_KEY, k)
        run = run_cli("convert", f"{robot}#{name}", "--to", "mujoco")
        assert run.code == 0, run.stderr
        row = [float(v) for v in run.stdout.splitlines()[1].split(",")]
        assert row == pytest.approx(list(model.key_qpos[k]), abs=1e-12)
    named = run_cli("convert", f"{robot}#home", "--to", "named", "--names", "swing")
    assert named.code == 2 and "--names: joint 'swing' (spherical)" in named.stderr


def test_a_keyframe_name_a_report_cannot_hold_is_refused(tmp_path: Path) -> None:
    """A pose's name goes in the report: past 256 characters, as a joint's, it is refused
    (a report holding it could not be read back)."""
    robot = tmp_path / "long.xml"
    robot.write_text(ROBOT.format(blank=0, keys=f'<key name="{"k" * 300}" qpos="0 0 1 0 0 0"/>'))
    run = run_cli("inspect", str(robot))
    assert run.code == 2 and "a keyframe name of 300 characters" in run.stderr
    assert "[name-too-long]" in run.stderr and run.stderr.count("\n") == 1
