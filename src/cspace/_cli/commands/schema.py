"""``cspace schema``: print the report's JSON Schema, or (``--collisions``) the collisions'."""

from __future__ import annotations

import argparse
from typing import Any

from .. import exit_codes, output
from . import add


def register(sub: Any) -> None:
    """Add the ``schema`` command."""
    parser = add(sub, "schema")
    parser.add_argument(
        "--collisions",
        action="store_true",
        help="the schema of 'cspace collisions --format json' instead of the inspect report's",
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Print the schema."""
    from cspace import _schema  # not on the start-up path of other commands

    text = _schema.collisions_schema_text() if args.collisions else _schema.report_schema_text()
    output.write(text)
    return exit_codes.OK
