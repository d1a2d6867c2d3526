"""Joints that together give a body its pose: ``planar-root`` and ``spatial-root``.

A file without a floating or planar joint may still give a body a pose: MJCF writes a
planar root as two slides and a hinge of one body (dm_control's and Gymnasium's cheetah,
walker and hopper: ``rootx``, ``rootz``, ``rooty``), URDF and SDF as a chain of links
from the world, each carrying the next. `recognise` tells such joints at the start of a
chain from the root link (slides with independent directions, and a ball or hinges that
turn the body every way, placed by Pinocchio's model: `Placer`), and `named` says what
they are together.
"""

import math
from collections.abc import Sequence
from typing import Any

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, RobotDescription
from cspace._joint_kind import JointKind
from cspace._record import NamedTuple

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


class RootChain(NamedTuple):
    """Joints that together give a body its pose: ``planar`` (SE(2)) or ``spatial``."""

    form: str
    joints: tuple[JointSpec, ...]


def recognise(
    description: RobotDescription,
    chain: Sequence[JointSpec],
    placer: "Placer | None",
    moves: frozenset[str],
) -> RootChain | None:
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
            return RootChain(form, joints)
    return None


def _together(letters: str, kinds: str) -> bool:
    """Whether the letters of ``kinds`` in ``letters`` stand next to each other."""
    at = [k for k, letter in enumerate(letters) if letter in kinds]
    return not at or at[-1] - at[0] == len(at) - 1


def _axes(
    description: RobotDescription,
    chain: Sequence[JointSpec],
    joints: Sequence[JointSpec],
    placer: "Placer | None",
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


class Placer:
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


def named(found: RootChain, root: str, root_joint: str | None) -> Diagnostic:
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
