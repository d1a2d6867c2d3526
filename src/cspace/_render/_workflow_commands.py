"""GitHub workflow commands made safe: an annotation no robot file can end or add to.

``::error file=F,line=N,title=T::MESSAGE`` (``warning``, ``notice`` for info). The text
is escaped as cspace escapes every output (`printable`: control, C1 and bidi characters
shown as escapes, ``::`` at the start and ``##[`` neutralised) and then by the
workflow-command rules: ``%``, CR and LF percent-encoded in the message, and ``:`` and
``,`` too in the properties, so that no robot file can end the command and start one of
its own in the log that runs it. The ``file`` property keeps the path as it is (but its
control characters), so that the annotation lands on the file: its ``:`` are
percent-encoded, and a ``##[`` in it is part of cspace's command, which the runner reads
first (a line is read in the older syntax only when it is no command of the new one).
Shared by every command's annotations (`cspace._render.annotations`,
`cspace._render._collisions_github`).
"""

from cspace._findings import Severity
from cspace._safetext import printable

COMMAND = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}
"""A finding's command by its severity (info is a ``notice``)."""


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
