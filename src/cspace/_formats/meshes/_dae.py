"""COLLADA (DAE), the subset robot meshes use, on cspace's hardened XML reader.

Read: each ``<geometry>``'s ``<mesh>`` (its ``<source>``'s ``<float_array>`` and
accessor stride, ``<vertices>``' POSITION input, ``<triangles>``, ``<polylist>`` with
``<vcount>``, ``<polygons>``, ``<trifans>`` and ``<tristrips>``, their ``<p>`` read with
the inputs' offsets, polygons and fans fanned, strips stripped), placed by the scene's
``<node>`` tree (``<matrix>``, ``<translate>``, ``<rotate>`` in degrees, ``<scale>``,
applied in order; ``<instance_node>`` places a node of the file again, as assimp does,
each placement counted against the bounds) at each ``<instance_geometry>``, and scaled
by ``<unit meter>``. ``<up_axis>`` is ignored, as assimp and pycollada do. A file
without a visual scene gives its geometries as they are. Lines (no area to collide) and
controllers are not read.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cspace._formats.meshes._bounds import (
    MAX_DAE_DEPTH,
    MAX_DAE_INSTANCES,
    MAX_DAE_NODES,
    MeshProblem,
    check_counts,
    finish,
)
from cspace._formats.shared.xmlio import line_of, parse_xml, source_from_bytes
from cspace.errors import RobotFileError

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    from lxml import etree

    from cspace._formats.meshes._bounds import Mesh

    Geometry = tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]


def read_dae(data: bytes, scale: tuple[float, float, float]) -> Mesh:
    """The mesh of a COLLADA file: every geometry the scene places, as one mesh.

    Raises:
        MeshProblem: Not safe or well-formed XML, a number that is not one, an array
            shorter than it says, an index out of range, too many nodes or too deep.
    """
    import numpy as np

    root = _parse(data)
    ids = {e.get("id"): e for e in root.iter("{*}source", "{*}vertices", "{*}geometry")}
    unit = root.find("{*}asset/{*}unit")
    meters = _floats(unit.get("meter") or "1", unit, 1)[0] if unit is not None else 1.0
    placed = _placements(root)
    geometries: dict[str, Geometry] = {}
    vertices_total = triangles_total = 0
    for url, _ in placed:
        geometry = ids.get(url)
        if geometry is None or _local(geometry) != "geometry":
            continue
        if url not in geometries:
            geometries[url] = _geometry(geometry, ids)
        vertices_total += len(geometries[url][0])
        triangles_total += len(geometries[url][1])
        check_counts(vertices_total, triangles_total)  # before any copy is made
    points: list[npt.NDArray[np.float64]] = []
    faces: list[npt.NDArray[np.int64]] = []
    offset = 0
    for url, matrix in placed:
        if url not in geometries:
            continue
        positions, triangles = geometries[url]
        points.append(positions @ matrix[:3, :3].T + matrix[:3, 3])
        faces.append(triangles + offset)
        offset += len(positions)
    vertices = np.concatenate(points) if points else np.zeros((0, 3))
    corners = np.concatenate(faces) if faces else np.zeros((0, 3), dtype=np.int64)
    return finish(vertices * meters, corners, scale)


def _parse(data: bytes) -> etree._Element:
    try:
        return parse_xml(source_from_bytes("mesh", data))
    except RobotFileError as exc:
        raise MeshProblem(exc.problem, exc.line) from None


def _local(element: etree._Element) -> str:
    tag = element.tag
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def _floats(text: str, element: etree._Element, count: int | None = None) -> Any:
    import numpy as np

    try:
        if "_" in text or not text.isascii():  # Python reads 1_0 as 10, and other digits
            raise ValueError
        values = np.array(text.split(), dtype=np.float64)
    except ValueError:
        raise MeshProblem(
            f"<{_local(element)}> holds a word that is not a number", line_of(element)
        ) from None
    if count is not None and len(values) < count:
        raise MeshProblem(
            f"<{_local(element)}> holds {len(values):,} numbers, fewer than the {count:,} "
            "it should",
            line_of(element),
        )
    return values


def _ints(text: str, element: etree._Element) -> Any:
    import numpy as np

    try:
        if "_" in text or not text.isascii():
            raise ValueError
        return np.array([int(word) for word in text.split()], dtype=np.int64)
    except (ValueError, OverflowError):
        raise MeshProblem(
            f"<{_local(element)}> holds a word that is not an index", line_of(element)
        ) from None


def _count(element: etree._Element, name: str = "count") -> int:
    text = element.get(name, "0")
    if not text.strip().isdigit():
        raise MeshProblem(f"<{_local(element)} {name}> is not a count", line_of(element))
    return int(text)


def _placements(root: etree._Element) -> list[tuple[str, Any]]:
    """Each geometry the scene places, by id, with its 4x4 placement."""
    import numpy as np

    scenes = list(root.iter("{*}visual_scene"))
    chosen = root.find("{*}scene/{*}instance_visual_scene")
    if chosen is not None:
        wanted = (chosen.get("url") or "").lstrip("#")
        scenes = [s for s in scenes if s.get("id") == wanted] or scenes[:1]
    if not scenes:
        return [(g.get("id") or "", np.eye(4)) for g in root.iter("{*}geometry")]
    placed: list[tuple[str, Any]] = []
    nodes = 0
    named = {n.get("id"): n for n in root.iter("{*}node") if n.get("id") is not None}
    stack = [(node, np.eye(4), 1) for node in reversed(scenes[0].findall("{*}node"))]
    while stack:
        node, parent, depth = stack.pop()
        nodes += 1
        if nodes > MAX_DAE_NODES:
            raise MeshProblem(f"more than {MAX_DAE_NODES:,} <node> elements", line_of(node))
        if depth > MAX_DAE_DEPTH:
            raise MeshProblem(f"<node> elements nested deeper than {MAX_DAE_DEPTH}", line_of(node))
        matrix = parent @ _local_matrix(node)
        below = []
        for child in node:
            kind = _local(child)
            if kind == "instance_geometry":
                placed.append(((child.get("url") or "").lstrip("#"), matrix))
                if len(placed) > MAX_DAE_INSTANCES:
                    raise MeshProblem(
                        f"more than {MAX_DAE_INSTANCES:,} <instance_geometry>", line_of(child)
                    )
            elif kind == "node":
                below.append(child)
            elif kind == "instance_node":  # a node placed here too (assimp reads it)
                target = named.get((child.get("url") or "").lstrip("#"))
                if target is not None:
                    below.append(target)
        stack.extend((c, matrix, depth + 1) for c in reversed(below))
    return placed


def _local_matrix(node: etree._Element) -> Any:
    import numpy as np

    matrix = np.eye(4)
    for step in node:
        kind = _local(step)
        if kind not in ("matrix", "translate", "rotate", "scale"):
            continue
        needed = {"matrix": 16, "translate": 3, "rotate": 4, "scale": 3}[kind]
        values = _floats(step.text or "", step, needed)[:needed]
        local = np.eye(4)
        if kind == "matrix":
            local = values.reshape(4, 4)
        elif kind == "translate":
            local[:3, 3] = values
        elif kind == "scale":
            local[:3, :3] = np.diag(values)
        else:
            local[:3, :3] = _rotation(values[:3], np.radians(values[3]))
        matrix = matrix @ local
    return matrix


def _rotation(axis: Any, angle: float) -> Any:
    import numpy as np

    norm = float(np.linalg.norm(axis))
    if norm == 0.0 or not np.isfinite(norm):
        return np.eye(3)
    x, y, z = axis / norm
    c, s, t = np.cos(angle), np.sin(angle), 1 - np.cos(angle)
    return np.array(
        [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
        ]
    )


def _positions(mesh: etree._Element, ids: dict[Any, etree._Element], url: str) -> Any:
    """The positions a ``<vertices>`` (or a ``<source>``) gives, ``(n, 3)``."""
    element = ids.get(url.lstrip("#"))
    if element is not None and _local(element) == "vertices":
        position = next(
            (i for i in element.findall("{*}input") if i.get("semantic") == "POSITION"), None
        )
        element = (
            ids.get((position.get("source") or "").lstrip("#")) if position is not None else None
        )
    if element is None or _local(element) != "source":
        raise MeshProblem(f"a mesh's positions '{url[:80]}' name no <source>", line_of(mesh))
    array = element.find("{*}float_array")
    if array is None:
        raise MeshProblem("a <source> of positions has no <float_array>", line_of(element))
    values = _floats(array.text or "", array, _count(array))
    accessor = element.find("{*}technique_common/{*}accessor")
    stride = _count(accessor, "stride") if accessor is not None and accessor.get("stride") else 3
    count = _count(accessor) if accessor is not None else len(values) // max(stride, 1)
    if stride < 3 or count * stride > len(values):
        raise MeshProblem(
            f"an accessor of {count:,} points of stride {stride} over {len(values):,} numbers",
            line_of(accessor if accessor is not None else element),
        )
    check_counts(count, 0)
    return values[: count * stride].reshape(count, stride)[:, :3]


def _geometry(geometry: etree._Element, ids: dict[Any, etree._Element]) -> Geometry:
    """A geometry's positions and triangles (every primitive of its mesh)."""
    import numpy as np

    mesh = geometry.find("{*}mesh")
    if mesh is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    positions: Any = None
    triangles: list[Any] = []
    for primitive in mesh:
        kind = _local(primitive)
        if kind not in ("triangles", "polylist", "polygons", "trifans", "tristrips"):
            continue
        inputs = primitive.findall("{*}input")
        vertex = next((i for i in inputs if i.get("semantic") == "VERTEX"), None)
        if vertex is None:
            raise MeshProblem(f"a <{kind}> without a VERTEX input", line_of(primitive))
        if positions is None:
            positions = _positions(mesh, ids, vertex.get("source") or "")
        stride = 1 + max(_count(i, "offset") for i in inputs)
        offset = _count(vertex, "offset")
        if kind in ("polygons", "trifans", "tristrips"):  # a <p> a polygon, fan or strip
            polygons = [_ints(p.text or "", p) for p in primitive.findall("{*}p")]
            counts = np.array([len(p) // stride for p in polygons], dtype=np.int64)
            indices = np.concatenate(polygons) if polygons else np.zeros(0, dtype=np.int64)
        else:
            p = primitive.find("{*}p")
            indices = _ints(p.text or "", p) if p is not None else np.zeros(0, dtype=np.int64)
            if kind == "triangles":
                counts = np.full(_count(primitive), 3, dtype=np.int64)
            else:
                vcount = primitive.find("{*}vcount")
                counts = (
                    _ints(vcount.text or "", vcount)
                    if vcount is not None
                    else np.zeros(0, dtype=np.int64)
                )
        if (counts < 3).any() or int(counts.sum()) * stride > len(indices):
            raise MeshProblem(
                f"a <{kind}> whose <p> holds fewer indices than its counts say", line_of(primitive)
            )
        check_counts(0, int((counts - 2).sum()))
        corners = indices[: int(counts.sum()) * stride][offset::stride]
        triangles.append(_strip(corners, counts) if kind == "tristrips" else _fan(corners, counts))
    if positions is None:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    faces = np.concatenate(triangles)
    if faces.size and (faces.min() < 0 or faces.max() >= len(positions)):
        raise MeshProblem(
            f"a primitive names position {int(faces.max())}, beyond the {len(positions):,} "
            "its source has",
            line_of(geometry),
        )
    return np.asarray(positions, dtype=np.float64), faces


def _fan(corners: Any, counts: Any) -> Any:
    """Triangles fanned from each polygon's first corner."""
    import numpy as np

    if not len(counts):
        return np.zeros((0, 3), dtype=np.int64)
    starts = np.concatenate(([0], np.cumsum(counts)[:-1])).astype(np.int64)
    fans = counts - 2
    first = np.repeat(starts, fans)
    step = np.arange(int(fans.sum())) - np.repeat(np.cumsum(fans) - fans, fans)
    second = first + 1 + step
    return np.stack([corners[first], corners[second], corners[second + 1]], axis=1)


def _strip(corners: Any, counts: Any) -> Any:
    """Triangles of triangle strips: corners ``k, k+1, k+2`` of each strip.

    Every other triangle is turned back, as a strip's winding alternates.
    """
    import numpy as np

    if not len(counts):
        return np.zeros((0, 3), dtype=np.int64)
    starts = np.concatenate(([0], np.cumsum(counts)[:-1])).astype(np.int64)
    strips = counts - 2
    step = np.arange(int(strips.sum())) - np.repeat(np.cumsum(strips) - strips, strips)
    first = np.repeat(starts, strips) + step
    odd = step % 2 == 1
    a, b = corners[first], corners[first + 1]
    return np.stack([np.where(odd, b, a), np.where(odd, a, b), corners[first + 2]], axis=1)
