"""MJCF model assets (``<model file>``): which file MuJoCo reads as which model, and by what name.

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

from lxml import etree

from cspace.errors import InvalidElementError
from cspace.formats.xmlio import line_of

DEFAULT_MODEL_NAME = "MuJoCo Model"
"""The name MuJoCo gives a model whose ``<model>`` element and file both name none."""

XML_MODEL_EXTENSIONS = (".xml", ".urdf")
"""The file name endings MuJoCo's ``mj_parse`` reads as XML (case as written); any other
goes to a decoder plug-in, unless ``content_type="text/xml"`` says otherwise."""

_XML_SPACE = str.maketrans({"\t": " ", "\n": " ", "\r": " "})


def name_key(name: str) -> str:
    """The name an attribute holds, as both XML readers agree on it.

    lxml (libxml2) turns a tab or line break written in an attribute into a space, as
    XML says; MuJoCo's tinyxml2 keeps it. Two names equal for MuJoCo are equal here.
    """
    return name.translate(_XML_SPACE)


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
            :func:`name_key`: what its own ``<attach>`` elements may name.
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
    if data.isascii():
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


def model_folder(folder: str, name: str) -> str:
    """The folder an attached model's own includes resolve from, as MuJoCo resolves them."""
    return os.path.dirname(os.path.join(folder, name))
