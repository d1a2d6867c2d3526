"""Where each joint sits in a tool's vector: the joint order ``cspace diff`` compares.

A tool's positions are named after their joints (``elbow``, ``base.qx``, ``elbow_q``) or,
for a floating body, after the body (``trunk_x``: Drake's, Isaac's and PyBullet's
names). The joint of each entry is read back from those names: the name itself, or a
joint's (or a floating joint's body's) name, a separator (``.`` or ``_``) and one of
the suffixes the conventions write. A joint's index is its first entry.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cspace._joint_kind import JointKind
from cspace._tools import TOOLS

if TYPE_CHECKING:
    from cspace._joint_report import JointReport

ORDERS = tuple(name for name in TOOLS if name != "mujoco-ctrl")
"""The conventions whose vectors hold joints (MuJoCo's ctrl holds actuators)."""

_SUFFIXES = frozenset(
    {"x", "y", "z", "qw", "qx", "qy", "qz", "q", "w", "v", "wx", "wy", "wz", "vx", "vy", "vz"}
    | {"theta", "theta.cos", "theta.sin", "cos", "sin", "TX", "TY", "RZ"}
)
"""What the conventions write after a joint's (or a body's) name."""


def _joint_of(name: str, joints: frozenset[str], bodies: dict[str, str]) -> str | None:
    """The joint an entry named ``name`` belongs to, or None (``q[3]``, an unknown name)."""
    if name in joints:
        return name
    for at in sorted((k for k, c in enumerate(name) if c in "._"), reverse=True):
        head, tail = name[:at], name[at + 1 :]
        if tail not in _SUFFIXES:
            continue
        if head in joints:
            return head
        body = head.lstrip("_")  # a body renamed away from a joint's name (Drake, Isaac)
        if body in bodies:
            return bodies[body]
    return None


def joint_indices(conventions: Any, convention: str) -> dict[str, int]:
    """Each joint's first entry in ``convention``'s position vector, in that order.

    Joints without an entry (fixed joints; a mimic follower in Pinocchio's q or the
    canonical coordinates) are left out.

    Raises:
        JointMatchError: The tool cannot store the robot (as ``conventions.names``).
    """
    report: tuple[JointReport, ...] = conventions.space.report_joints
    joints = frozenset(j.name for j in report)
    bodies = {j.child_link: j.name for j in report if j.kind is JointKind.FLOATING}
    found: dict[str, int] = {}
    for index, name in enumerate(conventions.names(convention)):
        joint = _joint_of(name, joints, bodies)
        if joint is not None and joint not in found:
            found[joint] = index
    return found
