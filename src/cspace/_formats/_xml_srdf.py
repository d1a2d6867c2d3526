"""Whether a ``<robot>`` file is an SRDF, read from its bytes as a folder's search reads.

The rule is `_srdf_kind`'s, which the loader applies to the parsed tree: outside the
SRDF elements (`SRDF_ELEMENTS`), no ``<link>``, no ``<joint>`` and no xacro element but
definitions, conditions and arguments; and an SRDF element, or a name that says SRDF
(``.srdf``, ``.srdf.xacro``: it decides only a ``<robot>`` that holds neither). Names
are compared as written. The scan stops at the first URDF element or xacro call (a
URDF's first tags are its links), so a robot file costs a few tags; an SRDF is read to
its root's end tag, on past the `PEEK_BYTES` the search reads first when need be (a
PR2's SRDF is 120 kB), up to the size cap and `MAX_SCANNED_TAGS` constructs. An SRDF
only when the scan is sure: a document type with an internal subset, an entity
reference, a ``<`` that begins nothing the scan reads (tinyxml2 reads ``< link`` as an
element), a file cut before its root's end, or too many constructs, and the file is no
SRDF here, whatever its name: it is inspected, and its reader (which parses it whole,
and expands a xacro file) refuses an SRDF in one line.
"""

from __future__ import annotations

from ._roots import SRDF_ELEMENTS, URDF_ELEMENTS, XACRO_QUIET
from ._xml_prolog import ENTITY, HIDDEN_END, MARKUP, MAX_FILE_BYTES, Budget, Reader, after, tag_end

__all__ = ["srdf_content"]

_SRDF = frozenset(name.encode() for name in SRDF_ELEMENTS)
_URDF = frozenset(name.encode() for name in URDF_ELEMENTS)
_QUIET = frozenset(f"xacro:{name}".encode() for name in XACRO_QUIET)


def srdf_content(
    data: bytes, ended: bool, more: Reader, subset: bool, *, named: bool = False
) -> tuple[bool, bytes]:
    """Whether a ``<robot>`` file is an SRDF by its content, and the bytes read past ``data``.

    Args:
        data: The file's bytes from its root's ``<`` on (`_xml_prolog.Root.data`).
        ended: Whether ``data`` ends the file.
        more: What reads the file on past ``data``.
        subset: A document type with an internal subset comes before the root.
        named: The file's name says SRDF (`named_srdf`).
    """
    if subset:
        return False, b""
    budget = Budget()
    verdict = _scan(data, budget, named)
    if verdict is not None or ended:
        return bool(verdict), b""
    extra = more.read(MAX_FILE_BYTES + 1 - len(data))
    if len(data) + len(extra) > MAX_FILE_BYTES:
        return False, extra
    return bool(_scan(data + extra, budget, named)), extra


def _scan(data: bytes, budget: Budget, named: bool) -> bool | None:
    """SRDF (True), not (False), or None: ``data`` ends before the root's end tag."""
    start = tag_end(data, 1, budget)
    if start < 0:
        return None if start == -1 else False
    if ENTITY.search(data, 0, start):
        return False
    if data.endswith(b"/>", 0, start):  # an empty root: its name decides
        return named
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
                return found or named
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
