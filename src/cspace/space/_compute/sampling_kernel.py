"""The compiled kernel of uniform sampling: uniform numbers to configurations, one pass.

`sample` draws every configuration's uniform numbers with
one ``Generator.random`` call, (rows, draws); this kernel maps them, a row at a time,
into the (rows, size) result: R^1 ``lower + span * u``, S^1 the same wrapped into
[-pi, pi), SO(3) Shoemake's map of three numbers onto the unit sphere of R^4, then the
upper hemisphere. `sample` is the same arithmetic in plain
Python for small batches (bit-identical, tested), so the first K configurations of a
sample of N are those of a sample of K whichever runs. A limited ball joint (a rotation
within a largest angle) is not mapped here: its sampling stays in NumPy
(`from_uniform`).
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import TYPE_CHECKING

import numba
import numpy as np

from cspace.space._compute.kernels import (
    TWO_PI,
    canonical_quaternion,
    helper_pool,
    jit,
    run_chunks,
    wrap,
)
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._sampling_plan import SamplingPlan


@jit()
def _sample_range(u: FloatArray, plan: SamplingPlan, out: FloatArray, start: int, stop: int) -> int:
    lines, line_draws, line_low, line_span = plan[0], plan[1], plan[2], plan[3]
    circles, circle_draws, circle_low, circle_span = plan[4], plan[5], plan[6], plan[7]
    rotations, rotation_draws = plan[8], plan[9]
    for i in range(start, stop):
        for k in range(lines.shape[0]):
            out[i, lines[k]] = line_low[k] + line_span[k] * u[i, line_draws[k]]
        for k in range(circles.shape[0]):
            out[i, circles[k]] = wrap(circle_low[k] + circle_span[k] * u[i, circle_draws[k]])
        for k in range(rotations.shape[0]):
            c, d = rotations[k], rotation_draws[k]
            u0 = u[i, d]
            r1, r2 = math.sqrt(1.0 - u0), math.sqrt(u0)
            a1, a2 = TWO_PI * u[i, d + 1], TWO_PI * u[i, d + 2]
            out[i, c] = r2 * math.cos(a2)
            out[i, c + 1] = r1 * math.sin(a1)
            out[i, c + 2] = r1 * math.cos(a1)
            out[i, c + 3] = r2 * math.sin(a2)
            canonical_quaternion(out, i, c, out, i, c)
    return -1


def sample(u: FloatArray, plan: SamplingPlan, out: FloatArray) -> int:
    """Set every row of out from the same row of u (see the module docstring); -1."""
    return run_chunks(_sample_range, out.shape[0], (u, plan, out))


DRAW_ROWS = 1024
"""Rows whose uniform numbers are drawn at a time (38 numbers a row: 300 kB, in L2)."""


def draw_and_map(rng: np.random.Generator, plan: SamplingPlan, out: FloatArray, draws: int) -> None:
    """Fill ``out`` (rows, size): draw DRAW_ROWS rows of uniform numbers, map them, repeat.

    The numbers are the same, in the same order, as one ``rng.random((rows, draws))``.
    With a helper thread (two or more threads), a chunk is mapped on it while the next
    is drawn (both release the GIL), from two buffers in turn.
    """
    rows = out.shape[0]
    buffers = [np.empty((min(rows, DRAW_ROWS), draws)) for _ in range(2)]
    helper = helper_pool() if numba.get_num_threads() > 1 else None
    mapping: tuple[Future[int], FloatArray, FloatArray] | None = None
    for k, start in enumerate(range(0, rows, DRAW_ROWS)):
        u = rng.random(out=buffers[k % 2][: min(DRAW_ROWS, rows - start)])
        _finish(mapping, plan)  # the previous chunk, whose buffer is drawn into next
        target = out[start : start + len(u)]
        if helper is None:
            sample(u, plan, target)
        else:
            mapping = (helper.submit(sample, u, plan, target), u, target)
    _finish(mapping, plan)


def _finish(mapping: tuple[Future[int], FloatArray, FloatArray] | None, plan: SamplingPlan) -> None:
    """Wait for a chunk's mapping, or map it here if the helper has not started it.

    On a busy machine the helper may not be scheduled for a while: waiting for it would
    make two threads slower than one.
    """
    if mapping is None:
        return
    job, u, target = mapping
    if job.cancel():
        sample(u, plan, target)
    else:
        job.result()
