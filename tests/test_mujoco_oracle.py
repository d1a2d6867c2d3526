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

from pathlib import Path

import mujoco
import numpy as np
import pytest

import cspace

from conftest import REPO

MJCF_FILES = sorted(
    path.relative_to(REPO)
    for folder in ("robots", "tests")
    for path in (REPO / folder).rglob("*.xml")
    if b"<mujoco" in path.read_bytes()  # the MJCF root (a comment may come first)
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


@pytest.mark.parametrize("relative", MJCF_FILES, ids=str)
def test_the_report_follows_mujocos_compiled_model(relative: Path) -> None:
    model = mujoco.MjModel.from_xml_path(str(REPO / relative))
    report = cspace.inspect(REPO / relative)
    moving = [j for j in report.joints if j.q_index is not None]
    names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, k) for k in range(model.njnt)]
    assert [j.name for j in moving] == names
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
    ("constraint", "name"),
    [
        ('<joint joint1="nope"/>', "joint 'nope'"),
        ('<weld body1="nobody"/>', "body 'nobody'"),
        ('<connect site1="nosite" body2="b" anchor="0 0 0"/>', "site 'nosite'"),
    ],
)
def test_an_equality_naming_nothing_is_refused(constraint: str, name: str, tmp_path: Path) -> None:
    path = tmp_path / "eq.xml"
    path.write_text(
        '<mujoco><worldbody><body name="b"><joint name="j"/><geom size=".1"/></body>'
        f"</worldbody><equality>{constraint}</equality></mujoco>"
    )
    with pytest.raises(ValueError):  # MuJoCo refuses it too
        mujoco.MjModel.from_xml_path(str(path))
    with pytest.raises(cspace.InvalidElementError, match=name) as refused:
        cspace.inspect(path)
    assert refused.value.code == "unknown-name" and refused.value.line == 1
