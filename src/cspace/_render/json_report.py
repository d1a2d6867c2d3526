"""JSON for CI and tools: ``inspect --format json`` and ``diff --format json``.

One robot's report is indented; several are JSON Lines, a compact report a line. Every
text from a file is escaped as in every JSON cspace writes (`json_text`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.diff import ReportDiff
    from cspace._reports.report import Report


def inspect_one(report: Report, options: Options) -> str:
    """The JSON report, indented."""
    return report.to_json()


def inspect_piece(report: Report) -> str:
    """One line of JSON Lines."""
    return report.to_json(indent=None)


def diff(
    old: Mapping[str, Any], new: Mapping[str, Any], changes: ReportDiff, options: Options
) -> str:
    """The diff as a JSON document (`ReportDiff.to_json`)."""
    return changes.to_json()


def collisions(report: CollisionReport, options: Options) -> str:
    """The self-collision report as a JSON document, indented."""
    from cspace._safetext import json_text

    return json_text(report.to_dict(), indent=2)
