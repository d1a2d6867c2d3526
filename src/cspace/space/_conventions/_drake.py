"""Drake's q and v: the order its parser gives joints, and the maps to and from them.

Drake's ``MultibodyPlant`` numbers a robot's positions depth first from the world, a
body's children in the order their joints are declared in the file (not by name, as
Pinocchio's URDF parser does), and keeps a mimic follower's entry (a coupler constraint
ties it to its leader). Per joint:

======================  ============================  ============================
joint                   q                             v
======================  ============================  ============================
revolute, continuous    ``j_q`` (any angle)           ``j_w``
prismatic               ``j_x``                       ``j_v``
planar                  ``j_x, j_y, j_qz``            ``j_vx, j_vy, j_wz``
floating (free body)    ``b_qw .. b_qz, b_x .. b_z``  ``b_wx .. b_wz, b_vx .. b_vz``
======================  ============================  ============================

A floating body is named after the body (``b``), not the joint, and its velocities are
both in the world frame: the angular one is ``R w`` of the canonical body-frame ``w``, so
the velocity maps need the configuration. Its q is the body's pose in the world: Drake's
URDF parser drops a floating joint's ``<origin>`` (it adds no joint, and the free body
it leaves starts at the world's origin), so a joint with one (`JointReport.origin`) has
the origin composed into its q and v (`DrakeLayout.origins`), and the same q places the
body alike in both tools. A robot cspace reads with a fixed base is
Drake's with its root welded to the world (Drake would float an unwelded URDF root).
A ball joint is Drake's ``BallRpyJoint``: roll, pitch and yaw (``j_qx, j_qy, j_qz``,
``R = Rz(yaw) Ry(pitch) Rx(roll)``) and the angular velocity in the parent frame; a
universal joint its two angles; a screw joint its angle. Other joints (translation)
are refused by name. Of an MJCF file, Drake's MJCF parser builds a body with several
joints otherwise than MuJoCo (and leaves out what ``<frame>``, ``<replicate>`` and
``<attach>`` place); of a URDF file, it moves a planar joint in the plane normal to its
``<axis>``, where Pinocchio moves it in its frame's x-y plane, and leaves a floating
joint's child free in the world where it hangs below another link: the report's
``drake-mjcf-differs`` and ``drake-urdf-differs`` findings say where, and the layout
carries them (`DrakeLayout.findings`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace._drake_order import (
    drake_names,
    drake_order,
    follower_kind,
    taken_names,
    welded_roots,
)
from cspace._joint_kind import JointKind
from cspace.space._checks import as_rows, check_finite
from cspace.space._compute.engines import canonicalize
from cspace.space._conventions._joint_blocks import joint_blocks
from cspace.space._conventions._layout import DrakeLayout, LayoutParts
from cspace.space._conventions._maps import Robot, rows_at
from cspace.space._geometry.rotations import (
    FloatArray,
    conjugate,
    matrix_from_quaternion,
    multiply,
)

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


def drake_layout(data: SpaceData) -> DrakeLayout:
    """Drake's layout of a robot's configuration space (see the module docstring).

    Raises:
        JointMatchError: A joint Drake stores in a way cspace does not map (ball,
            universal, translation, helical), named.
    """
    blocks, followers = joint_blocks(data)
    parts = LayoutParts()
    balls: list[tuple[int, int, int, int]] = []
    origins: list[tuple[int, int, tuple[float, ...]]] = []
    kinds = {j.name: j.kind for j in data.report_joints}  # a locked joint keeps its own
    fmt = "mjcf" if data.mujoco is not None else data.source_format
    taken = taken_names(data.report_joints, fmt)
    for joint in drake_order(data.report_joints, fmt):
        name = joint.name
        follower = followers.get(name)
        if follower is not None:
            q, v = drake_names(joint, follower_kind(joint, kinds.get(name)), fmt, taken)
            parts.follow(follower, blocks, q, v)
            continue
        block = blocks.get(name)
        if block is None:  # fixed: a weld, no coordinates
            continue
        c, t = block.columns.start, block.tangent.start
        q, v = drake_names(joint, block.kind, fmt, taken)
        at_q, at_v = len(parts.q_names), len(parts.v_names)
        if block.kind is JointKind.FLOATING:  # canonical x y z qw qx qy qz; v, then w
            parts.floating.append((at_v, c + 3, t + 3))
            if joint.origin is not None:
                origins.append((at_q, at_v, joint.origin))
            parts.add(
                q,
                v,
                [c + 3, c + 4, c + 5, c + 6, c, c + 1, c + 2],
                [t + 3, t + 4, t + 5, t, t + 1, t + 2],
            )
        elif block.kind is JointKind.SPHERICAL:  # roll, pitch, yaw; w in the parent frame
            balls.append((at_q, at_v, c, t))
            parts.add(q, v, [-1, -1, -1], [-1, -1, -1])
        else:  # the joint's coordinates in order (one, the two of a universal, x y theta)
            parts.add(q, v, list(range(c, c + len(q))), list(range(t, t + len(v))))
    return parts.layout(
        balls=tuple(balls),
        welded=welded_roots(data.report_joints, fmt),
        findings=data.drake_findings or (data.mujoco.drake if data.mujoco is not None else ()),
        origins=tuple(origins),
    )


def to_drake(data: SpaceData, layout: DrakeLayout, x: ArrayLike) -> FloatArray:
    """Drake's q (..., nq) of canonical configurations (..., n)."""
    xs, lead = as_rows(canonicalize(data, x, None), data.size, f"a configuration of '{data.robot}'")
    columns = np.array(layout.columns, dtype=np.intp)
    q = np.zeros((xs.shape[0], len(columns)))
    moving = columns >= 0
    q[:, moving] = xs[:, columns[moving]]
    for at, _, leader, _, multiplier, offset in layout.followers:
        q[:, at] = offset if leader < 0 else multiplier * xs[:, leader] + offset
    for at, _, quaternion, _ in layout.balls:
        q[:, at : at + 3] = _rpy(xs[:, quaternion : quaternion + 4])
    for at, _, origin in layout.origins:  # the body's pose in the world: origin * pose
        shift, turn = np.asarray(origin[:3]), np.asarray(origin[3:])
        q[:, at + 4 : at + 7] = shift + q[:, at + 4 : at + 7] @ _matrix(turn).T
        q[:, at : at + 4] = multiply(turn, q[:, at : at + 4], check=False)
    return q.reshape(*lead, len(columns))


def from_drake(data: SpaceData, layout: DrakeLayout, q: ArrayLike) -> FloatArray:
    """Canonical configurations (..., n) of Drake's q (..., nq).

    Followers' entries are not read: they follow their leaders.
    """
    qs, lead = as_rows(q, len(layout.columns), f"{layout.vectors[0]} of robot '{data.robot}'")
    check_finite(qs, list(layout.position_names), lead)
    if layout.origins:
        qs = qs.copy()
    for at, _, origin in layout.origins:  # the pose in the joint's frame: origin^-1 * pose
        shift, turn = np.asarray(origin[:3]), np.asarray(origin[3:])
        qs[:, at + 4 : at + 7] = (qs[:, at + 4 : at + 7] - shift) @ _matrix(turn)
        qs[:, at : at + 4] = multiply(conjugate(turn, check=False), qs[:, at : at + 4], check=False)
    x = np.zeros((qs.shape[0], data.size))
    for at, column in enumerate(layout.columns):
        if column >= 0:
            x[:, column] = qs[:, at]
    for at, _, quaternion, _ in layout.balls:
        x[:, quaternion : quaternion + 4] = _quaternion(qs[:, at : at + 3])
    return canonicalize(data, x.reshape(*lead, data.size), None)


def to_drake_velocity(
    data: SpaceData, layout: DrakeLayout, x: ArrayLike, dx: ArrayLike
) -> FloatArray:
    """Drake's v (..., nv) of tangent vectors dx (..., dimension) at configurations x."""
    what = f"a tangent vector of robot '{data.robot}'"
    xs, ds, lead = rows_at(data, x, dx, data.dimension, what)
    check_finite(ds, list(data.tangent_names), lead)
    tangent = np.array(layout.tangent, dtype=np.intp)
    v = np.zeros((ds.shape[0], len(tangent)))
    moving = tangent >= 0
    v[:, moving] = ds[:, tangent[moving]]
    for _, at, _, leader, multiplier, _ in layout.followers:
        v[:, at] = 0.0 if leader < 0 else multiplier * ds[:, leader]
    turning = [(at, q, w) for at, q, w in layout.floating]
    turning += [(at, q, w) for _, at, q, w in layout.balls]
    for at, quaternion, angular in turning:  # body-frame w -> parent-frame R w
        r = matrix_from_quaternion(xs[:, quaternion : quaternion + 4], check=False)
        v[:, at : at + 3] = np.matmul(r, ds[:, angular : angular + 3, None])[..., 0]
    for _, at, origin in layout.origins:  # the joint's frame's w and v -> the world's
        turn = _matrix(np.asarray(origin[3:]))
        v[:, at : at + 6] = (v[:, at : at + 6].reshape(-1, 2, 3) @ turn.T).reshape(-1, 6)
    return v.reshape(*lead, len(tangent))


def from_drake_velocity(
    data: SpaceData, layout: DrakeLayout, x: ArrayLike, v: ArrayLike
) -> FloatArray:
    """Tangent vectors (..., dimension) of Drake's v (..., nv) at configurations x."""
    what = f"{layout.vectors[1]} of robot '{data.robot}'"
    xs, vs, lead = rows_at(data, x, v, len(layout.tangent), what)
    check_finite(vs, list(layout.velocity_names), lead)
    if layout.origins:
        vs = vs.copy()
    for _, at, origin in layout.origins:  # the world's w and v -> the joint's frame's
        turn = _matrix(np.asarray(origin[3:]))
        vs[:, at : at + 6] = (vs[:, at : at + 6].reshape(-1, 2, 3) @ turn).reshape(-1, 6)
    dx = np.zeros((vs.shape[0], data.dimension))
    for at, column in enumerate(layout.tangent):
        if column >= 0:
            dx[:, column] = vs[:, at]
    turning = [(at, q, w) for at, q, w in layout.floating]
    turning += [(at, q, w) for _, at, q, w in layout.balls]
    for at, quaternion, angular in turning:  # parent-frame w -> body-frame R^T w
        r = matrix_from_quaternion(xs[:, quaternion : quaternion + 4], check=False)
        w = vs[:, at : at + 3, None]
        dx[:, angular : angular + 3] = np.matmul(np.swapaxes(r, -1, -2), w)[..., 0]
    return dx.reshape(*lead, data.dimension)


def _matrix(turn: FloatArray) -> FloatArray:
    """The rotation matrix (3, 3) of one unit quaternion (w, x, y, z)."""
    matrix: FloatArray = matrix_from_quaternion(turn[None, :], check=False)[0]
    return matrix


def _rpy(h: FloatArray) -> FloatArray:
    """Drake's (roll, pitch, yaw) (M, 3) of unit quaternions (M, 4) (w, x, y, z).

    The rotation is ``Rz(yaw) Ry(pitch) Rx(roll)``, pitch in [-pi/2, pi/2]. Pitch comes
    from the matrix; yaw + roll and yaw - roll from the quaternion (``x + z`` and
    ``w - y`` are ``sin`` and ``cos`` of the half sum times ``cos(p/2) - sin(p/2)``;
    ``z - x`` and ``w + y`` of the half difference times ``cos(p/2) + sin(p/2)``), so
    that near pitch
    = ±pi/2, where one pair vanishes and the split between yaw and roll is free, the
    rotation stays exact. (The factors are >= 0 for pitch in [-pi/2, pi/2]: one
    solution, whatever the quaternion's sign.) Roll and yaw in [-pi, pi).
    """
    r = matrix_from_quaternion(h, check=False)
    pitch = np.arctan2(-r[:, 2, 0], np.hypot(r[:, 0, 0], r[:, 1, 0]))
    w, x, y, z = h[:, 0], h[:, 1], h[:, 2], h[:, 3]
    half_sum = np.arctan2(x + z, w - y)  # (yaw + roll) / 2
    half_difference = np.arctan2(z - x, w + y)  # (yaw - roll) / 2
    yaw, roll = half_sum + half_difference, half_sum - half_difference
    angles = np.stack([roll, pitch, yaw], axis=-1)
    return (angles + np.pi) % (2.0 * np.pi) - np.pi


def _quaternion(rpy: FloatArray) -> FloatArray:
    """Unit quaternions (M, 4) (w, x, y, z) of Drake's (roll, pitch, yaw) (M, 3)."""
    half = rpy / 2.0
    cr, cp, cy = np.cos(half[:, 0]), np.cos(half[:, 1]), np.cos(half[:, 2])
    sr, sp, sy = np.sin(half[:, 0]), np.sin(half[:, 1]), np.sin(half[:, 2])
    return np.stack(
        [
            cy * cp * cr + sy * sp * sr,
            cy * cp * sr - sy * sp * cr,
            cy * sp * cr + sy * cp * sr,
            sy * cp * cr - cy * sp * sr,
        ],
        axis=-1,
    )


class LayoutMaps:
    """The `Maps <cspace.space._conventions._maps.Maps>` of vectors a `DrakeLayout` describes.

    Drake's, and any tool's whose vectors are the canonical ones reordered, with
    followers set from their leaders and floating bodies' angular velocities in the world
    frame (Isaac's).
    """

    def __init__(self, robot: Robot, layout: DrakeLayout) -> None:
        self.data = robot.data
        self.layout = layout

    def names(self, velocity: bool) -> tuple[str, ...]:
        """The tool's names of its positions (or velocities): Drake's ``GetPositionNames()``."""
        return self.layout.velocity_names if velocity else self.layout.position_names

    def to_tool(self, x: ArrayLike) -> FloatArray:
        """The tool's q (..., nq) of canonical configurations (..., n)."""
        return to_drake(self.data, self.layout, x)

    def from_tool(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of the tool's q (..., nq)."""
        return from_drake(self.data, self.layout, q)

    def to_velocity(self, at: ArrayLike, dx: ArrayLike) -> FloatArray:
        """The tool's v (..., nv) of tangent vectors at configurations ``at``."""
        return to_drake_velocity(self.data, self.layout, at, dx)

    def from_velocity(self, at: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of the tool's v at configurations ``at``."""
        return from_drake_velocity(self.data, self.layout, at, v)


class Maps(LayoutMaps):
    """Drake's maps: q and v in its parser's order."""

    def __init__(self, robot: Robot) -> None:
        super().__init__(robot, drake_layout(robot.data))
