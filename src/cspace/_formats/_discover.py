"""Robot descriptions found by what they are, among the files of a folder.

A folder given to ``cspace inspect`` stands for the robot files in it: ``.urdf``,
``.xacro`` and ``.sdf`` files, and any file whose root element is ``<robot>``,
``<mujoco>`` or ``<sdf>`` (the first `PEEK_BYTES` are read, no further). A fragment is
left to the description that includes it: a ``<mujocoinclude>`` file; a ``<mujoco>``
file that another MJCF file of the folder includes (``<include file=...>``) or attaches
(``<model file=...>``), relative to the including file's folder; a xacro file that
another ``.xacro`` or ``.urdf`` file includes (``<xacro:include filename=...>``,
relative, or ``$(find PKG)/PATH`` for a file of the folder whose path ends in
``/PATH``); and a xacro macro library (a ``<robot>`` without a name, holding macros and
no ``<link>`` outside them). Comments are not read for any of this. Every scan is a
single pass over the bytes read (no backtracking pattern over the whole file), and
only each file's root element and the names it includes are kept.

A file of a format told by its bytes (`by_content`: USD) is a robot description too,
unless a root layer of the walk composes it, directly or through others (a converter's
payload layers): a root layer is one no other USD file of the walk composes, and what
each composes (sublayers, references, payloads) is OpenUSD's answer, read in a confined
child (the ``arcs`` of `robot_files`). A layer in a cycle that no root reaches is read,
and an XML file's includes never make a USD file a fragment.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Sequence
from typing import NamedTuple

PEEK_BYTES = 64 << 10
"""Most bytes read of each file to find its root element (a long licence comment first)."""

ROBOT_SUFFIXES = (".urdf", ".xacro", ".sdf")
"""Names that say a robot description whatever the root (xacro may wrap it)."""

FRAGMENT_ROOTS = ("mujocoinclude",)
"""Root elements of files meant only to be included."""

MAX_TAG_BYTES = 4096
"""Longest start tag read for an ``include``'s file name."""

_ROOTS = ("robot", "mujoco", "sdf")
_CONTENT = ("usd",)
"""The formats of `by_content`, as `_Seen.root` names them."""
_NAME = re.compile(rb"[A-Za-z_][\w.:-]*")
_FILE = re.compile(rb"\bfile(?:name)?\s*=\s*([\"'])([^\"'<>]*)\1")
_ROBOT_NAME = re.compile(rb"\sname\s*=")
_FIND = re.compile(r"\$\((?:find|find-pkg-share)\s+[^)]*\)")


def _uncommented(data: bytes) -> bytes:
    """``data`` without its XML comments (an unclosed one runs to the end)."""
    out, at = [], 0
    while True:
        start = data.find(b"<!--", at)
        if start < 0:
            out.append(data[at:])
            return b"".join(out)
        out.append(data[at:start])
        end = data.find(b"-->", start + 4)
        if end < 0:
            return b"".join(out)
        at = end + 3


def root_tag(data: bytes) -> str | None:
    """The root element's name in the first bytes of an XML file, or None."""
    at = 3 if data.startswith(b"\xef\xbb\xbf") else 0
    while True:
        while at < len(data) and data[at : at + 1].isspace():
            at += 1
        if data.startswith(b"<?", at):
            close = b"?>"
        elif data.startswith(b"<!--", at):
            close = b"-->"
        elif data.startswith(b"<!", at):
            close = b">"
        elif data.startswith(b"<", at):
            found = _NAME.match(data, at + 1)
            return found.group(0).decode("ascii") if found else None
        else:
            return None
        end = data.find(close, at + 2)
        if end < 0:
            return None
        at = end + len(close)


def _start_tags(data: bytes, names: tuple[bytes, ...]) -> list[bytes]:
    """The start tags (up to `MAX_TAG_BYTES` each) of elements called ``names``."""
    tags = []
    at = data.find(b"<")
    while at >= 0:
        for name in names:
            after = at + 1 + len(name)
            if data.startswith(name, at + 1) and data[after : after + 1] in b" \t\r\n/>":
                end = data.find(b">", at, at + MAX_TAG_BYTES)
                tags.append(data[at : end if end >= 0 else at + MAX_TAG_BYTES])
                break
        at = data.find(b"<", at + 1)
    return tags


def _macros_only(data: bytes) -> bool:
    """A xacro macro library: a nameless ``<robot>``, macros, no ``<link>`` outside them."""
    robot = _start_tags(data, (b"robot",))
    if not robot or _ROBOT_NAME.search(robot[0]):
        return False
    rest, at, macros = [], 0, 0
    while True:
        start = data.find(b"<xacro:macro", at)
        if start < 0:
            rest.append(data[at:])
            break
        rest.append(data[at:start])
        end = data.find(b"</xacro:macro", start)
        macros += 1
        if end < 0:
            break
        at = end + 13
    return macros > 0 and b"<link" not in b"".join(rest)


class _Seen(NamedTuple):
    root: str | None
    includes: tuple[str, ...]  # paths, normalised
    tails: tuple[str, ...]  # /PATH of $(find PKG)/PATH
    library: bool


def _look(path: str) -> _Seen:
    """What `robot_files` needs of one file, from its first `PEEK_BYTES`."""
    from cspace.errors import FileUnreadableError
    from cspace.files import open_input

    try:
        with open_input(path, max_bytes=None, what="robot file") as stream:
            head = stream.read(PEEK_BYTES)
    except (FileUnreadableError, OSError):
        return _Seen(None, (), (), False)
    from cspace._formats.by_content import format_of

    content = format_of(path, head)
    if content is not None:  # a USD layer: what it composes is asked of OpenUSD
        return _Seen(content.name, (), (), False)
    root = root_tag(head)
    if root not in (*_ROOTS, *FRAGMENT_ROOTS):
        return _Seen(root, (), (), False)
    text = _uncommented(head)
    folder = os.path.dirname(path)
    includes: list[str] = []
    tails: list[str] = []
    names = (b"include", b"model") if root in ("mujoco", *FRAGMENT_ROOTS) else ()
    for tag in _start_tags(text, names):
        found = _FILE.search(tag)
        if found:
            target = found.group(2).decode("utf-8", "replace").replace("\\", "/")
            includes.append(os.path.normpath(os.path.join(folder, target)))
    if root == "robot":
        for tag in _start_tags(text, (b"xacro:include",)):
            found = _FILE.search(tag)
            target = found.group(2).decode("utf-8", "replace") if found else ""
            find = _FIND.match(target)
            if find:
                tails.append("/" + target[find.end() :].lstrip("/"))
            elif target and "$" not in target:
                includes.append(os.path.normpath(os.path.join(folder, target)))
    library = root == "robot" and path.endswith(".xacro") and _macros_only(text)
    return _Seen(root, tuple(includes), tuple(tails), library)


def _composed(seen: dict[str, _Seen]) -> set[str]:
    """The USD layers that a root layer of the walk composes, directly or through others.

    A root is a USD file no other one composes. A layer in a cycle that no root reaches
    is no fragment: it is read, and its reader says what is wrong with it.
    """
    usd = {os.path.normpath(p): s.includes for p, s in seen.items() if s.root in _CONTENT}
    targets = {t for includes in usd.values() for t in includes}
    reached: set[str] = set()
    stack = [p for p in usd if p not in targets]
    while stack:
        for target in usd.get(stack.pop(), ()):
            if target in usd and target not in reached:  # a USD layer, never a URDF
                reached.add(target)
                stack.append(target)
    return reached


class Found(NamedTuple):
    """The robot descriptions of a walk, and the fragments left to what includes them.

    ``by_content`` names the format of each robot told by its bytes (USD), whose reader
    needs an extra.
    """

    robots: list[str]
    fragments: list[str]
    by_content: dict[str, str]


def robot_files(
    paths: Sequence[str], arcs: Callable[[list[str]], dict[str, list[str]]] | None = None
) -> Found:
    """The robot descriptions among ``paths`` (files of one walk), in their order.

    Args:
        paths: Files, as a folder's walk names them.
        arcs: What reads the layers each USD layer composes (`usd.layer_arcs`, OpenUSD
            in a confined child), or None: no USD layer is then known as a fragment.
    """
    seen = {path: _look(path) for path in paths}
    layers = [p for p, s in seen.items() if s.root in _CONTENT]
    if arcs is not None and len(layers) > 1:  # one layer alone is a fragment of none
        spelt = {os.path.abspath(p): os.path.normpath(p) for p in paths}  # as the walk spells it
        for path, targets in arcs(layers).items():
            named = {spelt.get(os.path.abspath(t), os.path.normpath(t)) for t in targets}
            named.discard(os.path.normpath(path))
            seen[path] = seen[path]._replace(includes=tuple(sorted(named)))
    composed = _composed(seen)
    included = {  # an XML file's includes hide XML files; USD layers, what a root composes
        t
        for s in seen.values()
        if s.root not in _CONTENT
        for t in s.includes
        if t not in seen or seen[t].root not in _CONTENT
    } | composed
    tails = {tail for s in seen.values() for tail in s.tails}
    robots: list[str] = []
    fragments: list[str] = []
    content = {path: s.root for path, s in seen.items() if s.root in _CONTENT and s.root}
    for path, s in seen.items():
        if not (path.endswith(ROBOT_SUFFIXES) or s.root in (*_ROOTS, *FRAGMENT_ROOTS, *_CONTENT)):
            continue
        posix = "/" + path.replace(os.sep, "/")
        if (
            s.root in FRAGMENT_ROOTS
            or s.library
            or os.path.normpath(path) in included
            or any(posix.endswith(tail) for tail in tails)
        ):
            fragments.append(path)
        else:
            robots.append(path)
    return Found(robots, fragments, {p: f for p, f in content.items() if p in robots})
