"""How large a robot cspace reads: joints and links, names, degrees of freedom, depth.

Every format's reader holds a file to these limits before Pinocchio builds its model,
whose time and memory grow with them. Each broken limit raises a `RobotStructureError`
with its own ``code`` (``too-many-joints``, ``name-too-long``, ``too-many-dofs``,
``too-deep``) and, where there is one, the element's line and name.
"""

from __future__ import annotations

from collections.abc import Sequence

from cspace._formats.shared.description import JointSpec, LinkSpec
from cspace._joint_kind import JointKind
from cspace.errors import InvalidElementError, RobotStructureError

MAX_DEPTH = 1000
"""Most joints on one path from the root link (as for MJCF bodies): a chain this deep is
the deepest tree `MAX_DEPTH_SUM` admits. Pinocchio's URDF parser recurses once per
joint of depth (about 2.2 KiB of stack a level) and crashed (SIGSEGV, not an error)
7,538 deep on the 16 MiB stack it gets here (see
``cspace._model.native.BUILD_STACK_BYTES``); its memory stops a tree far sooner. Real
robots are tens of joints deep; a chain of 1,000 floating joints took 189 MiB."""


MAX_DEPTH_SUM = 500_500
"""Most joints' depths added up (each joint's chain of joints to the root): those of a
chain `MAX_DEPTH` deep, 1,000 x 1,001 / 2. Pinocchio keeps every joint's chain (its
``supports``), so its memory grows with this sum, more with the degrees of freedom on
each chain; and besides with each joint's degrees of freedom before it in Pinocchio's
order, which only the joint and degree-of-freedom limits bound (5,000 joints under one
link, 10,000 degrees of freedom, the 1,000 floating joints first: 469 MiB, as xacro
487). The worst tree within every limit, measured (``cspace inspect``): 100 floating
joints deep with 4,900 joints under the last one (900 floating first, then 4,000
continuous), adding up to 499,950 with 10,000 degrees of freedom, took 512 MiB (as xacro
517, as SDF with ball joints 438). In that shape 743,675 took 546 MiB as xacro, and a
1,700-deep chain with 3,300 joints under it (7.06 million, which an earlier limit of 7.1
million admitted) 628 MiB."""

MAX_JOINTS = 5000
"""Most joints (fixed ones included) or links in one robot file. Real robots have at most
a few hundred; Pinocchio's model building grows quadratically with the number of joints
(about 2 s for 5000 here, minutes for 50,000), so larger files are refused up front."""

MAX_CUTS = 1000
"""Most constraints that close kinematic loops in one robot file (SDF joints that close a
loop and Drake's ``<drake:ball_constraint>``, together; MJCF's equality constraints have
their own limit of the same size). Real mechanisms have a few (Cassie: 4); each one adds
a frame to each side of the tree's model and up to 6 rows to the constraint Jacobian the
closure analysis factors at every sample."""

MAX_NAME = 256
"""Longest robot, link or joint name, in characters, and in the bytes it takes in a
report (UTF-8, each character an output escapes as its escape: ``\u200b`` is 6 bytes).
Real names have a few dozen; a name is repeated in every section of a report, so
3,000-character names made a 63 MiB file into a 276 MB report, and names of 256
escaped characters a 5 MB file into a 164 MiB one, more than cspace reads back."""

MAX_DOF = 10_000
"""Most degrees of freedom in one robot file. Pinocchio's memory grows with them, not
with the joints: 5,000 floating joints (30,000 degrees of freedom) took 970 MiB and
5,000 planar ones 550 MiB, where 5,000 revolute ones take 240 MiB."""

DOF = {
    **dict.fromkeys(
        (JointKind.REVOLUTE, JointKind.CONTINUOUS, JointKind.PRISMATIC, JointKind.HELICAL), 1
    ),
    JointKind.UNIVERSAL: 2,
    **dict.fromkeys((JointKind.PLANAR, JointKind.SPHERICAL, JointKind.TRANSLATION), 3),
    JointKind.FLOATING: 6,
}
"""Degrees of freedom of each joint kind (fixed joints: 0)."""


def check_sizes(
    path: str,
    format: str,
    links: Sequence[LinkSpec],
    joints: Sequence[JointSpec],
    line: int | None = None,
) -> None:
    """Refuse more links, joints or degrees of freedom, or longer names, than `cspace` reads.

    Raises:
        RobotStructureError: ``too-many-joints``, ``name-too-long`` or ``too-many-dofs``.
    """
    check_count(path, f"{format.upper()} links", len(links), line, MAX_JOINTS + 1)
    check_count(path, f"{format.upper()} joints", len(joints), line, MAX_JOINTS)
    named = [(link.name, link.line) for link in links] + [(j.name, j.line) for j in joints]
    for item, at in named:
        if item is not None:
            check_name(path, item, at)
    dof = sum(DOF.get(joint.kind, 0) for joint in joints)
    if dof > MAX_DOF:
        raise RobotStructureError(
            path,
            f"the robot has {dof:,} degrees of freedom; cspace refuses more than {MAX_DOF:,} "
            "(Pinocchio's memory grows with them)",
            code="too-many-dofs",
            line=line,
        )


def check_name(path: str, item: str, line: int | None, what: str = "a name") -> None:
    """Refuse a name a report could not hold (`MAX_NAME` characters or bytes).

    Raises:
        RobotStructureError: ``name-too-long``.
    """
    if too_long(item):
        raise RobotStructureError(
            path,
            f"{what} of {len(item):,} characters ({name_bytes(item):,} bytes in a report), "
            f"more than the {MAX_NAME} cspace reads: '{item[:40]}...'",
            code="name-too-long",
            line=line,
            element=item[:40],
        )


def too_long(name: str) -> bool:
    """Whether a report could not hold ``name`` (`MAX_NAME` characters or bytes)."""
    return len(name) > MAX_NAME or name_bytes(name) > MAX_NAME


def name_bytes(name: str) -> int:
    """The bytes a name takes inside a JSON report's string (see `MAX_NAME`)."""
    if name.isascii() and name.isprintable():
        return len(name) + name.count('"') + name.count("\\")
    from cspace._safetext import json_text

    return len(json_text(name).encode("utf-8", "surrogatepass")) - 2


def check_count(
    path: str, what: str, count: int, line: int | None, limit: int = MAX_JOINTS
) -> None:
    """Refuse a robot with more than ``limit`` joints or links, before reading them.

    Args:
        path: The file, for messages.
        what: ``"joints"`` or ``"links"`` (the format's own word).
        count: How many the file declares.
        line: Line of the robot's element, or None.
        limit: The most allowed (links: one more than joints).

    Raises:
        RobotStructureError: ``count`` exceeds ``limit`` (code ``too-many-joints``).
    """
    if count > limit:
        raise RobotStructureError(
            path,
            f"the robot declares {count:,} {what}; cspace refuses more than {limit:,} "
            "(real robots have at most a few hundred, and building larger models takes "
            "minutes)",
            code="too-many-joints",
            line=line,
        )


def check_cuts(path: str, count: int, line: int | None) -> None:
    """Refuse more constraints closing loops than `MAX_CUTS`, before reading them.

    Args:
        path: The file, for messages.
        count: How many the file declares (loop joints and ball constraints together).
        line: Line of the robot's element, or None.

    Raises:
        InvalidElementError: ``too-many-constraints``.
    """
    if count > MAX_CUTS:
        raise InvalidElementError(
            path,
            f"the robot closes {count:,} kinematic loops (joints that close a loop and "
            f"<drake:ball_constraint>s); cspace refuses more than {MAX_CUTS:,}",
            code="too-many-constraints",
            line=line,
        )


def check_depth(path: str, ordered: list[JointSpec]) -> None:
    """Refuse a tree too deep for Pinocchio's parser, or too large for its memory.

    Deeper than ``MAX_DEPTH`` joints, or joints' depths adding up to more than
    ``MAX_DEPTH_SUM`` (``ordered``: parents first).
    """
    depth: dict[str, int] = {}
    total = 0
    for joint in ordered:
        depth[joint.child] = depth.get(joint.parent, 0) + 1
        total += depth[joint.child]
        if depth[joint.child] > MAX_DEPTH or total > MAX_DEPTH_SUM:
            why = (
                f"is more than {MAX_DEPTH} joints deep at joint '{joint.name}'; cspace "
                "refuses deeper trees (Pinocchio's memory grows with the square of the depth)"
                if depth[joint.child] > MAX_DEPTH
                else f"has joints whose depths add up to more than {MAX_DEPTH_SUM:,} at "
                f"joint '{joint.name}'; cspace refuses such trees (Pinocchio's memory "
                "grows with that sum)"
            )
            raise RobotStructureError(
                path,
                f"the kinematic tree {why}",
                code="too-deep",
                line=joint.line,
                element=joint.name,
            )
