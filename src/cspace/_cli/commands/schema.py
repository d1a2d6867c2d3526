"""``cspace schema``: print the JSON Schema of the report."""

from __future__ import annotations

import argparse
from typing import Any

from .. import exit_codes, output
from . import add


def register(sub: Any) -> None:
    """Add the ``schema`` command."""
    parser = add(sub, "schema")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the schema."""
    del args
    from cspace._schema import report_schema_text  # not on the start-up path of other commands

    output.write(report_schema_text())
    return exit_codes.OK
