"""The loops of an SDF document: joints that close them, and Drake's ball constraints.

SDFormat lets a link have several parent joints (example-robot-data's Cassie files close
each leg's linkages so); Drake and Pinocchio refuse such a file. cspace keeps a spanning
tree (`shared.loops.spanning_tree`: the first parent joint of each link in file order,
unless it would close a cycle) and makes each joint left out a cut (`CutSpec`): its
frame in its parent link (``frame_a``) and in its child link (``frame_b``), as the pose
graph resolves the joint's ``<pose>`` (in its child's frame unless ``relative_to``
says otherwise), held together up to the joint's motion: a ``ball`` leaves the rotation
free, a ``fixed`` joint nothing, a ``revolute`` or ``continuous`` one the rotation about
its axis, a ``prismatic`` one the translation along it (the axis in the joint frame,
``frame_a``, from its ``<xyz expressed_in>``). The cut adds no coordinates; its limits,
if any, are not read. A loop closed by any other joint type (``universal``,
``revolute2``, ``screw``) is refused; a ``gearbox`` is refused wherever it is
(`sdf.reader`).

Drake's ``<drake:ball_constraint>`` in a ``<model>`` (`shared.drake_ball`) is a cut too;
its bodies are links of that model itself, as Drake looks them up (not ``inner::link``
of a model inside it).
"""

from __future__ import annotations

import math

from lxml import etree

from cspace._findings import Diagnostic
from cspace._formats.sdf._poses import PoseGraph
from cspace._formats.sdf._scene import SEPARATOR, SdfJoint, SdfScene
from cspace._formats.shared.description import CutSpec, JointSpec
from cspace._formats.shared.drake_ball import ball_constraint
from cspace._formats.shared.loops import limits_ignored
from cspace._formats.shared.pose import inverse
from cspace._formats.shared.xmlio import line_of
from cspace._formats.urdf._drake import is_drake
from cspace.errors import InvalidElementError

LOOP_FREE = {
    "ball": "rotation",
    "fixed": "none",
    "revolute": "revolute",
    "continuous": "revolute",
    "prismatic": "prismatic",
}
"""The SDF joint types that may close a loop, and what each leaves free."""


def loop_cut(
    path: str, graph: PoseGraph, joint: SdfJoint, spec: JointSpec, holder: JointSpec | None
) -> CutSpec:
    """The cut a joint that closes a loop makes.

    Args:
        path: The file, for messages.
        graph: The document's pose graph.
        joint: The joint, as the scene reads it.
        spec: The joint, as the reader reads it.
        holder: The tree's joint that holds the joint's child, or None when the joint
            closes a cycle of joints each the only parent of its child.

    Raises:
        InvalidElementError: A joint type that cannot close a loop
            (``unsupported-loop-joint``), or a pose the graph does not resolve
            (``loop-not-placed``): without it, cspace cannot say where the loop closes.
    """
    why = (
        f"link '{spec.child}' already hangs from joint '{holder.name}' (line {holder.line})"
        if holder is not None
        else f"its parent link '{spec.parent}' already hangs below its child '{spec.child}'"
    )
    free = LOOP_FREE.get(spec.type)
    if free is None:
        raise InvalidElementError(
            path,
            f"joint '{spec.name}' closes a kinematic loop ({why}) and is a {spec.type} "
            "joint: cspace closes a loop with a ball, fixed, revolute, continuous or "
            "prismatic joint only",
            code="unsupported-loop-joint",
            line=spec.line,
            element=spec.name,
        )
    axes = (("axis", spec.axis),) if spec.axis is not None and free != "rotation" else ()
    placed = graph.joint(joint, axes)
    if placed is None:
        raise InvalidElementError(
            path,
            f"joint '{spec.name}' closes a kinematic loop ({why}), and its pose does not "
            "resolve as SDFormat defines (a relative_to or expressed_in naming no frame, "
            "a malformed <pose>, an unknown version): cspace cannot say where it closes",
            code="loop-not-placed",
            line=spec.line,
            element=spec.name,
        )
    axis = placed.axes[0] if placed.axes else (0.0, 0.0, 1.0)
    return CutSpec(
        kind=spec.type,
        name=spec.name,
        link_a=spec.parent,
        frame_a=placed.origin,
        link_b=spec.child,
        frame_b=inverse(placed.child_in_joint),
        free=free,
        axis=_unit(axis),
        line=spec.line,
    )


def _unit(axis: tuple[float, float, float]) -> tuple[float, float, float]:
    """``axis`` made unit; a zero or non-finite one as it is (the analysis refuses it)."""
    norm = math.hypot(*axis)
    if not math.isfinite(norm) or norm == 0.0:
        return axis
    return (axis[0] / norm, axis[1] / norm, axis[2] / norm)


def ball_constraints(scene: SdfScene) -> list[tuple[etree._Element, str]]:
    """Every ``<drake:ball_constraint>`` of the document's models, with its model's scope.

    In file order (a nested model's where it is written).
    """
    found = [
        (element, model.scope)
        for model in scene.models
        for element in model.element.iterchildren(tag=etree.Element)
        if is_drake(element, "ball_constraint")
    ]
    return sorted(found, key=lambda pair: line_of(pair[0]) or 0)


def ball_cut(
    path: str, element: etree._Element, scope: str, index: int, links: set[str]
) -> CutSpec:
    """A ``<drake:ball_constraint>`` of a model (body names in the model's ``scope``).

    Raises:
        InvalidElementError: A part missing, a point not three numbers.
        RobotStructureError: A body that is no link of the model (``missing-link``).
    """

    def link(name: str) -> str | None:  # the model's own link, as Drake looks it up
        scoped = scope + name
        return scoped if SEPARATOR not in name and scoped in links else None

    def value(part: etree._Element) -> str | None:
        return part.text

    return ball_constraint(path, element, index, value, link)


def limits_left(spec: JointSpec) -> Diagnostic:
    """The warning for a loop joint's limits, which the mechanism does not hold."""
    bounds = zip(spec.lower, spec.upper, strict=True)
    return limits_ignored(spec.name, bounds, spec.limit_line or spec.line)
