"""The formats told by their bytes, not by an XML root element: one row each.

XML formats (URDF, xacro, MJCF, SDF) are told by their root element
(``loader.FORMATS_BY_ROOT_TAG``). A format that is not XML is told here, by a look at
its first bytes, before any XML parse; its reader is imported only when a file is of it.
Adding one is a module with ``looks_like(path, data)`` and ``read(path, file, allowed)``,
and a row of `BY_CONTENT`.
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from typing import NamedTuple

from cspace._formats.shared.reading import Reading


class ContentFormat(NamedTuple):
    """A format told by its bytes.

    Attributes:
        name: The format's name in reports (``source.format``).
        module: The reader's module, imported when a file is of the format.
    """

    name: str
    module: str


BY_CONTENT = (ContentFormat("usd", "cspace._formats.usd.reader"),)
"""Every format told by its bytes, in the order they are tried."""

_MAGIC = {"usd": (b"#usda", b"PXR-USDC", b"PK\x03\x04")}
"""What each format's files begin with (a ``.usdz`` is a zip archive)."""


def format_of(path: str, data: bytes) -> ContentFormat | None:
    """The format ``data`` is of, when it is one of `BY_CONTENT`, else None."""
    for row in BY_CONTENT:
        if data.startswith(_MAGIC[row.name]):
            module = importlib.import_module(row.module)
            if module.looks_like(path, data):
                return row
    return None


def read(row: ContentFormat, path: str, file: str, allowed: Sequence[str]) -> Reading:
    """Read ``file`` (named ``path`` by the user) with ``row``'s reader."""
    reader = importlib.import_module(row.module).read
    result: Reading = reader(path, file, allowed)
    return result
