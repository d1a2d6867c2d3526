"""MuJoCo, the authority on MJCF, against cspace's report of every MJCF file in the repo.

For each file that MuJoCo compiles (the teaching robots compile: every moving body has
mass), the report must follow MuJoCo's compiled model: the same joints in the same
order, each joint's kind from ``jnt_type`` and ``jnt_limited``, its limits from
``jnt_range`` (MuJoCo applies the angle unit), and q and v slices at MuJoCo's
``jnt_qposadr`` and ``jnt_dofadr`` (Pinocchio's layout, which cspace reports, is
MuJoCo's for these files: a hinge keeps one angle, a ball and a free joint's rotation a
quaternion). The files are the repository's own, read by MuJoCo directly.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

import cspace

from conftest import REPO, run_cli

MJCF_FILES = sorted(
    path.relative_to(REPO)
    for folder in ("robots", "tests")
    for path in (REPO / folder).rglob("*.xml")
    if re.search(rb"<mujoco[\s>]", path.read_bytes())  # an MJCF root, not <mujocoinclude>
)

KIND_OF_TYPE = {
    mujoco.mjtJoint.mjJNT_FREE: {cspace.JointKind.FLOATING},
    mujoco.mjtJoint.mjJNT_BALL: {cspace.JointKind.SPHERICAL},
    mujoco.mjtJoint.mjJNT_SLIDE: {cspace.JointKind.PRISMATIC},
    mujoco.mjtJoint.mjJNT_HINGE: {cspace.JointKind.REVOLUTE, cspace.JointKind.CONTINUOUS},
}


def test_the_repository_has_mjcf_files_for_mujoco() -> None:
    assert Path("robots/mjcf_every_joint.xml") in MJCF_FILES
    assert len(MJCF_FILES) >= 5


def _body_name(model: mujoco.MjModel, body: int) -> str:
    """MuJoCo's name of a body, or the documented made-up one: body<ID>."""
    return mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, body) or f"body{body}"


def _joint_names(model: mujoco.MjModel) -> list[str]:
    """MuJoCo's joint names, unnamed ones as documented: <BODY>Joint_<K>."""
    names = []
    for k in range(model.njnt):
        body = model.jnt_bodyid[k]
        position = k - model.body_jntadr[body]
        given = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, k)
        names.append(given or f"{_body_name(model, body)}Joint_{position}")
    return names


@pytest.mark.parametrize("relative", MJCF_FILES, ids=str)
def test_the_report_follows_mujocos_compiled_model(relative: Path) -> None:
    model = mujoco.MjModel.from_xml_path(str(REPO / relative))
    report = cspace.inspect(REPO / relative)
    moving = [j for j in report.joints if j.q_index is not None]
    assert [j.name for j in moving] == _joint_names(model)
    assert (report.nq, report.nv) == (model.nq, model.nv)
    for k, joint in enumerate(moving):
        jnt_type = mujoco.mjtJoint(model.jnt_type[k])
        assert joint.kind in KIND_OF_TYPE[jnt_type], joint.name
        assert (joint.q_index, joint.v_index) == (model.jnt_qposadr[k], model.jnt_dofadr[k])
        limited = bool(model.jnt_limited[k])
        if jnt_type == mujoco.mjtJoint.mjJNT_HINGE:
            assert (joint.kind == cspace.JointKind.REVOLUTE) == limited, joint.name
        if limited and jnt_type in (mujoco.mjtJoint.mjJNT_HINGE, mujoco.mjtJoint.mjJNT_SLIDE):
            assert joint.limits is not None
            np.testing.assert_allclose(
                (joint.limits.lower[0], joint.limits.upper[0]), model.jnt_range[k], rtol=1e-12
            )
        if limited and jnt_type == mujoco.mjtJoint.mjJNT_BALL:  # a cone: 0 .. max angle
            assert joint.limits is not None
            np.testing.assert_allclose(joint.limits.upper[0], model.jnt_range[k][1], rtol=1e-12)
    assert report.dimension == model.nv
    equalities = [d.code for d in report.diagnostics if d.code.startswith("equality-")]
    assert equalities == [EQUALITY_CODE[mujoco.mjtEq(t)] for t in model.eq_type]


EQUALITY_CODE = {
    mujoco.mjtEq.mjEQ_CONNECT: "equality-connect",
    mujoco.mjtEq.mjEQ_WELD: "equality-weld",
    mujoco.mjtEq.mjEQ_JOINT: "equality-joint",
    mujoco.mjtEq.mjEQ_TENDON: "equality-tendon",
}


def test_equality_findings_name_the_joints_of_each_loop() -> None:
    report = cspace.inspect(REPO / "robots" / "mjcf_equality.xml")
    found = {d.code: d for d in report.diagnostics}
    assert found["equality-joint"].joint == "finger_right"
    assert "joint 'finger_left'" in found["equality-joint"].message
    assert "(rod_hinge, arm_pitch)" in found["equality-connect"].message
    assert "(lid_hinge)" in found["equality-weld"].message
    assert report.manifold.notation == "R^5"  # the joint space keeps its normal form


@pytest.mark.parametrize(
    "constraint",
    [
        '<joint joint1="nope"/>',
        '<weld body1="nobody"/>',
        '<connect site1="nosite" body2="b" anchor="0 0 0"/>',
    ],
)
def test_a_model_mujoco_refuses_gets_mujocos_reason(constraint: str, tmp_path: Path) -> None:
    path = tmp_path / "eq.xml"
    path.write_text(
        '<mujoco><worldbody><body name="b"><joint name="j"/><geom size=".1"/></body>'
        f"</worldbody><equality>{constraint}</equality></mujoco>"
    )
    with pytest.raises(ValueError) as oracle:
        mujoco.MjModel.from_xml_path(str(path))
    reason = str(oracle.value).splitlines()[0]
    with pytest.raises(cspace.errors.MujocoError) as refused:
        cspace.inspect(path)
    assert refused.value.code == "mujoco-refused" and refused.value.line == 1
    assert f"MuJoCo refuses the model: {reason}" in refused.value.problem
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1
    assert run.stderr.startswith(f"cspace: error: {path}:1: MuJoCo refuses the model: ")


def _random_qpos(model: mujoco.MjModel, rng: np.random.Generator) -> np.ndarray:
    """A configuration in MuJoCo's qpos: angles within limits, unit quaternions (w >= 0,
    a limited ball's within its cone)."""
    qpos = np.zeros(model.nq)
    for k in range(model.njnt):
        adr = model.jnt_qposadr[k]
        jnt_type = mujoco.mjtJoint(model.jnt_type[k])
        if jnt_type == mujoco.mjtJoint.mjJNT_FREE:
            qpos[adr : adr + 3] = rng.uniform(-1.0, 1.0, 3)
            adr += 3
        if jnt_type in (mujoco.mjtJoint.mjJNT_FREE, mujoco.mjtJoint.mjJNT_BALL):
            quaternion = rng.normal(size=4)
            if model.jnt_limited[k] and jnt_type == mujoco.mjtJoint.mjJNT_BALL:
                angle = rng.uniform(0.0, model.jnt_range[k][1])  # inside the cone
                axis = quaternion[1:] / np.linalg.norm(quaternion[1:])
                quaternion = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
            quaternion *= np.sign(quaternion[0]) or 1.0  # w >= 0: the same rotation
            qpos[adr : adr + 4] = quaternion / np.linalg.norm(quaternion)
        elif model.jnt_limited[k]:
            qpos[adr] = rng.uniform(*model.jnt_range[k])
        else:
            qpos[adr] = rng.uniform(-np.pi, np.pi)
    return qpos


def _pinocchio_q(model: mujoco.MjModel, qpos: np.ndarray) -> np.ndarray:
    """MuJoCo's qpos in Pinocchio's q: each quaternion from w-first to w-last."""
    q = qpos.copy()
    for k in range(model.njnt):
        jnt_type = mujoco.mjtJoint(model.jnt_type[k])
        adr = model.jnt_qposadr[k] + (3 if jnt_type == mujoco.mjtJoint.mjJNT_FREE else 0)
        if jnt_type in (mujoco.mjtJoint.mjJNT_FREE, mujoco.mjtJoint.mjJNT_BALL):
            q[adr : adr + 4] = np.roll(qpos[adr : adr + 4], -1)
    return q


def misplaced_body(
    model: mujoco.MjModel, built: Any, rng: np.random.Generator, samples: int
) -> str | None:
    """The first body Pinocchio's model places elsewhere than MuJoCo (1e-9), or None."""
    import pinocchio as pin

    data, pin_data = mujoco.MjData(model), built.createData()
    for _ in range(samples):
        data.qpos[:] = _random_qpos(model, rng)
        mujoco.mj_kinematics(model, data)
        pin.framesForwardKinematics(built, pin_data, _pinocchio_q(model, data.qpos))
        for body in range(1, model.nbody):
            name = _body_name(model, body)
            placement = pin_data.oMf[built.getFrameId(name, pin.FrameType.BODY)]
            rotation = data.xmat[body].reshape(3, 3)
            if not (
                np.allclose(placement.translation, data.xpos[body], rtol=0, atol=1e-9)
                and np.allclose(placement.rotation, rotation, rtol=0, atol=1e-9)
            ):
                return name
    return None


@pytest.mark.parametrize("relative", MJCF_FILES, ids=str)
def test_forward_kinematics_match_mujoco(relative: Path) -> None:
    model = mujoco.MjModel.from_xml_path(str(REPO / relative))
    built = cspace.pinocchio_model(REPO / relative)
    report = cspace.inspect(REPO / relative)
    moving = [j for j in report.joints if j.q_index is not None]
    # cspace's layout is MuJoCo's: Pinocchio's q index is the joint's qposadr.
    assert [(j.qposadr, j.dofadr) for j in moving] == [
        (model.jnt_qposadr[k], model.jnt_dofadr[k]) for k in range(model.njnt)
    ]
    assert all(j.q_index == j.qposadr for j in moving)
    assert misplaced_body(model, built, np.random.default_rng(7), 10) is None


def _cube_stl(path: Path) -> None:
    """A binary STL of a 10 cm cube (12 triangles), the format MuJoCo reads."""
    import struct

    corners = [(x, y, z) for x in (0.0, 0.1) for y in (0.0, 0.1) for z in (0.0, 0.1)]
    faces = [
        (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
        (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3),
    ]  # fmt: skip
    data = bytearray(80) + struct.pack("<I", len(faces))
    for face in faces:
        data += struct.pack("<3f", 0.0, 0.0, 0.0)
        for k in face:
            data += struct.pack("<3f", *corners[k])
        data += b"\0\0"
    path.write_bytes(bytes(data))


WITH_GEOMETRY = (
    '<asset><mesh name="link_mesh" file="meshes/link.stl"/>'
    '<texture name="wood" type="2d" file="textures/wood.png"/>'
    '<material name="wood" texture="wood"/>'
    '<hfield name="terrain" file="terrain.png" size="1 1 0.1 0.1"/></asset>'
)


def test_missing_meshes_textures_and_height_fields_change_nothing(tmp_path: Path) -> None:
    original = (REPO / "robots" / "mjcf_every_joint.xml").read_text()
    text = original.replace("<worldbody>", WITH_GEOMETRY + "<worldbody>", 1)
    text = text.replace(  # every body's geom becomes a mesh; the floor a height field
        '<geom size="0.05"/>', '<geom type="mesh" mesh="link_mesh" material="wood"/>'
    ).replace("<worldbody>", '<worldbody><geom type="hfield" hfield="terrain"/>', 1)
    robot = tmp_path / "robot.xml"
    robot.write_text(text)
    with pytest.raises(ValueError, match="Error opening file"):  # MuJoCo needs the files
        mujoco.MjModel.from_xml_path(str(robot))
    expected = cspace.inspect(REPO / "robots" / "mjcf_every_joint.xml").to_dict()
    expected.pop("source")
    without = cspace.inspect(robot).to_dict()
    without.pop("source")
    assert without == expected  # lines too: the geometry sits on the same lines
    # With the mesh there (the texture and height field left out), MuJoCo agrees.
    (tmp_path / "meshes").mkdir()
    _cube_stl(tmp_path / "meshes" / "link.stl")
    with_mesh = tmp_path / "with_mesh.xml"
    with_mesh.write_text(
        text.replace('<texture name="wood" type="2d" file="textures/wood.png"/>', "")
        .replace('<material name="wood" texture="wood"/>', '<material name="wood"/>')
        .replace('<hfield name="terrain" file="terrain.png" size="1 1 0.1 0.1"/>', "")
        .replace('<geom type="hfield" hfield="terrain"/>', "")
    )
    model = mujoco.MjModel.from_xml_path(str(with_mesh))
    report = cspace.inspect(with_mesh).to_dict()
    report.pop("source")
    assert report == expected and model.nmesh == 1 and (model.nq, model.nv) == (20, 17)


@pytest.mark.parametrize("relative", MJCF_FILES, ids=str)
def test_canonical_coordinates_are_mujocos_qpos(relative: Path) -> None:
    """A MuJoCo qpos is a configuration of cspace as it is, and maps to Pinocchio's q."""
    model = mujoco.MjModel.from_xml_path(str(REPO / relative))
    space = cspace.load(REPO / relative)
    assert space.size == model.nq
    rng = np.random.default_rng(11)
    qpos = np.stack([_random_qpos(model, rng) for _ in range(5)])
    unlimited_hinges = [
        model.jnt_qposadr[k]
        for k in range(model.njnt)
        if model.jnt_type[k] == mujoco.mjtJoint.mjJNT_HINGE and not model.jnt_limited[k]
    ]
    qpos[:, unlimited_hinges] = rng.uniform(-np.pi, np.pi, (5, len(unlimited_hinges)))
    assert np.all(space.contains(qpos))
    expected = np.stack([_pinocchio_q(model, row) for row in qpos])
    q = space.to_pinocchio(qpos)
    # Pinocchio keeps an MJCF hinge as one angle, as MuJoCo does: q is qpos reordered.
    np.testing.assert_allclose(q, expected, atol=1e-12)
    np.testing.assert_allclose(space.from_pinocchio(q), qpos, atol=1e-12)
