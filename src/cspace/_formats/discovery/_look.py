"""What a folder's search reads of an XML file: its root, includes, and if a library.

Of a ``<robot>``, also its ``name`` as written and whether it is an SRDF, MoveIt's
semantic description, which is no robot of its own (`srdf.bytes_scan`: by its content, read on
to its root's end tag when need be, its name deciding only a root that holds neither a
robot's elements nor an SRDF's; what that reads beyond the first bytes is handed on to a
library's reading, `_Again`, and never widens the includes scanned).

The root element is found past the prolog (white space, comments, processing
instructions, a document type with its internal subset, whose quoted literals, comments
and processing instructions may hold ``]`` and ``>``), read on in growing chunks for as
long as the prolog goes on, up to the robot file's size cap (`MAX_FILE_BYTES`): a file
whose prolog goes on past that, or past `MAX_SCANNED_TAGS` constructs, is `UNDECIDED`,
and inspected, so that its reader refuses it (MuJoCo would read a ``<mujoco>`` after any
amount of comment). A byte order mark is read as XML reads it: a UTF-16 or UTF-32 file
(by its mark, or by ``<?`` so encoded) is read in its characters. A file in which XML
finds no robot's root is `UNDECIDED` too when tinyxml2 (MuJoCo, urdfdom, sdformat) or
rapidxml (Pinocchio's MJCF reader) would find one (``junk <mujoco>``, ``<a/><robot>``,
``<a/><mujoco>``: `discovery._tiny`, `discovery._rapid`).

A xacro ``<robot>`` or an MJCF ``<mujoco>`` whose document type has an internal subset,
or that holds an entity reference other than XML's five (``&amp;``) and character
references, in what the search reads of it, is `UNDECIDED`: its entities and attribute
defaults make a content the search does not see (``<robot>&body;</robot>``), so it is no
library and no fragment, and inspected (cspace's readers refuse it).

What a file includes is read from the `PEEK_BYTES` that follow its root's start tag (a
start tag that goes on past them: nothing included, no library), up to the root's end
tag (MuJoCo reads nothing after it); a nameless xacro ``<robot>`` (a library, perhaps)
is read whole, up to the cap, since one ``<link>`` anywhere at its top level makes it a
robot, and a tag after its root's end makes it none. Comments, CDATA sections and
processing instructions are not read for any of this, and a tag's end is found past its
quoted attribute values (``params="x:=/>"`` does not end a ``<xacro:macro>``). Names are
XML's, any byte from 0x80 up a letter (``<jöint>``), so that every element is counted
where it opens and where it closes. Every scan is one pass over the bytes, with regular
expressions that do not backtrack, and at most `MAX_SCANNED_TAGS` constructs (tags,
quoted values, comments, CDATA sections, processing instructions) are looked at in each.

An include counts only where the reader surely follows it: an MJCF ``<include file>``
anywhere in the root (MuJoCo splices every one in, and checks what it spliced against
its schema); a ``<xacro:include filename>`` only as a child of the root, not in a
``<xacro:macro>`` or block ``<xacro:property>`` (whose body is read only where it is
used), not in ``<xacro:if>`` or ``<xacro:unless>`` (whose condition only xacro can
tell), not in any other element (``<gazebo>``, whose content the URDF reader skips).
``<model file>`` (MuJoCo's attached models) is no include: a model asset that nothing
attaches is never compiled. An include names the file the reader opens: its real path,
the including file's folder joined with the name as written, every link followed
(``lnk/../robot.xml`` is beside where ``lnk`` leads); a xacro include of a link to
another folder counts for nothing (xacro would read that file's own includes from the
link's folder). At most `MAX_INCLUDES` are kept of each file: one more only makes fewer
files fragments.

An MJCF file is `XmlLook.self_contained` when MuJoCo surely reads it the same from any
folder: the scan saw all of it up to its root's end tag, within the `PEEK_BYTES` after
its root's start tag and the construct budget, and found in it no element for which
MuJoCo reads a file from the model's folder that makes bodies or joints: no
``<include>`` (kept or not: a name with an entity, a tab, a line break or a NUL is one
too), no ``<model>``, no ``<flexcomp>`` (a mesh file's vertices make its bodies), in any
case or namespace prefix; no ``<`` that begins none of the constructs the scan reads
(tinyxml2 reads ``< include`` as an element), no document type with an internal subset,
no entity reference. Mesh, texture, height-field and skin files (and ``<compiler
meshdir texturedir assetdir>``, which say where they are) make no joint, and cspace's
MJCF reader never reads them.
"""

import os
import re
from typing import IO

from cspace._formats.discovery._tiny import tiny_robot
from cspace._formats.discovery.prolog import (
    ENTITY,
    HIDDEN_END,
    MARKUP,
    MAX_FILE_BYTES,
    MAX_SCANNED_TAGS,
    PEEK_BYTES,
    UNDECIDED,
    Budget,
    Reader,
    after,
    root,
    root_tag,
    tag_end,
    utf8,
)
from cspace._formats.shared.roots import (
    FRAGMENT_ROOTS,
    MJCF_ROOTS,
    ROBOT_SUFFIXES,
    XML_ROOTS,
    named_srdf,
)
from cspace._formats.srdf.bytes_scan import srdf_content
from cspace._record import NamedTuple

__all__ = [
    "FRAGMENT_ROOTS",
    "MAX_FILE_BYTES",
    "MAX_INCLUDES",
    "MAX_SCANNED_TAGS",
    "MJCF_ROOTS",
    "PEEK_BYTES",
    "ROBOT_SUFFIXES",
    "UNDECIDED",
    "XML_ROOTS",
    "XmlLook",
    "look_xml",
    "opened",
    "root_tag",
]

MAX_INCLUDES = 256
"""Most includes kept of one file (the reader's own bound on files, `shared.xmlio.MAX_FILES`)."""

_ATTRIBUTE = re.compile(rb"\s([^\s=/>]+)\s*=\s*(?:\"([^\"]*)\"|'([^']*)')")
_FIND = re.compile(r"\$\((?:find|find-pkg-share)\s+([^\s)/]+)\s*\)/*")
_FOLDER_READS = (b"include", b"model", b"flexcomp")
"""MJCF elements for which MuJoCo reads a file from the model's folder (bodies, joints)."""
_DEFINITIONS = (b"xacro:macro", b"xacro:property")
"""xacro elements whose content is read only where it is used (a call, a block)."""
_DIRECTIVES = (*_DEFINITIONS, b"xacro:if", b"xacro:unless", b"xacro:arg", b"xacro:include")
"""The xacro elements that make nothing of their own at a file's top level."""


class XmlLook(NamedTuple):
    """What the search needs of one XML file.

    Attributes:
        root: The root element's name (`UNDECIDED`, or None: no XML element).
        includes: The files it surely includes, as real paths (`os.path.realpath`).
        finds: ``PKG/PATH`` of each ``$(find PKG)/PATH`` it surely includes.
        library: A xacro library: a ``.xacro`` file, a ``<robot>`` without a name, that
            makes nothing at its top level (no ``<link>``, no xacro element but
            definitions, conditions, ``<xacro:arg>`` and ``<xacro:include>``: no macro
            call, no ``<xacro:attribute>`` naming the robot, no ``<xacro:element>``).
        self_contained: An MJCF file that MuJoCo surely reads the same from any folder:
            read whole to its root's end, it names no file MuJoCo would read from the
            model's folder (no ``<include>``, ``<model>`` or ``<flexcomp>``). False
            when unsure, and for any other file.
        srdf: A ``<robot>`` that is surely an SRDF by its content (`srdf.bytes_scan`).
        name: A ``<robot>``'s ``name`` as written, or None.
    """

    root: str | None
    includes: tuple[str, ...] = ()
    finds: tuple[str, ...] = ()
    library: bool = False
    self_contained: bool = False
    srdf: bool = False
    name: str | None = None


def look_xml(path: str, stream: IO[bytes], head: bytes) -> XmlLook:
    """What ``path`` is, from ``head`` (its first bytes) and ``stream`` (the rest).

    ``stream`` is a regular file's: it is read again from ``len(head)`` when tinyxml2's
    reading of the file must be followed past ``head``, and left where it was.
    """
    text, first = utf8(stream, head)
    top, data, ended, subset = root(text, first)
    if top not in (*XML_ROOTS, UNDECIDED) and _tiny_robot(stream, head):
        return XmlLook(UNDECIDED)
    xacro = top == "robot" and path.endswith(".xacro")  # as the loader tells xacro
    name = None
    if top == "robot":
        name = _robot_name(data)
        srdf, extra = srdf_content(data, ended, text, subset, named=named_srdf(path))
        if srdf:
            return XmlLook(top, srdf=True, name=name)
        text = _Again(extra, text) if extra else text  # read past data: read again
    if not (xacro or top in MJCF_ROOTS):
        return XmlLook(top, name=name)
    hidden = top != "mujocoinclude"  # a robot's content the scan may not see
    if subset and hidden:  # entities, attribute defaults: the scan reads another document
        return XmlLook(UNDECIDED)
    budget = Budget()
    start = tag_end(data, 1, budget)
    if start < 0:  # a root's start tag past the bytes read: no include, no library
        return XmlLook(top)
    nameless = xacro and _attribute(data[:start], b"name") is None
    if nameless and not ended:  # a library, perhaps: read whole
        data += text.read(MAX_FILE_BYTES + 1 - len(data))
        ended = len(data) <= MAX_FILE_BYTES
    scanned = _tags(data, start, budget)
    if hidden and (scanned.entity or ENTITY.search(data, 0, start)):
        return XmlLook(UNDECIDED)
    named: list[bytes | None]
    self_contained = False
    if top in MJCF_ROOTS:
        named = [_attribute(data[t[1] : t[2]], b"file") for t in scanned.tags if t[0] == b"include"]
        makes = False
        self_contained = _self_contained(scanned, subset or bool(ENTITY.search(data, 0, start)))
    else:
        xacro_named, makes = _xacro_includes(data, scanned.tags)
        named = list(xacro_named)
        makes = makes or scanned.capped or scanned.beyond
    includes: list[str] = []
    finds: list[str] = []
    for raw in [n for n in named if n is not None][:MAX_INCLUDES]:
        target = raw.decode("utf-8", "replace")
        if any(c in target for c in "&\t\n\r\0"):  # the parser reads another name: none here
            continue
        if not xacro:  # MuJoCo reads a backslash as a folder separator; xacro does not
            includes += _opened(path, target.replace("\\", "/"), xacro=False)
            continue
        found = _FIND.match(target)
        rest = target[found.end() :] if found else target
        if not rest or any(c in rest for c in "$*?["):  # xacro evaluates these, or globs
            continue
        if found:
            finds.append(f"{found.group(1)}/{rest}")
        else:
            includes += _opened(path, target, xacro=True)
    library = nameless and ended and not makes
    return XmlLook(top, tuple(includes), tuple(finds), library, self_contained, name=name)


def _robot_name(data: bytes) -> str | None:
    """The ``name`` of the root's start tag at the start of ``data``, as written."""
    end = tag_end(data, 1, Budget())
    value = _attribute(data[:end], b"name") if end > 0 else None
    return None if value is None else value.decode("utf-8", "replace")


class _Again:
    """A stream read on, its bytes already read first."""

    def __init__(self, read: bytes, stream: Reader) -> None:
        self.read_before, self.stream = read, stream

    def read(self, size: int, /) -> bytes:
        out, self.read_before = self.read_before[:size], self.read_before[size:]
        return out + self.stream.read(size - len(out)) if len(out) < size else out


def _self_contained(scanned: "_Scanned", unseen: bool) -> bool:
    """Whether an MJCF root's content, as ``scanned``, reads the same from any folder.

    ``unseen``: a document type's internal subset or an entity in the root's start tag.
    """
    if unseen or scanned.entity or scanned.stray or scanned.capped or not scanned.closed:
        return False
    return not any(
        name.lstrip(b"/").rpartition(b":")[2].lower() in _FOLDER_READS
        for name, _, _ in scanned.tags
    )


def opened(joined: str, *, xacro: bool) -> list[str]:
    """The real path of the file a reader opens for ``joined`` (a folder and a name).

    Links are followed as the system follows them (``lnk/..`` is the folder above where
    ``lnk`` leads). For xacro, none when the file is a link to another folder: xacro
    reads that file's own includes from the folder of the name, not of the file.
    """
    try:
        real = os.path.realpath(joined)
        if xacro and os.path.dirname(real) != os.path.realpath(os.path.dirname(joined)):
            return []
    except (OSError, ValueError):
        return []
    return [real]


def _opened(path: str, target: str, *, xacro: bool) -> list[str]:
    return opened(os.path.join(os.path.dirname(path), target), xacro=xacro)


def _tiny_robot(stream: IO[bytes], head: bytes) -> bool:
    """Whether tinyxml2's or rapidxml's readers may find a robot in the file (`tiny_robot`)."""
    ended = len(head) < PEEK_BYTES
    if not ended and not stream.seekable():
        return False
    position = stream.tell() if not ended else 0

    def read_at(offset: int, size: int) -> bytes:
        if ended:
            return head[offset : offset + size]
        stream.seek(offset)
        return stream.read(size)

    try:
        return tiny_robot(head, ended, read_at, MAX_FILE_BYTES, MAX_SCANNED_TAGS)
    finally:
        if not ended:
            stream.seek(position)  # where the other reads of the file left it


class _Scanned(NamedTuple):
    """What `_tags` read of a root's content.

    Attributes:
        tags: Each tag: its name (an end tag's begins with ``/``), where the tag goes on
            past its name, and where it ends.
        capped: There were too many constructs to look at all.
        beyond: A tag follows the root's end tag (no reader takes the file).
        entity: An entity reference other than XML's five and character references, in
            text or a value (its replacement is content the scan does not see).
        closed: The scan reached the root's end tag.
        stray: A ``<`` in the root's content that begins none of the constructs the
            scan reads (tinyxml2 reads ``< include`` as an element).
    """

    tags: list[tuple[bytes, int, int]]
    capped: bool
    beyond: bool
    entity: bool
    closed: bool = False
    stray: bool = False


def _tags(data: bytes, at: int, budget: Budget) -> _Scanned:
    """The tags of ``data`` from ``at`` (past the root's start tag) to the root's end tag.

    Comments, CDATA sections and processing instructions are passed over (one left open
    runs to the end); each, each tag and each quoted value counts against ``budget``.
    """
    tags: list[tuple[bytes, int, int]] = []
    depth = -1 if data.endswith(b"/>", 0, at) else 0  # elements open below the root
    entity = stray = False
    while True:
        found = MARKUP.search(data, at)
        if depth >= 0:  # the text before it: any `<` there begins nothing read here
            stray = stray or data.find(b"<", at, found.start() if found else len(data)) >= 0
        if found is None:
            entity = entity or bool(ENTITY.search(data, at))
            return _Scanned(tags, False, False, entity, depth < 0, stray)
        if not budget.spend(found.start()):
            return _Scanned(tags, True, False, entity, depth < 0, stray)
        if found.lastindex is not None and found.lastindex <= 3:  # hidden
            entity = entity or bool(ENTITY.search(data, at, found.start()))
            at = after(data, found.end(), HIDDEN_END[found.lastindex])
            if at < 0:
                return _Scanned(tags, False, False, entity, depth < 0, stray)
            continue
        if depth < 0:  # past the root's end tag
            return _Scanned(tags, False, True, entity, True, stray)
        end = tag_end(data, found.end(), budget)
        if end == -2:
            return _Scanned(tags, True, False, entity)
        if end < 0:  # a tag cut where the bytes read end: the last the scan sees
            if not found.group(4):
                tags.append((found.group(5), found.end(), len(data)))
            return _Scanned(tags, False, False, entity or bool(ENTITY.search(data, at)))
        entity = entity or bool(ENTITY.search(data, at, end))
        at = end
        if found.group(4):  # an end tag: of the root, at depth 0
            depth -= 1
            if depth < 0:
                continue
        else:
            depth += not data.endswith(b"/>", 0, end)
        tags.append((found.group(4) + found.group(5), found.end(), end))


def _attribute(tag: bytes, name: bytes) -> bytes | None:
    """The value of attribute ``name`` in a start tag's bytes, or None."""
    for found in _ATTRIBUTE.finditer(tag):
        if found.group(1) == name:
            value = found.group(2) if found.group(2) is not None else found.group(3)
            return bytes(value)
    return None


def _xacro_includes(data: bytes, tags: list[tuple[bytes, int, int]]) -> tuple[list[bytes], bool]:
    """The includes xacro surely follows, and whether the top level makes something.

    ``tags`` are those that follow the root's start tag. An include counts when it is a
    child of the root: in any other element its content could land where the URDF reader
    reads nothing (``<gazebo>``), and in a definition or a condition it may never be
    read. An ``optional`` include never counts (xacro skips it when it cannot read it,
    and drops what fails to read), and its file is no library: it may splice in a robot.
    Something: a ``<link>`` or a xacro element other than the `_DIRECTIVES`, outside the
    definitions.
    """
    named: list[bytes] = []
    depth = definitions = 0  # open elements below the root; of them, definitions
    makes = False
    for name, start, end in tags:
        if name.startswith(b"/"):  # an end tag
            depth = max(depth - 1, 0)
            if name[1:] in _DEFINITIONS:
                definitions = max(definitions - 1, 0)
            continue
        tag = data[start:end]
        if definitions == 0 and (name == b"link" or name.startswith(b"xacro:")):
            makes = makes or name not in _DIRECTIVES
        if name == b"xacro:include" and depth == 0:
            file = _attribute(tag, b"filename")
            if _attribute(tag, b"optional") is not None:  # skipped if unreadable: no fragment
                makes = True  # and no library: what it splices in is not looked at here
            elif file is not None:
                named.append(file)
        if not tag.endswith(b"/>"):
            depth += 1
            definitions += name in _DEFINITIONS
    return named, makes
