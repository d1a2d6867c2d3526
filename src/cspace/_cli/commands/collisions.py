"""``cspace collisions ROBOT``: which link pairs collide, against the robot's files' filters.

Samples the robot's C-space (seeded, ``-n`` samples, a count on a terminal), sorts
every pair of links with collision shapes as MoveIt's setup assistant does, and checks
what the robot's files say of each pair (the SRDF, MuJoCo's contact filters, PhysX's
collision filters; `cspace.space._collisions.run`). Exit 1 on an error finding (a pair
the SRDF disables that collides, a pair it checks that always collides, a link left out
whose shapes cspace cannot have), or a warning under ``--strict``; ``--write-srdf FILE``
writes the ``<disable_collisions>`` MoveIt's setup assistant would.
"""

from __future__ import annotations

import argparse
from typing import Any

from cspace._findings import COLLISION_CODES, Severity
from cspace._render import formats
from cspace._render.formats import Options

from .. import exit_codes, output
from ..configurations import add_robot_arguments, count
from ..robots import add_findings_arguments
from . import add

REFUSED = {
    "limits": "the samples stay within the robot file's own limits (a URDF's soft limits "
    "within them), as MoveIt's setup assistant draws them",
    "group": "every link pair of the whole robot is sampled",
    "hold": "every link pair of the whole robot is sampled",
}
"""The shared loading options ``cspace collisions`` refuses, and why (its ``--help``)."""


def register(sub: Any) -> None:
    """Add the ``collisions`` command."""
    parser = add(
        sub,
        "collisions",
        description="Sample the robot's C-space and sort every pair of links with collision "
        "shapes as MoveIt's setup assistant does (adjacent, in collision at the default "
        "configuration, always, never, the rest), with the share of samples in which each "
        "pair collides and its 95% interval; check the SRDF's <disable_collisions> (with "
        "--srdf), MuJoCo's contact filters (MJCF) or PhysX's collision filters (OpenUSD) "
        "against them. The same seed gives the same report.",
    )
    add_robot_arguments(parser, stdin=False)  # meshes and the SRDF are found beside it
    for action in parser._actions:  # the loading options `run` refuses say so in --help
        if action.dest in REFUSED:
            action.help = f"refused: {REFUSED[action.dest]}"
    parser.add_argument(
        "-n",
        type=count(1),
        default=10_000,
        metavar="N",
        help="samples, 1 to 1,000,000 (default 10,000, as MoveIt's setup assistant)",
    )
    parser.add_argument(
        "--seed", type=count(0), default=0, metavar="S", help="random seed, >= 0 (default 0)"
    )
    parser.add_argument(
        "--format",
        choices=formats.choices("collisions"),
        default="text",
        help=formats.help_text("collisions"),
    )
    parser.add_argument(
        "-j",
        "--jobs",
        type=count(1),
        default=None,
        metavar="N",
        help="worker processes for runs of 4,000 samples or more (default: one per core)",
    )
    parser.add_argument(
        "--write-srdf",
        metavar="FILE",
        default=None,
        help="write an SRDF whose <disable_collisions> are the pairs MoveIt's setup "
        "assistant would disable (Adjacent, Default, Always, Never) to FILE",
    )
    add_findings_arguments(parser, COLLISION_CODES)
    parser.add_argument(
        "--width",
        type=int,
        default=None,
        metavar="COLUMNS",
        help="text: fit the pair table into COLUMNS (default: the terminal's width)",
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Sample the robot, write its report (and the SRDF asked for)."""
    import os

    from cspace.errors import ArgumentError, OutputError
    from cspace.space._collisions.run import collisions

    from ..progress import Progress
    from ..robots import load_options, robot_name

    for dest in REFUSED:  # the shared loading options, all but these
        if getattr(args, dest) is not None:
            option = f"--{dest}"
            raise ArgumentError(f"{option} does not apply to cspace collisions", argument=option)
    robot = robot_name(args.robot)  # `-` or erd:NAME beside a file of that name: refused
    if robot == "-":
        raise ArgumentError(
            "cspace collisions reads its robot from a file, not standard input: the meshes "
            "and the SRDF are found beside it (save it first, or name ./- for a file named -)",
            argument="robot",
        )
    options = load_options(args)
    if args.write_srdf is not None:  # before the run: a refusal costs no samples
        _srdf_target(args.write_srdf, robot, options.srdf)
    jobs = args.jobs if args.jobs is not None else max(1, len(os.sched_getaffinity(0)))
    with Progress(args.n, "sample") as progress:
        report = collisions(
            robot,
            samples=args.n,
            seed=args.seed,
            srdf=options.srdf,
            root_joint=options.root_joint,
            xacro=options.xacro,
            force_xacro=options.force_xacro,
            allow_dirs=options.allow_dirs,
            jobs=jobs,
            progress=progress.update,
            cpu_limit=True,  # a file cannot make the command's checks take unbounded time
        )
    if args.write_srdf is not None:
        from cspace.files import open_output
        from cspace.space._collisions.srdf import srdf_text

        _srdf_target(args.write_srdf, report.srdf)  # the SRDF --srdf auto found
        try:
            text = srdf_text(report.robot, report.pairs, report.samples, report.seed)
        except ValueError as exc:  # a name of a format XML does not bound (OpenUSD's)
            raise OutputError(args.write_srdf, f"no SRDF can hold it: {exc}") from None
        with open_output(args.write_srdf, binary=False) as stream:
            stream.write(text)
    report = report.ignoring(set(args.ignore))
    width = output.width(args.width)
    text = formats.collisions(args.format, report, Options(width=width))
    if formats.FORMATS[args.format].commands:
        output.write_commands(text)
    else:
        output.write(text)
    if report.has(Severity.ERROR) or (args.strict and report.has(Severity.WARNING)):
        return exit_codes.FINDINGS
    return exit_codes.OK


def _srdf_target(target: str, *reads: object) -> None:
    """Refuse ``--write-srdf`` to standard output or over a file the run reads.

    Args:
        target: ``--write-srdf``'s FILE.
        reads: The robot file and the SRDF read (paths; anything else is skipped).

    Raises:
        OutputError: ``-`` (standard output holds the report), or a file of ``reads``
            (the SRDF written holds ``<disable_collisions>`` alone: the robot, or the
            SRDF's groups, end effectors and virtual joints, would be gone).
    """
    import os

    from cspace.errors import OutputError

    if target == "-":
        raise OutputError(
            target,
            "standard output holds the report: give --write-srdf a file (./- for a file named -)",
        )
    for read in reads:
        if not isinstance(read, (str, os.PathLike)):
            continue
        try:
            same = os.path.samefile(target, read)
        except (OSError, ValueError):  # no such file (yet), or no path at all
            continue
        if same:
            raise OutputError(
                target,
                "it is a file this run reads: the SRDF written holds <disable_collisions> "
                "alone and would replace it (write it elsewhere and merge it by hand)",
            )
