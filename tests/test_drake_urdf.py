"""Drake's URDF parser against Pinocchio: floating joints' origins, planar joints' axes.

Drake's parser (``Parser(plant).AddModels``) makes no joint of a URDF ``floating`` joint:
it leaves the child a free body, whose q is its pose in the world, starting at the
world's origin; the joint's ``<origin>`` is dropped. cspace's Drake convention composes
that origin into the free body's q and v (`JointReport.origin`), so the same
configuration places every body alike in both tools. Where the two build another
mechanism, the report says so (``drake-urdf-differs``, an info) and ``--to drake``
repeats it: a planar joint Drake moves in the plane normal to its ``<axis>`` (as URDF
specifies; (1, 0, 0) when absent) where Pinocchio moves it in its frame's x-y plane, and
a floating joint below another link, whose child Drake leaves free in the world (cspace
does not map Drake's vectors of that file).

The oracle is Drake itself: every body, at random configurations converted to Drake's q
through cspace's maps, at Pinocchio's pose of it (1e-9), and Drake's velocities those
of the motion; the finding is given exactly where they are not.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

import cspace

from conftest import run_cli

logging.getLogger("drake").setLevel(logging.CRITICAL)  # "Leaving 'base' as a free body"

CODE = "drake-urdf-differs"
LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
ARM = (
    '<link name="arm"/><joint name="elbow" type="revolute"><origin xyz="0.5 0.1 0"/>'
    f'<parent link="base"/><child link="arm"/><axis xyz="0 1 1"/>{LIMIT}</joint>'
)
"""A link below 'base', so that a pose of base is seen at a second body too."""


def _floating(parent: str, origin: str) -> str:
    return (
        f'<joint name="float" type="floating">{origin}<parent link="{parent}"/>'
        '<child link="base"/></joint>'
    )


def _planar(axis: str, origin: str = '<origin xyz="0 0 1" rpy="0.3 0 0"/>') -> str:
    return (
        f'<joint name="plane" type="planar">{origin}<parent link="world"/>'
        f'<child link="base"/>{axis}</joint>'
    )


TURNED = '<origin xyz="0.3 -1 2" rpy="0.3 -0.4 2.5"/>'
FILES = {
    # name: (the joints, Drake's model differs)
    "floating_turned": (_floating("world", TURNED), False),
    "floating_world_declared": ('<link name="world"/>' + _floating("world", TURNED), False),
    "floating_from_a_root_link": ('<link name="stand"/>' + _floating("stand", TURNED), False),
    "floating_no_origin": (_floating("world", ""), False),
    "planar_no_axis": (_planar(""), True),
    "planar_x": (_planar('<axis xyz="1 0 0"/>'), True),
    "planar_minus_z": (_planar('<axis xyz="0 0 -1"/>'), True),
    "planar_tilted": (_planar('<axis xyz="0 0.1 1"/>'), True),
    "planar_z_scaled": (_planar('<axis xyz="0 0 2"/>'), False),
    "planar_z_moved": (_planar('<axis xyz="0 0 1"/>'), False),
}
"""Small URDF files of one floating or planar joint above 'base' (and 'arm' below it)."""


def _write(tmp_path: Path, name: str, joints: str) -> Path:
    path = tmp_path / f"{name}.urdf"
    path.write_text(f'<robot name="{name}">\n<link name="base"/>{ARM}\n{joints}\n</robot>\n')
    return path


def _plant(path: Path, space: cspace.ConfigurationSpace) -> MultibodyPlant:
    """Drake's plant of the file, the root links cspace's Drake convention welds welded."""
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    for link in space.conventions().drake.welded:
        plant.WeldFrames(plant.world_frame(), plant.GetBodyByName(link).body_frame())
    plant.Finalize()
    return plant


def _gaps(path: Path) -> tuple[float, float]:
    """The largest distance between a body's pose in Drake and in Pinocchio at random
    configurations through cspace's maps (m and rotation-matrix entries), and between
    Drake's velocity of the motion and ``to_drake_velocity``."""
    space = cspace.load(path)
    conventions = space.conventions()
    plant = _plant(path, space)
    context = plant.CreateDefaultContext()
    model = cspace.pinocchio_model(path)
    data = model.createData()
    rng = np.random.default_rng(11)
    free = {n: (-2.0, 2.0) for n in space.names if n.endswith((".x", ".y", ".z"))}
    pose_gap = velocity_gap = 0.0
    h = 1e-7
    for x in space.sample(4, rng, bounds=free):
        q = conventions.to_drake(x)
        plant.SetPositions(context, q)
        pin.framesForwardKinematics(model, data, conventions.to_pinocchio(x))
        for name in ("base", "arm"):
            pose = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(name))
            placed = data.oMf[model.getFrameId(name, pin.FrameType.BODY)]
            pose_gap = max(
                pose_gap,
                np.abs(pose.translation() - placed.translation).max(),
                np.abs(pose.rotation().matrix() - placed.rotation).max(),
            )
        np.testing.assert_allclose(conventions.from_drake(q), x, atol=1e-12)
        dx = rng.normal(size=space.dimension)
        moved = conventions.to_drake(space.integrate(x, h * dx))
        v = conventions.to_drake_velocity(x, dx)
        expected = plant.MapQDotToVelocity(context, (moved - q) / h)
        velocity_gap = max(velocity_gap, np.abs(v - expected).max())
        np.testing.assert_allclose(conventions.from_drake_velocity(x, v), dx, atol=1e-12)
    return pose_gap, velocity_gap


@pytest.mark.parametrize("name", sorted(FILES))
def test_drake_urdf_differs_is_said_exactly_where_drake_moves_a_body_otherwise(
    name: str, tmp_path: Path
) -> None:
    joints, differs = FILES[name]
    path = _write(tmp_path, name, joints)
    pose_gap, velocity_gap = _gaps(path)
    said = [d for d in cspace.inspect(path).diagnostics if d.code == CODE]
    assert (pose_gap > 1e-9) == differs == bool(said), (name, pose_gap, said)
    if not differs:
        assert velocity_gap < 2e-5, (name, velocity_gap)
        return
    (finding,) = said
    assert finding.joint == "plane" and finding.line == 3
    assert finding.severity is cspace.Severity.INFO
    assert "in the plane normal to its axis" in finding.message
    assert cspace.load(path).conventions().drake.findings == (finding,)  # carried


def test_a_floating_joints_origin_is_composed_into_drakes_q(tmp_path: Path) -> None:
    """The report keeps the origin Drake drops (x y z, then the quaternion w first), the
    Drake convention composes it, and a saved report does the same. The free body's q at
    the joint's zero is the origin itself (Drake's default q puts it at the world's)."""
    path = _write(tmp_path, "turned", FILES["floating_turned"][0])
    report = cspace.inspect(path)
    (joint,) = [j for j in report.joints if j.name == "float"]
    origin = pin.SE3(pin.rpy.rpyToMatrix(0.3, -0.4, 2.5), np.array([0.3, -1.0, 2.0]))
    turn = pin.Quaternion(origin.rotation)
    np.testing.assert_allclose(
        joint.origin, [0.3, -1.0, 2.0, turn.w, turn.x, turn.y, turn.z], atol=1e-15
    )
    space = cspace.ConfigurationSpace.from_report(report)
    q = space.conventions().to_drake(space.neutral())
    names = space.conventions().names("drake")
    assert names[:7] == ("base_qw", "base_qx", "base_qy", "base_qz", "base_x", "base_y", "base_z")
    np.testing.assert_allclose(q[:7], [turn.w, turn.x, turn.y, turn.z, 0.3, -1.0, 2.0])
    plant = _plant(path, space)
    assert not np.allclose(plant.GetDefaultPositions()[:7], q[:7])  # Drake drops it
    saved = tmp_path / "turned.json"
    saved.write_text(json.dumps(report.to_dict()))
    again = cspace.Report.from_dict(json.loads(saved.read_text()))
    assert again.joints == report.joints
    bounds = {f"float.{a}": (-1.0, 1.0) for a in "xyz"}
    x = space.sample(3, np.random.default_rng(2), bounds=bounds)
    np.testing.assert_array_equal(
        cspace.ConfigurationSpace.from_report(again).conventions().to_drake(x),
        space.conventions().to_drake(x),
    )
    plain = _write(tmp_path, "plain", FILES["floating_no_origin"][0])
    document = json.loads(run_cli("inspect", str(plain), "--format", "json").stdout)
    assert all("origin" not in j for j in document["joints"])  # only off the world's


def test_a_floating_joint_below_a_link_is_said_and_refused(tmp_path: Path) -> None:
    """Drake leaves the child free in the world: it no longer moves with the link above
    (Pinocchio's does). The report says so, and cspace maps no Drake vector of it."""
    joints = (
        '<link name="world"/><joint name="lift" type="prismatic"><parent link="world"/>'
        f'<child link="stand"/><axis xyz="0 0 1"/>{LIMIT}</joint><link name="stand"/>\n'
        + _floating("stand", TURNED)
    )
    path = _write(tmp_path, "below", joints)
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    context = plant.CreateDefaultContext()
    lift = plant.GetJointByName("lift")
    base = plant.GetBodyByName("base")
    before = plant.EvalBodyPoseInWorld(context, base).translation()
    lift.set_translation(context, 0.7)
    after = plant.EvalBodyPoseInWorld(context, base).translation()
    np.testing.assert_array_equal(before, after)  # in Drake, base does not follow 'stand'
    model = cspace.pinocchio_model(path)
    data = model.createData()
    q = pin.neutral(model)
    pin.framesForwardKinematics(model, data, q)
    first = data.oMf[model.getFrameId("base", pin.FrameType.BODY)].translation.copy()
    q[model.idx_qs[model.getJointId("lift")]] = 0.7
    pin.framesForwardKinematics(model, data, q)
    moved = data.oMf[model.getFrameId("base", pin.FrameType.BODY)].translation
    np.testing.assert_allclose(moved - first, [0.0, 0.0, 0.7], atol=1e-12)  # in Pinocchio, it does
    (said,) = [d for d in cspace.inspect(path).diagnostics if d.code == CODE]
    assert said.joint == "float" and said.line == 4
    assert "does not move with link 'stand'" in said.message
    with pytest.raises(cspace.JointMatchError, match="Drake floats its child in the world"):
        cspace.load(path).conventions().names("drake")


def test_convert_warns_where_drake_differs_and_is_exact_where_it_composes(
    tmp_path: Path,
) -> None:
    """``--to drake`` repeats the finding on standard error as a warning, with the file
    and the joint's line, and writes the vectors all the same; of a floating joint with
    an origin it writes the composed pose, and says nothing."""
    planar = _write(tmp_path, "planar", FILES["planar_no_axis"][0])
    run = run_cli("convert", str(planar), "-", "--from", "canonical", "--to", "drake",
                  stdin=b"[0.1, 0.2, 0.3, 0.4]\n")  # fmt: skip
    assert run.code == 0, run.stderr
    assert run.stdout == "[0.1, 0.2, 0.3, 0.4]\n"
    assert run.stderr.startswith(f"cspace: warning: {planar}:3: Drake's URDF parser moves")
    assert run.stderr.endswith("[drake-urdf-differs]\n") and run.stderr.count("\n") == 1
    turned = _write(tmp_path, "turned", FILES["floating_turned"][0])
    run = run_cli("convert", str(turned), "-", "--from", "canonical", "--to", "drake",
                  stdin=b"[0, 0, 0, 1, 0, 0, 0, 0.5]\n")  # fmt: skip
    assert run.code == 0 and run.stderr == "", run.stderr
    space = cspace.load(turned)
    expected = space.conventions().to_drake([0, 0, 0, 1, 0, 0, 0, 0.5])
    np.testing.assert_allclose(json.loads(run.stdout), expected, atol=1e-15)
    assert json.loads(run.stdout)[4:7] == pytest.approx([0.3, -1.0, 2.0])


@pytest.mark.parametrize(
    ("origin", "kind", "problem"),
    [
        ([0, 0, 1, 2, 0, 0, 0], "floating", "not unit"),
        ([0, 0, 1, 1, 0, 0, 0], "revolute", "only a floating one has an origin"),
    ],
)
def test_a_saved_reports_origin_is_checked(
    tmp_path: Path, origin: list[float], kind: str, problem: str
) -> None:
    path = _write(tmp_path, "turned", FILES["floating_turned"][0])
    document = cspace.inspect(path).to_dict()
    joint = next(j for j in document["joints"] if j["kind"] == kind)
    joint["origin"] = origin
    saved = tmp_path / "saved.json"
    saved.write_text(json.dumps(document))
    run = run_cli("diff", str(saved), str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert problem in run.stderr and "/origin" in run.stderr and "[bad-report]" in run.stderr
