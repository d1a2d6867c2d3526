"""UsdPhysics joints as cspace's joints: units, locked axes, cone limits, D6 joints.

- revolute limits are degrees (to rad), prismatic ones stage units (times
  ``metersPerUnit``); a revolute joint without finite limits turns freely; a lower limit
  above the upper locks the joint at 0 (a joint of its kind that cannot move, as PhysX
  keeps it);
- a spherical joint's cone limit (``coneAngle0Limit``, ``coneAngle1Limit``) bounds its
  swing and leaves its twist free: R^2 × S^1;
- a generic (D6) joint is the joint its free axes make, or one factor per axis (chained
  through links of its own) where one of several is limited;
- each joint is placed (`placed`): its frame in the parent body's frame (``localPos0``
  and ``localRot0`` where the tree runs from body0 to body1), the child's frame in the
  joint frame (the inverse of the other side's), its axis in the joint frame. A joint
  the tree runs through backwards (from body1 to body0) moves the parent in the
  child's frame: its axis is turned round, so that its value stays PhysX's (body1's
  motion in body0's frame), and a chain of D6 axes is taken in the reverse order. A
  universal, planar or translation D6 joint run backwards is such a chain too, one
  joint per free axis (``joint.rotX`` ...), each value PhysX's: no single Pinocchio
  joint moves body0 in body1's frame with PhysX's values (`_per_axis`). A ball's or a
  free D6 joint's value run backwards is body0's turn (and pose) in body1's frame.
  Pinocchio's planar joint moves in its x-y plane: a D6 joint planar about x or y is
  turned so that its rotation axis is the joint frame's z.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from cspace._d6 import D6_AXES, axis_link
from cspace._formats.shared.description import JointSpec, JointToAdd
from cspace._formats.shared.pose import IDENTITY, Pose, compose, inverse, unit
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError, RobotStructureError

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def free_axes(limits: dict[str, list[float]]) -> list[str]:
    """A D6 joint's free axes: those without a limit, or limited with low <= high."""
    return [a for a in D6_AXES if a not in limits or limits[a][0] <= limits[a][1]]


def _limited(limits: dict[str, list[float]], axis: str) -> bool:
    """Whether a D6 axis has finite bounds (an unset limit is -inf to inf: none)."""
    return axis in limits and all(math.isfinite(v) for v in limits[axis])


def _d6(
    path: str, name: str, limits: dict[str, list[float]], parent: str, child: str
) -> tuple[JointSpec, JointToAdd | None] | None:
    """A D6 joint of several free axes as the joint they make (None for one or none).

    Two translations and the rotation about the third axis: planar, SE(2); three
    rotations: a ball, SO(3) (whatever angles PhysX keeps); three translations: R^3;
    all six: floating; two rotations: universal. Limits on these are not read yet.

    Raises:
        InvalidElementError: Another combination (not read yet).
    """
    free = free_axes(limits)
    if len(free) <= 1:
        return None
    trans = sorted(a[-1] for a in free if a.startswith("trans"))
    rots = sorted(a[-1] for a in free if a.startswith("rot"))
    shapes: dict[tuple[tuple[str, ...], tuple[str, ...]], tuple[JointKind, str]] = {}
    for turn, (u, v) in (("Z", ("X", "Y")), ("Y", ("X", "Z")), ("X", ("Y", "Z"))):
        shapes[((u, v), (turn,))] = (JointKind.PLANAR, "planar")
    shapes[((), ("X", "Y", "Z"))] = (JointKind.SPHERICAL, "spherical")
    shapes[(("X", "Y", "Z"), ())] = (JointKind.TRANSLATION, "translation")
    shapes[(("X", "Y", "Z"), ("X", "Y", "Z"))] = (JointKind.FLOATING, "floating")
    for pair in (("X", "Y"), ("X", "Z"), ("Y", "Z")):
        shapes[((), pair)] = (JointKind.UNIVERSAL, "universal")
    found = shapes.get((tuple(trans), tuple(rots)))
    if found is None:
        raise InvalidElementError(
            path,
            f"joint '{name}' is a generic joint free along {', '.join(free)}, which this "
            "reader does not read yet",
            element=name,
            code="unsupported-joint-type",
        )
    kind, model = found
    axes = [_AXES[r] for r in rots] + [(0.0, 1.0, 0.0)]
    add = JointToAdd(name, None, model, axes[0], axes[1] if len(axes) > 1 else (0.0, 1.0, 0.0))
    return JointSpec(name, "generic", parent, child, kind), add


def specs_of(
    path: str,
    joint: dict[str, Any],
    ends: tuple[str, str],
    meters: float,
    frames: tuple[Pose | None, Pose | None] = (None, None),
    reverse: bool = False,
) -> list[tuple[JointSpec, JointToAdd | None]]:
    """A joint as cspace's joints: one, or one per free axis of a limited D6 joint.

    A D6 joint with a limited axis among several free ones is chained through links of
    its own (``child::joint.axis``), each axis a factor of its own: an interval where
    limited.

    Args:
        path: The stage's path, for messages.
        joint: The joint as the worker read it (``name`` set to cspace's name).
        ends: Its parent and child in the tree.
        meters: The stage's ``metersPerUnit``.
        frames: The joint frame in the parent's frame and in the child's (m), each None
            where it cannot be placed (then the joint's ``origin`` is None).
        reverse: Whether the tree runs from body1 to body0.
    """
    parent, child = ends
    limits = joint.get("limits", {})
    free = free_axes(limits) if joint["type"] == "PhysicsJoint" else []
    if len(free) < 2 or not (
        any(_limited(limits, a) for a in free) or (reverse and _per_axis(path, joint, ends))
    ):
        return [placed(_spec(path, joint, parent, child, meters), frames, reverse)]
    out = []
    above = parent
    order = list(reversed(free)) if reverse else free
    for k, axis in enumerate(order):
        below = child if k == len(order) - 1 else axis_link(child, joint["name"], axis)
        bounds = limits[axis] if _limited(limits, axis) else [None, None]
        one = {
            **joint,
            "name": f"{joint['name']}.{axis}",
            "type": "PhysicsRevoluteJoint" if axis.startswith("rot") else "PhysicsPrismaticJoint",
            "axis": axis[-1],
            "lowerLimit": bounds[0],
            "upperLimit": bounds[1],
        }
        ours = (frames[0] if k == 0 else IDENTITY, frames[1] if below == child else IDENTITY)
        out.append(placed(_spec(path, one, above, below, meters), ours, reverse))
        above = below
    return out


_PER_AXIS = (JointKind.UNIVERSAL, JointKind.PLANAR, JointKind.TRANSLATION)
"""D6 joints whose values are one per axis (a ball's and a free joint's are a turn)."""


def _per_axis(path: str, joint: dict[str, Any], ends: tuple[str, str]) -> bool:
    """Whether a D6 joint of several free axes is one whose values are one per axis.

    Run backwards, such a joint is a chain of one joint per axis, in the reverse order:
    body0's motion in body1's frame applies the axes in the other order, so no single
    Pinocchio joint keeps each value PhysX's (a universal joint's first angle is about
    the axis fixed in the tree's parent, which is PhysX's second; a planar joint's
    translation, taken in body1's frame, turns with its angle).

    Raises:
        InvalidElementError: A combination of free axes this reader does not read.
    """
    made = _d6(path, joint["name"], joint.get("limits", {}), *ends)
    return made is not None and made[0].kind in _PER_AXIS


def in_metres(pose: Sequence[float] | None, meters: float) -> Pose | None:
    """A pose from the worker (``[x, y, z, qw, qx, qy, qz]``, stage units) in metres."""
    if pose is None or len(pose) != 7:
        return None
    x, y, z, w, i, j, k = (float(v) for v in pose)
    placed = Pose((x * meters, y * meters, z * meters), unit((w, i, j, k)))
    return placed if all(math.isfinite(v) for v in placed.position) else None


def refuse_dangling(path: str, joints: list[dict[str, Any]], names: dict[str, str]) -> None:
    """Refuse a joint whose body relationship names a prim the stage does not have.

    Raises:
        RobotStructureError: The first such joint (``missing-link``).
    """
    for joint in joints:
        for side, target in joint.get("dangling", ()):
            name = names[joint["path"]]
            raise RobotStructureError(
                path,
                f"joint '{name}' names {side} <{target}>, which does not exist (PhysX "
                "skips such a joint; OpenUSD's UsdPhysics reads it as the world)",
                element=name,
                code="missing-link",
            )


_TURNS: dict[tuple[float, float, float], Pose] = {
    (1.0, 0.0, 0.0): Pose(rotation_wxyz=(0.5, 0.5, 0.5, 0.5)),  # x, y, z to y, z, x
    (0.0, 1.0, 0.0): Pose(rotation_wxyz=(0.5, -0.5, -0.5, -0.5)),  # x, y, z to z, x, y
}
"""The turn that takes a planar joint's z to its rotation axis, and x, y into its plane."""


def placed(
    pair: tuple[JointSpec, JointToAdd | None],
    frames: tuple[Pose | None, Pose | None],
    reverse: bool,
) -> tuple[JointSpec, JointToAdd | None]:
    """A joint placed by its frames in its parent and its child (see the module docstring)."""
    spec, add = pair
    in_parent, in_child = frames
    if in_parent is None or in_child is None:
        return spec._replace(origin=None), add
    origin, child_in_joint = in_parent, inverse(in_child)
    if add is not None and add.model == "planar" and add.axis in _TURNS:
        turn = _TURNS[add.axis]
        origin, child_in_joint = compose(origin, turn), compose(inverse(turn), child_in_joint)
    spec = spec._replace(origin=origin, child_in_joint=child_in_joint)
    if reverse and add is not None and add.model in ("revolute", "continuous", "prismatic"):
        spec, add = spec._replace(axis=_back(add.axis)), add._replace(axis=_back(add.axis))
    elif reverse and add is not None and add.model == "universal":
        add = add._replace(axis=_back(add.axis2), axis2=_back(add.axis))
    return spec, add


def _back(axis: tuple[float, float, float]) -> tuple[float, float, float]:
    """An axis turned round (no -0.0)."""
    return (-axis[0] + 0.0, -axis[1] + 0.0, -axis[2] + 0.0)


def _spec(
    path: str, joint: dict[str, Any], parent: str, child: str, meters: float
) -> tuple[JointSpec, JointToAdd | None]:
    """One UsdPhysics joint as cspace's joint, and what Pinocchio is asked for."""
    kind_of = joint["type"]
    name = joint["name"]
    axis = _AXES.get(str(joint.get("axis", "X")), (1.0, 0.0, 0.0))
    low, high = joint.get("lowerLimit"), joint.get("upperLimit")
    if kind_of == "PhysicsJoint":  # D6: its free axes, and the joint they make together
        d6 = _d6(path, name, joint.get("limits", {}), parent, child)
        if d6 is not None:
            return d6
        moving = free_axes(joint.get("limits", {}))
        axis_name = moving[0] if moving else ""
        if not moving:
            kind_of = "PhysicsFixedJoint"
        else:
            axis = _AXES[axis_name[-1]]
            kind_of = (
                "PhysicsRevoluteJoint" if axis_name.startswith("rot") else "PhysicsPrismaticJoint"
            )
            bounds = joint.get("limits", {}).get(axis_name)
            low, high = bounds if bounds else (None, None)
    if kind_of == "PhysicsFixedJoint":
        return JointSpec(name, "fixed", parent, child, JointKind.FIXED), None
    if kind_of == "PhysicsSphericalJoint":
        cone = _cone(path, name, joint.get("coneAngle0Limit"), joint.get("coneAngle1Limit"))
        spec = JointSpec(name, "spherical", parent, child, JointKind.SPHERICAL, lower=cone[0],
                         upper=cone[1])  # fmt: skip
        return spec, JointToAdd(name, None, "spherical")
    lo = math.nan if low is None else float(low)
    hi = math.nan if high is None else float(high)
    finite = math.isfinite(lo) and math.isfinite(hi)
    locked = finite and lo > hi  # PhysX: a lower limit above the upper locks it at 0
    if locked:
        lo = hi = 0.0
    if kind_of == "PhysicsRevoluteJoint":
        if not finite:
            spec = JointSpec(name, "revolute", parent, child, JointKind.CONTINUOUS, axis=axis)
            return spec, JointToAdd(name, None, "continuous", axis)
        lower, upper = math.radians(lo), math.radians(hi)
        spec = JointSpec(name, "locked" if locked else "revolute", parent, child,
                         JointKind.REVOLUTE, axis=axis, lower=(lower,), upper=(upper,))  # fmt: skip
        return spec, JointToAdd(name, None, "revolute", axis)
    if kind_of == "PhysicsPrismaticJoint":
        bounds = ((lo * meters,), (hi * meters,)) if finite else ((), ())
        spec = JointSpec(name, "locked" if locked else "prismatic", parent, child,
                         JointKind.PRISMATIC, axis=axis, lower=bounds[0],
                         upper=bounds[1])  # fmt: skip
        return spec, JointToAdd(name, None, "prismatic", axis)
    raise InvalidElementError(
        path, f"joint '{name}' is a {kind_of}, which cspace does not read",
        element=name, code="unsupported-joint-type",
    )  # fmt: skip


def _cone(
    path: str, name: str, first: float | None, second: float | None
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """A spherical joint's cone limit as swing bounds (rad), or none for a whole ball.

    UsdPhysics: ``coneAngle0Limit`` and ``coneAngle1Limit`` in degrees, a negative (the
    default) or missing one not limited; the cone limits only when both are set. Both
    180 or more exclude nothing.

    Raises:
        InvalidElementError: One is 180 or more (infinite included) and the other less
            (a cone that reaches the opposite pole in one direction only), or one is NaN.
    """
    if first is None or second is None or first < 0.0 or second < 0.0:
        return (), ()
    if math.isnan(first) or math.isnan(second):
        raise InvalidElementError(
            path,
            f"joint '{name}' has a cone limit that is not a number ({first:g}, {second:g})",
            element=name,
            code="bad-number",
        )
    first, second = first + 0.0, second + 0.0  # -0 is 0
    if (first >= 180.0) != (second >= 180.0):
        raise InvalidElementError(
            path,
            f"joint '{name}' has cone limits of {first:g} and {second:g} degrees, a cone "
            "this reader does not read (one reaches the opposite pole, the other does not)",
            element=name,
            code="unsupported-joint-type",
        )
    if first >= 180.0:
        return (), ()
    radians = (math.radians(first), math.radians(second))
    return (-radians[0] or 0.0, -radians[1] or 0.0), radians
