"""Rotations of SO(3) as unit quaternions, batched over leading axes.

Conventions (see ``shared/reference/cspace-math.md`` section 3):

- A quaternion is an array of shape ``(..., 4)`` in **(w, x, y, z)** order, the order
  of LaValle's text (a, b, c, d). Pinocchio's q stores (x, y, z, w); convert with
  :func:`wxyz_from_xyzw` and :func:`xyzw_from_wxyz`.
- h and -h are the same rotation (SO(3) = RP^3). The canonical representative lies on
  the upper hemisphere: w > 0; or w = 0 and x > 0; or w = x = 0 and y > 0; or
  w = x = y = 0 and z = 1. :func:`canonicalize` maps h and -h to bit-identical output.
- A rotation matrix is an array of shape ``(..., 3, 3)`` acting on column vectors.
- A rotation vector (tangent) is an array of shape ``(..., 3)``: axis times angle, rad.

The two conversions a user calls directly, :func:`quaternion_from_matrix` and
:func:`matrix_from_quaternion`, check their input (``check=False`` skips it); the other
functions do not: callers (factors, the configuration space) validate once.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .errors import ConfigurationShapeError, NotARotationError, NotUnitQuaternionError

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

UNIT_TOLERANCE = 1e-6
"""A quaternion whose norm differs from 1 by more than this is rejected as input."""

_RENORMALIZE = 1e-12
"""Squared norms within this of 1 are left alone, so canonicalizing twice is bit-exact."""


def wxyz_from_xyzw(q: FloatArray) -> FloatArray:
    """Reorder Pinocchio's (x, y, z, w) quaternions, shape (..., 4), to (w, x, y, z)."""
    return np.ascontiguousarray(np.roll(q, 1, axis=-1))


def xyzw_from_wxyz(h: FloatArray) -> FloatArray:
    """Reorder (w, x, y, z) quaternions, shape (..., 4), to Pinocchio's (x, y, z, w)."""
    return np.ascontiguousarray(np.roll(h, -1, axis=-1))


def canonicalize(h: FloatArray) -> FloatArray:
    """The canonical representative of each rotation, shape (..., 4), (w, x, y, z).

    Input quaternions must be unit to within :data:`UNIT_TOLERANCE` (not checked here);
    they are normalized, then flipped to the upper hemisphere. Zeros come out as +0.0.
    """
    h = np.asarray(h, dtype=np.float64)
    n2 = np.einsum("...i,...i->...", h, h)
    scale = np.where(np.abs(n2 - 1.0) > _RENORMALIZE, 1.0 / np.sqrt(n2), 1.0)
    first = np.argmax(h != 0.0, axis=-1)
    lead = np.take_along_axis(h, first[..., None], axis=-1)
    sign = np.where(lead < 0.0, -1.0, 1.0)
    return np.asarray((h * (sign * scale[..., None])) + 0.0)


def multiply(h1: FloatArray, h2: FloatArray) -> FloatArray:
    """The Hamilton product h1 * h2 (rotate by h2, then by h1), shapes broadcast (..., 4)."""
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


def conjugate(h: FloatArray) -> FloatArray:
    """(w, -x, -y, -z): the inverse of a unit quaternion, shape (..., 4)."""
    return np.asarray(h * np.array([1.0, -1.0, -1.0, -1.0]))


def angle_between(h1: FloatArray, h2: FloatArray) -> FloatArray:
    """Rotation angle of h1^-1 h2 in [0, pi], rad; h and -h are one point.

    Uses 4 atan2(|h1 - s h2|, |h1 + s h2|) with s = sign <h1, h2>, which stays accurate
    near 0 and near pi, where acos of the inner product loses half the digits.
    """
    dot = np.einsum("...i,...i->...", h1, h2)
    s = np.where(dot < 0.0, -1.0, 1.0)[..., None]
    minus = np.linalg.norm(h1 - s * h2, axis=-1)
    plus = np.linalg.norm(h1 + s * h2, axis=-1)
    return np.asarray(4.0 * np.arctan2(minus, plus))


def log(h: FloatArray) -> FloatArray:
    """The rotation vector (axis * angle, angle in [0, pi]) of each rotation, shape (..., 3)."""
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


def exp(omega: FloatArray) -> FloatArray:
    """The unit quaternion (w, x, y, z) of each rotation vector, shape (..., 3) -> (..., 4)."""
    angle = np.linalg.norm(omega, axis=-1)
    half = 0.5 * angle
    small = angle < 1e-6
    # sin(angle / 2) / angle, with its Taylor series near 0
    ratio = np.where(small, 0.5 - angle * angle / 48.0, np.sin(half) / np.where(small, 1.0, angle))
    return np.concatenate((np.cos(half)[..., None], omega * ratio[..., None]), axis=-1)


def slerp(h1: FloatArray, h2: FloatArray, t: FloatArray) -> FloatArray:
    """Spherical interpolation along the shorter arc (h2 or -h2); canonical (..., 4).

    ``t`` has the leading shape (broadcast); 0 gives h1, 1 gives h2 (canonicalized).
    """
    dot = np.einsum("...i,...i->...", h1, h2)
    h2 = h2 * np.where(dot < 0.0, -1.0, 1.0)[..., None]
    phi = 2.0 * np.arctan2(np.linalg.norm(h1 - h2, axis=-1), np.linalg.norm(h1 + h2, axis=-1))
    t = np.asarray(t, dtype=np.float64)
    sin_phi = np.sin(phi)
    small = sin_phi < 1e-9
    safe = np.where(small, 1.0, sin_phi)
    w1 = np.where(small, 1.0 - t, np.sin((1.0 - t) * phi) / safe)
    w2 = np.where(small, t, np.sin(t * phi) / safe)
    out = w1[..., None] * h1 + w2[..., None] * h2
    out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    return canonicalize(out)


def _first(bad: NDArray[np.bool_]) -> int | None:
    """Row-major index of the first True entry, or None for a single item."""
    return None if bad.ndim == 0 else int(np.argmax(bad.reshape(-1)))


def matrix_from_quaternion(h: FloatArray, *, check: bool = True) -> FloatArray:
    """Rotation matrices, shape (..., 3, 3), of unit quaternions (w, x, y, z), (..., 4).

    LaValle eq. (4.20).

    Raises:
        ConfigurationShapeError: The last axis is not 4 long.
        NotUnitQuaternionError: A quaternion is not finite or not unit within
            :data:`UNIT_TOLERANCE` (only with ``check``).
    """
    h = np.asarray(h, dtype=np.float64)
    if check:
        if h.ndim == 0 or h.shape[-1] != 4:
            raise ConfigurationShapeError(
                f"a quaternion has 4 components, got shape {h.shape}", expected=4, shape=h.shape
            )
        norms = np.linalg.norm(h, axis=-1)
        bad = ~(np.abs(norms - 1.0) <= UNIT_TOLERANCE)
        if bad.any():
            row = _first(bad)
            norm = float(norms.reshape(-1)[row or 0])
            raise NotUnitQuaternionError(
                f"quaternion has norm {norm!r}, not 1 (tolerance {UNIT_TOLERANCE:g})",
                norm=norm,
                tolerance=UNIT_TOLERANCE,
                coordinate="quaternion",
                row=row,
            )
    a, b, c, d = np.moveaxis(h, -1, 0)
    rows = (
        (2 * (a * a + b * b) - 1, 2 * (b * c - a * d), 2 * (b * d + a * c)),
        (2 * (b * c + a * d), 2 * (a * a + c * c) - 1, 2 * (c * d - a * b)),
        (2 * (b * d - a * c), 2 * (c * d + a * b), 2 * (a * a + d * d) - 1),
    )
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def quaternion_from_matrix(r: FloatArray, *, check: bool = True) -> FloatArray:
    """Canonical unit quaternions (w, x, y, z), shape (..., 4), of rotation matrices (..., 3, 3).

    Exact for every rotation, rotations by pi and pure yaw, pitch or roll included: of
    the four expressions 4w^2, 4x^2, 4y^2, 4z^2 (1 + r11 + r22 + r33, 1 + r11 - r22 - r33,
    1 - r11 + r22 - r33, 1 - r11 - r22 + r33) the largest, at least 1, is the divisor.

    Raises:
        ConfigurationShapeError: The last two axes are not 3 x 3.
        NotARotationError: A matrix is not finite, not orthonormal within
            :data:`UNIT_TOLERANCE`, or a reflection (only with ``check``).
    """
    r = np.asarray(r, dtype=np.float64)
    if check:
        if r.ndim < 2 or r.shape[-2:] != (3, 3):
            raise ConfigurationShapeError(
                f"a rotation matrix is 3 x 3, got shape {r.shape}", expected=3, shape=r.shape
            )
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
    return canonicalize(h / np.linalg.norm(h, axis=-1, keepdims=True))


def is_rotation_matrix(r: FloatArray, tolerance: float = UNIT_TOLERANCE) -> NDArray[np.bool_]:
    """True where ``r`` (..., 3, 3) is finite, orthonormal and has determinant +1."""
    r = np.asarray(r, dtype=np.float64)
    finite = np.all(np.isfinite(r), axis=(-2, -1))
    rr = np.where(finite[..., None, None], r, 0.0)
    gram = np.einsum("...ji,...jk->...ik", rr, rr) - np.eye(3)
    orthonormal = np.max(np.abs(gram), axis=(-2, -1)) <= tolerance
    positive = np.linalg.det(rr) > 0.0
    return np.asarray(finite & orthonormal & positive)
