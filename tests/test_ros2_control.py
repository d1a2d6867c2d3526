"""``<ros2_control>`` in URDF and xacro: read as ros2_control reads it, checked against the URDF.

The fixtures (tests/ros2_control/) are ros2_control_demos' RRBot (xacro, its ros2_control
xacro included) and DiffBot, and a panda-style arm whose one component holds every case:
bounds narrower than the URDF's, wider, a number ros2_control's ``stod`` refuses, a
continuous joint bounded, a fixed joint, a mimic joint commanded, a joint the URDF lacks,
and initial values (one outside the limits) that make a stored pose.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import cspace

from conftest import REPO, run_cli

HERE = REPO / "tests" / "ros2_control"
ARM = HERE / "arm.urdf"

ARM_FINDINGS = [
    ("ros2-control-bounds-differ", "joint2", 79),
    ("ros2-control-bounds-exceed", "joint3", 88),
    ("pose-out-of-limits", "joint4", 98),
    ("ros2-control-number-invalid", "joint5", 103),
    ("ros2-control-continuous-bounded", "joint7", 110),
    ("ros2-control-fixed-joint", "hand_joint", 118),
    ("ros2-control-mimic-commanded", "finger_joint2", 127),
    ("ros2-control-unknown-joint", "joint8", 131),
]


@pytest.fixture(scope="module")
def arm() -> cspace.Report:
    return cspace.inspect(ARM)


def _ours(report: cspace.Report) -> list[tuple[str, str | None, int | None]]:
    return [
        (d.code, d.joint, d.line)
        for d in report.diagnostics
        if d.code.startswith("ros2-control-") or d.code.startswith("pose-")
    ]


def test_each_case_is_a_finding_on_its_line(arm: cspace.Report) -> None:
    assert _ours(arm) == ARM_FINDINGS
    by_code = {d.code: d for d in arm.diagnostics}
    assert "[-1.5, 1.5] rad" in by_code["ros2-control-bounds-differ"].message
    assert "[-1.7628, 1.7628] rad" in by_code["ros2-control-bounds-differ"].message
    assert "applies [-2.8973, 2.8973] rad" in by_code["ros2-control-bounds-exceed"].message
    assert "'nan'" in by_code["ros2-control-number-invalid"].message
    assert "outside [-3.0718, -0.0698] rad" in by_code["pose-out-of-limits"].message


def test_the_component_is_the_reports_part(arm: cspace.Report) -> None:
    (component,) = arm.ros2_control
    assert (component.name, component.type, component.plugin) == (
        "ArmSystem",
        "system",
        "mock_components/GenericSystem",
    )
    names = [j.name for j in component.joints]
    assert names[:3] == ["joint1", "joint2", "joint3"] and names[-1] == "joint8"
    joint2 = component.joints[1]
    position = joint2.interface("command", "position")
    assert position is not None
    assert (position.min, position.max, position.line) == ("-1.5", "1.5", 79)
    assert joint2.interface("state", "position").initial_value == "-0.785"  # type: ignore[union-attr]


def test_initial_values_are_a_pose_convert_reads(arm: cspace.Report) -> None:
    (pose,) = arm.poses
    assert (pose.name, pose.source, pose.line) == ("ArmSystem", "ros2_control", 65)
    assert pose.configuration is not None
    names = [e.name for e in arm.coordinates.entries]
    values = dict(zip(names, pose.configuration, strict=True))
    assert values["joint2"] == -0.785 and values["finger_joint1"] == 0.02
    assert values["joint7"] == 0.785
    assert values["joint5"] == 0.0  # no initial value: neutral
    run = run_cli("convert", f"{ARM}#ArmSystem", "--to", "pinocchio")
    assert run.code == 0, run.stderr
    header, row = run.stdout.split()
    assert header.split(",")[1] == "joint2" and row.split(",")[1] == "-0.785"


def test_errors_fail_inspect_and_leave_the_space(arm: cspace.Report) -> None:
    run = run_cli("inspect", str(ARM))
    assert run.code == 1
    assert "ros2-control-unknown-joint (line 131)" in run.stdout
    space = cspace.space.ConfigurationSpace.from_report(
        arm
    )  # controller's errors: the C-space is the URDF's
    assert space.dimension == 8


def test_rrbot_xacro_bounds_its_continuous_joints() -> None:
    report = cspace.inspect(HERE / "rrbot.urdf.xacro")
    found = [(d.code, d.joint, d.line) for d in report.diagnostics]
    assert found == [
        ("ros2-control-continuous-bounded", "joint1", None),
        ("ros2-control-continuous-bounded", "joint2", None),
    ]
    (component,) = report.ros2_control
    assert component.name == "RRBot" and component.line is None
    assert [j.name for j in component.joints] == ["joint1", "joint2"]
    assert report.poses == ()


def test_diffbot_velocity_interfaces_say_nothing() -> None:
    report = cspace.inspect(HERE / "diffbot.urdf")
    assert [d.code for d in report.diagnostics] == ["root-joint-suggested"]
    (component,) = report.ros2_control
    assert [i.name for i in component.joints[0].state] == ["position", "velocity"]
    assert component.plugin == "ros2_control_demo_example_2/DiffBotSystemHardware"


def test_the_part_reads_back_and_is_absent_without_one(tmp_path: Path) -> None:
    saved = tmp_path / "arm.json"
    run = run_cli("inspect", str(ARM), "--format", "json")
    assert run.code == 1, run.stderr
    saved.write_text(run.stdout)
    document = json.loads(run.stdout)
    assert document["ros2_control"][0]["joints"][1]["command_interfaces"][0]["min"] == "-1.5"
    again = cspace.Report.from_dict(document)
    assert again.ros2_control == cspace.inspect(ARM).ros2_control
    assert run_cli("diff", str(saved), str(saved)).code == 0
    plain = cspace.inspect(REPO / "tests" / "findings" / "joint_locked.urdf").to_dict()
    assert "ros2_control" not in plain


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            lambda d: d.__setitem__("source", {**d["source"], "format": "mjcf"}),
            "report with <ros2_control>",
        ),
        (
            lambda d: d["poses"][0].__setitem__("name", "Other"),
            "no <ros2_control> component's",
        ),
        (
            lambda d: d["ros2_control"][0]["joints"][0]["command_interfaces"][0].__setitem__(
                "min", "1" * 65
            ),
            "min",
        ),
    ],
)
def test_a_saved_report_that_contradicts_itself_is_refused(
    tmp_path: Path, arm: cspace.Report, change: object, message: str
) -> None:
    document = arm.to_dict()
    change(document)  # type: ignore[operator]
    saved = tmp_path / "bad.json"
    saved.write_text(json.dumps(document))
    run = run_cli("diff", str(saved), str(saved))
    assert run.code == 2
    assert run.stderr.count("\n") == 1 and message in run.stderr, run.stderr


def test_text_and_markdown_show_each_commanded_joint_beside_it() -> None:
    text = run_cli("inspect", str(ARM)).stdout
    rows = {line.split()[0]: line for line in text.splitlines() if line.startswith(("joint", "f"))}
    assert rows["joint2"].endswith("position [-1.5, 1.5] initial -0.785")
    assert rows["joint6"].endswith(" -")
    assert "ros2_control  ArmSystem (mock_components/GenericSystem, 10 joints)" in text
    markdown = run_cli("inspect", str(ARM), "--format", "markdown").stdout
    assert (
        "| `joint7` | continuous | S^1 | - | 6..7 | 6 | position [-3.14, 3.14] initial 0.785 |"
        in (markdown)
    )
    html = run_cli("inspect", str(ARM), "--format", "html").stdout
    assert "<td>joint2</td><td>position [-1.5, 1.5] initial -0.785</td><td>78</td>" in html
    plain = run_cli("inspect", str(REPO / "tests" / "findings" / "joint_locked.urdf")).stdout
    assert "ros2_control" not in plain


def test_diff_says_a_bound_or_initial_value_moved_with_its_line(tmp_path: Path) -> None:
    text = ARM.read_text()
    moved = text.replace('<param name="min">-1.5</param>', '<param name="min">-1.2</param>')
    moved = moved.replace(
        '<param name="initial_value">0.02</param>', '<param name="initial_value">0.03</param>'
    )
    assert moved.count("\n") == text.count("\n") and moved != text
    new = tmp_path / "arm.urdf"
    new.write_text(moved)
    run = run_cli("diff", str(ARM), str(new), "--format", "json")
    assert run.code == 1, run.stderr
    changes = json.loads(run.stdout)["changes"]
    assert changes == [
        {
            "kind": "ros2-control",
            "joint": "joint2",
            "before": "position [-1.5, 1.5], initial -0.785 (line 79)",
            "after": "position [-1.2, 1.5], initial -0.785 (line 79)",
        },
        {
            "kind": "ros2-control",
            "joint": "finger_joint1",
            "before": "initial 0.02 (line 122)",
            "after": "initial 0.03 (line 122)",
        },
    ]
    text_diff = run_cli("diff", str(ARM), str(new)).stdout
    assert "but ros2_control bounds differs" in text_diff
    within = moved.replace("-1.2</param>", "-1.5000001</param>").replace(">0.03<", ">0.02<")
    new.write_text(within)
    assert run_cli("diff", str(ARM), str(new)).code == 0  # within the tolerance


def test_github_and_sarif_put_each_finding_on_its_line() -> None:
    github = run_cli("inspect", "--format", "github", str(ARM)).stdout
    for code, _, line in ARM_FINDINGS:
        assert f",line={line},title=cspace {code}::" in github, (code, github)
    sarif = json.loads(run_cli("inspect", "--format", "sarif", str(ARM)).stdout)
    placed = [
        (r["ruleId"], r["locations"][0]["physicalLocation"]["region"]["startLine"])
        for r in sarif["runs"][0]["results"]
        if r["ruleId"].startswith(("ros2-control-", "pose-"))
    ]
    assert placed == [(code, line) for code, _, line in ARM_FINDINGS]
    rules = {rule["id"] for rule in sarif["runs"][0]["tool"]["driver"]["rules"]}
    assert {code for code, _, _ in ARM_FINDINGS} <= rules


GRIPPER = (
    '<robot name="gripper">\n'
    '  <link name="base"/><link name="a"/><link name="b"/>\n'
    '  <joint name="finger1" type="prismatic"><parent link="base"/><child link="a"/>\n'
    '    <limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>\n'
    '  <joint name="finger2" type="prismatic"><parent link="base"/><child link="b"/>\n'
    '    <limit lower="0" upper="0.04" effort="1" velocity="1"/>\n'
    '    <mimic joint="finger1"/></joint>\n'
)
"""A gripper's seven lines before its <ros2_control>: finger2 mimics finger1."""


def test_a_mimic_joint_without_its_leader_or_a_mimic_attribute_not_a_bool(tmp_path: Path) -> None:
    robot = tmp_path / "gripper.urdf"
    robot.write_text(
        GRIPPER + '  <ros2_control name="Hand" type="system">\n'
        "    <hardware><plugin>mock_components/GenericSystem</plugin></hardware>\n"
        '    <joint name="finger2">\n'  # line 10: ros2_control looks for finger1 here
        '      <state_interface name="position"/>\n'
        "    </joint>\n"
        "  </ros2_control>\n"
        '  <ros2_control name="Other" type="system">\n'
        "    <hardware><plugin>mock_components/GenericSystem</plugin></hardware>\n"
        '    <joint name="finger1" mimic="yes">\n'  # line 16: parse_bool refuses 'yes'
        '      <command_interface name="position"/>\n'
        "    </joint>\n"
        '    <joint name="finger2" mimic="false"><state_interface name="velocity"/></joint>\n'
        "  </ros2_control>\n"
        "</robot>\n"
    )  # (its position state interface is Hand's: a second one is refused, another finding)
    report = cspace.inspect(robot)
    assert sorted(_ours(report), key=lambda found: found[2] or 0) == [
        ("ros2-control-invalid", "finger2", 10),
        ("ros2-control-invalid", "finger1", 16),
    ]
    said = {d.joint: d.message for d in report.diagnostics if d.code == "ros2-control-invalid"}
    assert "not its leader 'finger1'" in said["finger2"] and 'mimic="yes"' in said["finger1"]
    run = run_cli("inspect", str(robot))
    assert run.code == 1 and "ros2-control-invalid" in run.stdout


def test_diff_says_a_velocity_or_effort_bound_moved(tmp_path: Path) -> None:
    """ros2_control applies every command interface's bounds it knows (velocity, effort,
    acceleration, jerk) as the tighter of them and the URDF's: raising one that is the
    tighter lets the controllers drive the joint faster."""

    def robot(velocity: str, effort: str) -> str:
        return (
            '<robot name="r">\n'
            '  <link name="base"/><link name="a"/>\n'
            '  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>\n'
            '    <limit lower="-1" upper="1" effort="10" velocity="2"/></joint>\n'
            '  <ros2_control name="S" type="system">\n'
            "    <hardware><plugin>mock_components/GenericSystem</plugin></hardware>\n"
            '    <joint name="j1">\n'
            '      <command_interface name="velocity">\n'  # line 8
            f'        <param name="min">-0.5</param><param name="max">{velocity}</param>\n'
            "      </command_interface>\n"
            f'      <command_interface name="effort">{effort}</command_interface>\n'
            '      <state_interface name="position"/>\n'
            "    </joint>\n"
            "  </ros2_control>\n"
            "</robot>\n"
        )

    old, new = tmp_path / "old.urdf", tmp_path / "new.urdf"
    old.write_text(robot("0.5", '<param name="max">5</param>'))
    new.write_text(robot("1.5", '<limits enable="false"/><param name="max">5</param>'))
    run = run_cli("diff", str(old), str(new), "--format", "json")
    assert run.code == 1, run.stdout + run.stderr
    changes = [
        (c["kind"], c["joint"], c["before"], c["after"]) for c in json.loads(run.stdout)["changes"]
    ]
    assert changes == [
        ("ros2-control", "j1", "velocity [-0.5, 0.5] (line 8)", "velocity [-0.5, 1.5] (line 8)"),
        ("ros2-control", "j1", "effort [-, 5] (line 11)", "effort: none (line 11)"),
    ]
    assert run_cli("diff", str(old), str(old)).code == 0


def test_a_mimic_joint_commanded_apart_has_its_bounds_checked(tmp_path: Path) -> None:
    robot = tmp_path / "gripper.urdf"
    robot.write_text(
        GRIPPER + '  <ros2_control name="Hand" type="system">\n'
        "    <hardware><plugin>mock_components/GenericSystem</plugin></hardware>\n"
        '    <joint name="finger2" mimic="false">\n'
        '      <command_interface name="position">\n'  # line 11: applied, as any joint's
        '        <param name="min">-0.5</param>\n'
        "      </command_interface>\n"
        "    </joint>\n"
        "  </ros2_control>\n"
        "</robot>\n"
    )
    found = _ours(cspace.inspect(robot))
    assert ("ros2-control-bounds-exceed", "finger2", 11) in found, found


def test_check_fails_on_an_error_ros2_control_refuses(tmp_path: Path) -> None:
    robot = tmp_path / "arm7.urdf"
    robot.write_text(
        (REPO / "robots" / "arm7.urdf")
        .read_text()
        .replace(
            "</robot>",
            '<ros2_control name="S" type="system"><hardware><plugin>p</plugin></hardware>'
            '<joint name="nope"><command_interface name="position"/></joint></ros2_control>'
            "</robot>",
        )
    )
    run = run_cli("check", str(robot), "--dimension", "7")
    assert run.code == 1 and "ros2-control-unknown-joint" in run.stdout + run.stderr, run
    ignored = run_cli(
        "check", str(robot), "--dimension", "7", "--ignore", "ros2-control-unknown-joint"
    )
    assert ignored.code == 0, ignored.stdout + ignored.stderr
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text("joint_limits:\n  elbow: {has_jerk_limits: true, max_jerk: -1.0}\n")
    plain = run_cli("check", str(REPO / "robots" / "arm7.urdf"), "--dimension", "7")
    assert plain.code == 0, plain.stdout + plain.stderr
    negative = run_cli(
        "check", str(REPO / "robots" / "arm7.urdf"), "--dimension", "7", "--limits", str(limits)
    )
    assert negative.code == 1 and "limits-file-negative" in negative.stdout + negative.stderr


def _two_components(high: str, initial: str, rate: str) -> str:
    """Joint j in two components: a sensor's state interface (its initial value) first,
    then an actuator's position and velocity command interfaces (their bounds)."""
    return (
        '<robot name="r">\n'
        '  <link name="base"/><link name="a"/>\n'
        '  <joint name="j" type="revolute"><parent link="base"/><child link="a"/>\n'
        '    <limit lower="-1" upper="1" effort="10" velocity="2"/></joint>\n'
        '  <ros2_control name="Sensors" type="sensor"><hardware><plugin>s</plugin></hardware>\n'
        '    <joint name="j"><state_interface name="position">\n'
        f'      <param name="initial_value">{initial}</param></state_interface></joint>\n'
        "  </ros2_control>\n"
        '  <ros2_control name="Motors" type="actuator"><hardware><plugin>m</plugin></hardware>\n'
        '    <joint name="j">\n'
        '      <command_interface name="position">\n'  # line 11
        f'        <param name="min">-0.5</param><param name="max">{high}</param>\n'
        "      </command_interface>\n"
        '      <command_interface name="velocity">\n'  # line 14
        f'        <param name="max">{rate}</param></command_interface>\n'
        "    </joint>\n"
        "  </ros2_control>\n"
        "</robot>\n"
    )


def test_diff_reads_a_joints_interfaces_in_every_component(tmp_path: Path) -> None:
    """A joint named by two components (no interface twice, as ros2_control accepts): the
    bounds of the component that commands it are the ones applied, and moving them, or
    the other component's initial value, is a change."""
    old, new = tmp_path / "old.urdf", tmp_path / "new.urdf"
    old.write_text(_two_components("0.5", "0.1", "1.0"))
    assert "ros2-control-invalid" not in {d.code for d in cspace.inspect(old).diagnostics}
    new.write_text(_two_components("0.9", "0.2", "1.5"))
    run = run_cli("diff", str(old), str(new), "--format", "json")
    assert run.code == 1, run.stdout + run.stderr
    changes = [
        (c["kind"], c["joint"], c["before"], c["after"]) for c in json.loads(run.stdout)["changes"]
    ]
    assert changes == [
        (
            "ros2-control",
            "j",
            "position [-0.5, 0.5], initial 0.1 (line 11)",
            "position [-0.5, 0.9], initial 0.2 (line 11)",
        ),
        ("ros2-control", "j", "velocity [-, 1.0] (line 14)", "velocity [-, 1.5] (line 14)"),
    ]
    assert run_cli("diff", str(old), str(old)).code == 0
