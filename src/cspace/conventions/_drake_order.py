"""Drake's joint order and the names of its positions and velocities, from a report.

No NumPy: the report's JSON slots (``drake_q``, ``drake_v``) are made from these, and
the maps of `_drake` build on them. Drake's parser numbers a robot's joints depth first
from the world, a body's children in the order their joints are declared in the file;
a joint's entries are named after it (a free body after the body):

======================  ============================  ============================
joint                   q                             v
======================  ============================  ============================
revolute, continuous    ``j_q``                       ``j_w``
prismatic               ``j_x``                       ``j_v``
ball (roll, pitch, yaw) ``j_qx, j_qy, j_qz``          ``j_wx, j_wy, j_wz``
universal               ``j_qx, j_qy``                ``j_wx, j_wy``
planar                  ``j_x, j_y, j_qz``            ``j_vx, j_vy, j_wz``
floating (free body)    ``b_qw .. b_qz, b_x .. b_z``  ``b_wx .. b_wz, b_vx .. b_vz``
======================  ============================  ============================
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from cspace._joint_kind import JointKind
from cspace._joint_table import locked
from cspace.errors import JointMatchError

if TYPE_CHECKING:
    from cspace._reports._joint import JointReport

_ONE = {
    JointKind.REVOLUTE: ("q", "w"),
    JointKind.CONTINUOUS: ("q", "w"),
    JointKind.HELICAL: ("q", "w"),  # Drake's screw joint: the angle
    JointKind.PRISMATIC: ("x", "v"),
}
"""The suffixes of a one-coordinate joint's position and velocity."""

_SEVERAL = {
    JointKind.SPHERICAL: (("qx", "qy", "qz"), ("wx", "wy", "wz")),
    JointKind.UNIVERSAL: (("qx", "qy"), ("wx", "wy")),
    JointKind.PLANAR: (("x", "y", "qz"), ("vx", "vy", "wz")),
}
"""The suffixes of the positions and velocities of a joint of several coordinates."""

_FREE = (("qw", "qx", "qy", "qz", "x", "y", "z"), ("wx", "wy", "wz", "vx", "vy", "vz"))
"""A free body's: its quaternion and position; its angular and linear velocities."""


def drake_order(joints: tuple[JointReport, ...], mjcf: bool) -> list[JointReport]:
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


def follower_kind(joint: JointReport, kind: JointKind | None) -> JointKind:
    """What a mimic or locked joint is in Drake: a prismatic or a revolute joint.

    Its own kind when it has one (a locked joint); a mimic joint's from MuJoCo's type or
    its limits' unit (m: it slides).
    """
    if kind in _ONE and kind is not None:
        return kind
    slides = joint.mujoco_type == "slide" or (joint.limits is not None and joint.limits.unit == "m")
    return JointKind.PRISMATIC if slides else JointKind.REVOLUTE


def drake_names(joint: JointReport, kind: JointKind) -> tuple[list[str], list[str]]:
    """Drake's names of a joint's positions and velocities, stored as ``kind``.

    Raises:
        JointMatchError: A kind Drake stores in coordinates cspace does not map.
    """
    if kind in _ONE:
        q, v = _ONE[kind]
        return [f"{joint.name}_{q}"], [f"{joint.name}_{v}"]
    if kind is JointKind.FLOATING:
        body = joint.child_link
        return [f"{body}_{s}" for s in _FREE[0]], [f"{body}_{s}" for s in _FREE[1]]
    if kind in _SEVERAL:
        qs, vs = _SEVERAL[kind]
        return [f"{joint.name}_{s}" for s in qs], [f"{joint.name}_{s}" for s in vs]
    raise JointMatchError(
        f"joint '{joint.name}' is {kind.value}: Drake stores it in coordinates cspace does not map"
    )


def drake_slots(joints: tuple[JointReport, ...], mjcf: bool) -> dict[str, dict[str, Any]]:
    """Each joint's ``drake_q`` and ``drake_v`` slots (index and names), by joint name.

    Empty when Drake's order or storage of the robot is not known (see `drake_order`,
    `drake_names`): the report then says nothing about Drake.

    Args:
        joints: A report's joints.
        mjcf: They are an MJCF file's (declaration order is the report's).
    """
    try:
        ordered = drake_order(joints, mjcf)
        slots: dict[str, dict[str, Any]] = {}
        nq = nv = 0
        for joint in ordered:
            moving = joint.kind is not JointKind.FIXED
            if joint.mimic is not None or (moving and locked(joint.limits)):
                kind = follower_kind(joint, joint.kind)  # Drake keeps its entry
            elif not moving or joint.q_index is None:
                continue
            else:
                kind = joint.kind
            q, v = drake_names(joint, kind)
            slots[joint.name] = {
                "drake_q": {"index": nq, "names": q},
                "drake_v": {"index": nv, "names": v},
            }
            nq, nv = nq + len(q), nv + len(v)
    except JointMatchError:
        return {}
    return slots


def welded_roots(joints: tuple[JointReport, ...], mjcf: bool) -> tuple[str, ...]:
    """The root links Drake's parser would float where cspace keeps them fixed.

    Drake's URDF and SDF parsers make a link that no joint holds a free body (6 more
    degrees of freedom) unless it is the world; cspace, as Pinocchio, keeps a root link
    fixed unless it is given a root joint. Drake's vectors here are those of a plant with
    these links welded to the world. None for MJCF (MuJoCo's and Drake's MJCF parsers
    weld a body without joints).
    """
    if mjcf:
        return ()
    children = {joint.child_link for joint in joints}
    roots = dict.fromkeys(j.parent_link for j in joints if j.parent_link not in children)
    return tuple(r for r in roots if r is not None and r != "world")
