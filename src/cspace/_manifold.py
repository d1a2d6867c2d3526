"""Products of R, S^1 and RP^3 in normal form: ``R^a × T^b × (RP^3)^c``.

A robot's configuration space is the product of its joints' spaces (LaValle, eq. 4.32).
Up to homeomorphism each joint contributes copies of three spaces: the line R (an
interval is homeomorphic to it), the circle S^1 and the rotation group SO(3) = RP^3.
Products of these commute up to homeomorphism, so the whole space is determined by
three counts. SE(2) = R^2 × S^1 and SE(3) = R^3 × RP^3 as topological spaces.
"""

from __future__ import annotations

from dataclasses import dataclass

TIMES = " × "
ASCII_TIMES = " x "


# A frozen dataclass whose constructor, repr, equality, order and hash are written out
# as `dataclass(frozen=True, order=True)` would write them: generated, they are compiled
# at every start, 3 % of what a URDF's `inspect` adds to Pinocchio's own load.
# tests/test_records.py holds it to the dataclass made of the same fields.
@dataclass(frozen=True, init=False, repr=False, eq=False)
class NormalForm:
    """The space ``R^r × T^t × (RP^3)^rp3``.

    Attributes:
        r: Number of R factors (intervals and lines).
        t: Number of S^1 factors (their product is the torus T^t).
        rp3: Number of RP^3 = SO(3) factors.
    """

    r: int = 0
    t: int = 0
    rp3: int = 0

    def __init__(self, r: int = 0, t: int = 0, rp3: int = 0) -> None:
        object.__setattr__(self, "r", r)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "rp3", rp3)
        self.__post_init__()

    def __post_init__(self) -> None:
        if min(self.r, self.t, self.rp3) < 0:
            raise ValueError(f"factor counts must be non-negative, got {self}")

    def __repr__(self) -> str:
        return f"{self.__class__.__qualname__}(r={self.r!r}, t={self.t!r}, rp3={self.rp3!r})"

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return _counts(self) == _counts(other)

    def __hash__(self) -> int:
        return hash(_counts(self))

    def __lt__(self, other: NormalForm) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return _counts(self) < _counts(other)

    def __le__(self, other: NormalForm) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return _counts(self) <= _counts(other)

    def __gt__(self, other: NormalForm) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return _counts(self) > _counts(other)

    def __ge__(self, other: NormalForm) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return _counts(self) >= _counts(other)

    def __mul__(self, other: NormalForm) -> NormalForm:
        """The Cartesian product: counts add."""
        return NormalForm(self.r + other.r, self.t + other.t, self.rp3 + other.rp3)

    @classmethod
    def product(cls, factors: list[NormalForm]) -> NormalForm:
        """The product of any number of spaces (a point when there are none)."""
        r = t = rp3 = 0
        for factor in factors:  # one record at the end: a report multiplies thousands
            r, t, rp3 = r + factor.r, t + factor.t, rp3 + factor.rp3
        return cls(r, t, rp3)

    @property
    def dimension(self) -> int:
        """Dimension as a manifold: r + t + 3 * rp3."""
        return self.r + self.t + 3 * self.rp3

    @property
    def is_point(self) -> bool:
        """True for the zero-dimensional space."""
        return self.dimension == 0

    def _terms(self) -> list[str]:
        terms = []
        if self.r:
            terms.append(f"R^{self.r}")
        if self.t == 1:
            terms.append("S^1")
        elif self.t >= 2:
            terms.append(f"T^{self.t}")
        if self.rp3 == 1:
            terms.append("RP^3")
        elif self.rp3 >= 2:
            terms.append(f"(RP^3)^{self.rp3}")
        return terms

    @property
    def notation(self) -> str:
        """E.g. ``R^8 × T^2 × RP^3``; ``point`` when zero-dimensional."""
        return TIMES.join(self._terms()) or "point"

    @property
    def ascii(self) -> str:
        """The notation with `` x `` for the product sign."""
        return ASCII_TIMES.join(self._terms()) or "point"

    @property
    def fundamental_group(self) -> str:
        """pi_1 = Z^t × (Z/2)^rp3, written like ``Z^2 × Z/2``; ``1`` when trivial."""
        terms = []
        if self.t == 1:
            terms.append("Z")
        elif self.t >= 2:
            terms.append(f"Z^{self.t}")
        if self.rp3 == 1:
            terms.append("Z/2")
        elif self.rp3 >= 2:
            terms.append(f"(Z/2)^{self.rp3}")
        return TIMES.join(terms) or "1"

    @property
    def simply_connected(self) -> bool:
        """True when the fundamental group is trivial (no circles, no rotation groups)."""
        return self.t == 0 and self.rp3 == 0

    def counts(self) -> dict[str, int]:
        """The factor counts as ``{"R": r, "T": t, "RP3": rp3}``."""
        return {"R": self.r, "T": self.t, "RP3": self.rp3}


def _counts(space: NormalForm) -> tuple[int, int, int]:
    return (space.r, space.t, space.rp3)


POINT = NormalForm()
LINE = NormalForm(r=1)
CIRCLE = NormalForm(t=1)
SO3 = NormalForm(rp3=1)
