"""JSON Lines however many files: ``inspect --format jsonl``, a compact report a line.

What ``cspace check --baseline`` reads back (a baseline is this output, committed), with
``collisions --format jsonl``'s line: a robot's self-collision report, compact.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.report import Report


def inspect_one(report: Report, options: Options) -> str:
    """The JSON report on one line."""
    return report.to_json(indent=None)


def inspect_piece(report: Report) -> str:
    """One line of JSON Lines."""
    return report.to_json(indent=None)


def collisions(report: CollisionReport, options: Options) -> str:
    """The self-collision report as JSON on one line (escaped as every JSON cspace writes)."""
    from cspace._safetext import json_text

    return json_text(report.to_dict(), indent=None)
