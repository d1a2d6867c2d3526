"""Pinocchio's convention: its configuration vector q and velocity v.

Pinocchio's q (length nq) stores a quaternion as (x, y, z, w), an unbounded revolute
joint (and a planar joint's angle) as (cos, sin), everything else as the value. Mimic
joints that Pinocchio had to keep free (the ``mimic-kept-free`` diagnostic) and locked
joints have q entries but no canonical coordinates: ``to_q`` fills them.

The canonical tangent holds, per factor, the rate of a line or an angle and, for a
rotation, the angular velocity in the body frame. Pinocchio's v agrees joint by joint
except for the linear part of a floating or planar joint, which Pinocchio expresses in
the body frame: ``v_linear = R^T (dx, dy, dz)`` with R the joint's rotation (for a planar
joint, the rotation by theta in the plane). So the map needs the configuration. Mimic
joints that Pinocchio keeps free have v entries of their own: ``multiplier * leader
velocity``; locked joints: 0.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace._joint_kind import JointKind
from cspace.space._checks import check_finite
from cspace.space._compute.engines import canonicalize
from cspace.space._conventions._joint_blocks import Follower, JointBlock
from cspace.space._conventions._maps import Robot, rows_at
from cspace.space._geometry.factors import Circle, Rotation
from cspace.space._geometry.layout import Slot, assemble
from cspace.space._geometry.rotations import FloatArray, matrix_from_quaternion

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def from_q(data: SpaceData, q: ArrayLike) -> FloatArray:
    """Canonical configurations (..., n) from Pinocchio's q (..., nq).

    Raises:
        ConfigurationShapeError: The last axis is not nq long.
        NonFiniteValueError: An entry that a coordinate uses is NaN or infinite.
        NotUnitQuaternionError: A quaternion or (cos, sin) pair is not unit.
        SizeLimitError: The result would be too large.
    """
    from cspace.space._checks import as_rows, check_finite, check_unit, output

    rows, lead = as_rows(q, data.nq, f"Pinocchio's q of robot '{data.robot}'")
    out = output(None, (len(rows), data.size))
    names = tuple(f"q[{i}]" for i in range(data.nq))

    def part(slot: Slot) -> FloatArray:
        f, block = slot.factor, rows[:, slot.q]
        check_finite(block, names[slot.q_index :], lead)
        if isinstance(f, Rotation):
            check_unit(block, slot.name, "quaternion in q", data.tolerance, lead)
        elif isinstance(f, Circle) and f.pinocchio == "cos_sin":
            check_unit(block, slot.name, "(cos, sin) pair in q", data.tolerance, lead)
        return f.from_pinocchio(block)

    return assemble(data.slots, out, "columns", part).reshape(*lead, data.size)


def to_q(data: SpaceData, x: ArrayLike) -> FloatArray:
    """Pinocchio's q (..., nq) of configurations (..., n), canonicalized first.

    Raises:
        The errors of `canonicalize`;
        SizeLimitError: q would be too large; ValueOverflowError: a mimic joint's
        ``multiplier * leader + offset`` overflows a double.
    """
    from cspace.space._checks import check_overflow, output

    canonical = canonicalize(data, x, None)
    lead = canonical.shape[:-1]
    rows = canonical.reshape(math.prod(lead), data.size)
    q = output(None, (len(rows), data.nq))
    q[:] = 0.0
    assemble(data.slots, q, "q", lambda slot: slot.factor.to_pinocchio(rows[:, slot.columns]))
    locked = {f.joint: f.offset for f in data.layout.fills if f.leader is None}
    columns = {c.joint: i for i, c in reversed(list(enumerate(data.coordinates)))}
    for fill in data.layout.fills:
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
    return q.reshape(*lead, data.nq)


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
    data: SpaceData,
    blocks: Mapping[str, JointBlock],
    followers: Mapping[str, Follower],
    x: ArrayLike,
    dx: ArrayLike,
) -> FloatArray:
    """Pinocchio's v (..., nv) of tangent vectors dx (..., dimension) at configurations x."""
    what = f"a tangent vector of robot '{data.robot}'"
    xs, ds, lead = rows_at(data, x, dx, data.dimension, what)
    check_finite(ds, data.tangent_names, lead)
    nv = sum(j.nv for j in data.report_joints)
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
    data: SpaceData,
    blocks: Mapping[str, JointBlock],
    x: ArrayLike,
    v: ArrayLike,
) -> FloatArray:
    """Tangent vectors (..., dimension) of Pinocchio's v (..., nv) at configurations x."""
    nv = sum(j.nv for j in data.report_joints)
    xs, vs, lead = rows_at(data, x, v, nv, f"Pinocchio's v of robot '{data.robot}'")
    check_finite(vs, [f"v[{i}]" for i in range(nv)], lead)
    dx = np.zeros((math.prod(lead), data.dimension))
    for block in blocks.values():
        width = block.tangent.stop - block.tangent.start
        out = dx[:, block.tangent]
        out[:] = vs[:, block.v_index : block.v_index + width]
        k = _linear(block)
        if k:  # body-frame linear velocity -> world-frame rates: R v
            r = _rotation(block, xs)
            out[:, :k] = np.matmul(r, vs[:, block.v_index : block.v_index + k, None])[..., 0]
    return dx.reshape(*lead, data.dimension)


def names(robot: Robot, velocity: bool) -> tuple[str, ...]:
    """Pinocchio's name of each entry of q (``base.qx``) or v, ``q[i]`` where it has none."""
    from cspace._slots import pinocchio_names

    data = robot.data
    size = sum(j.nv for j in data.report_joints) if velocity else data.nq
    found = [f"{'v' if velocity else 'q'}[{i}]" for i in range(size)]
    for joint in data.report_joints:
        start = joint.v_index if velocity else joint.q_index
        if start is not None:
            given = pinocchio_names(joint)[1 if velocity else 0]
            found[start : start + len(given)] = given
    return tuple(found)


class Maps:
    """Pinocchio's `Maps <cspace.space._conventions._maps.Maps>`: q and v."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot

    def names(self, velocity: bool) -> tuple[str, ...]:
        """Pinocchio's name of each entry of q or v."""
        return names(self.robot, velocity)

    def to_tool(self, x: ArrayLike) -> FloatArray:
        """Pinocchio's q (..., nq) of configurations (..., n)."""
        return to_q(self.robot.data, x)

    def from_tool(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of Pinocchio's q (..., nq)."""
        return from_q(self.robot.data, q)

    def to_velocity(self, at: ArrayLike, dx: ArrayLike) -> FloatArray:
        """Pinocchio's v (..., nv) of tangent vectors at configurations ``at``."""
        r = self.robot
        return to_v(r.data, r.blocks, r.followers, at, dx)

    def from_velocity(self, at: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of Pinocchio's v at configurations ``at``."""
        return from_v(self.robot.data, self.robot.blocks, at, v)
