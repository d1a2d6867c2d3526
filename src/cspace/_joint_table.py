"""The one joint table: what each joint is, and the factors its space is made of.

Each joint contributes a space to the product (``docs/cspace-math.md``, section 1): a
limited revolute joint an interval (homeomorphic to R), an unlimited one the circle S^1,
a prismatic or helical joint R, a planar joint SE(2) = R^2 × S^1, a spherical joint
SO(3) = RP^3 (a 3-ball, homeomorphic to R^3, when its rotation is limited), a floating
joint SE(3) = R^3 × RP^3, a universal joint T^2 (R^2 when limited); fixed, mimic and
locked joints a point.

`JOINT_TABLE` holds, for each `JointKind`, the Pinocchio
joint models of that kind and how a joint of it is split into factors
(`FactorSpec`). Everything else is derived from the factors:
the joint's space (the product of its factors' spaces), the report's normal form,
dimension and canonical coordinates, and the layout `_layout` computes
with. Nothing else names a Pinocchio joint model or decides a factor.

Canonical coordinates, per joint in tree order: R^1 -> the value; S^1 -> the angle in
[-pi, pi); a spherical joint -> (qw, qx, qy, qz); planar -> (x, y, theta); floating ->
(x, y, z, qw, qx, qy, qz); translation -> (x, y, z); universal -> (axis1, axis2).
"""

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from cspace._factor_kinds import Coordinate, Coordinates, FactorKind, FactorSpec
from cspace._joint_kind import JointKind
from cspace._manifold import NormalForm
from cspace._record import NamedTuple

if TYPE_CHECKING:
    from cspace._joint_report import JointReport, Limits


class JointFactors(NamedTuple):
    """The factors of one joint.

    Attributes:
        factors: Its factors, in coordinate order (none for a point).
        unsupported: Why cspace cannot compute with its coordinates (Euler angles), or
            None. The factors still give its space.
    """

    factors: tuple[FactorSpec, ...] = ()
    unsupported: str | None = None

    @property
    def space(self) -> NormalForm:
        """The joint's space: the product of its factors' spaces."""
        if len(self.factors) == 1:
            return self.factors[0].space
        return NormalForm.product([f.space for f in self.factors])


Build = Callable[[int, int, "Limits | None"], "JointFactors | None"]
"""(nq, nv, limits) -> the factors, or None when Pinocchio's sizes are not the kind's."""


class JointRow(NamedTuple):
    """One kind of joint in the table.

    Attributes:
        models: The Pinocchio joint models (``shortname()``) of this kind.
        build: Its factors from Pinocchio's (nq, nv) and the limits the report keeps.
        when_unlimited: The kind a joint of these models is when the file does not bound
            it (a revolute joint without finite limits is continuous), or None.
    """

    models: tuple[str, ...]
    build: Build
    when_unlimited: JointKind | None = None


EULER_MODELS = frozenset({"JointModelSphericalZYX"})
"""Joint models Pinocchio keeps in Euler-angle coordinates (singular at some orientations)."""

_AXES = ("x", "y", "z")
_QUATERNION = ("qw", "qx", "qy", "qz")


def bounded(limits: "Limits | None") -> bool:
    """True when limits are given, as many lower as upper bounds, and all are finite."""
    return (
        limits is not None
        and bool(limits.lower)
        and len(limits.lower) == len(limits.upper)
        and all(map(math.isfinite, limits.lower))
        and all(map(math.isfinite, limits.upper))
    )


def _bounds(limits: "Limits | None", i: int) -> tuple[float, float]:
    if limits is None or len(limits.lower) <= i or len(limits.upper) <= i:
        return -math.inf, math.inf
    lower, upper = limits.lower[i], limits.upper[i]
    return (
        lower if math.isfinite(lower) else -math.inf,
        upper if math.isfinite(upper) else math.inf,
    )


def _line(limits: "Limits | None", i: int, suffix: str, unit: str) -> FactorSpec:
    lower, upper = _bounds(limits, i)
    unit = limits.unit if limits is not None else unit
    return FactorSpec(suffix, FactorKind.LINE, lower, upper, unit, "value", (suffix,))


def _free(axis: str) -> FactorSpec:
    return FactorSpec(axis, FactorKind.LINE, -math.inf, math.inf, "m", "value", (axis,))


def _circle(suffix: str, encoding: str) -> FactorSpec:
    return FactorSpec(suffix, FactorKind.CIRCLE, -math.pi, math.pi, "rad", encoding, (suffix,))


def _rotation(suffix: str, largest: float, encoding: str = "xyzw") -> FactorSpec:
    return FactorSpec(suffix, FactorKind.ROTATION, 0.0, largest, "1", encoding, _QUATERNION)


def _of(*factors: FactorSpec) -> JointFactors:
    return JointFactors(factors)


def _one_line(unit: str) -> Build:
    def build(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
        return _of(_line(limits, 0, "", unit)) if (nq, nv) == (1, 1) else None

    return build


def _continuous(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
    # Pinocchio stores an unbounded revolute joint as (cos, sin); MuJoCo's hinge as one angle.
    if nv != 1 or nq not in (1, 2):
        return None
    return _of(_circle("", "cos_sin" if nq == 2 else "angle"))


def _planar(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
    # URDF's planar <limit> is not a rotation limit: always SE(2).
    return _of(_free("x"), _free("y"), _circle("theta", "cos_sin")) if (nq, nv) == (4, 3) else None


def _floating(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
    if (nq, nv) != (7, 6):
        return None
    return _of(*(_free(a) for a in _AXES), _rotation("rotation", math.pi))


def _spherical(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
    # A ball's range is its largest rotation angle; from pi on it excludes nothing.
    largest = min(_bounds(limits, 0)[1], math.pi)
    if (nq, nv) == (4, 3) and limits is not None and len(limits.upper) == 2:
        return _cone(limits)
    if (nq, nv) == (4, 3):
        return _of(_rotation("", largest))
    if (nq, nv) == (3, 3):
        reason = "Euler-angle (ZYX) coordinates are singular; use a quaternion spherical joint"
        return JointFactors((_rotation("", largest, "euler_zyx"),), reason)
    return None


def _cone(limits: "Limits") -> JointFactors:
    """A ball whose swing is limited by a cone (OpenUSD's, PhysX's) and whose twist is free.

    The rotations that keep the joint's axis within a cone of half-angles below pi are
    a disk of axis directions times a circle of twists: R^2 × S^1 (an angle of 0 locks
    that swing). cspace does not compute with swing and twist coordinates yet.
    """
    names = [f"swing{i + 1}" for i in range(len(limits.upper))]
    swings = [
        FactorSpec(name, FactorKind.LINE, -upper, upper, "rad", "swing_twist", (name,))
        for name, upper in zip(names, limits.upper, strict=True)
        if upper > 0.0
    ]
    twist = _circle("twist", "swing_twist")
    reason = "a cone-limited ball's swing and twist are coordinates cspace does not compute with"
    return JointFactors((*swings, twist), reason)


def _translation(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
    if (nq, nv) != (3, 3):
        return None
    return _of(*(_line(limits, i, a, "m") for i, a in enumerate(_AXES)))


def _universal(nq: int, nv: int, limits: "Limits | None") -> JointFactors | None:
    if (nq, nv) != (2, 2):
        return None
    names = ("axis1", "axis2")
    if bounded(limits):
        return _of(*(_line(limits, i, n, "rad") for i, n in enumerate(names)))
    return _of(*(_circle(n, "angle") for n in names))


def _point(nq: int, nv: int, limits: "Limits | None") -> JointFactors:
    return JointFactors()


def _axes(prefix: str, unaligned: str) -> tuple[str, ...]:
    return (*(f"JointModel{prefix}{a}" for a in "XYZ"), f"JointModel{unaligned}")


JOINT_TABLE: dict[JointKind, JointRow] = {
    JointKind.REVOLUTE: JointRow(
        _axes("R", "RevoluteUnaligned"), _one_line("rad"), when_unlimited=JointKind.CONTINUOUS
    ),
    JointKind.CONTINUOUS: JointRow(_axes("RUB", "RevoluteUnboundedUnaligned"), _continuous),
    JointKind.PRISMATIC: JointRow(_axes("P", "PrismaticUnaligned"), _one_line("m")),
    JointKind.HELICAL: JointRow(_axes("H", "HelicalUnaligned"), _one_line("rad")),
    JointKind.PLANAR: JointRow(("JointModelPlanar",), _planar),
    JointKind.SPHERICAL: JointRow(("JointModelSpherical", *EULER_MODELS), _spherical),
    JointKind.FLOATING: JointRow(("JointModelFreeFlyer",), _floating),
    JointKind.TRANSLATION: JointRow(("JointModelTranslation",), _translation),
    JointKind.UNIVERSAL: JointRow(("JointModelUniversal",), _universal),
    JointKind.MIMIC: JointRow(("JointModelMimic",), _point),
    JointKind.FIXED: JointRow((), _point),  # a frame in Pinocchio, not a joint
}
"""Each joint kind: its Pinocchio joint models and its factors. The only place either is
stated."""

KIND_OF_MODEL: dict[str, JointKind] = {
    model: kind for kind, row in JOINT_TABLE.items() for model in row.models
}
"""Pinocchio ``shortname()`` -> the kind of a joint of that model when the file bounds it."""


def kind_of(model: str, limits: "Limits | None") -> JointKind | None:
    """The kind of a joint of a Pinocchio joint model, or None for a model not in the table.

    Args:
        model: Pinocchio's ``shortname()`` of the joint model.
        limits: The limits the report keeps for the joint (None for none).
    """
    kind = KIND_OF_MODEL.get(model)
    if kind is None:
        return None
    unlimited = JOINT_TABLE[kind].when_unlimited
    return unlimited if unlimited is not None and not bounded(limits) else kind


def locked(limits: "Limits | None") -> bool:
    """True when one finite bound pair has lower == upper: the joint cannot move."""
    return (
        limits is not None
        and len(limits.lower) == 1
        and limits.lower == limits.upper
        and math.isfinite(limits.lower[0])
    )


def factors_of(kind: JointKind, nq: int, nv: int, limits: "Limits | None") -> JointFactors:
    """A joint's factors, from its kind, Pinocchio's sizes and its limits.

    Args:
        kind: The joint's kind.
        nq: Its entries in Pinocchio's q (0 for a joint without coordinates there).
        nv: Its entries in Pinocchio's v.
        limits: The limits the report keeps for it (None for none).

    Returns:
        The factors (none for fixed, mimic and locked joints); for sizes the kind does
        not have, no factors and the reason.
    """
    if kind in (JointKind.FIXED, JointKind.MIMIC) or locked(limits):
        return JointFactors()
    factors = JOINT_TABLE[kind].build(nq, nv, limits)
    if factors is None:
        return JointFactors((), f"{kind.value} joints with nq={nq}, nv={nv} are not supported")
    return factors


def joint_factors(joint: "JointReport") -> JointFactors:
    """The factors of a reported joint (none when it has no entries in Pinocchio's q)."""
    if joint.q_index is None:
        return JointFactors()
    return factors_of(joint.kind, joint.nq, joint.nv, joint.limits)


def dotted(joint: str, suffix: str) -> str:
    """``joint.suffix``, or the joint's name for an empty suffix."""
    return f"{joint}.{suffix}" if suffix else joint


def coordinates_of(joint: str, spec: FactorSpec) -> list[Coordinate]:
    """The canonical coordinates of one factor of a joint."""
    kind, lower, upper, unit = spec.kind, spec.lower, spec.upper, spec.unit
    space = kind.notation
    if kind is FactorKind.ROTATION:  # on the upper hemisphere, within the largest angle
        # cos(pi / 2) is 6e-17 in floating point: the whole hemisphere starts at exactly 0.
        qw_lower = 0.0 if upper >= math.pi else math.cos(upper / 2.0)
        bounds = [(qw_lower, 1.0)] + [(-1.0, 1.0)] * 3
        return [
            Coordinate(dotted(joint, s), joint, space, unit, lo, hi, True, float(k == 0))
            for k, (s, (lo, hi)) in enumerate(zip(spec.coordinates, bounds, strict=True))
        ]
    neutral = min(max(0.0, lower), upper)  # 0, or the bound nearest to it
    name = dotted(joint, spec.coordinates[0])
    return [Coordinate(name, joint, space, unit, lower, upper, kind.wraps, neutral)]


def canonical_coordinates(
    joints: "tuple[JointReport, ...]", factors: Sequence[JointFactors] | None = None
) -> Coordinates:
    """Each canonical coordinate of a robot's joints (in tree order), and the dimension.

    Args:
        joints: The reported joints.
        factors: Each joint's factors, when the caller has them already (the analysis);
            by default they are found from the table.
    """
    entries: list[Coordinate] = []
    dimension = 0
    found_all = factors if factors is not None else [joint_factors(j) for j in joints]
    for joint, found in zip(joints, found_all, strict=True):
        for spec in found.factors if found.unsupported is None else ():
            entries.extend(coordinates_of(joint.name, spec))
            dimension += spec.kind.dimension
    return Coordinates(tuple(entries), dimension)
