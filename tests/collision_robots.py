"""Robots written by the tests of the self-collision engine, as text.

The primitive robot (`LINKS`, `JOINTS`): boxes, spheres, cylinders and capsules on
rotated origins, a continuous, a prismatic and a fixed joint, a link without geometry,
two sibling fingers. It is written as a URDF (`primitive_urdf`, capsules as
``<capsule radius length>``, which PyBullet reads and URDF does not have) and as its
SDFormat twin (`primitive_sdf`), the same links and joints. `turned_links` turns its
shapes at random (seeded). `mesh_urdf` is a robot of example-robot-data's meshes in
three formats, scaled. Lengths in metres, angles in radians.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

Shape = tuple[str, tuple[float, ...], tuple[float, float, float], tuple[float, float, float]]
"""kind, sizes (box x y z; sphere r; cylinder and capsule r and the cylinder's length),
origin xyz (m) and rpy (rad) in the link's frame."""

LINKS: dict[str, list[Shape]] = {
    "base": [("box", (0.24, 0.24, 0.1), (0, 0, 0.05), (0, 0, 0))],
    "arm1": [
        ("cylinder", (0.05, 0.15), (0, 0, 0.075), (0, 0, 0)),
        ("sphere", (0.06,), (0, 0, 0.15), (0, 0, 0)),
    ],
    "arm2": [
        ("box", (0.06, 0.06, 0.2), (0, 0, 0.1), (0, 0, 0.4)),
        ("capsule", (0.035, 0.1), (0, 0.05, 0.15), (0.6, 0, 0)),
    ],
    "arm3": [
        ("capsule", (0.04, 0.08), (0, 0, 0.06), (0, 0, 0)),
        ("box", (0.04, 0.1, 0.03), (0, 0, 0.11), (0.2, 0.3, 0.1)),
    ],
    "arm4": [
        ("cylinder", (0.03, 0.12), (0, 0, 0.06), (0, 1.2, 0)),
        ("sphere", (0.04,), (0, 0, 0.1), (0, 0, 0)),
    ],
    "slider": [("box", (0.05, 0.05, 0.08), (0, 0, 0.04), (0, 0, 0))],
    "flange": [],  # no geometry: slider and hand are adjacent through it
    "hand": [
        ("sphere", (0.045,), (0, 0, 0.03), (0, 0, 0)),
        ("cylinder", (0.02, 0.08), (0, 0, 0.05), (1.5708, 0, 0.3)),
    ],
    "left": [("capsule", (0.012, 0.06), (0, 0, 0.03), (0, 0, 0))],
    "right": [("box", (0.02, 0.02, 0.06), (0, 0, 0.03), (0, 0, 0))],
}

Joint = tuple[
    str,
    str,
    str,
    str,
    tuple[float, float, float],
    tuple[float, float, float],
    tuple[float, float, float],
    tuple[float, float],
]
"""name, type, parent, child, origin xyz and rpy in the parent's frame, axis, limits."""

JOINTS: list[Joint] = [
    ("j1", "revolute", "base", "arm1", (0, 0, 0.1), (0, 0, 0), (0, 0, 1), (-2.9, 2.9)),
    ("j2", "revolute", "arm1", "arm2", (0, 0, 0.15), (0, 0, 0), (0, 1, 0), (-2.6, 2.6)),
    ("j3", "continuous", "arm2", "arm3", (0, 0, 0.2), (0.3, 0, 0), (0, 0, 1), (0, 0)),
    ("j4", "revolute", "arm3", "arm4", (0, 0.02, 0.12), (0, 0, 0), (1, 0, 0), (-2.8, 2.8)),
    ("j5", "prismatic", "arm4", "slider", (0, 0, 0.1), (0, 0, 0), (0, 0, 1), (0, 0.1)),
    ("j6", "fixed", "slider", "flange", (0, 0, 0.08), (0, 0, 0.5), (0, 0, 1), (0, 0)),
    ("j7", "revolute", "flange", "hand", (0, 0, 0.02), (0, 0, 0), (0, 1, 0), (-2.9, 2.9)),
    ("j8", "revolute", "hand", "left", (0, 0.03, 0.06), (0, 0, 0), (1, 0, 0), (-0.5, 1.5)),
    ("j9", "revolute", "hand", "right", (0, -0.03, 0.06), (0, 0, 0), (-1, 0, 0), (-0.5, 1.5)),
]


def turned_links() -> dict[str, list[Shape]]:
    """`LINKS` with every shape turned at random (seeded), each box's pitch a right angle
    (where rpy is singular)."""
    rng = np.random.default_rng(0)
    turned: dict[str, list[Shape]] = {}
    for link, shapes in LINKS.items():
        turned[link] = []
        for kind, sizes, xyz, _ in shapes:
            roll, pitch, yaw = (float(a) for a in rng.uniform(-math.pi, math.pi, 3))
            pitch = math.pi / 2 if kind == "box" else pitch
            turned[link].append((kind, sizes, xyz, (roll, pitch, yaw)))
    return turned


INERTIAL = (
    '<inertial><mass value="0.1"/>'
    '<inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial>'
)


def _words(values: Sequence[float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def primitive_urdf(links: dict[str, list[Shape]] = LINKS) -> str:
    """The primitive robot as a URDF, its capsules as ``<capsule radius length>``
    (PyBullet's reading: a ``btCapsuleShapeZ``, ``length`` the cylinder's)."""
    out = ['<?xml version="1.0"?>', '<robot name="primitives">']
    for link, shapes in links.items():
        out.append(f'<link name="{link}">{INERTIAL}')
        for kind, sizes, xyz, rpy in shapes:
            if kind == "box":
                element = f'<box size="{_words(sizes)}"/>'
            elif kind == "sphere":
                element = f'<sphere radius="{sizes[0]!r}"/>'
            else:
                element = f'<{kind} radius="{sizes[0]!r}" length="{sizes[1]!r}"/>'
            out.append(
                f'<collision><origin xyz="{_words(xyz)}" rpy="{_words(rpy)}"/>'
                f"<geometry>{element}</geometry></collision>"
            )
        out.append("</link>")
    for name, kind, parent, child, xyz, rpy, axis, (lower, upper) in JOINTS:
        out.append(
            f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{_words(xyz)}" rpy="{_words(rpy)}"/>'
        )
        if kind != "fixed":
            out.append(f'<axis xyz="{_words(axis)}"/>')
        if kind in ("revolute", "prismatic"):
            out.append(f'<limit lower="{lower!r}" upper="{upper!r}" effort="1" velocity="1"/>')
        out.append("</joint>")
    out.append("</robot>")
    return "\n".join(out)


def primitive_sdf(links: dict[str, list[Shape]] = LINKS) -> str:
    """The same robot as SDFormat 1.9: each link posed relative to its parent link at
    its joint's origin, the joint at the child's frame (its axis expressed there, as a
    URDF axis is), capsules as ``<capsule>``, the base fixed to the world."""
    parents = {child: (parent, xyz, rpy) for _, _, parent, child, xyz, rpy, _, _ in JOINTS}
    out = ['<?xml version="1.0"?>', '<sdf version="1.9"><model name="primitives">']
    for link, shapes in links.items():
        out.append(f'<link name="{link}">')
        if link in parents:
            parent, xyz, rpy = parents[link]
            out.append(f'<pose relative_to="{parent}">{_words(xyz)} {_words(rpy)}</pose>')
        for index, (kind, sizes, xyz, rpy) in enumerate(shapes):
            if kind == "box":
                element = f"<box><size>{_words(sizes)}</size></box>"
            elif kind == "sphere":
                element = f"<sphere><radius>{sizes[0]!r}</radius></sphere>"
            else:
                element = (
                    f"<{kind}><radius>{sizes[0]!r}</radius><length>{sizes[1]!r}</length></{kind}>"
                )
            out.append(
                f'<collision name="c{index}"><pose>{_words(xyz)} {_words(rpy)}</pose>'
                f"<geometry>{element}</geometry></collision>"
            )
        out.append("</link>")
    out.append(
        '<joint name="anchor" type="fixed"><parent>world</parent><child>base</child></joint>'
    )
    for name, kind, parent, child, _, _, axis, (lower, upper) in JOINTS:
        out.append(
            f'<joint name="{name}" type="{kind}"><parent>{parent}</parent><child>{child}</child>'
        )
        if kind != "fixed":
            limit = ""
            if kind in ("revolute", "prismatic"):
                limit = f"<limit><lower>{lower!r}</lower><upper>{upper!r}</upper></limit>"
            out.append(f"<axis><xyz>{_words(axis)}</xyz>{limit}</axis>")
        out.append("</joint>")
    out.append("</model></sdf>")
    return "\n".join(out)


ERD_MESHES = "package://example-robot-data/robots"
MESHES: list[tuple[str, str, str, str, str]] = [
    # link, mesh, scale, origin xyz, origin rpy
    ("base", "panda_description/meshes/collision/link3.stl", "1.5 0.8 1.2", "0 0 0", "0.3 0 0"),
    ("thigh", "go1_description/meshes/thigh.dae", "1 1 1", "0 0 0.05", "0 0.5 0"),
    ("calf", "laikago_description/meshes/calf.obj", "0.7 1.3 1", "0 0 0", "0 0 0.4"),
    ("hand", "panda_description/meshes/collision/hand.stl", "1 1 1", "0 0 0.02", "0 0 0"),
    ("mirror", "laikago_description/meshes/calf.obj", "1 -1 1", "0 0 0", "0 0 0"),
]
MESH_JOINTS = [  # name, parent, child, origin xyz, axis: revolute in [-3, 3]
    ("j1", "base", "thigh", "0 0 0.08", "0 1 0"),
    ("j2", "thigh", "calf", "0 0 -0.2", "1 0 0"),
    ("j3", "calf", "hand", "0 0 -0.25", "0 1 0"),
    ("j4", "thigh", "mirror", "0 0.05 -0.1", "0 0 1"),
]


def mesh_urdf() -> str:
    """A robot of example-robot-data's meshes: STL, COLLADA and OBJ, scaled (one
    mirrored), on rotated origins."""
    out = ['<robot name="meshes">']
    for link, mesh, scale, xyz, rpy in MESHES:
        out.append(
            f'<link name="{link}">{INERTIAL}<collision><origin xyz="{xyz}" rpy="{rpy}"/>'
            f'<geometry><mesh filename="{ERD_MESHES}/{mesh}" scale="{scale}"/></geometry>'
            "</collision></link>"
        )
    for name, parent, child, xyz, axis in MESH_JOINTS:
        out.append(
            f'<joint name="{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{xyz}"/><axis xyz="{axis}"/>'
            '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
        )
    out.append("</robot>")
    return "\n".join(out)
