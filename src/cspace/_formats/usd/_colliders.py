"""A stage's collision prims, filters and mesh arrays, read in `usd._worker`'s confined child.

It answers plain numbers and strings; `usd._collision` (in the parent) makes them shapes.
Each collider is read as UsdPhysics's own parser (``parseUtils.cpp``, which PhysX and
Isaac Sim use) reads it:

- a collider is a prim with ``PhysicsCollisionAPI`` whose ``physics:collisionEnabled`` is
  not false; it belongs to the nearest prim at or above it with ``PhysicsRigidBodyAPI``
  (``_GetRigidBody``); when that body is disabled, or there is none, it is a static
  collider, the world's, left out here (a ground, a table: not the robot);
- its pose in its body's frame is ``GfTransform(world * inverse(body world))``'s rotation
  and translation, the translation scaled by the body's world scale
  (``_GetCollisionShapeLocalTransfrom``): the body's frame is its world transform
  without scale, cspace's link frame; all in double precision;
- its size is scaled by the collider's own world scale (``GfTransform.GetScale``): a
  ``Cube``'s edges are ``|size|`` times ``|scale|`` per axis; a ``Sphere``'s radius
  ``|radius|`` times the largest ``|scale|``; a ``Cylinder``'s or ``Capsule``'s radius
  times the larger of the two scales across ``axis``, its height (between the caps'
  centres, for a capsule) times the scale along it, and its frame turned so that its
  axis is the shape's Z (coal's), an ``axis`` other than ``Y`` or ``Z`` being ``X`` as
  UsdPhysics reads it. A non-uniform scale on a sphere or capsule is thus PhysX's
  primitive (the largest radius), not an ellipsoid;
- a ``Mesh`` is named, not read here (its arrays come in `mesh_arrays`, asked for only
  by the self-collision command): ``usd:<prim path>``, its triangles as written, or
  ``usd-hull:<prim path>``, the convex hull of its points, by its
  ``physics:approximation`` (``PhysicsMeshCollisionAPI``; ``none`` without it): see
  `MESH_NAMES`; scaled by its world scale, as UsdPhysics's ``meshScale``;
- any other prim with the API (a ``Cone``, a ``Plane``, ``Points``, a ``Capsule_1``, an
  ``Xform``...) is a problem, one line.

Sizes and positions are in stage units (the parent applies ``metersPerUnit``).
"""

from __future__ import annotations

import json
import math
from typing import Any

from cspace._formats.meshes._bounds import (
    MAX_MESH_TRIANGLES,
    MAX_MESH_VERTICES,
    MAX_TOTAL_TRIANGLES,
    MAX_TOTAL_VERTICES,
)
from cspace._formats.usd._frames import FLAT

HULL = "usd-hull:"
"""The prefix of a mesh shape that is the convex hull of a USD mesh's points."""

TRIANGLES = "usd:"
"""The prefix of a mesh shape that is a USD mesh's triangles as written."""

MESH_NAMES: dict[str, str | None] = {
    "convexHull": HULL,
    "convexDecomposition": TRIANGLES,
    "sdf": TRIANGLES,
    "none": None,
    "meshSimplification": None,
}
"""The shape each ``physics:approximation`` makes of a mesh. ``convexHull`` is its points'
convex hull (PhysX's is the same hull, cut to ``hullVertexLimit`` vertices, 64 by
default); ``convexDecomposition`` (V-HACD's convex pieces, which cspace does not compute)
and ``sdf`` (PhysX's signed distance field of the triangles) are the triangles as
written; ``none`` and ``meshSimplification`` (None here) are the triangles on a kinematic
body and the convex hull on a dynamic one, as PhysX falls back ("triangle mesh collision
... cannot be a part of a dynamic body, falling back to convexHull approximation").
``boundingCube`` and ``boundingSphere`` (a box or sphere PhysX fits) are problems."""

MAX_FILTER_TARGETS = 200_000
"""Most ``physics:filteredPairs`` targets and collision-group members read from a stage."""

MESH_ANSWER_BYTES = 48 * 1024 * 1024
"""Most bytes of mesh arrays in one answer (the child's output bound is 64 MiB); one mesh
within `_bounds`'s is at most 44 MiB. The parent asks again for the meshes left."""

_SIZE_DEFAULTS = {"size": 2.0, "radius": 1.0, "height": 2.0}
_CAPSULE_DEFAULTS = {"radius": 0.5, "height": 1.0}
_KINDS = {"Cube": "box", "Sphere": "sphere", "Cylinder": "cylinder", "Capsule": "capsule"}
_HALF = math.sqrt(0.5)
_TO_AXIS = {"X": (_HALF, 0.0, _HALF, 0.0), "Y": (_HALF, -_HALF, 0.0, 0.0), "Z": None}
"""The rotation (w, x, y, z) that takes Z to each axis: about Y by +90 deg, about X by -90."""


class Unreadable(Exception):
    """A collider read no further: its problem, one line."""


def owner(prim: Any, bodies: set[str]) -> str | None:
    """The simulated body a collider belongs to (``bodies``: their paths), or None."""
    from pxr import UsdPhysics  # type: ignore[import-untyped]

    while prim and not prim.IsPseudoRoot():
        if prim.HasAPI(UsdPhysics.RigidBodyAPI):
            path = str(prim.GetPath())
            return path if path in bodies else None  # a disabled body: static
        prim = prim.GetParent()
    return None


def enabled(prim: Any) -> bool:
    """Whether a prim's ``physics:collisionEnabled`` is not false."""
    attribute = prim.GetAttribute("physics:collisionEnabled")
    return not (attribute and attribute.Get() is False)


def collider_facts(prim: Any, body: str, cache: Any, frames: dict[str, Any]) -> dict[str, Any]:
    """One collider's facts: its shape, or its problem (see the module docstring).

    Args:
        prim: The collider.
        body: Its body's path.
        cache: A ``UsdGeom.XformCache`` at the default time.
        frames: Each body's world transform, its inverse and its scale, or None when
            flat, as computed so far (filled here).
    """
    path = str(prim.GetPath())
    try:
        return {"path": path, "body": body, **_shape(prim, body, cache, frames)}
    except Unreadable as exc:
        return {"path": path, "body": body, "problem": str(exc)}


def _shape(prim: Any, body: str, cache: Any, frames: dict[str, Any]) -> dict[str, Any]:
    from pxr import Gf

    kind = prim.GetTypeName()
    if kind != "Mesh" and kind not in _KINDS:
        shown = f"a prim of type {kind}" if kind else "a prim of no type"
        raise Unreadable(
            f"it is {shown}, not a shape UsdPhysics makes a collider of that cspace checks "
            "(Cube, Sphere, Cylinder, Capsule, Mesh)"
        )
    world = cache.GetLocalToWorldTransform(prim)
    if body not in frames:
        matrix = cache.GetLocalToWorldTransform(prim.GetStage().GetPrimAtPath(body))
        transform = Gf.Transform(matrix)
        flat = _flat(matrix, transform)
        frames[body] = None if flat else (matrix.GetInverse(), transform.GetScale())
    own = Gf.Transform(world)
    if frames[body] is None or _flat(world, own):
        raise Unreadable("its transform or its body's is not finite or has a zero scale")
    rotation = Gf.Quatd(1.0)
    position = Gf.Vec3d(0.0)
    if str(prim.GetPath()) != body:
        inverse, body_scale = frames[body]
        local = Gf.Transform(world * inverse)
        rotation = local.GetRotation().GetQuat().GetNormalized()
        position = Gf.CompMult(local.GetTranslation(), body_scale)
    scale = _three(own.GetScale())
    size = [abs(s) for s in scale]
    facts: dict[str, Any] = {"kind": _KINDS.get(kind, "mesh")}
    if kind == "Cube":
        edge = abs(_number(prim, "size", 2.0))
        facts["sizes"] = [edge * s for s in size]
    elif kind == "Sphere":
        facts["sizes"] = [abs(_number(prim, "radius", 1.0)) * max(size)]
    elif kind in ("Cylinder", "Capsule"):
        defaults = _SIZE_DEFAULTS if kind == "Cylinder" else _CAPSULE_DEFAULTS
        radius = abs(_number(prim, "radius", defaults["radius"]))
        height = abs(_number(prim, "height", defaults["height"]))
        axis = _token(prim, "axis", "Z")
        along = {"Y": 1, "Z": 2}.get(axis, 0)
        across = max(s for k, s in enumerate(size) if k != along)
        facts["sizes"] = [radius * across, height * size[along]]
        turn = _TO_AXIS.get(axis, _TO_AXIS["X"])
        if turn is not None:
            rotation = rotation * Gf.Quatd(turn[0], Gf.Vec3d(*turn[1:]))
    else:
        facts["mesh"] = _mesh_name(prim, body) + str(prim.GetPath())
        facts["scale"] = scale
    facts["pos"] = _three(position)
    facts["rot"] = [float(rotation.GetReal()), *_three(rotation.GetImaginary())]
    return facts


def _flat(matrix: Any, transform: Any) -> bool:
    """Whether a transform is not finite or flattens space (`usd._frames._singular`).

    Its 3x3 part's determinant is finite only when every entry is (inf times 0 is NaN).
    """
    moved = matrix.ExtractTranslation().GetLength()
    if not math.isfinite(matrix.GetDeterminant3()) or not math.isfinite(moved):
        return True
    return min(abs(s) for s in _three(transform.GetScale())) < FLAT


def _three(vector: Any) -> list[float]:
    """A Gf vector's components (indexed: iterating one costs ten times as much)."""
    return [float(vector[0]), float(vector[1]), float(vector[2])]


def _mesh_name(prim: Any, body: str) -> str:
    from pxr import UsdPhysics

    approximation = "none"
    if prim.HasAPI(UsdPhysics.MeshCollisionAPI):
        approximation = _token(prim, "physics:approximation", "none")
    if approximation not in MESH_NAMES:
        said = json.dumps(approximation[:40])
        raise Unreadable(
            f"its physics:approximation {said} is a shape cspace does not fit "
            "(it reads none, convexHull, convexDecomposition, meshSimplification, sdf)"
        )
    name = MESH_NAMES[approximation]
    if name is None:  # PhysX's triangle mesh: on a kinematic body only
        kinematic = prim.GetStage().GetPrimAtPath(body).GetAttribute("physics:kinematicEnabled")
        name = TRIANGLES if kinematic and kinematic.Get() is True else HULL
    return name


def _number(prim: Any, name: str, default: float) -> float:
    attribute = prim.GetAttribute(name)
    got = attribute.Get() if attribute else None
    if got is None:
        return default
    if isinstance(got, bool) or not isinstance(got, (int, float)):
        raise Unreadable(f"its {name} is not a number")
    if not math.isfinite(got):
        raise Unreadable(f"its {name} is not finite")
    return float(got)


def _token(prim: Any, name: str, default: str) -> str:
    attribute = prim.GetAttribute(name)
    got = attribute.Get() if attribute else None
    return default if got is None else str(got)


def parsed_physics(stage: Any) -> dict[Any, Any]:
    """UsdPhysics's own parse of the stage (PhysX's), or {}.

    Empty where this OpenUSD has no parser or it fails.
    """
    import warnings

    from pxr import UsdPhysics

    parse = getattr(UsdPhysics, "UsdPhysicsLoadStageFromPrimRange", None) or getattr(
        UsdPhysics, "LoadUsdPhysicsFromRange", None
    )
    if parse is None:
        return {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            return dict(parse(stage, ["/"]))
    except Exception:
        return {}


def filter_facts(stage: Any, parsed: dict[Any, Any]) -> dict[str, Any]:
    """What UsdPhysics's parser says filters collisions, as paths (for `usd._filters`).

    Joints (enabled ones: their bodies, ``collisionEnabled``, ``excludeFromArticulation``),
    articulations (their prim, and PhysX's ``physxArticulation:enabledSelfCollisions`` on
    it), ``physics:filteredPairs`` of bodies, colliders and articulations, and
    collision groups (their filtered groups, ``invertFilteredGroups``, merged groups) with
    each collider's groups. At most `MAX_FILTER_TARGETS` targets and members are kept;
    ``cut`` says when some were not.
    """
    from pxr import UsdPhysics

    kinds = UsdPhysics.ObjectType
    budget = [MAX_FILTER_TARGETS]

    def paths(values: Any) -> list[str]:
        kept = [str(v) for v in list(values)[: max(budget[0], 0)]]
        budget[0] -= len(values)
        return kept

    joints, articulations, pairs, groups, members = [], [], [], [], []
    for kind, (_, descs) in parsed.items():
        for desc in descs:
            shape = isinstance(desc, UsdPhysics.ShapeDesc)
            if isinstance(desc, UsdPhysics.JointDesc) and desc.jointEnabled:
                joints.append([str(desc.primPath), str(desc.body0), str(desc.body1),
                               bool(desc.collisionEnabled),
                               bool(desc.excludeFromArticulation)])  # fmt: skip
            elif kind == kinds.Articulation:
                attribute = stage.GetPrimAtPath(desc.primPath).GetAttribute(
                    "physxArticulation:enabledSelfCollisions"
                )
                selfish = not (attribute and attribute.Get() is False)
                articulations.append([str(desc.primPath), selfish])
            elif kind == kinds.CollisionGroup:
                filtered, merged = paths(desc.filteredGroups), paths(desc.mergedGroups)
                # read here: the parser leaves it unset when unauthored (it has no
                # fallback), and its desc's field is then whatever memory held
                invert = stage.GetPrimAtPath(desc.primPath).GetAttribute(
                    "physics:invertFilteredGroups"
                )
                inverted = bool(invert) and invert.Get() is True
                groups.append([str(desc.primPath), filtered, inverted, merged])
            filtering = shape or kind in (kinds.Articulation, kinds.RigidBody)
            if filtering and len(desc.filteredCollisions):
                pairs.append([str(desc.primPath), paths(desc.filteredCollisions)])
            if shape and len(desc.collisionGroups):
                members.append([str(desc.primPath), paths(desc.collisionGroups)])
    return {
        "joints": joints,
        "articulations": articulations,
        "pairs": pairs,
        "groups": groups,
        "members": members,
        "cut": budget[0] < 0,
    }


def mesh_arrays(stage: Any, prims: list[list[Any]], spent: list[int]) -> bytes:
    """The arrays of USD meshes: a JSON header's length (8 bytes), the header, the arrays.

    Args:
        stage: The composed stage.
        prims: ``[path, hull]`` for each mesh: a hull needs its points alone.
        spent: Vertices and face-vertex indices already read for the robot.

    For each mesh the header says its counts (``points``, ``counts``, ``indices``), or its
    ``problem``, or ``later`` when the answer's `MESH_ANSWER_BYTES` are spent (the parent
    asks again). The arrays follow mesh after mesh: points (float32, x y z), then
    ``faceVertexCounts`` and ``faceVertexIndices`` (int32), in native byte order.
    """
    header: list[dict[str, Any]] = []
    chunks: list[bytes] = []
    size, full = 0, False
    vertices, indices = spent
    for path, hull in prims:
        if full:
            header.append({"later": True})
            continue
        try:
            arrays = _mesh(stage, str(path), bool(hull))
        except Unreadable as exc:
            header.append({"problem": str(exc)})
            continue
        nbytes = sum(a.nbytes for a in arrays)
        if size and size + nbytes > MESH_ANSWER_BYTES:
            header.append({"later": True})
            full = True
            continue
        points = len(arrays[0])
        corners = len(arrays[2]) if len(arrays) == 3 else 0
        if vertices + points > MAX_TOTAL_VERTICES:
            header.append({"problem": _over("vertices", MAX_TOTAL_VERTICES)})
            continue
        if indices + corners > 3 * MAX_TOTAL_TRIANGLES:
            header.append({"problem": _over("face-vertex indices", 3 * MAX_TOTAL_TRIANGLES)})
            continue
        vertices, indices, size = vertices + points, indices + corners, size + nbytes
        counts = [len(a) for a in arrays]
        header.append(dict(zip(("points", "counts", "indices"), counts, strict=False)))
        chunks += [a.tobytes() for a in arrays]
    told = json.dumps(header).encode("utf-8")
    return b"".join([len(told).to_bytes(8, "little"), told, *chunks])


def _over(what: str, most: int) -> str:
    return f"with it, the robot's meshes have more than the {most:,} {what} cspace reads"


def _mesh(stage: Any, path: str, hull: bool) -> list[memoryview]:
    """A mesh's points (and, unless ``hull``, its face counts and indices), checked."""
    from pxr import UsdGeom

    prim = stage.GetPrimAtPath(path)
    if not prim or not prim.IsA(UsdGeom.Mesh):
        raise Unreadable("it is no longer a UsdGeom.Mesh of the stage")
    points = _array(prim, "points", "f", 3)
    if len(points) > MAX_MESH_VERTICES:
        raise Unreadable(
            f"it has {len(points):,} points, more than the {MAX_MESH_VERTICES:,} a mesh may have"
        )
    if hull:
        return [points]
    counts = _array(prim, "faceVertexCounts", "i", 1)
    indices = _array(prim, "faceVertexIndices", "i", 1)
    if len(counts) > MAX_MESH_TRIANGLES or len(indices) > 3 * MAX_MESH_TRIANGLES:
        raise Unreadable(
            f"it has {len(counts):,} faces and {len(indices):,} face-vertex indices, more than "
            f"the {MAX_MESH_TRIANGLES:,} triangles a mesh may have make"
        )
    return [points, counts, indices]


def _array(prim: Any, name: str, kind: str, width: int) -> memoryview:
    attribute = prim.GetAttribute(name)
    got = attribute.Get() if attribute else None
    expected = {"f": "point3f[]", "i": "int[]"}[kind]
    if got is None:
        raise Unreadable(f"it has no {name}")
    try:
        view = memoryview(got)
    except TypeError:
        raise Unreadable(f"its {name} is not {expected}") from None
    shape = tuple(view.shape or ())
    flat = width == 1 and len(shape) == 1
    if view.format != kind or not (flat or shape[1:] == (width,)):
        raise Unreadable(f"its {name} is not {expected}")
    return view
