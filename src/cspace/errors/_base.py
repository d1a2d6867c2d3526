"""The root of every `cspace` exception, and of every problem with a robot file."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from cspace._safetext import printable


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``known`` to a misspelt ``name``, or ``""``.

    Used by every "unknown name" message (links, mimic leaders, joint types, ``erd:``
    names). difflib is imported only on this error path; past 10,000 candidates no
    suggestion is worth a slow error.
    """
    candidates = list(known)
    if len(candidates) > 10_000:
        return ""
    import difflib

    close = difflib.get_close_matches(name, candidates, n=1, cutoff=0.75)
    return f" (did you mean '{close[0]}'?)" if close else ""


class CspaceError(Exception):
    """Root of every error raised by `cspace`.

    Attributes:
        code: A stable short identifier of the kind of error; every subclass has its own.
        message_chars: Most characters of the one line the command line prints (what a
            file says is cut to fit; an error whose message is cspace's own may say more).
    """

    code = "cspace"
    message_chars = 600

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle as class, message and attributes (subclasses' ``__init__`` differ).

        Errors cross process boundaries: `cspace.inspect_many` on a process pool
        or a cluster sends each file's error back to the caller.
        """
        return (_restore, (type(self), self.args, dict(self.__dict__)))


def _restore(cls: type[CspaceError], args: tuple[Any, ...], state: dict[str, Any]) -> CspaceError:
    """An error of class ``cls`` with these ``args`` and attributes, ``__init__`` not run."""
    error = cls.__new__(cls)
    error.args = args
    error.__dict__.update(state)
    return error


class RobotFileError(CspaceError):
    """A robot file cannot be turned into a model.

    Attributes:
        path: The file, as the caller named it.
        line: 1-based line number of the offending element, or None when unknown.
        element: Name of the offending joint or link (or XML tag), or None.
        problem: What is wrong, without the location, as one printable line (see
            `printable`).
        code: A stable short identifier of the kind of problem, e.g. ``"missing-link"``;
            each subclass has its own, and a caller may give a more specific one.
    """

    code = "robot-file"

    def __init__(
        self,
        path: str,
        problem: str,
        *,
        line: int | None = None,
        element: str | None = None,
        code: str | None = None,
    ) -> None:
        if code is not None:
            self.code = code
        self.path = path
        self.problem = printable(problem)
        self.line = line
        self.element = element
        super().__init__(self._one_line())

    def _one_line(self) -> str:
        path = printable(self.path)  # a file name can hold anything but NUL and /
        where = path if self.line is None else f"{path}:{self.line}"
        return f"{where}: {self.problem}"


MAX_PROBLEMS = 100
"""Most problems of one robot file reported in one run (the last says how many more)."""


class RobotFileErrors(RobotFileError):
    """Several problems in one robot file, all found in one run (in file order).

    It reads as its first problem (``path``, ``line``, ``element``, ``problem`` and
    ``code`` are the first's); ``errors`` holds every one, so that a reviewer sees all
    of them at once instead of one per run.

    At most `MAX_PROBLEMS` are kept: a hostile file of 5,000 broken joints gets the
    first 99 and one line that says how many more there were, not 5,000 lines.

    Attributes:
        errors: Each problem, in file order (by line).
    """

    code = "several-problems"  # an instance carries its first problem's code

    def __init__(self, errors: Sequence[RobotFileError]) -> None:
        ordered = sorted(errors, key=lambda e: (e.line is None, e.line or 0))
        if len(ordered) > MAX_PROBLEMS:
            left = len(ordered) - (MAX_PROBLEMS - 1)
            more = RobotFileError(
                ordered[0].path, f"{left:,} more problems are not listed", code="more-problems"
            )
            ordered = [*ordered[: MAX_PROBLEMS - 1], more]
        self.errors = tuple(ordered)
        first = ordered[0]
        super().__init__(
            first.path, first.problem, line=first.line, element=first.element, code=first.code
        )

    @staticmethod
    def of(errors: Sequence[RobotFileError]) -> RobotFileError:
        """The one error, or the errors together when there are several."""
        flat = [
            e
            for err in errors
            for e in (err.errors if isinstance(err, RobotFileErrors) else (err,))
        ]
        return flat[0] if len(flat) == 1 else RobotFileErrors(flat)


class NotationError(CspaceError, ValueError):
    """A written C-space cannot be read.

    Attributes:
        text: The text given.
    """

    code = "bad-notation"

    def __init__(self, text: str, problem: str) -> None:
        self.text = text
        super().__init__(f"cannot read the C-space '{text}': {problem}")
