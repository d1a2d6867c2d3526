"""OpenUSD stages read as UsdPhysics describes them, and hostile stages refused.

``docs/examples/usd_joints.usda`` is hand-written with every joint kind cspace reads;
``tests/usd/converted`` holds what urdf-usd-converter 0.3.4 writes for each teaching URDF
(``tests/usd/converted/make.py`` remakes them, without their geometry): each has its
URDF's C-space. OpenUSD runs in a confined child; a stage's composition stays in its folder and
within counts, each refusal one line.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

import cspace

from conftest import ROBOTS, run_cli, usd_stages

HERE = Path(__file__).parent / "usd"
EXAMPLE = Path(__file__).parent.parent / "docs" / "examples" / "usd_joints.usda"


@pytest.fixture(scope="module", autouse=True)
def _stages(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """Where this file's tests that inspect stages in this process write them."""
    yield from usd_stages(tmp_path_factory, HERE, EXAMPLE.parent)


def test_every_joint_kind_of_usdphysics() -> None:
    report = cspace.inspect(EXAMPLE)
    kinds = {j.name: j.kind.value for j in report.joints}
    assert kinds == {
        "base": "floating",  # the articulation root, held by no joint: a floating base
        "shoulder": "revolute",
        "slide": "prismatic",
        "ball": "spherical",
        "spin": "continuous",  # no limits: turns freely
        "stuck": "revolute",  # lower above upper: locked at 0, no factor
        "planar": "planar",  # a D6 free along x, y and about z
    }
    limits = {j.name: j.limits for j in report.joints if j.limits is not None}
    assert limits["shoulder"].lower[0] == pytest.approx(-1.5707963, abs=1e-6)  # degrees
    assert limits["slide"].upper[0] == pytest.approx(0.5)  # 50 units of 1 cm
    assert report.manifold.notation == "R^7 × T^2 × (RP^3)^2"
    assert report.source.format == "usd"


CONVERTED = sorted((HERE / "converted").glob("*.usda"))


@pytest.mark.parametrize("stage", CONVERTED, ids=lambda p: p.stem)
def test_every_teaching_urdf_converted_has_the_urdfs_cspace(stage: Path) -> None:
    """``cspace diff robot.urdf robot.usda``: no change, whatever the converter renamed,
    dropped (a floating joint) or wrote as a schema of its own (a mimic joint)."""
    run = run_cli("diff", str(ROBOTS / f"{stage.stem}.urdf"), str(stage))
    assert run.code == 0 and run.stdout.startswith("no C-space change"), run.stdout


def test_every_teaching_urdf_is_converted() -> None:
    assert [p.stem for p in CONVERTED] == sorted(p.stem for p in ROBOTS.glob("*.urdf"))


def test_a_usd_report_passes_its_schema_and_reads_back(tmp_path: Path) -> None:
    saved = tmp_path / "arm7.json"
    saved.write_text(
        run_cli("inspect", str(HERE / "converted/arm7.usda"), "--format", "json").stdout
    )
    assert run_cli("check", str(saved), "--expect", "R^6 × S^1").code == 0


def _refused(path: Path, expected: str) -> None:
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "Traceback" not in run.stderr
    assert expected in run.stderr, run.stderr


def test_composition_stays_in_the_folder(tmp_path: Path) -> None:
    stage = tmp_path / "evil.usda"
    stage.write_text('#usda 1.0\n(\n    subLayers = [@/etc/passwd@]\n)\ndef Xform "r" {}\n')
    _refused(stage, "composes '/etc/passwd', outside the allowed folders")
    stage.write_text('#usda 1.0\ndef Xform "r" (references = @../outside.usda@) {}\n')
    _refused(stage, "outside.usda', outside the allowed folders")
    stage.write_text('#usda 1.0\ndef Xform "r" (payload = @http://example.com/a.usda@) {}\n')
    _refused(stage, "which is no local file")


def test_cycles_and_layer_bombs_are_bounded(tmp_path: Path) -> None:
    cycle = tmp_path / "cycle.usda"  # a layer that references itself, and two that loop
    cycle.write_text('#usda 1.0\n(\n    subLayers = [@./other.usda@]\n)\ndef Xform "r" {}\n')
    (tmp_path / "other.usda").write_text("#usda 1.0\n(\n    subLayers = [@./cycle.usda@]\n)\n")
    run = run_cli("inspect", str(cycle))
    assert run.code in (0, 1, 2) and "Traceback" not in run.stderr
    bomb = tmp_path / "bomb.usda"  # 300 layers, each a sublayer of the stage
    names = ", ".join(f"@./l{i}.usda@" for i in range(300))
    bomb.write_text(f'#usda 1.0\n(\n    subLayers = [{names}]\n)\ndef Xform "r" {{}}\n')
    for i in range(300):
        (tmp_path / f"l{i}.usda").write_text("#usda 1.0\n")
    _refused(bomb, "more than 256 layers")


def test_a_stage_of_too_many_prims_is_refused(tmp_path: Path) -> None:
    stage = tmp_path / "many.usda"
    prims = "".join(f'def Xform "p{i}" {{}}\n' for i in range(100_001))
    stage.write_text(f"#usda 1.0\n{prims}")
    _refused(stage, "more than 100,000 prims")


def test_a_usd_file_is_told_by_its_bytes_not_its_name(tmp_path: Path) -> None:
    named = tmp_path / "robot.urdf"  # OpenUSD reads a layer's format from its name
    named.write_bytes((EXAMPLE).read_bytes())
    _refused(named, "a USD file must be named .usd, .usda, .usdc or .usdz")
    broken = tmp_path / "broken.usda"
    broken.write_text("#usda 1.0\ndef Xform (\n")
    run = run_cli("inspect", str(broken))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "pxrInternal" not in run.stderr
    mobile = Path(__file__).parent.parent / "docs" / "examples" / "mobile_arm.srdf"
    srdf = run_cli("inspect", str(EXAMPLE), "--srdf", str(mobile))
    assert srdf.code == 2 and "an SRDF goes with a URDF, and this robot is USD" in srdf.stderr
    stdin = run_cli("inspect", "-", stdin=(EXAMPLE).read_bytes())
    assert stdin.code == 2 and "a USD file is read from a file, not standard input" in stdin.stderr


def test_a_crate_file_and_a_usdz_archive(folder: Path) -> None:
    from pxr import Sdf, UsdUtils

    layer = Sdf.Layer.FindOrOpen(str(EXAMPLE))
    crate = folder / "every_joint.usdc"
    layer.Export(str(crate))
    assert cspace.inspect(crate).manifold.notation == "R^7 × T^2 × (RP^3)^2"
    archive = folder / "every_joint.usdz"
    assert UsdUtils.CreateNewUsdzPackage(str(crate), str(archive))
    assert cspace.inspect(archive).manifold.notation == "R^7 × T^2 × (RP^3)^2"


BODIES = """#usda 1.0
(
    metersPerUnit = 1
)
def Xform "robot"
{{
    def Xform "base" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {{
        {base}
    }}
    def Xform "link1" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])
    {{
        def Xform "geom" {{}}
    }}
{joints}
}}
"""


def _joint(kind: str, name: str, *lines: str) -> str:
    return f'def {kind} "{name}"\n{{\n' + "".join(f"    {x}\n" for x in lines) + "}\n"


_HOLD = _joint("PhysicsFixedJoint", "hold", "rel physics:body0 = </robot/base>")


def _j1(a: str, b: str) -> str:
    return _joint(
        "PhysicsRevoluteJoint",
        "j1",
        f"rel physics:body0 = <{a}>",
        f"rel physics:body1 = <{b}>",
        "float physics:lowerLimit = -90",
        "float physics:upperLimit = 90",
    )


def _stage(tmp_path: Path, joints: str, base: str = "") -> Path:
    stage = tmp_path / "stage.usda"
    stage.write_text(BODIES.format(joints=joints, base=base))
    return stage


@pytest.mark.parametrize(
    ("case", "joints", "base"),
    [
        ("body0 alone holds to the world", _HOLD + _j1("/robot/base", "/robot/link1"), ""),
        ("bodies swapped", _HOLD + _j1("/robot/link1", "/robot/base"), ""),
        ("a target below a body", _HOLD + _j1("/robot/base", "/robot/link1/geom"), ""),
        ("a body not simulated", _j1("/robot/base", "/robot/link1"),
         "bool physics:rigidBodyEnabled = false"),
    ],
)  # fmt: skip
def test_joints_as_physx_reads_them(folder: Path, case: str, joints: str, base: str) -> None:
    """UsdPhysics joints have no direction; a body target is its rigid body; a joint's
    missing body is the world; a disabled body is static: each of these is R^1."""
    assert cspace.inspect(_stage(folder, joints, base)).manifold.notation == "R^1", case


def test_limited_d6_axes_are_intervals_and_names_by_path(folder: Path) -> None:
    locked = [f"float limit:{a}:physics:{e} = {v}" for a in ("transX", "transY", "transZ", "rotZ")
              for e, v in (("low", 1), ("high", -1))]  # fmt: skip
    swings = [f"float limit:{a}:physics:{e} = {v}" for a in ("rotX", "rotY")
              for e, v in (("low", -30), ("high", 30))]  # fmt: skip
    d6 = _joint("PhysicsJoint", "d6", "rel physics:body0 = </robot/base>",
                "rel physics:body1 = </robot/link1>", *locked, *swings)  # fmt: skip
    report = cspace.inspect(_stage(folder, _HOLD + d6))
    assert report.manifold.notation == "R^2"  # two limited rotations: no torus
    twins = (
        'def Scope "a"\n{\n'
        + _joint(
            "PhysicsRevoluteJoint",
            "j",
            "rel physics:body0 = </robot/base>",
            "rel physics:body1 = </robot/link1>",
        )
        + '}\ndef Scope "b"\n{\n'
        + _joint("PhysicsRevoluteJoint", "j", "rel physics:body0 = </robot/link1>")
        + "}\n"
    )
    report = cspace.inspect(_stage(folder, twins))
    assert {j.name for j in report.joints} >= {"/robot/a/j", "/robot/b/j"}


def test_an_empty_stage_and_an_expression_are_refused(tmp_path: Path) -> None:
    empty = tmp_path / "empty.usda"
    empty.write_text("#usda 1.0\n")
    _refused(empty, "the stage has no prim: no robot")
    expression = tmp_path / "expr.usda"
    expression.write_text(
        '#usda 1.0\n(\n    expressionVariables = { string D = ".." }\n)\n'
        'def Xform "r" (references = @`"${D}/x.usda"`@) {}\n'
    )
    _refused(expression, "an expression cspace does not evaluate yet")


@pytest.mark.parametrize(
    ("case", "space", "left_out", "cuts"),
    [
        ("ballapi", "RP^3", 0, []),  # a limit API without values limits nothing: still a ball
        ("par1", "point", 0, ["hinge"]),  # a weld beside a hinge: the weld holds, the hinge cuts
        ("par2", "point", 0, ["hinge"]),  # in either order
        ("loop", "R^3", 0, ["j4"]),  # the joint that closes the loop is its cut
        ("self", "R^3 × RP^3", 1, []),  # a joint of a body to itself is left out
        ("excl", "point", 0, []),  # excluded from the articulation, yet the only joint: it holds
        ("world_body", "R^4 × RP^3", 0, []),  # a body named world is a body
        ("float_clash", "R^7 × (RP^3)^2", 0, []),  # a free body named as a joint
        ("freeclash", "R^3 × T^2 × RP^3", 0, []),  # ... and as the name tried next
        ("bfs_fixed", "point", 0, ["hinge_b"]),  # welds hold before a hinge nearer the world
        ("bfs_excl", "T^2", 0, ["closure"]),  # the excluded joint is the cut, however far
    ],
)
def test_the_second_review_s_stages(case: str, space: str, left_out: int, cuts: list[str]) -> None:
    report = cspace.inspect(HERE / "cases" / f"{case}.usda")
    assert report.manifold.notation == space, case
    assert sum(d.code == "joint-left-out" for d in report.diagnostics) == left_out
    assert ([c.name for c in report.closure.cuts] if report.closure else []) == cuts


def test_a_scale_that_is_no_length_is_refused() -> None:
    _refused(HERE / "cases" / "mpu0.usda", "metersPerUnit is 0: lengths cannot be read")


def test_links_fifos_deep_nesting_and_escapes(folder: Path) -> None:
    """A sublayer that is a link out of the folder or a FIFO is refused unread (a FIFO
    beside the stage does not stop the confinement either); 3,000 nested prims are read;
    a hostile asset path reaches GitHub's workflow commands escaped, on one line."""
    import os

    (folder / "out.usda").symlink_to("/etc/passwd")
    linked = folder / "linked.usda"
    linked.write_text("#usda 1.0\n(\n    subLayers = [@./out.usda@]\n)\n")
    _refused(linked, "outside the allowed folders")
    os.mkfifo(folder / "pipe.usda")
    piped = folder / "piped.usda"
    piped.write_text("#usda 1.0\n(\n    subLayers = [@./pipe.usda@]\n)\n")
    _refused(piped, "pipe.usda', which is no regular file")
    deep = folder / "deep.usda"
    depth = 3_000
    nested = "".join(f'def Xform "p{i}" {{\n' for i in range(depth)) + "}\n" * depth
    deep.write_text(f"#usda 1.0\n{nested}")
    assert cspace.inspect(deep).manifold.notation == "point"
    hostile = folder / "hostile.usda"
    hostile.write_text("#usda 1.0\n(\n    subLayers = [@./a\u202e::error file=x::owned.usda@]\n)\n")
    github = run_cli("inspect", str(hostile), "--format", "github")
    assert github.stdout.count("\n") == 1 and "\u202e" not in github.stdout
    assert github.stdout.startswith("::error file=") and "a\\u202e::error" in github.stdout


def test_mimic_joints_of_newton_and_physx() -> None:
    """A relation that cannot hold (no leader, itself, an angle following a length,
    turned off) leaves the joint free, named (a URDF ``<mimic>`` converted keeps the
    URDF's C-space, above). Newton's own reading of the stages that hold is the oracle of
    `tests/test_isaac.py`."""
    report = cspace.inspect(HERE / "cases" / "mimic_ignored.usda")
    assert report.manifold.notation == "R^6"
    ignored = {d.joint: d.message for d in report.diagnostics if d.code == "mimic-ignored"}
    assert set(ignored) == {"itself", "no_leader", "other_kind"}  # "off" is turned off
    assert "its leader ('/robot/joints/missing') is no joint of the tree" in ignored["no_leader"]
    assert "of another kind" in ignored["other_kind"]


@pytest.mark.parametrize(
    ("cone", "space"),
    [
        ((45, 30), "R^2 × S^1"),  # the axis within a cone (a disk), the twist free
        ((0, 20), "R^1 × S^1"),  # one swing locked: an arc of directions
        ((0, 0), "S^1"),  # only the twist
        ((45, None), "RP^3"),  # a cone limits only when both angles are set
        ((-1, 30), "RP^3"),  # a negative angle: not limited
        ((180, 190), "RP^3"),  # both reach the opposite pole: nothing excluded
    ],
)
def test_a_cone_limit_bounds_the_swing_and_leaves_the_twist(
    folder: Path, cone: tuple[int, int | None], space: str
) -> None:
    angles = [f"float physics:coneAngle{i}Limit = {a}" for i, a in enumerate(cone) if a is not None]
    ball = _joint("PhysicsSphericalJoint", "ball", "rel physics:body0 = </robot/base>",
                  "rel physics:body1 = </robot/link1>", *angles)  # fmt: skip
    report = cspace.inspect(_stage(folder, _HOLD + ball))
    assert report.manifold.notation == space
    if space != "RP^3":  # its swing and twist are no coordinates cspace computes with
        run = run_cli("sample", str(folder / "stage.usda"), "-n", "1")
        assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
        assert "cone-limited ball's swing and twist" in run.stderr


def test_a_cone_that_reaches_the_pole_one_way_only_is_refused(tmp_path: Path) -> None:
    ball = _joint("PhysicsSphericalJoint", "ball", "rel physics:body0 = </robot/base>",
                  "rel physics:body1 = </robot/link1>", "float physics:coneAngle0Limit = 30",
                  "float physics:coneAngle1Limit = 180")  # fmt: skip
    _refused(_stage(tmp_path, _HOLD + ball), "joint 'ball' has cone limits of 30 and 180")
