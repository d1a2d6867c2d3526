"""SARIF 2.1.0: each finding on its file and line, as code scanning shows it.

One log, one run, tool ``cspace``: a rule per finding code that occurs (its meaning
from `MEANINGS`, its level from `CODES`), a result per finding (``error``, ``warning``,
``note`` for info) at the file (a URI reference relative to where cspace ran, as given)
and line, and an ``error`` result for each file that gave no report, under its error's
code. Messages are plain text, each character that could mislead escaped as everywhere
in cspace (`printable`) and then as JSON escapes it (`json_text`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any
from urllib.parse import quote

from cspace._findings import CODES, MEANINGS, Severity
from cspace._safetext import json_text, printable

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.report import Report
    from cspace._reports.summary import SummaryRow

SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
"""The ``$schema`` a SARIF 2.1.0 log names (GitHub's documentation uses it)."""

_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def _uri(path: str) -> str:
    """A file path as a URI reference (an absolute path as a ``file://`` URI).

    ``/`` separates folders; every other byte of the name as the file system holds it
    but unreserved characters is percent-encoded (a name that is not UTF-8 too: its
    bytes, as Python keeps them, ``os.fsencode``).
    """
    posix = path.replace(os.sep, "/") if os.sep != "/" else path
    uri = quote(os.fsencode(posix), safe="/")
    return f"file://{uri}" if posix.startswith("/") else uri


def _result(code: str, level: str, message: str, path: str, line: int | None) -> dict[str, Any]:
    location: dict[str, Any] = {"artifactLocation": {"uri": _uri(path)}}
    if line is not None and line >= 1:
        location["region"] = {"startLine": line}
    return {
        "ruleId": code,
        "level": level,
        "message": {"text": printable(message, limit=None)},
        "locations": [{"physicalLocation": location}],
    }


def inspect_piece(report: Report) -> str:
    """The results of one report, as a JSON array."""
    path = report.source.path
    results = [
        _result(d.code, _LEVEL[d.severity], d.message, d.file or path, d.line)
        for d in report.diagnostics
    ]
    return json.dumps(results)


def inspect_failed(path: str, message: str, code: str | None, line: int | None) -> str:
    """The result of a file that gave no report: an error at the file (and line)."""
    return json.dumps([_result(code or "no-report", "error", message, path, line)])


def _rule(code: str) -> dict[str, Any]:
    meaning = MEANINGS.get(code, "cspace cannot make a report of the file")
    level = _LEVEL[CODES[code]] if code in CODES else "error"
    return {
        "id": code,
        "shortDescription": {"text": meaning},
        "defaultConfiguration": {"level": level},
    }


def inspect_end(rows: Sequence[SummaryRow], pieces: Sequence[str], options: Options) -> str:
    """The SARIF log of every piece, rules first."""
    from cspace._version import __version__

    results = [result for piece in pieces for result in json.loads(piece)]
    codes = sorted({result["ruleId"] for result in results})
    index = {code: k for k, code in enumerate(codes)}
    for result in results:
        result["ruleIndex"] = index[result["ruleId"]]
    log = {
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "cspace",
                        "version": __version__,
                        "rules": [_rule(code) for code in codes],
                    }
                },
                "columnKind": "unicodeCodePoints",
                "results": results,
            }
        ],
    }
    return json_text(log, indent=2)


def inspect_one(report: Report, options: Options) -> str:
    """The SARIF log of one report."""
    return inspect_end([], [inspect_piece(report)], options)
