"""Isaac Lab's vectors: the root's pose, then ``joint_pos``, in PhysX's joint order.

Isaac Sim and Isaac Lab keep an articulation's joint positions (``joint_pos``) and
velocities (``joint_vel``) one entry per degree of freedom, in the order PhysX gives
them: breadth first from the articulation's root, the joints below one link in the
order UsdPhysics lists them (by prim path). Isaac Lab 3 emulates that order on its
other back end with Newton (``joint_ordering="bfs"``), which is this module's oracle.

For a USD file the joints below a link are taken in the order cspace's reader gives
them, which is by prim path. For a robot read from another format they are taken by
name: the order of the prim paths of a converter that puts every joint in one scope
(``urdf-usd-converter`` and Isaac Sim's URDF importer do). A root link that is not the world is an
articulation's root (Isaac Sim's URDF importer makes it so); each joint at the world
begins an articulation of its own; articulations are listed whole, one after another.

==========================  ======================================  =================
joint                       position                                velocity
==========================  ======================================  =================
revolute, continuous        ``j`` (rad, any angle)                  ``j`` (rad/s)
prismatic                   ``j`` (m)                               ``j`` (m/s)
floating root (body ``b``)  ``b_x b_y b_z b_qx b_qy b_qz b_qw``     ``b_vx .. b_wz``
==========================  ======================================  =================

A floating root is not in ``joint_pos``: it is Isaac Lab's ``root_link_pose_w``
(position, then the quaternion x, y, z, w, as Isaac Lab 3 writes it; Isaac Lab 2
wrote w first) and ``root_link_vel_w`` (linear, then angular velocity, both in the
world frame), put before the joints of its articulation. A mimic joint and a locked
joint keep their entries (PhysX simulates them as joints). Ball joints (PhysX keeps
three angles of its own), generic D6 joints of several free axes and the other
joints of several coordinates are refused by name.
"""

from __future__ import annotations

from collections import deque
from typing import TYPE_CHECKING

from cspace._d6 import is_axis_link
from cspace._formats.table import by_name
from cspace._joint_kind import JointKind
from cspace.errors import JointMatchError
from cspace.space._conventions._drake import LayoutMaps
from cspace.space._conventions._joint_blocks import joint_blocks
from cspace.space._conventions._layout import DrakeLayout, LayoutParts, xyzw_pose_columns
from cspace.space._conventions._maps import Robot

if TYPE_CHECKING:
    from cspace._joint_report import JointReport
    from cspace.space._data import SpaceData

_ONE = (JointKind.REVOLUTE, JointKind.CONTINUOUS, JointKind.PRISMATIC)
_ROOT_Q = ("x", "y", "z", "qx", "qy", "qz", "qw")
_ROOT_V = ("vx", "vy", "vz", "wx", "wy", "wz")
_WORLDS = ("world", "<world>")
"""What the readers call the world link (USD's when a body is named world)."""


def isaac_order(joints: tuple[JointReport, ...], fmt: str) -> list[JointReport]:
    """The joints in Isaac's order (see the module docstring).

    The joints below one link by the report's order for USD, else by name. A root link
    that is not the world is an articulation's root: its tree breadth first. Each joint
    at the world (a converter's static root link, an MJCF file's top bodies) and the
    tree below it is an articulation of its own, as PhysX makes them. Articulations in
    the order of their first joints.

    Raises:
        JointMatchError: A joint is one axis of a generic joint of several free axes, or
            one of several moving joints into one body (an MJCF body's joints, which
            Isaac's importer makes one such joint).
    """
    below: dict[str | None, list[tuple[object, JointReport]]] = {}
    children = {joint.child_link for joint in joints}
    into: dict[str, str] = {}
    for index, joint in enumerate(joints):
        if is_axis_link(joint.child_link) or is_axis_link(joint.parent_link or ""):
            raise JointMatchError(
                f"joint '{joint.name}' is one axis of a generic (D6) joint of several free "
                "axes, whose degrees of freedom Isaac orders in a way cspace does not map"
            )
        if joint.kind is not JointKind.FIXED:
            other = into.setdefault(joint.child_link, joint.name)
            if other != joint.name:
                raise JointMatchError(
                    f"joints '{other}' and '{joint.name}' both move body "
                    f"'{joint.child_link}': Isaac makes them one generic (D6) joint, whose "
                    "degrees of freedom it orders in a way cspace does not map"
                )
        key: object = index if by_name(fmt).articulation else (joint.name, index)
        below.setdefault(joint.parent_link, []).append((key, joint))
    for group in below.values():
        group.sort(key=lambda item: item[0])  # type: ignore[arg-type,return-value]
    articulations: list[list[tuple[object, JointReport]]] = []
    for link in below:
        if link not in children:
            whole = link not in _WORLDS and link is not None
            articulations += [below[link]] if whole else [[item] for item in below[link]]
    out: list[JointReport] = []
    entered: set[str] = set()  # each body's children once, whatever joints lead to it
    for tops in sorted(articulations, key=lambda group: group[0][0]):  # type: ignore[arg-type,return-value]
        queue = deque(joint for _, joint in tops)
        while queue:  # iterative: trees may be thousands of joints deep
            joint = queue.popleft()
            out.append(joint)
            if joint.child_link not in entered:
                entered.add(joint.child_link)
                queue.extend(j for _, j in below.get(joint.child_link, ()))
    return out


def isaac_names(
    joint: JointReport, kind: JointKind, taken: frozenset[str] = frozenset()
) -> tuple[list[str], list[str]]:
    """Isaac's names of a joint's positions and velocities, stored as ``kind``.

    A floating root's entries are named after its body, with ``_`` before it while a
    joint's name (``taken``) is one of them.

    Raises:
        JointMatchError: A kind Isaac stores in coordinates cspace does not map.
    """
    if kind in _ONE:
        return [joint.name], [joint.name]
    if kind is JointKind.FLOATING:
        body = joint.child_link
        while any(f"{body}_{s}" in taken for s in _ROOT_Q + _ROOT_V):  # as Drake does
            body = f"_{body}"
        return [f"{body}_{s}" for s in _ROOT_Q], [f"{body}_{s}" for s in _ROOT_V]
    raise JointMatchError(
        f"joint '{joint.name}' is {kind.value}: Isaac stores it in coordinates cspace does not map"
    )


def isaac_layout(data: SpaceData) -> DrakeLayout:
    """Isaac's layout of a robot's configuration space (see the module docstring).

    Raises:
        JointMatchError: A joint Isaac stores in a way cspace does not map, or a
            floating joint below the root.
    """
    blocks, followers = joint_blocks(data)
    parts = LayoutParts()
    held = {j.child_link for j in data.report_joints}
    taken = frozenset(j.name for j in data.report_joints if j.kind is not JointKind.FLOATING)
    for joint in isaac_order(data.report_joints, data.source_format):
        if joint.kind is JointKind.FLOATING and joint.parent_link in held:
            raise JointMatchError(
                f"joint '{joint.name}' is floating below link '{joint.parent_link}': an "
                "articulation floats only at its root"
            )
        follower = followers.get(joint.name)
        if follower is not None:
            parts.follow(follower, blocks, [joint.name], [joint.name])
            continue
        block = blocks.get(joint.name)
        if block is None:  # fixed: no degree of freedom
            continue
        c, t = block.columns.start, block.tangent.start
        q, v = isaac_names(joint, block.kind, taken)
        if block.kind is JointKind.FLOATING:  # canonical x y z qw qx qy qz; v, then w
            parts.floating.append((len(parts.v_names) + 3, c + 3, t + 3))
            columns, tangent = xyzw_pose_columns(c, t)
            parts.add(q, v, columns, tangent)
        else:
            parts.add(q, v, [c], [t])
    return parts.layout(
        vectors=("Isaac's root pose and joint_pos", "Isaac's root velocity and joint_vel"),
    )


class Maps(LayoutMaps):
    """Isaac's maps: a floating root's pose, then joint_pos (velocities likewise)."""

    def __init__(self, robot: Robot) -> None:
        super().__init__(robot, isaac_layout(robot.data))
