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


def _indices(document: Mapping[str, Any], convention: str) -> dict[str, int]:
    from cspace._reports.report import Report
    from cspace.space import ConfigurationSpace
    from cspace.space._conventions._order import joint_indices

    space = ConfigurationSpace.from_report(Report.from_dict(document))
    return joint_indices(space.conventions(), convention)


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
    found = []
    for document, convention, name in ((old, sides[0], args.old), (new, sides[1], args.new)):
        try:
            found.append(_indices(document, convention))
        except CspaceError as exc:
            code = getattr(exc, "code", None)
            output.error(f"{name}: {exc}" + (f" [{code}]" if isinstance(code, str) else ""))
            return None
    matched = match_joints(Report.from_dict(old), Report.from_dict(new), renames)[2]
    changes, notes, record = order_changes(sides, found[0], found[1], matched)
    return dataclasses.replace(
        diff,
        changes=(*diff.changes, *changes),
        notes=(*diff.notes, *notes),
        orders=record,
    )
