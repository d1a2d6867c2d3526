"""The JSON Schemas of the report and of the collisions report, shipped with the package.

The formats a report's ``source.format`` may name come from the format table
(`cspace._formats.table.FORMATS`): each shipped file lists the package's own, and the
schema given out lists the table's.
"""

from __future__ import annotations

import json
import re
from importlib import resources
from typing import Any

REPORT_SCHEMA_FILE = "report-v1.schema.json"
COLLISIONS_SCHEMA_FILE = "collisions-v1.schema.json"


_FORMAT_ENUM = re.compile(r'"format": \{"enum": \[[^\]]*\]\}')
"""``source.format``'s enumeration, as the shipped file writes it (one line)."""


def _schema_text(file: str) -> str:
    """A shipped schema's text, ``source.format`` listing the format table's formats."""
    from cspace._formats.table import names

    text = resources.files(__name__).joinpath(file).read_text(encoding="utf-8")
    enum = json.dumps({"enum": list(names())})
    return _FORMAT_ENUM.sub(lambda _: f'"format": {enum}', text, count=1)


def report_schema_text() -> str:
    """The JSON Schema of the report (schema_version 1), as text."""
    return _schema_text(REPORT_SCHEMA_FILE)


def report_schema() -> dict[str, Any]:
    """The JSON Schema of the report (schema_version 1), parsed."""
    schema: dict[str, Any] = json.loads(report_schema_text())
    return schema


def collisions_schema_text() -> str:
    """The JSON Schema of ``cspace collisions``' report (schema_version 1), as text."""
    return _schema_text(COLLISIONS_SCHEMA_FILE)


def collisions_schema() -> dict[str, Any]:
    """The JSON Schema of ``cspace collisions``' report, parsed."""
    schema: dict[str, Any] = json.loads(collisions_schema_text())
    return schema
