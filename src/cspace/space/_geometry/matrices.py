"""Rotation matrices of a configuration's S^1 and SO(3) factors, and back.

SO(3) factors give (..., 3, 3) matrices acting on column vectors, S^1 factors SO(2)
matrices [[cos, -sin], [sin, cos]], (..., 2, 2), of their angle (rad).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace._sizes import check_size
from cspace.errors import ArgumentTypeError, NotARotationError, UnknownJointError
from cspace.space._checks import FloatArray, broadcast_shapes
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry import rotations as rotations
from cspace.space._geometry.factors import Circle, Line, Rotation
from cspace.space._geometry.layout import Slot

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def rotation_slot(data: SpaceData, name: str) -> Slot:
    """The S^1 or SO(3) factor called ``name`` (or the joint's only such factor).

    Raises:
        ArgumentTypeError: ``name`` is not a string.
        UnknownJointError: No such factor, or the joint has several.
    """
    if not isinstance(name, str):
        raise ArgumentTypeError(
            f"a factor or joint name is a string, got {type(name).__name__}", argument="name"
        )
    turning = [s for s in data.slots if not isinstance(s.factor, Line)]
    found = [s for s in turning if s.name == name]
    if not found:
        found = [s for s in turning if s.joint == name]
    if len(found) != 1:
        raise UnknownJointError(
            f"'{name}' is not one S^1 or SO(3) factor",
            name=str(name),
            valid=[s.name for s in turning],
        )
    return found[0]


def matrix(data: SpaceData, x: ArrayLike, name: str) -> FloatArray:
    """The rotation matrices (..., 3, 3) or (..., 2, 2) of one factor of configurations."""
    slot = rotation_slot(data, name)
    rows = canonicalize(data, x, None)
    block = rows[..., slot.columns]
    if isinstance(slot.factor, Rotation):
        return Rotation.matrix_from_wxyz(block)
    return Circle.matrix_from_angle(block)


def with_matrix(data: SpaceData, x: ArrayLike, name: str, matrix: ArrayLike) -> FloatArray:
    """Configurations (..., n) with one factor set from rotation matrices, broadcast.

    Raises:
        ArgumentTypeError, ConfigurationShapeError: ``matrix`` is not an array of real
            3 x 3 (SO(3)) or 2 x 2 (S^1) matrices.
        NotARotationError: A matrix is not a rotation.
    """
    slot = rotation_slot(data, name)
    if isinstance(slot.factor, Rotation):
        value = Rotation.wxyz_from_matrix(matrix)  # type: ignore[arg-type]
    else:
        good = rotations.is_rotation_matrix(matrix, data.tolerance, dim=2)  # type: ignore[arg-type]
        if not good.all():
            raise NotARotationError(
                f"not a 2 x 2 rotation matrix for '{slot.name}'",
                row=None if good.ndim == 0 else int(np.argmax(~good.reshape(-1))),
            )
        value = Circle.angle_from_matrix(np.asarray(matrix, dtype=np.float64))
    rows = canonicalize(data, x, None)
    lead = broadcast_shapes(rows.shape[:-1], value.shape[:-1])
    check_size((*lead, data.size))
    out = np.array(np.broadcast_to(rows, (*lead, data.size)))
    out[..., slot.columns] = value
    return out
