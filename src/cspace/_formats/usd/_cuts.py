"""The joints that close a USD stage's loops, as the mechanism's cuts (`CutSpec`).

A joint the reader's spanning forest leaves out (it closes a loop: excluded from the
articulation, as PhysX writes a loop, or found so by the forest) holds its two bodies
together as a constraint, not as a coordinate. Its cut is:

- ``kind``: the joint's type, short: ``revolute``, ``prismatic``, ``spherical``,
  ``fixed`` or ``generic`` (a ``PhysicsJoint``, PhysX's D6);
- ``link_a`` and ``frame_a``: body0 and the joint frame in it (``localPos0`` and
  ``localRot0``), ``link_b`` and ``frame_b``: body1 and ``localPos1``/``localRot1``,
  placed as the tree's joints are (`usd._frames` in the child: scaled by the body's world
  scale, then by ``metersPerUnit``); a side with no body is the world, its frame in the
  world's;
- ``free``: ``revolute`` or ``prismatic`` about ``physics:axis`` (X, Y or Z of the joint
  frame), ``rotation`` for a spherical joint, ``none`` for a fixed one or a revolute or
  prismatic joint locked (its lower limit above its upper: PhysX holds it at 0); a
  generic joint by its free axes: none, one rotation or translation, or the three
  rotations. Limits and cone limits of a closing joint are inequalities, not kept.

What cannot be a cut stays out with a ``joint-left-out`` warning: a generic joint of
another set of free axes (a universal, planar or free one: cspace's cuts leave free a
rotation, one axis or nothing) and a distance joint. A frame the child could not compute
(a number that is not finite, a zero scale) is a cut with a position that is not a
number: the closure analysis names it (``closure-invalid``) and leaves it out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import CutSpec
from cspace._formats.shared.loops import limits_ignored
from cspace._formats.shared.pose import Pose
from cspace._formats.shared.robot_size import MAX_CUTS, check_name
from cspace._formats.usd._joints import free_axes, in_metres
from cspace.errors import InvalidElementError

KINDS = {
    "PhysicsRevoluteJoint": "revolute",
    "PhysicsPrismaticJoint": "prismatic",
    "PhysicsSphericalJoint": "spherical",
    "PhysicsFixedJoint": "fixed",
    "PhysicsJoint": "generic",
}
"""A cut's ``kind`` for each UsdPhysics joint type that can close a loop."""

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
_NOWHERE = Pose((math.nan, math.nan, math.nan))


def cuts_of(
    path: str, closing: Sequence[tuple[dict[str, Any], str, tuple[str, str]]], meters: float
) -> tuple[list[CutSpec], list[Diagnostic]]:
    """The cuts of the joints that close loops, and a finding for each left out.

    Args:
        path: The stage's path, for messages.
        closing: Each joint that closes a loop, as the worker read it, with its name and
            its body0 and body1 as link names, in the reader's order.
        meters: The stage's ``metersPerUnit``.

    Raises:
        InvalidElementError: More than `robot_size.MAX_CUTS` joints close loops
            (``too-many-constraints``).
        RobotStructureError: A closing joint's name is longer than a report holds.
    """
    if len(closing) > MAX_CUTS:
        raise InvalidElementError(
            path,
            f"the stage has {len(closing):,} joints that close kinematic loops; cspace "
            f"refuses more than {MAX_CUTS:,}",
            code="too-many-constraints",
        )
    cuts, found = [], []
    for joint, name, ends in closing:
        cut = cut_of(joint, name, ends, meters)
        if isinstance(cut, str):
            found.append(left_out(name, f"closes a kinematic loop but {cut}"))
        else:
            check_name(path, name, None)
            cuts.append(cut)
            found.extend(_limits_left(joint, name, cut))
    return cuts, found


def _limits_left(joint: dict[str, Any], name: str, cut: CutSpec) -> list[Diagnostic]:
    """A warning when a closing revolute or prismatic joint has limits the cut drops."""
    bounds = _bounds(joint)
    if cut.free not in ("revolute", "prismatic") or bounds is None:
        return []
    return [limits_ignored(name, [bounds])]


def _bounds(joint: dict[str, Any]) -> tuple[float, float] | None:
    """A joint's ``lowerLimit`` and ``upperLimit``, or None unless both are finite."""
    low, high = joint.get("lowerLimit"), joint.get("upperLimit")
    bounds = [math.nan if v is None else float(v) for v in (low, high)]
    return (bounds[0], bounds[1]) if all(math.isfinite(v) for v in bounds) else None


def left_out(name: str, why: str) -> Diagnostic:
    """The warning for a joint left out of the tree and of the mechanism's cuts."""
    return finding(
        "joint-left-out",
        None,
        f"joint '{name}' {why}: left out (the space is of the tree and the loops cspace "
        "reads; what the robot reaches is a subset of it)",
    )


def cut_of(joint: dict[str, Any], name: str, ends: tuple[str, str], meters: float) -> CutSpec | str:
    """The cut a joint that closes a loop makes, or why it cannot be one.

    Args:
        joint: The joint as the worker read it.
        name: Its name (the reader's: display name, else prim name, else path).
        ends: Its body0 and body1 as link names (the world where a side has no body).
        meters: The stage's ``metersPerUnit``.
    """
    kind = KINDS.get(str(joint["type"]))
    if kind is None:
        return f"is a {joint['type']}, which cspace does not read as a loop's closure"
    free, axis = _free(joint)
    if free is None:
        return f"is a generic joint free along {axis}, which cspace cannot hold as a loop's closure"
    frames = [in_metres(f, meters) for f in joint.get("frames", (None, None))]
    return CutSpec(
        kind=kind,
        name=name,
        link_a=ends[0],
        frame_a=frames[0] or _NOWHERE,
        link_b=ends[1],
        frame_b=frames[1] or _NOWHERE,
        free=free,
        axis=_AXES.get(axis, (1.0, 0.0, 0.0)),
    )


def _free(joint: dict[str, Any]) -> tuple[str | None, str]:
    """What a closing joint leaves free and its axis letter (None, and its free axes)."""
    kind = joint["type"]
    axis = str(joint.get("axis", "X"))
    if kind in ("PhysicsRevoluteJoint", "PhysicsPrismaticJoint"):
        bounds = _bounds(joint)
        if bounds is not None and bounds[0] > bounds[1]:
            return "none", axis  # locked at 0, as PhysX holds it
        return ("revolute" if kind == "PhysicsRevoluteJoint" else "prismatic"), axis
    if kind == "PhysicsSphericalJoint":
        return "rotation", axis
    if kind == "PhysicsFixedJoint":
        return "none", axis
    free = free_axes(joint.get("limits", {}))
    if not free:
        return "none", axis
    if len(free) == 1:
        return ("revolute" if free[0].startswith("rot") else "prismatic"), free[0][-1]
    if free == ["rotX", "rotY", "rotZ"]:
        return "rotation", axis
    return None, ", ".join(free)
