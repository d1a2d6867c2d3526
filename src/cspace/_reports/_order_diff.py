"""Two joint orders compared: ``cspace diff --old-order A --new-order B``.

Each side's vector in a convention of its own (the URDF in PyBullet's order, its USD in
Isaac's, its MJCF in MuJoCo's qpos) gives each joint an index, its first entry. A joint
both vectors hold is a change (``order``, "joint order") when its place among the joints
they both hold differs: a policy trained on one side reads another joint there. A joint
one vector holds and the other does not (a mimic follower Pinocchio's q leaves out) is a
change too: the two vectors are not the same length. When every joint keeps its place,
a note says so. Both sides' indices of every joint are the record the diff's JSON keeps
(``orders``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from cspace._reports._changes import Change
from cspace._tools import TOOLS


def _at(label: str, index: int | None) -> str:
    return "-" if index is None else f"{label} {index}"


def order_changes(
    conventions: tuple[str, str],
    old: Mapping[str, int],
    new: Mapping[str, int],
    matched: Mapping[str, str],
) -> tuple[list[Change], list[Change], dict[str, Any]]:
    """The changes and notes of two joint orders, and their record.

    Args:
        conventions: The old side's convention and the new side's.
        old: Each old joint's index in the old side's vector, in its order.
        new: Each new joint's index in the new side's vector, in its order.
        matched: Old joint names to new ones (``--map``); a name not in it is the same.

    Returns:
        The changes (kind ``order``, one a joint, in the new side's order), the notes
        (one, when nothing changed), and the record of the diff's JSON: ``{"old":
        convention, "new": convention, "joints": [{"joint", "old", "new"}, ...]}``, the
        joints in the new side's order, then those only the old side holds.
    """
    labels = TOOLS[conventions[0]].label(), TOOLS[conventions[1]].label()
    renamed = {matched.get(name, name): index for name, index in old.items()}
    both = [name for name in new if name in renamed]
    old_rank = {name: k for k, name in enumerate(sorted(both, key=lambda n: renamed[n]))}
    changes: list[Change] = []
    rows: list[dict[str, Any]] = []
    for rank, name in enumerate(both):
        rows.append({"joint": name, "old": renamed[name], "new": new[name]})
        if old_rank[name] != rank:
            before, after = _at(labels[0], renamed[name]), _at(labels[1], new[name])
            changes.append(Change("order", name, before, after))
    for name, index in new.items():
        if name not in renamed:
            rows.append({"joint": name, "old": None, "new": index})
            changes.append(Change("order", name, "-", _at(labels[1], index)))
    for name, index in renamed.items():
        if name not in new:
            rows.append({"joint": name, "old": index, "new": None})
            changes.append(Change("order", name, _at(labels[0], index), "-"))
    notes = []
    if not changes:
        count = f"{len(both)} joint{'s' if len(both) != 1 else ''} in the same order"
        notes.append(Change("order", None, labels[0], f"{labels[1]}: {count}"))
    record = {"old": conventions[0], "new": conventions[1], "joints": rows}
    return changes, notes, record
