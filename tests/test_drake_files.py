"""The robot files Drake ships, read as Drake reads them; a URDF link named ``world``.

Drake's URDF parser reads a link named ``world`` as its world body wherever a joint names
it, declared or not: ``Acrobot.urdf``, which pydrake installs, welds its base to an
undeclared ``world``. cspace reads it so (the C-space of the file with ``<link
name="world"/>`` declared, a ``world-undeclared`` info), matches Drake where ``world`` is
a child or the parent of several joints, and refuses what Drake floats (a second root).

Every URDF and SDF file under pydrake's ``share/drake`` (22 in pydrake 1.51) is held to
Drake itself: each that Drake parses, cspace reads with Drake's positions and velocities
(names, order, count) and joint kinds, each root Drake would float welded as cspace's
convention says (``plant.WeldFrames``); each Drake refuses, cspace refuses. Drake's
source tree and its downloaded models (``drake_models``) are swept by
``bench/sweep_drake.py``.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from pydrake.common import FindResourceOrThrow
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

import cspace

from conftest import run_cli

logging.getLogger("drake").setLevel(logging.CRITICAL)  # its notes on what it ignores

SHARE = Path(FindResourceOrThrow("drake/examples/acrobot/Acrobot.urdf")).parents[2]
"""pydrake's share/drake: the robot files Drake installs."""
SHIPPED = sorted([*SHARE.rglob("*.urdf"), *SHARE.rglob("*.sdf")])
ACROBOT = SHARE / "examples" / "acrobot" / "Acrobot.urdf"

DRAKE_KINDS = {
    "revolute": {"revolute", "continuous"},
    "prismatic": {"prismatic"},
    "weld": {"fixed"},
    "quaternion_floating": {"floating"},
    "planar": {"planar"},
    "ball_rpy": {"spherical"},
    "universal": {"universal"},
    "screw": {"helical"},
}
"""Each of Drake's joint types (``type_name()``) and the kinds cspace may call it."""


def _plant(path: Path, space: cspace.ConfigurationSpace | None) -> tuple[MultibodyPlant, set[str]]:
    """Drake's plant of the file, every root body welded that cspace does not float, and
    the names of the bodies welded.

    cspace's Drake convention welds the root links Drake's parser would float (it names
    them, `DrakeLayout.welded`, when the report has a joint; a file of one link and no
    joint has none to name it by).
    """
    plant = MultibodyPlant(0.0)
    models = Parser(plant).AddModels(str(path))
    floats = space is not None and any(j.kind.value == "floating" for j in space.report_joints)
    welded = set()
    for model in models if not floats else ():
        held = {plant.get_joint(i).child_body().index() for i in plant.GetJointIndices(model)}
        for index in plant.GetBodyIndices(model):
            if index not in held:
                plant.WeldFrames(plant.world_frame(), plant.get_body(index).body_frame())
                welded.add(plant.get_body(index).name())
    plant.Finalize()
    return plant, welded


def _drake_agrees(path: Path) -> None:
    """cspace's report of ``path`` has Drake's positions, velocities and joint kinds."""
    report = cspace.inspect(path)
    space = cspace.ConfigurationSpace.from_report(report)
    conventions = space.conventions()
    plant, welded_here = _plant(path, space)
    assert conventions.names("drake") == tuple(plant.GetPositionNames(False))
    assert conventions.names("drake", velocity=True) == tuple(plant.GetVelocityNames(False))
    assert plant.num_velocities() == report.dimension
    kinds = {j.name.rpartition("::")[2]: j.kind.value for j in report.joints}
    for index in plant.GetJointIndices():
        joint = plant.get_joint(index)
        if joint.name() in kinds:
            assert kinds[joint.name()] in DRAKE_KINDS[joint.type_name()], joint.name()
    welded = set(conventions.drake.welded)
    assert welded == welded_here if report.joints else welded == set()


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.relative_to(SHARE).as_posix())
def test_every_file_drake_ships_is_read_as_drake_reads_it(path: Path) -> None:
    try:
        _plant(path, None)
    except RuntimeError:
        with pytest.raises(cspace.RobotFileError):
            cspace.inspect(path)
        return
    _drake_agrees(path)


def test_drake_ships_robot_files() -> None:
    """Not a vacuous sweep: pydrake installs its examples' robots."""
    assert len(SHIPPED) >= 20 and ACROBOT in SHIPPED


def test_acrobot_is_the_file_with_world_declared(tmp_path: Path) -> None:
    """The same report as with ``<link name="world"/>`` declared, but the info; the model
    Pinocchio builds places every link where Drake does."""
    report = cspace.inspect(ACROBOT)
    assert report.manifold.notation == "T^2" and report.dimension == 2
    (said,) = report.diagnostics
    assert (said.code, said.severity, said.joint, said.line) == (
        "world-undeclared",
        cspace.Severity.INFO,
        "base_weld",
        62,
    )
    assert 'declare <link name="world"/>' in said.message
    declared = tmp_path / "Acrobot.urdf"
    text = ACROBOT.read_text()
    declared.write_text(text.replace("<link ", '<link name="world"/><link ', 1))
    other = cspace.inspect(declared)
    assert other.diagnostics == ()
    mine, theirs = report.to_dict(), other.to_dict()
    for document in (mine, theirs):
        del document["source"], document["diagnostics"]
    assert mine == theirs
    space = cspace.load(ACROBOT)
    model = cspace.pinocchio_model(ACROBOT)
    data = model.createData()
    plant, _ = _plant(ACROBOT, space)
    context = plant.CreateDefaultContext()
    conventions = space.conventions()
    for x in space.sample(3, np.random.default_rng(3)):
        plant.SetPositions(context, conventions.to_drake(x))
        pin.framesForwardKinematics(model, data, conventions.to_pinocchio(x))
        for name in ("base_link", "upper_link", "lower_link"):
            pose = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName(name))
            placed = data.oMf[model.getFrameId(name, pin.FrameType.BODY)]
            np.testing.assert_allclose(pose.translation(), placed.translation, atol=1e-12)
            np.testing.assert_allclose(pose.rotation().matrix(), placed.rotation, atol=1e-12)


def test_the_command_reads_acrobot() -> None:
    run = run_cli("inspect", str(ACROBOT), "--strict")
    assert run.code == 0 and run.stderr == "", run.stderr
    assert "C = T^2" in run.stdout and "info    world-undeclared (line 62)" in run.stdout


def _link(name: str) -> str:
    return f'<link name="{name}"/>'


def _joint(name: str, kind: str, parent: str, child: str) -> str:
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
        f'<child link="{child}"/><axis xyz="0 0 1"/>{limit}</joint>'
    )


READ_AS_DRAKE = {
    "world_parent": [
        _link("a"),
        _link("b"),
        _joint("w", "fixed", "world", "a"),
        _joint("j", "revolute", "a", "b"),
    ],
    "world_holds_two": [
        _link("a"),
        _link("b"),
        _joint("w2", "revolute", "world", "b"),
        _joint("w1", "prismatic", "world", "a"),
    ],
    "world_floats_one": [
        _link("a"),
        '<joint name="f" type="floating"><parent link="world"/><child link="a"/></joint>',
    ],
    "world_declared": [_link("world"), _link("a"), _joint("w", "revolute", "world", "a")],
}
"""URDF files Drake reads, with ``world`` undeclared (but the last): cspace reads each
with Drake's positions, velocities and joint kinds."""


def _urdf(tmp_path: Path, lines: list[str]) -> Path:
    path = tmp_path / "r.urdf"
    path.write_text("\n".join(['<robot name="r">', *lines, "</robot>"]) + "\n")
    return path


@pytest.mark.parametrize("name", sorted(READ_AS_DRAKE))
def test_world_named_is_drakes_world(name: str, tmp_path: Path) -> None:
    path = _urdf(tmp_path, READ_AS_DRAKE[name])
    _drake_agrees(path)
    codes = [d.code for d in cspace.inspect(path).diagnostics]
    assert codes == ([] if name == "world_declared" else ["world-undeclared"])


@pytest.mark.parametrize("kind", ["fixed", "revolute"])
def test_world_as_a_child_is_read_and_drakes_order_refused(kind: str, tmp_path: Path) -> None:
    """Drake turns a joint whose child is ``world`` around (its parent hangs from the
    world): the C-space is the same, Drake's vectors are not mapped, said by name."""
    lines = [
        _link("a"),
        _link("b"),
        _joint("w", kind, "a", "world"),
        _joint("j", "revolute", "a", "b"),
    ]
    path = _urdf(tmp_path, lines)
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    report = cspace.inspect(path)
    assert report.dimension == plant.num_velocities() == (2 if kind == "revolute" else 1)
    assert [d.code for d in report.diagnostics] == ["world-undeclared"]
    assert "names child link 'world'" in report.diagnostics[0].message
    space = cspace.ConfigurationSpace.from_report(report)
    with pytest.raises(cspace.JointMatchError, match="joint 'w' has link 'world' as its child"):
        space.conventions().names("drake")
    document = json.loads(run_cli("inspect", str(path), "--format", "json").stdout)
    assert not any("drake_q" in j.get("slots", {}) for j in document["joints"])  # nothing said


def test_a_second_root_beside_world_is_refused_where_drake_floats_it(tmp_path: Path) -> None:
    lines = [_link("a"), _link("b"), _link("c"), _joint("w", "revolute", "world", "a")]
    path = _urdf(tmp_path, [*lines, _joint("j", "revolute", "b", "c")])
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModels(str(path))
    plant.Finalize()
    assert plant.num_positions() == 1 + 7 + 1  # 'b' floats
    with pytest.raises(cspace.errors.RobotStructureError) as refused:
        cspace.inspect(path)
    assert refused.value.code == "several-roots" and refused.value.line == 3
    assert "2 links have no parent joint ('world', 'b')" in refused.value.problem


@pytest.mark.parametrize(
    ("lines", "code"),
    [
        ([_link("a"), _joint("w", "fixed", "world", "world")], "cycle"),
        ([_joint("w", "fixed", "world", "a")], "no-links"),
        (
            [_link("a"), _joint("w", "fixed", "world", "a"), _joint("v", "fixed", "world", "a")],
            "two-parents",
        ),
    ],
    ids=["world-to-itself", "no-links", "two-parents"],
)
def test_what_drake_refuses_is_refused(lines: list[str], code: str, tmp_path: Path) -> None:
    path = _urdf(tmp_path, lines)
    with pytest.raises(RuntimeError):
        _plant(path, None)
    with pytest.raises(cspace.RobotFileError) as refused:
        cspace.inspect(path)
    assert refused.value.code == code
