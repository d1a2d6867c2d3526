"""What changed in a robot's configuration space between two files: two versions, or two formats.

Both sides are reports: made from a robot file, or saved earlier with ``cspace inspect
--format json`` and checked by `read_report_document`.
Joints are matched by name, through explicit renames (``--map OLD=NEW``) where names
differ, and a root joint cspace added on one side (a flag, an SRDF's virtual joint) is
paired with the other side's own floating (or planar) root joint of the same kind above
the same body (`matching`): one joint declared in two places, said in a note.

A change is anything that breaks what a team relies on: the normal form, the dimension,
the root joint (added, removed, or placed elsewhere), joints added, removed or retyped
(kind or space), limits moved by more than the tolerance (absolute, or relative: MuJoCo
and many exporters write 6 significant digits, 6.28319 for 2π), and, between files
stored the same way, q/v layout shifts (a stored configuration vector would be read
wrongly). Between a MuJoCo file and a Pinocchio-stored one (URDF, xacro, SDF, OpenUSD)
storage differs by design: a continuous joint is (cos, sin) in one and one angle in the
other, siblings come in another order; a USD stage's tree is grown from the stage
(joints have no direction there), its siblings by prim path. Those differences are
*notes*, not changes: the C-space is the same. File paths, hashes, tool versions and
findings are not changes of the C-space, and neither is a fixed or mimic joint added or
removed (it has no coordinates and no dimension). A mechanism's loops, mobility and
assembly, and the constraints that close its loops, are part of its C-space
(`_closure_diff`). Between two MJCF files, MuJoCo's ctrl vector is compared too: its
actuators' order, what each drives, its gear and ctrlrange (`_actuator_diff`); between
two URDF or xacro files, the position bounds and initial values their ``<ros2_control>``
elements give (`_ros2_control_diff`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from itertools import zip_longest
from typing import Any

from cspace._drake_order import drake_slots, welded_roots
from cspace._formats.table import by_name
from cspace._reports._actuator_diff import actuator_changes
from cspace._reports._changes import (
    CHANGE_KINDS,
    CHANGE_LABELS,
    CSPACE_KINDS,
    NOTE_KINDS,
    Change,
    ReportDiff,
)
from cspace._reports._closure_diff import closure_changes
from cspace._reports.matching import match_joints, root_placed
from cspace._reports.report import JointReport, Limits, Report, index_range
from cspace._reports.savedreport import looks_like_json, read_report_document

__all__ = [
    "CHANGE_KINDS",
    "CHANGE_LABELS",
    "CSPACE_KINDS",
    "DEFAULT_REL_TOLERANCE",
    "DEFAULT_TOLERANCE",
    "NOTE_KINDS",
    "Change",
    "ReportDiff",
    "diff_reports",
    "looks_like_json",
    "read_report_document",
]

DEFAULT_TOLERANCE = 1e-6
"""Limits closer than this (rad or m) are the same limits."""

DEFAULT_REL_TOLERANCE = 1e-5
"""Limits whose difference is at most this fraction of the larger magnitude are the same
limits: a file written with 6 significant digits is off by at most 5e-6 of the value."""


def _numbers(values: Sequence[float | None]) -> str:
    # Every digit the file gave (shortest round trip): a change beyond the tolerance
    # must show, however small. A non-finite bound (null in JSON) is "none".
    return ", ".join(
        repr(float(v)).removesuffix(".0") if v is not None and math.isfinite(v) else "none"
        for v in values
    )


def _limits_text(limits: Limits | None) -> str:
    if limits is None:
        return "-"
    pairs = [
        f"[{_numbers([lo])}, {_numbers([hi])}]"
        for lo, hi in zip_longest(limits.lower, limits.upper)
    ]
    return " ".join(pairs) + f" {limits.unit}"


def _limits_equal(a: Limits | None, b: Limits | None, tol: float, rel: float) -> bool:
    if a is None or b is None:
        return a is b
    if a.unit != b.unit or (len(a.lower), len(a.upper)) != (len(b.lower), len(b.upper)):
        return False
    pairs = zip([*a.lower, *a.upper], [*b.lower, *b.upper], strict=True)
    return all(
        (not math.isfinite(x) and not math.isfinite(y))
        or (math.isfinite(x) and math.isfinite(y) and math.isclose(x, y, rel_tol=rel, abs_tol=tol))
        for x, y in pairs
    )


def _layout(joint: JointReport, qpos: bool, drake: Mapping[str, Any] | None = None) -> str:
    """Where a joint's coordinates are stored: q, v, MuJoCo's qpos, Drake's q.

    MuJoCo's qpos with ``qpos``, Drake's q with ``drake`` (the joint's Drake slots).
    Between two MJCF files, a mimic follower's qpos entry (set from its leader) counts
    too: a shift of it misreads a saved qpos as surely as one of q. Drake's q shifts
    where siblings are declared in another order, which Pinocchio's q does not see: it is
    said when nothing else moved.
    """
    at = f"q {index_range(joint.q_index, joint.nq)}, v {index_range(joint.v_index, joint.nv)}"
    if qpos and joint.qposadr is not None:
        at = f"{at}, qpos {joint.qposadr}"
    if drake is not None:
        slot = drake["drake_q"]
        at = f"{at}, Drake q {index_range(slot['index'], len(slot['names']))}"
    return at


def _counts(joint: JointReport) -> bool:
    """False for a joint without coordinates or dimension (fixed, mimic).

    Adding or removing one changes neither the C-space nor the layout of q and v.
    """
    return bool(joint.nq or joint.space.dimension)


def _type(joint: JointReport) -> str:
    return f"{joint.kind.value} ({joint.space.notation})"


def storage(report: Report) -> str:
    """How a report's q and v are stored: ``"mujoco"`` or ``"pinocchio"``.

    Its format's ``stores``: MuJoCo's qpos has one angle per hinge, Pinocchio's q a
    (cos, sin) per continuous joint.
    """
    return by_name(report.source.format).stores


def _order(report: Report) -> str:
    """Whose order a report's q and v follow: MuJoCo's, the USD reader's or Pinocchio's parser's."""
    return by_name(report.source.format).order


def _joint_changes(
    old: Report,
    new: Report,
    matched: Mapping[str, str],
    tolerance: float,
    rel_tolerance: float,
) -> dict[str, list[Change]]:
    by_kind: dict[str, list[Change]] = {kind: [] for kind in (*CHANGE_KINDS, *NOTE_KINDS)}
    # MuJoCo's qpos, compared between two MJCF files that both place every joint in it
    sizes = (_qpos_size(old), _qpos_size(new))
    qpos = storage(old) == storage(new) == "mujoco" and None not in sizes
    new_joints = {j.name: j for j in new.joints}
    before_of = {matched[j.name]: j for j in old.joints}
    drake_old = drake_slots(old.joints, old.source.format)
    drake_new = drake_slots(new.joints, new.source.format)
    for joint in old.joints:
        if matched[joint.name] not in new_joints and _counts(joint):
            by_kind["joint-removed"].append(Change("joint-removed", joint.name, _type(joint), "-"))
    for joint in new.joints:
        before = before_of.get(joint.name)
        if before is None:
            if _counts(joint):
                by_kind["joint-added"].append(Change("joint-added", joint.name, "-", _type(joint)))
            continue
        name = joint.name
        if (before.kind, before.space.notation) != (joint.kind, joint.space.notation):
            by_kind["joint-retyped"].append(
                Change("joint-retyped", name, _type(before), _type(joint))
            )
        if not _limits_equal(before.limits, joint.limits, tolerance, rel_tolerance):
            by_kind["limits"].append(
                Change("limits", name, _limits_text(before.limits), _limits_text(joint.limits))
            )
        both = qpos and before.qposadr is not None and joint.qposadr is not None
        was, now = _layout(before, both), _layout(joint, both)
        was_drake, now_drake = drake_old.get(before.name), drake_new.get(name)
        if was == now and None not in (was_drake, now_drake):  # only Drake's q moved
            was, now = _layout(before, both, was_drake), _layout(joint, both, now_drake)
        if was != now:
            by_kind["layout"].append(Change("layout", name, was, now))
    if qpos and sizes[0] != sizes[1]:  # a follower added or removed at the end
        by_kind["layout"].append(
            Change("layout", None, f"MuJoCo qpos size {sizes[0]}", f"MuJoCo qpos size {sizes[1]}")
        )
    return by_kind


def _qpos_size(report: Report) -> int | None:
    """The length of MuJoCo's qpos, mimic followers' entries included.

    None when a joint with coordinates has no place in it (a root cspace added, a saved
    report of an earlier version).
    """
    if any(j.nq and j.qposadr is None for j in report.joints):
        return None
    return max(
        (j.qposadr + max(j.nq, 1) for j in report.joints if j.qposadr is not None), default=0
    )


def _storage_notes(old: Report, new: Report, matched: Mapping[str, str]) -> list[Change]:
    """Joints each side's tool stores differently.

    One angle against (cos, sin), a quaternion w first against w last.
    """
    from cspace._slots import stored_as
    from cspace._tools import TOOLS

    a, b = storage(old), storage(new)
    new_joints = {j.name: j for j in new.joints}
    notes: list[Change] = []
    for joint in old.joints:
        other = new_joints.get(matched[joint.name])
        if other is None or other.kind is not joint.kind:
            continue
        before, after = stored_as(joint, a), stored_as(other, b)
        if before and after and before != after:
            notes.append(
                Change(
                    "storage",
                    other.name,
                    f"{TOOLS[a].label()} ({', '.join(before)})",
                    f"{TOOLS[b].label()} ({', '.join(after)})",
                )
            )
    return notes


def diff_reports(
    old: Report | Mapping[str, Any],
    new: Report | Mapping[str, Any],
    *,
    tolerance: float = DEFAULT_TOLERANCE,
    rel_tolerance: float = DEFAULT_REL_TOLERANCE,
    renames: Mapping[str, str] | None = None,
) -> ReportDiff:
    """Compare two reports: two versions of a robot, or the same robot in two formats.

    Args:
        old: The report of the old version: a `Report`, its
            ``to_dict()``, or a saved report read by `read_report_document` (which
            checks it against the report's JSON Schema and checks its tree: its shape
            is trusted here).
        new: The report of the new version.
        tolerance: Limits closer than this (rad or m) count as unchanged.
        rel_tolerance: So do limits whose difference is at most this fraction of the
            larger magnitude.
        renames: Old joint name -> new joint name, for joints whose names differ.

    Returns:
        The changes, empty when the C-space is the same, and the notes.

    Raises:
        JointMatchError: ``renames`` names a joint a side does not have.
    """
    old = old if isinstance(old, Report) else Report.from_dict(old)
    new = new if isinstance(new, Report) else Report.from_dict(new)
    old, new, matched, notes = match_joints(old, new, renames or {})
    by_kind = _joint_changes(old, new, matched, tolerance, rel_tolerance)
    if storage(old) != storage(new):
        by_kind["storage"] += _storage_notes(old, new, matched)
    for kind, joint, before, after in notes:
        by_kind[kind].append(Change(kind, joint, before, after))
    old_form, new_form = old.manifold.notation, new.manifold.notation
    if old_form != new_form or old.dimension != new.dimension:
        by_kind["manifold"].append(
            Change(
                "manifold",
                None,
                f"{old_form} (dimension {old.dimension})",
                f"{new_form} (dimension {new.dimension})",
            )
        )
    # a root joint added on one side only, unless it is the other side's own (a note)
    if old.root_joint != new.root_joint and not by_kind["root-joint-paired"]:
        by_kind["root-joint"].append(
            Change("root-joint", None, str(old.root_joint or "-"), str(new.root_joint or "-"))
        )
    if not by_kind["root-joint"] and not by_kind["root-joint-paired"]:
        placed = root_placed(old, new, matched)
        if placed is not None:
            by_kind["root-placed"].append(Change(*placed))
    floated = (
        welded_roots(old.joints, old.source.format),
        welded_roots(new.joints, new.source.format),
    )
    if floated[0] != floated[1]:  # cspace (as Pinocchio) keeps a root fixed that Drake floats
        old_root, new_root = (", ".join(links) or "none" for links in floated)
        by_kind["drake-root"].append(Change("drake-root", None, old_root, new_root))
    for kind, changes in closure_changes(old.closure, new.closure, tolerance).items():
        by_kind[kind] += changes
    if old.limits_file is not None or new.limits_file is not None:
        from cspace._reports._limits_diff import limits_changes

        by_kind["limits"] = limits_changes(
            old, new, matched, by_kind["limits"], tolerance, rel_tolerance
        )
    formats = (old.source.format, new.source.format)
    for change in actuator_changes(old.actuators, new.actuators, formats, tolerance, rel_tolerance):
        by_kind[change.kind].append(change)
    if old.ros2_control or new.ros2_control:
        from cspace._reports._ros2_control_diff import control_changes

        by_kind["ros2-control"] += control_changes(old, new, matched, tolerance, rel_tolerance)
    if (old.nq, old.nv) != (new.nq, new.nv):
        by_kind["size"].append(
            Change("size", None, f"nq {old.nq}, nv {old.nv}", f"nq {new.nq}, nv {new.nv}")
        )
    # Stored differently by design (a MuJoCo file against a Pinocchio-stored one; a USD
    # stage's tree, grown from the stage, against a URDF's in Pinocchio's parser's
    # order): the layout is a note; stored the same way, a shift would misread a saved
    # vector.
    stored_alike = _order(old) == _order(new)
    change_kinds = (
        CHANGE_KINDS
        if stored_alike
        else tuple(k for k in CHANGE_KINDS if k not in ("size", "layout"))
    )
    note_kinds = [k for k in NOTE_KINDS if k not in change_kinds]
    return ReportDiff(
        old_path=old.source.path,
        new_path=new.source.path,
        old_manifold=old_form,
        new_manifold=new_form,
        old_dimension=old.dimension,
        new_dimension=new.dimension,
        changes=tuple(c for kind in change_kinds for c in by_kind[kind]),
        tolerance=tolerance,
        rel_tolerance=rel_tolerance,
        notes=tuple(c for kind in note_kinds for c in by_kind[kind]),
    )
