"""The robot's root: joints that already give a body its pose, and advice to add a root joint.

A file without a floating or planar joint may still give a body a pose, through joints
from the root link that together move it as one would (`_root_chains`: ``planar-root``,
``spatial-root``). Such a chain is recognised where it starts, at a child of the root
link, and named; a body it moves is not one that a root joint could be added to, so it
is never advised.

``root-joint-suggested`` is a heuristic: two or more leg chains (joint names with hip,
knee, leg, ...) hanging from the root link, or two or more wheel joints, with no joint
that moves the rest of the robot, suggest that the file bolts a robot that walks or
drives to the world. It is never made when a root joint was added (``--root-joint``, an
SRDF's virtual joint) or the file has a floating or planar joint.
"""

import re
from collections.abc import Iterable, Iterator, Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, RobotDescription
from cspace._joint_kind import JointKind
from cspace._joint_report import kept_limits
from cspace._joint_table import locked
from cspace._model._root_chains import Placer, named, recognise
from cspace._record import NamedTuple

ADVICE = "root-joint-suggested"
"""The code of the advice to add a root joint."""

_ROOT_KINDS = (JointKind.FLOATING, JointKind.PLANAR)
_LEG_WORDS = ("leg", "hip", "knee", "ankle", "thigh", "calf", "shank", "haa", "hfe", "kfe")
"""Words in the joint names of a leg (HAA, HFE, KFE: ANYmal's and Solo's hip and knee)."""
_LEG = re.compile("|".join(_LEG_WORDS))


class _Branch(NamedTuple):
    """What hangs from the root link through one child link.

    Attributes:
        chain: The joints from the root link to that child (MJCF: a body's joints) and
            those below, in order, down to the first link that carries moving joints
            through more than one child link (or none).
        trunk_branches: How many child links of that last link carry moving joints.
    """

    chain: tuple[JointSpec, ...]
    trunk_branches: int


def robot_findings(
    description: RobotDescription, root_joint: str | None, model: Any = None
) -> Iterator[Diagnostic]:
    """Findings about the whole robot: its root, and a robot bolted to the world.

    Args:
        description: The file's joints.
        root_joint: The root joint added above the root link, or None.
        model: Pinocchio's model of the file (``pinocchio.Model``), which places the
            joints of a root chain, or None (then only the joints of one MJCF body are
            placed: they share its frame).
    """
    children = _children(description.joints)
    moves = _moving(description.joints)
    below = _moving_below(description.joints, moves)
    root = description.root_link
    held = {j.name: j.lower[0] for j in description.joints if j.lower and j.name not in moves}
    placer = None if model is None else Placer(model, held)
    carried: list[str] = []  # child links of the root moved by joints of their own
    for child, joints in children.get(root, {}).items():
        branch = _branch(children, below, moves, joints)
        found = recognise(description, branch.chain, placer, moves)
        if found is not None:
            yield named(found, root, root_joint)
        moving = any(j.name in moves for j in branch.chain)
        if found is not None or (moving and branch.trunk_branches >= 2):
            carried.append(child)
    if root_joint is not None or any(j.kind in _ROOT_KINDS for j in description.joints):
        return
    yield from _advice(description, children, set(carried), moves)


def _children(joints: Sequence[JointSpec]) -> dict[str, dict[str, list[JointSpec]]]:
    """Link -> child link -> the joints between them, in file order (MJCF: several)."""
    children: dict[str, dict[str, list[JointSpec]]] = {}
    for joint in joints:
        children.setdefault(joint.parent, {}).setdefault(joint.child, []).append(joint)
    return children


def _moving(joints: Sequence[JointSpec]) -> frozenset[str]:
    """The joints the report gives freedom, by name (`_moves`), decided once each."""
    return frozenset(j.name for j in joints if _moves(j))


def _moves(joint: JointSpec) -> bool:
    """Whether the report gives the joint freedom: neither fixed nor locked.

    Locked as the analysis reads it (`_joint_table.locked` of the limits the report
    keeps, `_joint_report.kept_limits`): it contributes dimension 0, and its child stays
    where its bound puts it, as below a fixed joint. A mimic joint moves with its leader,
    whatever its limits.
    """
    if joint.kind is JointKind.FIXED:
        return False
    return joint.mimic is not None or not locked(kept_limits(joint.kind, joint.lower, joint.upper))


def _moving_below(joints: Sequence[JointSpec], moves: frozenset[str]) -> dict[str, bool]:
    """Link -> whether a moving joint hangs below it (joints are depth-first: one pass up)."""
    below: dict[str, bool] = {}
    for joint in reversed(joints):
        moving = joint.name in moves or below.get(joint.child, False)
        below[joint.parent] = below.get(joint.parent, False) or moving
    return below


def _carries(joints: Iterable[JointSpec], below: dict[str, bool], moves: frozenset[str]) -> bool:
    return any(j.name in moves or below.get(j.child, False) for j in joints)


def _branch(
    children: dict[str, dict[str, list[JointSpec]]],
    below: dict[str, bool],
    moves: frozenset[str],
    first: list[JointSpec],
) -> _Branch:
    """The chain from the root link through ``first``: each link of it carries the next.

    Links that carry no moving joint (a camera, a sensor) do not end the chain.
    """
    chain = list(first)
    link = first[0].child
    while True:  # a tree: each link once
        onward = [js for js in children.get(link, {}).values() if _carries(js, below, moves)]
        if len(onward) != 1:
            return _Branch(tuple(chain), len(onward))
        chain.extend(onward[0])
        link = onward[0][0].child


def _advice(
    description: RobotDescription,
    children: dict[str, dict[str, list[JointSpec]]],
    carried: set[str],
    moves: frozenset[str],
) -> Iterator[Diagnostic]:
    """``root-joint-suggested``: legs hang from the root link, or wheels turn below it.

    Neither counts below a child of the root that joints of its own move (``carried``):
    a root joint added above the root link would move that body a second time.
    """
    # One pass from the leaves up (the joints are depth-first): a joint is a leg's when it
    # or a joint below it is named like one.
    leggy: dict[str, bool] = {}
    below: dict[str, bool] = {}  # link -> a leg's joint hangs below it
    for joint in reversed(description.joints):
        own = joint.name in moves and _LEG.search(joint.name.lower()) is not None
        leggy[joint.name] = own or below.get(joint.child, False)
        below[joint.parent] = below.get(joint.parent, False) or leggy[joint.name]
    root = description.root_link
    legs = [
        joints[0].name
        for child, joints in children.get(root, {}).items()
        if child not in carried and any(leggy[j.name] for j in joints)
    ]
    moved = _links_below(children, carried)
    wheels = [
        j.name
        for j in description.joints
        if j.kind is JointKind.CONTINUOUS
        and "wheel" in (j.name + j.child).lower()
        and j.parent not in moved
    ]
    if len(legs) >= 2:
        yield finding(
            ADVICE,
            None,
            f"{len(legs)} legs ({', '.join(legs[:6])}) hang from link '{root}', which the file "
            "bolts to the world: for a robot that walks, inspect with --root-joint floating",
        )
    elif len(wheels) >= 2:
        yield finding(
            ADVICE,
            None,
            f"{len(wheels)} wheel joints ({', '.join(wheels[:6])}) turn under link '{root}', "
            "which the file bolts to the world: for a robot that drives on the floor, "
            "inspect with --root-joint planar",
        )


def _links_below(children: dict[str, dict[str, list[JointSpec]]], tops: set[str]) -> set[str]:
    """``tops`` and every link below them."""
    found, frontier = set(tops), list(tops)
    while frontier:
        for child in children.get(frontier.pop(), {}):
            if child not in found:
                found.add(child)
                frontier.append(child)
    return found


def without_advice(diagnostics: Iterable[Diagnostic]) -> tuple[Diagnostic, ...]:
    """The findings less the advice to add a root joint (an SRDF's virtual joint decides)."""
    return tuple(d for d in diagnostics if d.code != ADVICE)
