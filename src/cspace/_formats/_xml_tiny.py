"""Whether a reader built on tinyxml2 finds a robot in a file that XML does not read.

MuJoCo, Pinocchio (urdfdom) and Drake (urdfdom's and sdformat's way) parse with
tinyxml2, which reads more than XML. Before and between the top-level elements it takes
text of any bytes but ``<`` and NUL (``junk <mujoco>``), ``<!...>`` up to its first
``>`` (a document type whose internal subset holds a ``>``, cut there), CDATA sections
and comments; a ``<`` may be followed by white space (``< mujoco>``); a NUL byte, or an
end tag at the top level, ends the document, whatever follows. MuJoCo compiles the
first top-level element (``<mujoco>``, or ``<robot>`` as URDF, its name in any case:
``<Robot>`` too); urdfdom and sdformat take the first top-level ``<robot>`` or ``<sdf>``
element, wherever it stands (``<a/><robot>`` is a URDF to them). tinyxml2 refuses a
document whose text runs to its end (or to a NUL byte), an element left open or closed
by another name, an attribute without a quoted value or given twice, a ``<`` before no
name, a declaration (``<?...?>``) after anything but declarations or within an element,
a comment, CDATA section or ``<!...>`` left open.

`tiny_robot` follows that parse over a file's first bytes, reading on only as long as no
element has begun (text, comments: what may come before a root), up to the robot file's
size cap; once an element has begun, the first bytes decide. It answers yes for a file
such a reader may take for a robot: one it would find a robot's root in, and not refuse
in the bytes read. Every step is a search or a match at one place, the bytes are
scanned once, and at most ``max_constructs`` are looked at (a file with more before its
first element is taken for a robot, whose reader then refuses it).
"""

from __future__ import annotations

import re
from collections.abc import Callable

_SPACE = re.compile(rb"[ \t\n\r\v\f]*")
"""tinyxml2's white space (``isspace`` in the C locale)."""
_TEXT = re.compile(rb"[^ \t\n\r\v\f]")
_NAME_BYTES = rb"[A-Za-z_:\x80-\xff][\w.:\x80-\xff-]*"
"""tinyxml2's names: any byte from 0x80 up is a letter to it, as to XML's names."""
_NAME = re.compile(_NAME_BYTES)
_ATTRIBUTE = re.compile(
    rb"(" + _NAME_BYTES + rb")[ \t\n\r\v\f]*=[ \t\n\r\v\f]*(?:\"[^\"\x00]*\"|'[^'\x00]*')"
)
_ATTRIBUTE_CUT = re.compile(
    _NAME_BYTES + rb"(?:[ \t\n\r\v\f]*(?:=[ \t\n\r\v\f]*(?:\"[^\"\x00]*|'[^'\x00]*)?)?)?"
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
    head: bytes, ended: bool, more: Callable[[int], bytes], limit: int, max_constructs: int
) -> bool:
    """Whether tinyxml2's readers may find a robot in a file that begins with ``head``.

    Args:
        head: The file's first bytes.
        ended: Whether ``head`` is the whole file.
        more: Reads up to that many more bytes of the file, after those read so far.
        limit: The most bytes read in all (no reader of cspace reads a larger file).
        max_constructs: The most constructs (tags, comments, runs of text) looked at.
    """
    scan = _Scan(max_constructs)
    data, read, chunk = head, len(head), max(len(head), 4096)
    at = _past_space(data, 0)
    if data.startswith(b"\xef\xbb\xbf", at):  # tinyxml2 skips white space, then a BOM
        at += 3
    while True:
        answer, at = scan.run(data, at, ended)
        if answer != _MORE:
            return answer == _YES
        if read >= limit:
            return False
        chunk = min(2 * chunk, limit - read)
        got = more(chunk)
        read += len(got)
        ended = len(got) < chunk
        data, at = data[at:] + got, 0


def _past_space(data: bytes, at: int) -> int:
    found = _SPACE.match(data, at)
    return found.end() if found else at


class _Scan:
    """tinyxml2's parse, one construct at a time, and what it has seen so far."""

    def __init__(self, max_constructs: int) -> None:
        self.left = max_constructs
        self.open: list[bytes] = []  # the names of the elements open, outermost first
        self.begun = False  # an element has begun: the bytes read decide
        self.declarations_only = True  # nothing but declarations at the top level yet
        self.text = False  # in text that no ``<`` has ended yet
        self.found = False  # a robot's root at the top level
        self.later = -1  # where the next ``<robot`` or ``<sdf`` is, once looked for

    def run(self, data: bytes, at: int, ended: bool) -> tuple[str, int]:
        """The answer from ``at`` on, or `_MORE`: read on, and run again from ``at``."""
        while self.left > 0:
            self.left -= 1
            less = data.find(b"<", at)  # two searches in C (a memchr each)
            stop = len(data) if less < 0 else less
            nul = data.find(b"\x00", at, stop)
            stop = stop if nul < 0 else nul
            if _TEXT.search(data, at, stop):
                self.text = True
                self.declarations_only = False
            if stop == len(data) and not ended:
                return (_MORE if not self.begun else self.answer()), len(data)
            if stop != less:  # the document ends: at a NUL byte, or at the file's end
                # text runs to its end, or an element is left open: refused
                return (_NO if self.text or self.open else self.answer()), stop
            self.text = False
            step, at = self.construct(data, stop, ended)
            if step is not None:
                return step, at
        return (self.answer() if self.begun else _YES), at  # the reader refuses so many

    def answer(self) -> str:
        return _YES if self.found else _NO

    def cut(self, ended: bool) -> str:
        """The answer when a construct runs to the end of the bytes read."""
        if ended:
            return _NO  # left open: refused
        return self.answer() if self.begun else _MORE

    def construct(self, data: bytes, at: int, ended: bool) -> tuple[str | None, int]:
        """Past the construct at ``at`` (a ``<``).

        Returns:
            None and where the next construct begins, or the answer and where to run
            again from.
        """
        if not ended and len(data) - at < _LONGEST_OPENER:
            return self.cut(ended), at  # what begins here may be cut
        opener = _OPENER.match(data, at)
        if opener is None:
            self.declarations_only = False
            return self.element(data, at, ended)
        end = data.find(_CLOSERS[opener.group()], opener.end())
        if end < 0:
            return self.cut(ended), at
        declaration = opener.group() == b"<?"
        if declaration and (self.open or not self.declarations_only):
            return _NO, at  # a declaration after other things, or in an element
        self.declarations_only = self.declarations_only and declaration
        return None, end + len(_CLOSERS[opener.group()])

    def element(self, data: bytes, at: int, ended: bool) -> tuple[str | None, int]:
        """Past a start or end tag at ``at``."""
        start = at
        at = _past_space(data, at + 1)
        closing = data.startswith(b"/", at)
        name = _NAME.match(data, at + closing)
        if name is None or name.end() == len(data):
            cut = name is not None or at + closing >= len(data)
            return (self.cut(ended) if cut else _NO), start
        at, seen = name.end(), set()
        while True:
            at = _past_space(data, at)
            attribute = _ATTRIBUTE.match(data, at)
            if attribute is not None:
                if attribute.group(1) in seen:
                    return _NO, start  # given twice
                seen.add(attribute.group(1))
                at = attribute.end()
            elif data.startswith((b">", b"/>"), at):
                break
            elif at >= len(data) - 1 or _ATTRIBUTE_CUT.fullmatch(data, at):
                return self.cut(ended), start  # cut where the bytes read end
            else:
                return _NO, start
        empty = data.startswith(b"/>", at)
        at += 2 if empty else 1
        if closing and not empty:
            if not self.open:
                return self.answer(), at  # an end tag at the top level ends the document
            return (None if self.open.pop() == name.group() else _NO), at
        if not self.open:
            return self.top_level(data, at, name.group(), empty)
        if not empty:
            self.open.append(name.group())
        return None, at

    def top_level(self, data: bytes, at: int, name: bytes, empty: bool) -> tuple[str | None, int]:
        """Past a top-level start tag, that ends at ``at``."""
        if name in _ROOTS or (not self.begun and name.lower() in _FIRST_ROOTS):
            self.found = True
        self.begun = True
        if not self.found:
            if self.later < at:
                later = _LATER_ROOT.search(data, at)
                self.later = len(data) if later is None else later.start()
            if self.later == len(data):
                return _NO, at  # no robot's root can follow in the bytes read
        if not empty:
            self.open.append(name)
        return None, at
