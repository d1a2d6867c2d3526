"""What a folder's search reads of an XML file: its root, includes, and if a library.

The root element is found past the prolog (white space, comments, processing
instructions, a document type), read on in growing chunks for as long as the prolog goes
on, up to the robot file's size cap (`MAX_FILE_BYTES`): a file whose prolog goes on
past that is `UNDECIDED`, and inspected, so that its reader refuses it (MuJoCo would
read a `<mujoco>` after any amount of comment). What a file includes is read from the
`PEEK_BYTES` that follow its root's start tag; a nameless xacro ``<robot>`` (a library,
perhaps) is read whole, up to the cap, since one ``<link>`` anywhere at its top level
makes it a robot. Comments, CDATA sections and processing instructions are not read for
any of this, and a tag's end is found past its quoted attribute values (``params="x:=/>"``
does not end a ``<xacro:macro>``). Every scan is one pass over the bytes, with regular
expressions that do not backtrack, and at most `MAX_SCANNED_TAGS` tags are looked at.

A file in which XML finds no robot's root is `UNDECIDED` too when tinyxml2, which
MuJoCo, urdfdom and sdformat parse with, would find one (``junk <mujoco>``,
``<a/><robot>``: `_xml_tiny`).

An include counts only where the reader surely follows it: an MJCF ``<include file>``
anywhere (MuJoCo splices every one in, and checks what it spliced against its schema);
a ``<xacro:include filename>`` only as a child of the root, not in a ``<xacro:macro>``
or block ``<xacro:property>`` (whose body is read only where it is used), not in
``<xacro:if>`` or ``<xacro:unless>`` (whose condition only xacro can tell), not in any
other element (``<gazebo>``, whose content the URDF reader skips). ``<model file>`` (MuJoCo's
attached models) is no include: a model asset that nothing attaches is never compiled.
"""

from __future__ import annotations

import os
import re
from typing import IO, NamedTuple

from ._xml_tiny import tiny_robot

PEEK_BYTES = 64 << 10
"""Bytes read of each file first, and read for its includes after its root's start tag."""

MAX_FILE_BYTES = 64 << 20
"""How far a prolog or a library is read: the robot file's size cap (`xmlio.MAX_FILE_BYTES`)."""

MAX_SCANNED_TAGS = 250_000
"""Most tags looked at in one file (the reader's own bound, `xmlio.MAX_TAGS`); a xacro
file with more is taken for a robot, whose reader then refuses it."""

ROBOT_SUFFIXES = (".urdf", ".xacro", ".sdf")
"""Names that say a robot description whatever the root (xacro may wrap it), in any case."""

FRAGMENT_ROOTS = ("mujocoinclude",)
"""Root elements of files meant only to be included."""

MJCF_ROOTS = ("mujoco", *FRAGMENT_ROOTS)
XML_ROOTS = ("robot", "mujoco", "sdf")
"""Root elements of robot descriptions."""

UNDECIDED = "?"
"""The root of a file that may be a robot description, but not one XML reads whole (its
prolog goes on past `MAX_FILE_BYTES`, or only tinyxml2 finds a robot's root in it):
inspected, never dropped."""

_NAME = re.compile(rb"[A-Za-z_][\w.:-]*")
_SPACE = re.compile(rb"\s*")
_HIDDEN = re.compile(rb"<!--|<!\[CDATA\[|<\?")
_CLOSE = {b"<!--": b"-->", b"<![CDATA[": b"]]>", b"<?": b"?>"}
_QUOTE_OR_END = re.compile(rb"[\"'>]")
_ATTRIBUTE = re.compile(rb"\s([^\s=/>]+)\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_MJCF_INCLUDE = re.compile(rb"<include(?=[\s/>])")
_TAG = re.compile(rb"<(/?)([A-Za-z_][\w.:-]*)")
_FIND = re.compile(r"\$\((?:find|find-pkg-share)\s+([^\s)/]+)\s*\)/*")
_DEFINITIONS = (b"xacro:macro", b"xacro:property")
"""xacro elements whose content is read only where it is used (a call, a block)."""
_DIRECTIVES = (*_DEFINITIONS, b"xacro:if", b"xacro:unless", b"xacro:arg", b"xacro:include")
"""The xacro elements that make nothing of their own at a file's top level."""


class XmlLook(NamedTuple):
    """What the search needs of one XML file.

    Attributes:
        root: The root element's name (`UNDECIDED`, or None: no XML element).
        includes: The files it surely includes, joined to its folder and normalised.
        finds: ``PKG/PATH`` of each ``$(find PKG)/PATH`` it surely includes.
        library: A xacro library: a ``.xacro`` file, a ``<robot>`` without a name, that
            makes nothing at its top level (no ``<link>``, no xacro element but
            definitions, conditions, ``<xacro:arg>`` and ``<xacro:include>``: no macro
            call, no ``<xacro:attribute>`` naming the robot, no ``<xacro:element>``).
    """

    root: str | None
    includes: tuple[str, ...] = ()
    finds: tuple[str, ...] = ()
    library: bool = False


def root_tag(data: bytes) -> str | None:
    """The root element's name in the bytes of an XML file, or None."""
    root, _ = _prolog(data, 3 if data.startswith(b"\xef\xbb\xbf") else 0, ended=True)
    return root


def look_xml(path: str, stream: IO[bytes], head: bytes) -> XmlLook:
    """What ``path`` is, from ``head`` (its first bytes) and ``stream`` (the rest).

    ``stream`` is a regular file's (it is read again from ``len(head)`` when tinyxml2's
    reading of the file must be followed past ``head``).
    """
    root, data, ended = _root(stream, head)
    if root not in (*XML_ROOTS, UNDECIDED) and _tiny_robot(stream, head):
        return XmlLook(UNDECIDED)
    xacro = root == "robot" and path.endswith(".xacro")  # as the loader tells xacro
    if not (xacro or root in MJCF_ROOTS):
        return XmlLook(root)
    start = _tag_end(data, 1)
    nameless = xacro and _attribute(data[:start], b"name") is None
    if nameless and not ended:  # a library, perhaps: read whole
        data += stream.read(MAX_FILE_BYTES + 1 - len(data))
        ended = len(data) <= MAX_FILE_BYTES
        start = _tag_end(data, 1)
        nameless = _attribute(data[:start], b"name") is None
    text = _markup(data[start:])
    folder = os.path.dirname(path)
    if root in MJCF_ROOTS:
        named = _mjcf_includes(text)
        makes = False
    else:
        named, makes = _xacro_includes(text)
    includes: list[str] = []
    finds: list[str] = []
    for raw in named:
        target = raw.decode("utf-8", "replace")
        if any(c in target for c in "&\t\n\r"):  # the parser reads another name: none here
            continue
        if not xacro:  # MuJoCo reads a backslash as a folder separator; xacro does not
            includes.append(os.path.normpath(os.path.join(folder, target.replace("\\", "/"))))
            continue
        found = _FIND.match(target)
        rest = target[found.end() :] if found else target
        if not rest or any(c in rest for c in "$*?["):  # xacro evaluates these, or globs
            continue
        if found:
            finds.append(f"{found.group(1)}/{rest}")
        else:
            includes.append(os.path.normpath(os.path.join(folder, target)))
    library = nameless and ended and not makes
    return XmlLook(root, tuple(includes), tuple(finds), library)


def _tiny_robot(stream: IO[bytes], head: bytes) -> bool:
    """Whether tinyxml2's readers may find a robot in the file (`tiny_robot`)."""
    ended = len(head) < PEEK_BYTES
    if not ended and not stream.seekable():
        return False
    offset = len(head)

    def more(size: int) -> bytes:
        nonlocal offset
        stream.seek(offset)
        got = stream.read(size)
        offset += len(got)
        return got

    return tiny_robot(head, ended, more, MAX_FILE_BYTES, MAX_SCANNED_TAGS)


def _root(stream: IO[bytes], head: bytes) -> tuple[str | None, bytes, bool]:
    """The root's name, the bytes from its start tag on, and whether they end the file.

    At least `PEEK_BYTES` bytes follow the root's ``<`` when the file has them. The
    prolog is read on in chunks that double, so that a long one is read in linear time.
    """
    data, at, read, chunk = head, 3 if head.startswith(b"\xef\xbb\xbf") else 0, len(head), 0
    ended = len(head) < PEEK_BYTES
    while True:
        root, at = _prolog(data, at, ended)
        if root is not None or at < 0:
            break
        if read > MAX_FILE_BYTES:
            return UNDECIDED, b"", ended
        chunk = min(max(2 * chunk, PEEK_BYTES), MAX_FILE_BYTES + 1 - read)
        more = stream.read(chunk)
        read += len(more)
        ended = len(more) < chunk
        data, at = data[at:] + more, 0
    if root is None:
        return None, b"", ended
    data = data[at:]
    if len(data) < PEEK_BYTES and not ended:
        more = stream.read(PEEK_BYTES - len(data))
        ended = len(more) < PEEK_BYTES - len(data)
        data += more
    return root, data, ended


def _prolog(data: bytes, at: int, ended: bool) -> tuple[str | None, int]:
    """Past the prolog from ``at``: (root name, where its ``<`` is).

    (None, -1): no root element there. (None, at): the prolog goes on past ``data``,
    which does not end the file: read on, and scan again from ``at``.
    """
    while True:
        space = _SPACE.match(data, at)
        at = space.end() if space else at
        if not ended and len(data) - at < 16:  # a construct may be cut: read on
            return None, at
        if data.startswith(b"<?", at):
            end = _after(data, at + 2, b"?>")
        elif data.startswith(b"<!--", at):
            end = _after(data, at + 4, b"-->")
        elif data.startswith(b"<!", at):
            end = _doctype_end(data, at + 2)
        elif data.startswith(b"<", at):
            found = _NAME.match(data, at + 1)
            if found is None:
                return None, -1
            if found.end() == len(data) and not ended:  # the name may go on
                return None, at
            return found.group(0).decode("ascii"), at
        else:
            return None, -1
        if end < 0:
            return (None, -1) if ended else (None, at)
        at = end


def _after(data: bytes, at: int, close: bytes) -> int:
    end = data.find(close, at)
    return end + len(close) if end >= 0 else -1


def _doctype_end(data: bytes, at: int) -> int:
    """Past ``<!...>``: a document type's internal subset (``[...]``) included."""
    end = data.find(b">", at)
    bracket = data.find(b"[", at, end if end >= 0 else len(data))
    if bracket < 0:
        return end + 1 if end >= 0 else -1
    close = data.find(b"]", bracket)
    return _after(data, close, b">") if close >= 0 else -1


def _markup(data: bytes) -> bytes:
    """``data`` without comments, CDATA sections and processing instructions.

    Each is a space, so that no two names join; one left open runs to the end.
    """
    out, at = [], 0
    while True:
        found = _HIDDEN.search(data, at)
        if found is None:
            out.append(data[at:])
            return b"".join(out)
        out.append(data[at : found.start()])
        out.append(b" ")
        end = data.find(_CLOSE[found.group()], found.end())
        if end < 0:
            return b"".join(out)
        at = end + len(_CLOSE[found.group()])


def _tag_end(text: bytes, at: int) -> int:
    """Where the tag that goes on at ``at`` ends: past its ``>``, not one in a value."""
    while True:
        found = _QUOTE_OR_END.search(text, at)
        if found is None:
            return len(text)
        if found.group() == b">":
            return found.end()
        close = text.find(found.group(), found.end())
        if close < 0:
            return len(text)
        at = close + 1


def _attribute(tag: bytes, name: bytes) -> bytes | None:
    """The value of attribute ``name`` in a start tag's bytes, or None."""
    for found in _ATTRIBUTE.finditer(tag):
        if found.group(1) == name:
            value = found.group(2) if found.group(2) is not None else found.group(3)
            return bytes(value)
    return None


def _mjcf_includes(text: bytes) -> list[bytes]:
    """The ``file`` of every ``<include>``: MuJoCo splices each in, wherever it stands."""
    named, at = [], 0
    for _ in range(MAX_SCANNED_TAGS):
        found = _MJCF_INCLUDE.search(text, at)
        if found is None:
            break
        at = _tag_end(text, found.end())
        file = _attribute(text[found.end() : at], b"file")
        if file is not None:
            named.append(file)
    return named


def _xacro_includes(text: bytes) -> tuple[list[bytes], bool]:
    """The includes xacro surely follows, and whether the top level makes something.

    ``text`` is what follows the root's start tag. An include counts when it is a child
    of the root: in any other element its content could land where the URDF reader
    reads nothing (``<gazebo>``), and in a definition or a condition it may never be
    read. Something: a ``<link>`` or a xacro element other than the `_DIRECTIVES`,
    outside the definitions; more than `MAX_SCANNED_TAGS` tags count as something.
    """
    named: list[bytes] = []
    depth = definitions = at = 0  # open elements below the root; of them, definitions
    makes = False
    for _ in range(MAX_SCANNED_TAGS):
        found = _TAG.search(text, at)
        if found is None:
            return named, makes
        at = _tag_end(text, found.end())
        name = found.group(2)
        if found.group(1):  # an end tag
            depth = max(depth - 1, 0)
            if name in _DEFINITIONS:
                definitions = max(definitions - 1, 0)
            continue
        tag = text[found.end() : at]
        if definitions == 0 and (name == b"link" or name.startswith(b"xacro:")):
            makes = makes or name not in _DIRECTIVES
        if name == b"xacro:include" and depth == 0:
            file = _attribute(tag, b"filename")
            if file is not None:
                named.append(file)
        if not tag.endswith(b"/>"):
            depth += 1
            definitions += name in _DEFINITIONS
    return named, True
