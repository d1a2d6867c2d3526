"""Where each canonical coordinate comes from: the joints of a report, as factors.

Canonical coordinates, per joint in tree order (fixed, mimic and locked joints have
none): R^1 -> the value; S^1 -> the angle in [-pi, pi); a spherical joint -> (w, x, y, z);
planar -> (x, y, theta); floating -> (x, y, z, w, qx, qy, qz); translation -> (x, y, z);
universal -> its two angles. The layout also says which entries of Pinocchio's q each
factor fills, and which q entries are filled otherwise (locked joints, and mimic joints
that Pinocchio had to keep as free joints: value = multiplier * leader + offset).

Which joint model a joint is never matters here: Pinocchio's sizes (nq, nv) and the
joint's kind decide, so joint-model names stay in :mod:`cspace.kinds`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .factors import Circle, Factor, Line, Rotation
from .kinds import JointKind

if TYPE_CHECKING:
    from .report import JointReport

_AXES = ("x", "y", "z")
_QUATERNION = ("qw", "qx", "qy", "qz")


@dataclass(frozen=True)
class Coordinate:
    """One canonical coordinate.

    Attributes:
        name: ``joint`` for a one-coordinate joint, else ``joint.part`` (``base.qw``).
        joint: The joint it belongs to.
        factor: The factor's space: ``"R^1"``, ``"S^1"`` or ``"RP^3"``.
        unit: ``"m"``, ``"rad"``, or ``"1"`` for quaternion components.
        lower: Lower bound (-inf when none).
        upper: Upper bound (+inf when none).
        wraps: True on S^1 and RP^3 factors, whose coordinates identify points.
        neutral: The coordinate's value in the neutral configuration.
    """

    name: str
    joint: str
    factor: str
    unit: str
    lower: float
    upper: float
    wraps: bool
    neutral: float

    def to_dict(self) -> dict[str, Any]:
        """JSON form; infinite bounds become null."""
        return {
            "name": self.name,
            "joint": self.joint,
            "factor": self.factor,
            "unit": self.unit,
            "lower": self.lower if math.isfinite(self.lower) else None,
            "upper": self.upper if math.isfinite(self.upper) else None,
            "wraps": self.wraps,
        }


@dataclass(frozen=True)
class Slot:
    """One factor of the product, and where it sits.

    Attributes:
        name: The factor's name: the joint's, or ``joint.x`` / ``joint.rotation``.
        joint: The joint.
        factor: The factor.
        offset: Its first canonical coordinate.
        tangent_offset: Its first tangent coordinate.
        q_index: Its first entry in Pinocchio's q.
    """

    name: str
    joint: str
    factor: Factor
    offset: int
    tangent_offset: int
    q_index: int


@dataclass(frozen=True)
class Fill:
    """A q entry (or (cos, sin) pair) that no coordinate gives.

    ``value = multiplier * leader + offset`` (leader None: ``value = offset``).
    """

    joint: str
    q_index: int
    cos_sin: bool
    leader: str | None
    multiplier: float
    offset: float


@dataclass(frozen=True)
class Layout:
    """The coordinates, factors and fills of one robot.

    Attributes:
        coordinates: Every canonical coordinate, in order.
        slots: Every factor, in order.
        fills: Pinocchio q entries set from leaders or locked values.
        joints: The joints with coordinates, in tree order.
        unsupported: (joint, reason) for joints without canonical coordinates.
    """

    coordinates: tuple[Coordinate, ...]
    slots: tuple[Slot, ...]
    fills: tuple[Fill, ...]
    joints: tuple[str, ...]
    unsupported: tuple[tuple[str, str, str], ...]

    @property
    def size(self) -> int:
        """Number of canonical coordinates."""
        return len(self.coordinates)

    @property
    def dimension(self) -> int:
        """Length of a tangent vector."""
        return sum(s.factor.dimension for s in self.slots)


def _bounds(joint: JointReport, i: int) -> tuple[float, float]:
    limits = joint.limits
    if limits is None or len(limits.lower) <= i or len(limits.upper) <= i:
        return -math.inf, math.inf
    lower, upper = limits.lower[i], limits.upper[i]
    return (
        lower if math.isfinite(lower) else -math.inf,
        upper if math.isfinite(upper) else math.inf,
    )


def _line(joint: JointReport, i: int, unit: str) -> Line:
    lower, upper = _bounds(joint, i)
    if joint.limits is not None:
        unit = joint.limits.unit
    return Line(lower, upper, unit)


_ONE_LINE = {
    JointKind.REVOLUTE: "rad",
    JointKind.HELICAL: "rad",
    JointKind.PRISMATIC: "m",
}


def _factors(joint: JointReport) -> list[tuple[str, Factor, tuple[str, ...]]] | str:
    """(factor name suffix, factor, coordinate suffixes) of a joint, or why it has none."""
    kind, nq, nv = joint.kind, joint.nq, joint.nv
    if kind in _ONE_LINE and nq == 1:
        return [("", _line(joint, 0, _ONE_LINE[kind]), ("",))]
    if kind is JointKind.CONTINUOUS and nv == 1:
        return [("", Circle("cos_sin" if nq == 2 else "angle"), ("",))]
    if kind is JointKind.PLANAR and (nq, nv) == (4, 3):
        lines: list[tuple[str, Factor, tuple[str, ...]]] = [
            (a, Line(unit="m"), (a,)) for a in _AXES[:2]
        ]
        return [*lines, ("theta", Circle("cos_sin"), ("theta",))]
    if kind is JointKind.FLOATING and (nq, nv) == (7, 6):
        lines = [(a, Line(unit="m"), (a,)) for a in _AXES]
        return [*lines, ("rotation", Rotation(), _QUATERNION)]
    if kind is JointKind.SPHERICAL and (nq, nv) == (4, 3):
        _, upper = _bounds(joint, 0)  # a limited ball: the largest rotation angle
        return [("", Rotation(min(upper, math.pi)), _QUATERNION)]
    if kind is JointKind.TRANSLATION and nq == 3:
        return [(a, _line(joint, i, "m"), (a,)) for i, a in enumerate(_AXES)]
    if kind is JointKind.UNIVERSAL and nq == 2:
        names = ("axis1", "axis2")
        if joint.space.t == 2:
            return [(n, Circle("angle"), (n,)) for n in names]
        return [(n, _line(joint, i, "rad"), (n,)) for i, n in enumerate(names)]
    if kind is JointKind.SPHERICAL:
        return "Euler-angle (ZYX) coordinates are singular; use a quaternion spherical joint"
    return f"{kind.value} joints with nq={nq}, nv={nv} are not supported"


def _dotted(joint: str, suffix: str) -> str:
    return f"{joint}.{suffix}" if suffix else joint


def _fill(joint: JointReport, q_index: int) -> Fill | None:
    if joint.kind is JointKind.MIMIC and joint.mimic is not None:
        m = joint.mimic
        return Fill(joint.name, q_index, joint.nq == 2, m.joint, m.multiplier, m.offset)
    if joint.space.dimension == 0 and joint.limits is not None and joint.nq == 1:
        return Fill(joint.name, q_index, False, None, 0.0, joint.limits.lower[0])
    return None


def build_layout(joints: tuple[JointReport, ...]) -> Layout:
    """The layout of a robot's joints (as a report lists them, in tree order)."""
    coordinates: list[Coordinate] = []
    slots: list[Slot] = []
    fills: list[Fill] = []
    names: list[str] = []
    unsupported: list[tuple[str, str, str]] = []
    tangent = 0
    for joint in joints:
        if joint.q_index is None or joint.space.dimension == 0 or joint.kind is JointKind.MIMIC:
            fill = None if joint.q_index is None else _fill(joint, joint.q_index)
            if fill is not None:
                fills.append(fill)
            continue
        parts = _factors(joint)
        if isinstance(parts, str):
            unsupported.append((joint.name, joint.pinocchio_model or "", parts))
            continue
        names.append(joint.name)
        q_index = joint.q_index
        for suffix, factor, coordinate_suffixes in parts:
            slots.append(
                Slot(
                    _dotted(joint.name, suffix),
                    joint.name,
                    factor,
                    len(coordinates),
                    tangent,
                    q_index,
                )
            )
            tangent += factor.dimension
            q_index += factor.pinocchio_size
            neutral = factor.neutral()
            for k, c in enumerate(coordinate_suffixes):
                lower, upper = float(factor.lower), float(factor.upper)
                if isinstance(factor, Rotation) and k == 0:
                    lower = math.cos(factor.max_angle / 2.0)
                coordinates.append(
                    Coordinate(
                        name=_dotted(joint.name, c),
                        joint=joint.name,
                        factor=factor.notation,
                        unit=factor.unit,
                        lower=lower,
                        upper=upper,
                        wraps=factor.wraps,
                        neutral=float(neutral[k]),
                    )
                )
    return Layout(tuple(coordinates), tuple(slots), tuple(fills), tuple(names), tuple(unsupported))


def coordinates_section(joints: tuple[JointReport, ...]) -> dict[str, Any]:
    """The report's ``coordinates`` section: each canonical coordinate, and the neutral one."""
    layout = build_layout(joints)
    return {
        "size": layout.size,
        "dimension": layout.dimension,
        "entries": [c.to_dict() for c in layout.coordinates],
        "neutral": [c.neutral for c in layout.coordinates],
    }
