"""The batched operations that run in compiled kernels, or for a few rows in plain Python.

`canonicalize`, `distance` and `interpolate` check their inputs
(`_validation`), pick the engine for the batch (`engine`:
`_rowwise` for a few rows, no numba to load; else
`_kernels`), give it read-only views and the space's columns
(`columns_of`), and turn a bad row into the error that names it. Shapes, units
and conventions are those of the
`ConfigurationSpace` methods of the same names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cspace.space._arguments import parameters
from cspace.space._checks import FloatArray, output
from cspace.space._compute import rowwise as rowwise
from cspace.space._geometry.factors import Circle, Line, Rotation
from cspace.space._validation import batch, broadcast, raise_for_row

if TYPE_CHECKING:
    from cspace.space._shape import Space


@dataclass(frozen=True)
class Columns:
    """Column index arrays and squared weights, as the kernels take them (read-only)."""

    lines: NDArray[np.int64]
    line_w2: FloatArray
    w2: FloatArray  # per column: the squared weight on R^1 columns, 0 elsewhere
    circles: NDArray[np.int64]
    circle_w2: FloatArray
    rotations: NDArray[np.int64]
    rotation_w2: FloatArray


_DISTANCE_OVERFLOW = (
    "the distance is not finite: a coordinate or weight is too large (beyond about 1e154, "
    "weighted squares overflow a double)"
)
_POINT_OVERFLOW = "the interpolated configuration is not finite: a value is beyond a double"


def _readonly(a: np.ndarray[Any, Any]) -> np.ndarray[Any, Any]:
    a.setflags(write=False)
    return a


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


def columns_of(space: Space) -> Columns:
    """The space's R^1, S^1 and SO(3) columns with their factors' squared weights."""
    kinds: dict[type, tuple[list[int], list[float]]] = {
        Line: ([], []),
        Circle: ([], []),
        Rotation: ([], []),
    }
    for slot, w in zip(space.slots, space.weights, strict=True):
        columns, w2 = kinds[type(slot.factor)]
        columns.append(slot.column)
        w2.append(w * w)

    def arrays(kind: type) -> tuple[NDArray[np.int64], FloatArray]:
        columns, w2 = kinds[kind]
        return (
            _readonly(np.array(columns, dtype=np.int64)),
            _readonly(np.array(w2, dtype=np.float64)),
        )

    lines, line_w2 = arrays(Line)
    per_column = np.zeros(space.size)
    per_column[lines] = line_w2
    return Columns(lines, line_w2, _readonly(per_column), *arrays(Circle), *arrays(Rotation))


def canonicalize(space: Space, x: ArrayLike, out: FloatArray | None) -> FloatArray:
    """`ConfigurationSpace.canonicalize`."""
    rows, lead = batch(space, x)
    out = output(out, (*lead, space.size), inputs=(rows,), in_place=rows)
    c = space._columns
    bad = engine(len(rows), space.size).canonicalize(
        _reading(rows), c.circles, c.rotations, space.tolerance, out.reshape(rows.shape)
    )
    if bad >= 0:
        raise_for_row(space, bad, lead, "the canonical form is not finite", rows)
    return out


def distance(
    space: Space, a: ArrayLike, b: ArrayLike, out: FloatArray | None
) -> FloatArray | float:
    """`ConfigurationSpace.distance`."""
    (ra, rb), lead = broadcast(space, a, b)
    out = output(out, lead, inputs=(ra, rb))
    c = space._columns
    bad = engine(math.prod(lead), space.size, exact=False).distance(
        _reading(ra),
        _reading(rb),
        c.w2,
        c.circles,
        c.circle_w2,
        c.rotations,
        c.rotation_w2,
        space.tolerance,
        out.reshape(-1),
    )
    if bad >= 0:
        raise_for_row(space, bad, lead, _DISTANCE_OVERFLOW, ra, rb)
    return float(out.reshape(-1)[0]) if lead == () else out


def interpolate(
    space: Space,
    a: ArrayLike,
    b: ArrayLike,
    t: ArrayLike,
    out: FloatArray | None,
) -> FloatArray:
    """`ConfigurationSpace.interpolate`."""
    (ra, rb, rt), lead = broadcast(space, a, b, t=parameters(t))
    out = output(out, (*lead, space.size), inputs=(ra, rb, rt))
    c = space._columns
    bad = engine(math.prod(lead), space.size).interpolate(
        _reading(ra),
        _reading(rb),
        _reading(rt[:, 0]),
        c.circles,
        c.rotations,
        space.tolerance,
        out.reshape(math.prod(lead), space.size),
    )
    if bad >= 0:
        raise_for_row(space, bad, lead, _POINT_OVERFLOW, ra, rb)
    return out
