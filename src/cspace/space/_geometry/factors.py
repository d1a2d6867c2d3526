"""The three factor spaces of a configuration space: R^1, S^1 and SO(3) = RP^3.

Each factor is a small frozen dataclass with the same operations, all batched over
leading axes (a configuration of the factor is the last axis):

- ``size`` canonical coordinates, ``dimension`` tangent coordinates;
- ``canonicalize``, ``distance``, ``difference``/``integrate``, ``interpolate``,
  ``contains``, ``neutral``;
- ``sample`` from a generator, through ``from_uniform``: ``draws`` uniform numbers in
  [0, 1) per configuration mapped onto the factor (see `_Sampled`);
- ``from_pinocchio``/``to_pinocchio`` between the canonical coordinates and the
  factor's entries of Pinocchio's q, and converters whose names say the convention
  (``angle_from_cos_sin``, ``wxyz_from_matrix``, ...).

Canonical coordinates: `Line` the value; `Circle` the angle in
[-pi, pi); `Rotation` a unit quaternion (w, x, y, z) on the upper hemisphere.
Inputs are assumed valid (finite, unit quaternions): `cspace.space` validates,
and the factors call `_rotations` with ``check=False``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar, Literal, TypeVar

import numpy as np

from cspace._factor_kinds import FactorKind
from cspace.space._geometry import rotations as rotations
from cspace.space._geometry.rotations import BoolArray, FloatArray

PI = math.pi
TWO_PI = 2.0 * math.pi


def wrap_angle(theta: FloatArray) -> FloatArray:
    """Angles in rad mapped to [-pi, pi); values already there are returned unchanged.

    ``fmod`` is exact, so even huge angles (1e18) land in [-pi, pi): subtracting a
    rounded multiple of 2*pi would not.
    """
    theta = np.asarray(theta, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        r = np.fmod(theta + PI, TWO_PI)
    r = np.where(r < 0.0, r + TWO_PI, r) - PI
    r = np.where(r >= PI, r - TWO_PI, r)
    inside = (theta >= -PI) & (theta < PI)
    return np.asarray(np.where(inside, theta, r))


def short_way(a: FloatArray, b: FloatArray) -> FloatArray:
    """The signed shortest way from angle a to angle b, in [-pi, pi].

    At a half turn both ways are shortest; the one taken does not depend on the order
    of a and b (from the smaller canonical angle, the positive way), so that the path
    from a to b is the path from b to a, reversed.
    """
    d = wrap_angle(b - a)
    tie = (d == -PI) & (wrap_angle(b) > wrap_angle(a))
    return np.asarray(np.where(tie, PI, d))


def _endpoints(t: FloatArray, a: FloatArray, b: FloatArray, inner: FloatArray) -> FloatArray:
    """``inner``, but exactly ``a`` where t == 0 and exactly ``b`` where t == 1."""
    t = np.asarray(t)[..., None]
    return np.asarray(np.where(t == 0.0, a, np.where(t == 1.0, b, inner)))


FACTOR_CLASSES: dict[FactorKind, type[_Sampled]] = {}
"""The factor class of each kind (`register_factor` fills it)."""

_Class = TypeVar("_Class", bound="type[_Sampled]")


def register_factor(kind: FactorKind) -> Callable[[_Class], _Class]:
    """Make a class the factor of ``kind``, with the kind's sizes (declared only there).

    Sets ``kind``, ``size``, ``dimension``, ``wraps`` and ``notation`` on the class from
    `FactorKind`, as jaxlie's ``register_lie_group`` does.
    """

    def register(cls: _Class) -> _Class:
        cls.kind = kind
        cls.size = kind.size
        cls.dimension = kind.dimension
        cls.wraps = kind.wraps
        cls.notation = kind.notation
        FACTOR_CLASSES[kind] = cls
        return cls

    return register


class _Sampled:
    """Sampling, shared by every factor: uniform numbers drawn row by row, then mapped.

    A factor draws ``draws`` numbers in [0, 1) per configuration with
    ``Generator.random`` and maps them with ``from_uniform``. Drawn for a whole batch at
    once, in row-major order, so the first k configurations of a batch do not depend on
    how many follow (see `cspace.space.ConfigurationSpace.sample`).
    """

    kind: ClassVar[FactorKind]
    size: ClassVar[int]
    dimension: ClassVar[int]
    wraps: ClassVar[bool]
    notation: ClassVar[str]
    draws: ClassVar[int]

    def from_uniform(self, u: FloatArray, bounds: tuple[float, float] | None = None) -> FloatArray:
        """Configurations (..., size) of uniform numbers u (..., draws) in [0, 1)."""
        raise NotImplementedError

    def sample(
        self,
        rng: np.random.Generator,
        shape: tuple[int, ...],
        bounds: tuple[float, float] | None = None,
    ) -> FloatArray:
        """Uniform configurations, shape (*shape, size); see `from_uniform`."""
        return self.from_uniform(rng.random((*shape, self.draws)), bounds)


@register_factor(FactorKind.LINE)
@dataclass(frozen=True)
class Line(_Sampled):
    """R^1: a translation or an angle that does not wrap, an interval when bounded.

    Attributes:
        lower: Lower bound (may be -inf), in ``unit``.
        upper: Upper bound (may be +inf), in ``unit``.
        unit: ``"m"`` or ``"rad"``.
    """

    lower: float = -math.inf
    upper: float = math.inf
    unit: str = "m"

    draws = 1
    pinocchio_size = 1

    @property
    def bounded(self) -> bool:
        """True when both bounds are finite (the factor is an interval)."""
        return math.isfinite(self.lower) and math.isfinite(self.upper)

    def canonicalize(self, x: FloatArray) -> FloatArray:
        """The value itself, shape (..., 1)."""
        return np.array(x, dtype=np.float64)

    def distance(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """|b - a|, shape (...)."""
        return np.asarray(np.abs(b[..., 0] - a[..., 0]))

    def difference(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """The difference b - a, shape (..., 1)."""
        return np.asarray(b - a)

    def integrate(self, a: FloatArray, v: FloatArray) -> FloatArray:
        """The sum a + v, shape (..., 1)."""
        return np.asarray(a + v)

    def interpolate(self, a: FloatArray, b: FloatArray, t: FloatArray) -> FloatArray:
        """(1 - t) a + t b, exact at t = 0 and t = 1; shape (..., 1)."""
        t = np.asarray(t, dtype=np.float64)[..., None]
        return np.asarray((1.0 - t) * a + t * b)

    def from_uniform(self, u: FloatArray, bounds: tuple[float, float] | None = None) -> FloatArray:
        """Uniform in [lower, upper] (or the given finite bounds) from u (..., 1) in [0, 1)."""
        lower, upper = bounds if bounds is not None else (self.lower, self.upper)
        return np.asarray(lower + (upper - lower) * u)

    def contains(self, x: FloatArray, tolerance: float = 0.0) -> BoolArray:
        """Whether lower - tolerance <= x <= upper + tolerance, shape (...)."""
        v = x[..., 0]
        return np.asarray((v >= self.lower - tolerance) & (v <= self.upper + tolerance))

    def neutral(self) -> FloatArray:
        """0, or the bound nearest to 0 when 0 is outside the bounds; shape (1,)."""
        return np.array([min(max(0.0, self.lower), self.upper)])

    def from_pinocchio(self, q: FloatArray) -> FloatArray:
        """Pinocchio stores the value itself."""
        return np.array(q, dtype=np.float64)

    def to_pinocchio(self, x: FloatArray) -> FloatArray:
        """Pinocchio stores the value itself."""
        return np.array(x, dtype=np.float64)


@register_factor(FactorKind.CIRCLE)
@dataclass(frozen=True)
class Circle(_Sampled):
    """S^1: an angle that wraps, canonical in [-pi, pi) rad.

    Attributes:
        pinocchio: How Pinocchio's q stores it: ``"cos_sin"`` (unbounded revolute,
            planar) or ``"angle"`` (a revolute joint model without finite limits).
    """

    pinocchio: Literal["cos_sin", "angle"] = "cos_sin"

    draws = 1
    unit = "rad"
    lower = -PI
    upper = PI

    @property
    def pinocchio_size(self) -> int:
        """Entries in Pinocchio's q: 2 for (cos, sin), 1 for an angle."""
        return 2 if self.pinocchio == "cos_sin" else 1

    def canonicalize(self, x: FloatArray) -> FloatArray:
        """The angle in [-pi, pi), shape (..., 1)."""
        return wrap_angle(x)

    def distance(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """The shortest way round, in [0, pi], shape (...)."""
        return np.asarray(np.abs(wrap_angle(b[..., 0] - a[..., 0])))

    def difference(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """The signed shortest way from a to b (see `short_way`), shape (..., 1)."""
        return short_way(a, b)

    def integrate(self, a: FloatArray, v: FloatArray) -> FloatArray:
        """The sum a + v wrapped to [-pi, pi), shape (..., 1)."""
        return wrap_angle(a + v)

    def interpolate(self, a: FloatArray, b: FloatArray, t: FloatArray) -> FloatArray:
        """Along the shortest way, crossing pi ~ -pi when shorter; canonical (..., 1)."""
        a, b = wrap_angle(a), wrap_angle(b)
        t = np.asarray(t, dtype=np.float64)
        inner = wrap_angle(a + t[..., None] * short_way(a, b))
        return _endpoints(t, a, b, inner)

    def from_uniform(self, u: FloatArray, bounds: tuple[float, float] | None = None) -> FloatArray:
        """Uniform on the circle (or in the given bounds, wrapped) from u (..., 1) in [0, 1)."""
        lower, upper = bounds if bounds is not None else (-PI, PI)
        return wrap_angle(lower + (upper - lower) * u)

    def contains(self, x: FloatArray, tolerance: float = 0.0) -> BoolArray:
        """Every angle is a point of the circle: all True, shape (...)."""
        return np.ones(x.shape[:-1], dtype=bool)

    def neutral(self) -> FloatArray:
        """Angle 0, shape (1,)."""
        return np.zeros(1)

    @staticmethod
    def angle_from_cos_sin(cs: FloatArray) -> FloatArray:
        """(cos, sin), shape (..., 2), to the angle in [-pi, pi), shape (..., 1)."""
        return wrap_angle(np.arctan2(cs[..., 1:2], cs[..., 0:1]))

    @staticmethod
    def cos_sin_from_angle(theta: FloatArray) -> FloatArray:
        """The angle, shape (..., 1), to (cos, sin), shape (..., 2)."""
        return np.concatenate((np.cos(theta), np.sin(theta)), axis=-1)

    @staticmethod
    def matrix_from_angle(theta: FloatArray) -> FloatArray:
        """SO(2) matrices [[cos, -sin], [sin, cos]], shape (..., 2, 2), of angles (..., 1)."""
        c, s = np.cos(theta[..., 0]), np.sin(theta[..., 0])
        return np.stack((np.stack((c, -s), axis=-1), np.stack((s, c), axis=-1)), axis=-2)

    @staticmethod
    def angle_from_matrix(r: FloatArray) -> FloatArray:
        """SO(2) matrices, shape (..., 2, 2), to angles in [-pi, pi), shape (..., 1)."""
        return wrap_angle(np.arctan2(r[..., 1, 0], r[..., 0, 0])[..., None])

    def from_pinocchio(self, q: FloatArray) -> FloatArray:
        """Pinocchio's (cos, sin) or angle, to the canonical angle."""
        if self.pinocchio == "cos_sin":
            return self.angle_from_cos_sin(q)
        return wrap_angle(q)

    def to_pinocchio(self, x: FloatArray) -> FloatArray:
        """The angle, to Pinocchio's (cos, sin) or angle."""
        if self.pinocchio == "cos_sin":
            return self.cos_sin_from_angle(x)
        return np.array(x, dtype=np.float64)


@register_factor(FactorKind.ROTATION)
@dataclass(frozen=True)
class Rotation(_Sampled):
    """SO(3) = RP^3: a unit quaternion (w, x, y, z) on the upper hemisphere.

    Distances are rotation angles in [0, pi] rad; the tangent is the rotation vector of
    a^-1 b in the frame of a (as Pinocchio's ``log3(Ra^T Rb)``).

    Attributes:
        max_angle: The largest rotation angle from the identity, rad (a limited ball
            joint: the space is then a 3-ball); pi for the whole of SO(3).
    """

    max_angle: float = PI

    draws = 3
    unit = "1"
    pinocchio_size = 4
    lower = -1.0
    upper = 1.0

    def canonicalize(self, x: FloatArray) -> FloatArray:
        """Normalized, on the upper hemisphere; h and -h give bit-identical output."""
        return rotations.canonicalize(x, check=False)

    def distance(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """Rotation angle between a and b, in [0, pi], shape (...)."""
        return rotations.angle_between(a, b, check=False)

    def difference(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """log(a^-1 b), shape (..., 3), norm in [0, pi]."""
        inverse = rotations.conjugate(a, check=False)
        return rotations.log(rotations.multiply(inverse, b, check=False), check=False)

    def integrate(self, a: FloatArray, v: FloatArray) -> FloatArray:
        """The product a exp(v), canonical, shape (..., 4)."""
        step = rotations.exp(v, check=False)
        return rotations.canonicalize(rotations.multiply(a, step, check=False), check=False)

    def interpolate(self, a: FloatArray, b: FloatArray, t: FloatArray) -> FloatArray:
        """Slerp along the shorter arc; canonical, exact endpoints; shape (..., 4)."""
        a, b = rotations.canonicalize(a, check=False), rotations.canonicalize(b, check=False)
        t = np.asarray(t, dtype=np.float64)
        return _endpoints(t, a, b, rotations.slerp(a, b, t, check=False))

    def from_uniform(self, u: FloatArray, bounds: tuple[float, float] | None = None) -> FloatArray:
        """Uniform (Haar) rotations within ``max_angle`` of the identity; (..., 3) -> (..., 4).

        The whole of SO(3): Shoemake's map of three uniform numbers in [0, 1) onto the
        unit sphere of R^4. A ball of rotations: the angle by inverting its distribution
        function (theta - sin theta) / (M - sin M), M the largest angle, about an axis
        uniform on the sphere. ``bounds`` is ignored.
        """
        if self.max_angle >= PI:
            r1, r2 = np.sqrt(1.0 - u[..., 0]), np.sqrt(u[..., 0])
            a1, a2 = TWO_PI * u[..., 1], TWO_PI * u[..., 2]
            h = np.stack((r2 * np.cos(a2), r1 * np.sin(a1), r1 * np.cos(a1), r2 * np.sin(a2)), -1)
            return rotations.canonicalize(h, check=False)
        m = self.max_angle
        target = u[..., 0] * (m - math.sin(m))
        theta = np.cbrt(6.0 * target)  # theta - sin theta ~ theta^3 / 6 near 0
        for _ in range(30):  # Newton on a convex increasing function: monotone
            slope = np.maximum(1.0 - np.cos(theta), 1e-300)
            theta = np.clip(theta - (theta - np.sin(theta) - target) / slope, 0.0, m)
        z = 1.0 - 2.0 * u[..., 1]
        ring, phi = np.sqrt(np.maximum(1.0 - z * z, 0.0)), TWO_PI * u[..., 2]
        axis = np.stack((ring * np.cos(phi), ring * np.sin(phi), z), axis=-1)
        return rotations.canonicalize(
            rotations.exp(axis * theta[..., None], check=False), check=False
        )

    def contains(self, x: FloatArray, tolerance: float = 0.0) -> BoolArray:
        """Whether the rotation angle from the identity is <= max_angle + tolerance."""
        if self.max_angle >= PI:
            return np.ones(x.shape[:-1], dtype=bool)
        angle = 2.0 * np.arctan2(np.linalg.norm(x[..., 1:], axis=-1), np.abs(x[..., 0]))
        return np.asarray(angle <= self.max_angle + tolerance)

    def neutral(self) -> FloatArray:
        """The identity (1, 0, 0, 0)."""
        return np.array([1.0, 0.0, 0.0, 0.0])

    @staticmethod
    def wxyz_from_matrix(r: FloatArray) -> FloatArray:
        """Rotation matrices (..., 3, 3) to canonical quaternions (w, x, y, z), (..., 4)."""
        return rotations.quaternion_from_matrix(r)  # checks the matrices

    @staticmethod
    def matrix_from_wxyz(h: FloatArray) -> FloatArray:
        """Quaternions (w, x, y, z), (..., 4), to rotation matrices (..., 3, 3)."""
        return rotations.matrix_from_quaternion(h, check=False)

    def from_pinocchio(self, q: FloatArray) -> FloatArray:
        """Pinocchio's (x, y, z, w) to canonical (w, x, y, z)."""
        return rotations.canonicalize(rotations.wxyz_from_xyzw(q, check=False), check=False)

    def to_pinocchio(self, x: FloatArray) -> FloatArray:
        """Canonical (w, x, y, z) to Pinocchio's (x, y, z, w)."""
        return rotations.xyzw_from_wxyz(x, check=False)


Factor = Line | Circle | Rotation
"""Any factor."""


def unit(f: Factor, block: FloatArray) -> FloatArray:
    """A factor's block of validated coordinates, quaternions normalized."""
    if isinstance(f, Rotation):
        return np.asarray(block / np.linalg.norm(block, axis=-1, keepdims=True))
    return block
