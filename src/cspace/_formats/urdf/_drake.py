"""Drake's joints in a URDF file (``<drake:joint>``): ball, universal and planar.

Drake's URDF parser reads ``<drake:joint name type>`` with ``<parent>``, ``<child>`` and
``<origin>`` (``drake`` being the prefix, as Drake matches it) as a joint URDF lacks:
``ball`` (Drake's ``BallRpyJoint``: the child turns freely about the joint frame's
origin), ``universal`` (about the joint frame's x axis, then the turned y axis) and
``planar`` (in the plane normal to its ``<axis>``, Drake's default (1, 0, 0)). cspace
reads these three, the planar one only with ``<axis xyz="0 0 1"/>`` (the joint frame's
x-y plane, as Pinocchio's planar joint moves), and refuses the others by name.

Of URDF's own joints, Drake builds two otherwise than Pinocchio (`drake_differs`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from lxml import etree

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec
from cspace._formats.shared.xmlio import line_of
from cspace._joint_kind import JointKind

if TYPE_CHECKING:
    from cspace._formats.urdf._elements import ElementReader


def is_drake(element: etree._Element, local: str) -> bool:
    """Whether an element is ``<drake:LOCAL>``: by its prefix, as Drake matches it.

    Drake's parser matches a name such as ``drake:joint`` as written, whatever namespace
    the prefix is declared for (``xmlns:drake="http://drake.mit.edu"`` by convention),
    and not ``<d:joint>`` under Drake's namespace URI.
    """
    return (
        isinstance(element.tag, str)
        and element.prefix == "drake"
        and etree.QName(element).localname == local
    )


def is_drake_joint(element: etree._Element) -> bool:
    """Whether an element is a ``<drake:joint>`` (`is_drake`)."""
    return is_drake(element, "joint")


DRAKE_JOINTS = {
    "ball": (JointKind.SPHERICAL, "floating"),
    "universal": (JointKind.UNIVERSAL, "floating"),
    "planar": (JointKind.PLANAR, "planar"),
}
"""``<drake:joint>`` types cspace reads: each one's kind, and the URDF joint type that
stands for it in the document Pinocchio's parser is given (a ball or a universal joint,
which URDF lacks, is given as ``floating`` and its joint model replaced once the model
is built, see `cspace._model._swap`)."""


def drake_joint(reader: ElementReader, element: etree._Element) -> JointSpec:
    """A ``<drake:joint>`` of a type in `DRAKE_JOINTS`.

    Raises:
        InvalidElementError: Another type, a planar joint whose plane is not its frame's
            x-y plane, or what a URDF joint would be refused for.
    """
    name, owner, joint_type = reader.begin(element)
    if joint_type not in DRAKE_JOINTS:
        reader.fail(
            "unsupported-element",
            f"{owner} is a <drake:joint> of type '{joint_type}', which cspace does not read "
            f"(it reads {', '.join(DRAKE_JOINTS)})",
            element,
            name,
        )
    parent = reader.link_name(element, "parent", owner)
    child = reader.link_name(element, "child", owner)
    reader.others(element, owner)
    if joint_type == "planar":
        axis = reader.axis(element, owner)
        finite = axis is not None and all(math.isfinite(a) for a in axis)
        if axis is None or not (finite and axis[0] == axis[1] == 0.0 and axis[2] > 0.0):
            reader.fail(
                "unsupported-element",
                f"{owner} is a planar <drake:joint> whose plane's normal (its <axis>, "
                f"{'(1, 0, 0) by default' if axis is None else axis}) is not z: cspace reads "
                'one with <axis xyz="0 0 1"/> only (the joint frame\'s x-y plane; turn '
                "the plane with <origin rpy>)",
                element,
                name,
            )
    kind = DRAKE_JOINTS[joint_type][0]
    return JointSpec(name, f"drake:{joint_type}", parent, child, kind, line=line_of(element))


def drake_differs(joints: Sequence[JointSpec]) -> list[Diagnostic]:
    """The ``drake-urdf-differs`` findings of a URDF file's joints (none where Drake agrees).

    Drake's URDF parser (``Parser(plant).AddModels``) places every joint by its
    ``<origin>`` and moves it as Pinocchio does, but two:

    - a ``planar`` joint moves in the plane normal to its ``<axis>`` ((1, 0, 0) when
      absent), as URDF specifies; Pinocchio's moves in its frame's x-y plane whatever
      the axis. They agree when the axis points along +z (a zero or non-finite axis is
      an error of its own, ``axis-invalid``). A planar ``<drake:joint>`` is read only so.
    - a ``floating`` joint is no joint in Drake: it leaves the child a free body, whose
      q is its pose in the world. From a root link, cspace's Drake convention composes
      the joint's ``<origin>`` into that pose, and the two agree; below another link,
      the child no longer moves with it, and cspace does not map Drake's vectors.
    """
    children = {joint.child for joint in joints}
    found = []
    for joint in joints:
        axis = joint.axis
        if joint.type == "planar" and not _along_z(axis):
            if axis is not None and not (all(map(math.isfinite, axis)) and any(axis)):
                continue  # no direction: axis-invalid, an error
            said = "(1, 0, 0) (URDF's default: it gives no <axis>)" if axis is None else _xyz(axis)
            found.append(
                finding(
                    "drake-urdf-differs",
                    joint.name,
                    f"Drake's URDF parser moves link '{joint.child}' of planar joint "
                    f"'{joint.name}' in the plane normal to its axis, {said}, as URDF "
                    "specifies; Pinocchio (and cspace's model) moves it in the x-y plane of "
                    "the joint's frame, whatever the axis: Drake's q of a configuration "
                    f"(--to drake) puts '{joint.child}', and the links below it, elsewhere. "
                    'To have both agree, give the joint <axis xyz="0 0 1"/> and turn its '
                    "frame with <origin rpy>",
                    joint.line,
                )
            )
        elif joint.type == "floating" and joint.parent in children:
            found.append(
                finding(
                    "drake-urdf-differs",
                    joint.name,
                    f"Drake's URDF parser makes no joint of floating joint '{joint.name}': "
                    f"it leaves link '{joint.child}' a free body, whose q is its pose in the "
                    f"world, and which does not move with link '{joint.parent}' as in the "
                    "file (and in Pinocchio); cspace does not map Drake's vectors of this "
                    "file (--to drake)",
                    joint.line,
                )
            )
    return found


def _along_z(axis: tuple[float, float, float] | None) -> bool:
    """Whether an axis points along +z (Drake's planar joint is then Pinocchio's)."""
    return axis is not None and axis[0] == axis[1] == 0.0 and 0.0 < axis[2] < math.inf


def _xyz(axis: tuple[float, float, float]) -> str:
    return "(" + ", ".join(f"{c:g}" for c in axis) + ")"
