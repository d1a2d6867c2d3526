"""The robot's root: joints that already give a body its pose, and advice to add a root joint.

A file without a floating or planar joint may still give a body a pose: MJCF writes a
planar root as two slides and a hinge of one body (dm_control's and Gymnasium's cheetah,
walker and hopper: ``rootx``, ``rootz``, ``rooty``), URDF and SDF as a chain of links
from the world, each carrying the next. Such a chain is recognised where it starts, at a
child of the root link, and named (``planar-root``, ``spatial-root``); a body it moves
is not one that a root joint could be added to, so it is never advised.

``root-joint-suggested`` is a heuristic: two or more leg chains (joint names with hip,
knee, leg, ...) hanging from the root link, or two or more wheel joints, with no joint
that moves the rest of the robot, suggest that the file bolts a robot that walks or
drives to the world. It is never made when a root joint was added (``--root-joint``, an
SRDF's virtual joint) or the file has a floating or planar joint.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Iterator, Sequence
from typing import Any, NamedTuple

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, RobotDescription
from cspace._joint_kind import JointKind
from cspace._joint_report import Limits
from cspace._joint_table import locked

ADVICE = "root-joint-suggested"
"""The code of the advice to add a root joint."""

_ROOT_KINDS = (JointKind.FLOATING, JointKind.PLANAR)
_LEG_WORDS = ("leg", "hip", "knee", "ankle", "thigh", "calf", "shank", "haa", "hfe", "kfe")
"""Words in the joint names of a leg (HAA, HFE, KFE: ANYmal's and Solo's hip and knee)."""
_LEG = re.compile("|".join(_LEG_WORDS))

_LETTER = {
    JointKind.PRISMATIC: "S",
    JointKind.REVOLUTE: "H",
    JointKind.CONTINUOUS: "H",
    JointKind.SPHERICAL: "B",
    JointKind.TRANSLATION: "T",
}
"""The joints a root chain is made of: slides, hinges, a ball, a translation (3 slides)."""

_ROOT_FORMS = (
    ("SSSB", "spatial"),
    ("TB", "spatial"),
    ("SSSHHH", "spatial"),
    ("THHH", "spatial"),
    ("SSH", "planar"),
)
"""Which joints, in some order, give a body a pose in space or in a plane."""

_TOLERANCE = 1e-6
"""How far from perpendicular (a cosine) or from dependent (a sine, a volume) counts as so."""

_PLACED_FORMATS = ("urdf", "mjcf")
"""Formats whose Pinocchio model always places every joint (urdfdom, MuJoCo's compiler);
a joint of another format is placed when the reader gave its origin."""

Vector = tuple[float, float, float]


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


class _Root(NamedTuple):
    """Joints that together give a body its pose: ``planar`` (SE(2)) or ``spatial``."""

    form: str
    joints: tuple[JointSpec, ...]


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
    placer = None if model is None else _Placer(model, held)
    carried: list[str] = []  # child links of the root moved by joints of their own
    for child, joints in children.get(root, {}).items():
        branch = _branch(children, below, moves, joints)
        found = _recognise(description, branch.chain, placer, moves)
        if found is not None:
            yield _named(found, root, root_joint)
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
    keeps, `Limits.kept`): it contributes dimension 0, and its child stays where its
    bound puts it, as below a fixed joint. A mimic joint moves with its leader, whatever
    its limits.
    """
    if joint.kind is JointKind.FIXED:
        return False
    return joint.mimic is not None or not locked(Limits.kept(joint.kind, joint.lower, joint.upper))


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


def _recognise(
    description: RobotDescription,
    chain: Sequence[JointSpec],
    placer: _Placer | None,
    moves: frozenset[str],
) -> _Root | None:
    """The root the first moving joints of ``chain`` are, or None.

    Slides (or a translation) next to each other with independent directions, and a
    ball or hinges that turn a body every way (two slides and a hinge about the normal of
    their plane; three hinges whose middle axis is perpendicular to the other two,
    Davenport's condition). Slides apart (a hinge between them) are not: the hinge turns
    one slide onto the other's direction, and the body loses a direction there. Locked
    joints are passed over, as fixed ones (they move nothing); a mimic joint ends the
    search (it moves with its leader, which may be one of the joints before it).
    """
    moving = [j for j in chain if j.name in moves]
    letters = ""
    for joint in moving[:6]:
        letter = _LETTER.get(joint.kind)
        if letter is None or joint.mimic is not None:
            break
        letters += letter
    for pattern, form in _ROOT_FORMS:
        head = letters[: len(pattern)]
        if sorted(head) != sorted(pattern) or not _together(head, "ST"):
            continue
        joints = tuple(moving[: len(pattern)])
        axes = _axes(description, chain, joints, placer)
        if axes is not None and _turns_every_way(head, axes):
            return _Root(form, joints)
    return None


def _together(letters: str, kinds: str) -> bool:
    """Whether the letters of ``kinds`` in ``letters`` stand next to each other."""
    at = [k for k, letter in enumerate(letters) if letter in kinds]
    return not at or at[-1] - at[0] == len(at) - 1


def _axes(
    description: RobotDescription,
    chain: Sequence[JointSpec],
    joints: Sequence[JointSpec],
    placer: _Placer | None,
) -> list[Vector] | None:
    """Each joint's direction (a slide's) or axis (a hinge's) in one frame, or None.

    Pinocchio's model places them (its Jacobian at its neutral configuration: the slide's
    linear part, the hinge's angular part); without it, only the joints of one MJCF
    body are placed, each axis in the body's frame. A format whose reader left a joint
    of the chain without its origin is not placed.
    """
    upto = chain[: chain.index(joints[-1]) + 1]
    placed = description.format in _PLACED_FORMATS or all(j.origin is not None for j in upto)
    if placer is not None and placed:
        return placer.axes(joints)
    if description.format == "mjcf" and len({(j.parent, j.child) for j in joints}) == 1:
        return [_unit(j.axis) for j in joints]
    return None


class _Placer:
    """Pinocchio's Jacobian at the neutral configuration, computed once, when first asked.

    Locked joints are at their bound (``held``), where they keep what hangs below them.
    """

    def __init__(self, model: Any, held: dict[str, float]) -> None:
        self.model = model
        self.held = held
        self._jacobian: Any = None

    def axes(self, joints: Sequence[JointSpec]) -> list[Vector] | None:
        """Each joint's direction (linear part) or axis (angular part), or None."""
        import pinocchio as pin

        model = self.model
        if not all(model.existJointName(j.name) for j in joints):
            return None
        if self._jacobian is None:
            q = pin.neutral(model)
            for name, value in self.held.items():
                one = model.joints[model.getJointId(name)] if model.existJointName(name) else None
                if one is not None and one.nq == 1 and math.isfinite(value):
                    q[one.idx_q] = value
            self._jacobian = pin.computeJointJacobians(model, model.createData(), q)
        axes: list[Vector] = []
        for joint in joints:
            found = model.joints[model.getJointId(joint.name)]
            # the Jacobian has a column for each mimic joint too (Pinocchio's "extended" v)
            column = int(getattr(found, "idx_vExtended", found.idx_v))
            part = slice(0, 3) if joint.kind is JointKind.PRISMATIC else slice(3, 6)
            x, y, z = (float(c) for c in self._jacobian[part, column])
            axes.append(_unit((x, y, z)))
        return axes


def _unit(v: tuple[float, float, float] | None) -> Vector:
    """``v`` of length 1, or zeros when it has no direction (no joint is placed by it)."""
    if v is None:
        return (0.0, 0.0, 0.0)
    norm = math.hypot(*v)
    if not math.isfinite(norm) or norm == 0.0:
        return (0.0, 0.0, 0.0)
    return (v[0] / norm, v[1] / norm, v[2] / norm)


def _dot(a: Vector, b: Vector) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a: Vector, b: Vector) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _turns_every_way(letters: str, axes: Sequence[Vector]) -> bool:
    """Whether the joints, placed, give the body every pose of their form."""
    slides = [a for letter, a in zip(letters, axes, strict=True) if letter == "S"]
    hinges = [a for letter, a in zip(letters, axes, strict=True) if letter == "H"]
    if any(math.hypot(*a) < 0.5 for a in (*slides, *hinges)):  # no direction
        return False
    if len(slides) == 2:  # planar: the slides span a plane, the hinge is its normal
        normal = _cross(slides[0], slides[1])
        return math.hypot(*normal) > _TOLERANCE and all(
            abs(_dot(s, hinges[0])) <= _TOLERANCE for s in slides
        )
    if len(slides) == 3 and abs(_dot(_cross(slides[0], slides[1]), slides[2])) <= _TOLERANCE:
        return False
    if len(hinges) == 3:
        return all(abs(_dot(hinges[1], h)) <= _TOLERANCE for h in (hinges[0], hinges[2]))
    return True


_HOW = {
    "HSS": "two slides and a hinge about the normal of their plane give it a position and "
    "a heading in that plane, as one planar joint would",
    "BSSS": "slides along three directions and a ball give it a position and an orientation "
    "in space, as one floating joint would",
    "HHHSSS": "slides along three directions and three hinges give it a position and an "
    "orientation in space, as one floating joint would",
}
_HOW["BT"] = _HOW["BSSS"]
_HOW["HHHT"] = _HOW["HHHSSS"]


def _named(found: _Root, root: str, root_joint: str | None) -> Diagnostic:
    """``planar-root`` or ``spatial-root``: what the joints are, together."""
    joints = found.joints
    names = ", ".join(j.name for j in joints)
    kinds = "".join(sorted(_LETTER[j.kind] for j in joints))
    group = "SE(2)" if found.form == "planar" else "SE(3)"
    said = (
        f"joints {names} together are a {found.form} root of link '{joints[-1].child}' "
        f"({group}): {_HOW[kinds]}"
    )
    limited = [j.name for j in joints if j.lower and j.kind is not JointKind.CONTINUOUS]
    if limited:  # the limits the report keeps (a continuous joint's are not)
        said += (
            f", but only within the limits of {', '.join(limited)} (the C-space is the "
            f"joints' own: a part of {group})"
        )
    if "HHH" in kinds:
        said += (
            "; the hinges are Euler angles: where the first and third axes line up they turn "
            "it about two axes only, and the C-space is the hinges' own, not SO(3)"
        )
    if root_joint is None:
        said += "; no root joint is needed"
    else:
        said += (
            f"; the {root_joint} root joint added above link '{root}' moves it a second "
            "time, on top of these"
        )
    code = "planar-root" if found.form == "planar" else "spatial-root"
    return finding(code, None, said, joints[0].line)


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
