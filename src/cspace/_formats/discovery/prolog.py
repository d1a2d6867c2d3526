"""The prolog of an XML file, read as XML reads it: where its root element begins.

Past a byte order mark (a UTF-16 or UTF-32 file, told by its mark or by ``<?`` so
encoded, is read in its characters, as UTF-8), white space, comments, processing
instructions and a document type, whose internal subset is read past its quoted
literals, comments and processing instructions (each may hold ``]`` and ``>``). The
prolog is read on in chunks that double, up to the robot file's size cap, each
construct counted once (a document type cut where the bytes read end is read on from
where it was cut); one longer, or of more than `MAX_SCANNED_TAGS` constructs (quoted
literals and items of an internal subset among them), leaves the root `UNDECIDED`.
"""

import codecs
import re
from typing import Protocol

from cspace._record import NamedTuple

PEEK_BYTES = 64 << 10
"""Bytes read of each file first, and read for its includes after its root's start tag."""

MAX_FILE_BYTES = 64 << 20
"""How far a prolog or a library is read: the robot file's size cap
(`shared.xmlio.MAX_FILE_BYTES`)."""

MAX_SCANNED_TAGS = 250_000
"""Most constructs (tags, attributes or quoted values, comments, CDATA sections,
processing instructions, a document type's literals) looked at in each scan of a file
(the reader's own bound on tags, `shared.xmlio.MAX_TAGS`); a xacro file with more is taken for
a robot, and so is a file whose prolog has more, whose reader then refuses it."""

UNDECIDED = "?"
"""The root of a file that may be a robot description, but not one the search reads
whole (its prolog goes on past `MAX_FILE_BYTES`, only tinyxml2 or rapidxml finds a
robot's root in it, entities make its content): inspected, never dropped, no fragment."""

_NAME_BYTES = rb"[A-Za-z_:\x80-\xff][\w.:\x80-\xff-]*"
"""XML's names, read in bytes: any byte from 0x80 up stands for a letter."""
_NAME = re.compile(_NAME_BYTES)
_QUOTE_OR_END = re.compile(rb"[\"'>]")
ENTITY = re.compile(rb"&(?!(?:lt|gt|amp|apos|quot|#[0-9]+|#x[0-9a-fA-F]+);)")
"""An ``&`` that begins no reference but XML's five and character references."""
MARKUP = re.compile(rb"<(?:(!--)|(!\[CDATA\[)|(\?)|(/?)(" + _NAME_BYTES + rb"))")
"""What a scan of an element's content looks at: a comment, a CDATA section, a
processing instruction (groups 1 to 3, hidden), or a tag (group 4 ``/`` for an end tag,
group 5 its name)."""
HIDDEN_END = {1: b"-->", 2: b"]]>", 3: b"?>"}
"""What ends each hidden construct `MARKUP` finds, by its group."""
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
    return root(text, head).name


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


class Budget:
    """The constructs a scan may still look at, each counted once by its place in a file.

    A construct cut where the bytes read end is looked at again, not counted again.
    """

    def __init__(self, total: int = MAX_SCANNED_TAGS) -> None:
        self.left = total
        self.counted = -1  # the furthest place counted

    def spend(self, position: int) -> bool:
        """Count the construct at ``position`` in the file: False once over budget."""
        if position > self.counted:
            self.counted = position
            self.left -= 1
        return self.left >= 0


class Root(NamedTuple):
    """Where a file's root element begins (`root`).

    Attributes:
        name: The root's name (`UNDECIDED`, or None: no root element).
        data: The bytes from the root's ``<`` on (empty without a name).
        ended: Whether ``data`` ends the file.
        subset: Whether a document type with an internal subset (``[...]``) comes
            before the root (its entities and attribute defaults may change the document).
    """

    name: str | None
    data: bytes
    ended: bool
    subset: bool


def root(stream: Reader, head: bytes) -> Root:
    """Where the root element begins, past the prolog.

    At least `PEEK_BYTES` bytes follow the root's ``<`` when the file has them. The
    prolog is read on in chunks that double, so that a long one is read in linear time,
    and each construct of it is counted once against `MAX_SCANNED_TAGS`.
    """
    data, read, chunk = head, len(head), 0
    ended = len(head) < PEEK_BYTES
    prolog = _Prolog()
    while True:
        name, at = prolog.walk(data, ended)
        if name is not None or at < 0:
            break
        if read > MAX_FILE_BYTES:
            return Root(UNDECIDED, b"", ended, prolog.subset)
        chunk = min(max(2 * chunk, PEEK_BYTES), MAX_FILE_BYTES + 1 - read)
        more = stream.read(chunk)
        read += len(more)
        ended = len(more) < chunk
        data = data[at:] + more
        prolog.base += at
    if name is None or name == UNDECIDED:
        return Root(name, b"", ended, prolog.subset)
    data = data[at:]
    if len(data) < PEEK_BYTES and not ended:
        more = stream.read(PEEK_BYTES - len(data))
        ended = len(more) < PEEK_BYTES - len(data)
        data += more
    return Root(name, data, ended, prolog.subset)


class _Prolog:
    """A walk over the prolog, as far as the bytes read go."""

    def __init__(self) -> None:
        self.budget = Budget()
        self.base = 0  # where the bytes walked begin in the file
        self.subset = False
        self.cut: tuple[int, int, bool] | None = None  # a document type cut: where, from, subset

    def spend(self, at: int) -> bool:
        return self.budget.spend(self.base + at)

    def walk(self, data: bytes, ended: bool) -> tuple[str | None, int]:
        """Past the prolog that begins ``data``: (root name, where its ``<`` is).

        (None, -1): no root element there. (None, at): the prolog goes on past ``data``,
        which does not end the file: read on, and walk again from ``at``. (`UNDECIDED`,
        at): more constructs than the budget allows.
        """
        at = 0
        while True:
            space = _SPACE.match(data, at)
            at = space.end() if space else at
            if not ended and len(data) - at < 16:  # a construct may be cut: read on
                return None, at
            if not self.spend(at):
                return UNDECIDED, at
            if data.startswith(b"<?", at):
                end = after(data, at + 2, b"?>")
            elif data.startswith(b"<!--", at):
                end = after(data, at + 4, b"-->")
            elif data.startswith(b"<!", at):
                end = self.doctype_end(data, at)
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

    def doctype_end(self, data: bytes, start: int) -> int:
        """Past ``<!...>`` at ``start``: -1, not in ``data``; -2, over budget.

        A quoted literal may hold ``>`` and ``[``; the internal subset (``[...]``) is read
        past its comments, processing instructions and quoted literals, which may hold
        ``]``. Each literal and each item of the subset counts against the budget. One
        cut where ``data`` ends is read on, once more bytes are read, from where it was
        cut: the bytes before are not walked again.
        """
        at, subset = start + 2, False
        if self.cut is not None and self.cut[0] == self.base + start:
            at, subset = self.cut[1] - self.base, self.cut[2]
        self.cut = None
        while True:
            found = (_SUBSET if subset else _DECLARATION).search(data, at)
            if found is None:
                return self.cut_at(start, at, subset)
            mark = found.group()
            if mark == b">":
                return found.end()
            if not self.spend(found.start()):
                return -2
            if mark in (b"[", b"]"):
                subset = mark == b"["
                self.subset = self.subset or subset
                at = found.end()
                continue
            at = after(data, found.end(), {b"<!--": b"-->", b"<?": b"?>"}.get(mark, mark))
            if at < 0:  # a literal, comment or processing instruction cut
                return self.cut_at(start, found.start(), subset)

    def cut_at(self, start: int, at: int, subset: bool) -> int:
        """Where the document type at ``start``, cut, is to be read on from: -1."""
        self.cut = (self.base + start, self.base + at, subset)
        return -1


def after(data: bytes, at: int, close: bytes) -> int:
    """Past the first ``close`` from ``at``, or -1."""
    end = data.find(close, at)
    return end + len(close) if end >= 0 else -1


def tag_end(text: bytes, at: int, budget: Budget) -> int:
    """Where the tag that goes on at ``at`` ends: past its ``>``, not one in a value.

    -1: not in ``text``; -2: more quoted values than ``budget`` allows.
    """
    while True:
        found = _QUOTE_OR_END.search(text, at)
        if found is None:
            return -1
        if found.group() == b">":
            return found.end()
        if not budget.spend(found.start()):
            return -2
        close = text.find(found.group(), found.end())
        if close < 0:
            return -1
        at = close + 1
