"""MuJoCo's actuators as a table of the text and Markdown reports: the ctrl vector's layout.

One row an actuator, in ctrl order: its entry, name, kind, what it drives, gear and
ctrlrange. At most `SHOWN` rows; the JSON report keeps every one. The cells are raw
(a file's names unescaped): each renderer escapes them its own way.
"""

from __future__ import annotations

from collections.abc import Sequence

from cspace._actuators import Actuator

COLUMNS = ("ctrl", "actuator", "kind", "drives", "gear", "ctrlrange")
"""The table's header."""

SHOWN = 200
"""Most actuators listed in a text or Markdown report."""


def actuators_head(actuators: Sequence[Actuator]) -> str:
    """The line above the table."""
    count = len(actuators)
    return f"actuators (MuJoCo's ctrl, {count:,} {'entry' if count == 1 else 'entries'})"


def actuator_rows(actuators: Sequence[Actuator]) -> list[list[str]]:
    """The table's rows (the first `SHOWN`), raw."""
    rows = []
    for index, actuator in enumerate(actuators[:SHOWN]):
        rows.append(
            [
                str(index),
                actuator.name or "-",
                actuator.kind,
                f"{actuator.transmission} {actuator.target or '?'}",
                actuator.gear_text(),
                actuator.ctrlrange_text() or "-",
            ]
        )
    return rows


def actuators_more(actuators: Sequence[Actuator]) -> str | None:
    """The line under a table that leaves actuators out, or None."""
    left = len(actuators) - SHOWN
    return f"({left:,} more actuators not shown)" if left > 0 else None
