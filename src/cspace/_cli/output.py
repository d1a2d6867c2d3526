"""Writing to the terminal: colour only for a terminal, ``NO_COLOR`` respected.

What is written comes from the library's renderers, which escape whatever a file says
(`_safetext`); errors are escaped here, the messages of every error alike. Whatever
reaches standard output or standard error goes through `no_commands` once more, whole,
so that no line of it is a workflow command in a CI log, however its parts were put
together; only `write_commands` writes cspace's own (``--format github``).
"""

from __future__ import annotations

import os
import sys
from typing import TextIO

from cspace._safetext import MAX_PROBLEM_CHARS, no_commands, printable


def use_color(choice: str, stream: TextIO = sys.stdout) -> bool:
    """Whether to colour output written to ``stream``.

    Args:
        choice: ``"always"``, ``"never"`` or ``"auto"`` (a terminal, no ``NO_COLOR``,
            and ``TERM`` is not ``dumb``).
        stream: The stream the output goes to.
    """
    if choice != "auto":
        return choice == "always"
    if os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("TERM") == "dumb":
        return False
    return stream.isatty()


def width(given: int | None, stream: TextIO = sys.stdout) -> int | None:
    """The columns to fit text into: ``given``, else ``COLUMNS``, else a terminal's width.

    ``COLUMNS`` is honoured in a pipe too (a CI job sets it for its log, which is no
    terminal); a value that is not a whole number from 1 to 100,000 is ignored. Without
    either, text written to a pipe is not fitted (None).
    """
    if given is not None:
        return max(given, 20)
    columns = os.environ.get("COLUMNS", "").strip().lstrip("0")
    if columns.isascii() and columns.isdigit() and len(columns) <= 6 and int(columns) <= 100_000:
        return max(int(columns), 20)
    if not stream.isatty():
        return None
    return terminal_columns()


def terminal_columns() -> int:
    """The columns of the terminal, as ``shutil.get_terminal_size`` gives them.

    ``COLUMNS`` when it is a positive number, else standard output's terminal, else 80;
    without shutil's imports (6 ms of every start-up).
    """
    try:
        columns = int(os.environ.get("COLUMNS", ""))
    except ValueError:
        columns = 0
    if columns > 0:
        return columns
    stdout = sys.__stdout__
    try:
        return (os.get_terminal_size(stdout.fileno()).columns if stdout else 0) or 80
    except (AttributeError, ValueError, OSError):
        return 80


def write(text: str) -> None:
    """Write ``text`` to standard output, ending it with one newline, no workflow command."""
    _out(no_commands(text))


def write_commands(text: str) -> None:
    """Write cspace's own workflow commands (``--format github``) to standard output.

    Their properties and messages are escaped where they are made
    (`cspace._render.annotations`); the lines are written as they are.
    """
    _out(text)


def _out(text: str) -> None:
    r"""``text`` and a newline on standard output; a character it cannot encode escaped.

    Renderers escape what a file names, a name that is not UTF-8 included (its bytes,
    ``\xff``); should one slip through, it is written escaped rather than abort the
    output of every other file.
    """
    text = text if text.endswith("\n") else text + "\n"
    try:
        sys.stdout.write(text)
    except UnicodeEncodeError:
        encoding = sys.stdout.encoding or "utf-8"
        sys.stdout.write(text.encode(encoding, "backslashreplace").decode(encoding))


def error(message: str, limit: int = MAX_PROBLEM_CHARS) -> None:
    """Write a one-line error to standard error, every unprintable character escaped."""
    sys.stderr.write(no_commands(f"cspace: error: {printable(message.strip(), limit=limit)}\n"))


def finding(severity: str, message: str) -> None:
    """Write ``cspace: <severity>: <message>`` (a finding that fails the run), escaped."""
    line = f"cspace: {severity}: {printable(message.strip(), limit=MAX_PROBLEM_CHARS)}\n"
    sys.stderr.write(no_commands(line))


def check_failed(message: str) -> None:
    """Write the one line of a failed ``cspace check`` to standard error, escaped."""
    sys.stderr.write(no_commands(f"cspace: check failed: {printable(message)}\n"))


def note(message: str, limit: int = MAX_PROBLEM_CHARS) -> None:
    """Write ``cspace: note: <message>`` to standard error: said, not an error."""
    sys.stderr.write(no_commands(f"cspace: note: {printable(message, limit=limit)}\n"))
