"""A stage's collision shapes as `CollisionSpec`s, and its inline meshes' arrays.

The child (`usd._colliders`) reads each collider as UsdPhysics reads it; here its facts
become a link's `CollisionSpec`s (`link_shapes`, for `usd.reader.describe`), in metres
(``metersPerUnit``), with no line (USD has none): an unreadable one is kept in
`LinkSpec.unread` as ``(None, "link 'NAME': collision prim '/PATH': PROBLEM")``. More
collision prims than `collisions.MAX_COLLISIONS` (counted over the composed stage,
every instance, reference and payload) refuse the stage, as for URDF and SDF.

A USD mesh is data in the stage, not a file: its shape's `CollisionSpec.mesh` is
``usd:/PRIM/PATH`` (its triangles) or ``usd-hull:/PRIM/PATH`` (its points' convex
hull), with its scale (the prim's world scale, in metres). `read_inline_meshes` (called
by `cspace._model._collision_meshes.read_shape_meshes` for such names when the robot file
is a USD stage) asks the same confined child for their arrays: points,
``faceVertexCounts`` and ``faceVertexIndices``, each face fanned into triangles from its
first vertex (a face of fewer than 3 vertices makes none), held to the mesh readers'
bounds (`meshes._bounds`: points and triangles a mesh, and for all the robot's meshes),
scaled, finite, every index a point of the mesh; a hull's mesh is its points alone (no
triangles), which `cspace._model._collision_hull` makes their hull.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from cspace._formats.meshes._bounds import Mesh, MeshProblem, check_counts, finish
from cspace._formats.shared.collisions import MAX_COLLISIONS, MAX_MESH_NAME
from cspace._formats.shared.description import CollisionSpec
from cspace._formats.shared.pose import Pose, unit
from cspace._formats.usd._colliders import HULL, TRIANGLES
from cspace.errors import InvalidElementError

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

Shapes = tuple[tuple[CollisionSpec, ...], tuple[tuple[int | None, str], ...]]
"""A link's shapes read and its collision prims not read."""

SHOWN_PATH = 200
"""Most characters of a prim path quoted in a problem."""


def is_inline(name: str) -> bool:
    """Whether a mesh shape's name is a USD mesh of the stage (``usd:`` or ``usd-hull:``)."""
    return name.startswith((TRIANGLES, HULL))


def link_shapes(
    path: str, facts: dict[str, Any], names: dict[str, str], meters: float
) -> dict[str, Shapes]:
    """Each link's collision shapes and problems, by link name (the stage's order).

    Args:
        path: The stage, for the error.
        facts: The child's facts (``colliders``, ``collision_prims``).
        names: Each body's link name, by prim path.
        meters: ``metersPerUnit``.

    Raises:
        InvalidElementError: ``too-many-elements``, past `MAX_COLLISIONS` collision prims.
    """
    if int(facts.get("collision_prims", 0)) > MAX_COLLISIONS:
        raise InvalidElementError(
            path,
            f"the stage has more than {MAX_COLLISIONS:,} prims with PhysicsCollisionAPI: "
            "more than cspace reads",
            code="too-many-elements",
            element="PhysicsCollisionAPI",
        )
    shapes: dict[str, list[CollisionSpec]] = {}
    unread: dict[str, list[tuple[int | None, str]]] = {}
    for fact in facts.get("colliders", ()):
        link = names.get(str(fact.get("body")))
        if link is None:
            continue
        try:
            shapes.setdefault(link, []).append(_spec(fact, meters))
        except ValueError as problem:
            prim = _shown(str(fact.get("path")))
            said = f"link '{link}': collision prim '{prim}': {problem}"
            unread.setdefault(link, []).append((None, said))
    return {
        link: (tuple(shapes.get(link, ())), tuple(unread.get(link, ())))
        for link in dict.fromkeys([*shapes, *unread])
    }


def usable(fact: dict[str, Any], meters: float) -> bool:
    """Whether a collider's facts make a shape (`link_shapes` keeps it)."""
    try:
        _spec(fact, meters)
    except ValueError:
        return False
    return True


def _shown(text: str) -> str:
    return text if len(text) <= SHOWN_PATH else text[:SHOWN_PATH] + "..."


def _floats(values: Any, count: int) -> list[float]:
    if not isinstance(values, list) or len(values) != count:
        raise ValueError("it has no shape cspace could read")
    out = [float(v) for v in values]
    if not all(math.isfinite(v) for v in out):
        raise ValueError("its size, scale or pose is not finite")
    return out


def _spec(fact: dict[str, Any], meters: float) -> CollisionSpec:
    """One collider's `CollisionSpec`, in metres, or ValueError with its problem."""
    if "problem" in fact:
        raise ValueError(str(fact["problem"]))
    kind = str(fact.get("kind"))
    x, y, z = (c * meters for c in _floats(fact.get("pos"), 3))
    w, i, j, k = unit(tuple(_floats(fact.get("rot"), 4)))  # type: ignore[arg-type]
    origin = Pose((x, y, z), (w, i, j, k))
    if kind == "mesh":
        name = str(fact.get("mesh"))
        if len(name) > MAX_MESH_NAME:
            raise ValueError(f"its prim path is longer than {MAX_MESH_NAME:,} characters")
        sx, sy, sz = (s * meters for s in _floats(fact.get("scale"), 3))
        return CollisionSpec("mesh", (), origin, name, (sx, sy, sz))
    count = {"box": 3, "sphere": 1, "cylinder": 2, "capsule": 2}.get(kind)
    if count is None:
        raise ValueError("it has no shape cspace could read")
    sizes = tuple(s * meters for s in _floats(fact.get("sizes"), count))
    if not all(math.isfinite(s) for s in sizes):
        raise ValueError("it is too large to be read in metres")
    return CollisionSpec(kind, sizes, origin)


def read_inline_meshes(
    stage: str, keys: Sequence[tuple[str, tuple[float, float, float]]], allowed: Sequence[str]
) -> dict[tuple[str, tuple[float, float, float]], Mesh | str]:
    """The meshes the USD stage at ``stage`` holds, each scaled, or its one-line problem.

    A ``usd-hull:`` mesh is its points, with no triangles (`_collision_hull.with_hulls`).

    Args:
        stage: The stage on disk.
        keys: Each mesh's `CollisionSpec.mesh` (``usd:`` or ``usd-hull:`` and the prim's
            path) and scale (metres per stage unit included).
        allowed: The folders the stage may compose files from (its own, ``--allow-dir``).
    """
    import numpy as np

    wanted = list(dict.fromkeys((name.startswith(HULL), _prim(name)) for name, _ in keys))
    arrays = _arrays(stage, wanted, allowed)
    results: dict[tuple[str, tuple[float, float, float]], Mesh | str] = {}
    for key in dict.fromkeys(keys):
        name, scale = key
        got = arrays[(name.startswith(HULL), _prim(name))]
        if isinstance(got, str):
            results[key] = got
            continue
        points, counts, indices = got
        hull = name.startswith(HULL)
        try:
            triangles = np.empty((0, 3), np.int64) if hull else _fan(counts, indices, len(points))
            results[key] = finish(points, triangles, scale)
        except MeshProblem as exc:
            results[key] = exc.problem
    return results


def _prim(name: str) -> str:
    return name.removeprefix(HULL) if name.startswith(HULL) else name.removeprefix(TRIANGLES)


_Arrays = tuple[Any, Any, Any]


def _arrays(
    stage: str, wanted: list[tuple[bool, str]], allowed: Sequence[str]
) -> dict[tuple[bool, str], _Arrays | str]:
    """Each mesh's points, face counts and indices (NumPy, read-only), or its problem.

    Asked of the OpenUSD child in as many answers as the arrays need (each at most
    `usd._colliders.MESH_ANSWER_BYTES`).
    """
    from cspace._confine.sandbox import ChildRefused
    from cspace._formats.usd.child import ask

    found: dict[tuple[bool, str], _Arrays | str] = {}
    folders = [os.path.abspath(a) for a in allowed]
    todo, spent = list(wanted), [0, 0]
    while todo:
        prims = [[path, hull] for hull, path in todo]
        request = {"meshes": os.path.abspath(stage), "prims": prims, "spent": spent}
        try:
            answer = ask(request, folders)
        except ChildRefused as exc:
            for item in todo:
                found[item] = f"OpenUSD could not read it: {exc}"
            break
        later = []
        for item, got in zip(todo, _unpack(answer), strict=True):
            if got is None:
                later.append(item)
                continue
            found[item] = got
            if not isinstance(got, str):
                spent = [spent[0] + len(got[0]), spent[1] + len(got[2])]
        if len(later) == len(todo):  # no progress: cannot happen, but never loop
            for item in later:
                found[item] = "its arrays do not fit in an answer of the OpenUSD child"
            break
        todo = later
    return found


def _unpack(answer: bytes) -> list[_Arrays | str | None]:
    import numpy as np

    size = int.from_bytes(answer[:8], "little")
    header = json.loads(answer[8 : 8 + size])
    at = 8 + size
    out: list[_Arrays | str | None] = []
    for told in header:
        if "later" in told:
            out.append(None)
            continue
        if "problem" in told:
            out.append(str(told["problem"]))
            continue
        points = np.frombuffer(answer, np.float32, 3 * int(told["points"]), at)
        at += points.nbytes
        counts = np.frombuffer(answer, np.int32, int(told.get("counts", 0)), at)
        at += counts.nbytes
        indices = np.frombuffer(answer, np.int32, int(told.get("indices", 0)), at)
        at += indices.nbytes
        out.append((points.reshape(-1, 3), counts, indices))
    return out


def _fan(
    counts: npt.NDArray[np.int32], indices: npt.NDArray[np.int32], points: int
) -> npt.NDArray[np.int64]:
    """Each face fanned into triangles from its first vertex, ``(m, 3)`` indices.

    Raises:
        MeshProblem: A negative count, counts that do not add up to the indices, more
            triangles than a mesh may have.
    """
    import numpy as np

    if len(counts) and int(counts.min()) < 0:
        first = int(np.argmax(counts < 0))
        raise MeshProblem(f"its faceVertexCounts[{first}] is negative")
    wide = counts.astype(np.int64)
    total = int(wide.sum())
    if total != len(indices):
        raise MeshProblem(
            f"its faceVertexCounts add up to {total:,}, not the {len(indices):,} "
            "faceVertexIndices it has"
        )
    per = np.maximum(wide - 2, 0)
    triangles = int(per.sum())
    check_counts(points, triangles)
    starts = np.cumsum(wide) - wide
    face = np.repeat(np.arange(len(wide)), per)
    step = np.arange(triangles) - np.repeat(np.cumsum(per) - per, per) + 1
    base = starts[face]
    corners = indices.astype(np.int64)
    return np.stack([corners[base], corners[base + step], corners[base + step + 1]], axis=1)
