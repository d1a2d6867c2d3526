"""The batch operations for a few rows, in plain Python: nothing to import or compile.

A one-pair ``distance`` must not wait for numba (about half a second to import it and
load its cached kernels). For small batches (see `takes`),
`ConfigurationSpace` runs these functions instead of
`_kernels`. They take the same arguments and return the same thing
(-1, or the first row holding a non-finite value or a quaternion off the unit sphere),
and do the same arithmetic in the same order on IEEE doubles with the same C library:
canonical forms, interpolated points, samples and distances are bit-identical to the
kernels' (tested), so a configuration's result never depends on its batch. Rows are
read as Python floats (``tolist``): a division by zero or a sine of inf, which the
kernels turn into NaN, mark the row bad here too.
"""

from __future__ import annotations

import math
import sys
from typing import TYPE_CHECKING

from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from cspace.space._sampling_plan import SamplingPlan

    IntArray = NDArray[np.int64]

SMALL_ROWS = 8
"""Batches of at most this many rows always take this module's path."""

PLAIN_NUMBERS = 1 << 18
"""Coordinates (in all, over every call) that canonicalize and interpolate may take here
before the kernels are loaded: ~0.1 s of plain Python against ~0.5 s to load numba."""

_plain_left = [PLAIN_NUMBERS]


def takes(rows: int, size: int, exact: bool) -> bool:
    """Whether this module runs a batch of ``rows`` rows of ``size`` coordinates.

    Always for at most `SMALL_ROWS` rows. Larger batches of an operation whose
    results are bit-identical on both paths (``exact``: canonicalize, interpolate) come
    here too until `PLAIN_NUMBERS` coordinates have, unless the kernels are loaded
    already: a short ``cspace interpolate`` never waits for numba, a long-running
    program moves to the kernels after a few batches. Distances, which may differ by
    rounding, depend on the batch size only.
    """
    if rows <= SMALL_ROWS:
        return True
    numbers = rows * size
    if not exact or "cspace.space._compute.kernels" in sys.modules or numbers > _plain_left[0]:
        return False
    _plain_left[0] -= numbers
    return True


_PI = math.pi
_TWO_PI = 2.0 * math.pi
_RENORMALIZE = 1e-12
_Quaternion = tuple[float, float, float, float]


def _wrap(x: float) -> float:
    if -_PI <= x < _PI:
        return x
    r = (x + _PI) % _TWO_PI - _PI
    if r >= _PI:
        r -= _TWO_PI
    return r


def _short_way(ca: float, cb: float) -> float:
    d = _wrap(cb - ca)
    if d == -_PI and cb > ca:
        return _PI
    return d


def _unit_range(tolerance: float) -> tuple[float, float]:
    return (1.0 - tolerance) * (1.0 - tolerance), (1.0 + tolerance) * (1.0 + tolerance)


def _row_ok(row: list[float], rotations: list[int], low: float, high: float) -> bool:
    if not all(map(math.isfinite, row)):
        return False
    for c in rotations:
        w, x, y, z = row[c : c + 4]
        if not low <= w * w + x * x + y * y + z * z <= high:
            return False
    return True


def _canonical_quaternion(w: float, x: float, y: float, z: float) -> _Quaternion:
    n2 = w * w + x * x + y * y + z * z
    scale = 1.0 / math.sqrt(n2) if abs(n2 - 1.0) > _RENORMALIZE else 1.0
    lead = w if w != 0.0 else (x if x != 0.0 else (y if y != 0.0 else z))
    f = math.copysign(1.0, lead) * scale
    return w * f + 0.0, x * f + 0.0, y * f + 0.0, z * f + 0.0


def _canonical_row(row: list[float], circles: list[int], rotations: list[int]) -> list[float]:
    out = list(row)
    for c in circles:
        out[c] = _wrap(row[c])
    for c in rotations:
        out[c : c + 4] = _canonical_quaternion(*row[c : c + 4])
    return out


def _rows(x: FloatArray, n: int) -> list[list[float]]:
    """The n rows of a batch that has 1 (broadcast) or n rows, as lists of floats."""
    rows: list[list[float]] = x.tolist()
    return rows * n if len(rows) == 1 else rows


def canonicalize(
    x: FloatArray, circles: IntArray, rotations: IntArray, tolerance: float, out: FloatArray
) -> int:
    """`canonicalize`, row by row."""
    low, high = _unit_range(tolerance)
    turns, spins = circles.tolist(), rotations.tolist()
    for i, row in enumerate(x.tolist()):
        if not _row_ok(row, spins, low, high):
            return i
        out[i] = _canonical_row(row, turns, spins)
    return -1


def distance(
    a: FloatArray,
    b: FloatArray,
    w2: FloatArray,
    circles: IntArray,
    circle_w2: FloatArray,
    rotations: IntArray,
    rotation_w2: FloatArray,
    tolerance: float,
    out: FloatArray,
) -> int:
    """`distance`, row by row."""
    low, high = _unit_range(tolerance)
    weights = w2.tolist()
    turns = list(zip(circles.tolist(), circle_w2.tolist(), strict=True))
    spins = list(zip(rotations.tolist(), rotation_w2.tolist(), strict=True))
    n = out.shape[0]
    for i, (ra, rb) in enumerate(zip(_rows(a, n), _rows(b, n), strict=True)):
        s = _weighted_squares(ra, rb, weights)
        for c, w in turns:
            d = _wrap(rb[c] - ra[c])
            s += w * (d * d)
        for c, w in spins:
            angle = _rotation_angle(ra[c : c + 4], rb[c : c + 4], low, high)
            s += w * (angle * angle)
        if not s < math.inf:
            return i
        out[i] = math.sqrt(s)
    return -1


def _weighted_squares(a: list[float], b: list[float], w2: list[float]) -> float:
    """``cspace.space._compute.kernels._weighted_squares``: four running sums, added in pairs."""
    sums = [0.0, 0.0, 0.0, 0.0]
    end = len(a) - len(a) % 4
    for c in range(end):
        d = b[c] - a[c]
        sums[c % 4] += w2[c] * (d * d)
    for c in range(end, len(a)):
        d = b[c] - a[c]
        sums[0] += w2[c] * (d * d)
    return (sums[0] + sums[1]) + (sums[2] + sums[3])


def _rotation_angle(qa: list[float], qb: list[float], low: float, high: float) -> float:
    """The rotation angle between two quaternions; NaN when one is not unit."""
    a0, a1, a2, a3 = qa
    b0, b1, b2, b3 = qb
    na2 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
    nb2 = b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3
    if not (low <= na2 <= high and low <= nb2 <= high):
        return math.nan
    fa = 1.0 / math.sqrt(na2)
    fb = math.copysign(1.0 / math.sqrt(nb2), a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3)
    m0, m1 = a0 * fa - b0 * fb, a1 * fa - b1 * fb
    m2, m3 = a2 * fa - b2 * fb, a3 * fa - b3 * fb
    p0, p1 = a0 * fa + b0 * fb, a1 * fa + b1 * fb
    p2, p3 = a2 * fa + b2 * fb, a3 * fa + b3 * fb
    m = m0 * m0 + m1 * m1 + m2 * m2 + m3 * m3
    r = math.sqrt(m / (p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3))
    return 4.0 * math.atan(r)


def _slerp(qa: list[float], qb: list[float], t: float) -> _Quaternion:
    """The kernels' slerp (see ``cspace.space._compute.kernels._slerp``) of two unit quaternions."""
    a0, a1, a2, a3 = qa
    b0, b1, b2, b3 = qb
    na2 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
    nb2 = b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3
    fa = 1.0 / math.sqrt(na2) if abs(na2 - 1.0) > _RENORMALIZE else 1.0
    fb = 1.0 / math.sqrt(nb2) if abs(nb2 - 1.0) > _RENORMALIZE else 1.0
    fb = math.copysign(fb, a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3)
    a0, a1, a2, a3 = a0 * fa, a1 * fa, a2 * fa, a3 * fa
    b0, b1, b2, b3 = b0 * fb, b1 * fb, b2 * fb, b3 * fb
    d0, d1, d2, d3 = a0 - b0, a1 - b1, a2 - b2, a3 - b3
    s0, s1, s2, s3 = a0 + b0, a1 + b1, a2 + b2, a3 + b3
    m = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3)
    p = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2 + s3 * s3)
    phi = 2.0 * math.atan(m / p)
    sin_phi = 0.5 * m * p
    if sin_phi < 1e-9:
        wa, wb = 1.0 - t, t
    else:
        wb = math.sin(t * phi) / sin_phi
        wa = math.cos(t * phi) - 0.25 * (p * p - m * m) * wb
    h0, h1 = wa * a0 + wb * b0, wa * a1 + wb * b1
    h2, h3 = wa * a2 + wb * b2, wa * a3 + wb * b3
    lead = h0 if h0 != 0.0 else (h1 if h1 != 0.0 else (h2 if h2 != 0.0 else h3))
    nh2 = h0 * h0 + h1 * h1 + h2 * h2 + h3 * h3
    f = math.copysign(1.0 / math.sqrt(nh2) if abs(nh2 - 1.0) > _RENORMALIZE else 1.0, lead)
    return h0 * f + 0.0, h1 * f + 0.0, h2 * f + 0.0, h3 * f + 0.0


def interpolate(
    a: FloatArray,
    b: FloatArray,
    t: FloatArray,
    circles: IntArray,
    rotations: IntArray,
    tolerance: float,
    out: FloatArray,
) -> int:
    """`interpolate`, row by row."""
    low, high = _unit_range(tolerance)
    turns, spins = circles.tolist(), rotations.tolist()
    n = out.shape[0]
    steps: list[float] = t.tolist()
    steps = steps * n if len(steps) == 1 else steps
    for i, (ra, rb, ti) in enumerate(zip(_rows(a, n), _rows(b, n), steps, strict=True)):
        if not (_row_ok(ra, spins, low, high) and _row_ok(rb, spins, low, high)):
            return i
        if ti == 0.0 or ti == 1.0:  # exactly the canonical end
            out[i] = _canonical_row(ra if ti == 0.0 else rb, turns, spins)
            continue
        try:
            row = [(1.0 - ti) * xa + ti * xb for xa, xb in zip(ra, rb, strict=True)]
            for c in turns:
                ca = _wrap(ra[c])
                row[c] = _wrap(ca + ti * _short_way(ca, _wrap(rb[c])))
            for c in spins:
                row[c : c + 4] = _slerp(ra[c : c + 4], rb[c : c + 4], ti)
        except (ValueError, ZeroDivisionError):  # a sine of inf: the kernels get NaN
            return i
        if not all(map(math.isfinite, row)):
            return i
        out[i] = row
    return -1


def sample(u: FloatArray, plan: SamplingPlan, out: FloatArray) -> int:
    """`sample`, row by row."""
    columns = [part.tolist() for part in plan]
    line_plan = list(zip(*columns[0:4], strict=True))
    circle_plan = list(zip(*columns[4:8], strict=True))
    rotation_plan = list(zip(*columns[8:10], strict=True))
    row = [0.0] * out.shape[1]
    for i, draws in enumerate(u.tolist()):
        for c, d, low, span in line_plan:
            row[c] = low + span * draws[d]
        for c, d, low, span in circle_plan:
            row[c] = _wrap(low + span * draws[d])
        for c, d in rotation_plan:
            u0 = draws[d]
            r1, r2 = math.sqrt(1.0 - u0), math.sqrt(u0)
            a1, a2 = _TWO_PI * draws[d + 1], _TWO_PI * draws[d + 2]
            row[c : c + 4] = _canonical_quaternion(
                r2 * math.cos(a2), r1 * math.sin(a1), r1 * math.cos(a1), r2 * math.sin(a2)
            )
        out[i] = row
    return -1
