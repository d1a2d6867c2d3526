"""What changed in a robot's configuration space between two versions of its file.

Both sides are JSON report documents (schema_version 1): made from a robot file, or
saved earlier with ``cspace inspect --format json`` and checked by
:func:`cspace.reports.savedreport.read_report_document`. A change is anything that breaks
what a team relies on: the normal form, the dimension, the root joint, joints added,
removed or retyped (kind or space), limits moved by more than a tolerance (rad or m),
and q/v layout shifts (a stored configuration vector would be read wrongly). File paths,
hashes, tool versions and findings are not changes of the C-space, and neither is a
fixed or mimic joint added or removed (it has no coordinates and no dimension).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from itertools import zip_longest
from typing import Any

from cspace.errors import ReportFileError
from cspace.reports.report import JointReport, Limits, Report, index_range
from cspace.reports.savedreport import looks_like_json, read_report_document
from cspace.safetext import json_text

__all__ = [
    "CHANGE_KINDS",
    "CHANGE_LABELS",
    "DEFAULT_TOLERANCE",
    "Change",
    "ReportDiff",
    "ReportDocumentError",
    "diff_reports",
    "looks_like_json",
    "read_report_document",
]

DEFAULT_TOLERANCE = 1e-6
"""Limits closer than this (rad or m) are the same limits."""

CHANGE_KINDS = (
    "manifold",
    "root-joint",
    "size",
    "joint-added",
    "joint-removed",
    "joint-retyped",
    "limits",
    "layout",
)
"""Every kind of change, in the order they are listed."""


ReportDocumentError = ReportFileError
"""The error of a saved report that cannot be used (an older name of ReportFileError)."""


@dataclass(frozen=True)
class Change:
    """One change of the C-space.

    Attributes:
        kind: One of :data:`CHANGE_KINDS`.
        joint: The joint it is about, or None for the whole robot.
        before: The old value, written for people (``-`` when absent).
        after: The new value, written for people (``-`` when absent).
    """

    kind: str
    joint: str | None
    before: str
    after: str

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"kind": self.kind, "joint": self.joint, "before": self.before, "after": self.after}


@dataclass(frozen=True)
class ReportDiff:
    """The difference between two reports.

    Attributes:
        old_path: The old side's ``source.path``.
        new_path: The new side's ``source.path``.
        old_manifold: The old normal form (notation).
        new_manifold: The new normal form (notation).
        old_dimension: The old dimension.
        new_dimension: The new dimension.
        changes: Every change, kinds in :data:`CHANGE_KINDS` order, joints in tree order.
        tolerance: The limit tolerance used (rad or m).
    """

    old_path: str
    new_path: str
    old_manifold: str
    new_manifold: str
    old_dimension: int
    new_dimension: int
    changes: tuple[Change, ...]
    tolerance: float

    @property
    def changed(self) -> bool:
        """True when the C-space changed (``cspace diff`` then exits 1)."""
        return bool(self.changes)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``cspace diff --format json``."""
        return {
            "changed": self.changed,
            "old": {
                "path": self.old_path,
                "manifold": self.old_manifold,
                "dimension": self.old_dimension,
            },
            "new": {
                "path": self.new_path,
                "manifold": self.new_manifold,
                "dimension": self.new_dimension,
            },
            "tolerance": self.tolerance if math.isfinite(self.tolerance) else None,
            "changes": [c.to_dict() for c in self.changes],
        }

    def to_json(self, *, indent: int | None = 2) -> str:
        """The JSON document as text: deterministic, unprintable characters escaped."""
        return json_text(self.to_dict(), indent=indent)


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


def _limits_equal(a: Limits | None, b: Limits | None, tol: float) -> bool:
    if a is None or b is None:
        return a is b
    if a.unit != b.unit or (len(a.lower), len(a.upper)) != (len(b.lower), len(b.upper)):
        return False
    pairs = zip([*a.lower, *a.upper], [*b.lower, *b.upper], strict=True)
    return all(
        (not math.isfinite(x) and not math.isfinite(y))
        or (math.isfinite(x) and math.isfinite(y) and math.isclose(x, y, rel_tol=0.0, abs_tol=tol))
        for x, y in pairs
    )


def _layout(joint: JointReport) -> str:
    return f"q {index_range(joint.q_index, joint.nq)}, v {index_range(joint.v_index, joint.nv)}"


def _counts(joint: JointReport) -> bool:
    """False for a joint without coordinates or dimension (fixed, mimic).

    Adding or removing one changes neither the C-space nor the layout of q and v.
    """
    return bool(joint.nq or joint.space.dimension)


def _type(joint: JointReport) -> str:
    return f"{joint.kind.value} ({joint.space.notation})"


def _joint_changes(old: Report, new: Report, tolerance: float) -> dict[str, list[Change]]:
    by_kind: dict[str, list[Change]] = {kind: [] for kind in CHANGE_KINDS}
    old_joints = {j.name: j for j in old.joints}
    new_joints = {j.name: j for j in new.joints}
    for name, joint in old_joints.items():
        if name not in new_joints and _counts(joint):
            by_kind["joint-removed"].append(Change("joint-removed", name, _type(joint), "-"))
    for name, joint in new_joints.items():
        before = old_joints.get(name)
        if before is None:
            if _counts(joint):
                by_kind["joint-added"].append(Change("joint-added", name, "-", _type(joint)))
            continue
        if (before.kind, before.space.notation) != (joint.kind, joint.space.notation):
            by_kind["joint-retyped"].append(
                Change("joint-retyped", name, _type(before), _type(joint))
            )
        if not _limits_equal(before.limits, joint.limits, tolerance):
            by_kind["limits"].append(
                Change("limits", name, _limits_text(before.limits), _limits_text(joint.limits))
            )
        if _layout(before) != _layout(joint):
            by_kind["layout"].append(Change("layout", name, _layout(before), _layout(joint)))
    return by_kind


def diff_reports(
    old: Report | Mapping[str, Any],
    new: Report | Mapping[str, Any],
    *,
    tolerance: float = DEFAULT_TOLERANCE,
) -> ReportDiff:
    """Compare two reports.

    Args:
        old: The report of the old version: a :class:`~cspace.reports.report.Report`, its
            ``to_dict()``, or a saved report read by :func:`read_report_document` (which
            checks it against the report's JSON Schema: its shape is trusted here).
        new: The report of the new version.
        tolerance: Limits closer than this (rad or m) count as unchanged.

    Returns:
        The changes, empty when the C-space is the same.
    """
    old = old if isinstance(old, Report) else Report.from_dict(old)
    new = new if isinstance(new, Report) else Report.from_dict(new)
    by_kind = _joint_changes(old, new, tolerance)
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
    if old.root_joint != new.root_joint:
        by_kind["root-joint"].append(
            Change("root-joint", None, str(old.root_joint or "-"), str(new.root_joint or "-"))
        )
    if (old.nq, old.nv) != (new.nq, new.nv):
        by_kind["size"].append(
            Change("size", None, f"nq {old.nq}, nv {old.nv}", f"nq {new.nq}, nv {new.nv}")
        )
    return ReportDiff(
        old_path=old.source.path,
        new_path=new.source.path,
        old_manifold=old_form,
        new_manifold=new_form,
        old_dimension=old.dimension,
        new_dimension=new.dimension,
        changes=tuple(c for kind in CHANGE_KINDS for c in by_kind[kind]),
        tolerance=tolerance,
    )


CHANGE_LABELS = {
    "manifold": "C-space",
    "root-joint": "root joint",
    "size": "q/v size",
    "joint-added": "joint added",
    "joint-removed": "joint removed",
    "joint-retyped": "joint retyped",
    "limits": "limits",
    "layout": "q/v layout",
}
"""How each kind of change is named in text and Markdown."""
