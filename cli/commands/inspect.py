"""``cspace inspect ROBOT``: the configuration space of a robot file."""

from __future__ import annotations

import argparse
from typing import Any

import cspace
from cspace.diagnostics import CODES

from .. import exit_codes, output

ROOT_JOINTS = ("floating", "planar")


def register(sub: Any) -> None:
    """Add the ``inspect`` command."""
    parser = sub.add_parser(
        "inspect",
        help="report the configuration space of a robot file",
        description="Report the configuration space of a robot file as a product manifold.",
    )
    parser.add_argument("robot", help="robot file (URDF)")
    parser.add_argument(
        "--format",
        choices=("text", "json"),
        default="text",
        help="text for people (default), json for CI and tools",
    )
    parser.add_argument(
        "--root-joint",
        choices=ROOT_JOINTS,
        default=None,
        help="add a root joint above the root link (mobile and legged robots)",
    )
    parser.add_argument(
        "--strict", action="store_true", help="exit 1 on warnings too, not only on errors"
    )
    parser.add_argument(
        "--ignore",
        action="append",
        default=[],
        metavar="CODE",
        choices=sorted(CODES),
        help="drop findings with this code (repeatable)",
    )
    parser.add_argument(
        "--color",
        choices=("auto", "always", "never"),
        default="auto",
        help="colour the text report (auto: on a terminal, unless NO_COLOR)",
    )
    parser.set_defaults(run=run)


def exit_code(report: cspace.Report, strict: bool) -> int:
    """1 when the report has errors (or warnings, under ``strict``); else 0."""
    if report.has(cspace.Severity.ERROR):
        return exit_codes.FINDINGS
    if strict and report.has(cspace.Severity.WARNING):
        return exit_codes.FINDINGS
    return exit_codes.OK


def run(args: argparse.Namespace) -> int:
    """Inspect one robot file and write its report."""
    report = cspace.inspect(args.robot, root_joint=args.root_joint)
    report = report.ignoring(frozenset(args.ignore))
    if args.format == "json":
        output.write(report.to_json())
    else:
        from cspace.render import render_text

        output.write(render_text(report, color=output.use_color(args.color)))
    return exit_code(report, args.strict)
