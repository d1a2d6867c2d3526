"""What a diff says: the kinds of change and of note, each `Change`, and the `ReportDiff`.

A change is a difference that fails ``cspace diff`` (`CHANGE_KINDS`; those of
`CSPACE_KINDS` change the C-space itself), a note one that does not (`NOTE_KINDS`);
`CHANGE_LABELS` names each kind for people. `diff_reports` (in `diff`) makes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from cspace._safetext import json_text

CSPACE_KINDS = (
    "manifold",
    "root-joint",
    "root-placed",
    "size",
    "joint-added",
    "joint-removed",
    "joint-retyped",
    "mechanism",
    "cut-added",
    "cut-removed",
    "cut-changed",
)
"""The kinds of change that change the C-space itself: its normal form, its dimension,
or what its configurations are (a joint retyped, a root joint added, removed or placed
elsewhere: the same q then puts the robot elsewhere; a mechanism's loops, mobility or
assembly, or a constraint that closes a loop added, removed or changed). The
other changes (limits, q/v layout, MuJoCo's actuators, ros2_control's bounds) leave the
C-space the same but still fail a diff."""

CHANGE_KINDS = (*CSPACE_KINDS, "limits", "layout", "actuators", "ros2-control", "order")
"""Every kind of change, in the order they are listed."""

NOTE_KINDS = (
    "root-joint-paired",
    "renamed",
    "planar-split",
    "storage",
    "size",
    "layout",
    "drake-root",
    "order",
    "actuators-listed",
)
"""Every kind of note (a difference that is not a change of the C-space), in order."""


def within(a: float, b: float, tolerance: float, rel: float) -> bool:
    """Whether two numbers of a diff count as unchanged.

    They do when equal (two NaNs too), or closer than ``tolerance`` or than ``rel``
    times the larger magnitude.
    """
    if math.isnan(a) or math.isnan(b):
        return math.isnan(a) and math.isnan(b)
    return a == b or abs(a - b) <= max(tolerance, rel * max(abs(a), abs(b)))


CHANGE_LABELS = {
    "manifold": "C-space",
    "root-joint": "root joint",
    "root-placed": "root joint placed",
    "size": "q/v size",
    "joint-added": "joint added",
    "joint-removed": "joint removed",
    "joint-retyped": "joint retyped",
    "mechanism": "mechanism",
    "cut-added": "loop cut added",
    "cut-removed": "loop cut removed",
    "cut-changed": "loop cut changed",
    "limits": "limits",
    "layout": "q/v layout",
    "actuators": "MuJoCo ctrl",
    "actuators-listed": "MuJoCo ctrl listed",
    "ros2-control": "ros2_control bounds",
    "root-joint-paired": "root joints paired",
    "renamed": "joint renamed",
    "planar-split": "planar as 3 joints",
    "storage": "stored as",
    "drake-root": "Drake floats",
    "order": "joint order",
}
"""How each kind of change is named in text and Markdown."""


@dataclass(frozen=True)
class Change:
    """One change of the C-space, or one note.

    Attributes:
        kind: One of `CHANGE_KINDS` (a change) or `NOTE_KINDS` (a note).
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
        changes: Every change, kinds in `CHANGE_KINDS` order, joints in tree order.
        tolerance: The absolute limit tolerance used (rad or m).
        rel_tolerance: The relative limit tolerance used.
        notes: Differences that are not changes (storage, renames, root-joint pairing),
            kinds in `NOTE_KINDS` order.
        orders: The joint orders compared (``cspace diff --old-order A --new-order B``):
            each side's convention and every joint's index on each side; None when not
            asked for.
    """

    old_path: str
    new_path: str
    old_manifold: str
    new_manifold: str
    old_dimension: int
    new_dimension: int
    changes: tuple[Change, ...]
    tolerance: float
    rel_tolerance: float = 0.0
    notes: tuple[Change, ...] = ()
    orders: dict[str, Any] | None = None

    @property
    def changed(self) -> bool:
        """True when the C-space itself changed (a change of a kind in `CSPACE_KINDS`)."""
        return any(c.kind in CSPACE_KINDS for c in self.changes)

    @property
    def differs(self) -> bool:
        """True when anything but notes differs (``cspace diff`` then exits 1)."""
        return bool(self.changes)

    @property
    def verdict(self) -> str:
        """``"changed"``, ``"differs"`` or ``"same"``.

        Changed: the C-space changed. Differs: the same C-space, but its limits or q/v
        layout differ. Same: notes at most.
        """
        return "changed" if self.changed else "differs" if self.differs else "same"

    @property
    def kinds_text(self) -> str:
        """The kinds of change, for people, in order: ``"C-space, q/v size, joint added"``."""
        return ", ".join(dict.fromkeys(CHANGE_LABELS[c.kind] for c in self.changes))

    @property
    def what_differs(self) -> str:
        """What differs, as the end of a sentence, for people.

        ``"limits differ"``, ``"q/v layout differs"``, ``"limits and q/v layout differ"``;
        ``"the C-space differs"`` when it changed; empty when nothing but notes differs.
        """
        if self.changed:
            return "the C-space differs"
        labels = list(dict.fromkeys(CHANGE_LABELS[c.kind] for c in self.changes))
        if not labels:
            return ""
        if len(labels) == 1:
            return f"{labels[0]} {'differ' if labels[0] == 'limits' else 'differs'}"
        return f"{', '.join(labels[:-1])} and {labels[-1]} differ"

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``cspace diff --format json``."""
        return {
            "verdict": self.verdict,
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
            "rel_tolerance": self.rel_tolerance if math.isfinite(self.rel_tolerance) else None,
            "changes": [c.to_dict() for c in self.changes],
            "notes": [c.to_dict() for c in self.notes],
        } | ({} if self.orders is None else {"orders": self.orders})

    @property
    def tolerance_text(self) -> str:
        """How limits were compared, for people: ``within 1e-06 or 1e-05 relative``."""
        return f"within {self.tolerance:g} or {self.rel_tolerance:g} relative"

    def to_json(self, *, indent: int | None = 2) -> str:
        """The JSON document as text: deterministic, unprintable characters escaped."""
        return json_text(self.to_dict(), indent=indent)
