"""MuJoCo's convex hulls of an MJCF robot's collision meshes, from cspace's own mesh arrays.

MuJoCo collides a mesh geom as the convex hull of its vertices, which it makes with qhull
(``Qt``; with ``maxhullvert``, ``Q9 TA<maxhullvert - 4>``) after the asset's
``refpos``, ``refquat`` and ``scale`` are applied. Here the vertices come from cspace's
mesh readers (`cspace._formats.meshes.load.load_meshes`, a confined child) or from the
numbers a ``<mesh vertex>`` writes (sent by MuJoCo's compiling child); they are moved as
MuJoCo moves them (`placed`) and MuJoCo itself makes the hull (`convex_hulls`): a model
built in code of these numbers only (no file, no XML), each mesh a geom of one body,
compiled in this process. MuJoCo's qhull is guarded (a degenerate mesh is MuJoCo's
one-line refusal, where coal's qhull binding would crash the process), its hull is
MuJoCo's to the vertex, ``maxhullvert`` included, and its vertices are single
precision as MuJoCo keeps them. The hull comes back in the frame of the input vertices.

Bounds: `MAX_HULL_INPUT` vertices of one mesh, `MAX_TOTAL_HULL_INPUT` of all, and
`MAX_HULL_VERTICES` vertices of one hull.
"""

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from cspace._formats.meshes._bounds import MAX_MESH_VERTICES, MAX_TOTAL_VERTICES
from cspace._record import NamedTuple

MAX_HULL_INPUT = MAX_MESH_VERTICES
"""Most vertices of one mesh whose hull is made (1,000,000: qhull about 0.5 s)."""

MAX_TOTAL_HULL_INPUT = MAX_TOTAL_VERTICES
"""Most vertices of all the meshes of one robot whose hulls are made (4,000,000)."""

MAX_HULL_VERTICES = 10_000
"""Most vertices of one hull (coal's support function climbs the hull's edges; real
collision meshes' hulls have tens to a few thousand)."""

FloatArray = npt.NDArray[np.float64]


class Hull(NamedTuple):
    """A convex hull: its vertices and its triangles.

    Attributes:
        vertices: float64 ``(n, 3)``, read-only, in the frame of the vertices given.
        triangles: int64 ``(m, 3)``, read-only, indices into ``vertices``.
    """

    vertices: "FloatArray"
    triangles: "npt.NDArray[np.int64]"


def rotation(quat: Sequence[float]) -> "FloatArray":
    """The rotation matrix of a quaternion (w, x, y, z), normalised first."""
    w, x, y, z = np.asarray(quat, dtype=float) / float(np.linalg.norm(quat))
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def placed(
    vertices: "FloatArray",
    scale: Sequence[float],
    refpos: Sequence[float],
    refquat: Sequence[float],
) -> "FloatArray":
    """A mesh file's vertices as MuJoCo places them in its geom's frame (as the file gives it).

    ``scale * R(refquat)^T (v - refpos)``, componentwise scale (MuJoCo's order, measured);
    the frame MuJoCo then moves the mesh to (its centre of mass) is undone in its geom's.
    """
    moved = (np.asarray(vertices, dtype=float) - np.asarray(refpos, dtype=float)) @ rotation(
        refquat
    )
    return np.asarray(moved * np.asarray(scale, dtype=float), dtype=float)


def _refusal(exc: Exception, names: Sequence[str]) -> str:
    """MuJoCo's message, one line, naming the mesh as the file does."""
    first = (str(exc).strip().splitlines() or ["MuJoCo refused the mesh"])[0]
    first = first.removeprefix("Error: ").strip()
    for made in names:
        first = first.replace(f"mesh '{made}'", "the mesh")
    return f"MuJoCo makes no convex hull of it: {first}"


def _compile(clouds: Mapping[str, tuple["FloatArray", int]]) -> Any:
    """MuJoCo's model of one body holding one mesh geom a cloud (raises ValueError)."""
    import mujoco

    spec = mujoco.MjSpec()
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.usethread = False
    body = spec.worldbody.add_body(mass=1.0, inertia=[1.0, 1.0, 1.0], explicitinertial=True)
    for name, (vertices, maxhullvert) in clouds.items():
        spec.add_mesh(name=name, uservert=vertices.ravel().tolist(), maxhullvert=maxhullvert)
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=name)
    return spec.compile()


def _hull_of(model: Any, k: int) -> Hull | str:
    """Mesh ``k``'s hull in the frame its vertices were given in."""
    start, count = int(model.mesh_vertadr[k]), int(model.mesh_vertnum[k])
    vertices = np.asarray(model.mesh_vert[start : start + count], dtype=float)
    at = int(model.mesh_graphadr[k])
    if at < 0:
        return "MuJoCo makes no convex hull of it"
    numvert, numface = int(model.mesh_graph[at]), int(model.mesh_graph[at + 1])
    if numvert > MAX_HULL_VERTICES:
        return f"its convex hull has {numvert:,} vertices, more than the {MAX_HULL_VERTICES:,} read"
    graph = np.asarray(model.mesh_graph[at : at + 2 + 3 * numvert + 6 * numface], dtype=np.int64)
    ids = graph[2 + numvert : 2 + 2 * numvert]
    faces = graph[2 + 3 * numvert + 3 * numface : 2 + 3 * numvert + 6 * numface].reshape(-1, 3)
    local = np.full(count, -1, dtype=np.int64)
    local[ids] = np.arange(numvert)
    triangles = local[faces]
    if (triangles < 0).any() or len(triangles) == 0:
        return "MuJoCo's convex hull of it is malformed"
    # MuJoCo keeps the mesh in its own frame (centre of mass, principal axes): back to ours
    turn = rotation(model.geom_quat[k])
    points = vertices[ids] @ turn.T + np.asarray(model.geom_pos[k], dtype=float)
    points.flags.writeable = False
    triangles.flags.writeable = False
    return Hull(points, triangles)


def convex_hulls(clouds: Sequence[tuple["FloatArray", int]]) -> list[Hull | str]:
    """MuJoCo's convex hull of each cloud of vertices, or why it makes none.

    Args:
        clouds: Each mesh's vertices ``(n, 3)`` (as `placed`) and its ``maxhullvert``.

    Returns:
        Each hull, or a one-line reason: MuJoCo's refusal (fewer than 4 vertices, all
        on a plane or a line, a number not finite, ``maxhullvert`` below 4), too many
        vertices.
    """
    results: list[Hull | str] = ["not made"] * len(clouds)
    wanted: dict[str, tuple[FloatArray, int]] = {}
    total = 0
    for k, (vertices, maxhullvert) in enumerate(clouds):
        total += len(vertices)
        if len(vertices) > MAX_HULL_INPUT:
            results[k] = f"{len(vertices):,} vertices, more than the {MAX_HULL_INPUT:,} read"
        elif total > MAX_TOTAL_HULL_INPUT:
            results[k] = (
                f"past the {MAX_TOTAL_HULL_INPUT:,} vertices of all the robot's meshes read"
            )
        else:
            wanted[f"mesh{k}"] = (vertices, maxhullvert)
    if not wanted:
        return results
    try:  # all at once; one at a time only when one is refused
        together = _compile(wanted)
        for index, name in enumerate(wanted):
            results[int(name[4:])] = _hull_of(together, index)
        return results
    except ValueError:
        pass
    for name, cloud in wanted.items():
        try:
            results[int(name[4:])] = _hull_of(_compile({name: cloud}), 0)
        except ValueError as exc:
            results[int(name[4:])] = _refusal(exc, [name])
    return results


def convex_geometry(hull: Hull) -> Any:
    """The coal ``Convex`` of a hull (its own triangles: no qhull call)."""
    import pinocchio as pin

    coal = pin.coal
    points = coal.StdVec_Vec3s()
    points.extend(list(np.ascontiguousarray(hull.vertices, dtype=float)))
    triangles = coal.StdVec_Triangle()
    triangles.extend([coal.Triangle(int(a), int(b), int(c)) for a, b, c in hull.triangles])
    return coal.Convex(points, triangles)
