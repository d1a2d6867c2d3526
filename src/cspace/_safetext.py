r"""Text that is safe to show: on a terminal, in a CI log, in a pull-request comment.

Robot files and saved reports are untrusted, and what they name ends up in every output.
A name can hold ANSI escape sequences that recolour or rewrite a terminal, OSC 8
hyperlinks, carriage returns and line breaks that forge lines, C1 controls (U+009B is
CSI on some terminals), bidirectional controls that make text read otherwise than its
bytes (U+202E, U+2066), and invisible zero-width characters.

One rule, here and nowhere else: every character that `str.isprintable` rejects
(C0 and C1 controls, DEL, format characters such as bidi controls and zero-width
characters, line and paragraph separators, unassigned code points, surrogates, every
space but U+0020) is escaped. Human-readable text gets Python's escapes (``\x1b``,
``\u202e``) by `printable`; JSON gets JSON's (``\u001b``, ``\u202e``) by
`json_text`, so that the JSON value is exactly the original text while its bytes
are safe. Both are deterministic: the same text gives the same bytes.

Any output may end up in a CI log, where GitHub's runner acts on a line that starts,
after white space, with ``::`` (``::error::``, ``::add-mask::``, ``::stop-commands::``)
and on ``##[`` anywhere in a line (its older syntax). So `printable` and `json_text`
also neutralise both (`no_commands`): a leading ``::`` becomes ``\x3a:`` and ``##[``
becomes ``##\x5b`` (``##\u005b`` in JSON, whose value is unchanged). The only workflow
commands cspace writes are its own annotations (``--format github``).
"""

from __future__ import annotations

import json
import json.encoder
import math
import re
from collections.abc import Callable
from typing import Any

MAX_PROBLEM_CHARS = 600
"""Longest text `printable` keeps by default; longer ones (a file's huge names or
values quoted in full) are shortened in the middle."""

_MARKER_CHARS = 40
"""Room left for the `` ... (N characters) ... `` marker of shortened text."""


_COMMAND_START = r"(\A|[\r\n])([^\S\r\n]*):(?=:)"  # compiled on first use (re's cache)
"""A line's first ``:`` when ``::`` starts it after white space (the runner splits lines
at CR and LF, and trims .NET's white space, which Python's white space covers)."""


def no_commands(text: str) -> str:
    r"""``text`` with no line a CI runner would read as a workflow command.

    A ``::`` that starts a line, after white space, gets its first colon escaped
    (``\x3a:error::``), and every ``##[`` its bracket (``##\x5b``): a reader still sees
    what was there, GitHub's runner sees no command. Idempotent; text without ``::``
    or ``##[`` is returned as is.
    """
    if "##[" in text:
        text = text.replace("##[", "##\\x5b")
    if "::" in text:
        text = re.sub(_COMMAND_START, r"\1\2\\x3a", text)
    return text


def _python_escape(ch: str) -> str:
    code = ord(ch)
    if 0xDC80 <= code <= 0xDCFF:  # a byte of a name that is not UTF-8 (surrogateescape)
        return f"\\x{code - 0xDC00:02x}"
    return ascii(ch)[1:-1]


def _json_escape(ch: str) -> str:
    code = ord(ch)
    if code <= 0xFFFF:
        return f"\\u{code:04x}"
    code -= 0x10000  # as JSON writes it: a UTF-16 surrogate pair
    return f"\\u{0xD800 + (code >> 10):04x}\\u{0xDC00 + (code & 0x3FF):04x}"


class _Table(dict[int, str]):
    """A `str.translate` table, built as characters are met.

    Printable characters map to themselves, the others to their escape; once warm,
    escaping runs at C speed.
    """

    def __init__(self, escape: Callable[[str], str]) -> None:
        super().__init__()
        self.escape = escape

    def __missing__(self, code: int) -> str:
        ch = chr(code)
        self[code] = value = ch if ch.isprintable() else self.escape(ch)
        return value


_TABLES: dict[Callable[[str], str], _Table] = {}


def _escape(text: str, escape: Callable[[str], str]) -> str:
    """``text`` with every character `str.isprintable` rejects replaced by ``escape``."""
    if text.isprintable():  # the usual case, checked at C speed
        return text
    table = _TABLES.get(escape)
    if table is None:
        table = _TABLES[escape] = _Table(escape)
    return text.translate(table)


def printable(
    text: str, *, limit: int | None = MAX_PROBLEM_CHARS, commands_kept: bool = False
) -> str:
    """``text`` as one printable line: unprintable characters escaped, shortened if huge.

    Every renderer passes what a file says through this (names, paths, messages). A
    character reference such as ``&#10;`` puts a line break in a name, which must not
    break the one-line rule; ``&#x1b;`` an escape sequence, which must not reach a terminal.

    Args:
        text: Any text.
        limit: Longest result; longer text keeps its start and end around a marker that
            says how many characters were left out. None keeps everything.
        commands_kept: Leave ``::`` and ``##[`` as they are: only for a property of
            cspace's own workflow command (an annotation's ``file``, which must name the
            file), whose line the runner reads as that command and nothing else.

    Returns:
        Text in which every character is printable (``str.isprintable()``) and no
        workflow command (`no_commands`). Applying it again changes nothing.
    """
    if limit is not None and len(text) > 4 * limit:  # cut before escaping: huge texts
        half = limit // 2  # an escape is at most 10 characters; the result is cut again
        text = f"{text[:half]} ... ({len(text) - 2 * half:,} characters) ... {text[-half:]}"
    escaped = _escape(text, _python_escape)
    if limit is not None and len(escaped) > limit:
        half = max(limit - _MARKER_CHARS, 2) // 2
        skipped = len(escaped) - 2 * half
        escaped = f"{escaped[:half]} ... ({skipped:,} characters) ... {escaped[-half:]}"
    return escaped if commands_kept else no_commands(escaped)


def json_text(value: Any, *, indent: int | None = None) -> str:
    r"""``value`` as JSON text whose characters are all printable (or a line break).

    Like ``json.dumps(value, ensure_ascii=False, allow_nan=False)`` (readable UTF-8, keys
    in their order), except that every character `str.isprintable` rejects is
    written as a ``\uXXXX`` escape: ``json.loads`` gives back exactly ``value``, and the
    bytes carry no control, C1, bidi or zero-width character. Line breaks appear only
    between tokens (with ``indent``); inside strings JSON escapes them.

    Args:
        value: A JSON-able value without NaN or infinities.
        indent: Spaces per level, or None for one line.

    Raises:
        ValueError: ``value`` holds a NaN or an infinity.
    """
    if indent is None:
        text = json.dumps(value, ensure_ascii=False, allow_nan=False)  # NumPy's C encoder
    else:
        try:
            text = _indented(value, indent)
        except (TypeError, RecursionError):  # json.dumps converts it, or says why
            text = json.dumps(value, indent=indent, ensure_ascii=False, allow_nan=False)
    if not text.replace("\n", "").isprintable():  # one pass in C for the usual clean text
        text = "\n".join(_escape(line, _json_escape) for line in text.split("\n"))
    # ``#`` stands only inside strings in JSON, and no JSON line starts with ``::``
    return text.replace("##[", "##\\u005b") if "##[" in text else text


def _indented(value: Any, indent: int) -> str:
    """``json.dumps(value, indent=indent, ensure_ascii=False, allow_nan=False)``, faster.

    The standard library encodes with an indent in pure Python, through generators; this
    walk of dicts (string keys), lists, tuples, strings, numbers, bools and None gives
    the same bytes in about half the time (tested against json.dumps). Anything else
    raises TypeError.
    """
    parts: list[str] = []
    put = parts.append
    string = json.encoder.encode_basestring  # C, as json.dumps uses with ensure_ascii=False
    spaces = " " * indent

    def walk(item: Any, pad: str) -> None:
        kind = type(item)
        if kind is str:
            put(string(item))
        elif kind is dict:
            if not item:
                put("{}")
                return
            inner = pad + spaces
            separator = "{" + inner
            for key, child in item.items():
                if type(key) is not str:
                    raise TypeError("a key that is not a string")
                if type(child) is str:  # the commonest leaf, without a call
                    put(separator + string(key) + ": " + string(child))
                else:
                    put(separator + string(key) + ": ")
                    walk(child, inner)
                separator = "," + inner
            put(pad + "}")
        elif kind is list or kind is tuple:
            if not item:
                put("[]")
                return
            inner = pad + spaces
            separator = "[" + inner
            for child in item:
                if type(child) is str:
                    put(separator + string(child))
                else:
                    put(separator)
                    walk(child, inner)
                separator = "," + inner
            put(pad + "]")
        elif kind is float:
            if item != item or item in (math.inf, -math.inf):
                raise ValueError(f"Out of range float values are not JSON compliant: {item!r}")
            put(float.__repr__(item))
        elif kind is int:
            put(int.__repr__(item))
        elif item is None or kind is bool:
            put("null" if item is None else "true" if item else "false")
        else:
            raise TypeError(f"{kind.__name__} is not a plain JSON value")

    walk(value, "\n")
    return "".join(parts)
