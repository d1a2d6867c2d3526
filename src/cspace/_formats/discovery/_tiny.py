"""Whether a reader built on tinyxml2 or rapidxml finds a robot in a file XML does not read.

MuJoCo, Pinocchio (urdfdom) and Drake (urdfdom's and sdformat's way) parse with
tinyxml2, which reads more than XML. Before and between the top-level elements it takes
text of any bytes but ``<`` (``junk <mujoco>``), ``<!...>`` up to its first ``>`` (a
document type whose internal subset holds a ``>``, cut there), CDATA sections and
comments; a ``<`` may be followed by white space (``< mujoco>``); an end tag at the top
level ends the document, whatever follows. MuJoCo compiles the first top-level element
(``<mujoco>``, or ``<robot>`` as URDF, its name in any case: ``<Robot>`` too); urdfdom
and sdformat take the first top-level ``<robot>`` or ``<sdf>`` element, wherever it
stands (``<a/><robot>`` is a URDF to them). tinyxml2 refuses a document whose text runs
to its end, an element left open or closed by another name, an attribute without a
quoted value or given twice, a ``<`` before no name, a declaration (``<?...?>``) after
anything but declarations or within an element, a comment, CDATA section or ``<!...>``
left open. Pinocchio's MJCF reader parses with rapidxml (`discovery._rapid`), and takes the
first top-level ``<mujoco>`` wherever it stands (``<a/><b/><mujoco>``). Both parsers
read a file up to its first NUL byte, as if it ended there.

`tiny_robot` follows each parse over the file, read on in chunks that double, up to the
robot file's size cap, until the parse has ended (its end, or the end of the top level).
It answers yes for a file either reader may take for a robot: one it finds a robot's
root in, and does not refuse. Once an element has begun with no robot's root found, the
parse goes on only while the root it looks for (``<robot`` or ``<sdf``; rapidxml's
``<mujoco``) lies ahead in the file, which a search reads ahead for (`Ahead`): a file
with none (a mesh, a launch file) is decided without parsing the rest. Every step is a
search or a match at one place, each byte is read a bounded number of times, and at
most ``max_constructs`` constructs (tags, attributes, comments, runs of text) are
looked at in each parse: a file with more is taken for a robot (its reader then refuses
it) when a robot's root was found, no element has begun, or such a root lies ahead.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from cspace._formats.discovery._rapid import Ahead, Rapid, ReadAt, Scan
from cspace._formats.discovery.prolog import Budget

__all__ = ["tiny_robot"]

_SPACE = re.compile(rb"[ \t\n\r\v\f]*")
"""tinyxml2's white space (``isspace`` in the C locale)."""
_TEXT = re.compile(rb"[^ \t\n\r\v\f]")
_NAME_BYTES = rb"[A-Za-z_:\x80-\xff][\w.:\x80-\xff-]*"
"""tinyxml2's names: any byte from 0x80 up is a letter to it, as to XML's names."""
_NAME = re.compile(_NAME_BYTES)
_ATTRIBUTE = re.compile(
    rb"(" + _NAME_BYTES + rb")[ \t\n\r\v\f]*=[ \t\n\r\v\f]*(?:\"[^\"]*\"|'[^']*')"
)
_ATTRIBUTE_CUT = re.compile(
    _NAME_BYTES + rb"(?:[ \t\n\r\v\f]*(?:=[ \t\n\r\v\f]*(?:\"[^\"]*|'[^']*)?)?)?"
)
"""The beginning of an attribute, cut where the bytes read end."""
_ROOTS = (b"robot", b"sdf")
"""Top-level elements urdfdom and sdformat read wherever they stand."""
_FIRST_ROOTS = (b"mujoco", b"robot")
"""First top-level elements MuJoCo compiles (``<robot>``: as URDF), in any case."""
_LATER_ROOT = re.compile(rb"<[ \t\n\r\v\f]*(?:robot|sdf)(?![\w.:\x80-\xff-])")
_OPENER = re.compile(rb"<(?:\?|!--|!\[CDATA\[|!)")
_CLOSERS = {b"<?": b"?>", b"<!--": b"-->", b"<![CDATA[": b"]]>", b"<!": b">"}
_LONGEST_OPENER = 9

_YES, _NO, _MORE = "yes", "no", "more"


def tiny_robot(
    head: bytes,
    ended: bool,
    read_at: Callable[[int, int], bytes],
    limit: int,
    max_constructs: int,
) -> bool:
    """Whether a tinyxml2 or rapidxml reader may find a robot in a file beginning ``head``.

    Args:
        head: The file's first bytes.
        ended: Whether ``head`` is the whole file.
        read_at: Reads up to that many bytes of the file from that offset.
        limit: The most bytes read of the file (no reader of cspace reads a larger one).
        max_constructs: The most constructs looked at in each parse.
    """
    scans: tuple[Scan, ...] = (
        _Tiny(Ahead(_LATER_ROOT, read_at, limit), max_constructs),
        Rapid(read_at, limit, max_constructs),
    )
    return any(_follow(scan, head, ended, read_at, limit) for scan in scans)


def _follow(scan: Scan, head: bytes, ended: bool, read_at: ReadAt, limit: int) -> bool:
    """Run one parse over the file, read on in doubling chunks until it answers."""
    nul = head.find(b"\0")
    data, ended = (head, ended) if nul < 0 else (head[:nul], True)
    base, chunk = 0, max(len(head), 4096)  # base: where data begins in the file
    at = scan.begin(data)
    while True:
        answer, at = scan.run(data, at, ended, base)
        if answer != _MORE:
            return answer == _YES
        offset = base + len(data)
        if offset >= limit:
            return scan.found
        chunk = min(2 * chunk, limit - offset)
        got = read_at(offset, chunk)
        ended = len(got) < chunk
        nul = got.find(b"\0")
        if nul >= 0:
            got, ended = got[:nul], True
        data, base, at = data[at:] + got, base + at, 0


def _past_space(data: bytes, at: int) -> int:
    found = _SPACE.match(data, at)
    return found.end() if found else at


class _Tiny:
    """tinyxml2's parse, one construct at a time, and what it has seen so far."""

    def __init__(self, ahead: Ahead, max_constructs: int) -> None:
        self.ahead = ahead
        self.budget = Budget(max_constructs)
        self.open: list[bytes] = []  # the names of the elements open, outermost first
        self.begun = False  # an element has begun at the top level
        self.declarations_only = True  # nothing but declarations at the top level yet
        self.text = False  # in text that no ``<`` has ended yet
        self.found = False  # a robot's root at the top level
        self.cut: tuple[int, int, set[bytes]] | None = None  # a start tag cut: where, from

    def begin(self, data: bytes) -> int:
        """Where the parse begins: tinyxml2 skips white space, then a byte order mark."""
        at = _past_space(data, 0)
        return at + 3 if data.startswith(b"\xef\xbb\xbf", at) else at

    def run(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str, int]:
        """The answer from ``at`` on, or `_MORE`: read on, and run again from ``at``."""
        while True:
            if self.begun and not self.found and not self.ahead.follows(data, at, ended, base):
                return _NO, at  # no robot's root can follow
            less = data.find(b"<", at)
            stop = len(data) if less < 0 else less
            if _TEXT.search(data, at, stop):
                self.text = True
                self.declarations_only = False
            if less < 0:  # the text goes on to the end of the bytes read
                if not ended:
                    return _MORE, stop
                # text runs to the end of the document, or an element is left open
                return (_NO if self.text or self.open else self.answer()), stop
            self.text = False
            if not self.budget.spend(base + stop):
                return _YES, stop  # found, or none begun, or a root ahead: its reader refuses
            step, at = self.construct(data, stop, ended, base)
            if step is not None:
                return step, at

    def answer(self) -> str:
        return _YES if self.found else _NO

    def construct(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str | None, int]:
        """Past the construct at ``at`` (a ``<``).

        Returns:
            None and where the next construct begins, or the answer (`_MORE`: the
            construct may be cut where the bytes read end) and where to run again from.
        """
        if not ended and len(data) - at < _LONGEST_OPENER:
            return _MORE, at  # what begins here may be cut
        opener = _OPENER.match(data, at)
        if opener is None:
            self.declarations_only = False
            return self.element(data, at, ended, base)
        end = data.find(_CLOSERS[opener.group()], opener.end())
        if end < 0:
            return (_NO if ended else _MORE), at  # left open, or cut
        declaration = opener.group() == b"<?"
        if declaration and (self.open or not self.declarations_only):
            return _NO, at  # a declaration after other things, or in an element
        self.declarations_only = self.declarations_only and declaration
        return None, end + len(_CLOSERS[opener.group()])

    def element(self, data: bytes, at: int, ended: bool, base: int) -> tuple[str | None, int]:
        """Past a start or end tag at ``at``."""
        start = at
        at = _past_space(data, at + 1)
        closing = data.startswith(b"/", at)
        name = _NAME.match(data, at + closing)
        if name is None or name.end() == len(data):
            cut = name is not None or at + closing >= len(data)
            return (_NO if ended or not cut else _MORE), start
        at, seen = name.end(), set[bytes]()
        if self.cut is not None and self.cut[0] == base + start:  # read on from the cut
            at, seen = self.cut[1] - base, self.cut[2]
        self.cut = None
        while True:
            at = _past_space(data, at)
            attribute = _ATTRIBUTE.match(data, at)
            if attribute is not None:
                if not self.budget.spend(base + at):  # so many: a root, or one ahead?
                    top = not self.open and self.root(name.group())
                    yes = self.found or top or self.ahead.follows(data, at, ended, base)
                    return (_YES if yes else _NO), start
                if attribute.group(1) in seen:
                    return _NO, start  # given twice
                seen.add(attribute.group(1))
                at = attribute.end()
            elif data.startswith((b">", b"/>"), at):
                break
            elif at >= len(data) - 1 or _ATTRIBUTE_CUT.fullmatch(data, at):
                if ended:
                    return _NO, start
                self.cut = (base + start, base + at, seen)  # cut where the bytes read end
                return _MORE, start
            else:
                return _NO, start
        empty = data.startswith(b"/>", at)
        at += 2 if empty else 1
        if closing and not empty:
            if not self.open:
                return self.answer(), at  # an end tag at the top level ends the document
            return (None if self.open.pop() == name.group() else _NO), at
        if not self.open:
            self.found = self.found or self.root(name.group())
            self.begun = True
        if not empty:
            self.open.append(name.group())
        return None, at

    def root(self, name: bytes) -> bool:
        """Whether a top-level element of this name is a robot's root to a reader."""
        return name in _ROOTS or (not self.begun and name.lower() in _FIRST_ROOTS)
