"""PyBullet's vectors: the base's pose, then each joint's positions by joint index.

``p.loadURDF`` numbers a robot's joints (and links: joint ``i`` moves link ``i``, the
base is link -1) depth first from the base link, a link's children in the order their
joints are declared in the file (bullet3's ``URDF2Bullet``, ``ComputeParentIndices``;
not with ``URDF_MERGE_FIXED_LINKS`` or ``URDF_MAINTAIN_LINK_ORDER``). Fixed joints
have an index and no coordinates (``getJointInfo``'s ``qIndex`` is -1). PyBullet's own
state vector puts the base's seven coordinates first whether the base floats or not,
so a joint's ``qIndex`` (``uIndex``) is its place in it; these vectors hold the base's
only when it floats, and then entry ``k`` is ``qIndex`` ``k`` (else ``k + 7``).

==========================  ======================================  =================
joint                       position                                velocity
==========================  ======================================  =================
revolute, continuous        ``j`` (rad, any angle)                  ``j`` (rad/s)
prismatic                   ``j`` (m)                               ``j`` (m/s)
spherical                   ``j_qx j_qy j_qz j_qw``                 ``j_wx j_wy j_wz``
free base (body ``b``)      ``b_x b_y b_z b_qx b_qy b_qz b_qw``     ``b_vx .. b_wz``
==========================  ======================================  =================

The free base is the base link's frame in the world (PyBullet's
``getBasePositionAndOrientation`` gives its inertial frame instead: the link's frame
times the ``<inertial><origin>``, ``getDynamicsInfo(body, -1)[3:5]``), its velocity
the link origin's linear and the angular velocity, both in the world frame. A
spherical joint's quaternion is ``resetJointStateMultiDof``'s (x, y, z, w) and its
angular velocity is in the child's frame (PyBullet's frames are the links' inertial
frames: the same when the child's ``<inertial>`` is not turned).

Where PyBullet's C-space is not the file's, the vectors are written all the same, and
`PybulletOrder` says so: PyBullet floats a URDF's base unless ``useFixedBase=True``
(or its mass is 0: a link named ``world`` without ``<inertial>``), it ignores
``<mimic>`` (a follower keeps its entry, set here from its leader, and moves freely
in PyBullet: ``pybullet-mimic-free``), and it makes a URDF floating joint fixed (these
vectors take it as the free base it would be without the world link above it:
``pybullet-floating-fixed``). A planar joint (PyBullet keeps three coordinates and
reports two), several floating joints and the joints PyBullet has no type for are
refused by name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from cspace._findings import CODES, Diagnostic
from cspace._joint_kind import JointKind
from cspace.errors import JointMatchError
from cspace.space._conventions._drake import LayoutMaps
from cspace.space._conventions._isaac import isaac_names
from cspace.space._conventions._joint_blocks import joint_blocks
from cspace.space._conventions._layout import DrakeLayout, LayoutParts, xyzw_pose_columns
from cspace.space._conventions._maps import Robot

if TYPE_CHECKING:
    from cspace._joint_report import JointReport
    from cspace.space._data import SpaceData

_ONE = (JointKind.REVOLUTE, JointKind.CONTINUOUS, JointKind.PRISMATIC, JointKind.MIMIC)
_BALL_Q = ("qx", "qy", "qz", "qw")
_BALL_V = ("wx", "wy", "wz")
_URDF = ("urdf", "xacro")
"""The formats whose joints PyBullet's URDF importer reads as the file declares them."""
BASE_Q = 7
"""How many coordinates PyBullet's state vector gives the base, free or not."""


@dataclass(frozen=True)
class PybulletJoint:
    """One joint as ``p.getJointInfo(body, index)`` describes it.

    Attributes:
        index: Its ``jointIndex`` (also the index of its child link).
        name: Its ``jointName``.
        kind: What it is in cspace's words (a mimic follower ``mimic``).
        link: Its child link (``linkName``).
        parent: The index of its parent link (``parentIndex``; -1: the base).
        q_index: Its first entry in PyBullet's state vector (``qIndex``; -1 when fixed).
        u_index: Its first entry in PyBullet's velocity vector (``uIndex``; -1 when fixed).
    """

    index: int
    name: str
    kind: JointKind
    link: str
    parent: int
    q_index: int
    u_index: int

    @property
    def moves(self) -> bool:
        """The joint has coordinates in PyBullet (it is not fixed)."""
        return self.q_index >= 0


@dataclass(frozen=True)
class PybulletOrder:
    """A robot as ``p.loadURDF`` numbers it, and where PyBullet's C-space differs.

    Attributes:
        base: The base link (``getBodyInfo``'s first name, link index -1); empty for a
            robot without joints, whose report names no link.
        free: The vectors hold the base's pose first (the robot's root joint is
            floating); else the base is fixed.
        joints: Every joint PyBullet makes, fixed ones included, by joint index.
        floats: The base link PyBullet floats where these vectors hold it fixed
            (unless ``loadURDF(..., useFixedBase=True)``); None when it does not.
        findings: Where PyBullet's C-space is not the file's (``pybullet-mimic-free``,
            ``pybullet-floating-fixed``).
    """

    base: str
    free: bool
    joints: tuple[PybulletJoint, ...]
    floats: str | None
    findings: tuple[Diagnostic, ...]


def _finding(code: str, joint: JointReport, message: str) -> Diagnostic:
    return Diagnostic(CODES[code], code, joint.name, message, joint.line)


def _base(joints: tuple[JointReport, ...]) -> tuple[str, JointReport | None]:
    """The base link, and the floating joint above it (None: the base is fixed).

    Raises:
        JointMatchError: Several roots, several floating joints, or a floating joint
            that is not the robot's one way to the world.
    """
    children = {joint.child_link for joint in joints}
    floating = [joint for joint in joints if joint.kind is JointKind.FLOATING]
    if len(floating) > 1:
        names = ", ".join(f"'{joint.name}'" for joint in floating[:3])
        raise JointMatchError(
            f"floating joints {names}: PyBullet loads one multibody a file, with one free base"
        )
    roots = list(dict.fromkeys(j.parent_link for j in joints if j.parent_link not in children))
    if floating:
        joint = floating[0]
        alone = [j for j in joints if j.parent_link == joint.parent_link]
        if joint.parent_link in children or len(alone) > 1 or len(roots) > 1:
            raise JointMatchError(
                f"joint '{joint.name}' is floating and not the robot's only joint to the "
                "world: PyBullet's multibody floats only at its base"
            )
        if joint.origin is not None:
            raise JointMatchError(
                f"joint '{joint.name}' is floating with an <origin>: PyBullet's base pose is "
                "in the world, which cspace does not map from the joint's frame"
            )
        return joint.child_link, joint
    if not joints:  # one link: the report names none
        return "", None
    for joint in joints:
        if joint.parent_link is None:  # cspace's root joint, and not floating
            raise JointMatchError(
                f"joint '{joint.name}' is {joint.kind.value}: PyBullet's base floats free "
                "or is fixed, and cspace does not map another root joint"
            )
    if len(roots) != 1 or roots[0] is None:
        raise JointMatchError(
            f"robot has {len(roots)} root links: PyBullet loads a URDF with one base link"
        )
    return roots[0], None


def _children(
    joints: tuple[JointReport, ...], fmt: str
) -> dict[str | None, list[list[JointReport]]]:
    """Each link's child joints, grouped by child link, in the order PyBullet takes them.

    Raises:
        JointMatchError: A URDF's report keeps no lines for siblings (a xacro file's).
    """
    below: dict[str | None, dict[str, list[tuple[float, int, JointReport]]]] = {}
    for index, joint in enumerate(joints):
        line = joint.line if fmt in _URDF and joint.line is not None else None
        key = float(line) if line is not None else (float("inf") if fmt in _URDF else index)
        below.setdefault(joint.parent_link, {}).setdefault(joint.child_link, []).append(
            (key, index, joint)
        )
    out: dict[str | None, list[list[JointReport]]] = {}
    for link, groups in below.items():
        found = sorted(sorted(group) for group in groups.values())
        keys = [group[0][0] for group in found]
        if len(found) > 1 and (float("inf") in keys or len(set(keys)) < len(keys)):
            raise JointMatchError(
                f"link '{link}' has several child joints and the report does not say in which "
                "order the file declares them, which is PyBullet's joint order: expand it to "
                "a URDF with one joint per line first (xacro FILE > robot.urdf)"
            )
        out[link] = [[joint for _, _, joint in group] for group in found]
    return out


def pybullet_order(data: SpaceData) -> PybulletOrder:
    """The joints as ``p.loadURDF`` numbers them (see the module docstring).

    Raises:
        JointMatchError: A joint PyBullet stores in a way cspace does not map (planar,
            universal, helical, translation), several floating joints, or several roots.
    """
    joints = data.report_joints
    base, free = _base(joints)
    below = _children(tuple(j for j in joints if j is not free), data.source_format)
    blocks, followers = joint_blocks(data)
    out: list[PybulletJoint] = []
    findings: list[Diagnostic] = []
    q_at, u_at = BASE_Q, BASE_Q - 1
    parents = {base: -1}
    stack = list(reversed(below.get(base, [])))
    while stack:  # iterative: trees may be thousands of joints deep
        group = stack.pop()
        for joint in group:
            kind = joint.kind
            if joint.name in followers:
                kind = JointKind.MIMIC if followers[joint.name].leader is not None else kind
            elif joint.name not in blocks:
                kind = JointKind.FIXED
            if kind not in (*_ONE, JointKind.SPHERICAL, JointKind.FIXED):
                said = {JointKind.PLANAR: " (its state has three positions, it reports two)"}
                raise JointMatchError(
                    f"joint '{joint.name}' is {joint.kind.value}: PyBullet stores it in "
                    f"coordinates cspace does not map{said.get(joint.kind, '')}"
                )
            nq, nv = (4, 3) if kind is JointKind.SPHERICAL else (1, 1)
            moving = kind is not JointKind.FIXED
            index = len(out)
            parent = parents.get(joint.parent_link or "", -1)
            out.append(
                PybulletJoint(
                    index,
                    joint.name,
                    kind,
                    joint.child_link,
                    parent,
                    q_at if moving else -1,
                    u_at if moving else -1,
                )
            )
            parents[joint.child_link] = index
            if moving:
                q_at, u_at = q_at + nq, u_at + nv
            follower = followers.get(joint.name)
            if follower is not None and follower.leader is not None:
                findings.append(
                    _finding(
                        "pybullet-mimic-free",
                        joint,
                        f"PyBullet ignores <mimic>: joint '{joint.name}' moves freely there "
                        f"(these vectors set it from '{follower.leader}'; hold it with a "
                        "JOINT_GEAR constraint)",
                    )
                )
        stack += reversed(below.get(group[0].child_link, []))
    if free is not None and free.parent_link is not None and data.source_format in _URDF:
        findings.append(
            _finding(
                "pybullet-floating-fixed",
                free,
                f"PyBullet's URDF importer makes floating joint '{free.name}' fixed; these "
                f"vectors are those of link '{base}' as the free base, which PyBullet gives "
                f"it without link '{free.parent_link}' and the joint",
            )
        )
    floats = None if free is not None or base in ("world", "") else base
    return PybulletOrder(base, free is not None, tuple(out), floats, tuple(findings))


def pybullet_layout(data: SpaceData, order: PybulletOrder) -> DrakeLayout:
    """PyBullet's vectors as a layout of the canonical ones (see the module docstring)."""
    blocks, followers = joint_blocks(data)
    parts = LayoutParts()
    free = next((j for j in data.report_joints if j.kind is JointKind.FLOATING), None)
    if order.free and free is not None:
        block = blocks[free.name]
        c, t = block.columns.start, block.tangent.start
        taken = frozenset(joint.name for joint in order.joints)
        q, v = isaac_names(free, JointKind.FLOATING, taken)  # named as Isaac names its root
        parts.floating.append((3, c + 3, t + 3))  # canonical x y z qw qx qy qz; v, then w
        columns, tangent = xyzw_pose_columns(c, t)
        parts.add(q, v, columns, tangent)
    for joint in order.joints:
        if not joint.moves:
            continue
        follower = followers.get(joint.name)
        if follower is not None:
            parts.follow(follower, blocks, [joint.name], [joint.name])
            continue
        block = blocks[joint.name]
        c, t = block.columns.start, block.tangent.start
        if joint.kind is JointKind.SPHERICAL:  # canonical qw qx qy qz -> x y z w
            parts.add(
                [f"{joint.name}_{s}" for s in _BALL_Q],
                [f"{joint.name}_{s}" for s in _BALL_V],
                [c + 1, c + 2, c + 3, c],
                [t, t + 1, t + 2],
            )
        else:
            parts.add([joint.name], [joint.name], [c], [t])
    return parts.layout(
        vectors=("PyBullet's base pose and joint positions", "PyBullet's velocities"),
        findings=order.findings,
    )


class Maps(LayoutMaps):
    """PyBullet's maps: a free base's pose, then joint positions by joint index."""

    def __init__(self, robot: Robot) -> None:
        self.order = pybullet_order(robot.data)
        super().__init__(robot, pybullet_layout(robot.data, self.order))
