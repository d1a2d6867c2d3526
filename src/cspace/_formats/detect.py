"""Which format a parsed XML robot file is of: its root element, and xacro asked for.

xacro runs code, so a ``<robot>`` is expanded as xacro only when the user asks for it:
a ``.xacro`` file name, or ``force_xacro`` (``--xacro``); a ``<robot>`` that uses xacro
without that is refused (`detect`), never expanded and never read as plain URDF.
"""

from __future__ import annotations

from lxml import etree

from cspace._formats.shared.roots import FRAGMENT_ROOTS
from cspace._formats.shared.xmlio import line_of
from cspace._formats.table import FORMATS, Format, with_root
from cspace.errors import NotARobotError, XacroNotRequestedError

XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"
"""The namespace of xacro's elements (``xmlns:xacro``)."""


def detect(
    path: str, root: etree._Element, *, force_xacro: bool = False, data: bytes | None = None
) -> Format:
    """The format of a parsed robot file, from its root element (`table.FORMATS`).

    A root is read by the first row of that root, unless the file's name has the
    suffix of a row read only on request (xacro) or ``force_xacro`` asks for it; a file
    read otherwise that uses xacro is refused, never expanded and never read as plain
    URDF.

    Args:
        path: The file's name (a ``.xacro`` name asks for xacro expansion).
        root: The parsed root element.
        force_xacro: The user asked for xacro expansion whatever the name.
        data: The bytes ``root`` was parsed from, if at hand: a file in which no xacro
            use can hide (see `_may_use_xacro`) is not searched.

    Raises:
        NotARobotError: The root element is not one of a robot format, or xacro was
            asked for on a file that is not a ``<robot>``.
        XacroNotRequestedError: A ``<robot>`` uses xacro but expansion was not asked for.
    """
    tag = root.tag if isinstance(root.tag, str) else ""
    rows = with_root(tag)
    if tag in FRAGMENT_ROOTS:
        raise NotARobotError(
            path,
            f"an MJCF fragment (<{tag}>), checked as part of the model that includes it: "
            "inspect that model",
            code="mjcf-fragment",
            line=line_of(root),
            element=tag,
        )
    if not rows:
        expected = ", ".join(
            f"<{r.root}> ({r.name.upper()})" for r in FORMATS if r.root and not r.on_request
        )
        raise NotARobotError(
            path,
            f"root element <{tag}> is not a robot description (expected {expected})",
            line=line_of(root),
            element=tag,
        )
    plain = next((r for r in rows if not r.on_request), rows[0])
    asked = [r for r in rows if r.on_request]
    if not asked:
        if force_xacro:
            raise NotARobotError(
                path,
                f"--xacro expands <robot> files, and this one is <{tag}>",
                line=line_of(root),
                element=tag,
            )
        return plain
    for row in asked:
        if force_xacro or path.endswith(row.suffixes):  # as written: xacro's own test
            return row
    used = _xacro_use(root) if data is None or _may_use_xacro(root, data) else None
    if used is not None:
        element, what = used
        raise XacroNotRequestedError(
            path,
            f"the file uses xacro ({what}); xacro runs code, so cspace expands it only for "
            "files named *.xacro or with --xacro",
            line=line_of(element),
            element=str(element.tag),
        )
    return plain


_ASCII_SUPERSETS = frozenset(
    ("utf-8", "utf8", "ascii", "us-ascii", "iso-8859-1", "latin1", "latin-1")
)
"""Encodings in which the ASCII markers of `_XACRO_MARKERS` are their ASCII bytes."""

_XACRO_MARKERS = (b"${", b"$(", XACRO_NAMESPACE.encode(), b"xacro:", b"&#")
"""What xacro use needs in a file's bytes: a substitution, xacro's namespace, an element
named ``xacro:...`` (xacro goes by the name, whatever namespace the prefix is bound to),
or a character reference that could spell any of them."""


def _may_use_xacro(root: etree._Element, data: bytes) -> bool:
    """False when the bytes rule out every use `_xacro_use` looks for.

    A search of the bytes in C is far cheaper than the XPath query over every attribute
    (25 ms at 4,000 joints). It rules out only what it can: in an encoding that is not
    ASCII's superset (UTF-16, say, declared or not) the markers are other bytes, so the
    query runs.
    """
    if b"\x00" in data:  # UTF-16 or UTF-32, which libxml2 detects with no declaration
        return True
    encoding = (root.getroottree().docinfo.encoding or "").lower().replace("_", "-")
    if encoding not in _ASCII_SUPERSETS:  # the declared encoding (UTF-8 when none)
        return True
    return any(marker in data for marker in _XACRO_MARKERS)


def _xacro_use(root: etree._Element) -> tuple[etree._Element, str] | None:
    """The first element of xacro's or attribute with a substitution, and what it is.

    Declaring ``xmlns:xacro`` alone does not count: URDF that xacro generated keeps the
    declaration and is plain URDF.
    """
    # One XPath query in libxml2 (document order) instead of a walk in Python: the first
    # element in xacro's namespace or named xacro:..., or the first attribute holding ${
    # or $(.
    found = _XACRO_USE(root, ns=XACRO_NAMESPACE)
    if not isinstance(found, list) or not found:
        return None
    first = found[0]
    if isinstance(first, etree._Element):
        tag = str(first.tag)
        return first, f"<xacro:{tag[tag.index('}') + 1 :]}>"
    if not isinstance(first, etree._ElementUnicodeResult):
        return None
    element = first.getparent()  # an attribute value (a "smart string") knows its element
    if element is None:
        return None
    text = str(first)
    start = min(i for i in (text.find("${"), text.find("$(")) if i >= 0)
    end = text.find("}" if text[start + 1] == "{" else ")", start)
    shown = text[start : end + 1] if 0 <= end - start < 60 else text[start : start + 60]
    return element, (
        f"attribute '{first.attrname!s}' of <{element.tag}> still holds the substitution "
        f"'{shown}': the file was meant to be processed by xacro (or roslaunch) first"
    )


_XACRO_USE = etree.XPath(
    "(//*[namespace-uri() = $ns or starts-with(name(), 'xacro:')]"
    " | //@*[contains(., '${') or contains(., '$(')])[1]",
    smart_strings=True,
)
"""The first element of xacro's (in its namespace, or named ``xacro:...`` as xacro finds
them: many files bind the prefix to ``http://ros.org/wiki/xacro``), or the first
attribute holding a substitution."""
