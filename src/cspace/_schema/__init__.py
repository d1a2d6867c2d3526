"""The JSON Schema of the report, shipped with the package."""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

REPORT_SCHEMA_FILE = "report-v1.schema.json"


def report_schema_text() -> str:
    """The JSON Schema of the report (schema_version 1), as text."""
    return resources.files(__name__).joinpath(REPORT_SCHEMA_FILE).read_text(encoding="utf-8")


def report_schema() -> dict[str, Any]:
    """The JSON Schema of the report (schema_version 1), parsed."""
    schema: dict[str, Any] = json.loads(report_schema_text())
    return schema
