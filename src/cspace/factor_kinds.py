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
space. The factor classes (:mod:`cspace.space.factors`) take their sizes from here, the
coordinates, the layout and the report's dimension too: nothing else states them.
"""

from __future__ import annotations

from enum import Enum
from typing import NamedTuple


class FactorKind(Enum):
    """A kind of factor, with its notation, size, tangent dimension and whether it wraps."""

    LINE = ("R^1", 1, 1, False)
    CIRCLE = ("S^1", 1, 1, True)
    ROTATION = ("RP^3", 4, 3, True)

    def __init__(self, notation: str, size: int, dimension: int, wraps: bool) -> None:
        self.notation = notation
        self.size = size
        self.dimension = dimension
        self.wraps = wraps


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
            angle), ``cos_sin`` (a unit complex number) or ``xyzw`` (a quaternion, w last).
        coordinates: The suffixes of its canonical coordinates, one per coordinate.
    """

    suffix: str
    kind: FactorKind
    lower: float
    upper: float
    unit: str
    encoding: str
    coordinates: tuple[str, ...]
