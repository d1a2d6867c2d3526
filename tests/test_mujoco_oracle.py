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

import json
import re
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

import cspace
from cspace.conventions import Conventions

from conftest import REPO, run_cli

MJCF_FILES = sorted(
    path.relative_to(REPO)
    for folder in ("robots", "tests")
    for path in (REPO / folder).rglob("*.xml")
    if re.search(rb"<mujoco[\s>]", path.read_bytes())  # an MJCF root, not <mujocoinclude>
    and path.name != "unreachable.xml"  # a mechanism that cannot assemble: no space
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


def linear_ties(model: mujoco.MjModel) -> dict[int, tuple[int, int]]:
    """``{constraint: (joint1, joint2)}`` of MuJoCo's joint equalities that may make a
    mimic joint: in force at the start, with a ``joint2`` and a linear ``polycoef``."""
    if model.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_EQUALITY:
        return {}
    return {
        e: (int(model.eq_obj1id[e]), int(model.eq_obj2id[e]))
        for e in range(model.neq)
        if model.eq_type[e] == mujoco.mjtEq.mjEQ_JOINT
        and model.eq_active0[e]
        and model.eq_obj2id[e] >= 0
        and not any(model.eq_data[e][2:5])
    }


def tie_residuals(model: mujoco.MjModel, qpos: np.ndarray) -> dict[int, float]:
    """MuJoCo's own residual (``efc_pos``) of each equality constraint in force at qpos."""
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    rows = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    return {int(e): float(r) for e, r in zip(data.efc_id[rows], data.efc_pos[rows], strict=True)}


def mimics_of(report: cspace.Report) -> dict[int, tuple[int, float, float]]:
    """``{follower's qposadr: (leader's qposadr, multiplier, offset)}`` as cspace reads them."""
    at = {j.name: j.qposadr for j in report.joints}
    return {
        j.qposadr: (at[j.mimic.joint], j.mimic.multiplier, j.mimic.offset)
        for j in report.joints
        if j.mimic is not None and j.qposadr is not None
    }


def dependent(report: cspace.Report) -> list[int]:
    """The qpos entries of the mimic joints Pinocchio's q does not have."""
    return sorted(
        j.qposadr
        for j in report.joints
        if j.kind is cspace.JointKind.MIMIC and j.q_index is None and j.qposadr is not None
    )


def _tie_path(ties: dict[int, tuple[int, int]], follower: int, leader: int) -> list[int]:
    """The constraints from ``follower`` to ``leader`` along MuJoCo's ties, or []."""
    paths = {follower: []}
    todo = [follower]
    while todo:
        joint = todo.pop()
        for e, (first, second) in ties.items():
            if first == joint and second not in paths:
                paths[second] = [*paths[joint], e]
                todo.append(second)
    return paths.get(leader, [])


@pytest.mark.parametrize("relative", MJCF_FILES, ids=str)
def test_the_report_follows_mujocos_compiled_model(relative: Path) -> None:
    model = mujoco.MjModel.from_xml_path(str(REPO / relative))
    report = cspace.inspect(REPO / relative)
    joints = [j for j in report.joints if j.qposadr is not None]
    names = _joint_names(model)
    assert [j.name for j in joints] == names
    kept, ties = len(dependent(report)), linear_ties(model)
    assert (report.nq, report.nv) == (model.nq - kept, model.nv - kept)
    mimics = 0
    for k, joint in enumerate(joints):
        jnt_type = mujoco.mjtJoint(model.jnt_type[k])
        assert (joint.qposadr, joint.dofadr) == (model.jnt_qposadr[k], model.jnt_dofadr[k])
        if joint.mimic is not None:  # a mimic joint: MuJoCo's ties lead to its leader
            assert joint.kind is cspace.JointKind.MIMIC
            assert _tie_path(ties, k, names.index(joint.mimic.joint)), joint.name
            mimics += 1
            continue
        assert joint.kind in KIND_OF_TYPE[jnt_type], joint.name
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
    assert report.dimension == model.nv - mimics
    codes = [d.code for d in report.diagnostics if d.code.startswith("equality-")]
    assert codes.count("equality-mimic") == mimics
    assert [c.replace("equality-mimic", "equality-joint") for c in codes] == [
        EQUALITY_CODE[mujoco.mjtEq(t)] for t in model.eq_type
    ]


def sampled(space: cspace.ConfigurationSpace, n: int) -> np.ndarray:
    """``n`` configurations, each unbounded line coordinate within [-2, 2]."""
    free = {c.name: (-2.0, 2.0) for c in space.coordinates if c.lower == -np.inf}
    return space.sample(n, np.random.default_rng(4), free)


@pytest.mark.parametrize("relative", MJCF_FILES, ids=str)
def test_mimic_joints_hold_mujocos_own_constraints(relative: Path) -> None:
    """Each configuration written as qpos (followers set from leaders) is one where
    MuJoCo finds no error in the ties that made the mimic joints: MuJoCo, not a copy of
    cspace's formula, says the relations (qpos0 folded in, chains composed) are right."""
    model = mujoco.MjModel.from_xml_path(str(REPO / relative))
    report = cspace.inspect(REPO / relative)
    space = cspace.ConfigurationSpace.from_report(report)
    names = _joint_names(model)
    ties = linear_ties(model)
    held = [
        e
        for j in report.joints
        if j.mimic is not None
        for e in _tie_path(ties, names.index(j.name), names.index(j.mimic.joint))
    ]
    qpos = Conventions.of(space).to_mujoco(sampled(space, 20))
    for row in qpos:
        residuals = tie_residuals(model, row)
        assert all(abs(residuals[e]) < 1e-9 for e in held), residuals


EQUALITY_CODE = {
    mujoco.mjtEq.mjEQ_CONNECT: "equality-connect",
    mujoco.mjtEq.mjEQ_WELD: "equality-weld",
    mujoco.mjtEq.mjEQ_JOINT: "equality-joint",
    mujoco.mjtEq.mjEQ_TENDON: "equality-tendon",
}


def test_equality_findings_name_the_joints_of_each_loop() -> None:
    report = cspace.inspect(REPO / "robots" / "mjcf_equality.xml")
    found = {(d.code, d.joint): d for d in report.diagnostics}
    assert "joint 'finger_left'" in found["equality-mimic", "finger_right"].message
    assert "(qpos[2])" in found["equality-mimic", "finger_right"].message
    assert "joint 'gear_in'" in found["equality-mimic", "gear_out"].message
    assert "degree above 1" in found["equality-joint", "cam"].message
    assert "(rod_hinge, arm_pitch)" in found["equality-connect", "rod_hinge"].message
    assert "(lid_hinge)" in found["equality-weld", "lid_hinge"].message
    # The linear ties make mimic joints; the others leave the joint space's normal form.
    assert report.manifold.notation == "R^6"
    kinds = {j.name: j.kind.value for j in report.joints}
    assert kinds["finger_right"] == kinds["gear_out"] == "mimic" and kinds["cam"] == "prismatic"


def test_a_linear_tie_maps_to_qpos_as_mujoco_moves_it() -> None:
    """gear_out's offset folds in both refs: MuJoCo's own simulation holds the relation."""
    path = REPO / "robots" / "mjcf_equality.xml"
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    data.qpos[model.joint("gear_in").qposadr[0]] = 0.7
    for _ in range(2000):  # the soft constraint pulls gear_out onto the line
        mujoco.mj_step(model, data)
    space = cspace.load(path)
    x = Conventions.of(space).from_mujoco(data.qpos)
    qpos = Conventions.of(space).to_mujoco(x)
    out = model.joint("gear_out").qposadr[0]
    np.testing.assert_allclose(qpos[out], data.qpos[out], atol=1e-3)


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


def _on_the_curve(report: cspace.Report, qpos: np.ndarray) -> np.ndarray:
    """``qpos`` (..., nq) with each mimic joint set from its leader, as cspace reads it."""
    for follower, (leader, multiplier, offset) in mimics_of(report).items():
        qpos[..., follower] = multiplier * qpos[..., leader] + offset
    return qpos


def _pinocchio_q(model: mujoco.MjModel, qpos: np.ndarray, skipped: list[int]) -> np.ndarray:
    """MuJoCo's qpos in Pinocchio's q: each quaternion from w-first to w-last, without
    the ``skipped`` entries (of the mimic joints Pinocchio's q does not hold)."""
    q = qpos.copy()
    for k in range(model.njnt):
        jnt_type = mujoco.mjtJoint(model.jnt_type[k])
        adr = model.jnt_qposadr[k] + (3 if jnt_type == mujoco.mjtJoint.mjJNT_FREE else 0)
        if jnt_type in (mujoco.mjtJoint.mjJNT_FREE, mujoco.mjtJoint.mjJNT_BALL):
            q[adr : adr + 4] = np.roll(qpos[adr : adr + 4], -1)
    return np.delete(q, skipped)


def misplaced_body(
    model: mujoco.MjModel,
    built: Any,
    rng: np.random.Generator,
    samples: int,
    report: cspace.Report,
) -> str | None:
    """The first body Pinocchio's model places elsewhere than MuJoCo (1e-9), or None
    (on random configurations, each mimic joint of ``report`` set from its leader)."""
    import pinocchio as pin

    data, pin_data = mujoco.MjData(model), built.createData()
    for _ in range(samples):
        data.qpos[:] = _on_the_curve(report, _random_qpos(model, rng))
        mujoco.mj_kinematics(model, data)
        q = _pinocchio_q(model, data.qpos, dependent(report))
        pin.framesForwardKinematics(built, pin_data, q)
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
    joints = [j for j in report.joints if j.qposadr is not None]
    assert [(j.qposadr, j.dofadr) for j in joints] == [
        (model.jnt_qposadr[k], model.jnt_dofadr[k]) for k in range(model.njnt)
    ]
    # cspace's layout is MuJoCo's: Pinocchio's q index is the joint's qposadr, less the
    # entries of the mimic joints before it.
    skipped = dependent(report)
    for joint in joints:
        if joint.qposadr not in skipped:
            assert joint.q_index == joint.qposadr - sum(s < joint.qposadr for s in skipped)
    assert misplaced_body(model, built, np.random.default_rng(7), 10, report) is None


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
    space_report = cspace.inspect(REPO / relative)
    followers = sorted(mimics_of(space_report))
    assert space.size == model.nq - len(followers)  # a mimic joint has no coordinate
    rng = np.random.default_rng(11)
    qpos = np.stack([_random_qpos(model, rng) for _ in range(5)])
    unlimited_hinges = [
        model.jnt_qposadr[k]
        for k in range(model.njnt)
        if model.jnt_type[k] == mujoco.mjtJoint.mjJNT_HINGE and not model.jnt_limited[k]
    ]
    qpos[:, unlimited_hinges] = rng.uniform(-np.pi, np.pi, (5, len(unlimited_hinges)))
    qpos = _on_the_curve(space_report, qpos)
    x = np.delete(qpos, followers, axis=1)
    assert np.all(space.contains(x))
    expected = np.stack([_pinocchio_q(model, row, dependent(space_report)) for row in qpos])
    q = space.to_pinocchio(x)
    # Pinocchio keeps an MJCF hinge as one angle, as MuJoCo does: q is qpos reordered.
    np.testing.assert_allclose(q, expected, atol=1e-12)
    np.testing.assert_allclose(space.from_pinocchio(q), x, atol=1e-12)
    conventions = Conventions.of(space)  # and back to qpos, followers set from leaders
    np.testing.assert_allclose(conventions.to_mujoco(x), qpos, atol=1e-12)
    np.testing.assert_allclose(conventions.from_mujoco(qpos), x, atol=1e-12)


def test_a_mimic_joint_keeps_its_qpos_entry_in_the_report_and_its_saved_form() -> None:
    path = REPO / "robots" / "mjcf_equality.xml"
    model = mujoco.MjModel.from_xml_path(str(path))
    saved = json.loads(run_cli("inspect", str(path), "--format", "json").stdout)
    space = cspace.ConfigurationSpace.from_report(cspace.Report.from_dict(saved))
    names = Conventions.of(space).names("mujoco")
    assert len(names) == model.nq and names[model.joint("gear_out").qposadr[0]] == "gear_out"
    table = run_cli("inspect", str(path)).stdout.splitlines()
    header = next(line for line in table if line.startswith("joint "))
    assert header.split() == ["joint", "kind", "space", "limits", "q", "v", "qpos"]
    gear_out = next(line for line in table if line.startswith("gear_out "))
    assert gear_out.split()[-3:] == ["-", "-", "6"]  # no q or v of its own; qpos[6]
