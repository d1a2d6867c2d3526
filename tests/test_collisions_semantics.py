"""``cspace collisions`` held to what the tools it follows do, on small robots written here.

- A pair a simulator's filters skip and the samples find in collision is a
  `collision-filtered-reachable` finding whatever the names in the filter's reason: only
  MuJoCo's own parent-child filter (its ``filterparent`` rule, decided by weld bodies)
  spares a pair, never a reason that merely holds the word ("/transparent").
"""

from __future__ import annotations

from pathlib import Path

import pytest
from pxr import Gf, Usd, UsdGeom, UsdPhysics

from cspace.space._collisions.run import collisions


def _sliders(path: Path, root: str) -> Path:
    """A base, a slider on it (its one shape far away) and a tip sliding on the slider.

    The tip's cube reaches the base's in about 40% of the samples; the base filters the
    tip by ``physics:filteredPairs``, so PhysX lets them pass through each other.
    """
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, root).GetPrim())

    def body(name: str, x: float) -> None:
        xform = UsdGeom.Xform.Define(stage, f"{root}/{name}")
        xform.AddTransformOp().Set(Gf.Matrix4d().SetTranslate(Gf.Vec3d(x, 0, 0)))
        UsdPhysics.RigidBodyAPI.Apply(xform.GetPrim())

    def collider(kind: type, path: str, **attributes: object) -> object:
        prim = kind.Define(stage, path).GetPrim()
        UsdPhysics.CollisionAPI.Apply(prim)
        for name, value in attributes.items():
            prim.GetAttribute(name).Set(value)
        return prim

    def joint(kind: type, name: str, body0: str | None, body1: str, **more: object) -> None:
        made = kind.Define(stage, f"{root}/{name}")
        if body0 is not None:
            made.CreateBody0Rel().SetTargets([f"{root}/{body0}"])
        made.CreateBody1Rel().SetTargets([f"{root}/{body1}"])
        for key, value in more.items():
            made.GetPrim().GetAttribute(key).Set(value)

    body("base", 0.0)
    collider(UsdGeom.Cube, f"{root}/base/box", size=0.2)
    body("mid", 0.5)
    ball = collider(UsdGeom.Sphere, f"{root}/mid/ball", radius=0.05)
    UsdGeom.Xformable(ball).AddTranslateOp().Set(Gf.Vec3d(0, 0, 5))
    body("tip", 0.5)
    collider(UsdGeom.Cube, f"{root}/tip/box", size=0.2)
    joint(UsdPhysics.FixedJoint, "mount", None, "base")
    slide = {"physics:axis": "X", "physics:lowerLimit": -0.1, "physics:upperLimit": 0.1}
    joint(UsdPhysics.PrismaticJoint, "s1", "base", "mid",
          **slide, **{"physics:localPos0": Gf.Vec3f(0.5, 0, 0)})  # fmt: skip
    slide |= {"physics:lowerLimit": -0.5, "physics:upperLimit": 0.0}
    joint(UsdPhysics.PrismaticJoint, "s2", "mid", "tip", **slide)
    filtered = UsdPhysics.FilteredPairsAPI.Apply(stage.GetPrimAtPath(f"{root}/base"))
    filtered.CreateFilteredPairsRel().SetTargets([f"{root}/tip"])
    stage.GetRootLayer().Save()
    return path


@pytest.mark.parametrize("root", ["/robot", "/transparent", "/parent"])
def test_a_filtered_pair_that_collides_is_a_finding_whatever_its_reason_names(
    tmp_path: Path, root: str
) -> None:
    report = collisions(_sliders(tmp_path / "sliders.usda", root), samples=300)
    (pair,) = [p for p in report.pairs if (p.link1, p.link2) == ("base", "tip")]
    assert pair.kind == "sometimes" and pair.rule is not None and not pair.rule.checked
    assert root in (pair.rule.reason or "")
    found = [d for d in report.diagnostics if d.code == "collision-filtered-reachable"]
    assert len(found) == 1 and "'base' and 'tip'" in found[0].message


SOFT = """<robot name="soft">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <link name="mount"><collision><origin xyz="0 0 3"/><geometry><sphere radius="0.01"/></geometry>
  </collision></link>
  <link name="slider"><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <joint name="fixed" type="fixed"><parent link="base"/><child link="mount"/></joint>
  <joint name="slide" type="prismatic"><parent link="mount"/><child link="slider"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
    <safety_controller soft_lower_limit="{low}" soft_upper_limit="1" k_position="10"
      k_velocity="1"/></joint>
</robot>
"""
"""A slider whose cube meets the base's while |slide| < 0.2 m; its soft lower limit
is written in."""


@pytest.mark.parametrize(("low", "kind"), [(0.5, "never"), (0.1, "sometimes")])
def test_a_safety_controller_bounds_the_samples_and_the_default_as_in_moveit(
    tmp_path: Path, low: float, kind: str
) -> None:
    # MoveIt's RobotModel bounds a joint with a <safety_controller> to its soft limits
    # within its limits (jointBoundsFromURDF): the setup assistant's default state (0,
    # or mid-range when 0 is outside) and its random states are taken within them.
    path = tmp_path / "soft.urdf"
    path.write_text(SOFT.format(low=low))
    report = collisions(path, samples=400)
    (pair,) = [p for p in report.pairs if (p.link1, p.link2) == ("base", "slider")]
    assert pair.kind == kind  # not "default": MoveIt's default is (low + 1) / 2
    assert pair.collisions is not None
    if kind == "never":
        assert pair.witness is None and report.free.hits == 400
    else:
        assert pair.witness is not None
        (value,) = dict(pair.witness.configuration)["slide"]
        assert low <= value < 0.2
        share = pair.collisions.hits / 400  # the slider in [low, 0.2) of [low, 1]
        assert abs(share - (0.2 - low) / (1 - low)) < 0.05


def _half_bounded(path: Path) -> Path:
    """A floating base and an arm on a revolute joint with a lower limit only (OpenUSD)."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, "/r").GetPrim())
    for name in ("base", "arm"):
        UsdPhysics.RigidBodyAPI.Apply(UsdGeom.Xform.Define(stage, f"/r/{name}").GetPrim())
        box = UsdGeom.Cube.Define(stage, f"/r/{name}/box").GetPrim()
        UsdPhysics.CollisionAPI.Apply(box)
        box.GetAttribute("size").Set(0.2)
    turn = UsdPhysics.RevoluteJoint.Define(stage, "/r/turn")
    turn.CreateBody0Rel().SetTargets(["/r/base"])
    turn.CreateBody1Rel().SetTargets(["/r/arm"])
    turn.CreateAxisAttr("Y")
    turn.CreateLowerLimitAttr(-60.0)
    stage.GetRootLayer().Save()
    return path


def test_what_is_sampled_is_what_the_mathematics_page_says(tmp_path: Path) -> None:
    from cspace._model.options import LoadOptions
    from cspace.space._collisions.setup import prepare

    # a revolute joint missing a bound is read as continuous: the whole circle, past
    # its one bound (-60 degrees)
    sampler = prepare(_half_bounded(tmp_path / "half.usda"), LoadOptions()).sampler
    x = sampler.block(0, 0)
    column = dict(zip(sampler.space.names, x.T, strict=True))
    assert column["turn"].min() < -3.0 and column["turn"].max() > 3.0
    # the base floats (no joint to the world): its position held at neutral, its
    # rotation Haar-uniform (the mean of each quaternion component's square is 1/4)
    (root,) = [name[: -len(".qw")] for name in column if name.endswith(".qw")]
    assert all(not column[f"{root}.{a}"].any() for a in "xyz")
    for part in ("qw", "qx", "qy", "qz"):
        assert abs(float((column[f"{root}.{part}"] ** 2).mean()) - 0.25) < 0.03


DOCS = Path(__file__).resolve().parent.parent / "docs"


@pytest.mark.parametrize(
    ("page", "says"),
    [
        ("getting-started.md", ["`srdf`", "`mjcf`", "`usd`", "`none`"]),
        ("ci.md", ["(`matrix`: the SRDF, MuJoCo's filters, PhysX's filters, none)"]),
        ("cli.md", ["MuJoCo's contact filters, an OpenUSD stage's\nagainst PhysX's"]),
    ],
)
def test_the_pages_name_every_matrix_a_report_may_hold(page: str, says: list[str]) -> None:
    import json

    from cspace._schema import __file__ as schema_package

    schema = Path(schema_package).parent / "collisions-v1.schema.json"
    matrices = json.loads(schema.read_text())["properties"]["matrix"]["enum"]
    assert matrices == ["srdf", "mjcf", "usd", "none"]
    text = (DOCS / page).read_text()
    if page == "getting-started.md":
        (row,) = [line for line in text.splitlines() if line.startswith("| `matrix` |")]
        text = row
    assert all(said in text for said in says), page
