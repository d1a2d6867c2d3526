"""MoveIt's SRDF read with a URDF: virtual and passive joints, groups, group states.

The hand-written robot (``docs/examples/mobile_arm``) uses every SRDF element cspace reads;
Pinocchio is the oracle for what a group state is (``loadReferenceConfigurations`` on
cspace's own Pinocchio model) and for a group's C-space (``buildReducedModel``), on it
and on every SRDF example-robot-data ships beside its URDF. Hostile SRDF files are
refused in one line naming the file and the line, or bounded.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import cspace
from cspace._model.semantics import find_srdf
from cspace.space import ConfigurationSpace

from conftest import OpenWatch, run_cli

HERE = Path(__file__).parent.parent / "docs" / "examples"
ROBOT = HERE / "mobile_arm.urdf"
SECRET = "TOKEN-ghp-5rdf0ut"
"""A secret's stand-in: a group's name in an SRDF outside the robot's project."""


def _codes(report: cspace.Report, code: str) -> list[str]:
    return [d.message for d in report.diagnostics if d.code == code]


def test_the_srdf_beside_the_urdf_is_read_with_every_element() -> None:
    report = cspace.inspect(ROBOT, srdf=True)
    assert report.srdf is not None and report.srdf.path.endswith("mobile_arm.srdf")
    assert report.root_joint == "planar"  # the virtual joint, in place of --root-joint
    assert report.srdf.virtual_joint == "world_joint:planar"
    assert report.srdf.passive == ("root_joint",)
    groups = {name: joints for name, joints, _ in report.srdf.groups}
    arm = ("turret_joint", "shoulder", "elbow")  # a chain: the fixed mount adds none
    gripper = ("finger_left_joint", "finger_right_joint")  # links: the joints above them
    assert groups == {
        "base": ("root_joint",),
        "arm": arm,
        "gripper": gripper,
        "manipulator": arm + gripper,  # subgroups
        "whole": ("root_joint", *arm, *gripper),
    }
    assert _codes(report, "joint-passive") and _codes(report, "srdf-virtual-joint")


def test_group_states_are_checked_and_listed_as_configurations() -> None:
    report = cspace.inspect(ROBOT, srdf=True)
    (outside,) = _codes(report, "pose-out-of-limits")
    assert outside == (
        "state 'parked' of group 'whole': joint 'shoulder' is 2, outside [-1.5, 1.5] rad"
    )
    (mimic,) = _codes(report, "pose-mimic-inconsistent")
    assert "'finger_right_joint' is 0.03, but it follows 'finger_left_joint'" in mimic
    poses = {p.label: p.configuration for p in report.poses}
    names = [c.name for c in report.coordinates.entries]
    assert names == ["root_joint.x", "root_joint.y", "root_joint.theta", "turret_joint",
                     "shoulder", "elbow", "finger_left_joint"]  # fmt: skip
    assert poses["arm/home"] == pytest.approx((0, 0, 0, 3.5 - 2 * math.pi, 0.5, -1, 0))
    assert poses["whole/parked"] == pytest.approx((1, 2, 0.5, 0.9272952, 2, 0, 0.01))
    assert poses["whole/home"] == pytest.approx((0, 0, math.pi / 2, 0, 0, 0, 0))  # x y cos sin
    run = run_cli("inspect", str(ROBOT), "--srdf", "auto")
    assert (
        run.code == 1 and "poses   arm/home, gripper/open, whole/parked, whole/home" in run.stdout
    )


def test_states_agree_with_pinocchio() -> None:
    """cspace's pose, in Pinocchio's q, is what Pinocchio's SRDF reader makes of it."""
    for urdf, srdf in _erd_pairs():
        try:
            report = cspace.inspect(urdf, srdf=True)
        except cspace.RobotFileError:  # the URDF's own fault (see the test below)
            continue
        if report.srdf is None or not report.poses:
            continue
        space = ConfigurationSpace.from_report(report)
        model = cspace.pinocchio_model(urdf, report.root_joint)
        pin.loadReferenceConfigurations(model, str(srdf), False)
        names = [p.name for p in report.poses]
        for pose in report.poses:
            if pose.configuration is None or names.count(pose.name) > 1:
                continue
            ours = space.to_pinocchio(np.asarray(pose.configuration))
            theirs = model.referenceConfigurations[pose.name]
            np.testing.assert_allclose(ours, theirs, atol=1e-9, err_msg=f"{urdf}#{pose.name}")


def _erd_pairs() -> list[tuple[Path, Path]]:
    from cspace._formats.shared.erd import robots_dir

    pairs = []
    for urdf in sorted(robots_dir().rglob("*.urdf")):
        found = find_srdf(urdf)
        if found is not None:
            pairs.append((urdf, Path(found)))
    assert len(pairs) >= 25
    return pairs


def test_every_example_robot_data_srdf_is_read() -> None:
    """Each SRDF beside a URDF is read; the names that dangle are warnings, as MoveIt logs."""
    broken = set()
    for urdf, _ in _erd_pairs():
        try:
            report = cspace.inspect(urdf, srdf=True)
        except cspace.RobotFileError as exc:  # the URDF's own fault (an unknown mimic leader)
            assert "mimics joint" in str(exc), exc
            continue
        assert report.srdf is not None
        broken |= {f"{urdf.stem}:{g[0]}" for g in report.srdf.groups if g[2] is not None}
    # its chain names link 'r_foot', which the URDF lacks: the group is left empty
    assert "simple_humanoid:r_leg" in broken


def test_a_group_is_its_own_cspace_as_pinocchio_reduces_it() -> None:
    report = cspace.inspect(ROBOT, srdf=True, group="arm", hold="parked")
    assert report.manifold.notation == "R^2 × S^1" and (report.nq, report.nv) == (4, 3)
    assert report.group is not None
    held = [joint for joint, _ in report.group.held]
    assert held == ["root_joint", "finger_left_joint", "finger_right_joint"]
    assert [p.label for p in report.poses] == ["arm/home"]
    model = cspace.pinocchio_model(ROBOT, srdf=True)  # the SRDF's planar virtual joint
    assert model.names[1] == "root_joint" and model.joints[1].shortname() == "JointModelPlanar"
    locked = [model.getJointId(n) for n in held if model.existJointName(n)]
    reduced = pin.buildReducedModel(model, locked, pin.neutral(model))
    assert (reduced.nq, reduced.nv) == (report.nq, report.nv)
    q_index = {j.name: j.q_index for j in report.joints if j.q_index is not None}
    assert q_index == {reduced.names[i]: reduced.idx_qs[i] for i in range(1, reduced.njoints)}
    # passive joints are held; a mimic finger moves with its leader
    whole = cspace.inspect(ROBOT, srdf=True, group="whole")
    assert whole.group is not None and whole.group.held == (("root_joint", (0.0, 0.0, 0.0)),)
    assert whole.dimension == 4
    assert cspace.inspect(ROBOT, srdf=True, group="base").manifold.notation == "point"


def test_a_stored_pose_converts_to_every_convention() -> None:
    run = run_cli("convert", f"{ROBOT}#arm/home", "--srdf", "auto", "--to", "pinocchio")
    assert run.code == 0, run.stderr
    header, row = run.stdout.splitlines()
    assert header.split(",")[:4] == ["root_joint.x", "root_joint.y", "root_joint.theta.cos",
                                     "root_joint.theta.sin"]  # fmt: skip
    values = [float(v) for v in row.split(",")]
    assert values[4:6] == pytest.approx([math.cos(3.5), math.sin(3.5)])
    for target in ("canonical", "drake", "named"):
        assert run_cli("convert", f"{ROBOT}#arm/home", "--srdf", "auto", "--to", target).code == 0
    ambiguous = run_cli("convert", f"{ROBOT}#home", "--srdf", "auto", "--to", "canonical")
    assert ambiguous.code != 0 and "(arm/home, whole/home)" in ambiguous.stderr
    assert ambiguous.stderr.count("\n") == 1


def test_an_srdf_is_read_when_asked_for() -> None:
    assert cspace.inspect(ROBOT).srdf is None and cspace.inspect(ROBOT).root_joint is None
    named = cspace.inspect(ROBOT, srdf=HERE / "mobile_arm.srdf")
    assert named.srdf is not None and named.root_joint == "planar"
    run = run_cli("inspect", str(ROBOT), "--format", "json")
    assert run.code == 0 and '"srdf"' not in run.stdout
    clash = run_cli("inspect", str(ROBOT), "--srdf", "auto", "--root-joint", "floating")
    assert (
        clash.code != 0
        and "mobile_arm.srdf:3:" in clash.stderr
        and "srdf-virtual-joint" in clash.stderr
    )


HOSTILE = {
    "not a number": (
        '<group name="a"><joint name="elbow"/></group>'
        '<group_state name="s" group="a"><joint name="elbow" value="1e3x"/></group_state>',
        "the value '1e3x', not a number",
    ),
    "eight numbers": (
        '<group_state name="s" group="a">'
        '<joint name="elbow" value="1 2 3 4 5 6 7 8"/></group_state>',
        "more than 7 numbers; a joint takes at most 7",
    ),
    "virtual type": (
        '<virtual_joint name="v" type="ball" parent_frame="w" child_link="base_link"/>',
        "virtual joint 'v' has type 'ball'",
    ),
    "twice": ('<group name="a"/><group name="a"/>', "group 'a' is given twice"),
    "entity": ("&x;", "entit"),
    "a urdf": ('<link name="l"/>', "a URDF, not an SRDF"),
    "no name": ("<group/>", "<group> has no 'name' attribute"),
    "long name": (f'<group_state name="{"s" * 300}"/>', "<group_state> name of 300 characters"),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_srdf_files_are_refused_in_one_line(tmp_path: Path, name: str) -> None:
    body, expected = HOSTILE[name]
    head = '<!DOCTYPE r [<!ENTITY x "y">]>' if name == "entity" else ""
    srdf = tmp_path / "hostile.srdf"
    srdf.write_text(f'<?xml version="1.0"?>{head}\n<robot name="r">\n{body}\n</robot>\n')
    run = run_cli("inspect", str(ROBOT), "--srdf", str(srdf))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert "hostile.srdf" in run.stderr and expected in run.stderr, run.stderr
    # GitHub's annotation is on the SRDF, not on the URDF
    github = run_cli("inspect", str(ROBOT), "--srdf", str(srdf), "--format", "github")
    assert f"::error file={srdf}" in github.stdout, github.stdout


def test_groups_that_contain_themselves_are_not_loaded(tmp_path: Path) -> None:
    """As MoveIt: each group in a cycle is dropped (and those that include it); no more."""
    srdf = tmp_path / "cycle.srdf"
    srdf.write_text(
        '<robot name="r"><group name="a"><group name="b"/></group>'
        '<group name="b"><joint name="elbow"/><group name="a"/></group>'
        '<group name="self"><group name="self"/></group>'
        '<group name="above"><group name="a"/></group>'
        '<group name="fine"><joint name="shoulder"/></group></robot>'
    )
    report = cspace.inspect(ROBOT, srdf=srdf)
    assert report.srdf is not None
    broken = {name: why for name, _, why in report.srdf.groups if why is not None}
    assert set(broken) == {"a", "b", "self", "above"}
    assert "contains itself (a -> b -> a)" in broken["a"]
    notes = _codes(report, "srdf-ignored")
    assert any("group 'self' contains itself (self -> self)" in m for m in notes)
    refused = run_cli("inspect", str(ROBOT), "--srdf", str(srdf), "--group", "self")
    assert refused.code == 2 and "group 'self' cannot be used" in refused.stderr
    assert cspace.inspect(ROBOT, srdf=srdf, group="fine").dimension == 1
    deep = tmp_path / "deep.srdf"  # 1,000 groups each in the next: no recursion
    nested = "".join(f'<group name="g{i}"><group name="g{i + 1}"/></group>' for i in range(999))
    last = '<group name="g999"><joint name="elbow"/></group>'
    deep.write_text(f'<robot name="r">{nested}{last}</robot>')
    assert cspace.inspect(ROBOT, srdf=deep, group="g0").dimension == 1


def test_a_chain_between_branches_is_moveits(tmp_path: Path) -> None:
    """From the tip up past the shared link's joint, and from the base up to it."""
    srdf = tmp_path / "chain.srdf"
    srdf.write_text(
        '<robot name="r"><group name="back"><chain base_link="tool" tip_link="upper"/></group>'
        '<group name="across"><chain base_link="finger_left" tip_link="finger_right"/></group>'
        "</robot>"
    )
    report = cspace.inspect(ROBOT, srdf=srdf)
    assert report.srdf is not None
    groups = {name: joints for name, joints, _ in report.srdf.groups}
    assert groups["back"] == ("shoulder", "elbow")  # and the fixed tool_mount
    assert groups["across"] == ("finger_left_joint", "finger_right_joint")


def test_a_zero_quaternion_is_no_pose(tmp_path: Path) -> None:
    srdf = tmp_path / "float.srdf"
    srdf.write_text(
        '<robot name="r"><virtual_joint name="w" type="floating" parent_frame="world" '
        'child_link="base_link"/><group name="all"><joint name="w"/></group>'
        '<group_state name="zero" group="all"><joint name="w" value="1 2 3 0 0 0 0"/>'
        '</group_state><group_state name="up" group="all">'
        '<joint name="w" value="1 2 3 0 0 0 2"/></group_state></robot>'
    )
    report = cspace.inspect(ROBOT, srdf=srdf)
    assert report.root_joint == "floating"
    assert any("(0, 0, 0, 0): no rotation" in m for m in _codes(report, "pose-out-of-limits"))
    assert any("of norm 2, not 1" in m for m in _codes(report, "pose-not-unit"))
    poses = {p.name: p.configuration for p in report.poses}
    assert poses["zero"] is None and poses["up"] is not None
    assert poses["up"][:7] == pytest.approx((1, 2, 3, 1, 0, 0, 0))
    held = run_cli("inspect", str(ROBOT), "--srdf", str(srdf), "--group", "all", "--hold", "zero")
    assert held.code == 2 and "pose 'all/zero' has no configuration" in held.stderr


def test_hold_names_one_configuration() -> None:
    run = run_cli("inspect", str(ROBOT), "--srdf", "auto", "--group", "arm", "--hold", "home")
    assert run.code == 2 and "pose 'home' is several (arm/home, whole/home)" in run.stderr
    report = cspace.inspect(ROBOT, srdf=True, group="arm", hold="whole/parked")
    assert report.group is not None and report.group.held_at == "whole/parked"
    assert dict(report.group.held)["root_joint"] == pytest.approx((1, 2, 0.5))


def test_the_options_reach_every_output(tmp_path: Path) -> None:
    """--srdf, --group and --hold apply with several robots and the CI formats too."""
    args = ("--srdf", "auto", "--group", "arm", "--format", "github")
    github = run_cli("inspect", str(ROBOT), *args)
    assert "R^2 × S^1" in github.stdout, github.stdout
    both = run_cli("inspect", str(ROBOT), str(ROBOT), "--srdf", str(HERE / "mobile_arm.srdf"))
    assert both.code == 2 and "--srdf FILE goes with one robot" in both.stderr
    copy = tmp_path / "urdf"
    copy.mkdir()
    (tmp_path / "srdf").mkdir()
    (tmp_path / "package.xml").write_text("<package><name>p</name></package>")  # the project
    (copy / "mobile_arm.urdf").write_bytes(ROBOT.read_bytes())
    (tmp_path / "srdf" / "mobile_arm.srdf").write_bytes((HERE / "mobile_arm.srdf").read_bytes())
    bare = run_cli("inspect", "mobile_arm.urdf", "--srdf", "auto", "--format", "json", cwd=copy)
    assert '"virtual_joint": "world_joint:planar"' in bare.stdout  # ../srdf of a bare name


def test_hostile_values_and_names_are_findings(tmp_path: Path) -> None:
    srdf = tmp_path / "values.srdf"
    srdf.write_text(
        '<robot name="r"><group name="a"><joint name="elbow"/><joint name="nope"/></group>'
        '<group_state name="nan" group="a"><joint name="elbow" value="nan"/></group_state>'
        '<group_state name="huge" group="a"><joint name="elbow" value="1e308"/>'
        '<joint name="ghost" value="1"/></group_state>'
        '<group_state name="planar" group="nothing"/></robot>'
    )
    report = cspace.inspect(ROBOT, srdf=srdf)
    out = _codes(report, "pose-out-of-limits")
    assert any("'nan' of group 'a': joint 'elbow' is nan: not finite" in m for m in out)
    assert any("joint 'elbow' is 1e+308, outside [-2, 2] rad" in m for m in out)
    ignored = _codes(report, "srdf-ignored")
    assert any("names joint 'nope', which the robot does not have" in m for m in ignored)
    assert any("joint 'ghost', which the robot does not have" in m for m in ignored)
    assert any("of group 'nothing', which the SRDF does not define" in m for m in ignored)
    # as srdfdom, the unknown member is dropped and the group kept
    group = cspace.inspect(ROBOT, srdf=srdf, group="a").group
    assert group is not None and group.joints == ("elbow",) and group.held_at == "neutral"
    assert [joint for joint, _ in group.held] == ["turret_joint", "shoulder", "finger_left_joint",
                                                  "finger_right_joint"]  # fmt: skip
    poses = {p.name: p.configuration for p in report.poses}
    assert poses["nan"] is None and poses["huge"] is not None


def test_srdf_limits_are_counted(tmp_path: Path) -> None:
    states = "".join(f'<group_state name="s{i}" group="g"/>' for i in range(5_001))
    srdf = tmp_path / "many.srdf"
    srdf.write_text(f'<robot name="r"><group name="g"/>{states}</robot>')
    run = run_cli("inspect", str(ROBOT), "--srdf", str(srdf))
    assert run.code == 2 and "more than 5,000 group states" in run.stderr
    outside = tmp_path / "link.srdf"
    outside.symlink_to("/etc/passwd")
    run = run_cli("inspect", str(ROBOT), "--srdf", str(outside))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "root:" not in run.stderr
    mjcf = run_cli("inspect", "tests/findings/keyframe_outside.xml", "--srdf", str(srdf))
    assert mjcf.code == 2 and "an SRDF goes with a URDF" in mjcf.stderr


def test_check_fails_on_a_state_outside_the_space() -> None:
    args = ("check", str(ROBOT), "--srdf", "auto", "--expect", "R^5 × T^2", "--dimension", "7")
    failed = run_cli(*args)
    assert failed.code == 1 and "state 'parked' of group 'whole'" in failed.stderr
    assert run_cli(*args, "--ignore", "pose-out-of-limits").code == 0
    group = run_cli("check", str(ROBOT), "--srdf", "auto", "--group", "arm", "--expect",
                    "R^2 × S^1", "--ignore", "pose-out-of-limits")  # fmt: skip
    assert group.code == 0 and "dimension 3" in group.stdout


def test_what_neither_tool_reads_is_no_pose(tmp_path: Path) -> None:
    """A continuous joint's cos-sin pair (Pinocchio and MoveIt take one angle), a number
    written with an underscore, a state of a group MoveIt does not load."""
    srdf = tmp_path / "forms.srdf"
    srdf.write_text(
        '<robot name="r"><group name="a"><joint name="turret_joint"/></group>'
        '<group name="b"><group name="missing"/></group>'
        '<group_state name="pair" group="a"><joint name="turret_joint" value="0.6 0.8"/>'
        '</group_state><group_state name="late" group="b">'
        '<joint name="turret_joint" value="9"/></group_state></robot>'
    )
    report = cspace.inspect(ROBOT, srdf=srdf)
    (wrong,) = [d for d in report.diagnostics if d.code == "pose-out-of-limits"]
    assert "takes 1 number(s), not 2" in wrong.message and wrong.line == 1
    assert wrong.file == str(srdf)  # the SRDF's line, in the SRDF
    assert {p.name: p.configuration for p in report.poses} == {"pair": None}
    assert any(
        "of group 'b', which MoveIt does not load" in m for m in _codes(report, "srdf-ignored")
    )
    github = run_cli("inspect", str(ROBOT), "--srdf", str(srdf), "--format", "github")
    assert f"::error file={srdf},line=1,title=cspace pose-out-of-limits::" in github.stdout
    sarif = run_cli("inspect", str(ROBOT), "--srdf", str(srdf), "--format", "sarif")
    assert '"uri": "' in sarif.stdout and "forms.srdf" in sarif.stdout
    srdf.write_text(
        '<robot name="r"><group name="a"><joint name="elbow"/></group>'
        '<group_state name="s" group="a"><joint name="elbow" value="-1_0"/></group_state></robot>'
    )
    run = run_cli("inspect", str(ROBOT), "--srdf", str(srdf))
    assert run.code == 2 and "the value '-1_0', not a number" in run.stderr


def test_many_states_of_a_large_robot_stay_bounded(tmp_path: Path) -> None:
    """States x coordinates is bounded: past 1,000,000 numbers, states are listed bare."""
    joints = "".join(
        f'<link name="l{i}"/><joint name="j{i}" type="continuous"><parent link="base"/>'
        f'<child link="l{i}"/></joint>'
        for i in range(1_000)
    )
    urdf = tmp_path / "star.urdf"
    urdf.write_text(f'<robot name="star"><link name="base"/>{joints}</robot>')
    states = "".join(
        f'<group_state name="s{i}"><joint name="j{i % 1000}" value="0.1"/></group_state>'
        for i in range(1_500)
    )
    every = '<group name="all">' + "".join(f'<link name="l{i}"/>' for i in range(1_000))
    every += "</group>" + "".join(
        f'<group name="g{i}"><group name="all"/></group>' for i in range(99)
    )
    srdf = tmp_path / "star.srdf"
    srdf.write_text(f'<robot name="star">{every}{states}</robot>')
    report = cspace.inspect(urdf, srdf=srdf)
    listed = [p for p in report.poses if p.configuration is not None]
    assert len(report.poses) == 1_500 and len(listed) == 250  # 250,000 numbers
    (note,) = _codes(report, "poses-not-checked")
    assert note.startswith("1,250 group states listed without their configuration")
    saved = tmp_path / "star.json"  # the report at the bound reads back
    saved.write_text(run_cli("inspect", str(urdf), "--srdf", str(srdf), "--format", "json").stdout)
    assert run_cli("diff", str(saved), str(urdf), "--srdf", str(srdf)).code == 0
    # 100 groups of 1,000 joints: the report lists 50,000 members, --group reads them all
    assert report.srdf is not None
    assert sum(len(joints) for _, joints, _ in report.srdf.groups) == 50_000
    assert any("50 groups listed without their joints" in m for m in _codes(report, "srdf-ignored"))
    assert cspace.inspect(urdf, srdf=srdf, group="g98").dimension == 1_000


def test_a_saved_group_report_is_read_back(tmp_path: Path) -> None:
    """diff, check and sample take the group as inspect does; a saved report round-trips."""
    saved = tmp_path / "arm.json"
    run = run_cli("inspect", str(ROBOT), "--srdf", "auto", "--group", "arm", "--format", "json")
    saved.write_text(run.stdout)
    report = cspace.inspect(ROBOT, srdf=True, group="arm")
    assert cspace.Report.from_dict(json.loads(run.stdout)) == report
    same = run_cli("diff", str(saved), str(ROBOT), "--srdf", "auto", "--group", "arm")
    assert same.code == 0 and same.stdout.startswith("no C-space change: R^2 × S^1")
    check = run_cli("check", str(saved), "--expect", "R^2 × S^1", "--ignore", "pose-out-of-limits")
    assert check.code == 0, check.stderr
    sample = run_cli("sample", str(ROBOT), "--srdf", "auto", "--group", "arm", "-n", "2",
                     "--format", "csv")  # fmt: skip
    assert sample.code == 0 and sample.stdout.splitlines()[0] == "turret_joint,shoulder,elbow"
    space = cspace.load(ROBOT, srdf=True, group="arm")
    assert space.names == ("turret_joint", "shoulder", "elbow")


def test_a_pose_named_with_a_hash_and_an_erd_robot(tmp_path: Path) -> None:
    srdf = tmp_path / "hash.srdf"
    srdf.write_text(
        '<robot name="r"><group name="a"><joint name="elbow"/></group>'
        '<group_state name="x#1" group="a"><joint name="elbow" value="0.5"/></group_state></robot>'
    )
    run = run_cli("convert", f"{ROBOT}#a/x#1", "--srdf", str(srdf), "--to", "canonical")
    header, row = run.stdout.splitlines()
    assert (
        run.code == 0
        and dict(zip(header.split(","), row.split(","), strict=True))["elbow"] == "0.5"
    )
    # example-robot-data names an SRDF after the robot: ur5.srdf for ur5_robot.urdf
    talos = cspace.inspect("erd:talos", srdf=True)
    assert talos.srdf is not None and talos.srdf.path.endswith("talos.srdf")
    assert [p.label for p in talos.poses] == ["all/half_sitting"]


def test_joints_moveit_lacks_take_pinocchios_numbers(tmp_path: Path) -> None:
    """A ball joint's qx qy qz qw, a universal joint's two angles, a planar joint's x y cos
    sin: as Pinocchio's loadReferenceConfigurations reads them on cspace's own model."""
    robot = Path(__file__).parent.parent / "docs" / "examples" / "drake_joints.urdf"
    srdf = tmp_path / "drake_joints.srdf"
    srdf.write_text(
        '<robot name="r"><group_state name="s">'
        '<joint name="base_plane" value="1 2 0 1"/><joint name="shoulder" value="0 0.6 0 0.8"/>'
        '<joint name="wrist" value="0.1 0.2"/><joint name="finger" value="0.5"/>'
        "</group_state></robot>"
    )
    report = cspace.inspect(robot, srdf=srdf)
    (pose,) = report.poses
    assert pose.configuration is not None
    space = ConfigurationSpace.from_report(report)
    ours = space.to_pinocchio(np.asarray(pose.configuration))
    model = cspace.pinocchio_model(robot)
    pin.loadReferenceConfigurations(model, str(srdf), False)
    np.testing.assert_allclose(ours, model.referenceConfigurations["s"], atol=1e-12)


def test_a_state_or_a_value_given_twice_is_read_as_the_tools_read_it(tmp_path: Path) -> None:
    """Pinocchio keeps a state's first definition and a joint's last value; cspace too."""
    srdf = tmp_path / "twice.srdf"
    srdf.write_text(
        '<robot name="r"><group name="a"><joint name="elbow"/></group>\n'
        '<group_state name="s" group="a"><joint name="elbow" value="0.1"/>'
        '<joint name="elbow" value="0.2"/></group_state>\n'
        '<group_state name="s" group="a"><joint name="elbow" value="0.3"/></group_state>\n'
        "</robot>"
    )
    report = cspace.inspect(ROBOT, srdf=srdf)
    (pose,) = report.poses
    elbow = [c.name for c in report.coordinates.entries].index("elbow")
    assert pose.configuration is not None and pose.configuration[elbow] == 0.2
    notes = [(d.line, d.message) for d in report.diagnostics if d.code == "srdf-ignored"]
    assert notes == [
        (2, "state 's' gives joint 'elbow' twice: the last value is read"),
        (3, "group state 'a/s' is given twice (first on line 2): this one is skipped"),
    ]
    model = cspace.pinocchio_model(ROBOT)
    pin.loadReferenceConfigurations(model, str(srdf), False)
    assert model.referenceConfigurations["s"][model.idx_qs[model.getJointId("elbow")]] == 0.2


def test_every_output_puts_an_srdf_finding_in_the_srdf(tmp_path: Path) -> None:
    html = run_cli("inspect", str(ROBOT), "--srdf", "auto", "--format", "html")
    assert "pose-out-of-limits (mobile_arm.srdf:34): state" in html.stdout
    check = run_cli("check", str(ROBOT), "--srdf", "auto", "--expect", "R^5 × T^2")
    assert (
        check.code == 1
        and f"mobile_arm.urdf: {HERE / 'mobile_arm.srdf'}:34: state 'parked'" in check.stderr
    )


def test_auto_looks_only_inside_the_robots_project(tmp_path: Path) -> None:
    """--srdf auto: NAME.srdf beside the URDF or in ../srdf/, only inside the URDF's project
    (links followed) or an --allow-dir folder, as MJCF includes; an SRDF outside it is
    neither opened nor named (issue 37)."""
    project, outside = tmp_path / "proj", tmp_path / "srdf"
    (project / "urdf").mkdir(parents=True)
    outside.mkdir()
    (project / "package.xml").write_text("<package><name>p</name></package>")
    for urdf in (project / "mobile_arm.urdf", project / "urdf" / "mobile_arm.urdf"):
        urdf.write_bytes(ROBOT.read_bytes())
    srdf = (
        (HERE / "mobile_arm.srdf")
        .read_text()
        .replace('<group name="base">', f'<group name="{SECRET}">')
    )
    (outside / "mobile_arm.srdf").write_text(srdf)
    (project / "srdf").symlink_to(outside)  # in the project, a link out of it
    watch = OpenWatch(outside)
    robots = ("proj/mobile_arm.urdf", "proj/urdf/mobile_arm.urdf")  # ../srdf: out; srdf/: a link
    run = run_cli("inspect", *robots, "--srdf", "auto", "--format", "jsonl", cwd=tmp_path)
    assert watch.opened() == [], "an SRDF outside the project was opened"
    watch.close()
    documents = [json.loads(line) for line in run.stdout.splitlines()]
    assert len(documents) == 2 and all("srdf" not in d for d in documents), run.stderr
    assert SECRET not in run.stdout + run.stderr and "srdf" not in run.stderr.lower()
    allowed = run_cli(
        "inspect", robots[0], "--srdf", "auto", "--allow-dir", "srdf", "--format", "json",
        cwd=tmp_path,
    )  # fmt: skip
    assert json.loads(allowed.stdout)["srdf"]["path"] == "proj/../srdf/mobile_arm.srdf"
