"""``cspace inspect ROBOT...``: the configuration space of one or several robot files.

One robot: its report (text, JSON or Markdown). Several (or a glob pattern): JSON Lines
(one compact report per line) with ``--format json``, else a summary table with one row
per file; ``--format jsonl`` writes JSON Lines however many files there are. A file
without a report is reported on standard error and the others go on, whatever went
wrong with it: a bug met on one file (any exception but a ``CspaceError``) is that
file's ``internal-error`` line (its traceback follows with ``--debug``), not the end of
the run. The exit code is the worst of all files.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

import cspace
from cspace._findings import CODES
from cspace._formats.table import titles
from cspace._render import formats
from cspace._render.formats import FORMATS, Options
from cspace._safetext import printable

from .. import exit_codes, output
from ..patterns import Searched, is_glob
from ..progress import Progress
from ..robots import (
    ROOT_JOINTS,
    add_findings_arguments,
    add_loading_arguments,
    expand_patterns,
    load_options,
    load_report,
    refuses_xacro_options,
    robots_among,
)
from . import add

if TYPE_CHECKING:
    from cspace._reports.summary import SummaryRow

__all__ = ["ROOT_JOINTS", "exit_code", "register", "run"]


def register(sub: Any) -> None:
    """Add the ``inspect`` command."""
    parser = add(
        sub,
        "inspect",
        description="Report the configuration space of robot files as product manifolds.",
    )
    parser.add_argument(
        "robot",
        nargs="+",
        help=f"robot file ({titles()}), folder (the robot files in it), "
        "quoted glob pattern, erd:NAME, or - for standard input; after --, each is that "
        "file or folder; several give JSON Lines or a summary table",
    )
    parser.add_argument(
        "--format",
        choices=formats.choices("inspect"),
        default="text",
        help=formats.help_text("inspect"),
    )
    add_loading_arguments(parser)
    add_findings_arguments(parser, CODES)
    parser.add_argument(
        "--robots-only",
        action="store_true",
        help="of the files named, inspect the robot descriptions and leave the rest, as for "
        "a folder (other XML, fragments that other files include): for file lists from "
        "git or pre-commit",
    )
    parser.add_argument(
        "--hide-fixed",
        action="store_true",
        help="text: leave fixed joints out of the joint table (they are counted)",
    )
    parser.add_argument(
        "-j",
        "--jobs",
        type=_jobs,
        default=None,
        metavar="N",
        help="several files: inspect N at a time in worker processes (default: one per "
        "core); results stay in input order",
    )
    parser.add_argument(
        "--output-dir",
        metavar="DIR",
        default=None,
        help="html and svg: write each robot's page to DIR (NN-NAME.html) and "
        "DIR/index.html linking them; the summary table goes to standard output",
    )
    parser.add_argument(
        "--width",
        type=int,
        default=None,
        metavar="COLUMNS",
        help="text: fit the joint table into COLUMNS (default: $COLUMNS when set, a "
        "pipe's too, else the terminal's width when writing to one, else no limit)",
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
    """Inspect the robot files and write their reports."""
    if refuses_xacro_options(args):
        return exit_codes.NO_REPORT
    single = args.robot[0]
    chosen = FORMATS[args.format]
    found = expand_patterns(args.robot)
    if args.robots_only:
        searched = [n for n in args.robot if os.path.isdir(n) and not os.path.islink(n)]
        found = robots_among(found, searched)
    if len(found) > 1 and args.srdf not in (None, "auto"):
        output.error("--srdf FILE goes with one robot (--srdf auto finds each robot's own)")
        return exit_codes.NO_REPORT
    if len(found) > 1 and args.limits not in (None, "auto"):
        output.error("--limits FILE goes with one robot (--limits auto finds each robot's own)")
        return exit_codes.NO_REPORT
    if args.output_dir is not None:
        if chosen.several:
            output.error("--output-dir is for --format html or svg (a page per robot)")
            return exit_codes.NO_REPORT
        return _several(args, found)
    plain = len(found) == 1 and (found == [single] or not chosen.several)
    if plain and not formats.shows_failures(args.format):  # one robot: its report, or error
        return _one(args, found[0])
    if not chosen.several:
        output.error(
            f"--format {args.format} draws one robot; give one file, or --output-dir DIR "
            "for a page each"
        )
        return exit_codes.NO_REPORT
    return _several(args, found)


def _one(args: argparse.Namespace, name: str) -> int:
    try:
        report = load_report(name, args).ignoring(frozenset(args.ignore))
    except cspace.RobotFileError as exc:
        from cspace._reports.summary import FRAGMENT_CODE

        if exc.code != FRAGMENT_CODE and not _left_out(name, exc):
            raise
        output.note(f"{exc} [{exc.code}]")  # no robot of its own: nothing is wrong
        return exit_codes.OK
    except cspace.CspaceError:
        raise
    except Exception as exc:  # a bug: said as in a batch, the file named
        raise cspace.InternalError.of(name, exc) from exc
    write = output.write_commands if FORMATS[args.format].commands else output.write
    write(formats.one(args.format, report, _options(args)))
    return exit_code(report, args.strict)


def _left_out(name: str, error: object) -> bool:
    """Whether a search told ``name`` a robot, unsure, and its reader found an SRDF.

    Such a file (a ``.srdf.xacro`` that only xacro tells) is left out with a note, as
    the search leaves out the SRDF files it is sure of; named as a robot, it is an error.
    """
    from cspace._formats.shared.roots import SRDF_CODE

    return isinstance(name, Searched) and getattr(error, "code", None) == SRDF_CODE


def _options(args: argparse.Namespace) -> Options:
    return Options(output.use_color(args.color), output.width(args.width), args.hide_fixed)


def _jobs(text: str) -> int:
    from ..configurations import count

    return count(1)(text)


def _several(args: argparse.Namespace, names: list[str]) -> int:
    from cspace._reports.summary import FRAGMENT_CODE, SummaryRow

    chosen = FORMATS[args.format]
    write = output.write_commands if chosen.commands else output.write
    worst = exit_codes.OK
    rows = []
    pieces: list[str] = []
    pages = None
    if args.output_dir is not None:
        from ..pages import Pages

        pages = Pages(args.output_dir, f".{args.format}", len(names))

    def put(piece: str | None, path: str = "") -> None:
        if pages is not None:  # a page each (None: a file without one)
            pages.write(path, piece)
            return
        if piece is None:
            return
        if not chosen.streams:
            pieces.append(piece)
            return
        with progress.paused():
            write(piece)

    with Progress(len(names), "file") as progress:
        for name, outcome in _outcomes(args, names):
            progress.update()
            if _left_out(name, outcome):  # an SRDF, as its reader tells: no row
                with progress.paused():
                    output.note(f"{outcome} [{getattr(outcome, 'code', '')}]")
                continue
            if getattr(outcome, "code", None) == FRAGMENT_CODE:  # left to its model
                with progress.paused():
                    output.note(f"{outcome} [{FRAGMENT_CODE}]")
                rows.append(SummaryRow.of_fragment(name))
                put(None, name)
                continue
            if isinstance(outcome, cspace.CspaceError):
                code = getattr(outcome, "code", None)  # as cspace's main says it for one file
                with progress.paused():
                    output.error(f"{outcome} [{code}]" if isinstance(code, str) else str(outcome))
                    if isinstance(outcome, cspace.InternalError) and getattr(args, "debug", False):
                        _traceback(outcome)
                rows.append(SummaryRow.of_error(name, str(outcome)))
                worst = max(worst, exit_codes.NO_REPORT)
                if pages is not None:
                    put(None, name)
                elif formats.shows_failures(args.format):
                    said = code if isinstance(code, str) else None
                    problem = str(getattr(outcome, "problem", "") or outcome)
                    at, line = _located(name, outcome)
                    put(formats.failed(args.format, at, problem, said, line))
                continue
            code, row, piece = outcome
            worst = max(worst, code)
            rows.append(row)
            if row.failing:  # each finding that fails the run, where a CI log shows it
                with progress.paused():
                    for severity, line, said, message in row.failing:
                        at = f"{row.path}:{line}" if line is not None else row.path
                        output.finding(severity, f"{at}: {message} [{said}]")
            put(piece, row.path)
    if pages is not None:
        index = pages.index(rows)
        output.write(formats.end_of("text", rows, pieces, _options(args)))
        written = sum(p is not None for p in pages.pages)
        output.note(f"wrote {written} page{'' if written == 1 else 's'} and {index}")
        return worst
    end = formats.end_of(args.format, rows, pieces, _options(args))
    if end:
        write(end)
    return worst


def _traceback(error: cspace.InternalError) -> None:
    """The traceback of a bug met on one file (as captured in the worker), escaped."""
    for line in error.traceback.splitlines():
        sys.stderr.write(printable(line, limit=None) + "\n")


Digest = tuple[int, "SummaryRow", str | None]
"""What ``_several`` needs of a report: its exit code, summary row and piece of output."""


def digest(report: cspace.Report, ignore: frozenset[str], strict: bool, fmt: str) -> Digest:
    """A report's exit code, summary row and piece in format ``fmt`` (or None): in workers."""
    from cspace._reports.summary import SummaryRow

    report = report.ignoring(ignore)
    code = exit_code(report, strict)
    row = SummaryRow.of_report(report, failed=code != exit_codes.OK, strict=strict)
    return code, row, formats.piece(fmt, report)


def _outcomes(
    args: argparse.Namespace, names: list[str]
) -> Iterator[tuple[str, Digest | cspace.CspaceError]]:
    """Each name's digest or error, in order: files in worker processes (``--jobs``).

    Standard input and patterns that matched nothing are handled here, as for one file,
    and as in the workers any exception is that name's error (``InternalError`` for a bug).
    """
    import functools

    from cspace._model.many import default_jobs, inspect_many_with

    summarise = functools.partial(
        digest, ignore=frozenset(args.ignore), strict=args.strict, fmt=args.format
    )
    here = [name == "-" or (is_glob(name) and not os.path.lexists(name)) for name in names]
    jobs = args.jobs if args.jobs is not None else default_jobs()
    files = [str(name) for name, local in zip(names, here, strict=True) if not local]
    inspected = inspect_many_with(
        files,
        load_options(args),
        jobs=1 if len(files) < 2 else min(jobs, len(files)),
        then=summarise,
    )
    for name, local in zip(names, here, strict=True):
        if local:
            yield name, _here(name, args, summarise)
        else:
            done = next(inspected)
            if done.error is not None:
                yield name, done.error
            else:
                yield name, done.value


def _located(name: str, error: cspace.CspaceError) -> tuple[str, int | None]:
    """The file and line an error is about: the file it names (an SRDF), when a file."""
    path, line = getattr(error, "path", name), getattr(error, "line", None)
    if path == name:
        return name, line
    return (path, line) if os.path.isfile(path) else (name, line)


def _here(
    name: str, args: argparse.Namespace, summarise: Callable[[cspace.Report], Digest]
) -> Digest | cspace.CspaceError:
    """The digest or error of a name handled in this process (as ``inspect_many`` does)."""
    try:
        report = load_report(name, args)
    except cspace.CspaceError as exc:
        return exc
    except Exception as exc:  # a bug: this name's error, not the end of the run
        return cspace.InternalError.of(name, exc)
    try:
        return summarise(report)
    except Exception as exc:
        return cspace.InternalError.of(name, exc, stage="then")
