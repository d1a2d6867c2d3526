"""Checking a configuration space's inputs against the space: widths, values, weights, limits.

What `ConfigurationSpace` checks before its operations run (on its `SpaceData`), and
how it names what a compiled kernel found wrong. All vectorized: O(rows) NumPy passes,
no Python loop over rows. Shapes and dtypes: `_checks`; scalar arguments:
`_arguments`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from cspace.errors import (
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
    from cspace.space._data import SpaceData


def reweighted(data: SpaceData, weights: object) -> tuple[float, ...]:
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
    valid = list(data.joints) + [s.name for s in data.slots if s.name not in data.joints]
    checked: dict[str, float] = {}
    for name, value in weights.items():
        if name not in valid:
            raise UnknownJointError(
                f"no joint or factor named '{name}'", name=str(name), valid=valid
            )
        checked[name] = weight(value, name)
    return tuple(
        checked.get(s.name, checked.get(s.joint, w))
        for s, w in zip(data.slots, data.weights, strict=True)
    )


def batch(
    data: SpaceData, x: object, what: str = "configuration"
) -> tuple[FloatArray, tuple[int, ...]]:
    """The array as C-contiguous (M, n) float64 rows, and its leading shape."""
    return as_rows(x, data.size, f"a {what} of robot '{data.robot}'")  # type: ignore[arg-type]


def validate(data: SpaceData, rows: FloatArray, lead: tuple[int, ...]) -> None:
    """Raise on NaN/inf or a non-unit quaternion, naming the coordinate and row."""
    check_finite(rows, data.names, lead)
    for slot in data.slots:
        if isinstance(slot.factor, Rotation):
            block = rows[:, slot.columns]
            check_unit(block, slot.name, "quaternion", data.tolerance, lead)


def broadcast(
    data: SpaceData, *arrays: object, t: FloatArray | None = None
) -> tuple[list[FloatArray], tuple[int, ...]]:
    """Rows of each array, broadcast so each has 1 or M rows, and the leading shape.

    ``t``, when given, is broadcast too and comes last, as (1 or M, 1) rows.
    """
    batches = [batch(data, a) for a in arrays]
    if t is not None:
        batches.append(as_rows(t[..., None], 1, "the interpolation parameter t"))
    lead = broadcast_shapes(*(lead for _, lead in batches))
    return [broadcast_rows(r, lead_r, lead) for r, lead_r in batches], lead


def raise_for_row(
    data: SpaceData, row: int, lead: tuple[int, ...], what: str, *arrays: FloatArray
) -> None:
    """Raise the error of the row a kernel found bad: its input's, else an overflow.

    Args:
        data: The configuration space's data.
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
        check_finite(validate_at, data.names, lead, first_row=r)
        for slot in data.slots:
            if isinstance(slot.factor, Rotation):
                block = validate_at[:, slot.columns]
                check_unit(block, slot.name, "quaternion", data.tolerance, lead, first_row=r)
    raise ValueOverflowError(what, row=None if lead == () else row)


def within_limits(
    data: SpaceData, rows: FloatArray, lead: tuple[int, ...], tolerance: object
) -> BoolArray:
    """Whether each factor of each row is within its limits +- tolerance, (factors, M).

    Raises:
        The errors of `validate`; ArgumentError, ArgumentTypeError: ``tolerance``
        is not a finite number >= 0.
    """
    validate(data, rows, lead)
    slack = real_number(tolerance, "tolerance", minimum=0.0)
    inside = np.ones((len(data.slots), len(rows)), dtype=bool)
    for k, slot in enumerate(data.slots):
        inside[k] = slot.factor.contains(rows[:, slot.columns], slack)
    return inside


def contains(data: SpaceData, x: object, tolerance: object) -> bool | BoolArray:
    """`ConfigurationSpace.contains`: whether configurations lie within the limits.

    Returns:
        A bool for one configuration, else a bool array of the leading shape.
    """
    rows, lead = batch(data, x)
    inside = np.all(within_limits(data, rows, lead, tolerance), axis=0)
    return bool(inside[0]) if lead == () else inside.reshape(lead)


def check(data: SpaceData, x: object, tolerance: object) -> None:
    """`ConfigurationSpace.check`: raise for the first coordinate outside its limits."""
    rows, lead = batch(data, x)
    check_limits(data, rows, lead, tolerance)


def check_limits(
    data: SpaceData, rows: FloatArray, lead: tuple[int, ...], tolerance: object
) -> None:
    """Raise OutOfLimitsError for the first factor (then row) outside its limits.

    For a limited ball joint the value is its rotation angle from the identity (rad).
    """
    inside = within_limits(data, rows, lead, tolerance)
    for slot, ok in zip(data.slots, inside, strict=True):
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
