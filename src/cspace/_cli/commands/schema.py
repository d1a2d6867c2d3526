"""``cspace schema``: print the JSON Schema of the report."""

from __future__ import annotations

import argparse
from typing import Any

from .. import exit_codes, output


def register(sub: Any) -> None:
    """Add the ``schema`` command."""
    parser = sub.add_parser("schema", help="print the JSON Schema of the JSON report")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the schema."""
    del args
    from cspace._schema import report_schema_text  # not on the start-up path of other commands

    output.write(report_schema_text())
    return exit_codes.OK
