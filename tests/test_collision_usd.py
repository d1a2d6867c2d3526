"""OpenUSD collision prims as the USD reader reads them, their meshes, and their filters.

Stages are written here with OpenUSD's own API and read by cspace as any stage is. The
oracles are independent of the reader:

- where each shape is: every collider's geometry computed from OpenUSD's composed
  transform of its prim (``UsdGeom.XformCache``, in metres): a box's eight corners, a
  sphere's centre, a capsule's or cylinder's two cap centres, each mesh point, against
  the same points of the coal shape `build_shapes` places through cspace's Pinocchio
  model (`cspace.pinocchio_model`), at a configuration the stage is authored in; a
  convex hull's vertices against scipy's hull of the same world points;
- whether two shapes collide: coal through the engine (`SelfCollision`) against the
  geometric truth of shapes placed 1 mm apart and 1 mm into each other;
- sizes that PhysX's parser reads otherwise than the geometry (a sphere or capsule
  scaled unevenly) against UsdPhysics's own parser (``LoadUsdPhysicsFromRange``).

The filters are held to what each rule of the stage says, and the hostile stages to
one line each, within their bounds.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
import pytest
from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics, Vt

import cspace
from cspace._formats.meshes._bounds import MAX_MESH_VERTICES
from cspace._formats.shared.collisions import MAX_COLLISIONS
from cspace._formats.shared.description import CollisionSpec, RobotDescription
from cspace._formats.usd.filters import collision_filters
from cspace._model._collision_meshes import ShapeMeshes, read_shape_meshes
from cspace._model._collision_pairs import SelfCollision
from cspace._model._collision_shapes import Shapes, build_shapes, mesh_key
from cspace._model.loader import _build, _open
from cspace._model.options import LoadOptions
from cspace.errors import RobotFileError

NEWTON = Path(__import__("newton").__file__).parent
BOOL = Sdf.ValueTypeNames.Bool


def describe(path: Path) -> RobotDescription:
    """The description cspace reads of the stage at ``path``."""
    source, file, _ = _open(str(path), ())
    return _build(source, LoadOptions(), file=file).reading.description


class Read:
    """A stage read by cspace: its description, model, meshes and placed shapes."""

    def __init__(self, path: Path) -> None:
        self.description = describe(path)
        self.model = cspace.pinocchio_model(str(path))
        self.meshes: ShapeMeshes = read_shape_meshes(self.description.links, str(path), {})
        self.shapes: Shapes = build_shapes(self.model, self.description.links, self.meshes.meshes)

    def placements(self, q: np.ndarray) -> list[pin.SE3]:
        data = self.model.createData()
        geometry_data = pin.GeometryData(self.shapes.geometry)
        pin.updateGeometryPlacements(self.model, data, self.shapes.geometry, geometry_data, q)
        return [pin.SE3(m) for m in geometry_data.oMg]

    def specs(self) -> list[CollisionSpec]:
        return [s for link in self.description.links for s in link.collisions]


def _stage(path: Path, meters: float = 1.0) -> Usd.Stage:
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageMetersPerUnit(stage, meters)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    root = UsdGeom.Xform.Define(stage, "/r")
    stage.SetDefaultPrim(root.GetPrim())
    return stage


def _body(stage: Usd.Stage, path: str, matrix: Gf.Matrix4d | None = None) -> Usd.Prim:
    xform = UsdGeom.Xform.Define(stage, path)
    if matrix is not None:
        xform.AddTransformOp().Set(matrix)
    UsdPhysics.RigidBodyAPI.Apply(xform.GetPrim())
    return xform.GetPrim()


def _place(prim: Any, translate: Any = None, turn: Any = None, scale: Any = None) -> None:
    xform = UsdGeom.Xformable(prim)
    if translate is not None:
        xform.AddTranslateOp().Set(Gf.Vec3d(*translate))
    if turn is not None:
        xform.AddRotateXYZOp().Set(Gf.Vec3f(*turn))
    if scale is not None:
        xform.AddScaleOp().Set(Gf.Vec3f(*scale))


def _collider(stage: Usd.Stage, kind: type, path: str, **attributes: Any) -> Usd.Prim:
    prim = kind.Define(stage, path).GetPrim()
    UsdPhysics.CollisionAPI.Apply(prim)
    for name, value in attributes.items():
        prim.GetAttribute(name).Set(value)
    return prim


BOX_POINTS = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
BOX_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def _mesh(
    stage: Usd.Stage, path: str, points: Any, faces: Any, approximation: str | None = None
) -> Usd.Prim:
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreatePointsAttr(Vt.Vec3fArray([Gf.Vec3f(*p) for p in points]))
    mesh.CreateFaceVertexCountsAttr([len(f) for f in faces])
    mesh.CreateFaceVertexIndicesAttr([i for f in faces for i in f])
    UsdPhysics.CollisionAPI.Apply(mesh.GetPrim())
    if approximation is not None:
        UsdPhysics.MeshCollisionAPI.Apply(mesh.GetPrim()).CreateApproximationAttr(approximation)
    return mesh.GetPrim()


def _joint(
    stage: Usd.Stage, kind: type, path: str, body0: str | None, body1: str, **more: Any
) -> Any:
    joint = kind.Define(stage, path)
    if body0 is not None:
        joint.CreateBody0Rel().SetTargets([body0])
    joint.CreateBody1Rel().SetTargets([body1])
    for name, value in more.items():
        joint.GetPrim().GetAttribute(name).Set(value)
    return joint


# -- where each shape is ------------------------------------------------------------------

THETA = 0.7
"""The arm's joint value the placed stage is authored at (rad)."""


def _placed(folder: Path) -> Path:
    """Bodies under turns and scales, in centimetres, every shape kind, the arm at THETA."""
    path = folder / "placed.usda"
    stage = _stage(path, meters=0.01)
    up = Gf.Matrix4d().SetRotate(Gf.Rotation(Gf.Vec3d(0, 0, 1), 30.0))
    base_matrix = Gf.Matrix4d().SetScale(2.0) * up * Gf.Matrix4d().SetTranslate(Gf.Vec3d(10, 0, 5))
    _body(stage, "/r/base", base_matrix)
    _joint(stage, UsdPhysics.FixedJoint, "/r/mount", None, "/r/base",
           **{"physics:localPos0": Gf.Vec3f(10, 0, 5),
              "physics:localRot0": Gf.Quatf(up.ExtractRotationQuat())})  # fmt: skip
    box = _collider(stage, UsdGeom.Cube, "/r/base/box", size=3.0)
    _place(box, (1, 2, 3), (10, -20, 35), (1, 2, 0.5))
    tilt = UsdGeom.Xform.Define(stage, "/r/base/tilt").GetPrim()
    _place(tilt, (-2, 1, 0), (15, 25, -40), (1.5, 1.5, 1.5))
    for axis in "XYZ":
        cap = _collider(stage, UsdGeom.Capsule, f"/r/base/tilt/cap{axis}", radius=0.3,
                        height=1.2, axis=axis)  # fmt: skip
        _place(cap, ({"X": 0, "Y": 2, "Z": 4}[axis], 0, 1))
        cylinder = _collider(stage, UsdGeom.Cylinder, f"/r/base/tilt/cyl{axis}", radius=0.2,
                             height=0.8, axis=axis)  # fmt: skip
        _place(cylinder, (0, {"X": 0, "Y": 2, "Z": 4}[axis], -1), (5, 0, 0))
    ball = _collider(stage, UsdGeom.Sphere, "/r/base/tilt/ball", radius=0.4)
    _place(ball, (3, 3, 3))
    points = [(0.3 * x, 0.5 * y + 0.1 * x, 0.2 * z) for x, y, z in BOX_POINTS]
    _place(_mesh(stage, "/r/base/tri", points, BOX_FACES, "convexDecomposition"), (0, -3, 0))
    ragged = [(math.cos(a) * (1 + 0.3 * math.sin(3 * a)), math.sin(a), 0.3 * math.cos(5 * a))
              for a in np.linspace(0.0, 6.0, 25)] + [(0.0, 0.0, 1.0)]  # fmt: skip
    fan = [(k, k + 1, 25) for k in range(24)]
    _place(_mesh(stage, "/r/base/hull", ragged, fan, "convexHull"), (0, 3, -2), None, (1, 2, 1))
    # the arm: a revolute joint about the base's (0, 0, 2), at THETA
    local0 = Gf.Vec3f(0, 0, 2)
    frame1 = Gf.Matrix4d().SetRotate(Gf.Rotation(Gf.Vec3d(1, 0, 0), 20.0))
    frame1.SetTranslateOnly(Gf.Vec3d(0.5, 0, -1))
    at = (
        Gf.Matrix4d().SetTranslate(Gf.Vec3d(local0) * 2.0)
        * up
        * Gf.Matrix4d().SetTranslate(Gf.Vec3d(10, 0, 5))
    )
    turned = Gf.Matrix4d().SetRotate(Gf.Rotation(Gf.Vec3d(0, 0, 1), math.degrees(THETA)))
    _body(stage, "/r/arm", frame1.GetInverse() * turned * at)
    _joint(stage, UsdPhysics.RevoluteJoint, "/r/elbow", "/r/base", "/r/arm",
           **{"physics:axis": "Z", "physics:localPos0": local0, "physics:lowerLimit": -170.0,
              "physics:upperLimit": 170.0,
              "physics:localPos1": Gf.Vec3f(frame1.ExtractTranslation()),
              "physics:localRot1": Gf.Quatf(frame1.ExtractRotationQuat())})  # fmt: skip
    fore = _collider(stage, UsdGeom.Cube, "/r/arm/fore", size=1.0)
    _place(fore, (0, 0, 2), (0, 30, 0), (0.5, 0.5, 3))
    _place(_collider(stage, UsdGeom.Capsule, "/r/arm/grip", radius=0.5, height=1.0, axis="Y"),
           (1, 1, 4))  # fmt: skip
    stage.GetRootLayer().Save()
    return path


def _world(cache: UsdGeom.XformCache, prim: Usd.Prim, meters: float) -> Any:
    """A function of USD local points of ``prim`` to world points in metres."""
    matrix = cache.GetLocalToWorldTransform(prim)

    def apply(points: Any) -> np.ndarray:
        return np.array([matrix.Transform(Gf.Vec3d(*map(float, p))) for p in points]) * meters

    return apply


def _act(placement: pin.SE3, points: Any) -> np.ndarray:
    return np.array([placement.act(np.asarray(p, float)) for p in points])


def _colliders(stage: Usd.Stage) -> list[Usd.Prim]:
    """The robot's colliders: each body's, bodies in the reader's order, then the stage's.

    A collider belongs to the nearest rigid body at or above it; one with none, or whose
    ``physics:collisionEnabled`` is false, is not the robot's.
    """
    prims = list(stage.Traverse())
    bodies = [p for p in prims if p.HasAPI(UsdPhysics.RigidBodyAPI)]
    order = {str(b.GetPath()): k for k, b in enumerate(bodies)}

    def body(prim: Usd.Prim) -> str | None:
        while prim and not prim.IsPseudoRoot():
            if prim.HasAPI(UsdPhysics.RigidBodyAPI):
                return str(prim.GetPath())
            prim = prim.GetParent()
        return None

    found = [
        p
        for p in prims
        if p.HasAPI(UsdPhysics.CollisionAPI)
        and body(p) is not None
        and p.GetAttribute("physics:collisionEnabled").Get() is not False
    ]
    return sorted(found, key=lambda p: order[str(body(p))])


def _check_placed(read: Read, stage: Usd.Stage, q: np.ndarray, tolerance: float) -> set[str]:
    """Every shape against OpenUSD's world points of its prim; the kinds seen."""
    import scipy.spatial

    meters = UsdGeom.GetStageMetersPerUnit(stage)
    cache = UsdGeom.XformCache()
    placements = read.placements(q)
    specs = read.specs()
    colliders = _colliders(stage)
    assert len(specs) == len(colliders) == len(placements)
    kinds = set()
    objects = read.shapes.geometry.geometryObjects
    for spec, prim, placed, item in zip(specs, colliders, placements, objects, strict=True):
        world = _world(cache, prim, meters)
        geometry = item.geometry
        kinds.add(prim.GetTypeName())
        if spec.kind == "box":
            half = prim.GetAttribute("size").Get() / 2
            corners = [np.multiply(c, half) for c in BOX_POINTS]
            ours = _act(placed, [np.multiply(c, geometry.halfSide) for c in BOX_POINTS])
            assert np.allclose(ours, world(corners), atol=tolerance)
        elif spec.kind in ("capsule", "cylinder"):
            axis = prim.GetAttribute("axis").Get()
            half = prim.GetAttribute("height").Get() / 2
            ends = [tuple(half * s * (axis == a) for a in "XYZ") for s in (-1, 1)]
            ours = _act(placed, [(0, 0, -geometry.halfLength), (0, 0, geometry.halfLength)])
            assert np.allclose(ours, world(ends), atol=tolerance)
            side = tuple(prim.GetAttribute("radius").Get() * (axis != a) for a in "XYZ")
            edge = world([(0, 0, 0), side])  # scaled evenly across its axis here
            assert geometry.radius * math.sqrt(2) == pytest.approx(
                np.linalg.norm(edge[1] - edge[0])
            )
        elif spec.kind == "sphere":
            assert np.allclose(placed.translation, world([(0, 0, 0)])[0], atol=tolerance)
            edge = world([(prim.GetAttribute("radius").Get(), 0, 0), (0, 0, 0)])
            assert geometry.radius == pytest.approx(np.linalg.norm(edge[0] - edge[1]))
        else:
            mesh = read.meshes.meshes[mesh_key(spec)]
            points = world(prim.GetAttribute("points").Get())
            ours = _act(placed, mesh.vertices)
            if spec.mesh is not None and spec.mesh.startswith("usd-hull:"):
                hull = scipy.spatial.ConvexHull(points)
                expected = points[hull.vertices]
                assert len(ours) == len(expected)
                nearest = np.min(np.linalg.norm(ours[:, None] - expected[None], axis=2), axis=1)
                assert nearest.max() < tolerance
                kinds.add("hull")
            else:
                assert np.allclose(ours, points, atol=tolerance)
                counts = prim.GetAttribute("faceVertexCounts").Get()
                assert len(mesh.triangles) == sum(c - 2 for c in counts)
    return kinds


def test_every_shape_is_where_openusd_puts_its_prim(tmp_path: Path) -> None:
    path = _placed(tmp_path)
    read = Read(path)
    q = np.array([THETA])
    assert read.model.nq == 1
    kinds = _check_placed(read, Usd.Stage.Open(str(path)), q, 1e-9)
    assert kinds == {"Cube", "Capsule", "Cylinder", "Sphere", "Mesh", "hull"}
    assert read.meshes.problems == ()
    # at another value the arm's shapes move, the base's do not
    moved = read.placements(np.array([THETA + 0.5]))
    still = read.placements(q)
    links = read.shapes.links
    for link, a, b in zip(links, moved, still, strict=True):
        assert np.allclose(a.homogeneous, b.homogeneous) == (link == "base"), link


def test_sizes_are_physx_parsers(tmp_path: Path) -> None:
    """A capsule or sphere scaled unevenly is PhysX's primitive: its largest radius."""
    path = tmp_path / "uneven.usda"
    stage = _stage(path)
    _body(stage, "/r/b")
    _place(_collider(stage, UsdGeom.Sphere, "/r/b/ball", radius=0.5), None, None, (1, 2, 3))
    for axis in "XYZ":
        cap = _collider(stage, UsdGeom.Capsule, f"/r/b/c{axis}", radius=0.25, height=2.0,
                        axis=axis)  # fmt: skip
        _place(cap, None, (10, 20, 30), (1.5, 2.5, 0.5))
    _place(_collider(stage, UsdGeom.Cube, "/r/b/box", size=0.5), None, None, (-1, 2, 3))
    stage.GetRootLayer().Save()
    load = getattr(UsdPhysics, "UsdPhysicsLoadStageFromPrimRange", None)
    parsed = (load or UsdPhysics.LoadUsdPhysicsFromRange)(stage, ["/"])
    theirs = {}
    for kind in ("SphereShape", "CapsuleShape", "CubeShape"):
        for prim, desc in zip(*parsed[getattr(UsdPhysics.ObjectType, kind)], strict=True):
            theirs[prim.name] = desc
    ours = dict(zip(["ball", "cX", "cY", "cZ", "box"], read_specs(path), strict=True))
    assert ours["ball"].sizes == pytest.approx([theirs["ball"].radius], rel=1e-6)
    for axis in "XYZ":
        desc = theirs[f"c{axis}"]
        radius, length = ours[f"c{axis}"].sizes
        assert (radius, length / 2) == pytest.approx((desc.radius, desc.halfHeight), rel=1e-6)
        w, x, y, z = ours[f"c{axis}"].origin.rotation_wxyz
        along = pin.Quaternion(w, x, y, z).matrix()[:, 2]  # coal's axis, in the body
        local = Gf.Rotation(Gf.Quatd(desc.localRot)).TransformDir(
            Gf.Vec3d(*[float(axis == a) for a in "XYZ"])
        )
        assert np.allclose(along, local, atol=1e-6)
    assert ours["box"].sizes == pytest.approx([2 * abs(h) for h in theirs["box"].halfExtents])


def read_specs(path: Path) -> list[CollisionSpec]:
    return [s for link in describe(path).links for s in link.collisions]


# -- collisions against the geometric truth -----------------------------------------------

REACH = {
    "box": 0.1,
    "sphere": 0.15,
    "capsuleX": 0.05 + 0.2,
    "capsuleY": 0.05,
    "cylinderZ": 0.08,
    "cylinderX": 0.15,
    "mesh": 0.1,
    "hull": 0.1,
}
"""How far each slider shape reaches towards -X from the slider's origin (m)."""


def _slider(folder: Path, shape: str, base: float = 0.2) -> Path:
    """A base with a ``base`` m cube at the origin, a slider along X from x = 0.5 with
    ``shape``."""
    path = folder / f"slide_{shape}_{base}.usda"
    stage = _stage(path)
    _body(stage, "/r/base")
    _joint(stage, UsdPhysics.FixedJoint, "/r/mount", None, "/r/base")
    _collider(stage, UsdGeom.Cube, "/r/base/box", size=base)
    _body(stage, "/r/slider", Gf.Matrix4d().SetTranslate(Gf.Vec3d(0.5, 0, 0)))
    _joint(stage, UsdPhysics.PrismaticJoint, "/r/slide", "/r/base", "/r/slider",
           **{"physics:axis": "X", "physics:localPos0": Gf.Vec3f(0.5, 0, 0)})  # fmt: skip
    if shape == "box":
        _collider(stage, UsdGeom.Cube, "/r/slider/s", size=0.2)
    elif shape == "sphere":
        _collider(stage, UsdGeom.Sphere, "/r/slider/s", radius=0.15)
    elif shape.startswith(("capsule", "cylinder")):
        kind = UsdGeom.Capsule if shape.startswith("capsule") else UsdGeom.Cylinder
        radius, height = (0.05, 0.4) if kind is UsdGeom.Capsule else (0.08, 0.3)
        _collider(stage, kind, "/r/slider/s", radius=radius, height=height, axis=shape[-1])
    else:  # a 0.2 m cube of triangles (on a kinematic body) or its hull
        points = [(0.1 * x, 0.1 * y, 0.1 * z) for x, y, z in BOX_POINTS]
        _mesh(stage, "/r/slider/s", points, BOX_FACES, "convexHull" if shape == "hull" else "sdf")
    stage.GetRootLayer().Save()
    return path


@pytest.mark.parametrize("shape", sorted(REACH))
def test_shapes_1_mm_apart_do_not_collide_1_mm_into_each_other_do(
    tmp_path: Path, shape: str
) -> None:
    read = Read(_slider(tmp_path, shape))
    engine = SelfCollision(read.model, read.shapes, [("base", "slider")])
    touching = 0.1 + REACH[shape] - 0.5  # the slider's value where the two shapes touch
    assert engine.colliding(np.array([touching - 0.001])) == {0}
    assert engine.colliding(np.array([touching + 0.001])) == set()


U_BARS = [((0.3, 0.4), (-0.3, 0.3)), ((0.0, 0.4), (0.2, 0.3)), ((0.0, 0.4), (-0.3, -0.2))]
"""The U's three bars, (x range, y range), z in [-0.1, 0.1]: open towards -X."""


def _u_stage(folder: Path, approximation: str, kinematic: bool) -> Path:
    """A U on a body, a probe in its notch sticking out of its mouth: only its hull hits."""
    path = folder / f"u_{approximation}_{kinematic}.usda"
    stage = _stage(path)
    _body(stage, "/r/base")
    _joint(stage, UsdPhysics.FixedJoint, "/r/mount", None, "/r/base")
    _place(_collider(stage, UsdGeom.Cube, "/r/base/probe", size=0.2), None, None, (1, 1, 0.5))
    u = _body(stage, "/r/u")
    if kinematic:
        u.GetAttribute("physics:kinematicEnabled").Set(True)
    _joint(stage, UsdPhysics.PrismaticJoint, "/r/slide", "/r/base", "/r/u", **{"physics:axis": "X"})
    points, faces = [], []
    for (x0, x1), (y0, y1) in U_BARS:
        first = len(points)
        points += [((x0, x1)[x > 0], (y0, y1)[y > 0], 0.1 * z) for x, y, z in BOX_POINTS]
        faces += [tuple(first + i for i in face) for face in BOX_FACES]
    _mesh(stage, "/r/u/u", points, faces, approximation)
    stage.GetRootLayer().Save()
    return path


@pytest.mark.parametrize(
    ("approximation", "kinematic", "hull"),
    [
        ("convexHull", False, True),
        ("none", False, True),  # PhysX's fallback on a dynamic body
        ("meshSimplification", False, True),
        ("none", True, False),  # a kinematic body keeps its triangles
        ("convexDecomposition", False, False),
        ("sdf", False, False),
    ],
)
def test_a_mesh_is_its_hull_or_its_triangles_as_physx_makes_it(
    tmp_path: Path, approximation: str, kinematic: bool, hull: bool
) -> None:
    read = Read(_u_stage(tmp_path, approximation, kinematic))
    (spec,) = [s for link in read.description.links for s in link.collisions if s.kind == "mesh"]
    assert spec.mesh == ("usd-hull:/r/u/u" if hull else "usd:/r/u/u")
    engine = SelfCollision(read.model, read.shapes, [("base", "u")])
    assert engine.colliding(np.zeros(1)) == ({0} if hull else set())
    assert engine.colliding(np.array([-0.4])) == {0}  # the U's back bar reached


# -- a real robot -------------------------------------------------------------------------

ROBOTS = [
    "examples/assets/humanoid.usda",
    "examples/assets/ant.usda",
    "tests/assets/humanoid_mjc.usda",
]


@pytest.mark.parametrize("robot", ROBOTS)
def test_newtons_robots_shapes_load_where_openusd_puts_them(robot: str) -> None:
    path = NEWTON / robot
    read = Read(path)
    stage = Usd.Stage.Open(str(path))
    assert len(read.shapes.links) >= 13
    assert all(not link.unread for link in read.description.links)
    # the humanoid's bodies are authored up to 3e-5 m off its (float32) joint frames
    kinds = _check_placed(read, stage, _authored(read, stage), 1e-4)
    assert "Capsule" in kinds
    filters = collision_filters(str(path))
    assert filters.problems == ()
    edges = {tuple(sorted((j.parent, j.child))) for j in read.description.joints}
    with_shapes = set(read.shapes.with_geometry)
    jointed = {e for e in edges if set(e) <= with_shapes}
    assert jointed and jointed <= set(filters.pairs)  # no joint of theirs enables collisions


def _authored(read: Read, stage: Usd.Stage) -> np.ndarray:
    """The configuration the stage is authored in: joints at zero, a free root where it is."""
    q = pin.neutral(read.model)
    root = read.description.joints[0]
    if root.kind.name == "FLOATING":
        (body,) = [
            p
            for p in stage.Traverse()
            if p.GetName() == root.child and p.HasAPI(UsdPhysics.RigidBodyAPI)
        ]
        pose = Gf.Transform(UsdGeom.XformCache().GetLocalToWorldTransform(body))
        turn = pose.GetRotation().GetQuat()
        meters = UsdGeom.GetStageMetersPerUnit(stage)
        q[:3] = np.array(pose.GetTranslation()) * meters
        q[3:7] = [*turn.GetImaginary(), turn.GetReal()]  # Pinocchio's x, y, z, w
    return q


# -- filters ------------------------------------------------------------------------------


def _boxes(stage: Usd.Stage, names: str, where: str = "/r") -> None:
    for k, name in enumerate(names):
        _body(stage, f"{where}/{name}", Gf.Matrix4d().SetTranslate(Gf.Vec3d(2.0 * k, 0, 0)))
        _collider(stage, UsdGeom.Cube, f"{where}/{name}/box", size=0.5)


def test_joints_and_articulations_filter_as_physx_does(tmp_path: Path) -> None:
    path = tmp_path / "joints.usda"
    stage = _stage(path)
    UsdPhysics.ArticulationRootAPI.Apply(stage.GetPrimAtPath("/r"))
    _boxes(stage, "abcde")
    _joint(stage, UsdPhysics.FixedJoint, "/r/mount", None, "/r/a")
    _joint(stage, UsdPhysics.RevoluteJoint, "/r/ab", "/r/a", "/r/b")  # collisionEnabled: false
    _joint(stage, UsdPhysics.RevoluteJoint, "/r/bc", "/r/b", "/r/c",
           **{"physics:collisionEnabled": True})  # fmt: skip
    out = {"physics:collisionEnabled": True, "physics:excludeFromArticulation": True}
    _joint(stage, UsdPhysics.RevoluteJoint, "/r/cd", "/r/c", "/r/d", **out)
    _joint(stage, UsdPhysics.RevoluteJoint, "/r/de", "/r/d", "/r/e",
           **{"physics:collisionEnabled": True, "physics:jointEnabled": False})  # fmt: skip
    stage.GetRootLayer().Save()
    pairs = collision_filters(str(path)).pairs
    assert set(pairs) == {("a", "b"), ("b", "c")}
    assert pairs[("a", "b")] == "joint 'ab' has physics:collisionEnabled false (the default)"
    assert "articulation" in pairs[("b", "c")]
    root = stage.GetPrimAtPath("/r")
    selfless = root.CreateAttribute("physxArticulation:enabledSelfCollisions", BOOL)
    selfless.Set(False)
    path = tmp_path / "selfless.usda"  # a file of its own: the OpenUSD child reads it anew
    stage.GetRootLayer().Export(str(path))
    pairs = collision_filters(str(path)).pairs
    # d is held by a joint out of the articulation; e by a disabled one: neither is in it
    assert set(pairs) == {("a", "b"), ("b", "c"), ("a", "c")}
    assert "enabledSelfCollisions false" in pairs[("a", "c")]


def test_filtered_pairs_and_collision_groups(tmp_path: Path) -> None:
    path = tmp_path / "groups.usda"
    stage = _stage(path)
    _boxes(stage, "abcdefghij")
    _collider(stage, UsdGeom.Sphere, "/r/c/ball", radius=0.1)  # c has two colliders
    pairs_of = UsdPhysics.FilteredPairsAPI.Apply
    pairs_of(stage.GetPrimAtPath("/r/a")).CreateFilteredPairsRel().SetTargets(["/r/b", "/r/nope"])
    pairs_of(stage.GetPrimAtPath("/r/c/box")).CreateFilteredPairsRel().SetTargets(["/r/d"])
    pairs_of(stage.GetPrimAtPath("/r/e/box")).CreateFilteredPairsRel().SetTargets(
        ["/r/c/box", "/r/c/ball"]
    )

    def group(name: str, members: list[str], filtered: list[str], **more: Any) -> None:
        made = UsdPhysics.CollisionGroup.Define(stage, f"/groups/{name}")
        made.GetCollidersCollectionAPI().CreateIncludesRel().SetTargets(members)
        made.CreateFilteredGroupsRel().SetTargets(filtered)
        for key, value in more.items():
            made.GetPrim().GetAttribute(key).Set(value)

    group("f", ["/r/f"], ["/groups/g"])  # f and g apart
    group("g", ["/r/g"], [])
    group("h", ["/r/h"], ["/groups/h"], **{"physics:invertFilteredGroups": True})  # h: only h
    group("i", ["/r/i"], ["/groups/i"], **{"physics:mergeGroup": "m"})  # i and j: one group
    group("j", ["/r/j"], [], **{"physics:mergeGroup": "m"})
    stage.GetRootLayer().Save()
    found = collision_filters(str(path))
    assert set(found.pairs) == {
        ("a", "b"),
        ("c", "e"),  # both of c's colliders against e's one
        ("f", "g"),
        ("f", "h"),
        ("g", "h"),
        ("h", "i"),
        ("h", "j"),
        ("i", "j"),
    }  # not c-d: c's sphere and d collide
    assert found.pairs[("a", "b")] == "physics:filteredPairs of '/r/a'"
    assert found.pairs[("f", "g")] == "collision groups '/groups/f' and '/groups/g'"
    assert found.problems == (
        "physics:filteredPairs of '/r/a' names '/r/nope', no body, collider or articulation "
        "of the robot",
    )


# -- hostile stages -----------------------------------------------------------------------


def _one_mesh(folder: Path, name: str, points: Any, counts: Any, indices: Any, **more: Any) -> Path:
    path = folder / f"{name}.usdc"
    stage = _stage(path)
    _body(stage, "/r/b")
    mesh = UsdGeom.Mesh.Define(stage, "/r/b/m")
    mesh.CreatePointsAttr(points)
    mesh.CreateFaceVertexCountsAttr(counts)
    mesh.CreateFaceVertexIndicesAttr(indices)
    UsdPhysics.CollisionAPI.Apply(mesh.GetPrim())
    if more.get("approximation"):
        UsdPhysics.MeshCollisionAPI.Apply(mesh.GetPrim()).CreateApproximationAttr(
            more["approximation"]
        )
    stage.GetRootLayer().Save()
    return path


def _problems(path: Path) -> list[str]:
    """The one-line problems of a stage's mesh shapes."""
    description = describe(path)
    found = read_shape_meshes(description.links, str(path), {})
    return [p.problem for p in found.problems]


TETRA = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]


@pytest.mark.parametrize(
    ("points", "counts", "indices", "approximation", "problem"),
    [
        (TETRA, [3, 3], [0, 1, 2, 0, 1, 9], "sdf", "a triangle names vertex 10, beyond the 4"),
        (TETRA, [3, 3], [0, 1, 2, 0, 1, -1], "sdf", "a triangle names vertex 0, beyond the 4"),
        ([(0, 0, 0), (1, float("nan"), 0), (0, 1, 0)], [3], [0, 1, 2], "sdf",
         "vertex 2 is not finite"),
        ([(0, 0, 0), (1, float("inf"), 0), (0, 1, 0), (0, 0, 1)], [3], [0, 1, 2], "convexHull",
         "vertex 2 is not finite"),
        (TETRA, [3, -3, 3], [0, 1, 2], "sdf", "its faceVertexCounts[1] is negative"),
        (TETRA, [2**31 - 1], [0, 1, 2], "sdf", "its faceVertexCounts add up to 2,147,483,647"),
        (TETRA, [2**30, 2**30, 2**30, 2**30], [0, 1, 2], "sdf", "add up to 4,294,967,296, not"),
        ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)], [3], [0, 1, 2], "convexHull",
         "its points lie in a plane or on a line: no convex hull"),
        ([(1, 1, 1)] * 9, [3], [0, 1, 2], "convexHull", "its points are all one point"),
        (TETRA[:3], [3], [0, 1, 2], "convexHull", "its 3 points make no convex hull"),
    ],
)  # fmt: skip
def test_a_malformed_mesh_is_one_line(
    tmp_path: Path, points: Any, counts: Any, indices: Any, approximation: str, problem: str
) -> None:
    path = _one_mesh(tmp_path, "bad", points, counts, indices, approximation=approximation)
    (said,) = _problems(path)
    assert problem in said and "\n" not in said


@pytest.mark.bounded
def test_a_mesh_past_the_bounds_is_refused_before_it_is_parsed(tmp_path: Path) -> None:
    many = np.zeros((MAX_MESH_VERTICES + 1, 3), np.float32)
    path = _one_mesh(tmp_path, "points", Vt.Vec3fArray.FromNumpy(many), [3], [0, 1, 2])
    (said,) = _problems(path)
    assert said == "it has 1,000,001 points, more than the 1,000,000 a mesh may have"
    faces = np.full(2_000_001, 3, np.int32)
    path = _one_mesh(
        tmp_path, "faces", TETRA, Vt.IntArray.FromNumpy(faces), [0, 1, 2], approximation="sdf"
    )
    (said,) = _problems(path)
    assert said.startswith("it has 2,000,001 faces and 3 face-vertex indices, more than")


@pytest.mark.bounded
def test_meshes_referenced_past_the_robots_bound_are_refused_each(tmp_path: Path) -> None:
    """One mesh layer of 900,000 points referenced five times: 4.5 million points."""
    part = tmp_path / "part.usdc"
    layer = Usd.Stage.CreateNew(str(part))
    mesh = UsdGeom.Mesh.Define(layer, "/m")
    rng = np.random.default_rng(5)
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(rng.normal(size=(900_000, 3)).astype(np.float32)))
    mesh.CreateFaceVertexCountsAttr([3])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2])
    UsdPhysics.CollisionAPI.Apply(mesh.GetPrim())
    UsdPhysics.MeshCollisionAPI.Apply(mesh.GetPrim()).CreateApproximationAttr("sdf")
    layer.SetDefaultPrim(mesh.GetPrim())
    layer.GetRootLayer().Save()
    path = tmp_path / "five.usda"
    stage = _stage(path)
    for k in range(5):
        _body(stage, f"/r/b{k}")
        UsdGeom.Mesh.Define(stage, f"/r/b{k}/m").GetPrim().GetReferences().AddReference(
            "./part.usdc"
        )
    stage.GetRootLayer().Save()
    description = describe(path)
    found = read_shape_meshes(description.links, str(path), {})
    assert len(found.meshes) == 4
    (problem,) = found.problems
    assert problem.link == "b4"
    assert problem.problem == (
        "with it, the robot's meshes have more than the 4,000,000 vertices cspace reads"
    )


@pytest.mark.bounded
def test_more_collision_prims_than_cspace_reads_refuse_the_stage(tmp_path: Path) -> None:
    cube = 'def Cube "c{0}" (prepend apiSchemas = ["PhysicsCollisionAPI"]) {{}}\n'
    path = tmp_path / "many.usda"
    path.write_text(
        '#usda 1.0\n(\n    defaultPrim = "r"\n)\ndef Xform "r"\n{\n'
        'def Xform "b" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])\n{\n'
        + "".join(cube.format(k) for k in range(MAX_COLLISIONS + 1))
        + "}\n}\n"
    )
    with pytest.raises(RobotFileError) as raised:
        describe(path)
    assert raised.value.code == "too-many-elements"
    assert "more than 50,000 prims with PhysicsCollisionAPI" in str(raised.value)


def test_colliders_cspace_cannot_check_are_one_line_each(tmp_path: Path) -> None:
    path = tmp_path / "odd.usda"
    stage = _stage(path)
    _body(stage, "/r/b")
    _collider(stage, UsdGeom.Cube, "/r/b/fine", size=1.0)
    _collider(stage, UsdGeom.Cone, "/r/b/cone")
    _collider(stage, UsdGeom.Sphere, "/r/b/nan", radius=float("nan"))
    _collider(stage, UsdGeom.Xform, "/r/b/empty")
    _mesh(stage, "/r/b/box", TETRA, [(0, 1, 2)], "boundingCube")
    _place(_collider(stage, UsdGeom.Cube, "/r/b/flat"), None, None, (1, 0, 1))
    _collider(stage, UsdGeom.Cube, "/r/b/off", **{"physics:collisionEnabled": False})
    _collider(stage, UsdGeom.Cube, "/r/static")  # no body: the world's, not the robot's
    stage.GetRootLayer().Save()
    (link,) = [link for link in describe(path).links if link.name == "b"]
    assert [s.kind for s in link.collisions] == ["box"]
    assert [line for line, _ in link.unread] == [None] * 5
    said = [problem for _, problem in link.unread]
    assert said == [
        "link 'b': collision prim '/r/b/cone': it is a prim of type Cone, not a shape "
        "UsdPhysics makes a collider of that cspace checks (Cube, Sphere, Cylinder, Capsule, "
        "Mesh)",
        "link 'b': collision prim '/r/b/nan': its radius is not finite",
        "link 'b': collision prim '/r/b/empty': it is a prim of type Xform, not a shape "
        "UsdPhysics makes a collider of that cspace checks (Cube, Sphere, Cylinder, Capsule, "
        "Mesh)",
        "link 'b': collision prim '/r/b/box': its physics:approximation \"boundingCube\" is a "
        "shape cspace does not fit (it reads none, convexHull, convexDecomposition, "
        "meshSimplification, sdf)",
        "link 'b': collision prim '/r/b/flat': its transform or its body's is not finite or "
        "has a zero scale",
    ]


@pytest.mark.parametrize("solid", [True, False], ids=["hull", "triangles"])
def test_a_hull_is_a_solid_and_triangles_a_surface(tmp_path: Path, solid: bool) -> None:
    """A 2 cm cube deep inside a 20 cm mesh cube: inside its hull (PhysX's convex solid,
    coal's ``Convex``), not touching its triangles (a surface: a BVH of them)."""
    read = Read(_slider(tmp_path, "hull" if solid else "mesh", base=0.02))
    engine = SelfCollision(read.model, read.shapes, [("base", "slider")])
    assert engine.colliding(np.array([-0.5])) == ({0} if solid else set())  # centred
    assert engine.colliding(np.array([-0.4])) == {0}  # on the mesh's face: both touch
