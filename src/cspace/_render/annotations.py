"""GitHub workflow commands: each finding an annotation on its file and line.

``::error file=F,line=N,title=T::MESSAGE`` (``warning``, ``notice`` for info), and a
``notice`` per file with its C-space (and its mechanism's summary, when it closes
loops). The text is escaped as cspace escapes every output (`printable`: control, C1
and bidi characters shown as escapes, ``::`` at the start and
``##[`` neutralised) and then by the workflow-command rules: ``%``, CR and LF
percent-encoded in the message, and ``:`` and ``,`` too in the properties, so that no
robot file can end the command and start one of its own in the log that runs it. The
``file`` property keeps the path as it is (but its control characters), so that the
annotation lands on the file: its ``:`` are percent-encoded, and a ``##[`` in it is part
of cspace's command, which the runner reads first (a line is read in the older syntax only
when it is no command of the new one).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace._findings import Severity
from cspace._safetext import printable

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.baseline import Row
    from cspace._reports.report import Report

_COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def escape_data(text: str) -> str:
    """A workflow command's message: ``%``, CR and LF percent-encoded."""
    safe = printable(text, limit=None)
    return safe.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(text: str, *, path: bool = False) -> str:
    """A workflow command's property value: as a message, and ``:`` and ``,`` too.

    ``path``: a file's path, kept as it is but for its control characters (no
    neutralised ``::`` or ``##[``: the annotation must name the file).
    """
    safe = printable(text, limit=None, commands_kept=path)
    safe = safe.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")
    return safe.replace(":", "%3A").replace(",", "%2C")


def command(kind: str, path: str, line: int | None, title: str, message: str) -> str:
    """One workflow command: ``::KIND file=PATH,line=LINE,title=TITLE::MESSAGE``, escaped.

    ``line`` None (or below 1): the annotation is on the file, not a line.
    """
    where = f"file={escape_property(path, path=True)}"
    if line is not None and line >= 1:
        where += f",line={line}"
    return f"::{kind} {where},title={escape_property(title)}::{escape_data(message)}"


def inspect_piece(report: Report) -> str:
    """One report's annotations: its C-space, then each finding."""
    path = report.source.path
    lines = [
        command(
            "notice",
            path,
            None,
            "cspace",
            f"C = {report.manifold.notation}, dimension {report.dimension}"
            + ("" if report.closure is None else f"; {report.closure.summary}"),
        )
    ]
    lines += [
        command(_COMMAND[d.severity], d.file or path, d.line, f"cspace {d.code}", d.message)
        for d in report.diagnostics
    ]
    return "\n".join(lines)


def inspect_failed(path: str, message: str, code: str | None, line: int | None) -> str:
    """The annotation of a file that gave no report (at its line, when known)."""
    return command("error", path, line, f"cspace {code or 'no-report'}", message)


def inspect_one(report: Report, options: Options) -> str:
    """One report's annotations."""
    return inspect_piece(report)


def check(rows: Sequence[Row], options: Options) -> str:
    """``check --baseline``: each difference at its line, a report not read at the baseline's."""
    return "\n".join(
        command(s.level, s.file or r.path, s.line, f"cspace baseline: {s.title}", s.message)
        for r in rows
        for s in r.spots
    )
