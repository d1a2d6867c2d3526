"""Checking and shaping the arrays that configuration operations take.

Every configuration operation turns its input into C-contiguous float64 rows of shape
(M, width) plus the leading shape, broadcasts batches against each other, and raises
a :class:`~cspace.errors.ConfigurationError` subclass that names the coordinate and
the row (in a batch) when something is wrong.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .errors import (
    ConfigurationError,
    ConfigurationShapeError,
    NonFiniteValueError,
    NotUnitQuaternionError,
)
from .factors import Circle, Line, Rotation
from .rotations import FloatArray


def output(out: FloatArray | None, shape: tuple[int, ...]) -> FloatArray:
    """A new array of ``shape``, or ``out`` when it is a writable C-contiguous one."""
    if out is None:
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
    return out


def unit(f: Line | Circle | Rotation, block: FloatArray) -> FloatArray:
    """Quaternions normalized (already validated); other blocks as they are."""
    if isinstance(f, Rotation):
        return np.asarray(block / np.linalg.norm(block, axis=-1, keepdims=True))
    return block


def as_rows(x: ArrayLike, size: int, what: str) -> tuple[FloatArray, tuple[int, ...]]:
    """``x`` as C-contiguous (M, size) float64 rows, and its leading shape.

    Raises:
        ConfigurationError: ``x`` is not an array of numbers.
        ConfigurationShapeError: Its last axis is not ``size`` long.
    """
    try:
        arr = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ConfigurationError(f"{what} must be an array of numbers ({exc})") from None
    if arr.ndim == 0 or arr.shape[-1] != size:
        raise ConfigurationShapeError(
            f"{what} has {size} coordinates, got an array of shape {arr.shape}",
            expected=size,
            shape=tuple(arr.shape),
        )
    lead = tuple(arr.shape[:-1])
    return np.ascontiguousarray(arr.reshape(math.prod(lead), size)), lead


def broadcast_shapes(*shapes: tuple[int, ...]) -> tuple[int, ...]:
    """NumPy's broadcast of leading shapes, or a ConfigurationError naming them."""
    try:
        return tuple(np.broadcast_shapes(*shapes))
    except ValueError:
        shown = ", ".join(str(s) for s in shapes)
        raise ConfigurationError(f"batch shapes do not broadcast: {shown}") from None


def expand(rows: FloatArray, lead: tuple[int, ...], full: tuple[int, ...]) -> FloatArray:
    """Rows with 1 or prod(full) entries (a copy only when partial broadcasting needs it)."""
    if lead == full or math.prod(lead) == 1:
        return rows
    width = rows.shape[1]
    spread = np.broadcast_to(rows.reshape(*lead, width), (*full, width))
    return np.ascontiguousarray(spread).reshape(math.prod(full), width)


def check_finite(
    rows: FloatArray, names: tuple[str, ...], lead: tuple[int, ...], offset: int = 0
) -> None:
    """Raise NonFiniteValueError for the first NaN or inf, naming its coordinate and row."""
    finite = np.isfinite(rows)
    if not finite.all():
        row, col = (int(i) for i in np.argwhere(~finite)[0])
        raise NonFiniteValueError(
            f"coordinate '{names[col]}' is {float(rows[row, col])!r}",
            coordinate=names[col],
            row=None if lead == () else row + offset,
        )


def check_unit(
    block: FloatArray,
    name: str,
    what: str,
    tolerance: float,
    lead: tuple[int, ...],
    offset: int = 0,
) -> None:
    """Raise NotUnitQuaternionError for the first row of ``block`` whose norm is not 1."""
    norms = np.linalg.norm(block, axis=-1)
    bad = np.abs(norms - 1.0) > tolerance
    if bad.any():
        row = int(np.argmax(bad))
        raise NotUnitQuaternionError(
            f"{what} of '{name}' has norm {float(norms[row])!r}, not 1 (tolerance {tolerance:g})",
            norm=float(norms[row]),
            tolerance=tolerance,
            coordinate=name,
            row=None if lead == () else row + offset,
        )
