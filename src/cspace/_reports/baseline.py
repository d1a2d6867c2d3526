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

A line may also be a ``cspace collisions --format jsonl`` report (``kind``
``collisions``, `read_saved_document`): a robot's accepted self-collision matrix, kept
apart from its inspect report (one of each per file), whose ``samples`` (at most
`MAX_BASELINE_SAMPLES` in all the baseline's collisions reports) the check draws again.

A check's verdicts are `Row` records (with their annotations, `Spot`), which every
format's ``check`` renderer takes (`cspace._render.formats`).
"""

import os
from collections.abc import Callable

from cspace._record import NamedTuple
from cspace._reports.savedreport import COLLISIONS_KIND, read_saved_document
from cspace.errors import ReportFileError

MAX_BASELINE_BYTES = 64 << 20
"""Largest baseline file read (64 MiB: thousands of robots' reports)."""

MAX_BASELINE_REPORTS = 10_000
"""Most reports in one baseline (as many as one pattern may name files)."""

MAX_BASELINE_SAMPLES = 10_000_000
"""Most samples the collisions reports of one baseline ask for in all: ``check`` draws
them again (ten robots at ``cspace collisions``' most, 1,000,000; a thousand at
MoveIt's 10,000)."""


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


class Baseline(NamedTuple):
    """A baseline's reports, by the key of their source path, in the file's order.

    Attributes:
        reports: The inspect reports (the accepted C-spaces).
        collisions: The collisions reports (the accepted self-collision matrices).
    """

    reports: dict[str, Entry]
    collisions: dict[str, Entry]


def read_baseline(path: str, key: Callable[[str], str] = os.path.normpath) -> Baseline:
    """The baseline's reports of each kind, by the key of their source path.

    Args:
        path: The baseline file.
        key: A source path's key: two paths of one key are one file's.

    Raises:
        FileUnreadableError: The file cannot be read, or is too large.
        ReportFileError: A line is not a valid report, there are too many, two reports
            of one kind and one key (code ``bad-report``), or the collisions reports
            ask for more than `MAX_BASELINE_SAMPLES` samples in all.
    """
    from cspace.files import read_input

    data = read_input(path, max_bytes=MAX_BASELINE_BYTES, what="baseline")
    baseline = Baseline({}, {})
    count = samples = 0
    for number, line in enumerate(data.split(b"\n"), start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        if count >= MAX_BASELINE_REPORTS:
            raise ReportFileError(
                where, f"more than {MAX_BASELINE_REPORTS:,} reports in one baseline", pointer=""
            )
        count += 1
        document = read_saved_document(where, line)
        source = str(document["source"]["path"])
        entries = baseline.reports
        if document.get("kind") == COLLISIONS_KIND:
            entries = baseline.collisions
            samples += document["samples"]
            if samples > MAX_BASELINE_SAMPLES:
                raise ReportFileError(
                    where,
                    f"collisions reports asking for more than {MAX_BASELINE_SAMPLES:,} "
                    "samples in all, which check would draw again",
                    pointer="/samples",
                )
        file = key(source)
        first = entries.get(file)
        if first is not None:
            kind = "collisions report" if entries is baseline.collisions else "report"
            raise ReportFileError(
                where,
                f"a second {kind} of '{file}'{_as(source, file)} (the first at {first.where}"
                f"{_as(first.path, file)}): a baseline holds one {kind} per file",
                pointer="/source/path",
            )
        entries[file] = Entry(where, number, line, source)
    return baseline


def _as(path: str, file: str) -> str:
    """`` as 'PATH'`` when a source path is written otherwise than its file's key."""
    return "" if path == file else f" as '{path}'"
