"""MJCF files as MuJoCo reads them: the document it is given, and its model assets.

MuJoCo's XML parser (tinyxml2) and lxml read some bytes differently: tinyxml2 ends a
DOCTYPE at its first ``>`` (in a comment of the internal subset, in a quoted system
id) and reads what follows as the document; it knows no namespaces, where lxml puts
every tag under ``xmlns="..."`` in that namespace; it keeps a tab or a line break
written in an attribute, which lxml turns into a space. So MuJoCo is never given a
file's bytes: it is given lxml's serialisation of the tree the pre-scan read
(`mujoco_document`), and a file with a DOCTYPE or a namespace is refused
(`check_plain`). Comments, processing instructions and CDATA sections do not
reach MuJoCo at all (lxml drops the first two and writes the third as text).

Model assets (``<model file>``):

MuJoCo (``mjXReader::Asset``, ``mjCModel::FindSpec``) parses every ``<model>`` asset's
file into a model of its own, attached or not, and names it:

1. the ``<model>`` element's ``name`` attribute, when it has one (``name=""`` too);
2. else the file's own ``<mujoco model>`` attribute (``model=""`` too);
3. else ``MuJoCo Model``, the name of every model whose file names none.

``<attach model="X">`` then attaches the *first* model named ``X`` among the assets of
the document it stands in (an attached model's own ``<attach>`` looks among that
model's assets, not its parent's). So that the pre-scan counts what MuJoCo builds, it
resolves names the same way, and refuses what it could not resolve exactly: two
assets of one document with the same name, a file MuJoCo would not read as MJCF, and
a document MuJoCo would read in another encoding than lxml.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from cspace._formats.shared.xmlio import line_of
from cspace.errors import InvalidElementError, UnsafeXmlError

DEFAULT_MODEL_NAME = "MuJoCo Model"
"""The name MuJoCo gives a model whose ``<model>`` element and file both name none."""

XML_MODEL_EXTENSIONS = (".xml", ".urdf")
"""The file name endings MuJoCo's ``mj_parse`` reads as XML (case as written); any other
goes to a decoder plug-in, unless ``content_type="text/xml"`` says otherwise."""

_XML_SPACE = str.maketrans({"\t": " ", "\n": " ", "\r": " "})


def name_key(name: str) -> str:
    """The name an attribute holds, as both XML readers agree on it.

    lxml (libxml2) turns a tab or line break written in an attribute into a space, as
    XML says; MuJoCo's tinyxml2 keeps it. MuJoCo is given lxml's serialisation, where
    such a character stands as a reference (``&#9;``) that both read alike; two names
    equal for MuJoCo are equal here all the same.
    """
    return name.translate(_XML_SPACE)


def file_key(name: str) -> str:
    r"""The key MuJoCo finds a file it is given by: its base name, in lower case.

    MuJoCo matches the files given in memory by base name (after the last ``/`` or
    ``\``), whatever the case: ``sub/Part.xml`` finds ``other/part.xml``.
    """
    return name.replace("\\", "/").rsplit("/", 1)[-1].lower()


def mujoco_document(root: etree._Element) -> str:
    """The document MuJoCo is given: the tree lxml read, serialised by lxml.

    Both parsers then read the same elements and attributes by construction. The root
    starts on the line it stood on (what stood before it, a declaration or comments,
    is blank lines), so that MuJoCo's line numbers are the file's wherever no start
    tag, comment or character reference spread over several lines came before.
    """
    text = etree.tostring(root, encoding="unicode", with_tail=False)
    return "\n" * ((line_of(root) or 1) - 1) + text


def original_line(
    root: etree._Element, data: bytes, text: str, line: int, by_name: bool, named: str | None
) -> int | None:
    """The file's line of the element MuJoCo names at ``line`` of `mujoco_document`.

    Serialising moves lines where a start tag, a comment or a character reference
    spread over several: the serialised document is parsed again and walked with the
    file's, element by element. Only an error costs this.

    Args:
        root: The file's root element, as read.
        data: The file's bytes.
        text: The document MuJoCo was given (``mujoco_document(root)``).
        line: The line MuJoCo names, in ``text``.
        by_name: Whether MuJoCo names the element by its name (else by its tag).
        named: The name (``""`` for an unnamed element) or tag MuJoCo gives, or None
            (any element at that line).

    Returns:
        The line the element's start tag begins on in the file, as MuJoCo would have
        said; None when no such element starts at ``line`` (MuJoCo meant another file).
    """
    if line <= 0:
        return None
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    try:
        again = etree.fromstring(text.encode("utf-8"), parser)
    except etree.XMLSyntaxError:  # lxml reads what it wrote; nothing to map otherwise
        return None
    found: etree._Element | None = None
    later = 0  # elements of its tag after it whose start tags end on its line
    copies = again.iter(tag=etree.Element)  # the same elements, in the same order
    for element, copy in zip(root.iter(tag=etree.Element), copies, strict=False):
        if found is not None:
            if line_of(element) != line_of(found):
                break
            later += element.tag == found.tag
        elif copy.sourceline == line and _is(copy, by_name, named):
            found = element
    return None if found is None else _start_line(data, found, later)


def _is(element: etree._Element, by_name: bool, named: str | None) -> bool:
    """Whether ``element`` is the one MuJoCo names (a replicated copy's name ends in digits)."""
    if named is None:
        return True
    if not by_name:
        return element.tag == named
    name = element.get("name") or ""
    return named == name or (bool(name) and named.startswith(name) and named[len(name) :].isdigit())


_AFTER_TAG = frozenset(b" \t\r\n/>")


def _start_line(data: bytes, element: etree._Element, later: int) -> int | None:
    """The line ``element``'s start tag begins on (lxml gives the line it ends on).

    A start tag holds no ``<``: it is the last ``<tag`` before the end of that line,
    but for the ``later`` elements of the same tag whose start tags end on it too.
    """
    line = line_of(element)
    if line is None:
        return None
    end = 0
    for _ in range(line):
        end = data.find(b"\n", end) + 1
        if end == 0:
            end = len(data)
            break
    opening = b"<" + str(element.tag).encode("utf-8")
    at, left = end, later + 1
    while left:
        at = data.rfind(opening, 0, at)
        if at < 0:
            return line
        after = at + len(opening)
        left -= after < len(data) and data[after] in _AFTER_TAG
    return data.count(b"\n", 0, at) + 1


@dataclass(eq=False)
class ModelAsset:
    """One ``<model file>`` asset, read by the pre-scan.

    Attributes:
        element: The ``<model>`` element.
        root: Its file's ``<mujoco>`` element.
        file: Its file, as the document names it.
        where: The file the ``<model>`` element stands in (None: the main file).
        name: The name MuJoCo gives it.
        assets: The model assets of its own file (and of the files it includes), by
            `name_key`: what its own ``<attach>`` elements may name.
    """

    element: etree._Element
    root: etree._Element
    file: str
    where: str | None
    name: str
    assets: dict[str, ModelAsset] = field(default_factory=dict)


def effective_name(element: etree._Element, root: etree._Element) -> tuple[str, str]:
    """The name MuJoCo gives the model of a ``<model>`` element, and where it comes from."""
    if "name" in element.attrib:
        return str(element.get("name")), "its name attribute"
    if "model" in root.attrib:
        return str(root.get("model")), "its file's <mujoco model>"
    return DEFAULT_MODEL_NAME, "MuJoCo's name for a model whose file names none"


def where_text(file: str | None, element: etree._Element) -> str:
    """``line N`` of the main file, or ``FILE, line N`` of an included one."""
    line = line_of(element)
    at = f"line {line}" if line is not None else "an unknown line"
    return at if file is None else f"{file}, {at}"


def fail_in(
    path: str, file: str | None, code: str, problem: str, element: etree._Element
) -> InvalidElementError:
    """The error about ``element``, which stands in ``file`` (None: the main file).

    An element of the main file is located by the error's line; one of an included or
    attached file says which file and line in the message (the error's line is the
    main file's).
    """
    if file is None:
        return InvalidElementError(
            path, problem, code=code, line=line_of(element), element=str(element.tag)
        )
    return InvalidElementError(
        path, f"{problem} (in {where_text(file, element)})", code=code, element=str(element.tag)
    )


def check_model_file(
    path: str, where: str | None, element: etree._Element, name: str, root: etree._Element
) -> None:
    """Refuse a ``<model>`` file MuJoCo would not read as an MJCF document.

    Raises:
        InvalidElementError: A name MuJoCo hands to a decoder plug-in (``bad-include``),
            or a root that is not ``<mujoco>`` (``unsupported-element``): MuJoCo reads a
            ``<robot>`` with its URDF importer, whose bodies the pre-scan does not count.
    """
    dot = name.rfind(".")
    ending = name[dot:] if dot >= 0 else ""
    if ending not in XML_MODEL_EXTENSIONS and element.get("content_type") != "text/xml":
        raise fail_in(
            path,
            where,
            "bad-include",
            f'<model file="{name}">: MuJoCo reads a model file as XML only when its name '
            "ends in .xml or .urdf (or content_type is text/xml); cspace reads no other",
            element,
        )
    if root.tag != "mujoco":
        shown = root.tag if isinstance(root.tag, str) else "?"
        raise fail_in(
            path,
            where,
            "unsupported-element",
            f'<model file="{name}"> holds <{shown}>, not <mujoco>: cspace attaches only MJCF '
            "models (MuJoCo would import any other, a URDF <robot> too, uncounted)",
            element,
        )


def register(path: str, assets: dict[str, ModelAsset], model: ModelAsset, how: str) -> None:
    """Add ``model`` to the assets of the document it stands in.

    Raises:
        InvalidElementError: Another asset of that document has the same name
            (``bad-include``): MuJoCo would attach the first wherever either is named.
    """
    key = name_key(model.name)
    other = assets.get(key)
    if other is not None:
        raise fail_in(
            path,
            model.where,
            "bad-include",
            f'<model file="{model.file}"> is named "{model.name}" ({how}), like '
            f'<model file="{other.file}"> ({where_text(other.where, other.element)}): '
            "MuJoCo would attach the first of them wherever that name is used; give each "
            "model a name of its own",
            model.element,
        )
    assets[key] = model


def check_encoding(path: str, where: str | None, root: etree._Element, data: bytes) -> None:
    """Refuse a document MuJoCo would read in another encoding than lxml did.

    MuJoCo's XML parser reads bytes as UTF-8 whatever the document declares; lxml
    follows the declaration. Two names MuJoCo reads as one (bytes E9 and EA of a
    Latin-1 file both become U+FFFD) would be two here, and an ``<attach>`` could then
    be counted for one model and build another.

    Raises:
        InvalidElementError: Not ASCII, and not UTF-8 as lxml read it
            (``unsupported-encoding``).
    """
    if data.isascii() and b"\0" not in data:  # UTF-16 of ASCII text is ASCII bytes too
        return
    encoding = (root.getroottree().docinfo.encoding or "").lower().replace("_", "-")
    if b"\0" in data or encoding not in ("utf-8", "utf8"):  # UTF-16 or UTF-32 holds NULs
        said = "is UTF-16 or UTF-32" if b"\0" in data else f"declares {encoding or '?'}"
        raise fail_in(
            path,
            where,
            "unsupported-encoding",
            f"the file {said}, not UTF-8: MuJoCo reads every MJCF file as UTF-8, so the "
            "names it reads would not be the names cspace reads",
            root,
        )


def check_plain(path: str, where: str | None, root: etree._Element, data: bytes | None) -> None:
    """Refuse a file MuJoCo's XML parser would read otherwise than lxml did.

    ``data`` is the file's bytes, when at hand: for the DOCTYPE's line, and to skip the
    walk for namespace declarations when it holds none.

    Raises:
        UnsafeXmlError: A DOCTYPE (tinyxml2 ends it at its first ``>`` and reads what
            follows, a document lxml never saw), or a namespace declaration or a
            namespaced element or attribute (MuJoCo knows no namespaces: an
            ``<include>`` under ``xmlns="urn:x"`` is one to MuJoCo, not to lxml)
            (``xml-unsafe``).
    """
    info: Any = root.getroottree().docinfo  # the stubs lack doctype
    if info.doctype or info.internalDTD is not None:
        at = -1 if data is None else data.find(b"<!DOCTYPE")
        line = None if data is None or at < 0 else data.count(b"\n", 0, at) + 1
        raise _unsafe_in(
            path,
            where,
            "the file has a DOCTYPE; MuJoCo's XML parser ends one at its first '>' and "
            "would read another document than cspace does",
            line,
            "DOCTYPE",
        )
    # A declaration is spelt "xmlns" (no reference can write a name); the "xml:" prefix
    # needs none. Elements in a namespace are also refused where the pre-scan walks.
    if data is None or b"xmlns" in data or b"xml:" in data or b"\0" in data:
        for element in root.iter(tag=etree.Element):
            if element.nsmap or _in_namespace(element):
                raise namespaced(path, where, element)


def _in_namespace(element: etree._Element) -> bool:
    """Whether an element or one of its attributes is in a namespace (lxml's ``{uri}name``)."""
    return str(element.tag).startswith("{") or any(
        str(key).startswith("{") for key in element.attrib
    )


def namespaced(path: str, where: str | None, element: etree._Element) -> UnsafeXmlError:
    """The error about an element in a namespace, or declaring one."""
    shown = etree.QName(element).localname
    return _unsafe_in(
        path,
        where,
        f"<{shown}> declares or uses an XML namespace; MuJoCo knows no namespaces, so it "
        "would read other elements than cspace does",
        line_of(element),
        shown,
    )


def _unsafe_in(
    path: str, where: str | None, problem: str, line: int | None, element: str
) -> UnsafeXmlError:
    """An `UnsafeXmlError` at ``line`` of ``where`` (None: the main file)."""
    if where is None:
        return UnsafeXmlError(path, problem, line=line, element=element)
    at = f"line {line}" if line is not None else "an unknown line"
    return UnsafeXmlError(path, f"{problem} (in {where}, {at})", element=element)


def model_folder(folder: str, name: str) -> str:
    """The folder an attached model's own includes resolve from, as MuJoCo resolves them."""
    return os.path.dirname(os.path.join(folder, name))
