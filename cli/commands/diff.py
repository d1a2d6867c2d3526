"""``cspace diff OLD NEW``: what changed in the C-space between two versions of a robot.

Each side is a robot file (any format, ``erd:NAME``, ``-``) or a saved JSON report. Exit
0 when the C-space is the same, 1 when it changed, 2 when a side gives no report.
"""

from __future__ import annotations

import argparse
from typing import Any

from .. import exit_codes, output
from ..robots import add_loading_arguments, load_document, xacro_options


def register(sub: Any) -> None:
    """Add the ``diff`` command."""
    parser = sub.add_parser(
        "diff",
        help="show what changed in the C-space between two robot files or reports",
        description="Compare the configuration spaces of two robot files or saved JSON "
        "reports; exit 1 when the C-space changed.",
    )
    parser.add_argument("old", help="the old robot file or JSON report")
    parser.add_argument("new", help="the new robot file or JSON report")
    parser.add_argument(
        "--format",
        choices=("text", "json", "markdown"),
        default="text",
        help="text for people (default), json for tools, markdown for a pull-request comment",
    )
    parser.add_argument(
        "--tolerance",
        type=float,
        default=None,
        metavar="X",
        help="limits closer than X (rad or m) are unchanged (default 1e-6)",
    )
    add_loading_arguments(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Diff two robots and write the changes."""
    from cspace.render.text import render_diff_text
    from cspace.reports.diff import DEFAULT_TOLERANCE, diff_reports

    tolerance = DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance
    if args.old == "-" and args.new == "-":
        output.error("only one side of diff can be read from standard input")
        return exit_codes.NO_REPORT
    if not tolerance >= 0.0:
        output.error(f"--tolerance must be a number >= 0, not {tolerance}")
        return exit_codes.NO_REPORT
    try:
        xacro_options(args)
    except ValueError as exc:
        output.error(str(exc))
        return exit_codes.NO_REPORT
    old = load_document(args.old, args)
    new = load_document(args.new, args)
    diff = diff_reports(old, new, tolerance=tolerance)
    if args.format == "json":
        output.write(diff.to_json())
    elif args.format == "markdown":
        from cspace.render.markdown import render_diff_markdown

        output.write(render_diff_markdown(diff))
    else:
        output.write(render_diff_text(diff))
    return exit_codes.FINDINGS if diff.changed else exit_codes.OK
