"""``cspace check``: pin a robot's C-space in CI, or hold robots to a baseline.

``cspace check ROBOT --expect SPACE --dimension N`` pins one robot; ``cspace check
--baseline FILE ROBOTS...`` fails only on what differs from a baseline, reading no file
outside the folders checked (`cspace._cli.baseline_check`).

Exit 0 when the robot's C-space is the expected one (up to the order of factors) and
has the expected dimension, no pose the file stores lies outside it (``--ignore
pose-out-of-limits`` accepts such poses; ``--baseline`` compares C-spaces only), and no
error is found in its ``<ros2_control>`` or joint_limits.yaml (`BESIDE_CODES`); 1 with
a one-line explanation when not; 2 when there is no report or the expectation cannot
be read.
"""

from __future__ import annotations

import argparse
from typing import Any

from cspace._findings import BESIDE_CODES
from cspace._render import formats
from cspace._safetext import printable

from .. import exit_codes, output
from ..robots import add_loading_arguments, load_document, xacro_options
from . import add


def _where(finding: dict[str, Any]) -> str:
    """``FILE:LINE: `` of a finding in another file than the robot's (an SRDF), else ''."""
    if not finding.get("file"):
        return ""
    line = f":{finding['line']}" if finding.get("line") else ""
    return f"{printable(str(finding['file']))}{line}: "


def dimension(text: str) -> int:
    """A dimension: a whole number, zero or more (argparse reports anything else)."""
    value = int(text)
    if value < 0:
        raise ValueError(text)
    return value


def register(sub: Any) -> None:
    """Add the ``check`` command."""
    parser = add(
        sub,
        "check",
        description="Check a robot's configuration space against what the team expects, "
        'e.g. --expect "R^6 × T^1" (ASCII x accepted, spaces optional) --dimension 7.',
    )
    parser.add_argument(
        "robot",
        nargs="+",
        help="robot file, erd:NAME, - (standard input) or JSON report; with --baseline, "
        "robot files, folders and patterns (a JSON file there has no report)",
    )
    parser.add_argument(
        "--baseline",
        metavar="FILE",
        help="the accepted reports (JSON Lines, as 'cspace inspect --format jsonl' writes "
        "them, run from this folder, and 'cspace collisions --format jsonl' lines, whose "
        "robots are sampled again): fail only on what differs from them; a report of a "
        "file outside the folders checked is not read",
    )
    parser.add_argument(
        "--format",
        choices=formats.choices("check"),
        default="text",
        help="with --baseline: " + formats.help_text("check", last="or "),
    )
    parser.add_argument(
        "--expect",
        metavar="SPACE",
        help='the expected C-space, e.g. "R^6 x S^1", "SE(3) x R^12", "R^7"',
    )
    parser.add_argument(
        "--dimension",
        type=dimension,
        metavar="N",
        help="the expected dimension of the C-space (a whole number >= 0)",
    )
    parser.add_argument(
        "--ignore",
        action="append",
        default=[],
        metavar="CODE",
        choices=sorted(BESIDE_CODES),
        help="with --expect or --dimension: accept a stored pose, <ros2_control> or "
        "joint_limits.yaml with this finding (repeatable; pose-out-of-limits, say, fails "
        "the check otherwise)",
    )
    add_loading_arguments(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Check the robot and say why it fails, if it does."""
    from cspace._manifold import NormalForm
    from cspace.notation import expectation_failures, parse_notation

    if args.baseline is not None:
        from ..baseline_check import check_baseline

        if args.expect is not None or args.dimension is not None:
            output.error(
                "--baseline compares with the accepted reports; --expect and --dimension pin "
                "one robot: give one or the other"
            )
            return exit_codes.NO_REPORT

        return check_baseline(args)
    if args.expect is None and args.dimension is None:
        output.error(
            "give --expect SPACE and/or --dimension N, or --baseline FILE "
            "(see 'cspace check --help')"
        )
        return exit_codes.NO_REPORT
    if args.format != "text":
        output.error(
            f"--format {args.format} is for --baseline; --expect and --dimension say ok or why not"
        )
        return exit_codes.NO_REPORT
    if len(args.robot) > 1:
        output.error("--expect and --dimension check one robot; --baseline checks several")
        return exit_codes.NO_REPORT
    try:
        xacro_options(args)
        expected = None if args.expect is None else parse_notation(args.expect)
    except ValueError as exc:
        output.error(str(exc))
        return exit_codes.NO_REPORT
    document = load_document(args.robot[0], args)
    counts = document["manifold"]["factors"]
    manifold = NormalForm(r=counts["R"], t=counts["T"], rp3=counts["RP3"])
    failures = expectation_failures(manifold, expected, args.dimension)
    path = printable(document["source"]["path"])
    failures += [  # a stored pose outside the space: the file is wrong, not the space
        _where(d) + f"{d['message']} [{d['code']}]"
        for d in document["diagnostics"]
        if d["severity"] == "error" and d["code"] in BESIDE_CODES and d["code"] not in args.ignore
    ][:1]
    if failures:
        output.check_failed(f"{path}: {'; '.join(failures)}")
        return exit_codes.FINDINGS
    output.write(f"ok: {path}: {manifold.notation}, dimension {manifold.dimension}")
    return exit_codes.OK
