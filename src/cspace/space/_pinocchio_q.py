"""Between canonical configurations and Pinocchio's configuration vector q.

Pinocchio's q (length nq) stores a quaternion as (x, y, z, w), an unbounded revolute
joint (and a planar joint's angle) as (cos, sin), everything else as the value. Mimic
joints that Pinocchio had to keep free (the ``mimic-kept-free`` diagnostic) and locked
joints have q entries but no canonical coordinates: ``to_q`` fills them.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace.space._factors import Circle, Rotation
from cspace.space._layout import Slot, assemble
from cspace.space._rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._shape import Space


def from_q(space: Space, q: ArrayLike) -> FloatArray:
    """Canonical configurations (..., n) from Pinocchio's q (..., nq).

    Raises:
        ConfigurationShapeError: The last axis is not nq long.
        NonFiniteValueError: An entry that a coordinate uses is NaN or infinite.
        NotUnitQuaternionError: A quaternion or (cos, sin) pair is not unit.
        SizeLimitError: The result would be too large.
    """
    from cspace.space._checks import as_rows, check_finite, check_unit, output

    rows, lead = as_rows(q, space.nq, f"Pinocchio's q of robot '{space.robot}'")
    out = output(None, (len(rows), space.size))
    names = tuple(f"q[{i}]" for i in range(space.nq))

    def part(slot: Slot) -> FloatArray:
        f, block = slot.factor, rows[:, slot.q]
        check_finite(block, names[slot.q_index :], lead)
        if isinstance(f, Rotation):
            check_unit(block, slot.name, "quaternion in q", space.tolerance, lead)
        elif isinstance(f, Circle) and f.pinocchio == "cos_sin":
            check_unit(block, slot.name, "(cos, sin) pair in q", space.tolerance, lead)
        return f.from_pinocchio(block)

    return assemble(space.slots, out, "columns", part).reshape(*lead, space.size)


def to_q(space: Space, x: ArrayLike) -> FloatArray:
    """Pinocchio's q (..., nq) of configurations (..., n), canonicalized first.

    Raises:
        The errors of `canonicalize`;
        SizeLimitError: q would be too large; ValueOverflowError: a mimic joint's
        ``multiplier * leader + offset`` overflows a double.
    """
    from cspace.space._checks import check_overflow, output

    canonical = space.canonicalize(x)
    lead = canonical.shape[:-1]
    rows = canonical.reshape(math.prod(lead), space.size)
    q = output(None, (len(rows), space.nq))
    q[:] = 0.0
    assemble(space.slots, q, "q", lambda slot: slot.factor.to_pinocchio(rows[:, slot.columns]))
    locked = {f.joint: f.offset for f in space.layout.fills if f.leader is None}
    columns = {c.joint: i for i, c in reversed(list(enumerate(space.coordinates)))}
    for fill in space.layout.fills:
        if fill.leader is None:
            leader: FloatArray | float = 0.0
        elif fill.leader in locked:
            leader = locked[fill.leader]
        else:
            leader = rows[:, columns[fill.leader]]
        with np.errstate(over="ignore", invalid="ignore"):
            value = fill.multiplier * leader + fill.offset
            if fill.cos_sin:
                q[:, fill.q_index] = np.cos(value)
                q[:, fill.q_index + 1] = np.sin(value)
            else:
                q[:, fill.q_index] = value
    check_overflow(q, "Pinocchio's q", lead)
    return q.reshape(*lead, space.nq)
