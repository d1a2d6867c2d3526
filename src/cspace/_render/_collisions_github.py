"""``cspace collisions --format github``: an annotation per finding, and nothing else.

Each finding is one workflow command (``::error``, ``::warning``, ``::notice`` for info)
at the file it names (``Diagnostic.file``: the SRDF of a ``<disable_collisions>`` or a
group state) or else at the robot file (an MJCF's filters, a keyframe), at its line when
it has one, titled ``cspace CODE``; escaped as ``inspect``'s annotations are
(`cspace._render._workflow_commands`). A report without findings writes nothing.
"""

from cspace._render._workflow_commands import COMMAND, command
from cspace._reports.collisions import CollisionReport


def render(report: CollisionReport) -> str:
    """The annotations of a self-collision report's findings, a line each."""
    path = report.source.path
    return "\n".join(
        command(COMMAND[d.severity], d.file or path, d.line, f"cspace {d.code}", d.message)
        for d in report.diagnostics
    )
