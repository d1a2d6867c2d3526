"""Between canonical vectors and values named by joint, in a given order (ROS JointState).

A ROS ``sensor_msgs/JointState`` holds one position (and velocity) per named joint, in
any order: a revolute or prismatic joint's value, a continuous joint's angle (any
angle; it is wrapped on the way in). Joints with several coordinates (floating, planar,
spherical) have no place in it. Mimic and locked joints may be listed: their values
follow from the others (a mimic joint's is ``multiplier * leader + offset``), so reading
ignores them and writing computes them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace.errors import JointMatchError
from cspace.space._checks import as_rows, check_finite, output
from cspace.space._compute.engines import canonicalize
from cspace.space._conventions._joint_blocks import Follower, JointBlock
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def check_names(
    data: SpaceData,
    blocks: Mapping[str, JointBlock],
    followers: Mapping[str, Follower],
    names: Sequence[str],
) -> list[str]:
    """The names as a list.

    Raises:
        JointMatchError: A name is repeated, unknown, a fixed joint's, or a joint with
            several coordinates.
    """
    names = [str(n) for n in names]
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise JointMatchError(f"joint '{name}' is named twice", joints=[name])
        seen.add(name)
        block = blocks.get(name)
        if block is not None and block.columns.stop - block.columns.start != 1:
            width = block.columns.stop - block.columns.start
            raise JointMatchError(
                f"joint '{name}' ({block.kind.value}) has {width} coordinates; a named "
                "vector (ROS JointState) holds one number per joint",
                joints=[name],
            )
        if block is None and name not in followers:
            why = "has no position (a fixed joint)" if name in data.other_joints else "is unknown"
            ones = [b for b, blk in blocks.items() if blk.columns.stop - blk.columns.start == 1]
            raise JointMatchError(
                f"joint '{name}' {why}: robot '{data.robot}' names " + ", ".join(ones[:20]),
                joints=[name],
            )
    return names


def to_named(
    data: SpaceData,
    blocks: Mapping[str, JointBlock],
    followers: Mapping[str, Follower],
    x: ArrayLike,
    names: Sequence[str],
    velocity: bool,
) -> FloatArray:
    """Values (..., len(names)) of configurations (or tangent vectors) (..., n)."""
    names = check_names(data, blocks, followers, names)
    if velocity:
        rows, lead = as_rows(x, data.dimension, f"a tangent vector of robot '{data.robot}'")
        check_finite(rows, data.tangent_names, lead)
    else:
        canonical = canonicalize(data, x, None)
        lead = canonical.shape[:-1]
        rows = canonical.reshape(math.prod(lead), data.size)
    out = output(None, (len(rows), len(names)))

    def column(joint: str) -> int:
        block = blocks[joint]
        return int((block.tangent if velocity else block.columns).start)

    for k, name in enumerate(names):
        if name in blocks:
            out[:, k] = rows[:, column(name)]
            continue
        f = followers[name]
        if f.leader is None:  # a locked joint
            out[:, k] = 0.0 if velocity else f.offset
        elif f.leader in blocks:  # a mimic joint
            value = f.multiplier * rows[:, column(f.leader)]
            out[:, k] = value if velocity else value + f.offset
        else:  # a mimic of a locked joint
            out[:, k] = 0.0 if velocity else f.multiplier * followers[f.leader].offset + f.offset
    return out.reshape(*lead, len(names))


def from_named(
    data: SpaceData,
    blocks: Mapping[str, JointBlock],
    followers: Mapping[str, Follower],
    values: ArrayLike,
    names: Sequence[str],
    default: ArrayLike | None,
    velocity: bool,
) -> FloatArray:
    """Configurations (or tangent vectors) (..., n) of named values (..., len(names)).

    Joints not named take their value from ``default`` (a configuration or tangent
    vector broadcast against the values); without one, every joint with coordinates
    must be named.
    """
    names = check_names(data, blocks, followers, names)
    width = data.dimension if velocity else data.size
    rows, lead = as_rows(values, len(names), f"named values of robot '{data.robot}'")
    check_finite(rows, names, lead)
    given = set(names)
    missing = [j for j in blocks if j not in given]
    if missing and default is None:
        raise JointMatchError(
            f"no value for joint(s) {', '.join(missing[:10])}"
            + (f", ... ({len(missing)} in all)" if len(missing) > 10 else "")
            + "; give them, or a default configuration",
            joints=missing,
        )
    out = np.empty((len(rows), width))
    if default is not None:
        base, shape = as_rows(default, width, "default")
        if shape != ():
            raise JointMatchError(f"default must be one vector of {width} entries, not a batch")
        out[:] = canonicalize(data, base[0], None) if not velocity else base[0]
    for k, name in enumerate(names):
        block = blocks.get(name)
        if block is not None:
            out[:, (block.tangent if velocity else block.columns).start] = rows[:, k]
    result = out.reshape(*lead, width)
    return result if velocity else canonicalize(data, result, None)
