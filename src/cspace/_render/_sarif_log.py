"""A SARIF 2.1.0 log of results, each on its file and line: the parts every command shares.

A result's location is a URI reference to its file, relative to where cspace ran as the
path was given (an absolute path as a ``file://`` URI), and its line; its message is
plain text, each character that could mislead escaped as everywhere in cspace
(`printable`), and the log is JSON as cspace writes it (`json_text`). The log's
rules are the finding codes that occur: the meaning of each from `MEANINGS`, its level
from `CODES` (`cspace._render.sarif` for ``inspect``, `cspace._render._collisions_sarif`
for ``collisions``).
"""

import os
from collections.abc import Sequence
from typing import Any
from urllib.parse import quote

from cspace._findings import CODES, MEANINGS, Severity
from cspace._safetext import json_text, printable

SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
"""The ``$schema`` a SARIF 2.1.0 log names (GitHub's documentation uses it)."""

LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}
"""A finding's SARIF level by its severity (info is a ``note``)."""


def uri(path: str) -> str:
    """A file path as a URI reference (an absolute path as a ``file://`` URI).

    ``/`` separates folders; every other byte of the name as the file system holds it
    but unreserved characters is percent-encoded (a name that is not UTF-8 too: its
    bytes, as Python keeps them, ``os.fsencode``).
    """
    posix = path.replace(os.sep, "/") if os.sep != "/" else path
    quoted = quote(os.fsencode(posix), safe="/")
    return f"file://{quoted}" if posix.startswith("/") else quoted


def result(code: str, level: str, message: str, path: str, line: int | None) -> dict[str, Any]:
    """One result: rule ``code`` at ``level``, ``message`` at ``path`` (and ``line`` >= 1)."""
    location: dict[str, Any] = {"artifactLocation": {"uri": uri(path)}}
    if line is not None and line >= 1:
        location["region"] = {"startLine": line}
    return {
        "ruleId": code,
        "level": level,
        "message": {"text": printable(message, limit=None)},
        "locations": [{"physicalLocation": location}],
    }


def rule(code: str) -> dict[str, Any]:
    """The rule of a finding code (a code that is no finding's: a file without a report)."""
    meaning = MEANINGS.get(code, "cspace cannot make a report of the file")
    level = LEVEL[CODES[code]] if code in CODES else "error"
    return {
        "id": code,
        "shortDescription": {"text": meaning},
        "defaultConfiguration": {"level": level},
    }


def log(results: Sequence[dict[str, Any]]) -> str:
    """The SARIF log of ``results`` (`result`), one run, the rules they name first.

    Each result gains its ``ruleIndex``; the results are changed in place.
    """
    from cspace._version import __version__

    codes = sorted({r["ruleId"] for r in results})
    index = {code: k for k, code in enumerate(codes)}
    for r in results:
        r["ruleIndex"] = index[r["ruleId"]]
    document = {
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "cspace",
                        "version": __version__,
                        "rules": [rule(code) for code in codes],
                    }
                },
                "columnKind": "unicodeCodePoints",
                "results": list(results),
            }
        ],
    }
    return json_text(document, indent=2)
