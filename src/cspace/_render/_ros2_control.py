"""The ``<ros2_control>`` part of a report, as the text and Markdown reports show it.

Each commanded joint gets one cell beside it in the joint table: its command interfaces,
its position bounds as written, and its position initial value; the components get one
line above the table. Everything a file wrote is escaped (`printable`).
"""

from collections.abc import Sequence

from cspace._reports.report import Report
from cspace._ros2_control import ControlHardware, ControlJoint
from cspace._safetext import printable

COLUMN = "ros2_control"
"""The joint table's column, present when the report has a ``ros2_control`` part."""


def raw_cell(joint: ControlJoint) -> str:
    """The joint's cell as the file writes it: the caller escapes it as its format does."""
    names = "+".join(i.name for i in joint.command) or "state only"
    parts = [names]
    position = joint.interface("command", "position")
    if position is not None and (position.min is not None or position.max is not None):
        low = "-" if position.min is None else position.min
        high = "-" if position.max is None else position.max
        off = "" if position.limits_enabled and joint.limits_enabled else " off"
        parts.append(f"[{low}, {high}]{off}")
    initial = joint.interface("state", "position") or position
    if initial is not None and initial.initial_value is not None:
        parts.append(f"initial {initial.initial_value}")
    return " ".join(parts)


def control_rows(hardware: Sequence[ControlHardware]) -> list[list[str]]:
    """A row of raw cells for each joint of each component (the caller escapes them)."""
    return [
        [c.name, j.name, raw_cell(j), "-" if j.line is None else str(j.line)]
        for c in hardware
        for j in c.joints
    ]


ROW_COLUMNS = ("component", "joint", "interfaces, position bounds, initial value", "line")
"""The columns of `control_rows`."""


def control_cells(report: Report) -> dict[str, str]:
    """Each joint the components name: its cell (several components' joined by ``;``)."""
    cells: dict[str, list[str]] = {}
    for component in report.ros2_control:
        for joint in component.joints:
            cells.setdefault(joint.name, []).append(printable(raw_cell(joint)))
    return {name: "; ".join(found) for name, found in cells.items()}


def control_line(report: Report) -> str | None:
    """The components, one line (None without any)."""
    if not report.ros2_control:
        return None
    shown = [
        f"{printable(c.name)} ({printable(c.plugin or c.type)}, {len(c.joints)} joints)"
        for c in report.ros2_control[:8]
    ]
    more = len(report.ros2_control) - len(shown)
    return "ros2_control  " + ", ".join(shown) + (f" and {more:,} more" if more else "")
