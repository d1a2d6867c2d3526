"""A URDF link's ``<collision>`` elements, read as Pinocchio's URDF parser (urdfdom) reads them.

urdfdom reads every ``<collision>`` of a ``<link>`` (``link.cpp``, ``parseCollision``):
its first ``<origin>`` (``xyz`` and ``rpy``, three numbers each, zero when absent; a
``quat_xyzw`` is ignored, by urdfdom and by Pinocchio), its first ``<geometry>`` and, in
that, the first element, which must be a ``<box size>``, ``<sphere radius>``,
``<cylinder radius length>`` or ``<mesh filename [scale]>`` (URDF has no capsule).
When it cannot read one, the urdfdom inside Pinocchio 4.1 prints an error and the link
has no collision shape at all, its readable ones included (the link and the model are
still built): so here, where each unreadable element is kept in `LinkSpec.unread` with
its line and the problem, and the link's `LinkSpec.collisions` is empty. A negative
size, which urdfdom keeps, is unreadable here too.

Nothing here raises for a malformed shape (the C-space does not depend on it, and a
report must not change): only more collision elements than `collisions.MAX_COLLISIONS`
are refused. No mesh is opened; its file name is kept as written.
"""

from __future__ import annotations

import math

from lxml import etree

from cspace._formats.shared.collisions import (
    MAX_MESH_NAME,
    CollisionCounter,
    Unread,
    read_shapes,
    shown,
)
from cspace._formats.shared.description import CollisionSpec, LinkSpec
from cspace._formats.shared.pose import IDENTITY, Pose, from_rpy
from cspace._formats.shared.xmlio import line_of
from cspace._formats.urdf.numbers import URDFDOM_NUMBER, URDFDOM_VECTOR, parse_number

_SIZES = {
    "box": ("size",),
    "sphere": ("radius",),
    "cylinder": ("radius", "length"),
}


def read_link(element: etree._Element, name: str, counter: CollisionCounter) -> LinkSpec:
    """A ``<link>`` with its collision shapes (``name``: its name, already read)."""
    shapes, unread = read_shapes(element.iterchildren("collision"), name, counter, _collision)
    kept = () if unread else shapes  # urdfdom keeps none of a link it fails on
    return LinkSpec(name, line_of(element), kept, unread)


def _collision(collision: etree._Element) -> CollisionSpec:
    origin_element = collision.find("origin")
    origin = IDENTITY if origin_element is None else _origin(origin_element)
    geometry = collision.find("geometry")
    if geometry is None:
        raise Unread("<collision> has no <geometry>")
    shape = next(geometry.iterchildren(tag=etree.Element), None)
    if shape is None:
        raise Unread("<collision><geometry> holds no shape")
    kind = str(shape.tag)
    line = line_of(collision)
    if kind == "mesh":
        filename = shape.get("filename")
        if filename is None:
            raise Unread("<mesh> has no 'filename' attribute")
        if len(filename) > MAX_MESH_NAME:
            raise Unread(f"<mesh filename> is longer than {MAX_MESH_NAME:,} characters")
        scale = (1.0, 1.0, 1.0) if shape.get("scale") is None else _vector(shape, "scale")
        return CollisionSpec("mesh", (), origin, filename, scale, line)
    if kind not in _SIZES:
        raise Unread(
            f"<geometry> holds <{shown(kind)}>, no URDF shape (box, sphere, cylinder, mesh)"
        )
    if kind == "box":
        if shape.get("size") is None:
            raise Unread("<box> has no 'size' attribute")
        sizes: tuple[float, ...] = _vector(shape, "size")
    else:
        sizes = tuple(_number(shape, key) for key in _SIZES[kind])
    keys = _SIZES[kind] * 3 if kind == "box" else _SIZES[kind]
    for key, value in zip(keys, sizes, strict=True):
        if value < 0:
            raise Unread(f"<{kind} {key}> is negative")
    return CollisionSpec(kind, sizes, origin, None, (1.0, 1.0, 1.0), line)


def _number(element: etree._Element, key: str) -> float:
    text = element.get(key)
    if text is None:
        raise Unread(f"<{element.tag}> has no '{key}' attribute")
    if URDFDOM_NUMBER.fullmatch(text):  # fast path: a plain decimal
        plain = float(text)
        if math.isfinite(plain):
            return plain
    value = parse_number(text)
    if value is None or not math.isfinite(value):
        raise Unread(f'<{element.tag} {key}="{shown(text)}"> is not a finite number')
    return value


def _vector(element: etree._Element, key: str) -> tuple[float, float, float]:
    text = str(element.get(key))
    if URDFDOM_VECTOR.fullmatch(text):  # fast path: three plain decimals
        x, y, z = map(float, text.split())
        if math.isfinite(x) and math.isfinite(y) and math.isfinite(z):
            return (x, y, z)
    words = text.split(" ")  # urdfdom splits on spaces alone
    values = [parse_number(word) for word in words if word]
    if len(values) != 3 or any(v is None or not math.isfinite(v) for v in values):
        raise Unread(f'<{element.tag} {key}="{shown(text)}"> is not three finite numbers')
    x, y, z = (float(v) for v in values if v is not None)
    return (x, y, z)


def _origin(origin: etree._Element) -> Pose:
    """``xyz`` and ``rpy``: urdfdom (and Pinocchio) ignore a ``quat_xyzw``."""
    position = (0.0, 0.0, 0.0) if origin.get("xyz") is None else _vector(origin, "xyz")
    if origin.get("rpy") is None:
        return Pose(position)
    roll, pitch, yaw = _vector(origin, "rpy")
    return Pose(position, from_rpy(roll, pitch, yaw))
