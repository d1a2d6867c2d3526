"""Drake as a convention, with Drake itself as the oracle.

For the teaching robots and example-robot-data's URDF files that Drake loads: the names
and order of Drake's positions and velocities (``GetPositionNames``,
``GetVelocityNames``) are cspace's ``names("drake")``; a configuration converted to
Drake's q places every body where Pinocchio places it for the same configuration; a
tangent vector converted to Drake's v is Drake's own velocity of the motion (its
``MapQDotToVelocity`` of a finite difference of q). A robot cspace reads with a fixed
base is loaded with its root welded to the world, as a Drake user does.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

import cspace
from cspace._formats.shared.erd import robots_dir, urdf_files

from conftest import REPO, ROBOTS, run_cli

TEACHING = [(p.name, None) for p in sorted(ROBOTS.glob("*.urdf"))] + [
    ("quadruped_nobase.urdf", "floating"),
    ("arm7.urdf", "floating"),
]
DRAKE_REFUSES = {
    "alex_description/urdf/alex_psyonic_hands.urdf",
    "talos_data/robots/talos_left_arm.urdf",
    "talos_data/robots/talos_reduced.urdf",
    "talos_data/robots/talos_reduced_box.urdf",
    "talos_data/robots/talos_reduced_corrected.urdf",
    "ur_description/urdf/ur3.urdf",
}
"""example-robot-data's URDF files Drake does not load (a fixed joint that mimics, a
missing mesh): every other one is an oracle case."""
ORDER = (REPO / "docs" / "examples" / "order.urdf").read_text()
"""Four joints, the b branch declared first, the a branch first by name (the docs' example)."""


def _plant(path: Path, space: cspace.ConfigurationSpace | None) -> MultibodyPlant:
    """Drake's plant of the file, each root body welded to the world unless cspace floats it."""
    plant = MultibodyPlant(0.0)
    parser = Parser(plant)
    parser.package_map().PopulateFromFolder(str(robots_dir()))
    (model,) = parser.AddModels(str(path))
    if space is None or not any(j.kind.value == "floating" for j in space.report_joints):
        held = {plant.get_joint(i).child_body().index() for i in plant.GetJointIndices(model)}
        for index in plant.GetBodyIndices(model):
            if index not in held:
                plant.WeldFrames(plant.world_frame(), plant.get_body(index).body_frame())
    plant.Finalize()
    return plant


DRAKE_MJCF_DIFFERS = {
    "mjcf_frame_childclass.xml": "Drake's MJCF parser drops the bodies inside <frame>",
    "mjcf_replicate.xml": "Drake's MJCF parser does not expand <replicate>",
    "mjcf_unnamed_joints.xml": "Drake names an unnamed MJCF joint after its bodies",
}
"""Teaching MJCF files Drake reads otherwise than MuJoCo (the authority on MJCF)."""
OTHER_FORMATS = [
    p.name
    for p in sorted([*ROBOTS.glob("*.xml"), *ROBOTS.glob("*.sdf")])
    if p.name not in DRAKE_MJCF_DIFFERS
]


def test_drake_reads_the_other_teaching_files_otherwise_as_said() -> None:
    """Each exclusion is true: Drake's names differ on exactly these files."""
    for name in DRAKE_MJCF_DIFFERS:
        space = cspace.load(ROBOTS / name)
        plant = _plant(ROBOTS / name, space)
        assert space.conventions().names("drake") != tuple(plant.GetPositionNames(False))


def _robots() -> list[tuple[str, Path, str | None]]:
    cases = [(name, ROBOTS / name, root) for name, root in TEACHING]
    cases += [(name, ROBOTS / name, None) for name in OTHER_FORMATS]
    cases.append(("drake_joints.urdf", REPO / "docs" / "examples" / "drake_joints.urdf", None))
    known = {p.relative_to(robots_dir()).as_posix(): p for p in urdf_files()}
    return cases + [(n, p, None) for n, p in sorted(known.items()) if n not in DRAKE_REFUSES]


def test_drake_refuses_only_the_files_it_is_known_to_refuse() -> None:
    """The oracle's own reach: every other example-robot-data URDF loads in Drake (and
    cspace refuses alex's hands, whose mimic names a joint that does not exist)."""
    refused = set()
    for path in urdf_files():
        try:
            _plant(path, None)
        except RuntimeError:
            refused.add(path.relative_to(robots_dir()).as_posix())
    assert refused == DRAKE_REFUSES


logging.getLogger("drake").setLevel(logging.ERROR)  # its notes on friction and the like
ROBOT_CASES = _robots()
IDS = [f"{name}-{root}" if root else name for name, _, root in ROBOT_CASES]


@pytest.mark.parametrize(("name", "path", "root"), ROBOT_CASES, ids=IDS)
def test_drake_names_its_positions_and_velocities_as_cspace_says(
    name: str, path: Path, root: str | None
) -> None:
    report = cspace.inspect(path, root)
    space = cspace.ConfigurationSpace.from_report(report)
    plant = _plant(path, space)
    conventions = space.conventions()
    assert conventions.names("drake") == tuple(plant.GetPositionNames(False))
    assert conventions.names("drake", velocity=True) == tuple(plant.GetVelocityNames(False))
    document = report.to_dict()  # the JSON report's slots say the same
    assert (_report_slots(document, "drake_q") or []) == list(plant.GetPositionNames(False))
    assert (_report_slots(document, "drake_v") or []) == list(plant.GetVelocityNames(False))


def _report_slots(document: dict[str, Any], slot: str) -> list[str] | None:
    """A vector's names, assembled from the JSON report's slots of each joint."""
    names: dict[int, str] = {}
    for joint in document["joints"]:
        found = joint.get("slots", {}).get(slot)
        if found is not None:
            names.update((found["index"] + i, n) for i, n in enumerate(found["names"]))
    return [names[i] for i in range(len(names))] if names else None


@pytest.mark.parametrize(("name", "path", "root"), ROBOT_CASES, ids=IDS)
def test_drake_places_every_body_where_pinocchio_does(
    name: str, path: Path, root: str | None
) -> None:
    """The same configuration, converted to each tool: every link at the same pose."""
    space = cspace.load(path, root)
    plant = _plant(path, space)
    context = plant.CreateDefaultContext()
    model = cspace.pinocchio_model(path, root)
    data = model.createData()
    conventions = space.conventions()
    rng = np.random.default_rng(7)
    free = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower) and not c.wraps}
    compared = 0
    for x in space.sample(4, rng, bounds=free):
        plant.SetPositions(context, conventions.to_drake(x))
        pin.framesForwardKinematics(model, data, conventions.to_pinocchio(x))
        for frame_id, frame in enumerate(model.frames):
            if frame.type != pin.FrameType.BODY or not plant.HasBodyNamed(frame.name):
                continue
            compared += 1
            pose = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(frame.name))
            placed = data.oMf[frame_id]
            np.testing.assert_allclose(pose.translation(), placed.translation, atol=1e-9)
            np.testing.assert_allclose(pose.rotation().matrix(), placed.rotation, atol=1e-9)
    assert compared > 0  # not a vacuous pass


@pytest.mark.parametrize(("name", "path", "root"), ROBOT_CASES, ids=IDS)
def test_drake_velocities_are_drakes_own_of_the_motion(
    name: str, path: Path, root: str | None
) -> None:
    """v of a tangent dx at x is Drake's MapQDotToVelocity of (q(x + h dx) - q(x)) / h."""
    space = cspace.load(path, root)
    plant = _plant(path, space)
    context = plant.CreateDefaultContext()
    conventions = space.conventions()
    rng = np.random.default_rng(8)
    free = {  # near the neutral: 1e16 rad (iris's rotors) plus a step of 1e-7 is 1e16
        c.name: (max(c.lower, -2.0), min(c.upper, 2.0))
        for c in space.coordinates
        if not c.wraps and c.upper - c.lower > 4.0
    }
    h = 1e-7
    for x in space.sample(4, rng, bounds=free):
        dx = rng.normal(size=space.dimension)
        q0, q1 = conventions.to_drake(x), conventions.to_drake(space.integrate(x, h * dx))
        plant.SetPositions(context, q0)
        expected = plant.MapQDotToVelocity(context, (q1 - q0) / h)
        v = conventions.to_drake_velocity(x, dx)
        np.testing.assert_allclose(v, expected, atol=2e-5)
        np.testing.assert_allclose(conventions.from_drake_velocity(x, v), dx, atol=1e-12)
        np.testing.assert_allclose(conventions.from_drake(q0), x, atol=1e-15)


def test_drake_orders_joints_as_declared_and_pinocchio_by_name(tmp_path: Path) -> None:
    """The issue's measurement: one file, two orders; cspace says both."""
    path = tmp_path / "order.urdf"
    path.write_text(ORDER)
    space = cspace.load(path)
    conventions = space.conventions()
    assert conventions.names("drake") == ("b_hip_q", "spin_q", "a_hip_q", "a_ankle_q")
    assert space.names == ("a_hip", "a_ankle", "b_hip", "spin")
    x = np.array([0.1, 0.2, 0.3, 0.4])
    np.testing.assert_array_equal(conventions.to_drake(x), [0.3, 0.4, 0.1, 0.2])
    np.testing.assert_array_equal(
        conventions.convert(x, "canonical", "drake"), conventions.to_drake(x)
    )


def test_convert_writes_drakes_vectors_and_asks_for_the_configurations(tmp_path: Path) -> None:
    path = tmp_path / "order.urdf"
    path.write_text(ORDER)
    (tmp_path / "q.csv").write_text("a_hip,a_ankle,b_hip,spin\n0.1,0.2,0.3,0.4\n")
    run = run_cli(
        "convert", "order.urdf", "q.csv", "--from", "canonical", "--to", "drake", cwd=tmp_path
    )
    assert run.code == 0, run.stderr
    assert run.stdout.splitlines() == ["b_hip_q,spin_q,a_hip_q,a_ankle_q", "0.3,0.4,0.1,0.2"]
    (tmp_path / "v.csv").write_text("a_hip,a_ankle,b_hip,spin\n0,0,0,0\n")
    velocity = run_cli(
        "convert", "order.urdf", "v.csv", "--velocity", "--from", "canonical", "--to", "drake",
        cwd=tmp_path,
    )  # fmt: skip
    assert velocity.code == 2 and "Drake velocities need --at FILE" in velocity.stderr


def test_a_xacro_tree_whose_declaration_order_is_lost_is_refused(tmp_path: Path) -> None:
    """A xacro file's report keeps no lines: siblings' order, which is Drake's, unknown."""
    path = tmp_path / "robot.urdf.xacro"
    path.write_text(
        ORDER.replace(
            '<robot name="order">',
            '<robot name="order" xmlns:xacro="http://www.ros.org/wiki/xacro">',
        )
    )
    space = cspace.load(path)
    with pytest.raises(cspace.JointMatchError, match="expand it to a URDF"):
        space.conventions().names("drake")
    assert _report_slots(cspace.inspect(path).to_dict(), "drake_q") is None  # nothing said
    run = run_cli("convert", str(path), "-", "--from", "canonical", "--to", "drake", cwd=tmp_path)
    assert run.code == 2 and run.stderr.count("\n") == 1 and "expand it to a URDF" in run.stderr


SCENE = """<mujoco model="scene"><worldbody>
  <body name="robot"><freejoint/><geom size="0.1"/>
    <body name="arm"><joint name="elbow" range="-1 1" limited="true"/><geom size="0.1"/></body>
  </body>
  <body name="ball"><freejoint name="ball_free"/><geom size="0.1"/></body>
  <body name="door" pos="1 0 0"><joint name="door_hinge" range="-1 1" limited="true"/>
    <geom size="0.1"/></body>
  <body name="cart"><joint name="rail" type="slide" range="0 1" limited="true"/>
    <geom size="0.1"/>
    <body name="pole"><joint name="tilt" range="-1 1" limited="true"/><geom size="0.1"/></body>
    <body name="lid"><joint name="lid_follow" type="slide" range="0 1" limited="true"/>
      <geom size="0.1"/></body>
  </body>
</worldbody>
<equality><joint joint1="lid_follow" joint2="tilt"/></equality>
</mujoco>
"""
"""Free bodies declared first, a follower that slides after a
hinge. Drake puts the jointed trees first, then floated trees, then single bodies, and
names a follower by its own kind."""


def test_drake_orders_a_scene_as_drake_does(tmp_path: Path) -> None:
    path = tmp_path / "scene.xml"
    path.write_text(SCENE)
    space = cspace.load(path)
    plant = _plant(path, space)
    conventions = space.conventions()
    assert conventions.names("drake") == tuple(plant.GetPositionNames(False))
    assert conventions.names("drake", velocity=True) == tuple(plant.GetVelocityNames(False))
    context = plant.CreateDefaultContext()
    model = cspace.pinocchio_model(path)
    data = model.createData()
    for x in space.sample(
        3,
        np.random.default_rng(2),
        bounds={c.name: (-1.0, 1.0) for c in space.coordinates if np.isinf(c.lower)},
    ):
        plant.SetPositions(context, conventions.to_drake(x))
        pin.framesForwardKinematics(model, data, conventions.to_pinocchio(x))
        for frame_id, frame in enumerate(model.frames):
            if frame.type == pin.FrameType.BODY and plant.HasBodyNamed(frame.name):
                pose = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(frame.name))
                np.testing.assert_allclose(
                    pose.translation(), data.oMf[frame_id].translation, atol=1e-9
                )


@pytest.mark.parametrize("pitch", [np.pi / 2, -np.pi / 2, np.pi / 2 - 1e-9, 0.3])
def test_a_ball_joint_at_the_roll_pitch_yaw_singularity_is_exact(pitch: float) -> None:
    """At pitch +-pi/2 the rotation was off by 1.98."""
    from pydrake.math import RollPitchYaw

    space = cspace.load(ROBOTS / "mjcf_balls.xml")
    conventions = space.conventions()
    x = space.neutral()
    start = space.names.index("neck.qw")
    rotation = RollPitchYaw([0.4, pitch, -2.5]).ToQuaternion()
    x[start : start + 4] = [rotation.w(), rotation.x(), rotation.y(), rotation.z()]
    x = space.canonicalize(x)
    q = conventions.to_drake(x)
    names = conventions.names("drake")
    rpy = q[names.index("neck_qx") : names.index("neck_qz") + 1]
    np.testing.assert_allclose(
        RollPitchYaw(rpy).ToRotationMatrix().matrix(),
        RollPitchYaw([0.4, pitch, -2.5]).ToRotationMatrix().matrix(),
        atol=1e-12,
    )
    np.testing.assert_allclose(conventions.from_drake(q), x, atol=1e-12)


def test_what_drake_cannot_be_told_is_refused(tmp_path: Path) -> None:
    """A floating joint below the root (Drake floats its child in the world); siblings
    declared on one line (their order unknown); a NaN velocity."""
    below = ORDER.replace(
        '<joint name="spin" type="continuous"><parent link="b1"/><child link="b2"/></joint>',
        '<joint name="spin" type="floating"><parent link="b1"/><child link="b2"/></joint>',
    )
    (tmp_path / "below.urdf").write_text(below)
    with pytest.raises(cspace.JointMatchError, match="Drake floats its child in the world"):
        cspace.load(tmp_path / "below.urdf").conventions().names("drake")
    (tmp_path / "line.urdf").write_text(ORDER.replace("\n", " "))
    with pytest.raises(cspace.JointMatchError, match="two joints on one line"):
        cspace.load(tmp_path / "line.urdf").conventions().names("drake")
    space = cspace.load(ROBOTS / "arm7.urdf")
    with pytest.raises(cspace.errors.NonFiniteValueError):
        space.conventions().to_drake_velocity(space.neutral(), np.full(space.dimension, np.nan))


@pytest.mark.bounded
def test_hostile_names_and_depth_in_drakes_vectors(tmp_path: Path) -> None:
    """Hostile names escaped in Drake's header, and the deepest tree ordered.

    A joint name that would start a workflow command or reverse text is escaped as in
    every output; a chain 1,000 joints deep (the most cspace reads) is ordered without
    recursion, within the time and memory bounds.
    """
    from conftest import SECONDS, measured

    evil = (
        '<robot name="e"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="x&#10;::error::own,&#8238;" type="revolute"><parent link="a"/>'
        '<child link="b"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        '<joint name="y" type="revolute"><parent link="b"/><child link="c"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    (tmp_path / "evil.urdf").write_text(evil)
    (tmp_path / "y.csv").write_text("y\n0.2\n")
    run = run_cli(
        "convert", "evil.urdf", "y.csv", "--from", "named", "--to", "drake", "--partial",
        cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 0, run.stderr
    assert run.stdout.splitlines() == ['"x\\n::error::own,\\u202e_q",y_q', "0.0,0.2"]
    links = "".join(f'<link name="l{k}"/>' for k in range(1001))
    joints = "".join(
        f'<joint name="j{k}" type="revolute"><parent link="l{k}"/><child link="l{k + 1}"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        for k in range(1000)
    )
    (tmp_path / "deep.urdf").write_text(f'<robot name="d">{links}\n{joints}</robot>')
    (tmp_path / "q.csv").write_text("j0\n0.1\n")
    result = measured(
        "convert", "deep.urdf", "q.csv", "--from", "named", "--to", "drake", "--partial",
        cwd=tmp_path,
    )  # fmt: skip
    assert result.run.code == 0, result.run.stderr
    assert result.run.stdout.splitlines()[0].split(",")[:2] == ["j0_q", "j1_q"]
    assert result.cpu_seconds < SECONDS


def test_a_root_drake_would_float_is_named_where_drakes_vectors_are_written(
    tmp_path: Path,
) -> None:
    """Drake's URDF parser floats a root link no joint holds (its plant gains a free body);
    cspace keeps it fixed, says which links its Drake vectors take welded, and `convert`
    notes it. With a root joint, or in MJCF, there is nothing to say."""
    path = REPO / "docs" / "examples" / "order.urdf"
    unwelded = MultibodyPlant(0.0)
    Parser(unwelded).AddModels(str(path))
    unwelded.Finalize()
    assert unwelded.num_positions() == 4 + 7  # base became a free body
    space = cspace.load(path)
    assert space.conventions().drake.welded == ("base",)
    assert cspace.load(path, "floating").conventions().drake.welded == ()
    assert cspace.load(ROBOTS / "mjcf_balls.xml").conventions().drake.welded == ()
    (tmp_path / "x.jsonl").write_text("[0, 0, 0, 0]\n")
    run = run_cli(
        "convert", str(path), "x.jsonl", "--from", "canonical", "--to", "drake", cwd=tmp_path
    )
    assert run.code == 0 and run.stdout == "[0.0, 0.0, 0.0, 0.0]\n"
    assert run.stderr == (
        "cspace: note: Drake's parser would float link(s) 'base', which no joint holds to the "
        "world; these are Drake's vectors with them welded (plant.WeldFrames before Finalize)\n"
    )
    run = run_cli(
        "convert", str(path), "x.jsonl", "--from", "canonical", "--to", "pinocchio", cwd=tmp_path
    )
    assert run.code == 0 and run.stderr == ""


def test_diff_says_when_only_drakes_order_moved(tmp_path: Path) -> None:
    """Siblings declared in another order move Drake's q, not
    Pinocchio's (which sorts them by name); diff said "no C-space change"."""
    reordered = ORDER
    for name in ("b_hip", "spin"):  # the b branch after the a branch
        start = reordered.index(f'<joint name="{name}"')
        end = reordered.index("</joint>", start) + len("</joint>")
        element = reordered[start:end]
        reordered = reordered[:start] + reordered[end:]
        reordered = reordered.replace("</robot>", f"  {element}\n</robot>")
    path = tmp_path / "reordered.urdf"
    path.write_text(reordered)
    assert cspace.load(path).conventions().names("drake")[0] == "a_hip_q"
    run = run_cli("diff", str(REPO / "docs" / "examples" / "order.urdf"), str(path))
    assert run.code == 1, run.stdout
    assert "C-space the same: R^3 × S^1 (dimension 4), but q/v layout differs" in run.stdout
    assert "q 0, v 0, Drake q 2" in run.stdout and "q 0, v 0, Drake q 0" in run.stdout


def test_a_free_body_named_as_a_joint_is_named_as_drake_names_it(tmp_path: Path) -> None:
    """Drake names a free body's joint after the body, with
    '_' before it while a joint has that name (here joint 'base' below body 'base')."""
    inertial = (
        '<inertial><mass value="1"/>'
        '<inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'
    )
    path = tmp_path / "same.urdf"
    path.write_text(
        f'<robot name="c">\n<link name="base">{inertial}</link>\n<link name="c">{inertial}</link>\n'
        '<joint name="base" type="revolute"><parent link="base"/><child link="c"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n'
        "</robot>"
    )
    report = cspace.inspect(path, "floating")
    space = cspace.ConfigurationSpace.from_report(report)
    plant = _plant(path, space)
    assert space.conventions().names("drake") == tuple(plant.GetPositionNames(False))
    assert space.conventions().names("drake")[0] == "_base_qw"
    assert _report_slots(report.to_dict(), "drake_v") == list(plant.GetVelocityNames(False))


def test_diff_notes_a_root_drake_floats_on_one_side_only(tmp_path: Path) -> None:
    """The same C-space to cspace (and Pinocchio), which keep a root link fixed; Drake
    floats the one no joint holds: one side bolts 'base' to a 'world' link, the other
    does not."""
    bolted = ORDER.replace(
        '<link name="base"/>',
        '<link name="world"/><link name="base"/>\n'
        '  <joint name="bolt" type="fixed"><parent link="world"/><child link="base"/></joint>',
    )
    path = tmp_path / "bolted.urdf"
    path.write_text(bolted)
    sizes = []
    for robot in (path, REPO / "docs" / "examples" / "order.urdf"):
        plant = MultibodyPlant(0.0)
        Parser(plant).AddModels(str(robot))
        plant.Finalize()
        sizes.append(plant.num_positions())
    assert sizes == [4, 4 + 7]  # Drake: welded, then floated
    run = run_cli("diff", str(path), str(REPO / "docs" / "examples" / "order.urdf"))
    assert run.code == 0 and run.stdout.startswith("no C-space change")
    assert "Drake floats  -      none  base" in run.stdout
    run = run_cli("diff", str(path), str(path))
    assert "Drake floats" not in run.stdout
