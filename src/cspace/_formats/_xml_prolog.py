"""The prolog of an XML file, read as XML reads it: where its root element begins.

Past a byte order mark (a UTF-16 or UTF-32 file, told by its mark or by ``<?`` so
encoded, is read in its characters, as UTF-8), white space, comments, processing
instructions and a document type, whose internal subset is read past its quoted
literals, comments and processing instructions (each may hold ``]`` and ``>``). The
prolog is read on in chunks that double, up to the robot file's size cap; one longer,
or of more than `MAX_SCANNED_TAGS` constructs, leaves the root `UNDECIDED`.
"""

from __future__ import annotations

import codecs
import re
from typing import Protocol

PEEK_BYTES = 64 << 10
"""Bytes read of each file first, and read for its includes after its root's start tag."""

MAX_FILE_BYTES = 64 << 20
"""How far a prolog or a library is read: the robot file's size cap (`xmlio.MAX_FILE_BYTES`)."""

MAX_SCANNED_TAGS = 250_000
"""Most constructs (tags, comments, CDATA sections, processing instructions) looked at in
one file (the reader's own bound, `xmlio.MAX_TAGS`); a xacro file with more is taken for
a robot, and so is a file whose prolog has more, whose reader then refuses it."""

UNDECIDED = "?"
"""The root of a file that may be a robot description, but not one XML reads whole (its
prolog goes on past `MAX_FILE_BYTES`, or only tinyxml2 finds a robot's root in it):
inspected, never dropped."""

_NAME_BYTES = rb"[A-Za-z_:\x80-\xff][\w.:\x80-\xff-]*"
"""XML's names, read in bytes: any byte from 0x80 up stands for a letter."""
_NAME = re.compile(_NAME_BYTES)
_SPACE = re.compile(rb"\s*")
_DECLARATION = re.compile(rb"[\"'\[>]")
_SUBSET = re.compile(rb"[\"'\]]|<!--|<\?")
_ENCODINGS = (
    (b"\x00\x00\xfe\xff", "utf-32-be", 4),
    (b"\xff\xfe\x00\x00", "utf-32-le", 4),
    (b"\xfe\xff", "utf-16-be", 2),
    (b"\xff\xfe", "utf-16-le", 2),
    (b"\x00\x00\x00<", "utf-32-be", 0),
    (b"<\x00\x00\x00", "utf-32-le", 0),
    (b"\x00<\x00?", "utf-16-be", 0),
    (b"<\x00?\x00", "utf-16-le", 0),
    (b"\xef\xbb\xbf", "utf-8", 3),
)
"""How XML tells a file's encoding from its first bytes (its Appendix F): a byte order
mark (skipped), or ``<?`` encoded; UTF-8 with no mark."""


class Reader(Protocol):
    """What reads a file on."""

    def read(self, size: int, /) -> bytes:
        """Up to ``size`` more bytes (fewer only at the end)."""
        ...


def root_tag(data: bytes) -> str | None:
    """The root element's name in the bytes of an XML file (`UNDECIDED`, or None)."""
    text, head = utf8(_Bytes(data[PEEK_BYTES:]), data[:PEEK_BYTES])
    return root(text, head)[0]


class _Bytes:
    """Bytes read as a stream."""

    def __init__(self, data: bytes) -> None:
        self.data, self.at = data, 0

    def read(self, size: int, /) -> bytes:
        self.at += size
        return self.data[self.at - size : self.at]


class _Utf8:
    """A stream of an encoding read as UTF-8, past its byte order mark.

    ``read(n)`` gives ``n`` bytes but at the end, which comes at the latest past
    `MAX_FILE_BYTES` of the stream's own.
    """

    def __init__(self, stream: Reader, head: bytes, encoding: str) -> None:
        self.stream = stream
        self.decoder = codecs.getincrementaldecoder(encoding)("replace")
        self.buffer = self.decoder.decode(head).encode("utf-8")
        self.left = MAX_FILE_BYTES + 1 - len(head)
        self.ended = False

    def read(self, size: int, /) -> bytes:
        while len(self.buffer) < size and not self.ended:
            raw = self.stream.read(min(max(size - len(self.buffer), PEEK_BYTES), self.left))
            self.left -= len(raw)
            self.ended = not raw
            self.buffer += self.decoder.decode(raw, final=self.ended).encode("utf-8")
        out, self.buffer = self.buffer[:size], self.buffer[size:]
        return out


def utf8(stream: Reader, head: bytes) -> tuple[Reader, bytes]:
    """A file as UTF-8, past its byte order mark: what reads on, and its first bytes.

    Args:
        stream: What reads the file on, past ``head``.
        head: The file's first `PEEK_BYTES` (all of it, when fewer).
    """
    for start, encoding, mark in _ENCODINGS:
        if head.startswith(start):
            text = _Utf8(stream, head[mark:], encoding)
            return text, text.read(PEEK_BYTES)
    return stream, head


class _Budget:
    """The constructs a file's scans may still look at (`MAX_SCANNED_TAGS` in all)."""

    def __init__(self) -> None:
        self.left = MAX_SCANNED_TAGS

    def spend(self) -> bool:
        """Count one construct: False once there were too many."""
        self.left -= 1
        return self.left >= 0


def root(stream: Reader, head: bytes) -> tuple[str | None, bytes, bool]:
    """The root's name, the bytes from its start tag on, and whether they end the file.

    At least `PEEK_BYTES` bytes follow the root's ``<`` when the file has them. The
    prolog is read on in chunks that double, so that a long one is read in linear time.
    """
    data, at, read, chunk = head, 0, len(head), 0
    ended = len(head) < PEEK_BYTES
    budget = _Budget()
    while True:
        name, at = _prolog(data, at, ended, budget)
        if name is not None or at < 0:
            break
        if read > MAX_FILE_BYTES:
            return UNDECIDED, b"", ended
        chunk = min(max(2 * chunk, PEEK_BYTES), MAX_FILE_BYTES + 1 - read)
        more = stream.read(chunk)
        read += len(more)
        ended = len(more) < chunk
        data, at = data[at:] + more, 0
    if name is None or name == UNDECIDED:
        return name, b"", ended
    data = data[at:]
    if len(data) < PEEK_BYTES and not ended:
        more = stream.read(PEEK_BYTES - len(data))
        ended = len(more) < PEEK_BYTES - len(data)
        data += more
    return name, data, ended


def _prolog(data: bytes, at: int, ended: bool, budget: _Budget) -> tuple[str | None, int]:
    """Past the prolog from ``at``: (root name, where its ``<`` is).

    (None, -1): no root element there. (None, at): the prolog goes on past ``data``,
    which does not end the file: read on, and scan again from ``at``. (`UNDECIDED`,
    at): more constructs than the budget allows.
    """
    while True:
        space = _SPACE.match(data, at)
        at = space.end() if space else at
        if not ended and len(data) - at < 16:  # a construct may be cut: read on
            return None, at
        if not budget.spend():
            return UNDECIDED, at
        if data.startswith(b"<?", at):
            end = after(data, at + 2, b"?>")
        elif data.startswith(b"<!--", at):
            end = after(data, at + 4, b"-->")
        elif data.startswith(b"<!", at):
            end = _doctype_end(data, at + 2, budget)
        elif data.startswith(b"<", at):
            found = _NAME.match(data, at + 1)
            if found is None:
                return None, -1
            if found.end() == len(data) and not ended:  # the name may go on
                return None, at
            return found.group(0).decode("utf-8", "replace"), at
        else:
            return None, -1
        if end == -2:
            return UNDECIDED, at
        if end < 0:
            return (None, -1) if ended else (None, at)
        at = end


def after(data: bytes, at: int, close: bytes) -> int:
    """Past the first ``close`` from ``at``, or -1."""
    end = data.find(close, at)
    return end + len(close) if end >= 0 else -1


def _doctype_end(data: bytes, at: int, budget: _Budget) -> int:
    """Past ``<!...>`` from ``at`` (past its ``<!``), or -1 (not in ``data``), -2 (over budget).

    A quoted literal may hold ``>`` and ``[``; the internal subset (``[...]``) is read
    past its comments, processing instructions and quoted literals, which may hold ``]``.
    """
    while True:
        found = _DECLARATION.search(data, at)
        if found is None:
            return -1
        if found.group() == b">":
            return found.end()
        if found.group() != b"[":  # a quoted literal
            at = after(data, found.end(), found.group())
            if at < 0:
                return -1
            continue
        at = found.end()
        while True:  # the internal subset
            if not budget.spend():
                return -2
            item = _SUBSET.search(data, at)
            if item is None:
                return -1
            if item.group() == b"]":
                at = item.end()
                break
            close = {b"<!--": b"-->", b"<?": b"?>"}.get(item.group(), item.group())
            at = after(data, item.end(), close)
            if at < 0:
                return -1
