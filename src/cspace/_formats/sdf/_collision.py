"""An SDF link's ``<collision>`` elements, as libsdformat reads them for Drake.

Each ``<collision>`` has a ``<pose>`` (in its link's frame unless ``relative_to`` names
another frame of the model: then resolved through the document's pose graph, as the
reader resolves joints, and expressed in the link's frame) and a ``<geometry>`` holding
a ``<box><size>``, ``<sphere><radius>``, ``<cylinder>`` or ``<capsule>`` (``<radius>``,
``<length>``) or ``<mesh>`` (``<uri>``, ``<scale>``, 1 1 1 by default). Another shape
(a plane, a height map, an ellipsoid...), a ``<mesh>`` with a ``<submesh>``, a size
missing, not a finite number or negative, or a pose that does not resolve, is kept in
`LinkSpec.unread` with its line and the problem, and the link's other shapes are kept
(Drake refuses such a file; there is no parser that goes on to follow). Nothing raises
here but the count of collision elements (`collisions.MAX_COLLISIONS`, as for URDF);
no mesh is opened.
"""

from __future__ import annotations

import math

from lxml import etree

from cspace._formats.sdf._poses import PoseGraph, read_pose
from cspace._formats.sdf._scene import SdfLink
from cspace._formats.shared.collisions import (
    MAX_MESH_NAME,
    CollisionCounter,
    Unread,
    read_shapes,
    shown,
)
from cspace._formats.shared.description import CollisionSpec, LinkSpec
from cspace._formats.shared.pose import IDENTITY, Pose, compose, inverse
from cspace._formats.shared.xmlio import line_of
from cspace._formats.urdf.numbers import parse_number

_SIZES = {
    "sphere": ("radius",),
    "cylinder": ("radius", "length"),
    "capsule": ("radius", "length"),
}


def read_link(link: SdfLink, graph: PoseGraph, counter: CollisionCounter) -> LinkSpec:
    """A link with its collision shapes, poses in its frame."""
    shapes, unread = read_shapes(
        link.element.iterchildren("collision"),
        link.name,
        counter,
        lambda collision: _collision(collision, link, graph),
    )
    return LinkSpec(link.name, line_of(link.element), shapes, unread)


def _collision(collision: etree._Element, link: SdfLink, graph: PoseGraph) -> CollisionSpec:
    origin = _origin(collision, link, graph)
    geometry = collision.find("geometry")
    shape = None if geometry is None else next(geometry.iterchildren(tag=etree.Element), None)
    if shape is None:
        raise Unread("<collision> has no <geometry> shape")
    kind, line = str(shape.tag), line_of(collision)
    if kind == "mesh":
        uri = shape.find("uri")
        name = "" if uri is None else (uri.text or "").strip()
        if not name:
            raise Unread("<mesh> has no <uri>")
        if len(name) > MAX_MESH_NAME:
            raise Unread(f"<mesh><uri> is longer than {MAX_MESH_NAME:,} characters")
        if shape.find("submesh") is not None:
            raise Unread("<mesh> has a <submesh>, which cspace does not read")
        scale = (1.0, 1.0, 1.0) if shape.find("scale") is None else _numbers(shape, "scale")
        return CollisionSpec("mesh", (), origin, name, scale, line)
    if kind == "box":
        sizes: tuple[float, ...] = _numbers(shape, "size", negative=False)
    elif kind in _SIZES:
        sizes = tuple(_number(shape, tag) for tag in _SIZES[kind])
    else:
        raise Unread(
            f"<geometry> holds <{shown(kind)}>, not a shape cspace checks (box, sphere, "
            "cylinder, capsule, mesh)"
        )
    return CollisionSpec(kind, sizes, origin, None, (1.0, 1.0, 1.0), line)


def _origin(collision: etree._Element, link: SdfLink, graph: PoseGraph) -> Pose:
    read = read_pose(collision.find("pose"), graph.version)
    if read is None:
        raise Unread("its <pose> is not one libsdformat reads")
    relative_to, pose = read
    if not relative_to or relative_to == _local(link.name):
        return pose
    frame = graph.vertex(relative_to, link.scope)
    base = None if frame is None else graph.world(frame)
    at = graph.world(link.name)
    if base is None or at is None:
        raise Unread(f"its <pose relative_to='{shown(relative_to)}'> does not resolve")
    return compose(inverse(at), compose(base, pose)) if at != IDENTITY else compose(base, pose)


def _local(scoped: str) -> str:
    return scoped.rpartition("::")[2]


def _number(shape: etree._Element, tag: str) -> float:
    element = shape.find(tag)
    if element is None:
        raise Unread(f"<{shape.tag}> has no <{tag}>")
    text = element.text or ""
    value = parse_number(text)
    if value is None or not math.isfinite(value):
        raise Unread(f"<{shape.tag}><{tag}>{shown(text.strip())}</{tag}> is not a finite number")
    if value < 0:
        raise Unread(f"<{shape.tag}><{tag}> is negative")
    return value


def _numbers(
    shape: etree._Element, tag: str, *, negative: bool = True
) -> tuple[float, float, float]:
    element = shape.find(tag)
    if element is None:
        raise Unread(f"<{shape.tag}> has no <{tag}>")
    text = element.text or ""
    values = [parse_number(word) for word in text.split()]
    if len(values) != 3 or any(v is None or not math.isfinite(v) for v in values):
        raise Unread(
            f"<{shape.tag}><{tag}>{shown(text.strip())}</{tag}> is not three finite numbers"
        )
    x, y, z = (float(v) for v in values if v is not None)
    if not negative and min(x, y, z) < 0:
        raise Unread(f"<{shape.tag}><{tag}> is negative")
    return (x, y, z)
