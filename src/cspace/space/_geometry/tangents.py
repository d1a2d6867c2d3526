"""Tangent vectors: the difference of two configurations, and integrating along one.

A tangent vector has ``space.dimension`` entries, factor by factor: R^1 and S^1 one each
(m or rad), SO(3) three, the rotation vector in the frame of the first configuration
(rad). Batches broadcast; every factor works on the whole batch at once.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace.space._checks import (
    FloatArray,
    as_rows,
    broadcast_rows,
    broadcast_shapes,
    check_finite,
    check_overflow,
    output,
)
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry.factors import Factor, unit
from cspace.space._geometry.layout import Target, assemble
from cspace.space._validation import batch, broadcast, validate

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def difference(data: SpaceData, a: ArrayLike, b: ArrayLike) -> FloatArray:
    """The tangent vectors from a to b, shape (..., dimension).

    Raises:
        ValueOverflowError: A difference is beyond a double (coordinates near 1e308).
    """
    (ra, rb), lead = broadcast(data, a, b)
    validate(data, ra, lead)
    validate(data, rb, lead)
    return _per_factor(
        data,
        "the difference",
        lead,
        True,
        lambda f, cols, tan: f.difference(unit(f, ra[:, cols]), unit(f, rb[:, cols])),
    )


def integrate(data: SpaceData, a: ArrayLike, v: ArrayLike) -> FloatArray:
    """The canonical configurations reached from a along v, shape (..., n).

    Raises:
        ValueOverflowError: A coordinate is beyond a double, or a rotation vector's norm.
    """
    rows, lead_a = batch(data, a)
    validate(data, rows, lead_a)
    vs, lead_v = as_rows(v, data.dimension, f"a tangent vector of robot '{data.robot}'")
    check_finite(vs, data.tangent_names, lead_v)
    lead = broadcast_shapes(lead_a, lead_v)
    rows, vs = broadcast_rows(rows, lead_a, lead), broadcast_rows(vs, lead_v, lead)
    out = _per_factor(
        data,
        "the integrated configuration",
        lead,
        False,
        lambda f, cols, tan: f.integrate(unit(f, rows[:, cols]), vs[:, tan]),
    )
    return canonicalize(data, out, None)


def _per_factor(
    data: SpaceData,
    what: str,
    lead: tuple[int, ...],
    tangent: bool,
    op: Callable[[Factor, slice, slice], FloatArray],
) -> FloatArray:
    """``op(factor, its columns, its tangent columns)`` for every factor, as one batch.

    Returns tangent vectors (*lead, dimension) when ``tangent``, else configurations
    (*lead, n), checked for overflow.
    """
    width = data.dimension if tangent else data.size
    out = output(None, (math.prod(lead), width))
    with np.errstate(over="ignore", invalid="ignore"):
        target: Target = "tangent" if tangent else "columns"
        assemble(data.slots, out, target, lambda s: op(s.factor, s.columns, s.tangent))
    check_overflow(out, what, lead)
    return out.reshape(*lead, width)
