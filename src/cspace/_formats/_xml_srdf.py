"""Whether a ``<robot>`` file is an SRDF, read from its bytes as a folder's search reads.

The rule is `_srdf_kind`'s: a name ending ``.srdf`` or ``.srdf.xacro``, or content with
an SRDF element (`SRDF_ELEMENTS`) and, outside the SRDF elements, no ``<link>``, no
``<joint>`` and no xacro element but definitions, conditions and arguments. The scan
stops at the first URDF element (a URDF's first tags are its links), so a robot file
costs a few tags; an SRDF is read to its root's end tag, on past the `PEEK_BYTES` the
search reads first when need be (a PR2's SRDF is 120 kB), up to the size cap and
`MAX_SCANNED_TAGS` constructs. An SRDF only when the scan is sure: a document type with
an internal subset, an entity reference, a ``<`` that begins nothing the scan reads
(tinyxml2 reads ``< link`` as an element), a file cut before its root's end, or too many
constructs, and the file is no SRDF here: it is inspected, and its reader (which parses
it whole) refuses an SRDF in one line.
"""

from __future__ import annotations

from ._roots import SRDF_ELEMENTS, URDF_ELEMENTS, XACRO_QUIET
from ._xml_prolog import ENTITY, HIDDEN_END, MARKUP, MAX_FILE_BYTES, Budget, Reader, after, tag_end

__all__ = ["srdf_content"]

_SRDF = frozenset(name.encode() for name in SRDF_ELEMENTS)
_URDF = frozenset(name.encode() for name in URDF_ELEMENTS)
_QUIET = frozenset(f"xacro:{name}".encode() for name in XACRO_QUIET)


def srdf_content(data: bytes, ended: bool, more: Reader, subset: bool) -> tuple[bool, bytes]:
    """Whether a ``<robot>`` file is an SRDF by its content, and the bytes read past ``data``.

    Args:
        data: The file's bytes from its root's ``<`` on (`_xml_prolog.Root.data`).
        ended: Whether ``data`` ends the file.
        more: What reads the file on past ``data``.
        subset: A document type with an internal subset comes before the root.
    """
    if subset:
        return False, b""
    budget = Budget()
    verdict = _scan(data, budget)
    if verdict is not None or ended:
        return bool(verdict), b""
    extra = more.read(MAX_FILE_BYTES + 1 - len(data))
    if len(data) + len(extra) > MAX_FILE_BYTES:
        return False, extra
    return bool(_scan(data + extra, budget)), extra


def _scan(data: bytes, budget: Budget) -> bool | None:
    """SRDF (True), not (False), or None: ``data`` ends before the root's end tag."""
    start = tag_end(data, 1, budget)
    if start < 0:
        return None if start == -1 else False
    if data.endswith(b"/>", 0, start) or ENTITY.search(data, 0, start):
        return False
    at, depth, inside, found = start, 0, -1, False  # inside: the depth of an SRDF element
    while True:
        markup = MARKUP.search(data, at)
        before = markup.start() if markup else len(data)
        if data.find(b"<", at, before) >= 0 or ENTITY.search(data, at, before):
            return False
        if markup is None:
            return None
        if not budget.spend(markup.start()):
            return False
        if markup.lastindex is not None and markup.lastindex <= 3:  # a comment, CDATA, a PI
            at = after(data, markup.end(), HIDDEN_END[markup.lastindex])
            if at < 0:
                return None
            continue
        end = tag_end(data, markup.end(), budget)
        if end < 0:
            return None if end == -1 else False
        if ENTITY.search(data, markup.end(), end):
            return False
        at, name = end, markup.group(5)
        if markup.group(4):  # an end tag
            if depth == 0:
                return found
            depth -= 1
            inside = -1 if depth == inside else inside
            continue
        if inside < 0:
            if name.startswith(b"xacro:"):
                if name not in _QUIET:
                    return False
            elif name in _URDF:
                return False
            elif name in _SRDF:
                found = True
                inside = depth
        if not data.endswith(b"/>", 0, end):
            depth += 1
        elif inside == depth:  # an empty SRDF element: nothing to skip
            inside = -1
