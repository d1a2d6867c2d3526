"""Rotations of SO(3) as unit quaternions, batched over leading axes.

Conventions (see ``docs/cspace-math.md`` section 3):

- A quaternion is an array of shape ``(..., 4)`` in **(w, x, y, z)** order, the order
  of LaValle's text (a, b, c, d). Pinocchio's q stores (x, y, z, w); convert with
  `wxyz_from_xyzw` and `xyzw_from_wxyz`.
- h and -h are the same rotation (SO(3) = RP^3). The canonical representative lies on
  the upper hemisphere: w > 0; or w = 0 and x > 0; or w = x = 0 and y > 0; or
  w = x = y = 0 and z = 1. `canonicalize` maps h and -h to bit-identical output.
- A rotation matrix is an array of shape ``(..., 3, 3)`` acting on column vectors.
- A rotation vector (tangent) is an array of shape ``(..., 3)``: axis times angle, rad.

Every function checks its input (``check=False`` skips it, for callers that have
validated once, such as `_factors`): arrays of real numbers of the right
shape, finite, quaternions unit within `UNIT_TOLERANCE`, batches that broadcast,
results within `MAX_ARRAY_BYTES`. A bad input raises a
`ConfigurationError` subclass (a zero quaternion:
`NotUnitQuaternionError`), never NaN output.
"""

from __future__ import annotations

import numpy as np

from cspace._sizes import check_size
from cspace.errors import ConfigurationShapeError, NotARotationError, ValueOverflowError
from cspace.space._arguments import parameters, real_number
from cspace.space._checks import (
    BoolArray,
    FloatArray,
    as_rows,
    broadcast_shapes,
    check_finite,
    check_overflow,
    check_unit,
    real_array,
)

__all__ = [
    "UNIT_TOLERANCE",
    "BoolArray",
    "FloatArray",
    "angle_between",
    "canonicalize",
    "conjugate",
    "exp",
    "is_rotation_matrix",
    "log",
    "matrix_from_quaternion",
    "multiply",
    "quaternion_from_matrix",
    "slerp",
    "wxyz_from_xyzw",
    "xyzw_from_wxyz",
]

UNIT_TOLERANCE = 1e-6
"""A quaternion whose norm differs from 1 by more than this is rejected as input."""

_RENORMALIZE = 1e-12
"""Squared norms within this of 1 are left alone, so canonicalizing twice is bit-exact."""


def _quaternions(h: object, name: str, check: bool, order: str = "wxyz") -> FloatArray:
    """``h`` as a float64 array (..., 4); with ``check``, finite unit quaternions.

    Raises:
        ArgumentTypeError, ConfigurationShapeError, NonFiniteValueError,
        NotUnitQuaternionError: Only with ``check``.
    """
    if not check:
        return np.asarray(h, dtype=np.float64)
    rows, lead = as_rows(h, 4, f"quaternion {name} ({', '.join(order)})")  # type: ignore[arg-type]
    check_finite(rows, [f"{name}.{part}" for part in order], lead)
    check_unit(rows, name, "quaternion", UNIT_TOLERANCE, lead)
    return rows.reshape(*lead, 4)


def _pair(h1: object, h2: object, check: bool) -> tuple[FloatArray, FloatArray]:
    """Two quaternion batches, checked, whose leading shapes broadcast (within the cap)."""
    a, b = _quaternions(h1, "h1", check), _quaternions(h2, "h2", check)
    if check:
        check_size((*broadcast_shapes(a.shape[:-1], b.shape[:-1]), 4))
    return a, b


def wxyz_from_xyzw(q: FloatArray, *, check: bool = True) -> FloatArray:
    """Reorder Pinocchio's (x, y, z, w) quaternions, shape (..., 4), to (w, x, y, z)."""
    return np.ascontiguousarray(np.roll(_quaternions(q, "q", check, "xyzw"), 1, axis=-1))


def xyzw_from_wxyz(h: FloatArray, *, check: bool = True) -> FloatArray:
    """Reorder (w, x, y, z) quaternions, shape (..., 4), to Pinocchio's (x, y, z, w)."""
    return np.ascontiguousarray(np.roll(_quaternions(h, "h", check), -1, axis=-1))


def canonicalize(h: FloatArray, *, check: bool = True) -> FloatArray:
    """The canonical representative of each rotation, shape (..., 4), (w, x, y, z).

    Input quaternions must be unit to within `UNIT_TOLERANCE`; they are
    normalized, then flipped to the upper hemisphere. Zeros come out as +0.0.
    """
    h = _quaternions(h, "h", check)
    n2 = np.einsum("...i,...i->...", h, h)
    scale = np.where(np.abs(n2 - 1.0) > _RENORMALIZE, 1.0 / np.sqrt(n2), 1.0)
    first = np.argmax(h != 0.0, axis=-1)
    lead = np.take_along_axis(h, first[..., None], axis=-1)
    sign = np.where(lead < 0.0, -1.0, 1.0)
    return np.asarray((h * (sign * scale[..., None])) + 0.0)


def multiply(h1: FloatArray, h2: FloatArray, *, check: bool = True) -> FloatArray:
    """The Hamilton product h1 * h2 (rotate by h2, then by h1), shapes broadcast (..., 4)."""
    h1, h2 = _pair(h1, h2, check)
    a1, b1, c1, d1 = np.moveaxis(h1, -1, 0)
    a2, b2, c2, d2 = np.moveaxis(h2, -1, 0)
    return np.stack(
        (
            a1 * a2 - b1 * b2 - c1 * c2 - d1 * d2,
            a1 * b2 + a2 * b1 + c1 * d2 - c2 * d1,
            a1 * c2 + a2 * c1 + b2 * d1 - b1 * d2,
            a1 * d2 + a2 * d1 + b1 * c2 - b2 * c1,
        ),
        axis=-1,
    )


def conjugate(h: FloatArray, *, check: bool = True) -> FloatArray:
    """(w, -x, -y, -z): the inverse of a unit quaternion, shape (..., 4)."""
    return np.asarray(_quaternions(h, "h", check) * np.array([1.0, -1.0, -1.0, -1.0]))


def angle_between(h1: FloatArray, h2: FloatArray, *, check: bool = True) -> FloatArray:
    """Rotation angle of h1^-1 h2 in [0, pi], rad; h and -h are one point; shapes broadcast.

    Uses 4 atan2(|h1 - s h2|, |h1 + s h2|) with s = sign <h1, h2>, which stays accurate
    near 0 and near pi, where acos of the inner product loses half the digits.
    """
    h1, h2 = _pair(h1, h2, check)
    dot = np.einsum("...i,...i->...", h1, h2)
    s = np.where(dot < 0.0, -1.0, 1.0)[..., None]
    minus = np.linalg.norm(h1 - s * h2, axis=-1)
    plus = np.linalg.norm(h1 + s * h2, axis=-1)
    return np.asarray(4.0 * np.arctan2(minus, plus))


def log(h: FloatArray, *, check: bool = True) -> FloatArray:
    """The rotation vector (axis * angle, angle in [0, pi]) of each rotation, shape (..., 3)."""
    h = _quaternions(h, "h", check)
    w = h[..., 0]
    v = h[..., 1:]
    s = np.where(w < 0.0, -1.0, 1.0)
    w = w * s
    v = v * s[..., None]
    sin_half = np.linalg.norm(v, axis=-1)
    angle = 2.0 * np.arctan2(sin_half, w)
    tiny = sin_half < 1e-12
    factor = np.where(tiny, 2.0 / np.where(tiny, w, 1.0), angle / np.where(tiny, 1.0, sin_half))
    return np.asarray(v * factor[..., None])


def exp(omega: FloatArray, *, check: bool = True) -> FloatArray:
    """The unit quaternion (w, x, y, z) of each rotation vector, shape (..., 3) -> (..., 4).

    Raises:
        ValueOverflowError: A rotation vector's norm overflows a double (only with
            ``check``; without, its quaternion is NaN).
    """
    if check:
        rows, lead = as_rows(omega, 3, "rotation vector omega")
        check_finite(rows, ["omega.x", "omega.y", "omega.z"], lead)
        check_size((*lead, 4))
        omega = rows.reshape(*lead, 3)
    omega = np.asarray(omega, dtype=np.float64)
    with np.errstate(over="ignore"):
        angle = np.linalg.norm(omega, axis=-1)
    if check and not np.isfinite(angle).all():
        raise ValueOverflowError("a rotation vector's norm overflows a double (beyond 1.8e308)")
    half = 0.5 * angle
    small = angle < 1e-6
    # sin(angle / 2) / angle, with its Taylor series near 0
    with np.errstate(invalid="ignore"):
        ratio = np.where(
            small, 0.5 - angle * angle / 48.0, np.sin(half) / np.where(small, 1.0, angle)
        )
        return np.concatenate((np.cos(half)[..., None], omega * ratio[..., None]), axis=-1)


def slerp(h1: FloatArray, h2: FloatArray, t: FloatArray, *, check: bool = True) -> FloatArray:
    """Spherical interpolation along the shorter arc (h2 or -h2); canonical (..., 4).

    ``t`` has the leading shape (broadcast); 0 gives h1, 1 gives h2 (canonicalized);
    outside [0, 1] the arc is extended.

    Raises:
        ValueOverflowError: A point is beyond a double (``t`` near 1e308; only with
            ``check``, else NaN).
    """
    h1, h2 = _pair(h1, h2, check)
    if check:
        t = parameters(t)
        check_size((*broadcast_shapes(h1.shape[:-1], h2.shape[:-1], t.shape), 4))
    dot = np.einsum("...i,...i->...", h1, h2)
    h2 = h2 * np.where(dot < 0.0, -1.0, 1.0)[..., None]
    phi = 2.0 * np.arctan2(np.linalg.norm(h1 - h2, axis=-1), np.linalg.norm(h1 + h2, axis=-1))
    t = np.asarray(t, dtype=np.float64)
    sin_phi = np.sin(phi)
    small = sin_phi < 1e-9
    safe = np.where(small, 1.0, sin_phi)
    with np.errstate(over="ignore", invalid="ignore"):
        w1 = np.where(small, 1.0 - t, np.sin((1.0 - t) * phi) / safe)
        w2 = np.where(small, t, np.sin(t * phi) / safe)
        out = w1[..., None] * h1 + w2[..., None] * h2
        out = canonicalize(out / np.linalg.norm(out, axis=-1, keepdims=True), check=False)
    if check:
        check_overflow(out.reshape(-1, 4), "slerp", out.shape[:-1])
    return out


def _first(bad: BoolArray) -> int | None:
    """Row-major index of the first True entry, or None for a single item."""
    return None if bad.ndim == 0 else int(np.argmax(bad.reshape(-1)))


def matrix_from_quaternion(h: FloatArray, *, check: bool = True) -> FloatArray:
    """Rotation matrices, shape (..., 3, 3), of unit quaternions (w, x, y, z), (..., 4).

    LaValle eq. (4.20).

    Raises:
        ConfigurationShapeError: The last axis is not 4 long.
        NonFiniteValueError, NotUnitQuaternionError: A quaternion is not finite or not
            unit within `UNIT_TOLERANCE` (only with ``check``).
    """
    h = _quaternions(h, "h", check)
    check_size((*h.shape[:-1], 3, 3))
    a, b, c, d = np.moveaxis(h, -1, 0)
    rows = (
        (2 * (a * a + b * b) - 1, 2 * (b * c - a * d), 2 * (b * d + a * c)),
        (2 * (b * c + a * d), 2 * (a * a + c * c) - 1, 2 * (c * d - a * b)),
        (2 * (b * d - a * c), 2 * (c * d + a * b), 2 * (a * a + d * d) - 1),
    )
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def _matrices(r: object, dim: int = 3) -> FloatArray:
    """``r`` as float64 (..., dim, dim) matrices, within the cap for the 4 x 4 work arrays."""
    m = real_array(r, "a rotation matrix")  # type: ignore[arg-type]
    if m.ndim < 2 or m.shape[-2:] != (dim, dim):
        raise ConfigurationShapeError(
            f"a rotation matrix here is {dim} x {dim}, got shape {m.shape}",
            expected=dim,
            shape=m.shape,
        )
    check_size((*m.shape[:-2], 4, 4))
    return m


def quaternion_from_matrix(r: FloatArray, *, check: bool = True) -> FloatArray:
    """Canonical unit quaternions (w, x, y, z), shape (..., 4), of rotation matrices (..., 3, 3).

    Exact for every rotation, rotations by pi and pure yaw, pitch or roll included: of
    the four expressions 4w^2, 4x^2, 4y^2, 4z^2 (1 + r11 + r22 + r33, 1 + r11 - r22 - r33,
    1 - r11 + r22 - r33, 1 - r11 - r22 + r33) the largest, at least 1, is the divisor.

    Raises:
        ConfigurationShapeError: The last two axes are not 3 x 3.
        NotARotationError: A matrix is not finite, not orthonormal within
            `UNIT_TOLERANCE`, or a reflection (only with ``check``).
    """
    r = _matrices(r)
    if check:
        bad = ~is_rotation_matrix(r)
        if bad.any():
            raise NotARotationError(
                "matrix is not a rotation (not finite, not orthonormal within "
                f"{UNIT_TOLERANCE:g}, or determinant -1)",
                row=_first(bad),
            )
    r11, r12, r13 = r[..., 0, 0], r[..., 0, 1], r[..., 0, 2]
    r21, r22, r23 = r[..., 1, 0], r[..., 1, 1], r[..., 1, 2]
    r31, r32, r33 = r[..., 2, 0], r[..., 2, 1], r[..., 2, 2]
    t = np.stack(
        (
            1 + r11 + r22 + r33,
            1 + r11 - r22 - r33,
            1 - r11 + r22 - r33,
            1 - r11 - r22 + r33,
        ),
        axis=-1,
    )
    # Row k: 4 h_k * h, whose k-th entry is t_k.
    candidates = np.stack(
        (
            np.stack((t[..., 0], r32 - r23, r13 - r31, r21 - r12), axis=-1),
            np.stack((r32 - r23, t[..., 1], r12 + r21, r13 + r31), axis=-1),
            np.stack((r13 - r31, r12 + r21, t[..., 2], r23 + r32), axis=-1),
            np.stack((r21 - r12, r13 + r31, r23 + r32, t[..., 3]), axis=-1),
        ),
        axis=-2,
    )
    best = np.argmax(t, axis=-1)
    chosen = np.take_along_axis(candidates, best[..., None, None], axis=-2)[..., 0, :]
    scale = 0.5 / np.sqrt(np.take_along_axis(t, best[..., None], axis=-1))
    h = chosen * scale
    return canonicalize(h / np.linalg.norm(h, axis=-1, keepdims=True), check=False)


def is_rotation_matrix(
    r: FloatArray, tolerance: float = UNIT_TOLERANCE, *, dim: int = 3
) -> BoolArray:
    """True where ``r`` (..., dim, dim) is finite, orthonormal and has determinant +1.

    ``dim`` is 3 for SO(3), 2 for SO(2).

    Raises:
        ArgumentTypeError, ConfigurationShapeError: ``r`` is not an array of dim x dim
            real matrices.
        ArgumentError: ``tolerance`` is not finite and >= 0.
    """
    tolerance = real_number(tolerance, "tolerance", minimum=0.0)
    r = _matrices(r, dim)
    # entries beyond 1 + tolerance cannot be a rotation's; zeroing them spares overflow
    finite = np.all(np.abs(r) <= 1.0 + tolerance, axis=(-2, -1))
    rr = np.where(finite[..., None, None], r, 0.0)
    gram = np.einsum("...ji,...jk->...ik", rr, rr) - np.eye(dim)
    orthonormal = np.max(np.abs(gram), axis=(-2, -1)) <= tolerance
    positive = np.linalg.det(rr) > 0.0
    return np.asarray(finite & orthonormal & positive)
