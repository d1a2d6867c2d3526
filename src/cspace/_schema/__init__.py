"""The JSON Schema of the report, shipped with the package.

The formats a report's ``source.format`` may name come from the format table
(`cspace._formats.table.FORMATS`): the shipped file lists the package's own, and the
schema given out lists the table's.
"""

from __future__ import annotations

import json
import re
from importlib import resources
from typing import Any

REPORT_SCHEMA_FILE = "report-v1.schema.json"


_FORMAT_ENUM = re.compile(r'"format": \{"enum": \[[^\]]*\]\}')
"""``source.format``'s enumeration, as the shipped file writes it (one line)."""


def report_schema_text() -> str:
    """The JSON Schema of the report (schema_version 1), as text."""
    from cspace._formats.table import names

    text = resources.files(__name__).joinpath(REPORT_SCHEMA_FILE).read_text(encoding="utf-8")
    enum = json.dumps({"enum": list(names())})
    return _FORMAT_ENUM.sub(lambda _: f'"format": {enum}', text, count=1)


def report_schema() -> dict[str, Any]:
    """The JSON Schema of the report (schema_version 1), parsed."""
    schema: dict[str, Any] = json.loads(report_schema_text())
    return schema
