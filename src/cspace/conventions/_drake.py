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
the velocity maps need the configuration. A robot cspace reads with a fixed base is
Drake's with its root welded to the world (Drake would float an unwelded URDF root).
A ball joint is Drake's ``BallRpyJoint``: roll, pitch and yaw (``j_qx, j_qy, j_qz``,
``R = Rz(yaw) Ry(pitch) Rx(roll)``) and the angular velocity in the parent frame; a
universal joint its two angles; a screw joint its angle. Other joints (translation)
are refused by name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace._joint_kind import JointKind
from cspace.errors import JointMatchError
from cspace.space._checks import as_rows, check_finite
from cspace.space._joint_blocks import joint_blocks
from cspace.space._rotations import FloatArray, matrix_from_quaternion

if TYPE_CHECKING:
    from cspace._reports.report import JointReport
    from cspace.space._shape import Space

_ONE = {
    JointKind.REVOLUTE: ("q", "w"),
    JointKind.CONTINUOUS: ("q", "w"),
    JointKind.HELICAL: ("q", "w"),  # Drake's screw joint: the angle
    JointKind.PRISMATIC: ("x", "v"),
}
"""The suffixes of a one-coordinate joint's position and velocity."""


@dataclass(frozen=True)
class DrakeLayout:
    """Where each Drake position and velocity comes from, in Drake's order.

    Attributes:
        position_names: Drake's name of each position (``GetPositionNames``).
        velocity_names: Its name of each velocity.
        columns: The canonical column of each position (-1: a mimic follower).
        tangent: The canonical tangent column of each velocity (-1: a follower).
        followers: (position, velocity, leader column, leader tangent column, multiplier,
            offset) of each mimic or locked joint (leader columns -1 when locked).
        floating: (first velocity, first canonical quaternion column, first canonical
            angular tangent column) of each floating body.
        balls: (first position, first velocity, first canonical quaternion column, first
            canonical tangent column) of each ball joint (Drake's roll, pitch, yaw).
    """

    position_names: tuple[str, ...]
    velocity_names: tuple[str, ...]
    columns: tuple[int, ...]
    tangent: tuple[int, ...]
    followers: tuple[tuple[int, int, int, int, float, float], ...]
    floating: tuple[tuple[int, int, int], ...]
    balls: tuple[tuple[int, int, int, int], ...] = ()


def _order(joints: tuple[JointReport, ...], mjcf: bool) -> list[JointReport]:
    """The joints in Drake's order (see the module docstring).

    Depth first from the world, a link's children in the order their joints are
    declared (an MJCF file's: the report's, MuJoCo's own order; else the joint's line),
    several joints between two links together. At the world, trees joined to it by a
    joint come first, then the bodies Drake floats: trees of several bodies, then
    single bodies.

    Raises:
        JointMatchError: The declaration order of siblings is unknown (a xacro file's
            report keeps no lines; two joints on one line), or a floating joint below
            the root (Drake floats its child in the world).
    """
    below: dict[str | None, dict[str, list[tuple[float, int, JointReport]]]] = {}
    child_links = set()
    for index, joint in enumerate(joints):
        line = joint.line if joint.line is not None else math.inf
        declared = float(index) if mjcf else float(line)
        below.setdefault(joint.parent_link, {}).setdefault(joint.child_link, []).append(
            (declared, index, joint)
        )
        child_links.add(joint.child_link)
    roots = [link for link in below if link not in child_links]

    def groups(link: str | None, root: bool) -> list[list[tuple[float, int, JointReport]]]:
        """The link's children, one group of joints each, last first (a stack)."""
        found = sorted(sorted(g) for g in below.get(link, {}).values())
        firsts = [g[0][0] for g in found]
        if len(found) > 1 and (math.inf in firsts or len(set(firsts)) < len(firsts)):
            raise JointMatchError(
                f"link '{link}' has several child joints and the report does not say in "
                "which order the file declares them (a xacro file's report keeps no "
                "lines; two joints on one line), which is Drake's order: expand it to a "
                "URDF with one joint per line first (xacro FILE > robot.urdf)"
            )
        for group in found:
            if group[0][2].kind is JointKind.FLOATING and not root:
                raise JointMatchError(
                    f"joint '{group[0][2].name}' is floating below link '{link}': Drake "
                    "floats its child in the world frame, which cspace does not map"
                )
        if root:  # jointed trees, then floated trees of several bodies, then single ones

            def rank(group: list[tuple[float, int, JointReport]]) -> int:
                if group[0][2].kind is not JointKind.FLOATING:
                    return 0
                return 1 if below.get(group[0][2].child_link) else 2

            found.sort(key=rank)  # stable: declaration order within each
        return found[::-1]

    out: list[JointReport] = []
    entered: set[str | None] = set()  # links whose children are stacked: each once
    for root in sorted(roots, key=lambda link: min(min(g) for g in below[link].values())[:2]):
        entered.add(root)
        stack = groups(root, True)
        while stack:  # iterative: trees may be thousands of joints deep
            group = stack.pop()
            out += [joint for _, _, joint in group]
            child = group[0][2].child_link
            if child not in entered:
                entered.add(child)
                stack += groups(child, False)
    return out


def drake_layout(space: Space) -> DrakeLayout:
    """Drake's layout of a robot's configuration space (see the module docstring).

    Raises:
        JointMatchError: A joint Drake stores in a way cspace does not map (ball,
            universal, translation, helical), named.
    """
    blocks, followers = joint_blocks(space)
    q_names: list[str] = []
    v_names: list[str] = []
    columns: list[int] = []
    tangent: list[int] = []
    tied: list[tuple[int, int, int, int, float, float]] = []
    floating: list[tuple[int, int, int]] = []
    balls: list[tuple[int, int, int, int]] = []
    kinds = {j.name: j.kind for j in space.report_joints}  # a locked joint keeps its own
    for joint in _order(space.report_joints, space.mujoco is not None):
        name = joint.name
        follower = followers.get(name)
        if follower is not None:
            leader = blocks.get(follower.leader) if follower.leader is not None else None
            q, v = _ONE[_follower_kind(joint, kinds.get(name))]
            tied.append(
                (
                    len(q_names),
                    len(v_names),
                    leader.columns.start if leader is not None else -1,
                    leader.tangent.start if leader is not None else -1,
                    follower.multiplier,
                    follower.offset,
                )
            )
            q_names.append(f"{name}_{q}")
            v_names.append(f"{name}_{v}")
            columns.append(-1)
            tangent.append(-1)
            continue
        block = blocks.get(name)
        if block is None:  # fixed: a weld, no coordinates
            continue
        c, t = block.columns.start, block.tangent.start
        if block.kind in _ONE:
            q, v = _ONE[block.kind]
            q_names.append(f"{name}_{q}")
            v_names.append(f"{name}_{v}")
            columns.append(c)
            tangent.append(t)
        elif block.kind is JointKind.FLOATING:  # canonical x y z qw qx qy qz; v, then w
            body = joint.child_link
            floating.append((len(v_names), c + 3, t + 3))
            q_names += [f"{body}_{s}" for s in ("qw", "qx", "qy", "qz", "x", "y", "z")]
            v_names += [f"{body}_{s}" for s in ("wx", "wy", "wz", "vx", "vy", "vz")]
            columns += [c + 3, c + 4, c + 5, c + 6, c, c + 1, c + 2]
            tangent += [t + 3, t + 4, t + 5, t, t + 1, t + 2]
        elif block.kind is JointKind.SPHERICAL:  # roll, pitch, yaw; w in the parent frame
            balls.append((len(q_names), len(v_names), c, t))
            q_names += [f"{name}_qx", f"{name}_qy", f"{name}_qz"]
            v_names += [f"{name}_wx", f"{name}_wy", f"{name}_wz"]
            columns += [-1, -1, -1]
            tangent += [-1, -1, -1]
        elif block.kind is JointKind.UNIVERSAL:  # the two angles, in order
            q_names += [f"{name}_qx", f"{name}_qy"]
            v_names += [f"{name}_wx", f"{name}_wy"]
            columns += [c, c + 1]
            tangent += [t, t + 1]
        elif block.kind is JointKind.PLANAR:  # canonical x y theta, rates in the plane
            q_names += [f"{name}_x", f"{name}_y", f"{name}_qz"]
            v_names += [f"{name}_vx", f"{name}_vy", f"{name}_wz"]
            columns += [c, c + 1, c + 2]
            tangent += [t, t + 1, t + 2]
        else:
            raise JointMatchError(
                f"joint '{name}' is {block.kind.value}: Drake stores it in coordinates "
                "cspace does not map yet (roll, pitch, yaw)"
            )
    return DrakeLayout(
        tuple(q_names),
        tuple(v_names),
        tuple(columns),
        tuple(tangent),
        tuple(tied),
        tuple(floating),
        tuple(balls),
    )


def _follower_kind(joint: JointReport, kind: JointKind | None) -> JointKind:
    """What a mimic or locked joint is in Drake: a prismatic or a revolute joint.

    Its own kind when it has one (a locked joint); a mimic joint's from MuJoCo's type or
    its limits' unit (m: it slides).
    """
    if kind in _ONE and kind is not None:
        return kind
    slides = joint.mujoco_type == "slide" or (joint.limits is not None and joint.limits.unit == "m")
    return JointKind.PRISMATIC if slides else JointKind.REVOLUTE


def to_drake(space: Space, layout: DrakeLayout, x: ArrayLike) -> FloatArray:
    """Drake's q (..., nq) of canonical configurations (..., n)."""
    xs, lead = as_rows(space.canonicalize(x), space.size, f"a configuration of '{space.robot}'")
    columns = np.array(layout.columns, dtype=np.intp)
    q = np.zeros((xs.shape[0], len(columns)))
    moving = columns >= 0
    q[:, moving] = xs[:, columns[moving]]
    for at, _, leader, _, multiplier, offset in layout.followers:
        q[:, at] = offset if leader < 0 else multiplier * xs[:, leader] + offset
    for at, _, quaternion, _ in layout.balls:
        q[:, at : at + 3] = _rpy(xs[:, quaternion : quaternion + 4])
    return q.reshape(*lead, len(columns))


def from_drake(space: Space, layout: DrakeLayout, q: ArrayLike) -> FloatArray:
    """Canonical configurations (..., n) of Drake's q (..., nq).

    Followers' entries are not read: they follow their leaders.
    """
    qs, lead = as_rows(q, len(layout.columns), f"Drake's q of robot '{space.robot}'")
    check_finite(qs, list(layout.position_names), lead)
    x = np.zeros((qs.shape[0], space.size))
    for at, column in enumerate(layout.columns):
        if column >= 0:
            x[:, column] = qs[:, at]
    for at, _, quaternion, _ in layout.balls:
        x[:, quaternion : quaternion + 4] = _quaternion(qs[:, at : at + 3])
    return space.canonicalize(x.reshape(*lead, space.size))


def to_drake_velocity(space: Space, layout: DrakeLayout, x: ArrayLike, dx: ArrayLike) -> FloatArray:
    """Drake's v (..., nv) of tangent vectors dx (..., dimension) at configurations x."""
    xs, ds, lead = _rows(space, layout, x, dx, space.dimension, "a tangent vector")
    check_finite(ds, list(space.tangent_names), lead)
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
    return v.reshape(*lead, len(tangent))


def from_drake_velocity(
    space: Space, layout: DrakeLayout, x: ArrayLike, v: ArrayLike
) -> FloatArray:
    """Tangent vectors (..., dimension) of Drake's v (..., nv) at configurations x."""
    xs, vs, lead = _rows(space, layout, x, v, len(layout.tangent), "Drake's v")
    check_finite(vs, list(layout.velocity_names), lead)
    dx = np.zeros((vs.shape[0], space.dimension))
    for at, column in enumerate(layout.tangent):
        if column >= 0:
            dx[:, column] = vs[:, at]
    turning = [(at, q, w) for at, q, w in layout.floating]
    turning += [(at, q, w) for _, at, q, w in layout.balls]
    for at, quaternion, angular in turning:  # parent-frame w -> body-frame R^T w
        r = matrix_from_quaternion(xs[:, quaternion : quaternion + 4], check=False)
        w = vs[:, at : at + 3, None]
        dx[:, angular : angular + 3] = np.matmul(np.swapaxes(r, -1, -2), w)[..., 0]
    return dx.reshape(*lead, space.dimension)


def _rows(
    space: Space,
    layout: DrakeLayout,
    x: ArrayLike,
    d: ArrayLike,
    width: int,
    what: str,
) -> tuple[FloatArray, FloatArray, tuple[int, ...]]:
    """Canonical configurations and velocities as rows of one leading shape."""
    from cspace.space._checks import broadcast_rows, broadcast_shapes

    xs, lead_x = as_rows(space.canonicalize(x), space.size, f"a configuration of '{space.robot}'")
    ds, lead_d = as_rows(d, width, f"{what} of robot '{space.robot}'")
    full = broadcast_shapes(lead_x, lead_d)
    return broadcast_rows(xs, lead_x, full), broadcast_rows(ds, lead_d, full), full


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
