"""Each joint's canonical coordinates: names, factors, units, bounds; no NumPy needed.

Canonical coordinates, per joint in tree order (fixed, mimic and locked joints have
none): R^1 -> the value; S^1 -> the angle in [-pi, pi); a spherical joint ->
(qw, qx, qy, qz); planar -> (x, y, theta); floating -> (x, y, z, qw, qx, qy, qz);
translation -> (x, y, z); universal -> (axis1, axis2). The analysis gives each report
its coordinates from here; :mod:`cspace.space.layout` turns the same factor
specifications into the factor objects that compute.

Which joint model a joint is never matters here: Pinocchio's sizes (nq, nv) and the
joint's kind decide, so joint-model names stay in :mod:`cspace.model.kinds`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from cspace.factor_kinds import Coordinate, Coordinates, FactorKind, FactorSpec
from cspace.joint_kind import JointKind

if TYPE_CHECKING:
    from cspace.reports.report import JointReport


_AXES = ("x", "y", "z")
_QUATERNION = ("qw", "qx", "qy", "qz")
_ONE_LINE = {JointKind.REVOLUTE: "rad", JointKind.HELICAL: "rad", JointKind.PRISMATIC: "m"}


def has_coordinates(joint: JointReport) -> bool:
    """False for fixed, mimic and locked joints."""
    return (
        joint.q_index is not None
        and joint.space.dimension > 0
        and joint.kind is not JointKind.MIMIC
    )


def dotted(joint: str, suffix: str) -> str:
    """``joint.suffix``, or the joint's name for an empty suffix."""
    return f"{joint}.{suffix}" if suffix else joint


def _bounds(joint: JointReport, i: int) -> tuple[float, float]:
    limits = joint.limits
    if limits is None or len(limits.lower) <= i or len(limits.upper) <= i:
        return -math.inf, math.inf
    lower, upper = limits.lower[i], limits.upper[i]
    return (
        lower if math.isfinite(lower) else -math.inf,
        upper if math.isfinite(upper) else math.inf,
    )


def _line(joint: JointReport, i: int, suffix: str, unit: str) -> FactorSpec:
    lower, upper = _bounds(joint, i)
    unit = joint.limits.unit if joint.limits is not None else unit
    return FactorSpec(suffix, FactorKind.LINE, lower, upper, unit, "value", (suffix,))


def _circle(suffix: str, encoding: str) -> FactorSpec:
    return FactorSpec(suffix, FactorKind.CIRCLE, -math.pi, math.pi, "rad", encoding, (suffix,))


def _rotation(suffix: str, largest: float) -> FactorSpec:
    return FactorSpec(suffix, FactorKind.ROTATION, 0.0, largest, "1", "xyzw", _QUATERNION)


def factor_specs(joint: JointReport) -> list[FactorSpec] | str:
    """The factors of a joint with coordinates, or why it has no canonical coordinates."""
    kind, nq, nv = joint.kind, joint.nq, joint.nv
    if kind in _ONE_LINE and nq == 1:
        return [_line(joint, 0, "", _ONE_LINE[kind])]
    if kind is JointKind.CONTINUOUS and nv == 1:
        return [_circle("", "cos_sin" if nq == 2 else "angle")]
    free = [FactorSpec(a, FactorKind.LINE, -math.inf, math.inf, "m", "value", (a,)) for a in _AXES]
    if kind is JointKind.PLANAR and (nq, nv) == (4, 3):
        return [*free[:2], _circle("theta", "cos_sin")]
    if kind is JointKind.FLOATING and (nq, nv) == (7, 6):
        return [*free, _rotation("rotation", math.pi)]
    if kind is JointKind.SPHERICAL and (nq, nv) == (4, 3):
        largest = min(_bounds(joint, 0)[1], math.pi)  # a limited ball: its largest angle
        return [_rotation("", largest)]
    if kind is JointKind.TRANSLATION and nq == 3:
        return [_line(joint, i, a, "m") for i, a in enumerate(_AXES)]
    if kind is JointKind.UNIVERSAL and nq == 2:
        names = ("axis1", "axis2")
        if joint.space.t == 2:
            return [_circle(n, "angle") for n in names]
        return [_line(joint, i, n, "rad") for i, n in enumerate(names)]
    if kind is JointKind.SPHERICAL:
        return "Euler-angle (ZYX) coordinates are singular; use a quaternion spherical joint"
    return f"{kind.value} joints with nq={nq}, nv={nv} are not supported"


def coordinates_of(joint: str, spec: FactorSpec) -> list[Coordinate]:
    """The canonical coordinates of one factor of a joint."""
    kind, lower, upper, unit, suffixes = (
        spec.kind,
        spec.lower,
        spec.upper,
        spec.unit,
        spec.coordinates,
    )
    space = kind.notation
    if kind is FactorKind.ROTATION:  # on the upper hemisphere, within the largest angle
        # cos(pi / 2) is 6e-17 in floating point: the whole hemisphere starts at exactly 0.
        qw_lower = 0.0 if upper >= math.pi else math.cos(upper / 2.0)
        bounds = [(qw_lower, 1.0)] + [(-1.0, 1.0)] * 3
        return [
            Coordinate(dotted(joint, s), joint, space, unit, lo, hi, True, float(k == 0))
            for k, (s, (lo, hi)) in enumerate(zip(suffixes, bounds, strict=True))
        ]
    neutral = min(max(0.0, lower), upper)  # 0, or the bound nearest to it
    return [
        Coordinate(
            dotted(joint, suffixes[0]), joint, space, unit, lower, upper, kind.wraps, neutral
        )
    ]


def canonical_coordinates(joints: tuple[JointReport, ...]) -> Coordinates:
    """Each canonical coordinate of a robot's joints (in tree order), and the dimension."""
    entries: list[Coordinate] = []
    dimension = 0
    for joint in joints:
        specs = factor_specs(joint) if has_coordinates(joint) else []
        for spec in specs if isinstance(specs, list) else []:
            entries.extend(coordinates_of(joint.name, spec))
            dimension += spec.kind.dimension
    return Coordinates(tuple(entries), dimension)
