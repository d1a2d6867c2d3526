"""UsdPhysics joints as cspace's joints: units, locked axes, cone limits, D6 joints.

- revolute limits are degrees (to rad), prismatic ones stage units (times
  ``metersPerUnit``); a revolute joint without finite limits turns freely; a lower limit
  above the upper locks the joint at 0 (a joint of its kind that cannot move, as PhysX
  keeps it);
- a spherical joint's cone limit (``coneAngle0Limit``, ``coneAngle1Limit``) bounds its
  swing and leaves its twist free: R^2 × S^1;
- a generic (D6) joint is the joint its free axes make, or one factor per axis (chained
  through links of its own) where one of several is limited.
"""

from __future__ import annotations

import math
from typing import Any

from cspace._d6 import D6_AXES, axis_link
from cspace._formats.description import JointSpec, JointToAdd
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError

_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def _free(limits: dict[str, list[float]]) -> list[str]:
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
    free = _free(limits)
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
    path: str, joint: dict[str, Any], parent: str, child: str, meters: float
) -> list[tuple[JointSpec, JointToAdd | None]]:
    """A joint as cspace's joints: one, or one per free axis of a limited D6 joint.

    A D6 joint with a limited axis among several free ones is chained through links of
    its own (``child::joint.axis``), each axis a factor of its own: an interval where
    limited.
    """
    limits = joint.get("limits", {})
    free = _free(limits) if joint["type"] == "PhysicsJoint" else []
    if len(free) < 2 or not any(_limited(limits, a) for a in free):
        return [_spec(path, joint, parent, child, meters)]
    out = []
    above = parent
    for k, axis in enumerate(free):
        below = child if k == len(free) - 1 else axis_link(child, joint["name"], axis)
        bounds = limits[axis] if _limited(limits, axis) else [None, None]
        one = {
            **joint,
            "name": f"{joint['name']}.{axis}",
            "type": "PhysicsRevoluteJoint" if axis.startswith("rot") else "PhysicsPrismaticJoint",
            "axis": axis[-1],
            "lowerLimit": bounds[0],
            "upperLimit": bounds[1],
        }
        out.append(_spec(path, one, above, below, meters))
        above = below
    return out


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
        moving = _free(joint.get("limits", {}))
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
                         upper=cone[1], has_limit_element=bool(cone[0]))  # fmt: skip
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
                         JointKind.REVOLUTE, axis=axis, lower=(lower,), upper=(upper,),
                         has_limit_element=True)  # fmt: skip
        return spec, JointToAdd(name, None, "revolute", axis)
    if kind_of == "PhysicsPrismaticJoint":
        bounds = ((lo * meters,), (hi * meters,)) if finite else ((), ())
        spec = JointSpec(name, "locked" if locked else "prismatic", parent, child,
                         JointKind.PRISMATIC, axis=axis, lower=bounds[0], upper=bounds[1],
                         has_limit_element=finite)  # fmt: skip
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
