"""Compiled batch kernels (numba) for the hot operations of a configuration space.

Each kernel makes one pass over its arrays, a configuration (row) at a time, with no
temporaries, so batch distance runs near memory bandwidth. The mathematics is the same
as the factors' (:mod:`cspace.factors`), which tests compare against. Imported only by
:mod:`cspace.space` on first use: numba stays out of ``cspace inspect``'s start-up.

Every kernel validates as it goes and returns -1, or the index of the first row that
holds a non-finite value or a quaternion whose norm is off by more than the tolerance
(then the caller names the problem). Inputs: 2-D float64 arrays whose first axis is
either the batch length or 1 (broadcast). Column index arrays say where each factor's
coordinates are: ``circles`` (one column each), ``rotations`` (first of four columns,
(w, x, y, z)); every other column is R^1.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .rotations import FloatArray

IntArray = np.typing.NDArray[np.int64]

_PI = math.pi
_TWO_PI = 2.0 * math.pi
_RENORMALIZE = 1e-12


@njit(cache=True, inline="always")
def _wrap(x: float) -> float:
    if x >= -_PI and x < _PI:
        return x
    r = x - _TWO_PI * math.floor((x + _PI) / _TWO_PI)
    if r >= _PI:
        r -= _TWO_PI
    if r < -_PI:
        r += _TWO_PI
    return r


@njit(cache=True, inline="always")
def _unit_ok(n2: float, tolerance: float) -> bool:
    norm = math.sqrt(n2)
    return abs(norm - 1.0) <= tolerance


@njit(cache=True)
def _canonical_quaternion(src: FloatArray, i: int, c: int, out: FloatArray, o: int, k: int) -> None:
    """out[o, k:k+4] = canonical form of src[i, c:c+4] (normalized, upper hemisphere)."""
    w, x, y, z = src[i, c], src[i, c + 1], src[i, c + 2], src[i, c + 3]
    n2 = w * w + x * x + y * y + z * z
    scale = 1.0 / math.sqrt(n2) if abs(n2 - 1.0) > _RENORMALIZE else 1.0
    lead = w if w != 0.0 else (x if x != 0.0 else (y if y != 0.0 else z))
    f = (-1.0 if lead < 0.0 else 1.0) * scale
    out[o, k] = w * f + 0.0
    out[o, k + 1] = x * f + 0.0
    out[o, k + 2] = y * f + 0.0
    out[o, k + 3] = z * f + 0.0


@njit(cache=True)
def _row_ok(src: FloatArray, i: int, rotations: IntArray, tolerance: float) -> bool:
    for c in range(src.shape[1]):
        if not math.isfinite(src[i, c]):
            return False
    for c in rotations:
        n2 = src[i, c] ** 2 + src[i, c + 1] ** 2 + src[i, c + 2] ** 2 + src[i, c + 3] ** 2
        if not _unit_ok(n2, tolerance):
            return False
    return True


@njit(cache=True)
def _canonical_row(
    src: FloatArray, i: int, circles: IntArray, rotations: IntArray, out: FloatArray, o: int
) -> None:
    for c in range(src.shape[1]):
        out[o, c] = src[i, c]
    for c in circles:
        out[o, c] = _wrap(src[i, c])
    for c in rotations:
        _canonical_quaternion(src, i, c, out, o, c)


@njit(cache=True)
def canonicalize(
    x: FloatArray, circles: IntArray, rotations: IntArray, tolerance: float, out: FloatArray
) -> int:
    """Set out to the canonical form of every row of x; returns -1 or the first invalid row."""
    for i in range(x.shape[0]):
        if not _row_ok(x, i, rotations, tolerance):
            return i
        _canonical_row(x, i, circles, rotations, out, i)
    return -1


@njit(cache=True)
def distance(
    a: FloatArray,
    b: FloatArray,
    lines: IntArray,
    line_w2: FloatArray,
    circles: IntArray,
    circle_w2: FloatArray,
    rotations: IntArray,
    rotation_w2: FloatArray,
    tolerance: float,
    out: FloatArray,
) -> int:
    """out[i] = weighted product distance of rows a[i], b[i]; -1 or the first bad row."""
    n = out.shape[0]
    sa = 1 if a.shape[0] > 1 else 0
    sb = 1 if b.shape[0] > 1 else 0
    for i in range(n):
        ia = i * sa
        ib = i * sb
        s = 0.0
        for k in range(lines.shape[0]):
            c = lines[k]
            d = b[ib, c] - a[ia, c]
            s += line_w2[k] * d * d
        for k in range(circles.shape[0]):
            c = circles[k]
            d = _wrap(b[ib, c] - a[ia, c])
            s += circle_w2[k] * d * d
        for k in range(rotations.shape[0]):
            c = rotations[k]
            a0, a1, a2, a3 = a[ia, c], a[ia, c + 1], a[ia, c + 2], a[ia, c + 3]
            b0, b1, b2, b3 = b[ib, c], b[ib, c + 1], b[ib, c + 2], b[ib, c + 3]
            na2 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
            nb2 = b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3
            if not (_unit_ok(na2, tolerance) and _unit_ok(nb2, tolerance)):
                return i
            fa = 1.0 / math.sqrt(na2)
            fb = 1.0 / math.sqrt(nb2)
            dot = a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3
            if dot < 0.0:
                fb = -fb
            m0, m1, m2, m3 = (
                a0 * fa - b0 * fb,
                a1 * fa - b1 * fb,
                a2 * fa - b2 * fb,
                a3 * fa - b3 * fb,
            )
            p0, p1, p2, p3 = (
                a0 * fa + b0 * fb,
                a1 * fa + b1 * fb,
                a2 * fa + b2 * fb,
                a3 * fa + b3 * fb,
            )
            angle = 4.0 * math.atan2(
                math.sqrt(m0 * m0 + m1 * m1 + m2 * m2 + m3 * m3),
                math.sqrt(p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3),
            )
            s += rotation_w2[k] * angle * angle
        if not s < math.inf:  # NaN or inf somewhere in the two rows
            return i
        out[i] = math.sqrt(s)
    return -1


@njit(cache=True)
def _slerp(out: FloatArray, i: int, c: int, t: float, bq: FloatArray) -> None:
    """out[i, c:c+4] (canonical a) <- slerp towards canonical bq[0:4], canonicalized."""
    a0, a1, a2, a3 = out[i, c], out[i, c + 1], out[i, c + 2], out[i, c + 3]
    b0, b1, b2, b3 = bq[0], bq[1], bq[2], bq[3]
    if a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3 < 0.0:
        b0, b1, b2, b3 = -b0, -b1, -b2, -b3
    m = math.sqrt((a0 - b0) ** 2 + (a1 - b1) ** 2 + (a2 - b2) ** 2 + (a3 - b3) ** 2)
    p = math.sqrt((a0 + b0) ** 2 + (a1 + b1) ** 2 + (a2 + b2) ** 2 + (a3 + b3) ** 2)
    phi = 2.0 * math.atan2(m, p)
    sin_phi = math.sin(phi)
    if sin_phi < 1e-9:
        wa, wb = 1.0 - t, t
    else:
        wa, wb = math.sin((1.0 - t) * phi) / sin_phi, math.sin(t * phi) / sin_phi
    out[i, c] = wa * a0 + wb * b0
    out[i, c + 1] = wa * a1 + wb * b1
    out[i, c + 2] = wa * a2 + wb * b2
    out[i, c + 3] = wa * a3 + wb * b3
    n = math.sqrt(out[i, c] ** 2 + out[i, c + 1] ** 2 + out[i, c + 2] ** 2 + out[i, c + 3] ** 2)
    for k in range(4):
        out[i, c + k] /= n
    _canonical_quaternion(out, i, c, out, i, c)


@njit(cache=True)
def interpolate(
    a: FloatArray,
    b: FloatArray,
    t: FloatArray,
    lines: IntArray,
    circles: IntArray,
    rotations: IntArray,
    tolerance: float,
    out: FloatArray,
) -> int:
    """out[i] = point at t[i] on the shortest path from a[i] to b[i]; canonical.

    Exact canonical endpoints at t = 0 and t = 1. Returns -1 or the first bad row.
    """
    n = out.shape[0]
    sa = 1 if a.shape[0] > 1 else 0
    sb = 1 if b.shape[0] > 1 else 0
    st = 1 if t.shape[0] > 1 else 0
    bq = np.empty((1, 4))
    for i in range(n):
        ia, ib, ti = i * sa, i * sb, t[i * st]
        if not (_row_ok(a, ia, rotations, tolerance) and _row_ok(b, ib, rotations, tolerance)):
            return i
        if not math.isfinite(ti):
            return i
        if ti == 1.0:
            _canonical_row(b, ib, circles, rotations, out, i)
            continue
        _canonical_row(a, ia, circles, rotations, out, i)
        if ti == 0.0:
            continue
        for c in lines:
            out[i, c] = (1.0 - ti) * a[ia, c] + ti * b[ib, c]
        for c in circles:
            ca = out[i, c]
            out[i, c] = _wrap(ca + ti * _wrap(_wrap(b[ib, c]) - ca))
        for c in rotations:
            _canonical_quaternion(b, ib, c, bq, 0, 0)
            _slerp(out, i, c, ti, bq[0])
    return -1
