"""SARIF 2.1.0: each finding on its file and line, as code scanning shows it.

One log, one run, tool ``cspace``: a rule per finding code that occurs (its meaning
from `MEANINGS`, its level from `CODES`), a result per finding (``error``, ``warning``,
``note`` for info) at the file (a URI reference relative to where cspace ran, as given)
and line, and an ``error`` result for each file that gave no report, under its error's
code; ``cspace collisions``' findings on the SRDF's line (or the robot file's: MJCF's
filters), by `cspace._render._collisions_sarif`. Messages are plain text, each character
that could mislead escaped as everywhere in cspace (`printable`) and then as JSON
escapes it (`json_text`); the log is made by `cspace._render._sarif_log`.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace._render._sarif_log import LEVEL, log, result

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.report import Report
    from cspace._reports.summary import SummaryRow


def inspect_piece(report: Report) -> str:
    """The results of one report, as a JSON array."""
    path = report.source.path
    results = [
        result(d.code, LEVEL[d.severity], d.message, d.file or path, d.line)
        for d in report.diagnostics
    ]
    return json.dumps(results)


def inspect_failed(path: str, message: str, code: str | None, line: int | None) -> str:
    """The result of a file that gave no report: an error at the file (and line)."""
    return json.dumps([result(code or "no-report", "error", message, path, line)])


def inspect_end(rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """The SARIF log of every piece, rules first."""
    return log([r for piece in pieces for r in json.loads(piece)])


def inspect_one(report: Report, options: Options) -> str:
    """The SARIF log of one report."""
    return inspect_end([], [inspect_piece(report)], options)


def collisions(report: CollisionReport, options: Options) -> str:
    """``cspace collisions --format sarif``: each finding on the SRDF's or the robot's line."""
    from cspace._render._collisions_sarif import render

    return render(report)
