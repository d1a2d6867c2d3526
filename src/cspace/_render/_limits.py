"""The limits MoveIt plans with (the report's ``limits_file``), for the text and Markdown.

One table: a row for each joint of one coordinate, a column for each limit; a limit the
joint_limits.yaml gave says so, with its line (``2.175 (YAML:11)``); one the robot file
gave is its value alone; ``none`` where there is none.
"""

import math

from cspace._reports.limits import KINDS, Bound, LimitsSummary
from cspace._safetext import printable

COLUMNS = ("joint", *KINDS)


def limits_head(summary: LimitsSummary) -> str:
    """The table's title: the file and its default scaling factors."""
    scaling = [
        f"{what} scaling {value:g}"
        for what, value in (
            ("velocity", summary.velocity_scaling),
            ("acceleration", summary.acceleration_scaling),
        )
        if value is not None
    ]
    said = f"; {', '.join(scaling)}" if scaling else ""
    return f"limits MoveIt plans with, from {printable(summary.file)} and the robot file{said}"


def shown(bound: Bound) -> str:
    """A bound as text: ``2.175`` (or ``none``), then ``(YAML:14)`` when the YAML gave it."""
    if bound.value is None:
        value = "none"
    elif math.isfinite(bound.value):
        value = f"{bound.value:g}"
    else:
        value = str(bound.value)
    if bound.origin == "robot":
        return value
    return f"{value} (YAML:{bound.line})" if bound.line is not None else f"{value} (YAML)"


def limits_rows(summary: LimitsSummary) -> list[list[str]]:
    """A row of raw cells for each joint (the caller escapes them as its format does)."""
    return [[j.joint, *(shown(getattr(j, k)) for k in KINDS)] for j in summary.joints]
