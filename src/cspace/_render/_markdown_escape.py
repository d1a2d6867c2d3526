"""Markdown's escaping of what a file says: code spans, plain cells, tables with pipes escaped.

What a file says (names, paths, messages) is first made printable (`printable`: no line
break, no control or bidi character), then set in a code span, where Markdown reads
nothing: no HTML, no link or autolink, no @mention, no emphasis. Text made only of the
characters of cspace's own values (``R^2 × S^1``, ``[-2, 2] rad``, ``q 1..2, v 1``)
stays plain. In a table every pipe is escaped, the one character a code span does not
protect there. Shared by every Markdown cspace writes (`cspace._render.markdown`, the
report of ``cspace collisions``).
"""

import re
from collections.abc import Sequence

from cspace._safetext import MAX_PROBLEM_CHARS, printable

_PLAIN = re.compile(r"[A-Za-z0-9 ^×().,;'/\[\]+=-]*")
"""What cspace's own values are made of: nothing Markdown gives a meaning to..."""
_LINK = re.compile(r"\]\(|www\.", re.IGNORECASE)
"""...unless it spells a link (``[a](b)``) or an autolink (``www.example.com``)."""
_BACKTICKS = re.compile(r"`+")


def code(text: str) -> str:
    """``text`` as a code span: printable, between more backticks than it has in a row."""
    text = printable(text)
    fence = "`" * (1 + max((len(run) for run in _BACKTICKS.findall(text)), default=0))
    # A space or backtick at an end needs a space of padding: Markdown strips one each side.
    edges = text[:1] + text[-1:]
    pad = " " if text.strip(" ") and ("`" in edges or " " in edges) else ""
    return f"{fence}{pad}{text or ' '}{pad}{fence}"


def cell(text: str) -> str:
    """``text`` as is when Markdown would read nothing into it, else as a code span."""
    if len(text) <= MAX_PROBLEM_CHARS and _PLAIN.fullmatch(text) and not _LINK.search(text):
        return text
    return code(text)


def md_table(
    header: Sequence[str], rows: Sequence[Sequence[str]], code_columns: Sequence[int] = ()
) -> list[str]:
    """A Markdown table of raw values; ``code_columns`` are set in code (unless ``-``).

    Every other cell goes through `cell`, and every pipe is escaped.
    """

    def line(cells: Sequence[str]) -> str:
        return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"

    body = [
        [code(c) if i in code_columns and c != "-" else cell(c) for i, c in enumerate(row)]
        for row in rows
    ]
    return [line(header), line(["---"] * len(header)), *(line(r) for r in body)]
