"""MJCF, SDF, xacro and erd:NAME: each read to the same report as URDF, from real files."""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import pinocchio as pin
import pytest

import cspace
from cspace._formats.shared.erd import ERD_ROBOTS, resolve
from cspace._formats.xacro.expand import XacroOptions

from conftest import ROBOTS, Run, run_cli

MJCF = ROBOTS / "mjcf_every_joint.xml"
MJCF_RADIAN = ROBOTS / "mjcf_radian_autolimits.xml"
SDF = ROBOTS / "sdf_every_joint.sdf"
XACRO = ROBOTS / "xacro_demo" / "urdf" / "arm.urdf.xacro"


def joints(report: cspace.Report) -> dict[str, cspace.JointReport]:
    return {j.name: j for j in report.joints}


def kinds_and_spaces(report: cspace.Report) -> list[tuple[str, str, str]]:
    return [(j.name, j.kind.value, j.space.notation) for j in report.joints]


# --- MJCF ---------------------------------------------------------------------------


def test_mjcf_every_joint_kind_in_pinocchio_order() -> None:
    report = cspace.inspect(str(MJCF))
    assert report.source.format == "mjcf"
    assert kinds_and_spaces(report) == [
        ("base_free", "floating", "R^3 × RP^3"),
        ("shoulder_yaw", "revolute", "R^1"),
        ("elbow", "revolute", "R^1"),  # its range comes from a <default> class
        ("forearm_spin", "continuous", "S^1"),  # a hinge without a range
        ("wrist_roll", "revolute", "R^1"),
        ("wrist_slide", "prismatic", "R^1"),
        ("flange_fixed", "fixed", "point"),  # a body without a joint is welded
        ("tool_ball", "spherical", "R^3"),  # a ball with a range: a 3-ball, not SO(3)
        ("head_ball", "spherical", "RP^3"),
    ]
    assert report.manifold.notation == "R^10 × S^1 × (RP^3)^2"
    assert report.dimension == 17


def test_mjcf_sizes_and_layout_are_pinocchios() -> None:
    report = cspace.inspect(str(MJCF))
    model = pin.buildModelFromMJCF(str(MJCF))
    assert (report.nq, report.nv) == (model.nq, model.nv)
    by_name = joints(report)
    for index in range(1, model.njoints):
        name = str(model.names[index])
        if name in by_name:
            assert by_name[name].q_index == model.joints[index].idx_q
            assert by_name[name].nq == model.joints[index].nq


def test_mjcf_body_with_two_joints_is_two_joints_in_mujocos_order() -> None:
    report = cspace.inspect(str(MJCF))
    roll, slide = joints(report)["wrist_roll"], joints(report)["wrist_slide"]
    assert (roll.pinocchio_model, slide.pinocchio_model) == ("JointModelRX", "JointModelPX")
    assert (roll.q_index, roll.nq, slide.q_index, slide.nq) == (10, 1, 11, 1)
    assert (roll.qposadr, slide.qposadr) == (10, 11)  # MuJoCo's jnt_qposadr
    assert roll.parent_link == slide.parent_link == "forearm"
    assert roll.child_link == slide.child_link == "wrist"
    # In Pinocchio, a chain: the slide acts after the roll, the body after both.
    model = cspace.pinocchio_model(MJCF)
    ids = {str(model.names[i]): i for i in range(model.njoints)}
    assert model.parents[ids["wrist_slide"]] == ids["wrist_roll"]
    assert (
        model.frames[model.getFrameId("wrist", pin.FrameType.BODY)].parentJoint
        == (ids["wrist_slide"])
    )


def test_mjcf_angles_are_degrees_by_default_and_radians_when_asked() -> None:
    degrees = joints(cspace.inspect(str(MJCF)))
    assert degrees["shoulder_yaw"].limits is not None
    assert degrees["shoulder_yaw"].limits.upper[0] == pytest.approx(math.pi / 2)
    assert degrees["elbow"].limits is not None
    assert degrees["elbow"].limits.upper[0] == pytest.approx(math.radians(150))
    # A slide's range is a length: never converted.
    assert degrees["wrist_slide"].limits is not None
    assert degrees["wrist_slide"].limits.upper == (0.05,)
    assert degrees["wrist_slide"].limits.unit == "m"
    # The ball's cone: "0 30" degrees.
    assert degrees["tool_ball"].limits is not None
    assert degrees["tool_ball"].limits.upper[0] == pytest.approx(math.radians(30))
    radians = cspace.inspect(str(MJCF_RADIAN))
    assert [j.kind.value for j in radians.joints] == ["revolute", "continuous", "prismatic"]
    assert joints(radians)["j1"].limits is not None
    assert joints(radians)["j1"].limits.upper == (1.5,)
    assert radians.manifold.notation == "R^2 × S^1"


def _mjcf(tmp_path: Path, body: str, compiler: str = "") -> Path:
    """An MJCF file; every body gets a small sphere (MuJoCo refuses massless moving bodies)."""
    body = re.sub(r"(<body[^>]*>)", r'\1<geom size="0.05"/>', body)
    path = tmp_path / "robot.xml"
    path.write_text(f'<mujoco model="t">{compiler}<worldbody>{body}</worldbody></mujoco>')
    return path


def test_mjcf_range_without_limited_under_autolimits_false_is_refused(tmp_path: Path) -> None:
    path = _mjcf(
        tmp_path,
        '<body name="a"><joint name="j" range="-1 1"/></body>',
        '<compiler autolimits="false"/>',
    )
    run = run_cli("inspect", str(path))
    assert run.code == 2
    # MuJoCo's own reason, with its line.
    assert f"{path}:1: MuJoCo refuses the model: " in run.stderr
    assert "autolimits" in run.stderr and run.stderr.rstrip().endswith("[mujoco-refused]")
    assert run.stderr.count("\n") == 1 and "Traceback" not in run.stderr


def test_mjcf_autolimits_default_makes_a_range_a_limit(tmp_path: Path) -> None:
    path = _mjcf(tmp_path, '<body name="a"><joint name="j" range="-1 1"/></body>')
    assert cspace.inspect(str(path)).manifold.notation == "R^1"
    path = _mjcf(tmp_path, '<body name="a"><joint name="j" limited="false" range="-1 1"/></body>')
    assert cspace.inspect(str(path)).manifold.notation == "S^1"


@pytest.mark.parametrize(
    ("range_", "angle", "space", "whole"),
    [
        ("0 30", "degree", "R^3", False),  # a cone of rotations: a 3-ball
        ("0 179", "degree", "R^3", False),
        ("0 180", "degree", "RP^3", True),  # no rotation exceeds pi: nothing excluded
        ("0 200", "degree", "RP^3", True),
        ("0 4", "radian", "RP^3", True),
    ],
)
def test_mjcf_ball_range_of_pi_or_more_limits_nothing(
    range_: str, angle: str, space: str, whole: bool, tmp_path: Path
) -> None:
    path = tmp_path / "ball.xml"
    path.write_text(
        f'<mujoco><compiler angle="{angle}"/><worldbody><body name="b">'
        f'<joint name="ball" type="ball" range="{range_}"/><geom size="0.1"/>'
        "</body></worldbody></mujoco>"
    )
    report = cspace.inspect(str(path))
    assert report.manifold.notation == space
    assert ("ball-range-whole" in {d.code for d in report.diagnostics}) is whole
    assert cspace.load(str(path)).dimension == 3


def test_mjcf_childclass_defaults_apply_to_nested_joints(tmp_path: Path) -> None:
    path = tmp_path / "robot.xml"
    path.write_text(
        '<mujoco model="t"><default><default class="slider">'
        '<joint type="slide" range="0 1"/><geom size="0.1"/></default></default>'
        '<worldbody><body name="a" childclass="slider"><joint name="j1"/><geom/>'
        '<body name="b"><joint name="j2" type="hinge"/><geom/></body></body></worldbody></mujoco>'
    )
    report = cspace.inspect(str(path))
    assert kinds_and_spaces(report) == [
        ("j1", "prismatic", "R^1"),
        ("j2", "revolute", "R^1"),  # type overridden, range inherited (0..1 degrees)
    ]
    assert joints(report)["j2"].limits is not None
    assert joints(report)["j2"].limits.upper[0] == pytest.approx(math.radians(1))


def test_mjcf_unknown_default_class_is_an_error(tmp_path: Path) -> None:
    path = _mjcf(tmp_path, '<body name="a"><joint name="j" class="nope"/></body>')
    run = run_cli("inspect", str(path))
    assert run.code == 2
    assert f"{path}:1: MuJoCo refuses the model: XML Error: unknown default class name 'nope'" in (
        run.stderr
    )


def test_mjcf_several_top_level_bodies_and_unnamed_bodies_are_read(tmp_path: Path) -> None:
    two_roots = _mjcf(
        tmp_path,
        '<body name="a"><joint name="j1"/></body><body name="b"><joint name="j2"/></body>',
    )
    report = cspace.inspect(two_roots)
    assert [(j.name, j.parent_link) for j in report.joints] == [("j1", "world"), ("j2", "world")]
    assert report.manifold.notation == "T^2"
    unnamed = _mjcf(tmp_path, '<body name="a"><joint name="j1"/><body><joint/></body></body>')
    report = cspace.inspect(unnamed)
    assert [j.name for j in report.joints] == ["j1", "body2Joint_0"]
    made_up = [d for d in report.diagnostics if d.code == "name-made-up"]
    assert len(made_up) == 1 and "body2, body2Joint_0" in made_up[0].message


def test_mjcf_unnamed_joints_take_pinocchios_names(tmp_path: Path) -> None:
    path = _mjcf(tmp_path, '<body name="a"><joint/><joint type="slide"/></body>')
    report = cspace.inspect(str(path))
    assert [j.name for j in report.joints] == ["aJoint_0", "aJoint_1"]
    assert report.manifold.notation == "R^1 × S^1"


def test_mjcf_from_standard_input_matches_the_file() -> None:
    from_file = run_cli("inspect", "--format", "json", str(MJCF))
    from_stdin = run_cli("inspect", "--format", "json", "-", stdin=MJCF.read_bytes())
    assert from_file.code == from_stdin.code == 0
    assert from_stdin.stdout == from_file.stdout.replace(f'"path": "{MJCF}"', '"path": "-"')


def test_mjcf_root_joint_option(tmp_path: Path) -> None:
    path = _mjcf(tmp_path, '<body name="a"><joint name="j" range="-1 1"/></body>')
    report = cspace.inspect(str(path), root_joint="planar")
    assert report.manifold.notation == "R^3 × S^1"
    assert report.joints[0].name == "root_joint"


# --- SDF ------------------------------------------------------------------------------


def test_sdf_every_joint_kind() -> None:
    report = cspace.inspect(str(SDF))
    assert report.source.format == "sdf"
    assert kinds_and_spaces(report) == [
        ("world_to_base", "fixed", "point"),
        ("j1_revolute", "revolute", "R^1"),
        ("j2_revolute_unlimited", "continuous", "S^1"),
        ("j3_continuous", "continuous", "S^1"),
        ("j4_prismatic", "prismatic", "R^1"),
        ("j5_ball", "spherical", "RP^3"),
        ("j6_universal", "universal", "R^2"),
        ("j7_screw", "helical", "R^1"),
        ("j8_tool", "fixed", "point"),
    ]
    assert report.manifold.notation == "R^5 × T^2 × RP^3"
    # Pinocchio's layout: a continuous joint keeps (cos, sin), a ball a quaternion.
    by_name = joints(report)
    assert (by_name["j2_revolute_unlimited"].nq, by_name["j2_revolute_unlimited"].nv) == (2, 1)
    assert (by_name["j5_ball"].nq, by_name["j5_ball"].nv) == (4, 3)
    assert (report.nq, report.nv) == (13, 10)


def _sdf(tmp_path: Path, joint: str) -> Path:
    path = tmp_path / "robot.sdf"
    bolted = '<joint name="bolted" type="fixed"><parent>world</parent><child>a</child></joint>'
    path.write_text(
        f'<sdf version="1.7"><model name="m"><link name="a"/><link name="b"/>{bolted}{joint}'
        "</model></sdf>"
    )
    return path


def test_sdf_gearbox_and_half_limited_universal_are_refused_clearly(tmp_path: Path) -> None:
    gearbox = _sdf(
        tmp_path, '<joint name="g" type="gearbox"><parent>a</parent><child>b</child></joint>'
    )
    run = run_cli("inspect", str(gearbox))
    assert run.code == 2 and "gearbox" in run.stderr
    half = _sdf(
        tmp_path,
        '<joint name="u" type="universal"><parent>a</parent><child>b</child>'
        "<axis><xyz>1 0 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis>"
        "<axis2><xyz>0 1 0</xyz></axis2></joint>",
    )
    run = run_cli("inspect", str(half))
    assert run.code == 2 and "limits only some of its two axes" in run.stderr


def test_sdf_unlimited_universal_is_a_torus(tmp_path: Path) -> None:
    path = _sdf(
        tmp_path, '<joint name="u" type="universal"><parent>a</parent><child>b</child></joint>'
    )
    assert cspace.inspect(str(path)).manifold.notation == "T^2"


# --- format detection -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "name", "fmt"),
    [
        (ROBOTS / "arm7.urdf", "robot.xml", "urdf"),
        (MJCF, "robot.urdf", "mjcf"),
        (SDF, "robot.xml", "sdf"),
    ],
)
def test_format_comes_from_the_content(source: Path, name: str, fmt: str, tmp_path: Path) -> None:
    folder = tmp_path / "pkg"
    shutil.copytree(ROBOTS / "xacro_demo" if source == XACRO else source.parent, folder)
    renamed = (folder / "urdf" if source == XACRO else folder) / name
    shutil.copy(source, renamed)
    report = cspace.inspect(str(renamed))
    assert report.source.format == fmt


def test_xacro_content_under_another_name_is_expanded_only_when_asked(tmp_path: Path) -> None:
    folder = tmp_path / "pkg"
    shutil.copytree(ROBOTS / "xacro_demo", folder)
    renamed = folder / "urdf" / "robot.urdf"
    shutil.copy(XACRO, renamed)
    with pytest.raises(cspace.errors.XacroNotRequestedError) as refused:
        cspace.inspect(renamed)
    assert refused.value.code == "xacro-not-requested"
    assert refused.value.line is not None
    assert cspace.inspect(renamed, force_xacro=True).source.format == "xacro"
    run = run_cli("inspect", str(renamed))
    assert run.code == 2 and run.stderr.rstrip().endswith("[xacro-not-requested]")
    assert run_cli("inspect", "--xacro", str(renamed)).code == 0


# --- xacro ----------------------------------------------------------------------------


def test_xacro_expands_includes_macros_find_and_arguments() -> None:
    report = cspace.inspect(str(XACRO))
    assert report.source.format == "xacro"
    assert kinds_and_spaces(report) == [
        ("shoulder", "revolute", "R^1"),
        ("elbow", "revolute", "R^1"),
        ("wrist", "revolute", "R^1"),
        ("finger", "prismatic", "R^1"),
    ]
    continuous = cspace.inspect(str(XACRO), xacro=XacroOptions(args={"wrist": "continuous"}))
    assert continuous.manifold.notation == "R^3 × S^1"
    run = run_cli("inspect", str(XACRO), "--arg", "wrist:=continuous")
    assert run.code == 0 and "C = R^3 × S^1" in run.stdout


def test_xacro_package_path_finds_a_package_elsewhere(tmp_path: Path) -> None:
    # The xacro files, without the package.xml above them: $(find) fails...
    lone = tmp_path / "lone"
    shutil.copytree(XACRO.parent, lone)
    run = run_cli("inspect", str(lone / "arm.urdf.xacro"))
    assert run.code == 2
    assert "cspace_xacro_demo" in run.stderr and "--package-path" in run.stderr
    # ...until --package-path names a folder that holds the package.
    run = run_cli("inspect", str(lone / "arm.urdf.xacro"), "--package-path", str(ROBOTS))
    assert run.code == 0, run.stderr
    assert "C = R^4" in run.stdout


def test_xacro_bad_argument_syntax_is_a_usage_error() -> None:
    run = run_cli("inspect", str(XACRO), "--arg", "wrist=continuous")
    assert run.code == 2
    assert "NAME:=VALUE" in run.stderr


def test_xacro_reports_have_no_line_numbers_of_the_expansion() -> None:
    report = cspace.inspect(str(XACRO))
    assert all(j.line is None for j in report.joints)


# --- example-robot-data by name -------------------------------------------------------


def test_erd_name_uses_the_packages_floating_base() -> None:
    talos = cspace.inspect("erd:talos")
    path, root = resolve("talos")
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    assert root == "floating"
    assert talos.root_joint == "floating"
    assert talos.source.path == "erd:talos"
    assert talos.dimension == model.nv
    panda = cspace.inspect("erd:panda")
    assert panda.root_joint is None


def test_erd_names_all_point_at_installed_files() -> None:
    for name in ERD_ROBOTS:
        path, _ = resolve(name)
        assert path.is_file(), name


def test_erd_unknown_name_lists_the_known_ones() -> None:
    run = run_cli("inspect", "erd:no_such_robot")
    assert run.code == 2
    assert "talos" in run.stderr and "no_such_robot" in run.stderr


# --- MJCF includes --------------------------------------------------------------------


def test_mjcf_scene_that_includes_the_robot() -> None:
    scene = cspace.inspect(str(ROBOTS / "mjcf_include" / "scene.xml"))
    alone = cspace.inspect(str(ROBOTS / "mjcf_include" / "arm.xml"))
    assert kinds_and_spaces(scene) == kinds_and_spaces(alone)
    assert scene.manifold.notation == "R^2 × S^1"
    assert (scene.nq, scene.nv) == (alone.nq, alone.nv) == (3, 3)


def test_mjcf_include_inside_a_body_and_nested(tmp_path: Path) -> None:
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "finger.xml").write_text(
        '<mujoco><body name="finger"><joint name="slide" type="slide" range="0 1"/>'
        '<geom size="1"/>'
        '<include file="parts/tip.xml"/></body></mujoco>'
    )
    (tmp_path / "parts" / "tip.xml").write_text(
        '<mujoco><body name="tip"><joint name="tip_ball" type="ball"/><geom size="1"/></body>'
        "</mujoco>"
    )
    main = _mjcf(
        tmp_path, '<body name="palm"><joint name="wrist"/><include file="parts/finger.xml"/></body>'
    )
    assert kinds_and_spaces(cspace.inspect(str(main))) == [
        ("wrist", "continuous", "S^1"),
        ("slide", "prismatic", "R^1"),
        ("tip_ball", "spherical", "RP^3"),
    ]


def test_mjcf_bad_includes_are_clear_errors(tmp_path: Path) -> None:
    looping = tmp_path / "loop.xml"
    looping.write_text('<mujoco><include file="loop.xml"/></mujoco>')
    run = run_cli("inspect", str(looping))
    assert run.code == 2 and "includes itself" in run.stderr
    missing = _mjcf(tmp_path, '<include file="nowhere.xml"/>')
    run = run_cli("inspect", str(missing))
    assert run.code == 2 and 'robot.xml:1: <include file="nowhere.xml">: no such file' in run.stderr
    run = run_cli("inspect", "-", stdin=(ROBOTS / "mjcf_include" / "scene.xml").read_bytes())
    assert run.code == 2 and "not standard input" in run.stderr


# Two files of example-robot-data that cspace refuses, each for a reason of its own:
# cassie's SDF closes loops through gearbox joints; alex_psyonic_hands mimics a joint
# name that its file does not have.
ERD_REFUSED = {
    "cassie": "is a gearbox",
    "alex_psyonic_hands": "mimics joint 'index_q1', which does not exist",
}


def test_every_erd_robot_in_one_multi_file_run() -> None:
    names = [f"erd:{n}" for n in ERD_ROBOTS]
    run = run_cli("inspect", "--format", "jsonl", *names, timeout=300)
    assert run.code == 2  # the refused ones
    documents = [json.loads(line) for line in run.stdout.splitlines()]
    reported = {d["source"]["path"][len("erd:") :]: d for d in documents}
    assert set(reported) == set(ERD_ROBOTS) - set(ERD_REFUSED)
    for name, document in reported.items():
        _, root = resolve(name)
        assert document["root_joint"] == root, name
        first = document["joints"][0]
        assert (first["name"] == "root_joint") is (root == "floating"), name
        if root == "floating":
            assert (first["kind"], first["manifold"]) == ("floating", "R^3 × RP^3")
    for name, reason in ERD_REFUSED.items():
        assert f"erd:{name}" in run.stderr and reason in run.stderr
    # Legged robots float: a quadruped is SE(3) × its 12 joints.
    assert reported["solo12"]["manifold"]["notation"] == "R^15 × RP^3"


def test_sdf_revolute_bounded_on_one_side_is_an_interval(tmp_path: Path) -> None:
    path = _sdf(
        tmp_path,
        '<joint name="r" type="revolute"><parent>a</parent><child>b</child>'
        "<axis><xyz>0 0 1</xyz><limit><lower>-1</lower></limit></axis></joint>",
    )
    report = cspace.inspect(str(path))
    assert report.manifold.notation == "R^1"
    (joint,) = [j for j in report.joints if j.name == "r"]
    assert joint.limits is not None
    assert joint.limits.lower == (-1.0,)
    assert joint.limits.upper == (1e16,)  # SDF's default upper bound


def test_urdf_that_xacro_generated_is_urdf(tmp_path: Path) -> None:
    # xacro's output keeps the xmlns:xacro declaration; nothing in it is xacro.
    path = tmp_path / "generated.urdf"
    path.write_text(
        '<robot name="g" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="a"/>'
        '<link name="b"/><joint name="j" type="continuous"><parent link="a"/>'
        '<child link="b"/><axis xyz="0 0 1"/></joint></robot>'
    )
    assert cspace.inspect(str(path)).source.format == "urdf"
    path.write_text(path.read_text().replace("www.ros.org", "ros.org"))  # the older URI
    assert cspace.inspect(str(path)).source.format == "urdf"
    # An attribute substitution makes it xacro, whatever the declaration: refused
    # unless asked for (xacro runs code), never read as plain URDF.
    path.write_text(
        '<robot name="g" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<link name="a"/><link name="${n}"/>'
        '<joint name="j" type="continuous"><parent link="a"/><child link="${n}"/>'
        '<axis xyz="0 0 1"/></joint></robot>'
    )
    held = "attribute 'name' of <link> still holds the substitution"
    with pytest.raises(cspace.errors.XacroNotRequestedError, match=held):
        cspace.inspect(str(path))
    path.write_text(
        '<robot name="g" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:property name="n" value="b"/><link name="a"/><link name="${n}"/>'
        '<joint name="j" type="continuous"><parent link="a"/><child link="${n}"/>'
        '<axis xyz="0 0 1"/></joint></robot>'
    )
    report = cspace.inspect(str(path), force_xacro=True)
    assert report.source.format == "xacro"
    assert report.joints[0].child_link == "b"


_BOMS = {"utf-16-le-bom": b"\xff\xfe", "utf-16-be-bom": b"\xfe\xff"}


def test_pinocchio_is_given_links_and_joints_and_the_tree_is_left_as_it_was(
    tmp_path: Path,
) -> None:
    # The document for Pinocchio's parser is the tree serialised in one call with the
    # rest taken out: no <gazebo> or top-level <material>, no version attribute (urdfdom
    # refuses version 2.0), no <mimic> the report ignores, numbers urdfdom would refuse
    # rewritten. Afterwards the reader's tree is exactly as parsed.
    from lxml import etree

    from cspace._formats.shared.xmlio import parse_xml, read_source
    from cspace._formats.urdf.reader import read_urdf

    path = tmp_path / "robot.urdf"
    path.write_text(
        '<robot name="r" version="2.0" xmlns:xacro="http://www.ros.org/wiki/xacro"'
        ' xmlns:a="u" xmlns:b="u" b:x="1" a:y="2">\n'
        "  <!-- a comment -->\n"
        '  <material name="m"><color rgba="x y"/></material>\n'
        '  <link name="a"/><link name="b"/><link name="c"/>\n'
        '  <gazebo reference="a"><junk/></gazebo>\n'
        '  <joint name="f" type="floating"><parent link="a"/><child link="b"/></joint>\n'
        '  <joint name="k" type="revolute"><parent link="b"/><child link="c"/>\n'
        '    <limit lower="-1" upper="1" effort="-5" velocity="1"/><mimic joint="f"/>\n'
        "  </joint>\n"
        "</robot>\n"
    )
    root = parse_xml(read_source(str(path)))
    before = etree.tostring(root)
    document = read_urdf(str(path), root, path.read_text()).recipe.text
    assert etree.tostring(root) == before
    for left_out in ("gazebo", "material", "version", "mimic", 'effort="-5"'):
        assert left_out not in document, left_out
    assert 'effort="5.0"' in document and document.count("<joint ") == 2
    report = cspace.inspect(str(path))
    assert report.nq == 8  # the floating joint's 7 and k's own: no mimic
    codes = {d.code for d in report.diagnostics}
    assert {"mimic-ignored", "number-invalid"} <= codes
    assert pin.buildModelFromXML(document, mimic=True).nq == 8


@pytest.mark.parametrize(
    ("body", "encoding", "held"),
    [
        # A substitution spelt with a character reference: no "${" in the bytes.
        ('<link name="a"/><link name="&#36;{n}"/>', "utf-8", "'${n}'"),
        ('<link name="a"/><link name="&#x24;(find p)"/>', "utf-8", "'$(find p)'"),
        # xacro's namespace spelt with character references.
        (
            '<x:property xmlns:x="http&#58;//www.ros.org/wiki/xacro" name="n" value="b"/>'
            '<link name="a"/>',
            "utf-8",
            "<xacro:property>",
        ),
        # UTF-16 and UTF-32: the markers are other bytes.
        ('<link name="a"/><link name="${n}"/>', "utf-16", "'${n}'"),
        ('<link name="a"/><link name="${n}"/>', "utf-32", "'${n}'"),
        ('<link name="a"/><link name="${n}"/>', "latin1", "'${n}'"),
        # xacro finds its elements by name: many files bind xacro: to the older URI.
        (
            '<xacro:include xmlns:xacro="http://ros.org/wiki/xacro" filename="o.xacro"/>'
            '<link name="a"/>',
            "utf-8",
            "<xacro:include>",
        ),
        # UTF-16 without a declaration: libxml2 finds it from a BOM or from "<?".
        ('<link name="a"/><link name="${n}"/>', "utf-16-le-bom", "'${n}'"),
        ('<link name="a"/><link name="${n}"/>', "utf-16-be-bom", "'${n}'"),
        ('<link name="a"/><link name="${n}"/>', "utf-16-le", "'${n}'"),
        (
            '<x:include xmlns:x="http://www.ros.org/wiki/xacro" filename="o.xacro"/>'
            '<link name="a"/>',
            "utf-16-le-bom",
            "<xacro:include>",
        ),
    ],
)
def test_xacro_use_is_found_however_it_is_spelt(
    body: str, encoding: str, held: str, tmp_path: Path
) -> None:
    # Files whose bytes rule out xacro are not searched (a byte search replaces the
    # XPath query); every spelling that could hide a use must still be searched.
    path = tmp_path / "robot.urdf"
    declaration = f'<?xml version="1.0" encoding="{encoding}"?>\n'
    if encoding.startswith(("utf-16-", "utf-32-")):  # no declaration: found from the bytes
        declaration = '<?xml version="1.0"?>\n'
    text = declaration + f'<robot name="r">{body}</robot>'
    path.write_bytes(
        text.encode(encoding.removesuffix("-bom"))
        if "bom" not in encoding
        else _BOMS[encoding] + text.encode(encoding.removesuffix("-bom"))
    )
    with pytest.raises(cspace.errors.XacroNotRequestedError) as refused:
        cspace.inspect(str(path))
    assert held in str(refused.value)
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.rstrip().endswith("[xacro-not-requested]")


def test_xacro_keeps_what_the_urdf_reader_found(tmp_path: Path) -> None:
    body = (
        '<link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
        '<child link="b"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="{effort}" velocity="1"/></joint>'
    )
    urdf = tmp_path / "plain.urdf"
    urdf.write_text(f'<robot name="n">{body.format(effort="nan")}</robot>')
    xacro = tmp_path / "same.urdf.xacro"
    xacro.write_text(
        '<robot name="n" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:property name="eff" value="nan"/>' + body.format(effort="${eff}") + "</robot>"
    )
    plain, expanded = cspace.inspect(str(urdf)), cspace.inspect(str(xacro))
    assert plain.diagnostics  # the reader's finding about the effort limit...
    assert expanded.diagnostics == plain.diagnostics  # ...survives the expansion
    assert expanded.manifold == plain.manifold


_NAME_SHARED = """<mujoco model="shared"><worldbody>
<body name="arm"><joint name="shoulder"/><geom size=".1"/>
<body name="tool_ball"><joint name="tool_ball" type="ball"/><geom size=".1"/></body>
</body></worldbody></mujoco>
"""


@pytest.mark.parametrize(("root", "extra"), [("floating", (3, 0, 1)), ("planar", (2, 1, 0))])
def test_mjcf_root_joint_over_a_body_and_joint_sharing_a_name(
    root: str, extra: tuple[int, int, int], tmp_path: Path
) -> None:
    path = tmp_path / "shared.xml"
    path.write_text(_NAME_SHARED)  # a body and a joint both called tool_ball
    plain = cspace.inspect(path)
    rooted = cspace.inspect(path, root_joint=root)
    assert rooted.manifold == plain.manifold * cspace.NormalForm(*extra)
    assert [j.name for j in rooted.joints[1:]] == [j.name for j in plain.joints]


@pytest.mark.parametrize("root", ["floating", "planar"])
def test_a_root_joint_is_never_stacked_on_a_free_joint(root: str) -> None:
    # robots/mjcf_every_joint.xml's first body is free already: a second base would
    # double the base's coordinates without a word.
    with pytest.raises(cspace.errors.InvalidElementError) as refused:
        cspace.inspect(ROBOTS / "mjcf_every_joint.xml", root_joint=root)
    assert refused.value.code == "root-joint-stacked"
    assert refused.value.element == "base_free"
    run = run_cli("inspect", str(ROBOTS / "mjcf_every_joint.xml"), "--root-joint", root)
    assert run.code == 2 and run.stderr.rstrip().endswith("[root-joint-stacked]")


@pytest.mark.parametrize("name", ["arm7.urdf", "sdf_every_joint.sdf", "mjcf_every_joint.xml"])
def test_pinocchio_model_is_the_model_behind_the_report(name: str) -> None:
    report = cspace.inspect(ROBOTS / name)
    model = cspace.pinocchio_model(ROBOTS / name)
    assert (model.nq, model.nv) == (report.nq, report.nv)
    moving = {j.name: (j.q_index, j.nq) for j in report.joints if j.q_index is not None}
    built = {
        str(model.names[i]): (model.joints[i].idx_q, model.joints[i].nq)
        for i in range(1, model.njoints)
    }
    assert built == moving


DRAKE_ROBOT = (
    '<robot name="r" xmlns:drake="http://drake.mit.edu"><link name="a"/><link name="b"/>\n'
    "{joint}</robot>"
)


def _drake_joint(tmp_path: Path, joint: str) -> Run:
    path = tmp_path / "drake.urdf"
    path.write_text(DRAKE_ROBOT.format(joint=joint))
    return run_cli("inspect", str(path), "--format", "json")


@pytest.mark.parametrize(
    ("joint", "space"),
    [
        ('<drake:joint name="j" type="ball"><parent link="a"/><child link="b"/>'
         "</drake:joint>", "RP^3"),
        ('<drake:joint name="j" type="universal"><parent link="a"/><child link="b"/>'
         "</drake:joint>", "T^2"),
        ('<drake:joint name="j" type="planar"><parent link="a"/><child link="b"/>'
         '<axis xyz="0 0 2"/></drake:joint>', "R^2 × S^1"),
    ],
)  # fmt: skip
def test_drakes_joints_in_a_urdf_are_read(tmp_path: Path, joint: str, space: str) -> None:
    """Drake's ball, universal and planar joints (its URDF extension), as Drake reads
    them (held to Drake in test_drake_convention on docs/examples/drake_joints.urdf)."""
    run = _drake_joint(tmp_path, joint)
    assert run.code == 0, run.stderr
    document = json.loads(run.stdout)
    assert document["manifold"]["notation"] == space
    (read,) = document["joints"]
    assert read["line"] == 2 and read["kind"] in ("spherical", "universal", "planar")


@pytest.mark.parametrize(
    ("joint", "said"),
    [
        ('<drake:joint name="j" type="screw"><parent link="a"/><child link="b"/>'
         "</drake:joint>", "of type 'screw', which cspace does not read (it reads ball, "),
        ('<drake:joint name="j" type="planar"><parent link="a"/><child link="b"/>'
         "</drake:joint>", "(1, 0, 0) by default) is not z"),
        ('<drake:joint name="j" type="planar"><parent link="a"/><child link="b"/>'
         '<axis xyz="0 1 1"/></drake:joint>', "is not z"),
        ('<drake:joint name="j" type="planar"><parent link="a"/><child link="b"/>'
         '<axis xyz="0 0 inf"/></drake:joint>', "is not z"),
        ('<drake:joint name="j" type="planar"><parent link="a"/><child link="b"/>'
         '<axis xyz="0 0 1e400"/></drake:joint>', "is not z"),
        ('<drake:joint type="ball"><parent link="a"/><child link="b"/></drake:joint>',
         "<drake:joint> has no 'name' attribute"),
        ('<drake:joint name="j" type="ball"><child link="b"/></drake:joint>',
         "has no <parent> element"),
        ('<drake:joint name="j" type="ball"><parent link="a"/><child link="zz"/>'
         "</drake:joint>", "'zz'"),
        ('<drake:joint name="j" type="ball"><parent link="a"/><child link="b"/>'
         '<origin xyz="1 0"/></drake:joint>', "origin"),
        ('<drake:joint name="j" type="ball"><parent link="a"/><child link="b"/></drake:joint>'
         '<joint name="k" type="fixed"><parent link="a"/><child link="b"/></joint>',
         "parent"),
        ('<drake:joint name="j" type="ball"><parent link="b"/><child link="b"/>'
         "</drake:joint>", "b"),
    ],
)  # fmt: skip
def test_drake_joints_cspace_cannot_read_are_refused_in_one_line(
    tmp_path: Path, joint: str, said: str
) -> None:
    run = _drake_joint(tmp_path, joint)
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "drake.urdf:2:" in run.stderr and said in run.stderr, run.stderr
    assert "Traceback" not in run.stderr


def test_drake_joints_count_towards_the_joint_limit(tmp_path: Path) -> None:
    """5,000 joints at most, counted over <joint> and <drake:joint> together."""
    links = '<link name="a"/><link name="b"/>'
    one = '<parent link="a"/><child link="b"/>'
    joints = "".join(
        f'<drake:joint name="j{k}" type="ball">{one}</drake:joint>' for k in range(3000)
    ) + "".join(f'<joint name="k{k}" type="fixed">{one}</joint>' for k in range(2001))
    path = tmp_path / "many.urdf"
    path.write_text(f'<robot name="r" xmlns:drake="http://drake.mit.edu">{links}{joints}</robot>')
    run = run_cli("inspect", str(path))
    assert run.code == 2 and "5,001 joints" in run.stderr and "[too-many-joints]" in run.stderr


MIMIC_BALL = (
    '<robot name="r" xmlns:drake="http://drake.mit.edu"><link name="a"/><link name="b"/>'
    '<link name="c"/><link name="d"/>\n'
    '<drake:joint name="j" type="ball"><parent link="a"/><child link="b"/></drake:joint>'
    '<joint name="m" type="revolute"><parent link="b"/><child link="c"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    '<dynamics damping="0.5" friction="0.25"/></joint>'
    '<joint name="f" type="revolute"><parent link="c"/><child link="d"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="m" multiplier="2"/>'
    "</joint></robot>"
)


def test_a_ball_drake_joint_beside_mimic_joints_keeps_them_and_their_dynamics(
    tmp_path: Path,
) -> None:
    """The model rebuilt around a ball joint refused mimic
    joints and lost the other joints' damping and friction."""
    path = tmp_path / "drake.urdf"
    path.write_text(MIMIC_BALL)
    report = cspace.inspect(path)
    assert report.manifold.notation == "R^1 × RP^3"
    assert {j.name: j.kind.value for j in report.joints}["f"] == "mimic"
    model = cspace.pinocchio_model(path)
    moving = model.joints[model.getJointId("m")]
    assert model.damping[moving.idx_v] == 0.5 and model.friction[moving.idx_v] == 0.25
    space = cspace.ConfigurationSpace.from_report(report)
    assert space.conventions().names("drake") == ("j_qx", "j_qy", "j_qz", "m_q", "f_q")


@pytest.mark.parametrize(
    ("root", "read"),
    [
        ('<robot name="r" xmlns:drake="http://example.com">', True),  # the prefix, as Drake
        ('<robot name="r" xmlns:d="http://drake.mit.edu">', False),  # Drake ignores <d:joint>
    ],
)
def test_a_drake_joint_is_known_by_its_prefix_as_drake_knows_it(
    tmp_path: Path, root: str, read: bool
) -> None:
    prefix = "drake" if "xmlns:drake" in root else "d"
    path = tmp_path / "drake.urdf"
    path.write_text(
        f'{root}<link name="a"/><link name="b"/>\n<{prefix}:joint name="j" type="ball">'
        f'<parent link="a"/><child link="b"/></{prefix}:joint></robot>'
    )
    run = run_cli("inspect", str(path))
    if read:
        assert run.code == 0 and "RP^3" in run.stdout
    else:  # no joint holds b: two roots
        assert run.code == 2 and "[several-roots]" in run.stderr


def test_a_joint_defined_twice_is_first_where_the_file_first_defines_it(tmp_path: Path) -> None:
    run = _drake_joint(
        tmp_path,
        '<drake:joint name="j" type="ball"><parent link="a"/><child link="b"/></drake:joint>\n'
        '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>',
    )
    assert run.code == 2 and "drake.urdf:3:" in run.stderr and "(first at line 2)" in run.stderr


@pytest.mark.parametrize(
    ("joint_name", "refused"),
    [
        ("中" * 85, False),  # 255 bytes in UTF-8
        ("中" * 86, True),  # 258
        ("j" + "\u200b" * 42, False),  # 1 + 42 escapes of 6 bytes: 253
        ("j" + "\u200b" * 43, True),  # 259
        ("\U000e0001" * 21, False),  # a tag character: a surrogate pair, 12 bytes each
        ("\U000e0001" * 22, True),
    ],
)
def test_a_name_is_bounded_by_the_bytes_it_takes_in_a_report(
    tmp_path: Path, joint_name: str, refused: bool
) -> None:
    """Names of 248 zero-width characters made a 4.6 MB file
    a 72 MB report that cspace could not read back; 256 bytes in a report bound them."""
    path = tmp_path / "named.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/>\n'
        f'<joint name="{joint_name}" type="fixed"><parent link="a"/><child link="b"/></joint>'
        "</robot>",
        encoding="utf-8",
    )
    run = run_cli("inspect", str(path), "--format", "json")
    if refused:
        assert (
            run.code == 2 and "[name-too-long]" in run.stderr and "bytes in a report" in run.stderr
        )
    else:
        assert run.code == 0, run.stderr


def test_a_mimic_follower_with_huge_limits_is_no_sentinel(tmp_path: Path) -> None:
    """A follower adds no coordinate; its limits say nothing
    about 'no limit'."""
    path = tmp_path / "mimic.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>\n'
        '<joint name="lead" type="revolute"><parent link="a"/><child link="b"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        '<joint name="mim" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit lower="-1e5" upper="1e5" effort="1" velocity="1"/><mimic joint="lead"/></joint>'
        "</robot>"
    )
    assert "limits-sentinel" not in {d.code for d in cspace.inspect(path).diagnostics}
