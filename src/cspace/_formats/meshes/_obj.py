"""Wavefront OBJ: its ``v`` and ``f`` lines, every object and group kept as one mesh.

A face's corners may be written ``i``, ``i/t``, ``i//n`` or ``i/t/n``; only ``i`` is
read: 1-based, or negative to count back from the last vertex read so far. A polygon
of more than three corners is fanned into triangles from its first corner (as assimp and
trimesh do for convex polygons). Every other line (normals, texture coordinates,
materials, ``o``, ``g``, ``s``, comments) is skipped.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from cspace._formats.meshes._bounds import (
    MAX_MESH_TRIANGLES,
    MAX_MESH_VERTICES,
    MAX_OBJ_LINES,
    MeshProblem,
    finish,
    shown,
)

if TYPE_CHECKING:
    from cspace._formats.meshes._bounds import Mesh


def read_obj(data: bytes, scale: tuple[float, float, float]) -> Mesh:
    """The mesh of an OBJ file.

    Raises:
        MeshProblem: Too many lines, vertices or triangles, a bad number, a face with
            fewer than three corners or a corner naming no vertex (with its line).
    """
    import numpy as np

    lines = data.count(b"\n") + 1
    if lines > MAX_OBJ_LINES:
        raise MeshProblem(f"{lines:,} lines, more than the {MAX_OBJ_LINES:,} an OBJ file may have")
    coordinates: list[bytes] = []
    corners: list[int] = []
    for number, line in enumerate(data.splitlines(), start=1):
        words = line.split()
        if not words:
            continue
        key = words[0]
        if key == b"v":
            if len(words) < 4:
                raise MeshProblem("a vertex ('v') of fewer than three coordinates", number)
            if len(coordinates) >= 3 * MAX_MESH_VERTICES:
                raise MeshProblem(
                    f"more than the {MAX_MESH_VERTICES:,} vertices a mesh may have", number
                )
            coordinates.extend(words[1:4])
        elif key == b"f":
            if len(words) < 4:
                raise MeshProblem("a face ('f') of fewer than three corners", number)
            face = [_corner(word, len(coordinates) // 3, number) for word in words[1:]]
            if len(corners) + 3 * (len(face) - 2) > 3 * MAX_MESH_TRIANGLES:
                raise MeshProblem(
                    f"more than the {MAX_MESH_TRIANGLES:,} triangles a mesh may have", number
                )
            for k in range(1, len(face) - 1):
                corners.extend((face[0], face[k], face[k + 1]))
    try:
        if b"_" in b" ".join(coordinates):  # Python reads 1_0 as 10; C parsers do not
            raise ValueError
        vertices = np.array([float(c) for c in coordinates], dtype=np.float64)
    except ValueError:
        bad = next(c for c in coordinates if not _is_number(c))
        where = _line_of_word(data, b"v", bad)
        raise MeshProblem(
            f"a vertex coordinate is not a number ({shown(bad)})",
            where,
        ) from None
    return finish(vertices, np.array(corners, dtype=np.int64), scale)


def _corner(word: bytes, vertices: int, line: int) -> int:
    """The 0-based vertex a face corner names (``i``, ``i/t``, ``i//n``, ``i/t/n``)."""
    text = word.split(b"/", 1)[0]
    try:
        if b"_" in text:
            raise ValueError
        index = int(text)
    except ValueError:
        raise MeshProblem(
            f"a face corner is not a vertex index ({shown(word)})",
            line,
        ) from None
    resolved = index - 1 if index > 0 else vertices + index
    if index == 0 or not 0 <= resolved < vertices:
        raise MeshProblem(
            f"a face names vertex {index}, and {vertices:,} vertices are defined before it", line
        )
    return resolved


def _is_number(word: bytes) -> bool:
    if b"_" in word:
        return False
    try:
        float(word)
    except ValueError:
        return False
    return True


def _line_of_word(data: bytes, key: bytes, word: bytes) -> int | None:
    """The line of the first ``key`` line holding ``word`` (for an error only)."""
    for number, line in enumerate(data.splitlines(), start=1):
        words = line.split()
        if words and words[0] == key and word in words[1:4]:
            return number
    return None
