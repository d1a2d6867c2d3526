"""What the documentation says of ``cspace collisions``, held to the command.

Each test is a claim of a page (docs/safety.md, docs/cli.md, docs/formats.md) that the
code once broke: the command is run on real files written here, never mocked.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from test_collisions_command import FOLDED

import cspace
from cspace._formats.mjcf._geom_facts import MAX_GEOMS

from conftest import Run, run_cli


def _one_line_error(run: Run, *words: str) -> None:
    """Exit 2, one line on standard error holding ``words``, no traceback."""
    assert run.code == 2, run
    assert run.stdout == ""
    assert run.stderr.count("\n") == 1 and run.stderr.startswith("cspace: error: "), run
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr, run
    for word in words:
        assert word in run.stderr, run.stderr


@pytest.mark.bounded
def test_an_mjcf_model_of_more_geoms_than_read_is_refused_in_one_line(tmp_path: Path) -> None:
    """safety.md: 5,000 geoms a model, "a one-line refusal when cspace collisions asks
    for it" (it was an internal error, a bug's message, exit 2)."""
    path = tmp_path / "many.xml"
    path.write_text(
        '<mujoco><worldbody><body><joint/><replicate count="'
        f'{MAX_GEOMS + 1}" offset=".01 0 0"><geom size=".1"/></replicate></body>'
        "</worldbody></mujoco>"
    )
    assert run_cli("inspect", str(path)).code == 0  # the C-space report needs no geometry
    run = run_cli("collisions", str(path), "-n", "10")
    _one_line_error(run, "many.xml", f"{MAX_GEOMS + 1:,} geoms", "[too-many-elements]")


ARM_OF_MESHES = """<robot name="r">
  <link name="a"><collision><geometry><mesh filename="gripper.obj"/></geometry></collision>
  </link>
  <link name="b"><collision><geometry><box size="1 1 1"/></geometry></collision></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""

MUJOCO_OF_MESHES = """<mujoco>
  <asset><mesh name="arm" file="gripper.obj"/></asset>
  <worldbody>
    <body><joint/><geom type="mesh" mesh="arm"/><geom size=".1"/></body>
    <body pos="1 0 0"><joint/><geom size=".1"/></body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize(("robot", "text", "where"), [
    ("arm.urdf", ARM_OF_MESHES, "link 'a': mesh 'gripper.obj': "),
    ("arm.xml", MUJOCO_OF_MESHES, "mesh 'arm': 'gripper.obj': "),
])  # fmt: skip
def test_a_bad_mesh_is_said_at_its_own_line(
    tmp_path: Path, robot: str, text: str, where: str
) -> None:
    """safety.md: a mesh's problem "names the mesh file, and its line where it has one"
    (the line was dropped, and the problem said "mesh:" twice)."""
    (tmp_path / "gripper.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    (tmp_path / robot).write_text(text)
    report = cspace.collisions(tmp_path / robot, samples=10)
    [skipped] = [d for d in report.diagnostics if d.code == "collision-skipped"]
    said = f"{where}line 4: a face names vertex 9, and 3 vertices are defined before it"
    assert said in skipped.message, skipped.message
    assert "mesh: " not in skipped.message


INNER_FLOATING = """<robot name="fl">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="a"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="b"><collision><geometry><sphere radius="0.01"/></geometry></collision></link>
  <link name="c"><collision><origin xyz="0 0 0.3"/><geometry><box size="0.1 0.1 0.1"/>
    </geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="floating"><parent link="a"/><child link="b"/></joint>
  <joint name="j3" type="fixed"><parent link="b"/><child link="c"/></joint>
</robot>
"""


def test_an_inner_floating_joint_is_held_in_position_and_turned(tmp_path: Path) -> None:
    """cspace-math.md: every unbounded translation keeps its neutral value, a floating
    joint's rotation is sampled; the warning says so (it said the joint was held)."""
    (tmp_path / "fl.urdf").write_text(INNER_FLOATING)
    report = cspace.collisions(tmp_path / "fl.urdf", samples=200)
    [held] = [d for d in report.diagnostics if d.code == "collision-held"]
    assert held.joint == "j2"
    assert "holds its position at its neutral value (its rotation is sampled)" in held.message
    [pair] = [p for p in report.pairs if (p.link1, p.link2) == ("base", "c")]
    assert pair.kind == "sometimes" and pair.witness is not None
    at = dict(pair.witness.configuration)
    assert at["j2.x"] == at["j2.y"] == at["j2.z"] == (0.0,)
    assert at["j2.qw"] != (1.0,)


@pytest.mark.bounded
def test_no_mesh_file_is_read_after_the_robots_bytes_are_spent(tmp_path: Path) -> None:
    """safety.md: 128 MiB a robot, "the file that passes it, and every one after it,
    unread" (each was read, up to 32 MiB, then refused: a robot naming one file under
    many names made cspace read it again and again). Here the bound is two files: the
    files after the one that passes it are refused unopened, a missing one too."""
    from cspace._formats.meshes._bounds import Mesh
    from cspace._formats.meshes.load import MeshFile, load_meshes

    good = tmp_path / "box.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n")
    size = good.stat().st_size
    names = [str(good), f"{tmp_path}/./box.obj", f"{tmp_path}/../{tmp_path.name}/box.obj"]
    files = [MeshFile(name) for name in names] + [MeshFile(str(tmp_path / "gone.obj"))]
    results = load_meshes(files, robot_bytes=2 * size)
    assert isinstance(results[0], Mesh) and isinstance(results[1], Mesh)
    for result in results[2:]:
        assert not isinstance(result, Mesh) and result.code == "bad-mesh", result
        assert f"pass the {2 * size:,} bytes cspace reads for one robot" in result.problem


def test_the_help_says_which_loading_options_are_refused() -> None:
    """cli.md: "It takes the options of Reading a robot but --limits, --group and
    --hold, which it refuses" (its --help offered them as for inspect), and its robot
    is no standard input."""
    run = run_cli("collisions", "--help", env={"COLUMNS": "200"})
    assert run.code == 0, run
    for option in ("--limits FILE", "--group NAME", "--hold POSE"):
        [line] = [line for line in run.stdout.splitlines() if line.strip().startswith(option)]
        assert "refused" in line, line
        refused = run_cli("collisions", "robot.urdf", option.split()[0], "x")
        _one_line_error(refused, f"{option.split()[0]} does not apply to cspace collisions")
    assert "standard input" not in run.stdout


def test_a_pair_with_an_error_finding_is_one_the_pages_show_first(tmp_path: Path) -> None:
    """A pair the SRDF disables as Never that collides at the default configuration is
    collision-disabled-but-reachable (safety.md); the pages (Markdown, HTML) list the
    pairs the findings are about first, and left this one among the setup assistant's."""
    from cspace._render._collisions_shared import against_file, first_look

    (tmp_path / "folded.urdf").write_text(FOLDED)
    (tmp_path / "folded.srdf").write_text(
        '<robot name="folded">\n'
        '  <disable_collisions link1="base" link2="tip" reason="Never"/>\n</robot>\n'
    )
    report = cspace.collisions(tmp_path / "folded.urdf", samples=300, srdf=tmp_path / "folded.srdf")
    [pair] = [p for p in report.pairs if (p.link1, p.link2) == ("base", "tip")]
    assert pair.kind == "default"
    assert [d.code for d in report.diagnostics] == ["collision-disabled-but-reachable"]
    assert against_file(pair, report.matrix) and first_look(pair, report.matrix)


ARM_STAGE = """#usda 1.0
(
    defaultPrim = "r"
    metersPerUnit = 1
    upAxis = "Z"
)

def Xform "r" (prepend apiSchemas = ["PhysicsArticulationRootAPI"])
{
    def Xform "base" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
        def Cube "box" (prepend apiSchemas = ["PhysicsCollisionAPI"])
        {
            double size = 0.2
        }
    }
    def Xform "arm" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
        double3 xformOp:translate = (0.5, 0, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
        def Cube "box" (prepend apiSchemas = ["PhysicsCollisionAPI"])
        {
            double size = 0.2
        }
    }
    def Xform "tip" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {
        double3 xformOp:translate = (1, 0, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
        def Cube "box" (prepend apiSchemas = ["PhysicsCollisionAPI"])
        {
            double size = 0.2
            double3 xformOp:translate = (-0.3, 0, 0)
            uniform token[] xformOpOrder = ["xformOp:translate"]
        }
    }
    def PhysicsFixedJoint "mount"
    {
        rel physics:body1 = </r/base>
    }
    def PhysicsRevoluteJoint "shoulder"
    {
        rel physics:body0 = </r/base>
        rel physics:body1 = </r/arm>
        point3f physics:localPos0 = (0.5, 0, 0)
        uniform token physics:axis = "Z"
        float physics:lowerLimit = -170
        float physics:upperLimit = 170
    }
    def PhysicsRevoluteJoint "elbow"
    {
        rel physics:body0 = </r/arm>
        rel physics:body1 = </r/tip>
        point3f physics:localPos0 = (0.5, 0, 0)
        uniform token physics:axis = "Z"
        float physics:lowerLimit = -170
        float physics:upperLimit = 170
    }
}
"""
"""An OpenUSD arm of three cubes: its joints filter the adjacent pairs (PhysX's filters)."""


def test_a_report_of_physx_filters_is_valid_under_the_schema(tmp_path: Path) -> None:
    """getting-started.md: the tests validate reports of every matrix against `cspace
    schema --collisions`, PhysX's filters (matrix usd) too, as a saved report is read."""
    import json

    import jsonschema

    from cspace._reports._collisions_check import check_collisions_document

    (tmp_path / "arm.usda").write_text(ARM_STAGE)
    run = run_cli("collisions", str(tmp_path / "arm.usda"), "-n", "300", "--format", "json")
    assert run.code == 0, run
    document = json.loads(run.stdout)
    schema = json.loads(run_cli("schema", "--collisions").stdout)
    jsonschema.Draft202012Validator(schema).validate(document)
    check_collisions_document("arm", document)
    assert document["matrix"] == "usd" and document["srdf"] is None
    rules = {(p["link1"], p["link2"]): p["rule"] for p in document["pairs"]}
    assert rules[("base", "tip")] == {"checked": True, "reason": None, "line": None}
    assert not rules[("arm", "base")]["checked"] and "shoulder" in rules[("arm", "base")]["reason"]
