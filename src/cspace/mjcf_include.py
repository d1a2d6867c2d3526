"""MJCF ``<include file="...">``: the included files spliced into one document.

MuJoCo reads an include as if the included file's elements (children of its own
``<mujoco>``) stood in its place; a file name is relative to the main file's folder.
Pinocchio's MJCF parser drops or refuses included bodies, so `cspace` splices the files
itself (each one read as safely as the main file) and gives Pinocchio the result, with
every ``<worldbody>`` merged into the first (as MuJoCo merges them).
"""

from __future__ import annotations

import os
from copy import deepcopy

from lxml import etree

from .errors import InvalidElementError
from .xmlio import line_of, parse_xml, read_source

MAX_INCLUDE_DEPTH = 16
"""Includes nested deeper than this are refused (a file that includes itself is refused
at once)."""


def _fail(path: str, problem: str, element: etree._Element) -> None:
    raise InvalidElementError(path, problem, code="bad-include", line=line_of(element))


def _splice(path: str, root: etree._Element, folder: str, chain: tuple[str, ...]) -> None:
    for include in list(root.iter("include")):
        name = include.get("file", "").strip()
        if not name:
            _fail(path, "<include> has no 'file' attribute", include)
        target = os.path.realpath(os.path.join(folder, name))
        if target in chain:
            _fail(path, f'<include file="{name}"> includes itself (through {target})', include)
        if len(chain) >= MAX_INCLUDE_DEPTH:
            _fail(path, f"<include> nested more than {MAX_INCLUDE_DEPTH} deep", include)
        included = parse_xml(read_source(os.path.join(folder, name)))
        if included.tag != "mujoco":
            _fail(path, f"included file '{name}' is <{included.tag}>, not <mujoco>", include)
        _splice(path, included, folder, (*chain, target))
        parent = include.getparent()
        if parent is None:  # pragma: no cover - the root is never an <include>
            continue
        at = parent.index(include)
        for offset, child in enumerate(list(included)):
            parent.insert(at + offset, child)
        parent.remove(include)


def splice_includes(path: str, root: etree._Element, file: str | None) -> etree._Element | None:
    """The document with its includes spliced in, or None when it has none.

    Args:
        path: The main file, for messages.
        root: Its parsed ``<mujoco>`` element (left unchanged).
        file: The main file on disk (include names are relative to its folder), or None
            when it was read from standard input.

    Returns:
        A new ``<mujoco>`` element without ``<include>`` and with one ``<worldbody>``.

    Raises:
        InvalidElementError: An include without a file, an include cycle, an included
            file that is not MJCF, or includes on standard input.
        RobotFileError: An included file cannot be read or parsed (it is named).
    """
    first = root.find(".//include")
    if first is None:
        return None
    if file is None:
        _fail(path, "<include> needs the file's folder: give the file, not standard input", first)
    folder = os.path.dirname(os.path.abspath(str(file)))
    spliced = deepcopy(root)
    _splice(path, spliced, folder, (os.path.realpath(str(file)),))
    worldbodies = spliced.findall("worldbody")
    for extra in worldbodies[1:]:
        for child in list(extra):
            worldbodies[0].append(child)
        spliced.remove(extra)
    return spliced
