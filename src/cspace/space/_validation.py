"""Checking a configuration space's inputs against the space: widths, values, weights.

What `ConfigurationSpace` checks before its operations run, and
how it names what a compiled kernel found wrong. All vectorized: O(rows) NumPy passes,
no Python loop over rows. Shapes and dtypes: `_checks`; scalar arguments:
`_arguments`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from cspace.errors import (
    ArgumentError,
    ArgumentTypeError,
    OutOfLimitsError,
    UnknownJointError,
    ValueOverflowError,
)
from cspace.space._arguments import real_number, weight
from cspace.space._checks import (
    BoolArray,
    FloatArray,
    as_rows,
    broadcast_rows,
    broadcast_shapes,
    check_finite,
    check_unit,
)
from cspace.space._geometry import rotations as rotations
from cspace.space._geometry.factors import Rotation, unit

if TYPE_CHECKING:
    from cspace.space._shape import Space


def check_space(space: Space) -> None:
    """Raise unless the space's weights and tolerance are usable (run on construction).

    Raises:
        ArgumentTypeError: ``weights`` is not a sequence, or an entry is not a number.
        ArgumentError: Not one weight per factor, a weight negative, not finite or with
            a square beyond a double, or a tolerance outside [0, 1) (at 1, a zero
            quaternion would pass as unit).
    """
    if not isinstance(space.weights, Sequence):
        raise ArgumentTypeError(
            f"weights must be a sequence, got {type(space.weights).__name__}", argument="weights"
        )
    if len(space.weights) != len(space.slots):
        raise ArgumentError(
            f"weights has {len(space.weights)} entries; the space has {len(space.slots)} "
            "factors, one weight each",
            argument="weights",
        )
    for slot, w in zip(space.slots, space.weights, strict=True):
        weight(w, slot.name)
    real_number(space.tolerance, "tolerance", minimum=0.0, below=1.0)


def reweighted(space: Space, weights: object) -> tuple[float, ...]:
    """One weight per factor: the given ones by joint or factor name, the others kept.

    Raises:
        ArgumentTypeError: ``weights`` is not a mapping, or a weight not a number.
        UnknownJointError: A name is neither a joint with coordinates nor a factor.
        ArgumentError: A weight is negative, not finite, or its square beyond a double.
    """
    if not isinstance(weights, Mapping):
        raise ArgumentTypeError(
            f"weights must map joint or factor names to numbers, got {type(weights).__name__}",
            argument="weights",
        )
    valid = list(space.joints) + [s.name for s in space.slots if s.name not in space.joints]
    checked: dict[str, float] = {}
    for name, value in weights.items():
        if name not in valid:
            raise UnknownJointError(
                f"no joint or factor named '{name}'", name=str(name), valid=valid
            )
        checked[name] = weight(value, name)
    return tuple(
        checked.get(s.name, checked.get(s.joint, w))
        for s, w in zip(space.slots, space.weights, strict=True)
    )


def batch(
    space: Space, x: object, what: str = "configuration"
) -> tuple[FloatArray, tuple[int, ...]]:
    """The array as C-contiguous (M, n) float64 rows, and its leading shape."""
    return as_rows(x, space.size, f"a {what} of robot '{space.robot}'")  # type: ignore[arg-type]


def validate(space: Space, rows: FloatArray, lead: tuple[int, ...]) -> None:
    """Raise on NaN/inf or a non-unit quaternion, naming the coordinate and row."""
    check_finite(rows, space.names, lead)
    for slot in space.slots:
        if isinstance(slot.factor, Rotation):
            block = rows[:, slot.columns]
            check_unit(block, slot.name, "quaternion", space.tolerance, lead)


def broadcast(
    space: Space, *arrays: object, t: FloatArray | None = None
) -> tuple[list[FloatArray], tuple[int, ...]]:
    """Rows of each array, broadcast so each has 1 or M rows, and the leading shape.

    ``t``, when given, is broadcast too and comes last, as (1 or M, 1) rows.
    """
    batches = [batch(space, a) for a in arrays]
    if t is not None:
        batches.append(as_rows(t[..., None], 1, "the interpolation parameter t"))
    lead = broadcast_shapes(*(lead for _, lead in batches))
    return [broadcast_rows(r, lead_r, lead) for r, lead_r in batches], lead


def raise_for_row(
    space: Space, row: int, lead: tuple[int, ...], what: str, *arrays: FloatArray
) -> None:
    """Raise the error of the row a kernel found bad: its input's, else an overflow.

    Args:
        space: The configuration space.
        row: The first bad row (of the broadcast batch).
        lead: The batch's leading shape.
        what: What overflowed, the whole message (``"the distance is not finite: ..."``).
        arrays: The kernel's inputs, with 1 or M rows each.

    Raises:
        NonFiniteValueError, NotUnitQuaternionError: The row's input is bad.
        ValueOverflowError: The input is valid but the result overflowed.
    """
    for rows in arrays:
        r = row if len(rows) > 1 else 0
        validate_at = rows[r : r + 1]
        check_finite(validate_at, space.names, lead, first_row=r)
        for slot in space.slots:
            if isinstance(slot.factor, Rotation):
                block = validate_at[:, slot.columns]
                check_unit(block, slot.name, "quaternion", space.tolerance, lead, first_row=r)
    raise ValueOverflowError(what, row=None if lead == () else row)


def within_limits(
    space: Space, rows: FloatArray, lead: tuple[int, ...], tolerance: object
) -> BoolArray:
    """Whether each factor of each row is within its limits +- tolerance, (factors, M).

    Raises:
        The errors of `validate`; ArgumentError, ArgumentTypeError: ``tolerance``
        is not a finite number >= 0.
    """
    validate(space, rows, lead)
    slack = real_number(tolerance, "tolerance", minimum=0.0)
    inside = np.ones((len(space.slots), len(rows)), dtype=bool)
    for k, slot in enumerate(space.slots):
        inside[k] = slot.factor.contains(rows[:, slot.columns], slack)
    return inside


def check_limits(space: Space, rows: FloatArray, lead: tuple[int, ...], tolerance: object) -> None:
    """Raise OutOfLimitsError for the first factor (then row) outside its limits.

    For a limited ball joint the value is its rotation angle from the identity (rad).
    """
    inside = within_limits(space, rows, lead, tolerance)
    for slot, ok in zip(space.slots, inside, strict=True):
        if ok.all():
            continue
        f = slot.factor
        row = int(np.argmin(ok))
        block = rows[row, slot.columns]
        if isinstance(f, Rotation):  # a limited ball: its rotation angle, rad
            identity = np.array([1.0, 0.0, 0.0, 0.0])
            value = float(rotations.angle_between(unit(f, block), identity, check=False))
            lower, upper = 0.0, f.max_angle
        else:
            value, lower, upper = float(block[0]), f.lower, f.upper
        raise OutOfLimitsError(
            coordinate=slot.name,
            joint=slot.joint,
            value=value,
            lower=lower,
            upper=upper,
            row=None if lead == () else row,
        )
