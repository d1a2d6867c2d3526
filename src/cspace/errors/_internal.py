"""A bug met while one file was handled, reported as that file's error."""

from __future__ import annotations

from typing import Literal

from cspace._safetext import printable
from cspace.errors._base import CspaceError

Stage = Literal["inspect", "then", "return"]
"""Where an `InternalError` happened (see its ``stage``)."""

MAX_TRACEBACK_CHARS = 20_000
"""Longest traceback an `InternalError` keeps (a deep recursion's is far longer);
a longer one keeps its start and end."""

_WHERE: dict[str, tuple[str, str]] = {
    "inspect": ("", "a bug in cspace"),
    "then": (" in then", "a bug in the then function or in cspace"),
    "return": (" sending the result back", "a bug in the then function or in cspace"),
}
"""Each stage's words in the message: where, and whose bug it is."""


class InternalError(CspaceError):
    """An unexpected exception while one file was handled: a bug, not a fault of the file.

    `cspace.inspect_many` (and ``cspace inspect`` on several files) makes any
    exception that is not a `CspaceError` (a ``RecursionError``, a
    ``MemoryError``, a parser's ``ValueError``, ...) that file's error, so that the
    other files still get their reports: raised while the file was inspected, while
    ``then`` ran on its report, or while its result was pickled in the worker (or
    unpickled in the caller). ``KeyboardInterrupt`` and ``SystemExit`` are not caught:
    they still stop the run. It pickles, as every error does, its traceback as text.

    ``str(error)`` is one line that names the file, e.g. ``deep.xml: internal error:
    RecursionError: maximum recursion depth exceeded (a bug in cspace; run with --debug
    for the traceback)``.

    Attributes:
        path: The file, as the caller named it.
        stage: Where it happened: ``"inspect"`` (reading and analysing the file),
            ``"then"`` (the ``then`` function on its report) or ``"return"`` (pickling
            its result in the worker, or unpickling it in the caller).
        exception_type: The exception's class, with its module unless a built-in, e.g.
            ``"RecursionError"`` or ``"lxml.etree.XMLSyntaxError"``.
        exception_message: What the exception said, as one printable line (shortened
            if huge; see `printable`).
        traceback: The exception's traceback, formatted where it was raised (in the
            worker process), at most `MAX_TRACEBACK_CHARS` characters; ``""`` when
            unknown. ``cspace --debug`` prints it.
    """

    code = "internal-error"

    def __init__(
        self,
        path: str,
        exception_type: str,
        exception_message: str,
        *,
        stage: Stage = "inspect",
        traceback: str = "",
    ) -> None:
        where, whose = _WHERE.get(stage, _WHERE["inspect"])
        self.path = path
        self.stage = stage
        self.exception_type = printable(exception_type)
        self.exception_message = printable(exception_message)
        self.traceback = traceback
        said = self.exception_type + (f": {self.exception_message}" if exception_message else "")
        super().__init__(
            f"{printable(path)}: internal error{where}: {said} "
            f"({whose}; run with --debug for the traceback)"
        )

    @classmethod
    def of(cls, path: str, exc: BaseException, stage: Stage = "inspect") -> InternalError:
        """The error of ``exc``, raised while ``path`` was handled (call it where caught).

        Args:
            path: The file, as the caller named it.
            exc: The exception.
            stage: Where it happened (see the class's ``stage``).
        """
        import traceback

        kind = type(exc)
        name = kind.__qualname__
        if kind.__module__ != "builtins":
            name = f"{kind.__module__}.{name}"
        try:
            message = str(exc)
        except Exception:  # a broken __str__ must not hide the error it describes
            message = "(its message cannot be shown)"
        try:
            text = "".join(traceback.format_exception(exc))
        except Exception:
            text = ""
        if len(text) > MAX_TRACEBACK_CHARS:
            half = MAX_TRACEBACK_CHARS // 2
            cut = len(text) - 2 * half
            text = f"{text[:half]}\n... ({cut:,} characters left out) ...\n{text[-half:]}"
        return cls(path, name, message, stage=stage, traceback=text)
