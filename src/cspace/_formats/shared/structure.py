"""Checks of a robot's kinematic structure, shared by every format reader.

A robot file describes a tree: every link but one (the root) has exactly one parent
joint, joints connect links that exist, names are unique, and mimic joints follow
joints that exist without following each other in a circle. Each broken rule raises a
`RobotStructureError` with its own ``code``, the element's line
and its name. How large a robot may be (joints, names, degrees of freedom, depth) is
`robot_size`'s to say.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import TypeVar

from cspace._formats.shared.description import JointSpec, LinkSpec, RobotDescription
from cspace._formats.shared.robot_size import check_depth, check_sizes, name_bytes, too_long
from cspace.errors import RobotFileError, RobotFileErrors, RobotStructureError
from cspace.errors._base import did_you_mean

MAX_SUGGESTIONS = 10
"""Missing links given a "did you mean" (each compares the name with every link: 800
misspelt links of 5,000 took more than 30 s)."""

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

    # Every format's limits (URDF's reader checks the counts before reading, too).
    check_sizes(path, format, links, joints, line)
    if too_long(name):
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
    check_depth(path, ordered)
    _check_mimics(path, joint_by_name)
    return RobotDescription(
        name=name,
        format=format,
        root_link=roots[0].name,
        links=tuple(links),
        joints=tuple(ordered),
    )


def _depth_first(root: str, children: dict[str, list[JointSpec]]) -> list[JointSpec]:
    ordered: list[JointSpec] = []
    stack = list(reversed(children.get(root, [])))
    while stack:
        joint = stack.pop()
        ordered.append(joint)
        stack.extend(reversed(children.get(joint.child, [])))
    return ordered


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
