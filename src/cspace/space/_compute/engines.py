"""The batched operations that run in compiled kernels, or for a few rows in plain Python.

`canonicalize`, `distance` and `interpolate` check their inputs
(`_validation`), pick the engine for the batch (`engine`:
`_rowwise` for a few rows, no numba to load; else
`_kernels`), give it read-only views and the space's columns
(`SpaceData.columns`), and turn a bad row into the error that names it. Shapes, units
and conventions are those of the
`ConfigurationSpace` methods of the same names.
"""

from __future__ import annotations

import math
from types import ModuleType
from typing import TYPE_CHECKING

from numpy.typing import ArrayLike

from cspace.space._arguments import parameters
from cspace.space._checks import FloatArray, output
from cspace.space._compute import rowwise as rowwise
from cspace.space._validation import batch, broadcast, raise_for_row

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


_DISTANCE_OVERFLOW = (
    "the distance is not finite: a coordinate or weight is too large (beyond about 1e154, "
    "weighted squares overflow a double)"
)
_POINT_OVERFLOW = "the interpolated configuration is not finite: a value is beyond a double"


def _reading(a: FloatArray) -> FloatArray:
    """A read-only view of a kernel's input (no copy).

    numba compiles one specialisation per array type, and a read-only array is another
    type: every input is passed read-only, so a caller's read-only array (a memory map,
    a frozen buffer) loads the same cached kernel instead of compiling a new one.
    """
    view = a.view()
    view.flags.writeable = False
    return view


def engine(rows: int, size: int, exact: bool = True) -> ModuleType:
    """The module that runs a batch: plain Python when small (`rowwise.takes`)."""
    if rowwise.takes(rows, size, exact):
        return rowwise
    from cspace.space._compute import kernels as kernels

    return kernels


def canonicalize(data: SpaceData, x: ArrayLike, out: FloatArray | None) -> FloatArray:
    """`ConfigurationSpace.canonicalize`."""
    rows, lead = batch(data, x)
    out = output(out, (*lead, data.size), inputs=(rows,), in_place=rows)
    c = data.columns
    bad = engine(len(rows), data.size).canonicalize(
        _reading(rows), c.circles, c.rotations, data.tolerance, out.reshape(rows.shape)
    )
    if bad >= 0:
        raise_for_row(data, bad, lead, "the canonical form is not finite", rows)
    return out


def distance(
    data: SpaceData, a: ArrayLike, b: ArrayLike, out: FloatArray | None
) -> FloatArray | float:
    """`ConfigurationSpace.distance`."""
    (ra, rb), lead = broadcast(data, a, b)
    out = output(out, lead, inputs=(ra, rb))
    c = data.columns
    bad = engine(math.prod(lead), data.size, exact=False).distance(
        _reading(ra),
        _reading(rb),
        c.w2,
        c.circles,
        c.circle_w2,
        c.rotations,
        c.rotation_w2,
        data.tolerance,
        out.reshape(-1),
    )
    if bad >= 0:
        raise_for_row(data, bad, lead, _DISTANCE_OVERFLOW, ra, rb)
    return float(out.reshape(-1)[0]) if lead == () else out


def interpolate(
    data: SpaceData,
    a: ArrayLike,
    b: ArrayLike,
    t: ArrayLike,
    out: FloatArray | None,
) -> FloatArray:
    """`ConfigurationSpace.interpolate`."""
    (ra, rb, rt), lead = broadcast(data, a, b, t=parameters(t))
    out = output(out, (*lead, data.size), inputs=(ra, rb, rt))
    c = data.columns
    bad = engine(math.prod(lead), data.size).interpolate(
        _reading(ra),
        _reading(rb),
        _reading(rt[:, 0]),
        c.circles,
        c.rotations,
        data.tolerance,
        out.reshape(math.prod(lead), data.size),
    )
    if bad >= 0:
        raise_for_row(data, bad, lead, _POINT_OVERFLOW, ra, rb)
    return out
