"""``check --baseline``: a robot's self-collision matrix against its accepted collisions report.

A baseline line may be a ``cspace collisions ROBOT --format jsonl`` report (kind
``collisions``). For a robot checked whose baseline holds one, the robot's samples are
drawn again with that report's ``samples`` and ``seed`` (at most 1,000,000, as the
report's schema says, and `cspace._reports.baseline.MAX_BASELINE_SAMPLES` in all), and
the two reports are compared pair by pair (`diff_collisions`): a row ``same``,
``differs`` (shares moved out of their intervals) or ``changed`` (pairs added or gone,
classes, rules, new error findings), after the robot's C-space row.

The saved report is untrusted, and says nothing of which files are read: the robot is
the file checked (read as its C-space row reads it), its meshes are found as
``cspace collisions`` finds them, and its SRDF is the check's own ``--srdf`` (a FILE, or
``auto``) whenever it is given, whatever the accepted report had (an SRDF added since
is a changed matrix), else the one ``--srdf auto`` finds when the accepted report had
one; never the path the report gives. A report that forges classes or counts can only differ
from the robot's: what the robot gives now is drawn, never read.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import cspace
from cspace._reports.baseline import Row, Spot

from . import exit_codes, output
from .robots import load_options, robot_name

if TYPE_CHECKING:
    from cspace._reports._collision_diff import CollisionDiff
    from cspace._reports.baseline import Entry

MAX_NAMED = 5
"""Most changes a row's text names (the rest counted)."""

MAX_SPOTS = 50
"""Most annotations of one robot's changes (the last says how many more)."""


def compared(name: str, entry: Entry, args: argparse.Namespace) -> tuple[Row, int]:
    """The row of robot ``name`` against its accepted collisions report, and its exit code.

    Args:
        name: The robot as checked (a file the check read, or ``erd:NAME``).
        entry: The baseline's collisions report of it.
        args: The check's command line (how robots are read).

    Returns:
        The row, and `exit_codes.OK`, `exit_codes.FINDINGS` (it differs) or
        `exit_codes.NO_REPORT` (the robot cannot be sampled).
    """
    from cspace._reports._collision_diff import diff_collisions
    from cspace._reports.savedreport import read_saved_document

    accepted = read_saved_document(entry.where, entry.data)
    try:
        now = _drawn_again(name, accepted, args)
    except cspace.CspaceError as exc:
        code = getattr(exc, "code", None)
        output.error(f"{exc} [{code}]" if isinstance(code, str) else str(exc))
        what = f"self-collision: no report: {exc}"
        return Row(name, "no report", what, (Spot(None, "no report", what),)), (
            exit_codes.NO_REPORT
        )
    diff = diff_collisions(accepted, now)
    drawn = f"{diff.samples:,} samples, seed {diff.seed}"
    if diff.verdict == "same":
        what = f"self-collision: {diff.pairs} pairs, classes and rules as accepted ({drawn})"
        return Row(name, "same", what), exit_codes.OK
    named = "; ".join(c.text for c in diff.changes[:MAX_NAMED])
    more = len(diff.changes) - MAX_NAMED
    named += f"; and {more} more" if more > 0 else ""
    if diff.verdict == "changed":
        what = f"self-collision matrix: {named} ({drawn})"
    else:
        what = f"self-collision: same classes and rules, shares moved: {named} ({drawn})"
    return Row(name, diff.verdict, what, _spots(diff, _accept(name, accepted, now))), (
        exit_codes.FINDINGS
    )


def _accept(name: str, accepted: Mapping[str, Any], now: Mapping[str, Any]) -> str:
    """How a change is accepted: the command that writes the robot's line again.

    It reads an SRDF when one was read now.
    """
    import shlex

    srdf = " --srdf auto" if now["srdf"] is not None else ""
    return (
        f"write its line again to accept it: cspace collisions {shlex.quote(name)}{srdf} "
        f"-n {accepted['samples']} --seed {accepted['seed']} --format jsonl"
    )


def _drawn_again(
    name: str, accepted: Mapping[str, Any], args: argparse.Namespace
) -> dict[str, Any]:
    """The robot's collisions report now, with the accepted report's samples and seed.

    Raises:
        CspaceError: The robot cannot be read or sampled (a robot read from standard
            input, read once already, is not read again).
    """
    if name == "-":
        raise cspace.errors.ArgumentError(
            "-: a robot read from standard input is not read again to draw its samples"
        )
    options = load_options(args)
    srdf = options.srdf if options.srdf not in (None, False) else None  # always, when given
    if srdf is None and accepted["srdf"] is not None:  # never the path the report gives
        srdf = True
    report = cspace.collisions(
        robot_name(name),
        samples=accepted["samples"],
        seed=accepted["seed"],
        srdf=srdf,
        root_joint=options.root_joint,
        xacro=options.xacro,
        force_xacro=options.force_xacro,
        allow_dirs=options.allow_dirs,
        jobs=max(1, len(os.sched_getaffinity(0))),
    )
    return report.to_dict()


def _spots(diff: CollisionDiff, accept: str) -> tuple[Spot, ...]:
    """Each change at the line of the robot's files that says it (the SRDF's), capped."""
    spots = []
    for c in diff.changes[:MAX_SPOTS]:
        file = None if c.file is None else os.path.normpath(c.file)
        title = f"self-collision {c.kind}"
        spots.append(Spot(c.line, title, f"{c.text} ({accept})", "error", file))
    more = len(diff.changes) - MAX_SPOTS
    if more > 0:
        spots.append(Spot(None, "self-collision", f"and {more} more changes ({accept})"))
    return tuple(spots)
