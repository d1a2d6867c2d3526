"""Findings about a file that can still be analysed, each with a stable code.

Each code, its severity and its meaning are in ``cspace._findings`` (``CODES``,
``MEANINGS``); docs/safety.md explains each. The findings about the robot's root
(`robot_findings`) are `cspace._model._root_advice`'s.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec
from cspace._joint_kind import JointKind
from cspace._model._root_advice import robot_findings as robot_findings

TWO_PI = 2.0 * math.pi
ANGLE_TOLERANCE = 1e-4
"""How close to pi or 2*pi a limit must be to count as "exactly" (3.1416 does, 3.14 not)."""
AXIS_TOLERANCE = 1e-6


_ONE_AXIS = (JointKind.REVOLUTE, JointKind.CONTINUOUS, JointKind.PRISMATIC, JointKind.HELICAL)
_ROTATIONS = (JointKind.REVOLUTE, JointKind.CONTINUOUS)
_MOVING = (*_ROTATIONS, JointKind.PRISMATIC)
"""One-coordinate joints a file gives limits: a lower == upper == 0 there is a stand-in."""


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= ANGLE_TOLERANCE


_AXIS_CODES = frozenset({"axis-invalid", "axis-normalized"})
_LIMIT_CODES = frozenset(
    {
        "limits-empty",
        "limits-not-finite",
        "joint-locked",
        "continuous-has-limits",
        "mimic-limits-contradict",
        "mimic-not-periodic",
        "revolute-ambiguous-range",
        "multi-turn",
        "limits-in-degrees",
        "limits-sentinel",
        "limits-unset",
        "limit-bound-missing",
    }
)


def joint_findings(spec: JointSpec, leader: JointSpec | None) -> Iterator[Diagnostic]:
    """Every finding about one joint, each at the line of the element it is about.

    The ``<axis>`` for axis findings, the ``<limit>`` for limit findings (when the file
    has them), else the joint's own line.
    """
    for found in _joint_findings(spec, leader):
        line = spec.line
        if found.code in _AXIS_CODES and spec.axis_line is not None:
            line = spec.axis_line
        elif found.code in _LIMIT_CODES and spec.limit_line is not None:
            line = spec.limit_line
        yield found._replace(line=line)


def _joint_findings(spec: JointSpec, leader: JointSpec | None) -> Iterator[Diagnostic]:
    """Every finding about one joint, from what the file says of it.

    Args:
        spec: The joint as the file gives it.
        leader: For a mimic joint, the joint it follows; else None.
    """
    name = spec.name
    yield from _axis_findings(spec)
    if leader is not None:
        yield from _unwound(spec, leader)
    bad = _not_finite(spec)
    if bad:
        limits = spec.lower + spec.upper
        treated = (
            "; the joint is reported as if it had no limits"
            if not all(math.isfinite(x) for x in limits)
            else ""
        )
        yield finding(
            "limits-not-finite",
            name,
            f"joint '{name}' has {', '.join(bad)}: not finite numbers{treated}"
            if len(bad) > 1
            else f"joint '{name}' has {bad[0]}: not a finite number{treated}",
        )
        return
    if spec.kind is JointKind.CONTINUOUS and spec.lower:
        yield finding(
            "continuous-has-limits",
            name,
            f"continuous joint '{name}' gives limits [{spec.lower[0]:g}, "
            f"{spec.upper[0]:g}], which URDF ignores: it is S^1; make it revolute "
            "if the limits are meant",
        )
        return
    cone = spec.kind is JointKind.SPHERICAL and len(spec.lower) == 2
    if not spec.lower or cone:  # a cone's swings: two bounds, checked when read
        return
    if len(spec.lower) > 1:  # a joint of several axes (universal, translation): each
        yield from _axes_findings(spec)
        return
    lower, upper = spec.lower[0], spec.upper[0]
    if spec.type == "locked":  # a USD joint whose lower limit is above its upper
        yield finding(
            "joint-locked",
            name,
            f"joint '{name}' has a lower limit above its upper, which locks it at 0 (as "
            "PhysX does): it contributes dimension 0",
        )
        return
    if lower > upper:
        yield finding(
            "limits-empty",
            name,
            f"joint '{name}' has lower limit {lower:g} > upper limit {upper:g}: "
            "its interval is empty, so the C-space is empty; pybullet reads lower > upper "
            "as 'no limit', which URDF does not: if that is meant, "
            + (
                "make the joint continuous"
                if spec.kind is JointKind.REVOLUTE
                else "give the limits of its travel"
            ),
        )
        return
    if lower == upper and spec.mimic is None and spec.limits_defaulted:
        yield finding(
            "joint-locked",
            name,
            f"joint '{name}' has a <limit> without lower and upper, which URDF "
            "reads as 0 and 0: it is locked and contributes dimension 0 "
            "(make it continuous if it turns freely)",
        )
    elif lower == upper == 0.0 and spec.mimic is None and spec.kind in _MOVING:
        yield finding(
            "limits-unset",
            name,
            f"joint '{name}' has lower == upper == 0, which files write for 'limits not "
            "given': it is read as locked (dimension 0); if it moves, give its limits"
            + (", or make it continuous if it turns freely" if spec.kind in _ROTATIONS else ""),
        )
    elif lower == upper and spec.mimic is None:
        yield finding(
            "joint-locked",
            name,
            f"joint '{name}' has lower == upper == {lower:g}: it is locked "
            "and contributes dimension 0",
        )
    if leader is not None and spec.mimic is not None:
        yield from _mimic_findings(spec, leader)
    if len(spec.bounds_missing) == 1:
        yield _bound_missing(spec, lower, upper)
    if spec.kind in _MOVING and spec.mimic is None and max(abs(lower), abs(upper)) >= SENTINEL:
        yield _sentinel(spec, lower, upper)
    elif spec.kind in _ROTATIONS and spec.mimic is None:
        yield from _turn_findings(name, lower, upper)


def _axes_findings(spec: JointSpec) -> Iterator[Diagnostic]:
    """Each axis of a joint of several axes: an empty interval, or one that cannot move."""
    for axis, (lower, upper) in enumerate(zip(spec.lower, spec.upper, strict=False), 1):
        if lower > upper:
            yield finding(
                "limits-empty",
                spec.name,
                f"axis {axis} of joint '{spec.name}' has lower limit {lower:g} > upper limit "
                f"{upper:g}: its interval is empty, so the C-space is empty",
            )
        elif lower == upper:
            yield finding(
                "joint-locked",
                spec.name,
                f"axis {axis} of joint '{spec.name}' has lower == upper == {lower:g}: it cannot "
                "move, but cspace counts it as an interval (dimension 1) in a joint of "
                "several axes; split the joint to lock that axis",
            )


SENTINEL = 1e4
"""A limit of this magnitude or more (rad or m) stands for 'no limit': 1,592 turns, 10 km."""


def _sentinel(spec: JointSpec, lower: float, upper: float) -> Diagnostic:
    """``limits-sentinel``: a huge limit written for 'no limit'; what it probably meant."""
    if spec.kind in _ROTATIONS:
        meant = (
            f"{(upper - lower) / TWO_PI:,.0f} turns, an interval (R^1); if it turns freely, "
            "say so: a continuous joint (URDF), a hinge without range (MJCF, "
            'limited="false"), no <limit> (SDF), and it is S^1'
        )
        unit = "rad"
    else:
        meant = "an interval (R^1) as long as it says; a slide without limits is R^1 too"
        unit = "m"
    return finding(
        "limits-sentinel",
        spec.name,
        f"joint '{spec.name}' has limits [{lower:g}, {upper:g}] {unit}: a magnitude of "
        f"{SENTINEL:g} or more usually stands for 'no limit'. It is read as {meant}",
    )


def _bound_missing(spec: JointSpec, lower: float, upper: float) -> Diagnostic:
    missing = spec.bounds_missing[0]
    given = upper if missing == "lower" else lower
    hint = f' (for a symmetric range, {missing}="{-given:g}")' if given else ""
    return finding(
        "limit-bound-missing",
        spec.name,
        f"joint '{spec.name}' has a <limit> without {missing}, which URDF reads as 0: "
        f"[{lower:g}, {upper:g}]; write the {missing} bound if 0 is not meant{hint}",
    )


def _not_finite(spec: JointSpec) -> list[str]:
    """``lower limit nan``, ``mimic multiplier inf``, ...: each non-finite number."""
    if spec.mimic is None and all(map(math.isfinite, spec.lower + spec.upper)):
        return []  # the usual joint, without building a label per number
    named = [
        (f"lower limit {k}" if len(spec.lower) > 1 else "lower limit", x)
        for k, x in enumerate(spec.lower)
    ]
    named += [
        (f"upper limit {k}" if len(spec.upper) > 1 else "upper limit", x)
        for k, x in enumerate(spec.upper)
    ]
    if spec.mimic is not None:
        named += [("mimic multiplier", spec.mimic.multiplier), ("mimic offset", spec.mimic.offset)]
    return [f"{label} {value}" for label, value in named if not math.isfinite(value)]


def _no_direction(axis: tuple[float, float, float]) -> str:
    xyz = " ".join(f"{c:g}" for c in axis)
    if all(math.isfinite(c) for c in axis):
        return f"has axis ({xyz}), which is zero: it has no direction"
    return f"has axis ({xyz}), which is not finite: it has no direction"


def _axis_findings(spec: JointSpec) -> Iterator[Diagnostic]:
    name = spec.name
    if spec.kind is JointKind.PLANAR and spec.axis is not None:
        # The plane's normal: it only has to be a direction (Pinocchio ignores it).
        norm = math.hypot(*spec.axis)  # scaled: no overflow or underflow
        if not math.isfinite(norm) or norm == 0.0:
            yield finding(
                "axis-invalid",
                name,
                f"planar joint '{name}' {_no_direction(spec.axis)} (the normal of its plane)",
            )
        return
    if spec.kind not in _ONE_AXIS:
        return
    if spec.axis is None:
        yield finding(
            "axis-default",
            name,
            f"joint '{name}' gives no <axis>: (1, 0, 0) assumed, as URDF specifies",
        )
        return
    norm = math.hypot(*spec.axis)  # scaled: no overflow or underflow
    if not math.isfinite(norm) or norm == 0.0:
        yield finding("axis-invalid", name, f"joint '{name}' {_no_direction(spec.axis)}")
    elif abs(norm - 1.0) > AXIS_TOLERANCE:
        yield finding(
            "axis-normalized",
            name,
            f"joint '{name}' has axis {list(spec.axis)} of length {norm:g}; it is used normalised",
        )


COMMON_DEGREES = frozenset({45, 90, 120, 135, 150, 160, 165, 166, 170, 175, 180, 270, 360})
"""Limits robot makers give in degrees (Panda's 166, a servo's 90 or 180)."""


DEGREES_FROM = 30.0
"""Whole limits from this magnitude up read as degrees (below it, rad such as Solo's +-10,
a multi-turn allowance, are as likely)."""


def _looks_like_degrees(lower: float, upper: float) -> bool:
    """Beyond 2*pi, and a common degree limit or whole numbers of 30 or more: degrees."""
    biggest = max(abs(lower), abs(upper))
    if biggest <= TWO_PI + ANGLE_TOLERANCE or biggest > 720.0:
        return False
    if any(round(abs(x), 3) in COMMON_DEGREES for x in (lower, upper)):
        return True
    return biggest >= DEGREES_FROM and all(float(x).is_integer() for x in (lower, upper))


def _turn_findings(name: str, lower: float, upper: float) -> Iterator[Diagnostic]:
    span = upper - lower
    if _looks_like_degrees(lower, upper):
        in_rad = f"[{math.radians(lower):.4g}, {math.radians(upper):.4g}] rad"
        yield finding(
            "limits-in-degrees",
            name,
            f"revolute joint '{name}' has limits [{lower:g}, {upper:g}], {span / TWO_PI:.1f} "
            f"turns in rad: they look like degrees (in rad: {in_rad}); the file's limits "
            "are read as rad. A true multi-turn joint can --ignore limits-in-degrees",
        )
        return
    if (_close(lower, -math.pi) and _close(upper, math.pi)) or _close(span, TWO_PI):
        yield finding(
            "revolute-ambiguous-range",
            name,
            f"revolute joint '{name}' spans [{lower:g}, {upper:g}], exactly one turn: "
            "an interval here, but the author may have meant continuous (S^1)",
        )
    if span > TWO_PI + ANGLE_TOLERANCE:  # exactly one turn: the warning above says so
        yield finding(
            "multi-turn",
            name,
            f"revolute joint '{name}' spans {span / TWO_PI:.2f} turns; it is still an "
            "interval (R^1): a planner must respect the limits",
        )


def _turns_freely(joint: JointSpec) -> bool:
    """A joint whose angle is a point of S^1: continuous, or an unlimited revolute one.

    An MJCF hinge without a range is such a revolute joint.
    """
    return joint.kind is JointKind.CONTINUOUS or (
        joint.kind is JointKind.REVOLUTE and not joint.lower
    )


def _unwound(spec: JointSpec, leader: JointSpec) -> Iterator[Diagnostic]:
    """``mimic-not-periodic``: a mimic whose value depends on its leader's turns.

    A leader that turns freely is a point of S^1; a turn of it must bring the mimic back
    to the same pose: a rotation by a whole number of turns, so a rotating mimic with a
    whole-number multiplier (or none at all).
    """
    m = spec.mimic.multiplier if spec.mimic is not None else 0.0
    if not (_turns_freely(leader) and math.isfinite(m) and m != 0.0):
        return
    if spec.kind in _ROTATIONS and m == round(m):
        return
    moves = f"{abs(m) * TWO_PI:g} m" if spec.kind not in _ROTATIONS else f"{abs(m):g} of a turn"
    yield finding(
        "mimic-not-periodic",
        spec.name,
        f"mimic joint '{spec.name}' follows '{leader.name}', which turns freely (S^1), "
        f"with multiplier {m:g}: a turn of '{leader.name}' moves '{spec.name}' by "
        f"{moves}, so its value depends on the turns '{leader.name}' made, which the "
        f"angle of S^1 does not keep; limit '{leader.name}'"
        + (", or use a whole-number multiplier" if spec.kind in _ROTATIONS else ""),
    )


def _mimic_findings(spec: JointSpec, leader: JointSpec) -> Iterator[Diagnostic]:
    mimic = spec.mimic
    if mimic is None or len(leader.lower) != 1 or not spec.lower:
        return
    ends = sorted(mimic.multiplier * x + mimic.offset for x in (leader.lower[0], leader.upper[0]))
    if not all(math.isfinite(x) for x in ends):
        return
    lower, upper = spec.lower[0], spec.upper[0]
    slack = 1e-9 * max(1.0, abs(lower), abs(upper))
    if ends[0] < lower - slack or ends[1] > upper + slack:
        yield finding(
            "mimic-limits-contradict",
            spec.name,
            f"mimic joint '{spec.name}' follows '{leader.name}' into "
            f"[{ends[0]:g}, {ends[1]:g}], outside its own limits "
            f"[{lower:g}, {upper:g}]",
        )
