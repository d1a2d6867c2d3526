"""PyBullet as a convention (``--to pybullet``), with PyBullet itself as the oracle.

For every URDF of the test corpora (the teaching robots, example-robot-data's, pybullet's
data): cspace's joint table (`Conventions.pybullet`) is ``p.getJointInfo``'s, joint by
joint (name, type, child link, parent index, ``qIndex``, ``uIndex``), and its names
(``names("pybullet")``) follow it. For a selection of them, a configuration converted
to PyBullet's vectors and set with ``resetBasePositionAndOrientation``,
``resetJointState`` and ``resetJointStateMultiDof`` places every link
(``getLinkState(computeForwardKinematics=True)``) where Pinocchio places it for the same
configuration, within PyBullet's float32 precision. One DIRECT client for the module.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin
import pybullet as p
import pybullet_data
import pytest

import cspace
from cspace._formats.shared.erd import robots_dir, urdf_files

from conftest import REPO, ROBOTS, run_cli

PYBULLET_DATA = Path(pybullet_data.getDataPath())
TYPES = {0: "revolute", 1: "prismatic", 2: "spherical", 3: "planar", 4: "fixed"}
"""``p.JOINT_REVOLUTE`` .. ``p.JOINT_FIXED``: a continuous joint is revolute there."""


def _corpus() -> list[tuple[str, Path, str | None]]:
    cases: list[tuple[str, Path, str | None]] = [
        (f"robots/{path.name}", path, None) for path in sorted(ROBOTS.glob("*.urdf"))
    ]
    cases += [
        ("robots/quadruped_nobase.urdf-floating", ROBOTS / "quadruped_nobase.urdf", "floating"),
        ("docs/examples/order.urdf", REPO / "docs" / "examples" / "order.urdf", None),
    ]
    cases += [(f"erd/{path.relative_to(robots_dir())}", path, None) for path in urdf_files()]
    cases += [
        (f"pybullet_data/{path.relative_to(PYBULLET_DATA)}", path, None)
        for path in sorted(PYBULLET_DATA.rglob("*.urdf"))
    ]
    return cases


CORPUS = _corpus()


@pytest.fixture(scope="module")
def client() -> Iterator[int]:
    """One PyBullet server in this process, without a window; its C printing silenced."""
    saved = os.dup(1)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    try:
        handle = p.connect(p.DIRECT)
    finally:
        os.dup2(saved, 1)
    p.setAdditionalSearchPath(str(PYBULLET_DATA), physicsClientId=handle)
    yield handle
    p.disconnect(handle)
    os.close(saved)
    os.close(null)


def _kinematics(path: Path) -> str:
    """The URDF without its ``<visual>`` and ``<collision>`` elements (PyBullet's time is
    in their meshes; the joints' indices, frames and inertials are the file's)."""
    text = path.read_text().strip().rstrip("\x00")  # what urdfdom and tinyxml2 forgive
    root = ElementTree.fromstring(text.replace('version="0.0"', 'version="1.0"', 1))
    for link in root.iter("link"):
        for shape in [*link.findall("visual"), *link.findall("collision")]:
            link.remove(shape)
    return ElementTree.tostring(root, encoding="unicode")


def _both(
    client: int, case: str, root: str | None
) -> tuple[Any, Any, int, Any, dict[str, int], Any]:
    """The robot as cspace's space and conventions, PyBullet's body and Pinocchio's model
    (its links' frames by name), and bounds for the coordinates without limits."""
    path = _path(case)
    space = cspace.load(path, root)
    conventions = space.conventions()
    body = _quiet_load(client, path, fixed=not conventions.pybullet.free)
    model = cspace.pinocchio_model(path, root)
    frames = {f.name: i for i, f in enumerate(model.frames) if f.type == pin.FrameType.BODY}
    free = {c.name: (-2.0, 2.0) for c in space.coordinates if np.isinf(c.lower) and not c.wraps}
    return space, conventions, body, model, frames, free


def _quiet_load(handle: int, path: Path, fixed: bool) -> int:
    """``p.loadURDF`` of the file's kinematics, its warnings (printed on the C side) kept
    out of the log."""
    folder = Path(tempfile.mkdtemp())
    bare = folder / path.name
    bare.write_text(_kinematics(path))
    saved = os.dup(1), os.dup(2)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    try:
        return p.loadURDF(str(bare), useFixedBase=fixed, physicsClientId=handle)
    finally:
        bare.unlink()
        folder.rmdir()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, null):
            os.close(fd)


def _table(handle: int, body: int) -> list[tuple[str, str, str, int, int, int]]:
    rows = []
    for index in range(p.getNumJoints(body, physicsClientId=handle)):
        info = p.getJointInfo(body, index, physicsClientId=handle)
        name, link = info[1].decode(), info[12].decode()
        rows.append((name, TYPES[info[2]], link, info[16], info[3], info[4]))
    return rows


def _ours(space: cspace.ConfigurationSpace) -> list[tuple[str, str, str, int, int, int]]:
    order = space.conventions().pybullet
    kinds = {"continuous": "revolute", "mimic": "?"}
    rows = []
    for joint in order.joints:
        kind = kinds.get(joint.kind.value, joint.kind.value)
        rows.append((joint.name, kind, joint.link, joint.parent, joint.q_index, joint.u_index))
    return rows


def _load(path: Path, root: str | None) -> cspace.ConfigurationSpace | None:
    try:
        return cspace.load(path, root)
    except cspace.CspaceError:
        return None  # a file cspace refuses (test_erd and the sweeps say why)


def test_every_urdf_of_the_corpora_is_numbered_as_pybullet_numbers_it(client: int) -> None:
    """Joint by joint, ``getJointInfo``: name, type, link, parent, qIndex, uIndex.

    A mimic follower is whatever PyBullet makes of its joint (it ignores ``<mimic>``: a
    joint of its own); a file's floating joint is fixed in PyBullet and the base below
    it, as ``pybullet-floating-fixed`` says.
    """
    compared = refused = 0
    for name, path, root in CORPUS:
        space = _load(path, root)
        if space is None:
            continue
        try:
            ours = _ours(space)
        except cspace.JointMatchError as exc:
            kinds = {j.kind.value for j in space.report_joints}
            assert "planar" in kinds or "floating" in kinds, (name, str(exc))
            refused += 1
            continue
        order = space.conventions().pybullet
        body = _quiet_load(client, path, fixed=not order.free)
        theirs = _table(client, body)
        codes = [d.code for d in order.findings]
        if "pybullet-floating-fixed" in codes:
            (finding,) = [d for d in order.findings if d.code == "pybullet-floating-fixed"]
            assert theirs[0][:2] == (finding.joint, "fixed"), name
            theirs = [
                (n, t, link, parent - 1, q, u) for n, t, link, parent, q, u in theirs[1:]
            ]  # the floating joint's child is the base
        assert len(ours) == len(theirs), name
        for mine, pybullet in zip(ours, theirs, strict=True):
            if mine[1] == "?":  # a follower: its own joint in PyBullet, free
                assert pybullet[1] in ("revolute", "prismatic") and pybullet[4] >= 0, name
                mine = (mine[0], pybullet[1], *mine[2:])
            assert mine == pybullet, (name, mine, pybullet)
        followers = [d.joint for d in order.findings if d.code == "pybullet-mimic-free"]
        assert followers == [j.name for j in order.joints if j.kind.value == "mimic"], name
        names = space.conventions().names("pybullet")
        shift = 0 if order.free else 7
        for joint in order.joints:
            if joint.moves and joint.kind.value != "spherical":
                assert names[joint.q_index - shift] == joint.name, name
        p.removeBody(body, physicsClientId=client)
        compared += 1
    assert compared == 1163 and refused == 1  # mobile_manipulator.urdf: a planar base


FK_CASES = [
    ("robots/arm7.urdf", None),
    ("robots/gripper_mimic.urdf", None),
    ("robots/quadruped_nobase.urdf", "floating"),
    ("robots/turntable_multiturn.urdf", None),
    ("robots/sensor_head_fixed.urdf", "floating"),
    ("erd/ur_description/urdf/ur5_robot.urdf", None),
    ("erd/panda_description/urdf/panda.urdf", "floating"),
    ("pybullet_data/kuka_iiwa/model.urdf", None),
    ("pybullet_data/r2d2.urdf", "floating"),
    ("pybullet_data/laikago/laikago_toes.urdf", "floating"),
]


def _path(case: str) -> Path:
    where, _, rest = case.partition("/")
    return {"robots": ROBOTS, "erd": robots_dir(), "pybullet_data": PYBULLET_DATA}[where] / rest


def _set(handle: int, body: int, order: Any, q: np.ndarray) -> None:
    """Put PyBullet's body at q: the base (its inertial frame), then every moving joint."""
    shift = 0
    if order.free:
        inertial = p.getDynamicsInfo(body, -1, physicsClientId=handle)[3:5]
        where, turn = p.multiplyTransforms(q[:3], q[3:7], *inertial)
        p.resetBasePositionAndOrientation(body, where, turn, physicsClientId=handle)
    else:
        shift = 7
    for joint in order.joints:
        if not joint.moves:
            continue
        at = joint.q_index - shift
        if joint.kind.value == "spherical":
            value = list(q[at : at + 4])
            p.resetJointStateMultiDof(body, joint.index, value, physicsClientId=handle)
        else:
            p.resetJointState(body, joint.index, float(q[at]), physicsClientId=handle)


@pytest.mark.parametrize(("case", "root"), FK_CASES, ids=[c for c, _ in FK_CASES])
def test_pybullet_places_every_link_where_pinocchio_does(
    client: int, case: str, root: str | None
) -> None:
    """Random configurations (seeded) converted by cspace: every link's frame in the
    world, PyBullet's ``worldLinkFramePosition`` and ``worldLinkFrameOrientation``
    against Pinocchio's, within 1e-6 m and 1e-6 (PyBullet reads the file in float32:
    4.7e-7 at most here)."""
    space, conventions, body, model, frames, free = _both(client, case, root)
    order, data, rng = conventions.pybullet, model.createData(), np.random.default_rng(41)
    worst = 0.0
    for x in space.sample(5, rng, bounds=free):
        q = conventions.to_pybullet(x)
        np.testing.assert_allclose(conventions.from_pybullet(q), x, atol=1e-12)
        _set(client, body, order, q)
        pin.framesForwardKinematics(model, data, conventions.to_pinocchio(x))
        for joint in order.joints:
            state = p.getLinkState(
                body, joint.index, computeForwardKinematics=True, physicsClientId=client
            )
            placed = data.oMf[frames[joint.link]]
            turn = np.array(p.getMatrixFromQuaternion(state[5])).reshape(3, 3)
            worst = max(worst, float(np.abs(np.array(state[4]) - placed.translation).max()))
            worst = max(worst, float(np.abs(turn - placed.rotation).max()))
    p.removeBody(body, physicsClientId=client)
    assert 0.0 < worst < 1e-6, worst


def test_the_findings_say_what_pybullet_does(client: int) -> None:
    """The mimic follower moves alone in PyBullet; the floating joint is fixed there."""
    space = cspace.load(ROBOTS / "gripper_mimic.urdf")
    (finding,) = space.conventions().pybullet.findings
    assert finding.code == "pybullet-mimic-free" and finding.line is not None
    body = _quiet_load(client, ROBOTS / "gripper_mimic.urdf", fixed=True)
    leader, follower = (j for j in space.conventions().pybullet.joints if j.moves)
    p.resetJointState(body, leader.index, 0.02, physicsClientId=client)
    assert p.getJointState(body, follower.index, physicsClientId=client)[0] == 0.0
    p.removeBody(body, physicsClientId=client)
    floating = cspace.load(ROBOTS / "quadrotor_floating.urdf").conventions().pybullet
    assert [d.code for d in floating.findings] == ["pybullet-floating-fixed"]
    assert floating.free and floating.base == "body" and floating.floats is None


def test_a_fixed_base_floats_in_pybullet_unless_told(client: int) -> None:
    """``floats`` names the base PyBullet floats by default; it falls when nothing holds it."""
    order = cspace.load(ROBOTS / "arm7.urdf").conventions().pybullet
    assert order.floats == "base_link" and not order.free
    body = _quiet_load(client, ROBOTS / "arm7.urdf", fixed=False)
    p.setGravity(0, 0, -10, physicsClientId=client)
    for _ in range(20):
        p.stepSimulation(physicsClientId=client)
    assert p.getBasePositionAndOrientation(body, physicsClientId=client)[0][2] < -0.01
    p.setGravity(0, 0, 0, physicsClientId=client)
    p.removeBody(body, physicsClientId=client)


def test_continuous_joints_and_lower_above_upper_are_pybullets_no_limit(client: int) -> None:
    """PyBullet reports a continuous joint's limits as lower 0, upper -1: its sentinel for
    none (any lower > upper is unlimited there); cspace's canonical angle wraps."""
    path = ROBOTS / "turntable_multiturn.urdf"
    space = cspace.load(path)
    body = _quiet_load(client, path, fixed=True)
    for joint in space.conventions().pybullet.joints:
        info = p.getJointInfo(body, joint.index, physicsClientId=client)
        if joint.kind.value == "continuous":
            assert (info[8], info[9]) == (0.0, -1.0)
    p.removeBody(body, physicsClientId=client)


def test_convert_to_pybullet_on_the_command_line(tmp_path: Path) -> None:
    """Names as the CSV header, PyBullet's order, the findings on standard error."""
    path = ROBOTS / "gripper_mimic.urdf"
    (tmp_path / "x.jsonl").write_text("[0.02]\n")
    run = run_cli(
        "convert", str(path), "x.jsonl", "--from", "canonical", "--to", "pybullet",
        "--format", "csv", cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 0, run.stderr
    assert run.stdout.splitlines()[0] == "left_finger_joint,right_finger_joint"
    assert "[pybullet-mimic-free]" in run.stderr and "gripper_mimic.urdf:" in run.stderr
    assert "PyBullet floats link 'mount'" in run.stderr
    back = run_cli(
        "convert", str(path), "-", "--from", "pybullet", "--to", "canonical", cwd=tmp_path,
        stdin=(json.dumps([0.01, 0.5]) + "\n").encode(),
    )  # fmt: skip
    assert back.code == 0 and json.loads(back.stdout) == [0.01]


def test_the_findings_names_reach_no_ci_log_as_commands(tmp_path: Path) -> None:
    """A mimic follower, its leader and the base named as workflow commands: the notes
    and warnings ``convert --to pybullet`` writes on standard error are escaped."""
    from test_ci_log import CARRIED, EVIL, assert_no_command, assert_printable

    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    (tmp_path / "r.urdf").write_text(
        f'<robot name="r"><link name="{EVIL}base"/><link name="a"/><link name="b"/>\n'
        f'<joint name="{EVIL}lead" type="revolute"><parent link="{EVIL}base"/>'
        f'<child link="a"/>{limit}</joint>\n'
        f'<joint name="{EVIL}follow" type="revolute"><parent link="{EVIL}base"/>'
        f'<child link="b"/>{limit}<mimic joint="{EVIL}lead"/></joint>\n</robot>'
    )
    (tmp_path / "x.jsonl").write_text("[0.5]\n")
    run = run_cli(
        "convert", "r.urdf", "x.jsonl", "--from", "canonical", "--to", "pybullet",
        "--format", "csv", cwd=tmp_path,
    )  # fmt: skip
    assert run.code == 0, run.stderr
    for text in (run.stdout, run.stderr):
        assert_no_command(text)
        assert_printable(text)
    assert "[pybullet-mimic-free]" in run.stderr and "r.urdf:3:" in run.stderr
    assert all(carried in run.stdout for carried in CARRIED)  # the CSV header
    assert CARRIED[1] in run.stderr and "\\n::error::y" in run.stderr


VELOCITY_CASES = [
    ("robots/arm7.urdf", None),
    ("robots/quadruped_nobase.urdf", "floating"),
    ("pybullet_data/r2d2.urdf", "floating"),
    ("pybullet_data/laikago/laikago_toes.urdf", "floating"),  # the trunk's centre of mass
]  # off its frame: resetBaseVelocity's linear velocity is not the frame's


@pytest.mark.parametrize(("case", "root"), VELOCITY_CASES, ids=[c for c, _ in VELOCITY_CASES])
def test_pybullet_moves_every_link_as_pinocchio_does(
    client: int, case: str, root: str | None
) -> None:
    """A tangent vector converted to PyBullet's velocities (the base's through
    ``resetBaseVelocity``, which takes its centre of mass's, the joints' through
    ``resetJointState``): every link's velocity from ``getLinkState(...,
    computeLinkVelocity=True)`` is Pinocchio's at that link's centre of mass."""
    space, conventions, body, model, frames, free = _both(client, case, root)
    order, data, rng = conventions.pybullet, model.createData(), np.random.default_rng(42)
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for x in space.sample(3, rng, bounds=free):
        dx = rng.normal(size=space.dimension)
        q, u = conventions.to_pybullet(x), conventions.to_pybullet_velocity(x, dx)
        np.testing.assert_allclose(conventions.from_pybullet_velocity(x, u), dx, atol=1e-12)
        _set(client, body, order, q)
        shift = 0 if order.free else 7
        if order.free:
            turn = np.array(p.getMatrixFromQuaternion(q[3:7])).reshape(3, 3)
            offset = turn @ np.array(p.getDynamicsInfo(body, -1, physicsClientId=client)[3])
            linear = u[:3] + np.cross(u[3:6], offset)
            p.resetBaseVelocity(body, linear.tolist(), u[3:6].tolist(), physicsClientId=client)
        for joint in order.joints:  # the positions again, with the velocities
            if joint.moves:
                at, rate = joint.q_index - shift, joint.u_index - (0 if order.free else 6)
                p.resetJointState(
                    body, joint.index, float(q[at]), float(u[rate]), physicsClientId=client
                )
        v = conventions.to_pinocchio_velocity(x, dx)
        pin.forwardKinematics(model, data, conventions.to_pinocchio(x), v)
        pin.updateFramePlacements(model, data)
        for joint in order.joints:
            state = p.getLinkState(
                body, joint.index, computeLinkVelocity=True, computeForwardKinematics=True,
                physicsClientId=client,
            )  # fmt: skip
            frame = frames[joint.link]
            motion = pin.getFrameVelocity(model, data, frame, world)
            com = data.oMf[frame].rotation @ np.array(
                p.getDynamicsInfo(body, joint.index, physicsClientId=client)[3]
            )
            expected = motion.linear + np.cross(motion.angular, com)
            np.testing.assert_allclose(state[7], motion.angular, atol=1e-5)
            np.testing.assert_allclose(state[6], expected, atol=1e-5)
    p.removeBody(body, physicsClientId=client)


def test_what_pybullet_stores_otherwise_is_refused_by_name(tmp_path: Path) -> None:
    """A planar root, several free bodies, and a xacro tree whose siblings' declaration
    order (PyBullet's) its report does not keep: each a `JointMatchError` naming why."""
    refused = [
        (cspace.load(ROBOTS / "arm7.urdf", "planar"), "joint 'root_joint' is planar"),
        (cspace.load(ROBOTS / "mobile_manipulator.urdf"), "joint 'base_planar' is planar"),
        (cspace.load(ROBOTS / "mjcf_scene_objects.xml"), "one free base"),
    ]
    order = (REPO / "docs" / "examples" / "order.urdf").read_text()
    xacro = tmp_path / "order.urdf.xacro"
    xacro.write_text(
        order.replace(
            '<robot name="order">',
            '<robot name="order" xmlns:xacro="http://www.ros.org/wiki/xacro">',
        )
    )
    refused.append((cspace.load(xacro), "expand it to a URDF"))
    for space, said in refused:
        with pytest.raises(cspace.JointMatchError, match=said):
            space.conventions().names("pybullet")


def test_the_bases_names_step_aside_for_a_joints(tmp_path: Path) -> None:
    """A joint named as the base's entries are (``b_x``): the base's get a ``_`` first."""
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="b"/><link name="c"/><joint name="b_x" type="continuous">'
        '<parent link="b"/><child link="c"/></joint></robot>'
    )
    names = cspace.load(tmp_path / "r.urdf", "floating").conventions().names("pybullet")
    assert names == ("_b_x", "_b_y", "_b_z", "_b_qx", "_b_qy", "_b_qz", "_b_qw", "b_x")
