"""Between canonical configurations and ``{joint name: value}`` mappings (JSON-friendly).

A one-coordinate joint's value is a number; other joints give a list in coordinate
order: planar [x, y, theta], floating [x, y, z, qw, qx, qy, qz], spherical
[qw, qx, qy, qz], translation [x, y, z], universal [axis1, axis2].
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from cspace.errors import (
    ConfigurationShapeError,
    JointValueError,
    MissingJointError,
    UnknownJointError,
)
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def _number(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _float(joint: str, value: Any) -> float:
    """A joint's number as a float; an int beyond a double is a JointValueError."""
    try:
        return float(value)
    except OverflowError:
        raise JointValueError(
            f"joint '{joint}' has a value too large for a double", joint=joint, value=value
        ) from None


def from_mapping(
    data: SpaceData, values: Mapping[str, Any], default: ArrayLike | None
) -> FloatArray:
    """A canonical configuration (n,) from ``{joint: value}``; see the module docstring."""
    columns = data.layout.joint_columns
    if not isinstance(values, Mapping):
        raise JointValueError(
            f"a configuration must map joint names to values, got {type(values).__name__}",
            joint="",
            value=values,
        )
    for name in values:
        if name not in columns:
            problem = (
                f"joint '{name}' has no coordinates (fixed, mimic or locked)"
                if name in data.other_joints
                else f"robot '{data.robot}' has no joint '{name}'"
            )
            raise UnknownJointError(problem, name=str(name), valid=data.joints)
    missing = [j for j in data.joints if j not in values]
    if missing and default is None:
        raise MissingJointError(missing)
    x = np.empty(data.size)
    if default is not None:
        base = canonicalize(data, default, None)
        if base.shape != (data.size,):
            raise ConfigurationShapeError(
                f"default must be one configuration of shape ({data.size},), got {base.shape}",
                expected=data.size,
                shape=base.shape,
            )
        x[:] = base
    for joint, value in values.items():
        cols = columns[joint]
        width = cols.stop - cols.start
        if width == 1 and _number(value):
            x[cols] = _float(joint, value)
        elif (
            width > 1
            and isinstance(value, Sequence | np.ndarray)
            and not isinstance(value, str)
            and len(value) == width
            and all(_number(v) for v in value)
        ):
            x[cols] = [_float(joint, v) for v in value]
        else:
            shape = "a number" if width == 1 else f"a list of {width} numbers"
            names = ", ".join(data.names[cols])
            raise JointValueError(
                f"joint '{joint}' needs {shape} ({names}), got {value!r}", joint=joint, value=value
            )
    return canonicalize(data, x, None)


def to_mapping(data: SpaceData, x: ArrayLike) -> dict[str, float | list[float]]:
    """``{joint: value}`` of one canonical configuration (n,), in tree order."""
    from cspace.space._checks import as_rows

    _, lead = as_rows(x, data.size, f"a configuration of robot '{data.robot}'")
    if lead != ():
        raise JointValueError(
            f"to_dict takes one configuration of shape ({data.size},), got a batch {lead}",
            joint="",
            value=None,
        )
    canonical = canonicalize(data, x, None)
    out: dict[str, float | list[float]] = {}
    for joint, cols in data.layout.joint_columns.items():
        block = [float(v) for v in canonical[cols]]
        out[joint] = block[0] if len(block) == 1 else block
    return out
