"""Robot descriptions found by what they are, among the files of a folder.

A folder given to ``cspace inspect`` stands for the robot files in it: ``.urdf``,
``.xacro`` and ``.sdf`` files, and any file whose root element is ``<robot>``,
``<mujoco>`` or ``<sdf>`` (the first `PEEK_BYTES` are read, no further). A fragment is
left to the description that includes it: a ``<mujocoinclude>`` file; a ``<mujoco>``
file that another file of the folder includes (``<include file=...>``) or attaches
(``<model file=...>``), relative to the including file's folder; a xacro file that
another includes (``<xacro:include filename=...>``, relative, or ``$(find PKG)/PATH``
for any file of the folder whose path ends in ``/PATH``), and a xacro macro library
(macros, and no ``<link>`` outside them, in its first `PEEK_BYTES`).
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence

PEEK_BYTES = 64 << 10
"""Most bytes read of each file to find its root element (a long licence comment first)."""

ROBOT_SUFFIXES = (".urdf", ".xacro", ".sdf")
"""Names that say a robot description whatever the root (xacro may wrap it)."""

FRAGMENT_ROOTS = ("mujocoinclude",)
"""Root elements of files meant only to be included."""

_ROOTS = ("robot", "mujoco", "sdf")
_PROLOGUE = re.compile(
    rb"\s*(?:<\?[^>]*\?>|<!--.*?-->|<!DOCTYPE[^>]*>\s*)*\s*<([A-Za-z_][\w.:-]*)", re.S
)
_INCLUDED = re.compile(rb"<(?:include|model)\b[^>]*?\bfile\s*=\s*[\"']([^\"']+)[\"']")
_XACRO_INCLUDED = re.compile(rb"<xacro:include\b[^>]*?\bfilename\s*=\s*[\"']([^\"']+)[\"']")
_FIND = re.compile(r"^\$\((?:find|find-pkg-share)\s+[^)]*\)")
_MACRO = re.compile(rb"<xacro:macro\b.*?</xacro:macro\s*>", re.S)


def _macros_only(head: bytes) -> bool:
    """A xacro macro library: macros, and no ``<link>`` outside them."""
    rest, found = _MACRO.subn(b"", head)
    return found > 0 and b"<link" not in rest


def _head(path: str) -> bytes:
    """The first `PEEK_BYTES` of a file, through `open_input` (a link out, a fifo: none)."""
    from cspace.errors import FileUnreadableError
    from cspace.files import open_input

    try:
        with open_input(path, max_bytes=None, what="robot file") as stream:
            return stream.read(PEEK_BYTES)
    except (FileUnreadableError, OSError):
        return b""


def root_tag(data: bytes) -> str | None:
    """The root element's name in the first bytes of an XML file, or None."""
    found = _PROLOGUE.match(data.removeprefix(b"\xef\xbb\xbf"))
    return found.group(1).decode("ascii", "replace") if found else None


def robot_files(paths: Sequence[str]) -> list[str]:
    """The robot descriptions among ``paths`` (files of one walk), in their order.

    Args:
        paths: Files, as a folder's walk names them.
    """
    heads = {path: _head(path) for path in paths}
    roots = {path: root_tag(head) for path, head in heads.items()}
    included: set[str] = set()
    tails: set[str] = set()  # $(find PKG)/TAIL: any file of the walk ending in /TAIL
    for path, head in heads.items():
        folder = os.path.dirname(path)
        if roots[path] in ("mujoco", *FRAGMENT_ROOTS):
            for name in _INCLUDED.findall(head):
                target = name.decode("utf-8", "replace").replace("\\", "/")
                included.add(os.path.normpath(os.path.join(folder, target)))
        for name in _XACRO_INCLUDED.findall(head):
            target = name.decode("utf-8", "replace")
            found = _FIND.match(target)
            if found:
                tails.add("/" + target[found.end() :].lstrip("/"))
            elif "$" not in target:
                included.add(os.path.normpath(os.path.join(folder, target)))
    return [
        path
        for path in paths
        if os.path.normpath(path) not in included
        and not any(("/" + path.replace(os.sep, "/")).endswith(tail) for tail in tails)
        and roots[path] not in FRAGMENT_ROOTS
        and not (path.endswith(".xacro") and _macros_only(heads[path]))
        and (path.endswith(ROBOT_SUFFIXES) or roots[path] in _ROOTS)
    ]
