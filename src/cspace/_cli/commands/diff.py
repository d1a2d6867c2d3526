"""``cspace diff OLD NEW``: what changed in the C-space between two versions of a robot.

Each side is a robot file (any format, ``erd:NAME``, ``-``) or a saved JSON report; the
two may be in different formats (a URDF and the MJCF made from it). Exit 0 when nothing
but notes differs, 1 when the C-space changed or its limits or q/v layout differ, 2 when
a side gives no report.
"""

from __future__ import annotations

import argparse
from typing import Any

from cspace._render import formats

from .. import exit_codes, output
from ..robots import (
    ROOT_JOINTS,
    add_loading_arguments,
    load_document,
    refuses_xacro_options,
)
from . import add


def register(sub: Any) -> None:
    """Add the ``diff`` command."""
    parser = add(
        sub,
        "diff",
        description="Compare the configuration spaces of two robot files or saved JSON "
        "reports; exit 1 when the C-space changed or its limits or q/v layout differ.",
    )
    parser.add_argument("old", help="the old robot file or JSON report")
    parser.add_argument("new", help="the new robot file or JSON report")
    parser.add_argument(
        "--format",
        choices=formats.choices("diff"),
        default="text",
        help=formats.help_text("diff"),
    )
    parser.add_argument(
        "--tolerance",
        type=float,
        default=None,
        metavar="X",
        help="limits, and loop cuts' frames, closer than X (rad or m) are unchanged (default 1e-6)",
    )
    parser.add_argument(
        "--rel-tolerance",
        type=float,
        default=None,
        metavar="X",
        help="limits that differ by at most X times the larger magnitude are unchanged "
        "(default 1e-5: files written with 6 significant digits, such as MuJoCo's)",
    )
    parser.add_argument(
        "--map",
        action="append",
        default=[],
        metavar="OLD=NEW",
        help="the old side's joint OLD is the new side's joint NEW (repeatable); "
        "'OLD*=NEW*' maps every joint named OLD... to NEW... with the same rest",
    )
    parser.add_argument(
        "--width",
        type=int,
        default=None,
        metavar="COLUMNS",
        help="text: fit the tables into COLUMNS (default: $COLUMNS when set, a pipe's too, "
        "else the terminal's width when writing to one, else no limit)",
    )
    for side in ("old", "new"):
        parser.add_argument(
            f"--{side}-root-joint",
            choices=ROOT_JOINTS,
            default=None,
            help=f"add a root joint on the {side} side only (overrides --root-joint there)",
        )
        parser.add_argument(
            f"--{side}-limits",
            metavar="FILE",
            default=None,
            help=f"read MoveIt's joint_limits.yaml (or 'auto') with the {side} robot only "
            "(overrides --limits there)",
        )
    from ._diff_orders import add_order_arguments

    add_order_arguments(parser)
    add_loading_arguments(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Diff two robots and write the changes."""
    from cspace._reports._renames import expand_renames, prefix_hint
    from cspace._reports.diff import DEFAULT_REL_TOLERANCE, DEFAULT_TOLERANCE, diff_reports

    tolerance = DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance
    rel = DEFAULT_REL_TOLERANCE if args.rel_tolerance is None else args.rel_tolerance
    if args.old == "-" and args.new == "-":
        output.error("only one side of diff can be read from standard input")
        return exit_codes.NO_REPORT
    for option, value in (("--tolerance", tolerance), ("--rel-tolerance", rel)):
        if not value >= 0.0:
            output.error(f"{option} must be a number >= 0, not {value}")
            return exit_codes.NO_REPORT
    pairs: list[tuple[str, str]] = []
    for pair in args.map:
        old_name, sep, new_name = pair.partition("=")
        if not sep or not old_name or not new_name:
            output.error(f"--map takes OLD=NEW (two joint names, or OLD*=NEW*), not {pair!r}")
            return exit_codes.NO_REPORT
        pairs.append((old_name, new_name))
    if refuses_xacro_options(args):
        return exit_codes.NO_REPORT
    old_root, new_root = (
        args.old_root_joint or args.root_joint,
        args.new_root_joint or args.root_joint,
    )
    old = load_document(args.old, args, old_root, limits=args.old_limits)
    new = load_document(args.new, args, new_root, limits=args.new_limits)
    try:
        renames = expand_renames(
            pairs, (j["name"] for j in old["joints"]), (j["name"] for j in new["joints"])
        )
    except ValueError as exc:
        output.error(str(exc))
        return exit_codes.NO_REPORT
    diff = diff_reports(old, new, tolerance=tolerance, rel_tolerance=rel, renames=renames)
    if args.old_order or args.new_order:
        from ._diff_orders import with_orders

        diff = with_orders(args, old, new, diff, renames)
        if diff is None:
            return exit_codes.NO_REPORT
    removed = [c.joint for c in diff.changes if c.kind == "joint-removed" and c.joint]
    added = [c.joint for c in diff.changes if c.kind == "joint-added" and c.joint]
    rule = prefix_hint(removed, added)
    if rule is not None:  # every joint renamed alike: say how to match them
        output.note(f"the joints differ only by a prefix: try --map '{rule}'")
    options = formats.Options(width=output.width(args.width))
    write = output.write_commands if formats.FORMATS[args.format].commands else output.write
    write(formats.diff(args.format, old, new, diff, options))
    return exit_codes.FINDINGS if diff.differs else exit_codes.OK
