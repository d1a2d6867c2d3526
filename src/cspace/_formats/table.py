"""Every robot format cspace reads, one row each: the one place a format is declared.

The loader (which reader a file goes to), a folder's search (which files are robots),
the report's schema (``source.format``), the command line's help and the docs' lists
all come from `FORMATS`. An XML format is told by its root element (``root``); a format
that is not XML by the bytes its files begin with (``magic``), before any XML parse.

Adding a format is a reader module (a sub-package of ``_formats``, whose
``read(request)`` turns a `shared.reading.ReadRequest` into a `shared.reading.Reading`)
and a row here; ``docs/architecture.md`` walks through it. This module imports nothing of cspace, so
that every layer may read it.
"""

import importlib

from cspace._record import NamedTuple


class Format(NamedTuple):
    """One robot format.

    Attributes:
        name: Its name in reports (``source.format``) and messages.
        title: How people write it (``"URDF"``, ``"OpenUSD"``), for help and messages.
        reader: The module whose ``read(request)`` reads a file of it, imported only when
            a file is of the format. A format told by its bytes may give the module a
            ``looks_like(path, data)`` too, asked once the bytes match.
        root: The root element of its XML files, or ``""`` for a format told by ``magic``.
        magic: What its files begin with (a format that is not XML).
        binary: Those of ``magic`` that begin binary files (a crate, a zip archive):
            their bytes are not counted as XML tags (`xmlio.MAX_TAGS`); a text file of
            the format is.
        suffixes: File names that say the format, in any case. For an XML format they
            say a robot description whatever the root (xacro may wrap it), which a
            folder's search goes by; ``on_request`` rows are chosen by them.
        on_request: A file of ``root`` is read as this format only when its name has one
            of ``suffixes`` or the user asks (xacro runs code); otherwise the first row
            of that root reads it.
        srdf: An SRDF may go with the robot (MoveIt's semantic description of a URDF).
        extra: The optional dependency its reader needs (``pip install 'cspace[EXTRA]'``),
            or ``""``.
        library: The module ``extra`` installs; files of the format are left out of a
            folder's search, with a note, when it is missing.
        stores: Whose configuration vector its reports store: ``"mujoco"`` (MuJoCo's
            qpos: one angle per hinge, several joints a body) or ``"pinocchio"``.
        order: Whose joint order its reports follow: ``"mujoco"``, ``"pinocchio"`` (the
            parser's depth-first order) or ``"usd"`` (the USD reader's).
        free_bodies: A free body floats without a joint in the file (a USD stage's, as
            converters write it): its root joint, named after the body, pairs with a
            declared one in a diff.
        articulation: Isaac keeps the file's joint order within a body (a USD stage is
            Isaac's own), rather than the order of names its importers sort by.
    """

    name: str
    title: str
    reader: str
    root: str = ""
    magic: tuple[bytes, ...] = ()
    binary: tuple[bytes, ...] = ()
    suffixes: tuple[str, ...] = ()
    on_request: bool = False
    srdf: bool = False
    extra: str = ""
    library: str = ""
    stores: str = "pinocchio"
    order: str = "pinocchio"
    free_bodies: bool = False
    articulation: bool = False


FORMATS: list[Format] = [
    Format(
        "urdf", "URDF", "cspace._formats.urdf.reader", root="robot", suffixes=(".urdf",), srdf=True
    ),
    Format(
        "mjcf",
        "MJCF",
        "cspace._formats.mjcf.reader",
        root="mujoco",
        stores="mujoco",
        order="mujoco",
    ),
    Format("sdf", "SDF", "cspace._formats.sdf.reader", root="sdf", suffixes=(".sdf",)),
    Format(
        "xacro",
        "xacro",
        "cspace._formats.xacro.reader",
        root="robot",
        suffixes=(".xacro",),
        on_request=True,
        srdf=True,
    ),
    Format(
        "usd",
        "OpenUSD",
        "cspace._formats.usd.reader",
        magic=(b"#usda", b"PXR-USDC", b"PK\x03\x04"),  # a .usdz is a zip archive
        binary=(b"PXR-USDC", b"PK\x03\x04"),
        suffixes=(".usd", ".usda", ".usdc", ".usdz"),
        extra="usd",
        library="pxr",
        order="usd",
        free_bodies=True,
        articulation=True,
    ),
]
"""Every format, in the order a file is tried against them (a list, so that a test can
add a format from outside the package)."""


def by_name(name: str) -> Format:
    """The row of format ``name`` (a report's ``source.format``).

    Raises:
        KeyError: No format has that name.
    """
    for row in FORMATS:
        if row.name == name:
            return row
    raise KeyError(name)


def names() -> tuple[str, ...]:
    """Every format's name, in `FORMATS`'s order."""
    return tuple(row.name for row in FORMATS)


def titles() -> str:
    """Every format as people write them, for help texts: ``"URDF, xacro, ..."``."""
    return ", ".join(row.title for row in FORMATS)


def xml_roots() -> tuple[str, ...]:
    """The root elements of the XML formats, each once."""
    return tuple(dict.fromkeys(row.root for row in FORMATS if row.root))


def with_root(tag: str) -> list[Format]:
    """The rows of the XML formats whose root element is ``tag``."""
    return [row for row in FORMATS if row.root and row.root == tag]


def robot_suffixes() -> tuple[str, ...]:
    """Names that say an XML robot description whatever its root (lower case)."""
    return tuple(s for row in FORMATS if row.root for s in row.suffixes)


def binary() -> tuple[bytes, ...]:
    """What the binary files of every format that is not XML begin with."""
    return tuple(b for row in FORMATS for b in row.binary)


def told_by_bytes(path: str, data: bytes) -> Format | None:
    """The format ``data`` (a file's first bytes) is of, when one is told by bytes.

    Args:
        path: The file's name, for a reader whose ``looks_like`` goes by it too.
        data: The file's first bytes (a few hundred suffice).
    """
    for row in FORMATS:
        if row.magic and data.startswith(row.magic):
            looks_like = getattr(importlib.import_module(row.reader), "looks_like", None)
            if looks_like is None or looks_like(path, data):
                return row
    return None
