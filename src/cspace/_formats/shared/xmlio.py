"""Reading robot files safely: regular files only, read once, bounded, no entities, no network.

Robot files arrive from anywhere (CI runs `cspace` on files nobody has read yet), so the
XML parser is configured to do nothing but parse: entity declarations are refused
outright (no "billion laughs", no ``<!ENTITY x SYSTEM "file:///...">``), no DTD is
loaded, nothing is fetched, and the file's size is checked before it is read.
"""

# Python's built-in SHA-256 loads faster than OpenSSL's (which hashlib loads), and
# gives the same digest; Python 3.12 moved it from _sha256 to _sha2.
try:
    from _sha256 import sha256  # type: ignore[import-not-found,unused-ignore]
except ImportError:
    try:
        from _sha2 import sha256  # type: ignore[import-not-found,unused-ignore]
    except ImportError:  # a Python built without its own hashes
        from hashlib import sha256
import os
import re
from collections.abc import Sequence
from typing import Any, NoReturn

from lxml import etree

from cspace._paths import allowed_folders as allowed_folders  # re-exported: includes use it
from cspace._paths import within as within
from cspace._record import NamedTuple
from cspace.errors import (
    FileUnreadableError,
    InvalidElementError,
    UnknownJointTypeError,
    UnsafeXmlError,
    XmlSyntaxError,
)
from cspace.files import path_text as path_text
from cspace.files import read_input

MAX_FILE_BYTES = 64 * 1024 * 1024
"""Largest robot file `cspace` reads (64 MiB); real URDFs are well under 10 MiB."""

MAX_TAGS = 250_000
"""Most XML tags (counted as ``<`` bytes) in a file `cspace` parses. A parsed element
costs lxml a few hundred bytes, so 64 MiB of tiny elements would take gigabytes; real
robot files have a few thousand tags (example-robot-data's largest, about 5,500)."""


MAX_FILES = 256
"""Most files read for one robot (the main file and every MJCF include, counted each time
it is included); real robots have a few dozen."""

MAX_ATTRIBUTES = 256
"""Most attributes on one element. Robot files use a handful (MJCF's richest elements,
a few dozen); lxml reads an element's attribute values in time quadratic in their
number, and so does Pinocchio's parser, so 300,000 on one element would take minutes."""


class SourceFile(NamedTuple):
    """A robot file's bytes, read once.

    Attributes:
        path: The path as the caller gave it (``-`` for standard input).
        data: The file's bytes.
        sha256: Hex SHA-256 of ``data``.
    """

    path: str
    data: bytes
    sha256: str

    @property
    def text(self) -> str:
        """The file decoded as UTF-8 (invalid bytes replaced)."""
        return self.data.decode("utf-8", errors="replace")


def read_source(
    path: str | os.PathLike[str],
    *,
    max_bytes: int = MAX_FILE_BYTES,
    budget: "ReadBudget | None" = None,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    what: str = "robot file",
) -> SourceFile:
    """Read a robot file once, refusing what cannot be a robot file.

    The file is opened without blocking and checked through the open descriptor
    (``fstat``): only a regular file is read (after following symbolic links), so a FIFO,
    a device or a socket is refused at once instead of hanging or streaming forever, and
    what is read is what was checked. A link must lead to a file inside the folder it
    stands in (or in one of ``allow_dirs``): a committed ``robot.urdf -> /etc/passwd``
    is refused unread.

    Args:
        path: File to read (``str`` or ``os.PathLike``).
        max_bytes: Refuse files larger than this many bytes.
        budget: The run's budget, when this file is one of several read for one robot
            (MJCF includes): its bytes and tags are counted against the run's total.
        allow_dirs: Folders, besides the file's own, that a link may lead into.
        what: What the file is, for messages (``package.xml`` read for xacro).

    Returns:
        The file's bytes and their hash; ``path`` is the name as given.

    Raises:
        FileUnreadableError: Missing, not a regular file, empty, too large, unreadable,
            a link out of its folder, or over the run's budget.
    """
    name = path_text(path)
    data = read_input(name, max_bytes=max_bytes, allow_dirs=allow_dirs, what=what)
    source = source_from_bytes(name, data, max_bytes=max_bytes)
    if budget is not None:
        budget.charge(source)
    return source


class ReadBudget:
    """What one run may read in all, counted across every file it reads for one robot.

    One robot can be many files (MJCF ``<include>``, each occurrence counted again, since
    an include is spliced in where it stands); the per-file limits alone would let ten
    includes a file, eight levels deep, reach gigabytes. Every file read for the robot is
    charged here, the main file included.

    Attributes:
        path: The robot file the run is about, for messages.
        files: Files read so far.
        bytes: Bytes read so far.
        tags: XML tags (``<`` bytes) read so far.
    """

    def __init__(
        self,
        path: str,
        *,
        max_files: int = MAX_FILES,
        max_bytes: int = MAX_FILE_BYTES,
        max_tags: int = MAX_TAGS,
    ) -> None:
        self.path = path
        self.files = 0
        self.bytes = 0
        self.tags = 0
        self._limits = (max_files, max_bytes, max_tags)

    def charge(self, source: SourceFile) -> None:
        """Count one more file read for this run.

        Raises:
            FileUnreadableError: The run has now read more files, bytes or tags than its
                limits allow (named against the robot file, with the file that tipped it).
        """
        self.files += 1
        self.bytes += len(source.data)
        self.tags += source.data.count(b"<")
        max_files, max_bytes, max_tags = self._limits
        over = (
            (self.files > max_files, f"{max_files:,} files"),
            (self.bytes > max_bytes, f"{max_bytes:,} bytes"),
            (self.tags > max_tags, f"{max_tags:,} XML tags"),
        )
        for exceeded, what in over:
            if exceeded:
                raise FileUnreadableError(
                    self.path,
                    f"reading '{source.path}' takes the robot past {what} in all its files "
                    "(includes counted each time they are included); cspace reads no more",
                    code="too-much-input",
                )


def source_from_bytes(path: str, data: bytes, *, max_bytes: int = MAX_FILE_BYTES) -> SourceFile:
    """Wrap bytes already read (e.g. from standard input) as a source file.

    Raises:
        FileUnreadableError: Empty or larger than ``max_bytes``.
    """
    if len(data) > max_bytes:
        raise FileUnreadableError(path, f"input is larger than the {max_bytes:,}-byte limit")
    if not data.strip():
        raise FileUnreadableError(path, "file is empty")
    from cspace._formats.table import binary

    tags = 0 if data.startswith(binary()) else data.count(b"<")  # a crate's bytes are no tags
    if tags > MAX_TAGS:
        raise FileUnreadableError(
            path,
            f"file has {tags:,} XML tags, more than the {MAX_TAGS:,} cspace parses "
            "(robot files have far fewer)",
        )
    return SourceFile(path=path, data=data, sha256=sha256(data).hexdigest())


def _parser() -> etree.XMLParser:
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_comments=True,
        remove_pis=True,
    )


def parse_xml(source: SourceFile) -> etree._Element:
    """Parse a source file as XML, safely.

    Returns:
        The root element; elements carry ``sourceline``.

    Raises:
        XmlSyntaxError: Not well-formed (with line and column).
        UnsafeXmlError: The document declares entities.
    """
    data = lenient_bytes(source.data)
    if xml_version(data) not in (None, "1.0", "1.1"):
        # pybullet's Minitaur family declares version="0.0"; urdfdom and Pinocchio read
        # such files, libxml2 refuses them: read as 1.0 (the readers say so, a finding).
        data = _VERSION.sub(b"\\g<1>1.0\\g<2>", data, count=1)
    try:
        root = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as exc:
        declared = re.search(_ENTITY_DECLARATION, source.data)
        if declared is not None:  # e.g. "billion laughs": refused for what it is
            raise _unsafe(source, declared.group(1).decode("utf-8", "replace")) from None
        line, column = exc.position if exc.position else (exc.lineno, None)
        message = " ".join((exc.msg or "not well-formed XML").split(", line ")[0].split())
        raise XmlSyntaxError(
            source.path,
            _syntax_problem(message, source.data, line, column),
            line=line or None,
            column=column,
        ) from None
    if root is None:
        raise XmlSyntaxError(source.path, "no XML document", line=None, column=None)
    for element in root.iter(tag=etree.Element):
        if len(element.attrib) > MAX_ATTRIBUTES:  # len() is cheap; reading them is not
            raise FileUnreadableError(
                source.path,
                f"element <{element.tag}> has {len(element.attrib):,} attributes, more than "
                f"the {MAX_ATTRIBUTES} cspace reads on one element (robot files have a few)",
                line=line_of(element),
                element=str(element.tag),
            )
    dtd: Any = root.getroottree().docinfo.internalDTD
    if dtd is not None:
        for entity in dtd.iterentities():
            raise _unsafe(source, str(entity.name))
        declared = re.search(_DTD_DECLARATION, source.data)
        if declared is not None:
            # An <!ATTLIST> default would change what the file says for our reader,
            # but not for Pinocchio's parser (which ignores DTDs): refuse both.
            kind, name = (g.decode("utf-8", "replace") for g in declared.groups())
            raise UnsafeXmlError(
                source.path,
                f"declares <!{kind} {name}> in a DTD; robot files must not carry DTD "
                "declarations (their attribute defaults would be read one way by cspace "
                "and another by Pinocchio)",
                line=_line_of_bytes(source.data, declared.group(0)),
                element=name,
            )
    return root


_LATE_DECLARATION = re.compile(rb"\A((?:\xef\xbb\xbf)?\s+)(<\?xml\s[^>]*\?>)")
# The patterns of rarer cases are compiled on first use, through `re`'s cache.
_DECLARED_ENCODING = rb"""encoding\s*=\s*["']([^"']*)["']"""
_TRAILING_NULS = rb"\x00[\x00\s]*\Z"
"""NUL bytes (and white space) that end a file."""


def lenient_bytes(data: bytes) -> bytes:
    """``data`` as urdfdom reads it, where XML is stricter, line numbers kept.

    Two leniencies pybullet's files rely on: white space before the XML declaration
    (the declaration is blanked out: without it, XML reads the same text, when it
    declares UTF-8 or nothing) and NUL bytes after the root element (urdfdom reads a C
    string, which ends at the first NUL: they are cut). `leniencies` says which apply.
    """
    late = _LATE_DECLARATION.match(data)
    if late is not None:
        encoding = re.search(_DECLARED_ENCODING, late.group(2))
        if encoding is None or encoding.group(1).lower() in (
            b"utf-8",
            b"utf8",
            b"us-ascii",
            b"ascii",
        ):
            blank = bytes(b if b in b"\r\n" else 0x20 for b in late.group(2))
            data = late.group(1) + blank + data[late.end() :]
    cut = _nul_tail(data)
    return data if cut is None else data[:cut]


def _nul_tail(data: bytes) -> int | None:
    """Where the NUL bytes at the end of ``data`` start, when they are its only NULs.

    A file in UTF-16 or UTF-32 holds NULs throughout (and may end in one): not cut.
    """
    first = data.find(b"\x00")
    if first < 0:
        return None
    found = re.compile(_TRAILING_NULS).match(data, first)
    return first if found is not None else None


def leniencies(data: bytes) -> list[str]:
    """What `lenient_bytes` forgave in ``data``, one sentence each."""
    said = []
    late = _LATE_DECLARATION.match(data)
    if late is not None and lenient_bytes(data[: late.end()]) != data[: late.end()]:
        said.append(
            "white space comes before the XML declaration, which XML forbids and urdfdom "
            "allows: read without the declaration"
        )
    if _nul_tail(data) is not None:
        said.append("NUL bytes follow the document, which urdfdom stops at: read without them")
    return said


_DTD_DECLARATION = rb"<!(ATTLIST|ELEMENT)\s+([^\s<>\"']+)"
_VERSION = re.compile(rb"""\A(\s*<\?xml\s+version\s*=\s*["'])[^"']*(["'])""")


def xml_version(data: bytes) -> str | None:
    """The version an XML declaration at the start of ``data`` gives, or None."""
    found = _VERSION.match(data)
    if found is None:
        return None
    end = found.end(1)
    return data[end : data.index(found.group(2), end)].decode("ascii", "replace")


_ENTITY_DECLARATION = rb"<!ENTITY\s+(?:%\s+)?([^\s<>\"']+)"


def _unsafe(source: SourceFile, entity: str) -> UnsafeXmlError:
    return UnsafeXmlError(
        source.path,
        f"declares the XML entity '{entity}'; "
        "robot files must not use entities (they are never expanded)",
        line=_line_of_bytes(source.data, b"<!ENTITY"),
        element=entity,
    )


def _line_of_bytes(data: bytes, needle: bytes) -> int | None:
    at = data.find(needle)
    return None if at < 0 else data.count(b"\n", 0, at) + 1


def _syntax_problem(message: str, data: bytes, line: int | None, column: int | None) -> str:
    """libxml2's message, with what it means for a robot file when that is clearer."""
    last_line = data.rsplit(b"\n", 1)[-1]
    end_line = data.count(b"\n") + 1
    at_end = line is not None and (
        line > end_line or (line == end_line and (column or 0) >= len(last_line))
    )
    if message.startswith(("Start tag expected", "Document is empty")):
        if at_end:
            return "no XML element: the file holds only a declaration, comments or white space"
        return f"not XML ({message})"
    if "encoding" in message.lower() or "utf-8" in message.lower():
        return (
            f"XML syntax error: {message} (the file is not in the encoding it declares; "
            "without a declaration that is UTF-8)"
        )
    if message.startswith("Extra content at the end of the document"):
        return (
            "content follows the root element's end (a second root element, or stray "
            f"text): a robot file holds one element ({message})"
        )
    if at_end:
        return f"the XML ends before the document is complete: the file is truncated ({message})"
    return f"XML syntax error: {message}"


def line_of(element: etree._Element | None) -> int | None:
    """The 1-based line an element starts on, or None when unknown (or no element)."""
    if element is None:
        return None
    line: Any = element.sourceline
    return line if isinstance(line, int) else None


def fail_at(
    path: str, code: str, problem: str, element: etree._Element, name: str | None = None
) -> NoReturn:
    """Raise the one error of a malformed element: the file, its line, the problem, a code.

    Every format reader reports a bad element through this.

    Raises:
        InvalidElementError: Always.
    """
    raise InvalidElementError(path, problem, code=code, line=line_of(element), element=name)


def check_joint_type(
    path: str, name: str, joint_type: str, valid: Sequence[str], element: etree._Element
) -> None:
    """Refuse a joint type the format does not define, naming the ones it does.

    Raises:
        UnknownJointTypeError: ``joint_type`` is not in ``valid``.
    """
    if joint_type not in valid:
        raise UnknownJointTypeError(
            path, joint=name, joint_type=joint_type, valid_types=valid, line=line_of(element)
        )
