"""Whether rapidxml, Pinocchio's MJCF parser, finds a top-level ``<mujoco>`` in a file.

Pinocchio reads MJCF with boost's property_tree, which parses with rapidxml, and takes
the first top-level ``<mujoco>`` element wherever it stands (``<a/><b/><mujoco>``).
rapidxml takes less than tinyxml2 before and between the top-level elements (white
space only: no text, no white space after a ``<``, no end tag), and more elsewhere: an
end tag closes the element open whatever its name (``</>`` too), an attribute may be
given twice, a declaration or a processing instruction may stand anywhere, a name is
any bytes but white space, ``/``, ``>`` and ``?`` (an attribute's, nor ``<``, ``=``,
``!``), and a document type ends at the first ``>`` past the ``]`` that balances its
``[`` (quotes are not read). It refuses an element left open, an attribute without a
quoted value, a comment, CDATA section, declaration or ``<!...>`` left open; it reads
the file up to its first NUL byte (`discovery._tiny` ends the bytes there).

The parse goes on only while a ``<mujoco`` lies ahead (`Ahead`), so that a file without
one is decided by a search, and looks at most at a budget of constructs (tags,
attributes, comments, brackets of a document type): a file with more, and a
``<mujoco`` ahead, is taken for a robot, whose reader then refuses it.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Protocol

from cspace._formats.discovery.prolog import Budget

__all__ = ["Ahead", "Rapid", "ReadAt", "Scan"]

ReadAt = Callable[[int, int], bytes]
"""Reads up to that many bytes of a file from that offset (fewer only at its end)."""

_YES, _NO, _MORE = "yes", "no", "more"

_SPACE = re.compile(rb"[ \t\n\r]*")
"""rapidxml's white space."""
_NAME = re.compile(rb"[^ \t\n\r/>?]+")
_ATTRIBUTE = re.compile(rb"[^ \t\n\r/<>=?!]+[ \t\n\r]*=[ \t\n\r]*(?:\"[^\"]*\"|'[^']*')[ \t\n\r]*")
_ATTRIBUTE_CUT = re.compile(rb"[^ \t\n\r/<>=?!]+[ \t\n\r]*(?:=[ \t\n\r]*(?:\"[^\"]*|'[^']*)?)?")
_END_TAG = re.compile(rb"</[^ \t\n\r/>?]*[ \t\n\r]*(>)?")
_BRACKET = re.compile(rb"[\[\]>]")
_MUJOCO = re.compile(rb"<mujoco(?![^ \t\n\r/>?])")
_DOCTYPE = re.compile(rb"<!DOCTYPE[ \t\n\r]")
_HIDDEN = ((b"<?", b"?>"), (b"<!--", b"-->"), (b"<![CDATA[", b"]]>"), (b"<!", b">"))
"""What ends each construct rapidxml skips, by how it begins, first match first."""
_LONGEST_OPENER = 10
_CUT_ROOT = re.compile(rb"<[ \t\n\r\v\f]*[A-Za-z]*")
"""A ``<`` and a name begun, cut where the bytes read end: it may be a root's."""
_AHEAD_CHUNK = 1 << 22


class Ahead:
    """Where the next root a parse looks for lies in the file, searched for ahead of it."""

    def __init__(self, pattern: re.Pattern[bytes], read_at: ReadAt, limit: int) -> None:
        self.pattern = pattern
        self.read_at = read_at
        self.limit = limit
        self.next = -1  # where the next root lies in the file, once found

    def follows(self, data: bytes, at: int, ended: bool, base: int) -> bool:
        """Whether a root lies at ``at`` of ``data`` (at ``base`` in the file) or after it."""
        if self.next >= base + at:
            return True
        found = self.pattern.search(data, at)
        if found is not None:
            self.next = base + found.start()
            return True
        if ended:
            return False
        cut = data.rfind(b"<", at)  # a root cut where data ends begins at its last '<'
        ahead = self._search(base + (cut if cut >= 0 else len(data)))
        self.next = -1 if ahead is None else ahead
        return ahead is not None

    def _search(self, offset: int) -> int | None:
        """Where the first root at ``offset`` or after it lies, read in chunks."""
        keep, size = b"", 1 << 16
        while offset < self.limit:
            want = min(size, self.limit - offset)
            got = self.read_at(offset, want)
            nul = got.find(b"\0")
            data = keep + (got if nul < 0 else got[:nul])
            last = nul >= 0 or len(got) < want or offset + len(got) >= self.limit
            found = self.pattern.search(data)
            if found is not None and (found.end() < len(data) or last):
                return offset - len(keep) + found.start()
            if last:
                return None
            cut = data.rfind(b"<")
            keep = data[cut:] if cut >= 0 and _CUT_ROOT.fullmatch(data, cut) else b""
            offset += len(got)
            size = min(2 * size, _AHEAD_CHUNK)
        return None


class Scan(Protocol):
    """A parse followed over a file's bytes as they are read (`discovery._tiny._follow`)."""

    @property
    def found(self) -> bool:
        """Whether a robot's root has been found, and nothing refused since."""
        ...

    def begin(self, data: bytes) -> int:
        """Where the parse begins in the file's first bytes."""
        ...

    def run(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str, int]:
        """The answer from ``at`` of ``data`` (at ``base`` in the file).

        Or "more", and where to run again from once more bytes are read.
        """
        ...


def _past_space(data: bytes, at: int) -> int:
    found = _SPACE.match(data, at)
    return found.end() if found else at


class Rapid:
    """rapidxml's parse, one construct at a time: whether it finds a top-level ``<mujoco>``."""

    def __init__(self, read_at: ReadAt, limit: int, max_constructs: int) -> None:
        self.ahead = Ahead(_MUJOCO, read_at, limit)
        self.budget = Budget(max_constructs)
        self.depth = 0  # elements open
        self.found = False

    def begin(self, data: bytes) -> int:
        """Where the parse begins: past a byte order mark at the very start."""
        return 3 if data.startswith(b"\xef\xbb\xbf") else 0

    def run(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str, int]:
        """The answer from ``at`` on, or "more": read on, and run again from ``at``."""
        while True:
            if self.depth == 0:  # white space only, then '<' or the end
                at = _past_space(data, at)
                if at == len(data):
                    return (_MORE if not ended else _YES if self.found else _NO), at
                if data[at] != ord("<"):
                    return _NO, at  # text at the top level
            else:
                less = data.find(b"<", at)
                if less < 0:  # text to the end of the bytes read; at the file's end, open
                    return (_MORE if not ended else _NO), len(data)
                at = less
            if not self.found and not self.ahead.follows(data, at, ended, base):
                return _NO, at
            if not self.budget.spend(base + at):
                return _YES, at  # found, or a <mujoco> ahead: its reader refuses so many
            step, at = self.construct(data, at, ended, base)
            if step is not None:
                return step, at

    def construct(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str | None, int]:
        """Past the construct at ``at`` (a ``<``).

        Returns:
            None and where the next one begins, or the answer and where to run again from.
        """
        if not ended and len(data) - at < _LONGEST_OPENER:
            return _MORE, at  # what begins here may be cut
        if data.startswith(b"</", at):
            if self.depth == 0:
                return _NO, at  # an end tag at the top level: no element name
            tag = _END_TAG.match(data, at)
            if tag is None or tag.group(1) is None:  # not ended by '>', or cut
                cut = tag is not None and tag.end() == len(data) and not ended
                return (_MORE if cut else _NO), at
            self.depth -= 1
            return None, tag.end()
        if _DOCTYPE.match(data, at):
            answer, end = self.doctype(data, at + 10, ended, base)
            return answer, (at if answer is not None else end)
        for opener, closer in _HIDDEN:
            if data.startswith(opener, at):
                end = data.find(closer, at + len(opener))
                if end < 0:
                    return (_MORE if not ended else _NO), at
                return None, end + len(closer)
        return self.element(data, at, ended, base)

    def doctype(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str | None, int]:
        """Past a document type whose body begins at ``at``: its brackets balanced, a '>'."""
        depth = 0
        while True:
            found = _BRACKET.search(data, at)
            if found is None:
                return (_MORE if not ended else _NO), at
            if not self.budget.spend(base + found.start()):
                return _YES, at
            at, mark = found.end(), found.group()
            if mark == b">" and depth == 0:
                return None, at
            depth += {b"[": 1, b"]": -1 if depth else 0}.get(mark, 0)

    def element(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str | None, int]:
        """Past a start tag at ``at``."""
        start = at
        name = _NAME.match(data, at + 1)
        if name is None:
            return _NO, start  # no element name
        if name.end() == len(data):
            return (_MORE if not ended else _NO), start
        at = _past_space(data, name.end())
        while True:
            attribute = _ATTRIBUTE.match(data, at)
            if attribute is None:
                break
            if not self.budget.spend(base + at):
                return _YES, start
            at = attribute.end()
        empty = data.startswith(b"/>", at)
        if not (empty or data.startswith(b">", at)):
            cut = at >= len(data) - 1 or _ATTRIBUTE_CUT.fullmatch(data, at)
            return (_MORE if cut and not ended else _NO), start
        if self.depth == 0 and name.group() == b"mujoco":
            self.found = True
        self.depth += not empty
        return None, at + (2 if empty else 1)
