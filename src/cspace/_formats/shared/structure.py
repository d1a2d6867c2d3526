"""Checks of a robot's kinematic structure, shared by every format reader.

A robot file describes a tree: every link but one (the root) has exactly one parent
joint, joints connect links that exist, names are unique, and mimic joints follow
joints that exist without following each other in a circle. Each broken rule raises a
`RobotStructureError` with its own ``code``, the element's line
and its name.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import TypeVar

from cspace._formats.shared.description import JointSpec, LinkSpec, RobotDescription
from cspace._joint_kind import JointKind
from cspace.errors import RobotFileError, RobotFileErrors, RobotStructureError
from cspace.errors._base import did_you_mean

MAX_SUGGESTIONS = 10
"""Missing links given a "did you mean" (each compares the name with every link: 800
misspelt links of 5,000 took more than 30 s)."""

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

_Named = TypeVar("_Named", JointSpec, LinkSpec)


def unique_by_name(path: str, items: Iterable[_Named], what: str) -> dict[str, _Named]:
    """The items by name, in order.

    Raises:
        RobotStructureError: Two share a name (``duplicate-link`` or ``duplicate-joint``).
    """
    by_name: dict[str, _Named] = {}
    for item in items:
        if item.name in by_name:
            first = by_name[item.name].line
            where = f" (first at line {first})" if first is not None else ""
            raise RobotStructureError(
                path,
                f"{what} '{item.name}' is defined twice{where}",
                code=f"duplicate-{what}",
                line=item.line,
                element=item.name,
            )
        by_name[item.name] = item
    return by_name


def build_description(
    path: str,
    *,
    name: str,
    format: str,
    links: Sequence[LinkSpec],
    joints: Sequence[JointSpec],
    siblings_by_name: bool = False,
    line: int | None = None,
) -> RobotDescription:
    """Check the structure and order the joints depth-first from the root link.

    Args:
        path: The file, for error messages.
        name: Robot name.
        format: Format identifier (``"urdf"``, ...).
        links: Links in file order.
        joints: Joints in file order.
        siblings_by_name: Visit sibling joints in order of name (as Pinocchio's URDF
            parser does, so that the order matches Pinocchio's q) instead of file order.
        line: Line of the robot's own element (for a robot without links), or None.

    Returns:
        The checked description.

    Raises:
        RobotStructureError: A structural rule is broken.
    """

    def fail(code: str, problem: str, line: int | None, element: str | None) -> None:
        raise RobotStructureError(path, problem, code=code, line=line, element=element)

    # Every format's limit (URDF's reader checks it before reading, too).
    check_count(path, f"{format.upper()} links", len(links), line, MAX_JOINTS + 1)
    check_sizes(path, format, links, joints, line)
    if len(name) > MAX_NAME or name_bytes(name) > MAX_NAME:
        said = f"{len(name):,} characters ({name_bytes(name):,} bytes in a report)"
        fail("name-too-long", f"the robot's name has {said}", line, None)
    if not links:
        robot = f"robot '{name}'" if name else "the robot element"
        fail(
            "no-links",
            f"{robot} has no links: the file describes no robot "
            "(an empty robot element is often xacro output whose macros were never called)",
            line,
            name or None,
        )
    link_by_name = unique_by_name(path, links, "link")
    joint_by_name = unique_by_name(path, joints, "joint")
    parent_joint: dict[str, JointSpec] = {}
    children: dict[str, list[JointSpec]] = {}
    problems: list[RobotFileError] = []  # every joint's, reported together

    def suggest() -> bool:  # "did you mean" costs a scan of every link: a few at most
        return len(problems) < MAX_SUGGESTIONS

    def note(code: str, problem: str, joint: JointSpec) -> None:
        problems.append(
            RobotStructureError(path, problem, code=code, line=joint.line, element=joint.name)
        )

    for joint in joints:
        for role, link_name in (("parent", joint.parent), ("child", joint.child)):
            if link_name not in link_by_name:
                note(
                    "missing-link",
                    f"joint '{joint.name}' names {role} link '{link_name}', which does not "
                    f"exist{did_you_mean(link_name, link_by_name) if suggest() else ''}",
                    joint,
                )
        if joint.parent == joint.child:
            note("cycle", f"joint '{joint.name}' connects link '{joint.child}' to itself", joint)
            continue  # its link's other parent, if any, is not a second problem
        if joint.child in parent_joint:
            other = parent_joint[joint.child]
            note(
                "two-parents",
                f"link '{joint.child}' has two parent joints, '{other.name}' "
                f"(line {other.line}) and '{joint.name}'",
                joint,
            )
        parent_joint[joint.child] = joint
        children.setdefault(joint.parent, []).append(joint)
    if problems:
        raise RobotFileErrors.of(problems)

    roots = [link for link in links if link.name not in parent_joint]
    if not roots:
        # Every link has a parent: the joints close at least one loop.
        _raise_cycle(path, links[0].name, parent_joint)
    if len(roots) > 1:
        names = ", ".join(f"'{r.name}'" for r in roots[:5]) + (", ..." if len(roots) > 5 else "")
        fail(
            "several-roots",
            f"{len(roots)} links have no parent joint ({names}); a robot has exactly one root link",
            roots[1].line,
            roots[1].name,
        )
    if siblings_by_name:
        for group in children.values():
            group.sort(key=lambda j: j.name)
    ordered = _depth_first(roots[0].name, children)
    if len(ordered) < len(joints):
        reached = {j.name for j in ordered}
        stray = next(j for j in joints if j.name not in reached)
        _raise_cycle(path, stray.child, parent_joint)
    _check_depth(path, ordered)
    _check_mimics(path, joint_by_name)
    return RobotDescription(
        name=name,
        format=format,
        root_link=roots[0].name,
        links=tuple(links),
        joints=tuple(ordered),
    )


def check_sizes(
    path: str,
    format: str,
    links: Sequence[LinkSpec],
    joints: Sequence[JointSpec],
    line: int | None = None,
) -> None:
    """Refuse more joints, longer names or more degrees of freedom than `cspace` reads.

    Raises:
        RobotStructureError: ``too-many-joints``, ``name-too-long`` or ``too-many-dofs``.
    """
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


def _depth_first(root: str, children: dict[str, list[JointSpec]]) -> list[JointSpec]:
    ordered: list[JointSpec] = []
    stack = list(reversed(children.get(root, [])))
    while stack:
        joint = stack.pop()
        ordered.append(joint)
        stack.extend(reversed(children.get(joint.child, [])))
    return ordered


MAX_JOINTS = 5000
"""Most joints (fixed ones included) or links in one robot file. Real robots have at most
a few hundred; Pinocchio's model building grows quadratically with the number of joints
(about 2 s for 5000 here, minutes for 50,000), so larger files are refused up front."""

MAX_NAME = 256
"""Longest robot, link or joint name, in characters, and in the bytes it takes in a
report (UTF-8, each character an output escapes as its escape: ``\u200b`` is 6 bytes).
Real names have a few dozen; a name is repeated in every section of a report, so
3,000-character names made a 63 MiB file into a 276 MB report, and names of 256
escaped characters a 5 MB file into a 164 MiB one, more than cspace reads back."""


def check_name(path: str, item: str, line: int | None, what: str = "a name") -> None:
    """Refuse a name a report could not hold (`MAX_NAME` characters or bytes).

    Raises:
        RobotStructureError: ``name-too-long``.
    """
    if len(item) > MAX_NAME or name_bytes(item) > MAX_NAME:
        raise RobotStructureError(
            path,
            f"{what} of {len(item):,} characters ({name_bytes(item):,} bytes in a report), "
            f"more than the {MAX_NAME} cspace reads: '{item[:40]}...'",
            code="name-too-long",
            line=line,
            element=item[:40],
        )


def name_bytes(name: str) -> int:
    """The bytes a name takes inside a JSON report's string (see `MAX_NAME`)."""
    if name.isascii() and name.isprintable():
        return len(name) + name.count('"') + name.count("\\")
    from cspace._safetext import json_text

    return len(json_text(name).encode("utf-8", "surrogatepass")) - 2


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


def _check_depth(path: str, ordered: list[JointSpec]) -> None:
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


def _raise_cycle(path: str, start: str, parent_joint: dict[str, JointSpec]) -> None:
    """Walk up parent joints from ``start`` until a link repeats, and report that loop."""
    seen: dict[str, None] = {}
    link = start
    while link not in seen:
        seen[link] = None
        link = parent_joint[link].parent
    names = list(seen)
    loop = [*names[names.index(link) :], link]
    joint = parent_joint[loop[0]]
    raise RobotStructureError(
        path,
        f"the joints form a cycle through links {_arrow_list(list(reversed(loop)))}",
        code="cycle",
        line=joint.line,
        element=joint.name,
    )


def _check_mimics(path: str, joints: dict[str, JointSpec]) -> None:
    for joint in joints.values():
        if joint.mimic is not None and joint.mimic.joint not in joints:
            raise RobotStructureError(
                path,
                f"joint '{joint.name}' mimics joint '{joint.mimic.joint}', which does not "
                f"exist{did_you_mean(joint.mimic.joint, joints)}",
                code="mimic-unknown-joint",
                line=joint.line,
                element=joint.name,
            )
    # Follow each mimic chain once (linear time): a chain that reaches a joint already
    # on it is a circle; one that reaches a joint already cleared is not.
    cleared: set[str] = set()
    for joint in joints.values():
        chain: dict[str, None] = {}
        leader: JointSpec | None = joint
        while leader is not None and leader.name not in cleared:
            if leader.name in chain:
                names = list(chain)
                loop = [*names[names.index(leader.name) :], leader.name]
                culprit = joints[loop[0]]
                problem = (
                    f"joint '{culprit.name}' mimics itself"
                    if len(loop) == 2
                    else f"mimic joints follow each other in a circle: {_arrow_list(loop)}"
                )
                raise RobotStructureError(
                    path, problem, code="mimic-cycle", line=culprit.line, element=culprit.name
                )
            chain[leader.name] = None
            leader = joints[leader.mimic.joint] if leader.mimic is not None else None
        cleared.update(chain)


def _arrow_list(names: list[str]) -> str:
    """``a -> b -> c``, shortened in the middle when long (messages stay one short line)."""
    if len(names) > 9:
        names = [*names[:4], f"... ({len(names) - 8} more)", *names[-4:]]
    return " -> ".join(names)


JOINT_OWN = frozenset({"missing-link", "two-parents", "cycle", "duplicate-joint", "duplicate-link"})
"""Structure problems that belong to one joint, whatever else the file holds."""

T = TypeVar("T")
E = TypeVar("E")


def read_each(
    elements: Iterable[E], read: Callable[[E], T], problems: list[RobotFileError]
) -> list[T]:
    """``read`` of each element; one that cannot be read is left out, its problem kept.

    So that every element's problem is reported in one run (see `build_checked`).
    """
    out: list[T] = []
    for element in elements:
        try:
            out.append(read(element))
        except RobotFileError as exc:
            problems.append(exc)
    return out


def build_checked(
    problems: list[RobotFileError], build: Callable[[], RobotDescription]
) -> RobotDescription:
    """``build()``, raising the readers' ``problems`` and its own together, in file order.

    With elements left out, the tree's shape (roots, loops) says nothing: only the
    joints' own structure problems join the readers' then.

    Raises:
        RobotFileError: One problem, or `RobotFileErrors` for several.
    """
    try:
        description = build()
    except RobotFileError as exc:
        own = exc.errors if isinstance(exc, RobotFileErrors) else (exc,)
        problems += [e for e in own if not problems or e.code in JOINT_OWN]
        raise RobotFileErrors.of(problems) from None
    if problems:
        raise RobotFileErrors.of(problems)
    return description
