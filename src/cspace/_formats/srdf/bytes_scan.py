"""Whether a ``<robot>`` file is an SRDF, read from its bytes as a folder's search reads.

The rule is `srdf.kind`'s, which the loader applies to the parsed tree: outside the
SRDF elements (`SRDF_ELEMENTS`), no ``<link>``, no ``<joint>`` and no xacro element but
definitions, conditions and arguments; and an SRDF element, or a name that says SRDF
(``.srdf``, ``.srdf.xacro``: it decides only a ``<robot>`` that holds neither). Names
are compared as written. The scan stops at the first URDF element or xacro call (a
URDF's first tags are its links), so a robot file costs a few tags; an SRDF is read to
the file's end, on past the `PEEK_BYTES` the search reads first when need be (a PR2's
SRDF is 120 kB), up to the size cap and `MAX_SCANNED_TAGS` constructs. An SRDF only when
the scan is sure: a document type with an internal subset, an entity reference, a ``<``
that begins nothing the scan reads (tinyxml2 reads ``< link`` as an element), an end tag
that is not the open element's own, anything but white space, comments and processing
instructions after the root's end, a comment or processing instruction XML forbids, a
file cut before its root's end, or too many constructs, and the file is no SRDF here,
whatever its name: it is inspected, and its reader (which parses it whole, and expands a
xacro file) refuses an SRDF in one line, and a malformed file as such.
"""

from __future__ import annotations

import re

from cspace._formats.discovery.prolog import (
    ENTITY,
    HIDDEN_END,
    MARKUP,
    MAX_FILE_BYTES,
    Budget,
    Reader,
    after,
    tag_end,
)
from cspace._formats.shared.roots import SRDF_ELEMENTS, URDF_ELEMENTS, XACRO_QUIET

__all__ = ["srdf_content"]

_SRDF = frozenset(name.encode() for name in SRDF_ELEMENTS)
_URDF = frozenset(name.encode() for name in URDF_ELEMENTS)
_QUIET = frozenset(f"xacro:{name}".encode() for name in XACRO_QUIET)
_SPACE = re.compile(rb"[ \t\r\n]*")
_CLOSE = re.compile(rb"[ \t\r\n]*>")
"""What follows an end tag's name: XML allows white space alone."""
_TARGET = re.compile(
    rb"(?![Xx][Mm][Ll](?:[ \t\r\n]|\?>))[A-Za-z_:\x80-\xff][\w.:\x80-\xff-]*(?:[ \t\r\n]|\?>)"
)
"""A processing instruction's target: a name, not ``xml`` (which only a declaration is)."""


def srdf_content(
    data: bytes, ended: bool, more: Reader, subset: bool, *, named: bool = False
) -> tuple[bool, bytes]:
    """Whether a ``<robot>`` file is an SRDF by its content, and the bytes read past ``data``.

    Args:
        data: The file's bytes from its root's ``<`` on (`discovery.prolog.Root.data`).
        ended: Whether ``data`` ends the file.
        more: What reads the file on past ``data``.
        subset: A document type with an internal subset comes before the root.
        named: The file's name says SRDF (`named_srdf`).
    """
    if subset:
        return False, b""
    budget = Budget()
    verdict = _scan(data, budget, named, ended)
    if verdict is not None or ended:
        return bool(verdict), b""
    extra = more.read(MAX_FILE_BYTES + 1 - len(data))
    if len(data) + len(extra) > MAX_FILE_BYTES:
        return False, extra
    return bool(_scan(data + extra, budget, named, True)), extra


def _scan(data: bytes, budget: Budget, named: bool, ended: bool) -> bool | None:
    """SRDF (True), not or not sure (False), or None: ``data`` ends before the verdict.

    ``ended``: whether ``data`` ends the file, which is read to its end: past the root's
    end tag only white space, comments and processing instructions may follow.
    """
    start = tag_end(data, 1, budget)
    if start < 0:
        return None if start == -1 else False
    if ENTITY.search(data, 0, start):
        return False
    top = MARKUP.match(data)
    if top is None or top.group(5) is None:
        return False
    if data.endswith(b"/>", 0, start):  # an empty root: its name decides
        return _tail(data, start, budget, ended, named)
    names = [top.group(5)]  # the elements open, the root first
    at, inside, found = start, -1, False  # inside: how many were open at an SRDF element
    while True:
        markup = MARKUP.search(data, at)
        before = markup.start() if markup else len(data)
        if data.find(b"<", at, before) >= 0 or ENTITY.search(data, at, before):
            return False
        if data.find(b"]]>", at, before) >= 0:  # XML allows it in no text
            return False
        if markup is None:
            return None
        if not budget.spend(markup.start()):
            return False
        if markup.lastindex is not None and markup.lastindex <= 3:  # a comment, CDATA, a PI
            at = _hidden(data, markup.end(), markup.lastindex)
            if at < 0:
                return None if at == -1 else False
            continue
        end = tag_end(data, markup.end(), budget)
        if end < 0:
            return None if end == -1 else False
        if ENTITY.search(data, markup.end(), end):
            return False
        at, name = end, markup.group(5)
        if markup.group(4):  # an end tag: the open element's own, its name alone
            if name != names.pop() or _CLOSE.fullmatch(data, markup.end(), end) is None:
                return False
            if not names:
                return _tail(data, at, budget, ended, found or named)
            inside = -1 if len(names) == inside else inside
            continue
        if inside < 0:
            if name.startswith(b"xacro:"):
                if name not in _QUIET:
                    return False
            elif name in _URDF:
                return False
            elif name in _SRDF:
                found = True
                inside = len(names)
        if not data.endswith(b"/>", 0, end):
            names.append(name)
        elif inside == len(names):  # an empty SRDF element: nothing to skip
            inside = -1


def _hidden(data: bytes, at: int, kind: int) -> int:
    """Past a comment, CDATA section or PI (`MARKUP` group ``kind``) opened before ``at``.

    -1: cut where ``data`` ends; -2: one XML forbids (``--`` in a comment, a PI with no
    target or the target ``xml``).
    """
    end = after(data, at, HIDDEN_END[kind])
    if end < 0:
        return -1
    if kind == 1 and (data.find(b"--", at, end - 3) >= 0 or data.endswith(b"-", at, end - 3)):
        return -2
    if kind == 3 and _TARGET.match(data, at, end) is None:
        return -2
    return end


def _tail(data: bytes, at: int, budget: Budget, ended: bool, verdict: bool) -> bool | None:
    """``verdict`` if only white space, comments and PIs follow the root's end at ``at``.

    False when anything else follows; None: ``data`` ends before the file does.
    """
    while True:
        space = _SPACE.match(data, at)
        at = space.end() if space else at
        if at == len(data):
            return verdict if ended else None
        if not ended and len(data) - at < 4:  # an opening may be cut
            return None
        if not budget.spend(at):
            return False
        kind = 1 if data.startswith(b"<!--", at) else 3 if data.startswith(b"<?", at) else 0
        if not kind:
            return False
        at = _hidden(data, at + (4 if kind == 1 else 2), kind)
        if at < 0:
            return None if at == -1 else False
