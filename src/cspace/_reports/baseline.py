"""A baseline of accepted C-spaces: the reports a repository has agreed to, as JSON Lines.

A baseline is what ``cspace inspect --format jsonl FILES > cspace-baseline.jsonl``
writes: one report per line. ``cspace check --baseline FILE ROBOTS...`` fails only on
what differs from it: a robot whose C-space changed (`diff_reports`), a robot the
baseline does not hold, a file the baseline holds that is gone. Accepting a change is
writing the baseline again and committing it.

The file is untrusted: at most `MAX_BASELINE_BYTES` and `MAX_BASELINE_REPORTS` reports,
each line read as a saved report is (`read_report_document`: strict JSON, the schema,
consistency, a tree), one report per source path. Lines are kept as bytes and parsed
again only when compared, so memory follows the file's size.
"""

from __future__ import annotations

from cspace._reports.savedreport import read_report_document
from cspace.errors import ReportFileError

MAX_BASELINE_BYTES = 64 << 20
"""Largest baseline file read (64 MiB: thousands of robots' reports)."""

MAX_BASELINE_REPORTS = 10_000
"""Most reports in one baseline (as many as one pattern may name files)."""


def read_baseline(path: str) -> dict[str, tuple[str, bytes]]:
    """The baseline's reports: source path -> (where it stands, its line's bytes).

    Raises:
        FileUnreadableError: The file cannot be read, or is too large.
        ReportFileError: A line is not a valid report, there are too many, or two
            reports of one source path (code ``bad-report``).
    """
    from cspace.files import read_input

    data = read_input(path, max_bytes=MAX_BASELINE_BYTES, what="baseline")
    entries: dict[str, tuple[str, bytes]] = {}
    for number, line in enumerate(data.split(b"\n"), start=1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        if len(entries) >= MAX_BASELINE_REPORTS:
            raise ReportFileError(
                where, f"more than {MAX_BASELINE_REPORTS:,} reports in one baseline", pointer=""
            )
        source = str(read_report_document(where, line)["source"]["path"])
        if source in entries:
            raise ReportFileError(
                where,
                f"a second report of '{source}' (the first at {entries[source][0]})",
                pointer="/source/path",
            )
        entries[source] = (where, line)
    return entries
