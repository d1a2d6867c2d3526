"""GitHub workflow commands: each finding an annotation on its file and line.

``::error file=F,line=N,title=T::MESSAGE`` (``warning``, ``notice`` for info), and a
``notice`` per file with its C-space (and its mechanism's summary, when it closes
loops); ``cspace collisions`` writes one per finding and nothing else
(`cspace._render._collisions_github`). Each is escaped where it is made
(`cspace._render._workflow_commands`): as cspace escapes every output (`printable`),
then by the workflow-command rules, so that no robot file can end the command and start
one of its own in the log that runs it, while the ``file`` property still names the file.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace._render._workflow_commands import COMMAND, command

if TYPE_CHECKING:
    from cspace._render.formats import Options
    from cspace._reports.baseline import Row
    from cspace._reports.collisions import CollisionReport
    from cspace._reports.report import Report


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
        command(COMMAND[d.severity], d.file or path, d.line, f"cspace {d.code}", d.message)
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


def collisions(report: CollisionReport, options: Options) -> str:
    """``cspace collisions --format github``: one annotation per finding, nothing else."""
    from cspace._render._collisions_github import render

    return render(report)
