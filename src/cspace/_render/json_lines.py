"""JSON Lines however many files: ``inspect --format jsonl``, a compact report a line.

What ``cspace check --baseline`` reads back (a baseline is this output, committed).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.report import Report


def inspect_one(report: Report, options: Options) -> str:
    """The JSON report on one line."""
    return report.to_json(indent=None)


def inspect_piece(report: Report) -> str:
    """One line of JSON Lines."""
    return report.to_json(indent=None)
