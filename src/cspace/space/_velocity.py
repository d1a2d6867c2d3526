"""Between canonical tangent vectors and Pinocchio's velocity v.

The canonical tangent holds, per factor, the rate of a line or an angle and, for a
rotation, the angular velocity in the body frame. Pinocchio's v agrees joint by joint
except for the linear part of a floating or planar joint, which Pinocchio expresses in
the body frame: ``v_linear = R^T (dx, dy, dz)`` with R the joint's rotation (for a planar
joint, the rotation by theta in the plane). So the map needs the configuration.

Mimic joints that Pinocchio keeps free have v entries of their own: ``multiplier *
leader velocity``; locked joints: 0.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace._joint_kind import JointKind
from cspace.space._checks import as_rows, broadcast_rows, broadcast_shapes, check_finite
from cspace.space._joint_blocks import Follower, JointBlock
from cspace.space._rotations import FloatArray, matrix_from_quaternion

if TYPE_CHECKING:
    from cspace.space._shape import Space


def _rows(
    space: Space, x: ArrayLike, d: ArrayLike, width: int, what: str
) -> tuple[FloatArray, FloatArray, tuple[int, ...]]:
    """Canonical configurations and velocities as rows broadcast against each other."""
    canonical = space.canonicalize(x)
    xs, lead_x = as_rows(canonical, space.size, f"a configuration of robot '{space.robot}'")
    ds, lead_d = as_rows(d, width, what)
    full = broadcast_shapes(lead_x, lead_d)
    return broadcast_rows(xs, lead_x, full), broadcast_rows(ds, lead_d, full), full


def _rotation(block: JointBlock, xs: FloatArray) -> FloatArray:
    """(M, 3, 3) world-from-body rotations of a floating joint, (M, 2, 2) of a planar one."""
    start = block.columns.start
    if block.kind is JointKind.FLOATING:
        return matrix_from_quaternion(xs[:, start + 3 : start + 7], check=False)
    theta = xs[:, start + 2]
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)


def _linear(block: JointBlock) -> int:
    return {JointKind.FLOATING: 3, JointKind.PLANAR: 2}.get(block.kind, 0)


def to_v(
    space: Space,
    blocks: Mapping[str, JointBlock],
    followers: Mapping[str, Follower],
    x: ArrayLike,
    dx: ArrayLike,
) -> FloatArray:
    """Pinocchio's v (..., nv) of tangent vectors dx (..., dimension) at configurations x."""
    what = f"a tangent vector of robot '{space.robot}'"
    xs, ds, lead = _rows(space, x, dx, space.dimension, what)
    check_finite(ds, space.tangent_names, lead)
    nv = sum(j.nv for j in space.report_joints)
    v = np.zeros((math.prod(lead), nv))
    for block in blocks.values():
        width = block.tangent.stop - block.tangent.start
        out = v[:, block.v_index : block.v_index + width]
        out[:] = ds[:, block.tangent]
        k = _linear(block)
        if k:  # world-frame rates -> body-frame linear velocity: R^T (dx, dy, dz)
            r = np.swapaxes(_rotation(block, xs), -1, -2)
            out[:, :k] = np.matmul(r, ds[:, block.tangent.start : block.tangent.start + k, None])[
                ..., 0
            ]
    for f in followers.values():
        leader = blocks.get(f.leader) if f.leader is not None else None
        if f.v_index is not None and leader is not None:
            v[:, f.v_index] = f.multiplier * ds[:, int(leader.tangent.start)]
    return v.reshape(*lead, nv)


def from_v(
    space: Space,
    blocks: Mapping[str, JointBlock],
    x: ArrayLike,
    v: ArrayLike,
) -> FloatArray:
    """Tangent vectors (..., dimension) of Pinocchio's v (..., nv) at configurations x."""
    nv = sum(j.nv for j in space.report_joints)
    xs, vs, lead = _rows(space, x, v, nv, f"Pinocchio's v of robot '{space.robot}'")
    check_finite(vs, [f"v[{i}]" for i in range(nv)], lead)
    dx = np.zeros((math.prod(lead), space.dimension))
    for block in blocks.values():
        width = block.tangent.stop - block.tangent.start
        out = dx[:, block.tangent]
        out[:] = vs[:, block.v_index : block.v_index + width]
        k = _linear(block)
        if k:  # body-frame linear velocity -> world-frame rates: R v
            r = _rotation(block, xs)
            out[:, :k] = np.matmul(r, vs[:, block.v_index : block.v_index + k, None])[..., 0]
    return dx.reshape(*lead, space.dimension)
