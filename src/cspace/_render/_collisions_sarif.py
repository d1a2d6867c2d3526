"""``cspace collisions --format sarif``: a SARIF 2.1.0 log, a result per finding.

Each finding is a result under its code's rule (`cspace._render._sarif_log`), at the
file it names (``Diagnostic.file``: the SRDF of a ``<disable_collisions>`` or a group
state) or else at the robot file (an MJCF's filters, a keyframe), and at its line when it
has one. URIs and escaping are those of ``inspect --format sarif``.
"""

from cspace._render._sarif_log import LEVEL, log, result
from cspace._reports.collisions import CollisionReport


def render(report: CollisionReport) -> str:
    """The SARIF log of a self-collision report's findings (no result when it has none)."""
    path = report.source.path
    return log(
        [
            result(d.code, LEVEL[d.severity], d.message, d.file or path, d.line)
            for d in report.diagnostics
        ]
    )
