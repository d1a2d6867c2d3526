"""MuJoCo's legacy MSH: four int32 counts, float32 vertices, normals, texture coordinates.

Then int32 faces. MuJoCo reads it only when its size is exactly ``16 + 4 (3 nvertex + 3 nnormal +
2 ntexcoord + 3 nface)`` bytes, with normals and texture coordinates either absent or
one a vertex; a file of no faces is a point cloud (MuJoCo takes its convex hull), read
here as vertices and no triangles.
"""

from __future__ import annotations

import struct
from typing import TYPE_CHECKING

from cspace._formats.meshes._bounds import MeshProblem, check_counts, finish

if TYPE_CHECKING:
    from cspace._formats.meshes._bounds import Mesh


def read_msh(data: bytes, scale: tuple[float, float, float]) -> Mesh:
    """The mesh of an MSH file.

    Raises:
        MeshProblem: Shorter than its header, counts that are negative, that do not match
            the file's size, or too large.
    """
    import numpy as np

    if len(data) < 16:
        raise MeshProblem(f"{len(data)} bytes, shorter than the 16-byte header of an MSH file")
    nvertex, nnormal, ntexcoord, nface = struct.unpack_from("<4i", data)
    if min(nvertex, nnormal, ntexcoord, nface) < 0 or nvertex < 4:
        raise MeshProblem(
            f"header counts {nvertex}, {nnormal}, {ntexcoord}, {nface}: MuJoCo needs at "
            "least 4 vertices and no negative count"
        )
    if nnormal not in (0, nvertex) or ntexcoord not in (0, nvertex):
        raise MeshProblem(
            f"{nnormal:,} normals and {ntexcoord:,} texture coordinates for {nvertex:,} "
            "vertices: MuJoCo needs none or one a vertex"
        )
    check_counts(nvertex, nface)
    expected = 16 + 4 * (3 * nvertex + 3 * nnormal + 2 * ntexcoord + 3 * nface)
    if expected != len(data):
        raise MeshProblem(
            f"{len(data):,} bytes, while its header's counts ({nvertex:,} vertices, "
            f"{nnormal:,} normals, {ntexcoord:,} texture coordinates, {nface:,} faces) "
            f"make {expected:,}: truncated or not an MSH file"
        )
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nvertex, offset=16)
    faces_at = 16 + 4 * (3 * nvertex + 3 * nnormal + 2 * ntexcoord)
    faces = np.frombuffer(data, dtype="<i4", count=3 * nface, offset=faces_at)
    return finish(vertices, faces, scale)
