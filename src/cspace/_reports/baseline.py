"""A baseline of accepted C-spaces: the reports a repository has agreed to, as JSON Lines.

A baseline is what ``cspace inspect --format jsonl FILES > cspace-baseline.jsonl``
writes: one report per line. ``cspace check --baseline FILE ROBOTS...`` fails only on
what differs from it: a robot whose C-space changed (`diff_reports`), a robot the
baseline does not hold, a file the baseline holds that is gone. Accepting a change is
writing the baseline again and committing it.

The file is untrusted: at most `MAX_BASELINE_BYTES` and `MAX_BASELINE_REPORTS` reports,
each line read as a saved report is (`read_report_document`: strict JSON, the schema,
consistency, a tree), one report per file: each source path has a key (the caller's:
the command line's is the file's path with every spelling folded to one), and two
lines of one key are refused, naming both. Lines are kept as bytes and parsed again
only when compared, so memory follows the file's size.

A check's verdicts are `Row` records (with their annotations, `Spot`), which every
format's ``check`` renderer takes (`cspace._render.formats`).
"""

import os
from collections.abc import Callable

from cspace._record import NamedTuple
from cspace._reports.savedreport import read_report_document
from cspace.errors import ReportFileError

MAX_BASELINE_BYTES = 64 << 20
"""Largest baseline file read (64 MiB: thousands of robots' reports)."""

MAX_BASELINE_REPORTS = 10_000
"""Most reports in one baseline (as many as one pattern may name files)."""


class Entry(NamedTuple):
    """One report of a baseline.

    Attributes:
        where: ``FILE:LINE`` of its line.
        line: Its line's number in the file.
        data: The line's bytes (the report, parsed again when it is compared).
        path: Its source path, as written.
    """

    where: str
    line: int
    data: bytes
    path: str


class Spot(NamedTuple):
    """One place a verdict is shown at, as an annotation: a line, a title, a message.

    Attributes:
        line: The line, or None: the whole file.
        title: What differs, in a word or two.
        message: What to do about it.
        level: ``error`` or ``warning``.
        file: The file, or None: the row's robot file.
    """

    line: int | None
    title: str
    message: str
    level: str = "error"
    file: str | None = None


class Row(NamedTuple):
    """One robot's verdict against the baseline (``same``, ``changed``, ``new``, ...).

    Attributes:
        path: The robot file, as named (or the baseline's path of a file not read).
        verdict: The verdict.
        what: What the verdict is about, in words.
        spots: Where an annotation shows it, for a verdict that is not ``same``.
    """

    path: str
    verdict: str
    what: str
    spots: tuple[Spot, ...] = ()


def read_baseline(path: str, key: Callable[[str], str] = os.path.normpath) -> dict[str, Entry]:
    """The baseline's reports by the key of their source path, in the file's order.

    Args:
        path: The baseline file.
        key: A source path's key: two paths of one key are one file's.

    Raises:
        FileUnreadableError: The file cannot be read, or is too large.
        ReportFileError: A line is not a valid report, there are too many, or two
            reports of one key (code ``bad-report``).
    """
    from cspace.files import read_input

    data = read_input(path, max_bytes=MAX_BASELINE_BYTES, what="baseline")
    entries: dict[str, Entry] = {}
    for number, line in enumerate(data.split(b"\n"), start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        if len(entries) >= MAX_BASELINE_REPORTS:
            raise ReportFileError(
                where, f"more than {MAX_BASELINE_REPORTS:,} reports in one baseline", pointer=""
            )
        source = str(read_report_document(where, line)["source"]["path"])
        file = key(source)
        first = entries.get(file)
        if first is not None:
            raise ReportFileError(
                where,
                f"a second report of '{file}'{_as(source, file)} (the first at {first.where}"
                f"{_as(first.path, file)}): a baseline holds one report per file",
                pointer="/source/path",
            )
        entries[file] = Entry(where, number, line, source)
    return entries


def _as(path: str, file: str) -> str:
    """`` as 'PATH'`` when a source path is written otherwise than its file's key."""
    return "" if path == file else f" as '{path}'"
