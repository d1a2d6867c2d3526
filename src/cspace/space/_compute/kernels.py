"""Compiled batch kernels (numba) for the hot operations of a configuration space.

Each kernel makes one pass over its arrays, a configuration (row) at a time, with no
temporaries, so batch distance runs near memory bandwidth. The mathematics is the same
as the factors' (`_factors`), which tests compare against. Imported only by
`cspace.space` on first use: numba stays out of ``cspace inspect``'s start-up.

Every kernel validates as it goes and returns -1, or the index of the first row that
holds a non-finite value or a quaternion whose norm is off by more than the tolerance
(then the caller names the problem). Compiled with NumPy's error model (`jit`):
a division by zero (a zero quaternion) gives inf or NaN, found as above, never an
exception. Large batches are cut into chunks of `CHUNK_NUMBERS` numbers that the
calling thread and helper threads (one per other core, or ``NUMBA_NUM_THREADS`` in all) take
in turn (`run_chunks`); a batch of one chunk runs on the calling thread.
Inputs: 2-D float64 arrays whose first axis is either the batch length or 1
(broadcast). Column index arrays say where each factor's coordinates are: ``circles``
(one column each), ``rotations`` (first of four columns, (w, x, y, z)); every other
column is R^1.
"""

from __future__ import annotations

import functools
import itertools
import math
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numba
import numpy as np
from numba import njit

from cspace.space._geometry.rotations import FloatArray

IntArray = np.typing.NDArray[np.int64]

_PI = math.pi
TWO_PI = 2.0 * math.pi
_RENORMALIZE = 1e-12

CHUNK_NUMBERS = 1 << 15
"""Numbers per chunk of a row-wise input (256 kB): the unit of work a thread takes."""


jit = functools.partial(njit, cache=True, error_model="numpy", nogil=True)
"""numba's ``njit``, cached next to the package, dividing by zero as NumPy does, not
holding the GIL (so that helper threads run at once)."""

BLOCK = 256
"""Rows per block: two blocks of 39-coordinate rows (160 kB) stay in a core's L2 cache."""


@jit(inline="always")
def wrap(x: float) -> float:
    if x >= -_PI and x < _PI:
        return x
    # Python's float % is an exact fmod, then a sign fix: huge angles land in range too.
    r = (x + _PI) % TWO_PI - _PI
    if r >= _PI:
        r -= TWO_PI
    return r


@jit(inline="always")
def _short_way(ca: float, cb: float) -> float:
    """Signed shortest way between canonical angles; a half turn goes up from the smaller."""
    d = wrap(cb - ca)
    if d == -_PI and cb > ca:
        return _PI
    return d


@jit(inline="always")
def _unit_ok(n2: float, tolerance: float) -> bool:
    """|sqrt(n2) - 1| <= tolerance, without a square root."""
    low = 1.0 - tolerance
    high = 1.0 + tolerance
    return low * low <= n2 <= high * high


@jit(inline="always")
def canonical_quaternion(src: FloatArray, i: int, c: int, out: FloatArray, o: int, k: int) -> None:
    """Set out[o, k:k+4] to the canonical form of src[i, c:c+4] (normalized, upper hemisphere)."""
    w, x, y, z = src[i, c], src[i, c + 1], src[i, c + 2], src[i, c + 3]
    n2 = w * w + x * x + y * y + z * z
    scale = 1.0 / math.sqrt(n2) if abs(n2 - 1.0) > _RENORMALIZE else 1.0
    lead = w if w != 0.0 else (x if x != 0.0 else (y if y != 0.0 else z))
    f = math.copysign(1.0, lead) * scale
    out[o, k] = w * f + 0.0
    out[o, k + 1] = x * f + 0.0
    out[o, k + 2] = y * f + 0.0
    out[o, k + 3] = z * f + 0.0


@jit(fastmath={"reassoc"})
def _finite_row(src: FloatArray, i: int) -> bool:
    """True when every entry of row i is finite (x * 0 is NaN for NaN and inf)."""
    z = 0.0
    for c in range(src.shape[1]):
        z += src[i, c] * 0.0
    return z == 0.0


@jit(inline="always")
def _row_ok(src: FloatArray, i: int, rotations: IntArray, tolerance: float) -> bool:
    if not _finite_row(src, i):
        return False
    for c in rotations:
        w, x, y, z = src[i, c], src[i, c + 1], src[i, c + 2], src[i, c + 3]
        n2 = w * w + x * x + y * y + z * z
        if not _unit_ok(n2, tolerance):
            return False
    return True


@jit(inline="always")
def _canonical_row(
    src: FloatArray, i: int, circles: IntArray, rotations: IntArray, out: FloatArray, o: int
) -> None:
    for c in range(src.shape[1]):
        out[o, c] = src[i, c]
    for c in circles:
        out[o, c] = wrap(src[i, c])
    for c in rotations:
        canonical_quaternion(src, i, c, out, o, c)


def run_chunks(serial: Any, n: int, args: tuple[Any, ...]) -> int:
    """Run a kernel over n rows, a chunk at a time, on this thread and helpers.

    The calling thread and up to (threads - 1) helpers (never more than there are
    chunks after the first) take the next chunk from one counter until none is left:
    a helper that a busy machine does not schedule leaves its share to the others
    instead of holding them up, so two threads are never slower than one by more than
    a chunk. The kernels release the GIL. Returns -1, or the first row (over all
    chunks) that the kernel found invalid.
    """
    step = chunk_rows(args[0].shape[1])
    chunks = (n + step - 1) // step
    helpers = min(numba.get_num_threads() - 1, chunks - 1)
    if helpers <= 0:
        return int(serial(*args, 0, n))
    claim = itertools.count()
    results = [-1] * chunks

    def work() -> None:
        for k in claim:  # chunks are claimed in order, each once (next() holds the GIL)
            if k >= chunks:
                return
            results[k] = int(serial(*args, k * step, min(n, (k + 1) * step)))

    pending = [helper_pool().submit(work) for _ in range(helpers)]
    work()
    for future in pending:  # a helper that has not started has nothing left to do
        if not future.cancel():
            future.result()
    bad = [row for row in results if row >= 0]
    return min(bad) if bad else -1


def chunk_rows(width: int) -> int:
    """Rows per chunk for rows of ``width`` numbers: `CHUNK_NUMBERS`, at least a block."""
    return max(BLOCK, CHUNK_NUMBERS // max(1, width))


_pools: dict[int, ThreadPoolExecutor] = {}


def helper_pool() -> ThreadPoolExecutor:
    """The helper threads of this process, by process id.

    A forked child gets a pool of its own: its copy of the parent's has no threads.
    """
    pid = os.getpid()
    if pid not in _pools:
        _pools.clear()
        workers = max(1, (os.cpu_count() or 1) - 1)
        _pools[pid] = ThreadPoolExecutor(workers, thread_name_prefix="cspace-kernel")
    return _pools[pid]


# --- canonicalize ------------------------------------------------------------------


@jit()
def _canonicalize_range(
    x: FloatArray,
    circles: IntArray,
    rotations: IntArray,
    tolerance: float,
    out: FloatArray,
    start: int,
    stop: int,
) -> int:
    for i in range(start, stop):
        if not _row_ok(x, i, rotations, tolerance):
            return i
        _canonical_row(x, i, circles, rotations, out, i)
    return -1


def canonicalize(
    x: FloatArray, circles: IntArray, rotations: IntArray, tolerance: float, out: FloatArray
) -> int:
    """Set out to the canonical form of every row of x; -1 or the first invalid row."""
    args = (x, circles, rotations, tolerance, out)
    return run_chunks(_canonicalize_range, x.shape[0], args)


# --- distance ----------------------------------------------------------------------


@jit(inline="always")
def _weighted_squares(a: FloatArray, b: FloatArray, w2: FloatArray) -> float:
    """Sum of w2[c] (b[c] - a[c])^2 over a row, in four running sums added in pairs.

    Column c goes into sum c % 4 (the last width % 4 columns into the first). A fixed
    order (no fast-math reassociation), so `_rowwise` gets the same
    bits; four independent sums keep the pipeline full.
    """
    s0 = s1 = s2 = s3 = 0.0
    width = a.shape[0]
    end = width - width % 4
    for c in range(0, end, 4):
        d0, d1 = b[c] - a[c], b[c + 1] - a[c + 1]
        d2, d3 = b[c + 2] - a[c + 2], b[c + 3] - a[c + 3]
        s0 += w2[c] * (d0 * d0)
        s1 += w2[c + 1] * (d1 * d1)
        s2 += w2[c + 2] * (d2 * d2)
        s3 += w2[c + 3] * (d3 * d3)
    for c in range(end, width):
        d = b[c] - a[c]
        s0 += w2[c] * (d * d)
    return (s0 + s1) + (s2 + s3)


@jit()
def _distance_range(
    a: FloatArray,
    b: FloatArray,
    w2: FloatArray,
    circles: IntArray,
    circle_w2: FloatArray,
    rotations: IntArray,
    rotation_w2: FloatArray,
    tolerance: float,
    out: FloatArray,
    start: int,
    stop: int,
) -> int:
    """Distances of rows start..stop, a block of BLOCK rows at a time.

    Each block is read from memory once (the weighted R^1 pass), then its S^1 and SO(3)
    columns come from the cache. A non-unit quaternion makes its row's sum NaN, caught
    with NaN and inf at the end. No fast-math: the plain-Python path gets the same bits.
    """
    sa = 1 if a.shape[0] > 1 else 0
    sb = 1 if b.shape[0] > 1 else 0
    low = (1.0 - tolerance) * (1.0 - tolerance)
    high = (1.0 + tolerance) * (1.0 + tolerance)
    for first in range(start, stop, BLOCK):
        last = min(stop, first + BLOCK)
        for i in range(first, last):
            ia = i * sa
            ib = i * sb
            out[i] = _weighted_squares(a[ia], b[ib], w2)
        for k in range(circles.shape[0]):
            c = circles[k]
            w = circle_w2[k]
            for i in range(first, last):
                d = wrap(b[i * sb, c] - a[i * sa, c])
                out[i] += w * (d * d)
        for k in range(rotations.shape[0]):
            c = rotations[k]
            w = rotation_w2[k]
            for i in range(first, last):
                ia = i * sa
                ib = i * sb
                a0, a1, a2, a3 = a[ia, c], a[ia, c + 1], a[ia, c + 2], a[ia, c + 3]
                b0, b1, b2, b3 = b[ib, c], b[ib, c + 1], b[ib, c + 2], b[ib, c + 3]
                na2 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
                nb2 = b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3
                fa = 1.0 / math.sqrt(na2)
                fb = math.copysign(1.0 / math.sqrt(nb2), a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3)
                m0, m1 = a0 * fa - b0 * fb, a1 * fa - b1 * fb
                m2, m3 = a2 * fa - b2 * fb, a3 * fa - b3 * fb
                p0, p1 = a0 * fa + b0 * fb, a1 * fa + b1 * fb
                p2, p3 = a2 * fa + b2 * fb, a3 * fa + b3 * fb
                # |a - b| / |a + b| = tan(angle / 4): accurate near 0 and pi; |a + b| >= sqrt 2
                m = m0 * m0 + m1 * m1 + m2 * m2 + m3 * m3
                r = math.sqrt(m / (p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3))
                unit = (low <= na2) & (na2 <= high) & (low <= nb2) & (nb2 <= high)
                angle = 4.0 * math.atan(r) if unit else math.nan
                out[i] += w * (angle * angle)
        for i in range(first, last):
            s = out[i]
            if not s < math.inf:  # NaN or inf in the two rows, or a non-unit quaternion
                return i
            out[i] = math.sqrt(s)
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
    """Set out[i] to the weighted product distance of rows a[i], b[i]; -1 or the first bad row.

    ``w2`` holds one squared weight per column for R^1 columns and 0 elsewhere.
    """
    args = (a, b, w2, circles, circle_w2, rotations, rotation_w2, tolerance, out)
    return run_chunks(_distance_range, out.shape[0], args)


# --- interpolate -------------------------------------------------------------------


@jit(inline="always")
def _slerp(
    a: FloatArray,
    ia: int,
    b: FloatArray,
    ib: int,
    c: int,
    t: float,
    out: FloatArray,
    i: int,
    low: float,
    high: float,
) -> None:
    """Set out[i, c:c+4] to the canonical slerp at t from a[ia, c:c+4] to b[ib, c:c+4].

    Along the shorter arc (b or -b); NaN when a quaternion's squared norm is outside
    [low, high].
    """
    a0, a1, a2, a3 = a[ia, c], a[ia, c + 1], a[ia, c + 2], a[ia, c + 3]
    b0, b1, b2, b3 = b[ib, c], b[ib, c + 1], b[ib, c + 2], b[ib, c + 3]
    na2 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
    nb2 = b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3
    unit = (low <= na2) & (na2 <= high) & (low <= nb2) & (nb2 <= high)
    # normalize only what is not unit already (canonical input is): square roots are dear
    fa = 1.0 / math.sqrt(na2) if abs(na2 - 1.0) > _RENORMALIZE else 1.0
    fb = 1.0 / math.sqrt(nb2) if abs(nb2 - 1.0) > _RENORMALIZE else 1.0
    fb = math.copysign(fb, a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3)
    a0, a1, a2, a3 = a0 * fa, a1 * fa, a2 * fa, a3 * fa
    b0, b1, b2, b3 = b0 * fb, b1 * fb, b2 * fb, b3 * fb
    d0, d1, d2, d3 = a0 - b0, a1 - b1, a2 - b2, a3 - b3
    s0, s1, s2, s3 = a0 + b0, a1 + b1, a2 + b2, a3 + b3
    m = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3)
    p = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2 + s3 * s3)
    phi = 2.0 * math.atan(m / p)  # the angle between a and b in R^4; p >= sqrt 2
    sin_phi = 0.5 * m * p  # 2 sin(phi / 2) cos(phi / 2)
    if sin_phi < 1e-9:
        wa, wb = 1.0 - t, t
    else:
        # sin((1 - t) phi) = sin phi cos(t phi) - cos phi sin(t phi): one sine and cosine
        # of the same angle; cos phi = (p^2 - m^2) / 4 for unit a and b
        wb = math.sin(t * phi) / sin_phi
        wa = math.cos(t * phi) - 0.25 * (p * p - m * m) * wb
    h0, h1 = wa * a0 + wb * b0, wa * a1 + wb * b1
    h2, h3 = wa * a2 + wb * b2, wa * a3 + wb * b3
    lead = h0 if h0 != 0.0 else (h1 if h1 != 0.0 else (h2 if h2 != 0.0 else h3))
    nh2 = h0 * h0 + h1 * h1 + h2 * h2 + h3 * h3
    scale = 1.0 / math.sqrt(nh2) if abs(nh2 - 1.0) > _RENORMALIZE else 1.0
    f = math.copysign(scale if unit else math.nan, lead)
    out[i, c] = h0 * f + 0.0
    out[i, c + 1] = h1 * f + 0.0
    out[i, c + 2] = h2 * f + 0.0
    out[i, c + 3] = h3 * f + 0.0


@jit()
def _interpolate_range(
    a: FloatArray,
    b: FloatArray,
    t: FloatArray,
    circles: IntArray,
    rotations: IntArray,
    tolerance: float,
    out: FloatArray,
    start: int,
    stop: int,
) -> int:
    """Interpolate rows start..stop, a block of BLOCK rows at a time (one read from memory)."""
    sa = 1 if a.shape[0] > 1 else 0
    sb = 1 if b.shape[0] > 1 else 0
    st = 1 if t.shape[0] > 1 else 0
    low = (1.0 - tolerance) * (1.0 - tolerance)
    high = (1.0 + tolerance) * (1.0 + tolerance)
    width = out.shape[1]
    for first in range(start, stop, BLOCK):
        last = min(stop, first + BLOCK)
        for i in range(first, last):  # R^1 columns; the others are overwritten below
            ia, ib, ti = i * sa, i * sb, t[i * st]
            for c in range(width):
                out[i, c] = (1.0 - ti) * a[ia, c] + ti * b[ib, c]
        for c in circles:
            for i in range(first, last):
                ti = t[i * st]
                ca = wrap(a[i * sa, c])
                out[i, c] = wrap(ca + ti * _short_way(ca, wrap(b[i * sb, c])))
        for c in rotations:
            for i in range(first, last):
                _slerp(a, i * sa, b, i * sb, c, t[i * st], out, i, low, high)
        for i in range(first, last):
            ti = t[i * st]
            if ti == 0.0 or ti == 1.0:  # exactly the canonical end; both ends must be valid
                if not (
                    _row_ok(a, i * sa, rotations, tolerance)
                    and _row_ok(b, i * sb, rotations, tolerance)
                ):
                    return i
                src, row = (a, i * sa) if ti == 0.0 else (b, i * sb)
                _canonical_row(src, row, circles, rotations, out, i)
            elif not _finite_row(out, i):  # NaN or inf in a, b or t, or a non-unit quaternion
                return i
    return -1


def interpolate(
    a: FloatArray,
    b: FloatArray,
    t: FloatArray,
    circles: IntArray,
    rotations: IntArray,
    tolerance: float,
    out: FloatArray,
) -> int:
    """Set out[i] to the point at t[i] on the shortest path from a[i] to b[i], canonical.

    Exact canonical endpoints at t = 0 and t = 1. Returns -1 or the first bad row.
    """
    args = (a, b, t, circles, rotations, tolerance, out)
    return run_chunks(_interpolate_range, out.shape[0], args)
