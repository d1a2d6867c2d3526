"""The factors of a configuration space, each kind with its sizes declared once.

A joint's configuration space is a product of factors; each factor is of one kind:

============  ========  ====  =========  =====  ===========================================
kind          notation  size  dimension  wraps  canonical coordinates
============  ========  ====  =========  =====  ===========================================
``LINE``      ``R^1``   1     1          no     a length or an angle, within [lower, upper]
``CIRCLE``    ``S^1``   1     1          yes    an angle in [-pi, pi)
``ROTATION``  ``RP^3``  4     3          yes    a unit quaternion (w, x, y, z), w >= 0
============  ========  ====  =========  =====  ===========================================

``size`` is the number of canonical coordinates, ``dimension`` that of the tangent
space. Up to homeomorphism a factor is R, S^1 or RP^3 (`FactorSpec.space`): an
interval is R, and a rotation factor whose largest angle is below pi (a limited ball
joint) is a 3-ball, R^3. The factor classes (`_factors`) take their
sizes from here, the coordinates, the layout and the report's dimension too: nothing
else states them.
"""

import math
from collections.abc import Mapping
from enum import Enum
from typing import Any

from cspace._manifold import CIRCLE as _CIRCLE
from cspace._manifold import LINE as _LINE
from cspace._manifold import SO3 as _SO3
from cspace._manifold import NormalForm
from cspace._record import NamedTuple


class FactorKind(Enum):
    """A kind of factor, with its notation, size, tangent dimension and whether it wraps."""

    LINE = ("R^1", 1, 1, False, _LINE)
    CIRCLE = ("S^1", 1, 1, True, _CIRCLE)
    ROTATION = ("RP^3", 4, 3, True, _SO3)

    def __init__(
        self, notation: str, size: int, dimension: int, wraps: bool, space: NormalForm
    ) -> None:
        self.notation = notation
        self.size = size
        self.dimension = dimension
        self.wraps = wraps
        self.space = space


class FactorSpec(NamedTuple):
    """One factor of a joint, as the joint table gives it.

    Attributes:
        suffix: The factor's name within the joint (``""`` for a one-factor joint, ``x``,
            ``theta``, ``rotation``, ``axis1``, ...).
        kind: Its kind.
        lower: Lower bound (rad or m; -inf when none). For a rotation, 0.
        upper: Upper bound (+inf when none). For a rotation, its largest angle (pi for
            the whole of SO(3), less for a limited ball joint).
        unit: ``"m"``, ``"rad"``, or ``"1"`` for quaternion components.
        encoding: How Pinocchio's q stores it: ``value`` (as it is), ``angle`` (one
            angle), ``cos_sin`` (a unit complex number), ``xyzw`` (a quaternion, w last)
            or ``euler_zyx`` (Euler angles, which cspace does not compute with).
        coordinates: The suffixes of its canonical coordinates, one per coordinate.
    """

    suffix: str
    kind: FactorKind
    lower: float
    upper: float
    unit: str
    encoding: str
    coordinates: tuple[str, ...]

    @property
    def space(self) -> NormalForm:
        """The factor up to homeomorphism.

        A rotation factor whose largest angle is below pi is a 3-ball (R^3); any other
        factor is its kind's space.
        """
        if self.kind is FactorKind.ROTATION and self.upper < math.pi:
            return NormalForm(r=3)
        return self.kind.space


class Coordinate(NamedTuple):
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

    @classmethod
    def from_dict(cls, document: Mapping[str, Any], neutral: float) -> "Coordinate":
        """The coordinate of a JSON entry (null bounds are infinite), with its neutral value."""
        lower, upper = document["lower"], document["upper"]
        return cls(
            name=str(document["name"]),
            joint=str(document["joint"]),
            factor=str(document["factor"]),
            unit=str(document["unit"]),
            lower=-math.inf if lower is None else float(lower),
            upper=math.inf if upper is None else float(upper),
            wraps=bool(document["wraps"]),
            neutral=float(neutral),
        )


class Coordinates(NamedTuple):
    """A robot's canonical coordinates: the report's ``coordinates`` section.

    Attributes:
        entries: Each canonical coordinate, joints in tree order.
        dimension: The dimension of the space they describe (a quaternion's four
            coordinates count three).
    """

    entries: tuple[Coordinate, ...] = ()
    dimension: int = 0

    def to_dict(self) -> dict[str, Any]:
        """The JSON section: size, dimension, entries and the neutral configuration."""
        return {
            "size": len(self.entries),
            "dimension": self.dimension,
            "entries": [c.to_dict() for c in self.entries],
            "neutral": [c.neutral for c in self.entries],
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Coordinates":
        """The section of a JSON report."""
        neutral = document["neutral"]
        entries = tuple(
            Coordinate.from_dict(e, n) for e, n in zip(document["entries"], neutral, strict=True)
        )
        return cls(entries, int(document["dimension"]))
