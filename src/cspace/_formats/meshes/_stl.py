"""STL, binary and ASCII: a triangle soup (three vertices a triangle, none shared).

A file is binary when its size is 84 + 50 n bytes, n the count its header gives at
byte 80: binary files may begin with the word ``solid`` too (Blender's do). Any other
file is read as ASCII STL (``solid``, ``facet``, ``vertex x y z``, ...).
"""

from __future__ import annotations

import re
import struct
from typing import TYPE_CHECKING

from cspace._formats.meshes._bounds import (
    MeshProblem,
    check_counts,
    finish,
    line_at,
    shown,
)

if TYPE_CHECKING:
    from cspace._formats.meshes._bounds import Mesh

_VERTEX = re.compile(rb"\bvertex[ \t]+(\S+)[ \t]+(\S+)[ \t]+(\S+)")
_NUMBER = re.compile(rb"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|[+-]?(?:nan|inf)", re.I)


def read_stl(data: bytes, scale: tuple[float, float, float]) -> Mesh:
    """The mesh of an STL file.

    Raises:
        MeshProblem: Neither binary nor ASCII STL, a bad number, too many triangles.
    """
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * count == len(data):
            return _binary(data, count, scale)
    return _ascii(data, scale)


def _binary(data: bytes, count: int, scale: tuple[float, float, float]) -> Mesh:
    import numpy as np

    check_counts(3 * count, count)
    record = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attr", "<u2")])
    facets = np.frombuffer(data, dtype=record, count=count, offset=84)
    vertices = facets["corners"].reshape(-1, 3)
    return finish(vertices, np.arange(3 * count).reshape(-1, 3), scale)


def _ascii(data: bytes, scale: tuple[float, float, float]) -> Mesh:
    import numpy as np

    start = data.lstrip()[:5].lower()
    if start != b"solid":
        size = len(data)
        told = struct.unpack_from("<I", data, 80)[0] if size >= 84 else None
        said = f", its header says {told:,} triangles" if told is not None else ""
        raise MeshProblem(
            f"neither binary STL (84 + 50 n bytes for n triangles: the file has {size:,}"
            f"{said}) nor ASCII STL (beginning with 'solid')"
        )
    corners = data.count(b"vertex")
    check_counts(corners, corners // 3)
    numbers: list[bytes] = []
    for match in _VERTEX.finditer(data):
        for group in (1, 2, 3):
            if _NUMBER.fullmatch(match.group(group)) is None:
                raise MeshProblem(
                    f"'vertex' is not followed by three numbers ({shown(match.group(group))})",
                    line_at(data, match.start()),
                )
        numbers.extend(match.groups())
    if len(numbers) % 9 or len(numbers) // 3 != corners:
        raise MeshProblem(
            f"ASCII STL of {corners:,} 'vertex' lines, not three numbers each in facets "
            "of three: truncated or malformed"
        )
    vertices = np.array([float(n) for n in numbers], dtype=np.float64).reshape(-1, 3)
    return finish(vertices, np.arange(len(vertices)).reshape(-1, 3), scale)
