"""A count on standard error while a long command runs, when a person is watching.

Shown only when standard error is a terminal (never in a pipe, a file or a CI log),
and only once the work has taken more than a second (``CSPACE_PROGRESS``: another
delay in seconds, or ``off``). tqdm draws it, imported only then. It shows counts
(files, rows), never what a file says; it is cleared when the work ends, and messages
written while it shows go around it (`Progress.paused`).
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time
from collections.abc import Iterable, Iterator, Sized
from typing import Any, TypeVar

DELAY = 1.0
"""Seconds of work before the count appears (short runs show nothing)."""

_T = TypeVar("_T", bound=Sized)


def _delay() -> float | None:
    """The delay ``CSPACE_PROGRESS`` asks for (default `DELAY`); None: no count."""
    asked = os.environ.get("CSPACE_PROGRESS", "").strip().lower()
    if not asked:
        return DELAY
    if asked in ("off", "no", "false", "never"):
        return None
    try:
        delay = float(asked)
    except ValueError:
        return DELAY
    return delay if math.isfinite(delay) and delay >= 0 else DELAY


class Progress:
    """A count of ``total`` things (``unit``: ``file``, ``row``) on a terminal's stderr.

    Nothing is drawn, and tqdm is not imported, until the work has taken the delay:
    a short run leaves the terminal as it was.

    Args:
        total: How many there will be.
        unit: What is counted, singular.
        shown: False to show nothing (the work's output goes to the same terminal).
    """

    def __init__(self, total: int, unit: str, *, shown: bool = True) -> None:
        self._bar: Any = None
        self._total, self._unit, self._done = total, unit, 0
        delay = _delay()
        self._delay = delay if shown and sys.stderr.isatty() else None
        self._start = time.monotonic()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def update(self, done: int = 1) -> None:
        """``done`` more are done."""
        self._done += done
        if self._bar is not None:
            self._bar.update(done)
        elif self._delay is not None and time.monotonic() - self._start >= self._delay:
            from tqdm import tqdm

            self._bar = tqdm(
                total=self._total,
                initial=self._done,
                unit=self._unit,
                unit_scale=self._total >= 10_000,  # 1.2M/100M rows; 12/385 files
                leave=False,
                file=sys.stderr,
                dynamic_ncols=True,
            )

    def counted(self, chunks: Iterable[_T]) -> Iterator[_T]:
        """``chunks`` as they come, each counted (its length) once it has been used."""
        for chunk in chunks:
            yield chunk
            self.update(len(chunk))

    @contextlib.contextmanager
    def paused(self) -> Iterator[None]:
        """The count taken off the terminal while a message is written, then redrawn."""
        if self._bar is None:
            yield
            return
        self._bar.clear()
        try:
            yield
        finally:
            self._bar.refresh()

    def close(self) -> None:
        """Take the count off the terminal."""
        if self._bar is not None:
            self._bar.close()
            self._bar = None
