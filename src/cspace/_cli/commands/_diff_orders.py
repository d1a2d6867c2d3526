"""``cspace diff --old-order A --new-order B``: two joint orders, side by side.

Each side's report becomes its configuration space, whose conventions give each joint's
index in that side's vector (`joint_indices`); `order_changes` compares them, and the
diff gains their changes, their note and their record (``orders`` in its JSON).
"""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Mapping
from typing import Any

from .. import output


def add_order_arguments(parser: argparse.ArgumentParser) -> None:
    """``--old-order`` and ``--new-order``: the conventions whose orders are compared."""
    from cspace.space._conventions._order import ORDERS

    for side in ("old", "new"):
        other = "new" if side == "old" else "old"
        parser.add_argument(
            f"--{side}-order",
            choices=ORDERS,
            default=None,
            help=f"compare the joint order of the {side} side's vector in this convention "
            f"with the {other} side's (default: --{other}-order's); a joint in another "
            "place is a change",
        )


def _indices(report: Any, convention: str) -> tuple[dict[str, int], Any]:
    """Each joint's index in ``convention``'s vector, and the side's conventions."""
    from cspace.space import ConfigurationSpace
    from cspace.space._conventions._order import joint_indices

    conventions = ConfigurationSpace.from_report(report).conventions()
    return joint_indices(conventions, convention), conventions


def _joint_index_changes(
    old: Any, new: Any, matched: Mapping[str, str], moved: set[str]
) -> list[Any]:
    """A moving joint whose PyBullet ``jointIndex`` differs, where its entry kept its place.

    PyBullet numbers fixed joints too (`PybulletOrder.joints`): a fixed joint added
    before a moving one leaves the vector's order as it was, but every later joint's
    index, which ``setJointMotorControl2`` and ``getJointState`` take, is another.
    """
    from cspace._reports._changes import Change

    was = {matched.get(j.name, j.name): j.index for j in old.pybullet.joints if j.moves}
    out = []
    for joint in new.pybullet.joints:
        before = was.get(joint.name)
        if joint.moves and before is not None and before != joint.index and joint.name not in moved:
            out.append(
                Change(
                    "order",
                    joint.name,
                    f"PyBullet jointIndex {before}",
                    f"PyBullet jointIndex {joint.index}",
                )
            )
    return out


def with_orders(
    args: argparse.Namespace,
    old: Mapping[str, Any],
    new: Mapping[str, Any],
    diff: Any,
    renames: Mapping[str, str],
) -> Any:
    """The diff with the two orders compared, or None after a one-line error.

    Joints are paired as the diff pairs them (``--map``, root joints).

    Returns:
        The diff, its changes, notes and ``orders`` record added (a `ReportDiff`).
    """
    from cspace import CspaceError
    from cspace._reports._order_diff import order_changes
    from cspace._reports.matching import match_joints
    from cspace._reports.report import Report

    sides = (args.old_order or args.new_order, args.new_order or args.old_order)
    reports = Report.from_dict(old), Report.from_dict(new)
    found = []
    for report, convention, name in zip(reports, sides, (args.old, args.new), strict=True):
        try:
            found.append(_indices(report, convention))
        except CspaceError as exc:
            code = getattr(exc, "code", None)
            output.error(f"{name}: {exc}" + (f" [{code}]" if isinstance(code, str) else ""))
            return None
    matched = match_joints(*reports, renames)[2]
    changes, notes, record = order_changes(sides, found[0][0], found[1][0], matched)
    if sides == ("pybullet", "pybullet"):
        moved = {c.joint for c in changes if c.joint is not None}
        shifted = _joint_index_changes(found[0][1], found[1][1], matched, moved)
        if shifted:
            changes, notes = [*changes, *shifted], []
    return dataclasses.replace(
        diff,
        changes=(*diff.changes, *changes),
        notes=(*diff.notes, *notes),
        orders=record,
    )
