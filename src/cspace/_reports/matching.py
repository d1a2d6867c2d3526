"""Which joint of one report is which joint of another: names, renames, root joints.

Two files of one robot name its joints alike, mostly. Where they do not:

- an explicit rename (``cspace diff --map OLD=NEW``) says so;
- a root joint cspace added to one side (``--root-joint floating``, or an SRDF's virtual
  joint) is the other side's own floating (or planar) root joint (the first joint with
  coordinates, at q 0) when both are the same joint: of one kind, above the same link,
  carrying the same links (every link below it, through fixed joints too, by name),
  and the file's joint placed where cspace places the one it adds (at the world's
  origin, its coordinates its child link's pose in the world: the report's
  ``at_world_origin``). Under the same name it is one joint declared in two places;
  under another, it is paired as if renamed. Either way a note says where each is
  declared, and neither is a change: the configurations are the same. Otherwise there
  is no pairing (the diff then says the root joint changed);
- MuJoCo has no planar joint: its URDF converter writes a planar joint ``P`` as two
  slides ``P_TX``, ``P_TY`` and a hinge ``P_RZ`` on one body. When one side has the
  planar joint and the other those three, the three are read as the one planar joint
  (R^2 × S^1 either way).

Each of these is said in a note: they are differences of naming or storage, not of the
C-space.
"""

from collections import Counter
from collections.abc import Mapping

from cspace._formats.table import by_name
from cspace._joint_kind import JointKind
from cspace._joint_table import bounded
from cspace._manifold import NormalForm
from cspace._record import NamedTuple
from cspace._reports.report import JointReport, Report
from cspace.errors import JointMatchError

Note = tuple[str, str | None, str, str]
"""(kind, joint, old, new): a difference that is not a change of the C-space."""

_ROOT_KINDS = (JointKind.FLOATING, JointKind.PLANAR)
SPLIT_PLANAR = (
    ("_TX", JointKind.PRISMATIC),
    ("_TY", JointKind.PRISMATIC),
    ("_RZ", JointKind.CONTINUOUS),
)
"""How MuJoCo's URDF converter writes a planar joint: suffix and kind of each part."""


class Matching(NamedTuple):
    """Two reports, their joints matched.

    Attributes:
        old: The old report (split planar joints read as one).
        new: The new report (the same).
        names: Each old joint's name on the new side.
        notes: What the matching had to assume, in order.
    """

    old: Report
    new: Report
    names: dict[str, str]
    notes: tuple[Note, ...]


def _root(report: Report) -> JointReport | None:
    """The first joint with coordinates, when it is at q 0 and floating or planar."""
    first = next((j for j in report.joints if j.q_index is not None), None)
    if first is None or first.q_index != 0 or first.kind not in _ROOT_KINDS:
        return None
    return first


def _root_text(report: Report, joint: JointReport) -> str:
    """What a root joint is and where it is declared, for the pairing's note."""
    who = "in the file"
    if report.root_joint is not None:
        virtual = report.srdf.virtual_joint if report.srdf is not None else None
        who = "added by cspace"
        if virtual:  # ``name:type``, as the report's srdf section says it
            who = f"the SRDF's virtual joint '{virtual.rpartition(':')[0]}'"
    elif by_name(report.source.format).free_bodies:
        who = "a free body of the stage"
    return f"{joint.kind.value} '{joint.name}' ({who})"


def _carried(report: Report, link: str) -> set[str]:
    """``link`` and every link below it, through fixed joints too: what a joint above it moves."""
    below: dict[str, list[str]] = {}
    for joint in report.joints:
        if joint.parent_link is not None:
            below.setdefault(joint.parent_link, []).append(joint.child_link)
    carried, todo = {link}, [link]
    while todo:
        for other in below.get(todo.pop(), ()):
            if other not in carried:
                carried.add(other)
                todo.append(other)
    return carried


def _at_world_origin(report: Report, joint: JointReport) -> bool:
    """Whether a root joint's coordinates are its child link's pose in the world.

    A root joint cspace added is (its record has no parent link); a file's own one is
    when its record says so (``at_world_origin``, which reports saved by earlier
    versions of cspace lack: then it is not known, and not taken).
    """
    added = report.root_joint is not None and joint.parent_link is None
    return added or joint.at_world_origin is True


def _same_joint(old: tuple[Report, JointReport], new: tuple[Report, JointReport]) -> bool:
    """Whether two root joints of one kind are one joint: the same q, the same links moved.

    They are when they sit above the same link, carry the same links (by name: cspace's
    root joint on an MJCF file floats the world body and the bodies welded to it, where
    a file's free joint floats its own body, and a body welded to the world stays put),
    and each is at the world's origin (a URDF ``<origin>`` off the identity puts the
    link elsewhere for the same q).
    """
    (a_report, a), (b_report, b) = old, new
    if a.child_link != b.child_link:
        return False
    if not (_at_world_origin(a_report, a) and _at_world_origin(b_report, b)):
        return False
    return _carried(a_report, a.child_link) == _carried(b_report, b.child_link)


def _pair_roots(
    old: Report, new: Report, names: dict[str, str], renames: Mapping[str, str]
) -> Note | None:
    """Pair the two sides' root joints when they are one joint declared in two places.

    Each side's root joint is its first joint with coordinates, at q 0, floating or
    planar. They are one joint when they are of one kind, the same joint (`_same_joint`),
    and declared in different places: cspace added one (a flag, an SRDF's virtual
    joint) and the file holds the other, or a USD stage's free body stands for a joint a
    converter dropped. Under the same name (or names ``renames`` maps) nothing is
    renamed; under another, ``names`` maps the old one to the new one, unless
    ``renames`` names either.

    Returns:
        The note that says so, or None when they are not paired.
    """
    a, b = _root(old), _root(new)
    # a USD stage's free body floats without a joint (converters drop a URDF's floating
    # joint): its joint, named after the body, is the other side's root joint
    free = by_name(old.source.format).free_bodies or by_name(new.source.format).free_bodies
    if old.root_joint == new.root_joint and not free:
        return None  # declared alike: matched by name, or not at all
    if a is None or b is None or a.kind is not b.kind:
        return None
    if not _same_joint((old, a), (new, b)):
        return None
    if names[a.name] != b.name:
        if a.name in renames or b.name in renames.values():
            return None
        names[a.name] = b.name
    elif old.root_joint == new.root_joint:
        return None  # one name, declared alike
    return ("root-joint-paired", b.name, _root_text(old, a), _root_text(new, b))


PLACEMENT_TOLERANCE = 1e-9
"""Largest difference (m, or of a unit quaternion's entries) between two root joints'
``origin`` still the same placement: rounding, as `_root_place` reads it."""


def _origin(joint: JointReport) -> tuple[float, ...]:
    """A root joint's frame in the world, (x, y, z, qw, qx, qy, qz): the identity when unset."""
    return joint.origin if joint.origin is not None else (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)


def _same_origin(a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    """Whether two frames are one within `PLACEMENT_TOLERANCE` (q and -q: one turn)."""
    near = all(abs(x - y) <= PLACEMENT_TOLERANCE for x, y in zip(a[:3], b[:3], strict=True))
    turn = all(abs(x - y) <= PLACEMENT_TOLERANCE for x, y in zip(a[3:], b[3:], strict=True))
    flip = all(abs(x + y) <= PLACEMENT_TOLERANCE for x, y in zip(a[3:], b[3:], strict=True))
    return near and (turn or flip)


def _placement_text(joint: JointReport) -> str:
    """Where a root joint is placed, for the change that says both sides'."""
    if joint.origin is not None:
        xyz = ", ".join(f"{v:.9g}" for v in joint.origin[:3])
        wxyz = ", ".join(f"{v:.9g}" for v in joint.origin[3:])
        return f"origin xyz ({xyz}), quaternion wxyz ({wxyz})"
    if joint.at_world_origin is None:
        return "placement not recorded"
    return "at the world's origin" if joint.at_world_origin else "placed off the world's origin"


def root_placed(old: Report, new: Report, names: Mapping[str, str]) -> Note | None:
    """The change of a root joint (one on both sides, one kind) placed elsewhere on one side.

    The same q then puts the robot elsewhere: a URDF ``<origin>`` moved (the report's
    ``origin``, composed into Drake's q), or one side's joint at the world's origin and
    the other's not (``at_world_origin``; not compared where a side does not say).

    Returns:
        ``("root-placed", joint, old placement, new placement)``, or None when both
        are placed alike (or there is no such pair of root joints).
    """
    a, b = _root(old), _root(new)
    if a is None or b is None or a.kind is not b.kind or names.get(a.name) != b.name:
        return None
    known = a.at_world_origin is not None and b.at_world_origin is not None
    if _same_origin(_origin(a), _origin(b)) and not (
        known and a.at_world_origin != b.at_world_origin
    ):
        return None
    return ("root-placed", b.name, _placement_text(a), _placement_text(b))


def split_planar_parts(by_name: Mapping[str, JointReport], base: str) -> list[JointReport] | None:
    """The three joints MuJoCo's converter writes for planar joint ``base``, if present.

    Only unbounded parts are read as a planar joint (R^2 × S^1): a slide with limits is
    an interval and a limited hinge an arc, which the diff then reports as such.
    """
    parts = [by_name.get(f"{base}{suffix}") for suffix, _ in SPLIT_PLANAR]
    found = [
        p
        for p, (_, kind) in zip(parts, SPLIT_PLANAR, strict=True)
        if p is not None and p.kind is kind and not bounded(p.limits)
    ]
    if len(found) != len(SPLIT_PLANAR) or len({p.child_link for p in found}) != 1:
        return None
    return found


def _fold_split_planar(report: Report, planar: set[str]) -> tuple[Report, list[Note]]:
    """``report`` with each MuJoCo-split planar joint named in ``planar`` read as one.

    The folded joint stands where the first of its parts stood, whatever their order; it
    is at the world's origin when each part's record says so.
    """
    by_name = {j.name: j for j in report.joints}
    folded: dict[str, JointReport] = {}  # part name -> the planar joint
    notes: list[Note] = []
    for base in sorted(planar - set(by_name)):
        parts = split_planar_parts(by_name, base)
        if parts is None:
            continue
        starts = [p.q_index for p in parts if p.q_index is not None]
        v_starts = [p.v_index for p in parts if p.v_index is not None]
        joint = parts[0]._replace(
            name=base,
            kind=JointKind.PLANAR,
            space=NormalForm(r=2, t=1),
            limits=None,
            q_index=min(starts) if starts else None,
            nq=sum(p.nq for p in parts),
            v_index=min(v_starts) if v_starts else None,
            nv=sum(p.nv for p in parts),
            at_world_origin=True if all(p.at_world_origin is True for p in parts) else None,
        )
        folded.update((p.name, joint) for p in parts)
        names = ", ".join(p.name for p in parts)
        notes.append(("planar-split", base, "planar", f"slide, slide, hinge ({names})"))
    joints: list[JointReport] = []
    emitted: set[str] = set()
    for joint in report.joints:
        planar_joint = folded.get(joint.name)
        if planar_joint is None:
            joints.append(joint)
        elif planar_joint.name not in emitted:
            emitted.add(planar_joint.name)
            joints.append(planar_joint)
    return report._replace(joints=tuple(joints)), notes


def match_joints(old: Report, new: Report, renames: Mapping[str, str]) -> Matching:
    """Match the joints of two reports.

    Args:
        old: The old report.
        new: The new report.
        renames: Old joint name -> new joint name, where names differ.

    Raises:
        JointMatchError: A rename names a joint one side does not have, or two old
            joints map to one new joint.
    """
    notes: list[Note] = []
    old_planar = {j.name for j in old.joints if j.kind is JointKind.PLANAR}
    new_planar = {j.name for j in new.joints if j.kind is JointKind.PLANAR}
    new, folded = _fold_split_planar(new, {renames.get(n, n) for n in old_planar})
    notes += folded
    old, folded = _fold_split_planar(old, new_planar)
    notes += [(kind, joint, after, before) for kind, joint, before, after in folded]
    old_names = {j.name for j in old.joints}
    new_names = {j.name for j in new.joints}
    unknown = [o for o in renames if o not in old_names]
    missing = [n for n in renames.values() if n not in new_names]
    if unknown or missing:
        said = [f"old side has no joint '{o}'" for o in unknown]
        said += [f"new side has no joint '{n}'" for n in missing]
        raise JointMatchError(f"--map: {'; '.join(said)}", joints=[*unknown, *missing])
    notes += [("renamed", n, o, n) for o, n in renames.items() if o != n]
    names = {name: renames.get(name, name) for name in sorted(old_names)}
    paired = _pair_roots(old, new, names, renames)
    if paired is not None:
        notes.append(paired)
    targets = Counter(n for n in names.values() if n in new_names)  # linear, not count()
    twice = sorted(n for n, count in targets.items() if count > 1)
    if twice:
        raise JointMatchError(f"--map: several old joints map to '{twice[0]}'", joints=twice)
    return Matching(old, new, names, tuple(notes))
