"""Checking and shaping the arrays that configuration operations take and make.

Every configuration operation (and every function of `_rotations`) turns
its input into C-contiguous float64 rows of shape (M, width) plus the leading shape,
broadcasts batches against each other, and raises a
`ConfigurationError` subclass that names the coordinate and the
row (in a batch) when something is wrong. Arrays of anything but real numbers
(strings, objects, complex, bool) are refused rather than converted. Every array
allocated here is first checked against `MAX_ARRAY_BYTES`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cspace._sizes import check_size
from cspace.errors import (
    ArgumentError,
    ArgumentTypeError,
    ConfigurationError,
    ConfigurationShapeError,
    NonFiniteValueError,
    NotUnitQuaternionError,
    ValueOverflowError,
)

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

_REAL_KINDS = "fiu"
"""NumPy dtype kinds taken as numbers: floating point, signed and unsigned integers."""


def real_array(x: ArrayLike, what: str) -> FloatArray:
    """``x`` as a float64 array of any shape (not copied when it is one already).

    Raises:
        ArgumentTypeError: ``x`` is not an array of real numbers: ragged, or of strings,
            objects, complex numbers or bools (NumPy would convert some of them silently).
        SizeLimitError: The float64 copy would be too large.
    """
    try:
        arr = np.asarray(x)
    except (TypeError, ValueError, OverflowError) as exc:
        raise ArgumentTypeError(f"{what} must be an array of numbers ({exc})") from None
    if arr.dtype.kind not in _REAL_KINDS:
        raise ArgumentTypeError(
            f"{what} must be an array of real numbers (float or int), got dtype {arr.dtype}"
        )
    if arr.dtype != np.float64:
        check_size(arr.shape, f"{what} converted to float64")
        with np.errstate(over="ignore"):  # long doubles beyond a double: inf, caught later
            arr = arr.astype(np.float64)
    return arr


def as_rows(x: ArrayLike, size: int, what: str) -> tuple[FloatArray, tuple[int, ...]]:
    """``x`` as C-contiguous (M, size) float64 rows, and its leading shape.

    Raises:
        ArgumentTypeError: ``x`` is not an array of real numbers.
        ConfigurationShapeError: Its last axis is not ``size`` long.
        SizeLimitError: A contiguous copy would be too large.
    """
    arr = real_array(x, what)
    if arr.ndim == 0 or arr.shape[-1] != size:
        raise ConfigurationShapeError(
            f"{what} has {size} coordinates, got an array of shape {arr.shape}",
            expected=size,
            shape=tuple(arr.shape),
        )
    lead = tuple(arr.shape[:-1])
    if not arr.flags.c_contiguous:
        check_size(arr.shape, f"a contiguous copy of {what}")
    return np.ascontiguousarray(arr.reshape(math.prod(lead), size)), lead


def output(
    out: FloatArray | None,
    shape: tuple[int, ...],
    inputs: Sequence[FloatArray] = (),
    in_place: FloatArray | None = None,
) -> FloatArray:
    """A new array of ``shape``, or ``out`` when it is a writable C-contiguous one.

    Args:
        out: The caller's buffer, or None.
        shape: The result's shape.
        inputs: The arrays the operation reads while it writes ``out``: ``out`` must
            not overlap them (the result would be computed from half-written input).
        in_place: An input that ``out`` may be exactly (same memory), for operations
            that finish reading each row before writing it.

    Raises:
        ConfigurationShapeError: ``out`` has the wrong shape, dtype or layout.
        ArgumentError: ``out`` overlaps an input.
        SizeLimitError: A new array would be too large.
    """
    if out is None:
        check_size(shape)
        return np.empty(shape)
    if (
        not isinstance(out, np.ndarray)
        or out.shape != shape
        or out.dtype != np.float64
        or not out.flags.c_contiguous
        or not out.flags.writeable
    ):
        got = getattr(out, "shape", type(out).__name__)
        raise ConfigurationShapeError(
            f"out must be a writable C-contiguous float64 array of shape {shape}, got {got}",
            expected=shape[-1] if shape else 1,
            shape=tuple(getattr(out, "shape", ())),
        )
    same = in_place is not None and out.ctypes.data == in_place.ctypes.data
    for arr in inputs:
        if np.may_share_memory(out, arr) and not (same and arr is in_place):
            raise ArgumentError(
                "out overlaps an input: the result would be computed from overwritten values",
                argument="out",
            )
    return out


def broadcast_shapes(*shapes: tuple[int, ...]) -> tuple[int, ...]:
    """NumPy's broadcast of leading shapes, or a ConfigurationError naming them."""
    try:
        return tuple(np.broadcast_shapes(*shapes))
    except ValueError:
        shown = ", ".join(str(s) for s in shapes)
        raise ConfigurationError(f"batch shapes do not broadcast: {shown}") from None


def broadcast_rows(rows: FloatArray, lead: tuple[int, ...], full: tuple[int, ...]) -> FloatArray:
    """Rows with 1 or prod(full) entries (a copy only when partial broadcasting needs it).

    Raises:
        SizeLimitError: The copy would be too large.
    """
    if lead == full or math.prod(lead) == 1:
        return rows
    width = rows.shape[1]
    check_size((math.prod(full), width), f"a batch broadcast to shape {full}")
    spread = np.broadcast_to(rows.reshape(*lead, width), (*full, width))
    return np.ascontiguousarray(spread).reshape(math.prod(full), width)


def check_finite(
    rows: FloatArray, names: Sequence[str], lead: tuple[int, ...], first_row: int = 0
) -> None:
    """Raise NonFiniteValueError for the first NaN or inf, naming its coordinate and row."""
    finite = np.isfinite(rows)
    if not finite.all():
        row, col = (int(i) for i in np.argwhere(~finite)[0])
        raise NonFiniteValueError(
            f"coordinate '{names[col]}' is {float(rows[row, col])!r}",
            coordinate=names[col],
            row=None if lead == () else row + first_row,
        )


def check_unit(
    block: FloatArray,
    name: str,
    what: str,
    tolerance: float,
    lead: tuple[int, ...],
    first_row: int = 0,
) -> None:
    """Raise NotUnitQuaternionError for the first row of ``block`` whose norm is not 1."""
    with np.errstate(over="ignore"):  # a norm beyond a double is inf: not 1 either
        norms = np.linalg.norm(block, axis=-1)
    bad = ~(np.abs(norms - 1.0) <= tolerance)
    if bad.any():
        row = int(np.argmax(bad))
        raise NotUnitQuaternionError(
            f"{what} of '{name}' has norm {float(norms[row])!r}, not 1 (tolerance {tolerance:g})",
            norm=float(norms[row]),
            tolerance=tolerance,
            coordinate=name,
            row=None if lead == () else row + first_row,
        )


def check_overflow(rows: FloatArray, what: str, lead: tuple[int, ...]) -> None:
    """Raise ValueOverflowError when a result row (M, width) of finite inputs is not finite.

    Raises:
        ValueOverflowError: An entry overflowed; the row is named in a batch.
    """
    bad = ~np.isfinite(rows)
    if bad.any():
        row = int(np.argmax(bad.any(axis=-1)))
        raise ValueOverflowError(
            f"{what} is not finite: a value is too large for a double (beyond about 1.8e308)",
            row=None if lead == () else row,
        )
