"""OpenUSD loops: the joint that closes one is a cut of the mechanism (`usd._cuts`).

The planar four-bar of ``tests/closed/fourbar.xml`` (ground 2, crank 0.5, coupler 2,
rocker 1.5) in two stages: ``fourbar.usda``, the closing joint excluded from the
articulation as Isaac writes loops, and ``fourbar_cut.usda``, in centimetres with the
rocker scaled by 2 and no joint excluded (the reader's spanning tree cuts one, between
two moving bodies, its frames turned). Held to:

1. OpenUSD's own world transforms (``UsdGeom.XformCache`` on the bodies, computed here
   with ``pxr``): at the authored configuration the closing joint's two frames coincide,
   and the cut's frames, placed by cspace's model at its neutral configuration, are
   where OpenUSD puts them (float32: within 1e-6);
2. the geometry, written by hand here (not the reader's frames): at configurations
   projected onto the constraints, the rocker's pivot is on the ground at (2, 0, 0)
   and the coupler's tip at the rocker's pivot;
3. hand counts: the tree is T^3 (3 hinges), a revolute cut is 5 equations, so
   Grübler-Kutzbach's spatial count is 3 - 5 = -2; the planar count, 3 (4 - 1) - 2 x 4
   = 1, is the mobility (the constraint Jacobian's rank is 2).
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
from pxr import Gf, Usd, UsdGeom

import cspace
from cspace._formats.shared.description import CutSpec
from cspace._formats.usd import child
from cspace._formats.usd.reader import describe
from cspace._model.closure import LoopConstraints
from cspace.errors import RobotFileError

from conftest import REPO, run_cli, usd_stages

CLOSED = REPO / "tests" / "closed"
FOURBAR = CLOSED / "fourbar.usda"
CUT = CLOSED / "fourbar_cut.usda"
STAGES = {FOURBAR: ("ground_pivot", ("world", "rocker")), CUT: ("d_rocker", ("coupler", "rocker"))}
FLOAT32 = 1e-6


@pytest.fixture(scope="module", autouse=True)
def _stages(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """One OpenUSD child for the file: the stages written here and ``tests/closed``."""
    yield from usd_stages(tmp_path_factory, CLOSED)


def _cuts(path: Path) -> tuple[tuple[CutSpec, ...], str]:
    """The reader's cuts and root link (its description, from this process's child)."""
    facts = json.loads(child.ask({"path": str(path)}, [str(path.parent)]))
    description = describe(str(path), facts).description
    return description.cuts, description.root_link


@pytest.mark.parametrize("stage", list(STAGES), ids=lambda p: p.name)
def test_a_four_bar_s_closing_joint_is_a_revolute_cut_of_mobility_1(stage: Path) -> None:
    report = cspace.inspect(stage)
    name, links = STAGES[stage]
    assert report.manifold.notation == "T^3"  # the tree: the ambient space
    closure = report.closure
    assert closure is not None
    assert [(c.kind, c.name, c.links, c.rows) for c in closure.cuts] == [
        ("revolute", name, links, 5)
    ]
    assert closure.loops == 1 and closure.constraint_rows == 5
    assert closure.grubler == 3 - 5  # spatial count
    assert closure.mobility == 3 * (4 - 1) - 2 * 4  # the planar count: 1
    assert closure.rank == (2, 2) and closure.assembled is True
    assert closure.max_residual is not None and closure.max_residual < 1e-8
    codes = [d.code for d in report.diagnostics]
    assert "joint-left-out" not in codes and "closure-grubler-differs" in codes


def _world(stage: Any, joint: Any, side: int) -> tuple[np.ndarray, Gf.Quatd]:
    """A joint frame in the world as OpenUSD composes it (stage units)."""
    cache = UsdGeom.XformCache()
    targets = joint.GetRelationship(f"physics:body{side}").GetTargets()
    matrix = cache.GetLocalToWorldTransform(stage.GetPrimAtPath(targets[0])) if targets else None
    matrix = matrix if matrix is not None else Gf.Matrix4d(1.0)
    local = joint.GetAttribute(f"physics:localPos{side}").Get() or Gf.Vec3f(0.0)
    rot = joint.GetAttribute(f"physics:localRot{side}").Get() or Gf.Quatf(1.0)
    point = matrix.Transform(Gf.Vec3d(local))  # the body's scale applies to the anchor
    turn = matrix.RemoveScaleShear().ExtractRotationQuat() * Gf.Quatd(rot)
    return np.array(point), turn.GetNormalized()


def _matrix(q: Gf.Quatd) -> np.ndarray:
    return np.array(Gf.Matrix3d(Gf.Rotation(q)).GetTranspose())  # Gf's rows are columns


def _placed(model: Any, data: Any, link: str, pose: Any) -> Any:
    """A frame given in a link's frame, in the world of the model's last kinematics."""
    body = pin.SE3.Identity()
    if model.existFrame(link, pin.FrameType.BODY):
        body = data.oMf[model.getFrameId(link, pin.FrameType.BODY)]
    w, x, y, z = pose.rotation_wxyz
    rotation = pin.Quaternion(w, x, y, z).normalized().matrix()
    return body * pin.SE3(rotation, np.array(pose.position))


@pytest.mark.parametrize("stage", list(STAGES), ids=lambda p: p.name)
def test_the_cut_s_frames_are_where_openusd_puts_the_joint_s(stage: Path) -> None:
    opened = Usd.Stage.Open(str(stage))
    meters = UsdGeom.GetStageMetersPerUnit(opened)
    joint = opened.GetPrimAtPath(f"/fourbar/joints/{STAGES[stage][0]}")
    sides = [_world(opened, joint, k) for k in (0, 1)]
    # the file is a closed four-bar as authored: OpenUSD's two frames coincide
    assert np.allclose(sides[0][0] * meters, sides[1][0] * meters, atol=FLOAT32)
    assert np.allclose(_matrix(sides[0][1]), _matrix(sides[1][1]), atol=FLOAT32)
    cuts, root = _cuts(stage)
    (cut,) = cuts
    model = cspace.pinocchio_model(stage)
    data = model.createData()
    q = pin.neutral(model)  # the authored configuration: every joint at zero
    pin.framesForwardKinematics(model, data, q)
    for (point, turn), link, pose in zip(
        sides, (cut.link_a, cut.link_b), (cut.frame_a, cut.frame_b), strict=True
    ):
        placed = _placed(model, data, link, pose)
        assert np.allclose(placed.translation, point * meters, atol=FLOAT32)
        assert np.allclose(placed.rotation, _matrix(turn), atol=FLOAT32)
    constraints = LoopConstraints(model, cuts, root)
    assert np.abs(constraints.residual(q)).max() < FLOAT32


COUPLER_TIP = (1.74452, 0.0, 0.97808)  # in the coupler's frame, m
ROCKER_FOOT = (0.25548, 0.0, -1.47808)  # in the rocker's frame (its scale removed), m


@pytest.mark.parametrize("stage", list(STAGES), ids=lambda p: p.name)
def test_projected_configurations_close_the_four_bar_as_drawn(stage: Path) -> None:
    cuts, root = _cuts(stage)
    model = cspace.pinocchio_model(stage)
    constraints = LoopConstraints(model, cuts, root)
    data = model.createData()
    rng = np.random.default_rng(40)
    cranks = []
    for _ in range(4):
        start = pin.integrate(model, pin.neutral(model), rng.uniform(-1.0, 1.0, model.nv))
        q, residual, _ = constraints.project(start)
        assert residual < 1e-9
        pin.framesForwardKinematics(model, data, q)
        frame = {n: data.oMf[model.getFrameId(n, pin.FrameType.BODY)] for n in
                 ("crank", "coupler", "rocker")}  # fmt: skip
        assert np.allclose(frame["rocker"].act(np.array(ROCKER_FOOT)), (2.0, 0.0, 0.0), atol=1e-6)
        tip = frame["coupler"].act(np.array(COUPLER_TIP))
        assert np.allclose(tip, frame["rocker"].translation, atol=1e-6)
        top = frame["coupler"].translation
        assert math.isclose(np.linalg.norm(top), 0.5, abs_tol=1e-9)  # the crank's length
        cranks.append(math.atan2(top[0], top[2]))
    assert max(abs(c) for c in cranks) > 0.3  # moved off the authored configuration


def _variant(folder: Path, stage: Path, *edits: tuple[str, str]) -> Path:
    text = stage.read_text()
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new)
    path = folder / stage.name
    path.write_text(text)
    return path


def test_the_axis_is_the_joint_frame_s(folder: Path) -> None:
    """d_rocker's frames turn its Z to the world's y: read as X, the linkage is rigid."""
    axis = ('uniform token physics:axis = "Z"', 'uniform token physics:axis = "X"')
    report = cspace.inspect(_variant(folder, CUT, axis))
    assert report.closure is not None and report.closure.mobility == 0
    assert "closure-rigid" in {d.code for d in report.diagnostics}


ROCKER_SIDE = "rel physics:body1 = </fourbar/rocker>\n            point3f physics:localPos0 = (2"
"""ground_pivot's body1 (the only joint whose localPos0 starts so)."""
CLOSING = """        def PhysicsRevoluteJoint "ground_pivot"
        {"""


@pytest.mark.parametrize(
    ("joint", "kind", "rows", "mobility"),
    [
        ('def PhysicsSphericalJoint "ground_pivot"\n        {', "spherical", 3, 1),
        ('def PhysicsFixedJoint "ground_pivot"\n        {', "fixed", 6, 0),
        # a revolute joint locked by its limits (lower above upper) holds as PhysX does
        (
            'def PhysicsRevoluteJoint "ground_pivot"\n        {\n'
            "            float physics:lowerLimit = 10\n            float physics:upperLimit = -10",
            "revolute",
            6,
            0,
        ),
        # a generic joint free about y alone: a hinge
        (
            'def PhysicsJoint "ground_pivot" (prepend apiSchemas = ["PhysicsLimitAPI:transX", '
            '"PhysicsLimitAPI:transY", "PhysicsLimitAPI:transZ", "PhysicsLimitAPI:rotX", '
            '"PhysicsLimitAPI:rotZ"])\n        {\n'
            + "".join(
                f"            float limit:{a}:physics:low = 1\n"
                f"            float limit:{a}:physics:high = -1\n"
                for a in ("transX", "transY", "transZ", "rotX", "rotZ")
            ),
            "generic",
            5,
            1,
        ),
    ],
    ids=["spherical", "fixed", "locked", "generic"],
)
def test_each_joint_type_is_its_cut(
    folder: Path, joint: str, kind: str, rows: int, mobility: int
) -> None:
    stage = _variant(folder, FOURBAR, (CLOSING, "        " + joint))
    report = cspace.inspect(stage)
    assert report.closure is not None
    assert [(c.kind, c.rows) for c in report.closure.cuts] == [(kind, rows)]
    assert report.closure.mobility == mobility


def test_a_generic_joint_no_cut_holds_and_a_self_joint_are_left_out(folder: Path) -> None:
    universal = (
        'def PhysicsJoint "ground_pivot" (prepend apiSchemas = ["PhysicsLimitAPI:transX", '
        '"PhysicsLimitAPI:transY", "PhysicsLimitAPI:transZ", "PhysicsLimitAPI:rotX"])\n'
        "        {\n"
        + "".join(
            f"            float limit:{a}:physics:low = 1\n"
            f"            float limit:{a}:physics:high = -1\n"
            for a in ("transX", "transY", "transZ", "rotX")
        )
    )
    report = cspace.inspect(_variant(folder, FOURBAR, (CLOSING, "        " + universal)))
    assert report.closure is None and report.manifold.notation == "T^3"
    (said,) = [d.message for d in report.diagnostics if d.code == "joint-left-out"]
    assert "ground_pivot" in said and "rotY, rotZ" in said
    itself = (ROCKER_SIDE, "rel physics:body0 = </fourbar/rocker>\n            " + ROCKER_SIDE)
    report = cspace.inspect(_variant(folder, FOURBAR, itself))
    assert report.closure is None
    (said,) = [d.message for d in report.diagnostics if d.code == "joint-left-out"]
    assert "joins 'rocker' to itself" in said


def test_a_closing_joint_with_a_number_that_is_not_one_is_named(folder: Path) -> None:
    nan = ("point3f physics:localPos0 = (2, 0, 0)", "point3f physics:localPos0 = (nan, 0, 0)")
    report = cspace.inspect(_variant(folder, FOURBAR, nan))
    assert report.closure is not None and report.closure.mobility is None
    (said,) = [d.message for d in report.diagnostics if d.code == "closure-invalid"]
    assert "'ground_pivot'" in said
    assert report.joints and cspace.pinocchio_model(folder / FOURBAR.name).nv == 3  # placed


def test_a_closing_joint_naming_no_body_is_refused(folder: Path) -> None:
    missing = (ROCKER_SIDE, ROCKER_SIDE.replace("rocker>", "gone>"))
    stage = _variant(folder, FOURBAR, missing)
    with pytest.raises(RobotFileError) as raised:
        cspace.inspect(stage)
    assert raised.value.code == "missing-link" and "ground_pivot" in str(raised.value)


def _many(folder: Path, closing: int) -> Path:
    """Two bodies, a hinge between them and ``closing`` more, each closing a loop."""
    bodies = "".join(
        f'    def Xform "{b}" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])\n    {{\n    }}\n'
        for b in ("a", "b")
    )
    hinge = (
        '    def PhysicsRevoluteJoint "j{0:04d}"\n    {{\n'
        '        uniform token physics:axis = "Z"\n'
        "        rel physics:body0 = </r/a>\n        rel physics:body1 = </r/b>\n    }}\n"
    )
    joints = '    def PhysicsFixedJoint "base"\n    {\n        rel physics:body1 = </r/a>\n    }\n'
    joints += "".join(hinge.format(i) for i in range(closing + 1))
    path = folder / f"many{closing}.usda"
    path.write_text('#usda 1.0\ndef Xform "r"\n{\n' + bodies + joints + "}\n")
    return path


def test_more_closing_joints_than_cspace_reads_are_refused_in_one_line(folder: Path) -> None:
    from cspace._formats.shared.robot_size import MAX_CUTS

    run = run_cli("inspect", str(_many(folder, MAX_CUTS + 1)))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    said = r"1,001 joints that close kinematic loops.*\[too-many-constraints\]"
    assert re.search(said, run.stderr), run.stderr


def test_every_joint_of_a_stage_counts_against_the_joints_limit(folder: Path) -> None:
    """The child places a stage's joints only up to `MAX_JOINTS` of them, loops' too."""
    from cspace._formats.shared.robot_size import MAX_JOINTS

    with pytest.raises(RobotFileError) as raised:
        cspace.inspect(_many(folder, MAX_JOINTS - 1))  # with the base and the hinge: 5,001
    assert raised.value.code == "too-many-joints" and "5,001 USD joints" in str(raised.value)
