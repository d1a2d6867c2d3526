"""A robot's collision shapes as a Pinocchio ``GeometryModel``, built by hand.

Each `CollisionSpec` of a link becomes one ``pin.GeometryObject`` on that link's
``BODY`` frame of the model cspace builds (`cspace.pinocchio_model`): boxes, spheres,
cylinders and capsules as coal's primitives, meshes as coal ``BVHModelOBBRSS``
triangle soups built from the vertex and triangle arrays cspace's own readers return
(`cspace._formats.meshes.load.load_meshes`), as MoveIt's FCL checker holds URDF meshes;
an OpenUSD mesh PhysX collides as its convex hull (a ``usd-hull:`` name) as a coal
``Convex`` of that hull, a solid. Neither coal's nor Pinocchio's mesh loaders (assimp)
are ever called: a mesh file's bytes are parsed only by cspace's readers, in their
confined child.
"""

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from cspace._formats.meshes._bounds import Mesh
from cspace._formats.shared.description import CollisionSpec, LinkSpec
from cspace._formats.usd._colliders import HULL
from cspace._record import NamedTuple

MeshKey = tuple[str, tuple[float, float, float]]
"""A mesh as a collision shape names it: its file name as written and its scale."""

MAX_SHAPES = 2_000
"""Most collision shapes of one robot. Pinocchio's ``GeometryModel`` grows an n-by-n
matrix of collision pairs at each object added, so that building one costs n^3 (measured:
1,000 shapes 0.9 s, 2,000 6 s, 3,000 21 s; the 50,000 ``<collision>`` elements a robot
file may hold, a day and 10 GB). talos_reduced has 52, the Shadow hand's MJCF 60."""


class TooManyShapes(ValueError):
    """A robot with more collision shapes than `MAX_SHAPES` (one line)."""


def check_shape_count(count: int) -> None:
    """Refuse ``count`` collision shapes past `MAX_SHAPES`, before any is built.

    Raises:
        TooManyShapes: ``count`` is more than `MAX_SHAPES`.
    """
    if count > MAX_SHAPES:
        raise TooManyShapes(
            f"{count:,} collision shapes, more than the {MAX_SHAPES:,} cspace checks of one robot"
        )


class Shapes(NamedTuple):
    """A robot's collision shapes, ready to be checked.

    Attributes:
        geometry: The ``pin.GeometryModel``, one object a shape, no collision pair yet.
        links: The name of each object's link, by object index.
        with_geometry: The links that have at least one shape, in the file's order.
    """

    geometry: Any
    links: tuple[str, ...]
    with_geometry: tuple[str, ...]


def mesh_key(shape: CollisionSpec) -> MeshKey:
    """The key of a mesh shape in the ``meshes`` mapping `build_shapes` takes."""
    return (shape.mesh or "", shape.scale)


def _mesh_geometry(mesh: Mesh) -> Any:
    import pinocchio as pin

    vertices = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
    triangles = np.ascontiguousarray(mesh.triangles, dtype=np.int64)
    bvh = pin.coal.BVHModelOBBRSS()
    bvh.beginModel(len(triangles), len(vertices))
    bvh.addVertices(vertices)
    bvh.addTriangles(triangles)
    bvh.endModel()
    return bvh


def shape_geometry(shape: CollisionSpec, meshes: Mapping[MeshKey, Mesh]) -> Any:
    """The coal geometry of one collision shape, in the shape's own frame.

    Raises:
        LookupError: A mesh shape whose mesh ``meshes`` lacks, or a kind coal has no
            primitive for.
    """
    import pinocchio as pin

    coal = pin.coal
    sizes = shape.sizes
    if shape.kind == "box":
        return coal.Box(*sizes)
    if shape.kind == "sphere":
        return coal.Sphere(sizes[0])
    if shape.kind == "cylinder":
        return coal.Cylinder(sizes[0], sizes[1])
    if shape.kind == "capsule":
        return coal.Capsule(sizes[0], sizes[1])
    if shape.kind == "mesh":
        key = mesh_key(shape)
        if key not in meshes:
            raise LookupError(f"no mesh read for {shape.mesh!r} at scale {shape.scale}")
        if key[0].startswith(HULL):  # a solid, as PhysX collides it: not its surface
            from cspace._model._collision_hulls import Hull, convex_geometry

            mesh = meshes[key]
            return convex_geometry(Hull(mesh.vertices, mesh.triangles.astype(np.int64)))
        return _mesh_geometry(meshes[key])
    raise LookupError(f"no collision geometry of kind {shape.kind!r}")


def _shared(shape: CollisionSpec, meshes: Mapping[MeshKey, Mesh], made: dict[MeshKey, Any]) -> Any:
    """`shape_geometry`, a mesh's built once and shared by every shape that names it.

    A mesh's BVH costs about 575 bytes and 6 us a triangle: a 6.5 MB OBJ named by 20
    links, a BVH each, took 2.3 GB and 18 s (coal only reads a geometry as it checks).
    """
    if shape.kind != "mesh":
        return shape_geometry(shape, meshes)
    key = mesh_key(shape)
    if key not in made:
        made[key] = shape_geometry(shape, meshes)
    return made[key]


def build_shapes(model: Any, links: Sequence[LinkSpec], meshes: Mapping[MeshKey, Mesh]) -> Shapes:
    """The ``GeometryModel`` of ``links``' collision shapes on ``model``'s link frames.

    Each shape is placed at its origin in its link's ``BODY`` frame, so its placement in
    its joint's frame is the frame's placement times the shape's origin. Objects are
    named ``<link>/<index of the shape in the link>``.

    Args:
        model: The ``pin.Model`` cspace builds for the robot file.
        links: The description's links (`RobotDescription.links`).
        meshes: Every mesh shape's mesh by `mesh_key`, as read and scaled.

    Raises:
        LookupError: A link with shapes that is not a ``BODY`` frame of ``model``, or a
            shape `shape_geometry` refuses.
        TooManyShapes: More shapes than `MAX_SHAPES`.
    """
    import pinocchio as pin

    from cspace._model.closure import se3

    check_shape_count(sum(len(link.collisions) for link in links))
    made: dict[MeshKey, Any] = {}  # one coal geometry a mesh, however many shapes use it
    geometry = pin.GeometryModel()
    names: list[str] = []
    with_geometry: list[str] = []
    for link in links:
        if not link.collisions:
            continue
        if not model.existFrame(link.name, pin.BODY):
            raise LookupError(f"link {link.name!r} is not a body of the model")
        frame_id = model.getFrameId(link.name, pin.BODY)
        frame = model.frames[frame_id]
        with_geometry.append(link.name)
        for index, shape in enumerate(link.collisions):
            item = pin.GeometryObject(
                f"{link.name}/{index}",
                frame.parentJoint,
                frame_id,
                frame.placement * se3(shape.origin),
                _shared(shape, meshes, made),
            )
            geometry.addGeometryObject(item)
            names.append(link.name)
    return Shapes(geometry, tuple(names), tuple(with_geometry))
