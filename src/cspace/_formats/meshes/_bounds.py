"""The bounds of mesh reading, the record a reader returns and the problem it raises."""

from typing import TYPE_CHECKING, Any

from cspace._record import NamedTuple

if TYPE_CHECKING:  # NumPy is imported where arrays are made
    import numpy as np
    import numpy.typing as npt

MAX_MESH_BYTES = 32 * 1024 * 1024
"""Largest mesh file read (32 MiB); example-robot-data's collision meshes are under 4 MB."""

MAX_ROBOT_MESH_BYTES = 128 * 1024 * 1024
"""Most bytes of all the mesh files of one robot (128 MiB)."""

MAX_MESH_VERTICES = 1_000_000
"""Most vertices of one mesh (dm_control's largest MSH has 177,912)."""

MAX_MESH_TRIANGLES = 2_000_000
"""Most triangles of one mesh, after polygons are fanned."""

MAX_TOTAL_VERTICES = 4_000_000
"""Most vertices of all the meshes of one robot."""

MAX_TOTAL_TRIANGLES = 8_000_000
"""Most triangles of all the meshes of one robot."""

MAX_OBJ_LINES = 4_000_000
"""Most lines of an OBJ file."""

MAX_DAE_NODES = 10_000
"""Most ``<node>`` elements of a COLLADA file."""

MAX_DAE_DEPTH = 64
"""Deepest nesting of COLLADA ``<node>`` elements."""

MAX_DAE_INSTANCES = 10_000
"""Most geometries a COLLADA scene places (each ``<instance_geometry>`` reached)."""

FORMATS = ("stl", "obj", "msh", "dae")
"""The mesh formats read, by their names' endings (in any case)."""


class Mesh(NamedTuple):
    """A triangle mesh.

    Attributes:
        vertices: float64 ``(n, 3)``, scaled.
        triangles: int32 ``(m, 3)``, indices into ``vertices``.
    """

    vertices: "npt.NDArray[np.float64]"
    triangles: "npt.NDArray[np.int32]"


class MeshProblem(Exception):
    """What is wrong with a mesh file, in one line, and the line of the file if known.

    Attributes:
        problem: The one line.
        line: 1-based line of the file, or None.
    """

    def __init__(self, problem: str, line: int | None = None) -> None:
        super().__init__(problem)
        self.problem = problem
        self.line = line


def shown(word: bytes) -> str:
    """A word of a mesh file, for a problem: its first 40 bytes, quoted."""
    return repr(word[:40].decode("ascii", "replace"))


def line_at(data: bytes, offset: int) -> int:
    """The 1-based line of ``data`` that holds byte ``offset``."""
    return data.count(b"\n", 0, offset) + 1


def check_counts(vertices: int, triangles: int) -> None:
    """Refuse a mesh of more vertices or triangles than one mesh may have.

    Raises:
        MeshProblem: Over `MAX_MESH_VERTICES` or `MAX_MESH_TRIANGLES`.
    """
    if vertices > MAX_MESH_VERTICES:
        raise MeshProblem(
            f"{vertices:,} vertices, more than the {MAX_MESH_VERTICES:,} a mesh may have"
        )
    if triangles > MAX_MESH_TRIANGLES:
        raise MeshProblem(
            f"{triangles:,} triangles, more than the {MAX_MESH_TRIANGLES:,} a mesh may have"
        )


def finish(
    vertices: "npt.NDArray[np.floating[Any]]",
    triangles: "npt.NDArray[np.integer[Any]]",
    scale: tuple[float, float, float],
) -> Mesh:
    """The mesh, scaled and checked: sizes, finite vertices, indices in range.

    Raises:
        MeshProblem: Too large, a vertex not finite, an index out of range.
    """
    import numpy as np

    points = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    check_counts(len(points), len(faces))
    with np.errstate(over="ignore", invalid="ignore"):
        points = points * np.asarray(scale, dtype=np.float64)
    bad = ~np.isfinite(points).all(axis=1)
    if bad.any():
        first = int(np.argmax(bad))
        raise MeshProblem(f"vertex {first + 1} is not finite (NaN or infinite, after scaling)")
    if faces.size:
        low, high = int(faces.min()), int(faces.max())
        if low < 0 or high >= len(points):
            wrong = low if low < 0 else high
            raise MeshProblem(
                f"a triangle names vertex {wrong + 1}, beyond the {len(points):,} the mesh has"
            )
    return Mesh(points, faces.astype(np.int32))
