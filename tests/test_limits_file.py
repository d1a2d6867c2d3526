"""MoveIt's joint_limits.yaml read with a URDF (``--limits``, ``limits=``).

The files are MoveIt Setup Assistant's layout (``tests/limits/``): panda's with
moveit_resources' panda_moveit_config values, ur5's as the assistant writes it for
example-robot-data's ``ur5_robot.urdf`` (yaml-cpp's integer ``0``) with one user edit.
MoveIt 2's ``RobotModelLoader`` is the rule: ``min_position``/``max_position`` replace
the URDF's (narrower or wider), not for a continuous joint; ``max_velocity`` only with
``has_velocity_limits: true``; ``has_position_limits`` is not read.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

import cspace
from cspace._formats.shared.erd import robots_dir
from cspace._reports.savedreport import read_report_document

from conftest import ROBOTS, OpenWatch, run_cli

LIMITS = Path(__file__).parent / "limits"
PANDA_LIMITS = LIMITS / "panda_joint_limits.yaml"
UR5_LIMITS = LIMITS / "ur5_joint_limits.yaml"


@pytest.fixture(scope="module")
def panda() -> Path:
    return robots_dir() / "panda_description" / "urdf" / "panda.urdf"


@pytest.fixture(scope="module")
def ur5() -> Path:
    return robots_dir() / "ur_description" / "urdf" / "ur5_robot.urdf"


def _line(path: Path, text: str, after: str = "") -> int:
    """The 1-based line of the first ``text`` in ``path`` after the line holding ``after``."""
    lines = path.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if after in line)
    return next(i for i, line in enumerate(lines) if i >= start and text in line) + 1


def _codes(report: cspace.Report) -> list[str]:
    return [d.code for d in report.diagnostics]


def test_panda_moveit_resources_limits_are_shown_beside_each_joint(panda: Path) -> None:
    report = cspace.inspect(panda, limits=PANDA_LIMITS)
    plain = cspace.inspect(panda)
    # moveit_resources' panda gives no positions: the C-space and every joint are the URDF's
    assert report.joints == plain.joints and report.manifold == plain.manifold
    summary = report.limits_file
    assert summary is not None and summary.file == str(PANDA_LIMITS)
    assert (summary.velocity_scaling, summary.acceleration_scaling) == (0.1, 0.1)
    joint1 = summary.by_joint()["panda_joint1"]
    urdf_line = _line(panda, "<limit", after='joint name="panda_joint1"')
    assert joint1.lower.value == -2.8973 and joint1.lower.origin == "robot"
    assert joint1.lower.line == urdf_line
    yaml_line = _line(PANDA_LIMITS, "max_acceleration", after="panda_joint1:")
    assert joint1.acceleration.value == 3.75 and joint1.acceleration.origin == "limits"
    assert joint1.acceleration.line == yaml_line
    assert joint1.jerk.value == 300.0 and joint1.effort.value == 87.0
    assert joint1.effort.origin == "robot" and joint1.acceleration.replaced == (None, None)
    assert [v.joint for v in summary.joints] == [
        *(f"panda_joint{i}" for i in range(1, 8)),
        "panda_finger_joint1",
        "panda_finger_joint2",
    ]
    # the fingers' 0.1 m/s against the URDF's 0.2: narrower, both files and lines said
    differs = [d for d in report.diagnostics if d.code == "limits-file-differs"]
    assert [d.joint for d in differs] == ["panda_finger_joint1", "panda_finger_joint2"]
    finger = differs[0]
    assert finger.file == str(PANDA_LIMITS)
    assert finger.line == _line(PANDA_LIMITS, "max_velocity", after="panda_finger_joint1:")
    line = _line(panda, "<limit", after='joint name="panda_finger_joint1"')
    assert f"0.1 ({PANDA_LIMITS}:{finger.line})" in finger.message
    assert f"0.2 ({panda}:{line})" in finger.message
    assert not report.has(cspace.Severity.WARNING)
    # the JSON document holds it, the schema and the saved-report checks accept it
    document = read_report_document("saved.json", report.to_json().encode())
    assert cspace.Report.from_dict(document) == report


def test_ur5_setup_assistant_file_narrows_the_shoulder(ur5: Path) -> None:
    run = run_cli("inspect", str(ur5), "--limits", str(UR5_LIMITS), "--format", "json")
    assert run.code == 0, run.stderr
    document = json.loads(run.stdout)
    joints = {j["name"]: j for j in document["joints"]}
    # MoveIt plans the shoulder within one turn: the report's joint is so limited
    assert joints["shoulder_pan_joint"]["limits"]["lower"] == [-math.pi]
    assert joints["shoulder_pan_joint"]["limits"]["upper"] == [math.pi]
    assert joints["shoulder_lift_joint"]["limits"]["upper"] == [6.28318530718]
    views = {v["joint"]: v for v in document["limits_file"]["joints"]}
    pan = views["shoulder_pan_joint"]
    upper = _line(UR5_LIMITS, "max_position", after="shoulder_pan_joint:")
    urdf = _line(ur5, "<limit", after='joint name="shoulder_pan_joint"')
    assert pan["upper"] == {
        "value": math.pi,
        "from": "limits",
        "line": upper,
        "replaced": {"value": 6.28318530718, "line": urdf},
    }
    # has_acceleration_limits: false switches it off; max_velocity with has_: true is read
    assert pan["acceleration"]["value"] is None and pan["acceleration"]["from"] == "limits"
    assert pan["velocity"]["value"] == 3.15 and pan["velocity"]["from"] == "limits"
    findings = document["diagnostics"]
    integers = [d for d in findings if d["code"] == "limits-file-integer"]
    assert len(integers) == 6 and all(d["file"] == str(UR5_LIMITS) for d in integers)
    assert {d["severity"] for d in integers} == {"warning"}
    # the analysis' finding on the limits MoveIt plans with is on the YAML's line
    ambiguous = [
        d
        for d in findings
        if d["code"] == "revolute-ambiguous-range" and d["joint"] == "shoulder_pan_joint"
    ]
    lower = _line(UR5_LIMITS, "min_position", after="shoulder_pan_joint:")
    assert [(d["file"], d["line"]) for d in ambiguous] == [(str(UR5_LIMITS), lower)]
    # the space samples within MoveIt's limits
    space = cspace.load(ur5, limits=UR5_LIMITS)
    column = space.names.index("shoulder_pan_joint")
    samples = space.sample(200, np.random.default_rng(0))[:, column]
    assert samples.min() >= -math.pi and samples.max() <= math.pi


def test_a_wider_yaml_is_a_warning_on_its_line_in_every_ci_format(
    panda: Path, tmp_path: Path
) -> None:
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  panda_joint1:\n"
        "    min_position: -2.5\n"
        "    max_position: 3.0\n"
        "  panda_hand_joint: {max_position: 1.0}\n"
        "  not_a_joint: {max_velocity: 1.0, has_velocity_limits: true}\n"
    )
    report = cspace.inspect(panda, limits=limits)
    joint1 = next(j for j in report.joints if j.name == "panda_joint1")
    assert joint1.limits is not None and joint1.limits.lower == (-2.5,)
    assert joint1.limits.upper == (3.0,)
    by_code = {d.code: d for d in report.diagnostics if d.file == str(limits)}
    assert set(by_code) == {
        "limits-file-differs",
        "limits-file-widens",
        "limits-file-unusable",
        "limits-file-unknown-joint",
    }
    assert by_code["limits-file-widens"].line == 4 and by_code["limits-file-differs"].line == 3
    assert "3 (" in by_code["limits-file-widens"].message
    assert "2.8973" in by_code["limits-file-widens"].message
    assert by_code["limits-file-unusable"].joint == "panda_hand_joint"
    assert "'not_a_joint'" in by_code["limits-file-unknown-joint"].message
    github = run_cli("inspect", str(panda), "--limits", str(limits), "--format", "github")
    assert f"::warning file={limits},line=4,title=cspace limits-file-widens::" in github.stdout
    sarif = json.loads(
        run_cli("inspect", str(panda), "--limits", str(limits), "--format", "sarif").stdout
    )
    located = {
        r["ruleId"]: r["locations"][0]["physicalLocation"] for r in sarif["runs"][0]["results"]
    }
    assert located["limits-file-widens"]["region"] == {"startLine": 4}
    assert located["limits-file-widens"]["artifactLocation"]["uri"].endswith("joint_limits.yaml")
    text = run_cli("inspect", str(panda), "--limits", str(limits)).stdout
    assert "-2.5 (YAML:3)" in text and "3 (YAML:4)" in text
    markdown = run_cli("inspect", str(panda), "--limits", str(limits), "--format", "markdown")
    assert "`3 (YAML:4)`" in markdown.stdout


def test_what_moveit_does_not_read_or_refuses(tmp_path: Path) -> None:
    limits = tmp_path / "limits.yaml"
    limits.write_text(
        "robot_description_planning:\n"
        "  default_velocity_scaling_factor: 1.5\n"
        "  joint_limits:\n"
        "    wrist_roll:\n"  # arm7's continuous joint: MoveIt refuses its positions
        "      min_position: -1.0\n"
        "      max_position: 1.0\n"
        "    shoulder_pan:\n"
        "      has_position_limits: false\n"
        "      max_velocity: 9.0\n"  # without has_velocity_limits: not read
        "      has_acceleration_limits: true\n"  # without max_acceleration
        "      max_jerk: -1.0\n"
        "      has_jerk_limits: true\n"
        "      max_position: 400.0\n"
        "      colour: red\n"
    )
    robot = ROBOTS / "arm7.urdf"
    report = cspace.inspect(robot, limits=limits)
    codes = sorted((d.line, d.code) for d in report.diagnostics if d.file == str(limits))
    assert codes == [
        (2, "limits-file-scaling"),
        (5, "limits-file-unusable"),
        (8, "limits-file-ignored"),  # has_position_limits
        (9, "limits-file-ignored"),  # max_velocity without has_velocity_limits
        (10, "limits-file-missing-value"),
        (11, "limits-file-negative"),
        (13, "limits-file-degrees"),
        (13, "limits-file-widens"),
        (13, "multi-turn"),  # the analysis' own, of the limits MoveIt plans with
        (14, "limits-file-ignored"),  # a key no reader knows
    ]
    roll = next(j for j in report.joints if j.name == "wrist_roll")
    assert roll.limits is None and roll.space.notation == "S^1"  # still turns freely
    pan = next(j for j in report.joints if j.name == "shoulder_pan")
    assert pan.limits is not None and pan.limits.upper == (400.0,)  # MoveIt reads rad
    # one finding on degrees, on the YAML: the analysis' own is not said twice
    assert "limits-in-degrees" not in _codes(report)
    assert report.has(cspace.Severity.ERROR)  # a negative max_jerk
    run = run_cli("inspect", str(robot), "--limits", str(limits))
    assert run.code == 1 and "limits-file-negative (limits.yaml:11)" in run.stdout


def test_a_speed_in_degrees_a_second_is_said(tmp_path: Path) -> None:
    """A UR's 180 deg/s written as max_velocity; 30 rad/s (a legged robot's) is not."""
    limits = tmp_path / "limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  shoulder_pan:\n"
        "    has_velocity_limits: true\n"
        "    max_velocity: 180.0\n"
        "  wrist_roll:\n"  # continuous: a speed all the same
        "    has_velocity_limits: true\n"
        "    max_velocity: 30.0\n"
    )
    report = cspace.inspect(ROBOTS / "arm7.urdf", limits=limits)
    found = [(d.line, d.joint) for d in report.diagnostics if d.code == "limits-file-degrees"]
    assert found == [(4, "shoulder_pan")]
    message = next(d.message for d in report.diagnostics if d.code == "limits-file-degrees")
    assert "3.142 rad/s" in message, message  # what 180 degrees a second is
    view = next(v for v in report.limits_file.joints if v.joint == "shoulder_pan")
    assert view.velocity.value == 180.0  # shown as written: not made C-space


def test_auto_finds_the_moveit_config_package(panda: Path, tmp_path: Path) -> None:
    workspace = tmp_path / "ws"
    (workspace / ".git").mkdir(parents=True)
    description = workspace / "panda_description"
    (description / "urdf").mkdir(parents=True)
    (description / "package.xml").write_text("<package><name>panda_description</name></package>")
    shutil.copy(panda, description / "urdf" / "panda.urdf")
    robot = "ws/panda_description/urdf/panda.urdf"
    none = run_cli("inspect", robot, "--limits", "auto", "--format", "json", cwd=tmp_path)
    document = json.loads(none.stdout)
    assert "limits_file" not in document
    notes = [d for d in document["diagnostics"] if d["code"] == "limits-file-not-found"]
    assert len(notes) == 1 and "looked in ws/panda_description/urdf" in notes[0]["message"]
    config = workspace / "panda_moveit_config" / "config"
    config.mkdir(parents=True)
    shutil.copy(PANDA_LIMITS, config / "joint_limits.yaml")
    found = run_cli("inspect", robot, "--limits", "auto", "--format", "json", cwd=tmp_path)
    summary = json.loads(found.stdout)["limits_file"]
    assert (
        summary["file"]
        == "ws/panda_description/urdf/../../panda_moveit_config/config/joint_limits.yaml"
    )
    # a joint_limits.yaml that leads out of the project is neither opened nor named
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "joint_limits.yaml").write_text("joint_limits: {SECRET_JOINT: {}}\n")
    (config / "joint_limits.yaml").unlink()
    (config / "joint_limits.yaml").symlink_to(outside / "joint_limits.yaml")
    watch = OpenWatch(outside)
    linked = run_cli("inspect", robot, "--limits", "auto", "--format", "json", cwd=tmp_path)
    assert watch.opened() == []
    watch.close()
    assert "SECRET_JOINT" not in linked.stdout + linked.stderr
    assert "limits_file" not in json.loads(linked.stdout)


def test_diff_shows_each_limit_change_with_its_source(panda: Path, tmp_path: Path) -> None:
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  panda_joint1:\n"
        "    max_position: 2.5\n"
        "    has_velocity_limits: true\n"
        "    max_velocity: 1.0\n"
    )
    run = run_cli("diff", str(panda), str(panda), "--new-limits", str(limits), "--format", "json")
    assert run.code == 1, run.stderr
    changes = json.loads(run.stdout)["changes"]
    line = _line(panda, "<limit", after='joint name="panda_joint1"')
    assert [(c["kind"], c["joint"], c["before"], c["after"]) for c in changes] == [
        (
            "limits",
            "panda_joint1",
            "[-2.8973, 2.8973] rad",
            "[-2.8973, 2.5] rad (upper from joint_limits.yaml:3)",
        ),
        (
            "limits",
            "panda_joint1",
            f"velocity 2.175 (panda.urdf:{line})",
            "velocity 1 (joint_limits.yaml:5)",
        ),
    ]
    same = run_cli("diff", str(panda), str(panda), "--limits", str(limits))
    assert same.code == 0, same.stdout
    # a saved report keeps its limits: diffed against the robot file read with them
    saved = tmp_path / "saved.json"
    saved.write_text(
        run_cli("inspect", str(panda), "--limits", str(limits), "--format", "json").stdout
    )
    again = run_cli("diff", str(saved), str(panda), "--new-limits", str(limits))
    assert again.code == 0, again.stdout


def test_check_baseline_with_limits(panda: Path, tmp_path: Path) -> None:
    shutil.copy(panda, tmp_path / "panda.urdf")
    (tmp_path / "joint_limits.yaml").write_text(
        "joint_limits:\n  panda_joint1: {max_position: 2.5}\n"
    )
    options = ("--limits", "joint_limits.yaml")
    baseline = run_cli("inspect", "panda.urdf", *options, "--format", "jsonl", cwd=tmp_path)
    (tmp_path / "base.jsonl").write_text(baseline.stdout)
    held = run_cli("check", "--baseline", "base.jsonl", "panda.urdf", *options, cwd=tmp_path)
    assert held.code == 0, held.stdout + held.stderr
    moved = run_cli("check", "--baseline", "base.jsonl", "panda.urdf", cwd=tmp_path)
    assert moved.code == 1 and "limits differ" in moved.stdout


def test_limits_go_with_a_urdf_only(tmp_path: Path) -> None:
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text("joint_limits: {}\n")
    mjcf = Path(__file__).parent / "pairs" / "arm7.xml"
    run = run_cli("inspect", str(mjcf), "--limits", str(limits))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "[limits-format]" in run.stderr
    auto = cspace.inspect(mjcf, limits=True)  # auto: nothing to look for
    assert auto.limits_file is None and "limits-file-not-found" not in _codes(auto)


def test_a_hostile_saved_limits_file_is_refused_in_one_line(panda: Path, tmp_path: Path) -> None:
    document = cspace.inspect(panda, limits=PANDA_LIMITS).to_dict()
    document["limits_file"]["joints"][0]["upper"]["value"] = 9.0  # not the joint's limit
    saved = tmp_path / "saved.json"
    saved.write_text(json.dumps(document))
    run = run_cli("diff", str(saved), str(saved))
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "upper limit of 'panda_joint1' other than the joint's" in run.stderr
    document["limits_file"]["joints"][0]["upper"]["value"] = 2.8973
    document["limits_file"]["joints"][0]["joint"] = "::error::forged"
    saved.write_text(json.dumps(document))
    forged = run_cli("diff", str(saved), str(saved), "--format", "github")
    assert forged.code == 2 and "::error::forged" not in forged.stdout + forged.stderr


def test_auto_reads_the_one_beside_the_srdf_and_a_file_goes_with_one_robot(
    panda: Path, tmp_path: Path
) -> None:
    config = tmp_path / "config"
    config.mkdir()
    shutil.copy(panda.parent.parent / "srdf" / "panda.srdf", config / "panda.srdf")
    shutil.copy(PANDA_LIMITS, config / "joint_limits.yaml")
    shutil.copy(panda, tmp_path / "panda.urdf")
    run = run_cli(
        "inspect", "panda.urdf", "--srdf", "config/panda.srdf", "--limits", "auto",
        "--format", "json", cwd=tmp_path,
    )  # fmt: skip
    assert json.loads(run.stdout)["limits_file"]["file"] == "config/joint_limits.yaml"
    two = run_cli("inspect", str(panda), str(ROBOTS / "arm7.urdf"), "--limits", str(PANDA_LIMITS))
    assert two.code == 2 and "--limits FILE goes with one robot" in two.stderr


def test_a_groups_report_keeps_moveits_limits_and_reads_back(panda: Path, tmp_path: Path) -> None:
    srdf = panda.parent.parent / "srdf" / "panda.srdf"
    report = cspace.inspect(panda, srdf=srdf, group="arm", limits=PANDA_LIMITS)
    assert report.limits_file is not None and report.group is not None
    saved = tmp_path / "arm.json"
    saved.write_text(report.to_json())
    run = run_cli("diff", str(saved), str(saved))
    assert run.code == 0, run.stderr


def test_a_ros2_parameter_file_and_a_planar_joints_variables(tmp_path: Path) -> None:
    robot = ROBOTS / "arm7.urdf"
    limits = tmp_path / "move_group.yaml"
    limits.write_text(
        "/**:\n"
        "  ros__parameters:\n"
        "    robot_description_planning:\n"
        "      joint_limits:\n"
        "        shoulder_pan: {max_position: 1.0}\n"
        "        tool_mount/x: {max_position: 1.0}\n"
    )
    report = cspace.inspect(robot, limits=limits)
    pan = next(j for j in report.joints if j.name == "shoulder_pan")
    assert pan.limits is not None and pan.limits.upper == (1.0,)
    unusable = [d for d in report.diagnostics if d.code == "limits-file-unusable"]
    assert [(d.joint, d.line) for d in unusable] == [("tool_mount", 6)]


def test_auto_leaves_another_robots_limits(panda: Path, tmp_path: Path) -> None:
    (tmp_path / "config").mkdir()
    shutil.copy(PANDA_LIMITS, tmp_path / "config" / "joint_limits.yaml")
    shutil.copy(ROBOTS / "arm7.urdf", tmp_path / "arm7.urdf")
    shutil.copy(panda, tmp_path / "panda.urdf")
    arm = cspace.inspect(tmp_path / "arm7.urdf", limits=True)
    assert arm.limits_file is None
    note = [d.message for d in arm.diagnostics if d.code == "limits-file-not-found"]
    assert len(note) == 1 and "names none of the robot's joints" in note[0]
    assert cspace.inspect(tmp_path / "panda.urdf", limits=True).limits_file is not None


def test_the_html_page_shows_the_limits_table(panda: Path) -> None:
    page = run_cli("inspect", str(panda), "--limits", str(PANDA_LIMITS), "--format", "html")
    assert page.code == 0 and "<h2>Limits</h2>" in page.stdout
    line = _line(PANDA_LIMITS, "max_acceleration", after="panda_joint1:")
    assert f"<td>3.75 (YAML:{line})</td>" in page.stdout
    assert "<h2>Limits</h2>" not in run_cli("inspect", str(panda), "--format", "html").stdout


def test_numbers_read_as_ros2_reads_them(tmp_path: Path) -> None:
    """PyYAML (YAML 1.1) reads 1e3 as text; ROS 2's parameter files read 1000.0."""
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  shoulder_pan: {has_jerk_limits: true, max_jerk: 1e3, max_position: 5E-1}\n"
    )
    view = cspace.inspect(ROBOTS / "arm7.urdf", limits=limits).limits_file
    assert view is not None
    pan = view.by_joint()["shoulder_pan"]
    assert (pan.jerk.value, pan.upper.value) == (1000.0, 0.5)


def test_a_negative_rate_is_an_error_that_leaves_the_c_space(tmp_path: Path) -> None:
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n  shoulder_pan:\n    has_velocity_limits: true\n    max_velocity: -1.0\n"
    )
    robot = ROBOTS / "arm7.urdf"
    # a velocity is no part of the C-space: the space of the robot's positions is built
    space = cspace.load(robot, limits=limits)
    assert space.dimension == cspace.load(robot).dimension
    sampled = run_cli("sample", str(robot), "--limits", str(limits), "-n", "1")
    assert sampled.code == 0, sampled.stderr
    inspected = run_cli("inspect", str(robot), "--limits", str(limits))
    assert inspected.code == 1 and "limits-file-negative" in inspected.stdout
    # empty position limits from the YAML still leave no space
    limits.write_text("joint_limits:\n  shoulder_pan: {min_position: 1.0, max_position: -1.0}\n")
    with pytest.raises(cspace.errors.RobotHasErrorsError, match="limits-empty"):
        cspace.load(robot, limits=limits)


def test_a_default_scaling_factor_raised_fails_the_baseline(panda: Path, tmp_path: Path) -> None:
    shutil.copy(panda, tmp_path / "panda.urdf")
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text("default_velocity_scaling_factor: 0.1\njoint_limits: {}\n")
    options = ("--limits", "joint_limits.yaml")
    baseline = run_cli("inspect", "panda.urdf", *options, "--format", "jsonl", cwd=tmp_path)
    (tmp_path / "base.jsonl").write_text(baseline.stdout)
    # MoveIt then moves every plan ten times as fast
    limits.write_text("default_velocity_scaling_factor: 1.0\njoint_limits: {}\n")
    moved = run_cli("check", "--baseline", "base.jsonl", "panda.urdf", *options, cwd=tmp_path)
    assert moved.code == 1 and "limits differ" in moved.stdout, moved.stdout
    saved = tmp_path / "base.json"
    saved.write_text(json.dumps(json.loads(baseline.stdout.splitlines()[0])))
    run = run_cli("diff", "base.json", "panda.urdf", *options, "--format", "json", cwd=tmp_path)
    changes = json.loads(run.stdout)["changes"]
    assert [(c["kind"], c["joint"], c["before"], c["after"]) for c in changes] == [
        (
            "limits",
            None,
            "default_velocity_scaling_factor 0.1 (joint_limits.yaml)",
            "default_velocity_scaling_factor 1 (joint_limits.yaml)",
        )
    ]


def test_an_integer_moveit_reads_stops_that_joints_entry(tmp_path: Path) -> None:
    """move_group declares the file's parameters as written: an integer is no double, and
    ``RobotModelLoader`` logs the error and reads none of the joint's later keys."""
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  shoulder_pan:\n"
        "    min_position: -0.5\n"
        "    max_position: 2\n"  # read first, an integer: nothing of this joint is taken
        "  shoulder_lift:\n"
        "    max_position: 0.5\n"
        "    has_velocity_limits: true\n"
        "    max_velocity: 3\n"  # an integer: the URDF's velocity stands
        "    has_acceleration_limits: true\n"
        "    max_acceleration: 4.0\n"  # after it: not read
        "  elbow:\n"
        "    has_acceleration_limits: false\n"
        "    max_acceleration: 0\n"  # not read at all (Setup Assistant's 0): no matter
    )
    robot = ROBOTS / "arm7.urdf"
    report = cspace.inspect(robot, limits=limits)
    plain = {j.name: j for j in cspace.inspect(robot).joints}
    joints = {j.name: j for j in report.joints}
    assert joints["shoulder_pan"].limits == plain["shoulder_pan"].limits
    assert joints["shoulder_lift"].limits is not None
    assert joints["shoulder_lift"].limits.upper == (0.5,)
    view = report.limits_file
    assert view is not None
    pan, lift = view.by_joint()["shoulder_pan"], view.by_joint()["shoulder_lift"]
    assert (pan.lower.origin, pan.upper.origin) == ("robot", "robot")
    assert (lift.upper.origin, lift.velocity.origin) == ("limits", "robot")
    assert (lift.acceleration.origin, lift.acceleration.value) == ("robot", None)
    integers = sorted(d.line for d in report.diagnostics if d.code == "limits-file-integer")
    assert integers == [4, 8, 13]
    said = [d.code for d in report.diagnostics if d.line in (3, 4) and d.file == str(limits)]
    assert "limits-file-differs" not in said and "limits-file-widens" not in said


def test_shared_limits_by_anchors_and_merge_keys(tmp_path: Path) -> None:
    """An entry merging shared limits and overriding one, itself used twice (YAML 1.1's
    ``<<``, which ROS 2's parameter files read too): the explicit key wins each time."""
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "defaults: &d {has_velocity_limits: true, max_velocity: 1.0, max_position: 0.4}\n"
        "arm: &arm {<<: *d, max_velocity: 2.0}\n"
        "joint_limits:\n"
        "  shoulder_pan: *arm\n"
        "  elbow: *arm\n"
        "  shoulder_lift: {<<: *arm, max_position: 0.3}\n"
    )
    view = cspace.inspect(ROBOTS / "arm7.urdf", limits=limits).limits_file
    assert view is not None
    joints = view.by_joint()
    for name, upper in (("shoulder_pan", 0.4), ("elbow", 0.4), ("shoulder_lift", 0.3)):
        assert (joints[name].velocity.value, joints[name].upper.value) == (2.0, upper), name
    limits.write_text(
        "joint_limits:\n  elbow: {<<: {max_velocity: 1.0}, max_jerk: 1.0, max_jerk: 2.0}\n"
    )
    with pytest.raises(cspace.errors.InvalidElementError, match="gives key 'max_jerk' twice"):
        cspace.inspect(ROBOTS / "arm7.urdf", limits=limits)


def test_moveit_starts_from_the_safety_controllers_soft_limits(tmp_path: Path) -> None:
    """MoveIt's bounds of a URDF joint with a <safety_controller> are its soft limits within
    its limits (robot_model.cpp's jointBoundsFromURDF): the YAML's replace them side by side."""
    robot = tmp_path / "arm.urdf"
    robot.write_text(
        '<robot name="arm">\n'
        '  <link name="base"/><link name="a"/><link name="b"/>\n'
        '  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>\n'
        '    <limit lower="-2.0" upper="2.0" effort="1" velocity="1"/>\n'
        '    <safety_controller k_velocity="1" soft_lower_limit="-1.5" soft_upper_limit="3"/>\n'
        "  </joint>\n"
        '  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/>\n'
        '    <limit lower="0" upper="0.5" effort="1" velocity="1"/>\n'
        '    <safety_controller k_velocity="1" soft_lower_limit="0.1" soft_upper_limit="0.4"/>\n'
        "  </joint>\n"
        "</robot>\n"
    )
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text("joint_limits:\n  j1: {max_position: 1.0}\n  j2: {}\n")
    report = cspace.inspect(robot, limits=limits)
    bounds = {j.name: (j.limits.lower, j.limits.upper) for j in report.joints if j.limits}
    assert bounds == {"j1": ((-1.5,), (1.0,)), "j2": ((0.1,), (0.4,))}
    assert report.limits_file is not None
    j1 = report.limits_file.by_joint()["j1"]
    assert (j1.lower.value, j1.lower.origin, j1.upper.origin) == (-1.5, "robot", "limits")
    # compared with what MoveIt had: 1.0 narrows the soft limit's 2.0 (not the limit's)
    differs = [d.message for d in report.diagnostics if d.code == "limits-file-differs"]
    assert len(differs) == 1 and "narrows the robot file's 2 " in differs[0], differs
    plain = {j.name: (j.limits.lower, j.limits.upper) for j in cspace.inspect(robot).joints}
    assert plain["j2"] == ((0.0,), (0.5,))  # without --limits: the URDF's, as Pinocchio's
    saved = tmp_path / "saved.json"
    saved.write_text(
        run_cli("inspect", str(robot), "--limits", str(limits), "--format", "json").stdout
    )
    assert run_cli("diff", str(saved), str(robot), "--limits", str(limits)).code == 0


def test_a_sides_limits_for_a_saved_report_are_refused(panda: Path, tmp_path: Path) -> None:
    """A saved report keeps the limits it was made with: --old-limits naming a YAML for
    it would otherwise be dropped, and the diff say nothing of that YAML."""
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text("joint_limits:\n  panda_joint1: {max_position: 2.5}\n")
    saved = tmp_path / "saved.json"
    saved.write_text(run_cli("inspect", str(panda), "--format", "json").stdout)
    run = run_cli("diff", str(saved), str(panda), "--old-limits", str(limits))
    assert run.code == 2 and "[limits-format]" in run.stderr, run.stdout + run.stderr
    assert run.stderr.count("\n") == 1
    both = run_cli("diff", str(saved), str(panda), "--limits", str(limits))
    assert both.code == 1 and "limits differ" in both.stdout  # the robot file's side read


def test_a_urdf_velocity_of_zero_is_no_velocity_limit_to_moveit(tmp_path: Path) -> None:
    """MoveIt's ``jointBoundsFromURDF`` bounds a variable's velocity at ``fabs(velocity)``
    only above machine epsilon: a URDF ``velocity="0"`` (what CAD exporters write) is no
    velocity limit to MoveIt, and a negative one is its magnitude. A
    ``has_velocity_limits: true`` without ``max_velocity`` keeps that magnitude, bounded."""
    robot = tmp_path / "robot.urdf"
    robot.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>'
        '<joint name="free_speed" type="revolute"><parent link="a"/><child link="b"/>'
        '<limit lower="-1" upper="1" effort="0" velocity="0"/></joint>\n'
        '<joint name="held" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="0"/></joint>\n'
        '<joint name="backwards" type="prismatic"><parent link="c"/><child link="d"/>'
        '<limit lower="0" upper="1" effort="1" velocity="-0.5"/></joint>\n'
        '<joint name="slow" type="revolute"><parent link="d"/><child link="e"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="-2"/></joint><link name="e"/></robot>\n'
    )
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n"
        "  held:\n"
        "    has_velocity_limits: true\n"  # no max_velocity: MoveIt keeps 0, now bounded
        "  backwards:\n"
        "    has_acceleration_limits: true\n"
        "    max_acceleration: 1.0\n"
        "  slow:\n"
        "    has_velocity_limits: true\n"
        "    max_velocity: 1.0\n"  # narrower than the 2 both tools read
    )
    report = cspace.inspect(robot, limits=limits)
    said = {(d.code, d.line) for d in report.diagnostics if d.file == str(limits)}
    assert ("limits-file-differs", 9) in said and ("limits-file-widens", 9) not in said
    view = report.limits_file
    assert view is not None
    joints = view.by_joint()
    assert (joints["free_speed"].velocity.value, joints["free_speed"].velocity.origin) == (
        None,
        "robot",
    )
    assert joints["held"].velocity.value == 0.0
    assert joints["backwards"].velocity.value == 0.5
    run = run_cli("inspect", str(robot), "--limits", str(limits), "--format", "json")
    shown = {
        j["joint"]: j["velocity"]["value"] for j in json.loads(run.stdout)["limits_file"]["joints"]
    }
    assert shown == {"free_speed": None, "held": 0.0, "backwards": 0.5, "slow": 1.0}
