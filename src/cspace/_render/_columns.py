"""Text columns and finding locations, shared by the text renderers of every command."""

from collections.abc import Sequence

from cspace._findings import Diagnostic
from cspace._safetext import printable

__all__ = ["location", "table"]

MIN_COLUMN = 6
"""Narrowest a column is shortened to when a table must fit a terminal."""


def _fit(widths: list[int], width: int | None) -> list[int]:
    """Column widths within ``width`` characters: the widest column shrinks first."""
    widths = list(widths)
    if width is None:
        return widths
    while sum(widths) + 2 * (len(widths) - 1) > width:
        widest = max(range(len(widths)), key=lambda i: widths[i])
        if widths[widest] <= MIN_COLUMN:
            break  # narrower than this, a table says nothing: let the terminal wrap it
        widths[widest] -= 1
    return widths


def _cell(text: str, width: int, keep_end: bool = False) -> str:
    if len(text) <= width:
        return text
    return "…" + text[len(text) - width + 1 :] if keep_end else text[: width - 1] + "…"


def table(
    header: Sequence[str],
    rows: Sequence[Sequence[str]],
    width: int | None = None,
    keep_end: Sequence[int] = (),
) -> list[str]:
    """Left-aligned columns separated by two spaces, header underlined.

    With ``width`` (a terminal's columns), the widest columns are shortened until each
    line fits, a cut cell ending in ``…`` (starting with it for the columns in
    ``keep_end``, such as file paths, whose end says most): a row never breaks.
    """
    full = [
        max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(header)
    ]
    widths = _fit(full, width)

    def line(cells: Sequence[str]) -> str:
        padded = (
            _cell(c, w, i in keep_end).ljust(w)
            for i, (c, w) in enumerate(zip(cells, widths, strict=True))
        )
        return "  ".join(padded).rstrip()

    return [line(header), line(["-" * w for w in widths]), *(line(r) for r in rows)]


def location(d: Diagnostic) -> str | None:
    """``line N``, ``FILE:N`` for a finding in another file (an SRDF), or None."""
    if d.file is not None:
        name = printable(d.file.replace("\\", "/").rsplit("/", 1)[-1], limit=80)
        return f"{name}:{d.line}" if d.line is not None else name
    return None if d.line is None else f"line {d.line}"
