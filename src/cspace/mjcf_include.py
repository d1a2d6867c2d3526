"""MJCF ``<include file="...">``: the included files spliced into one document, read once.

MuJoCo reads an include as if the included file's elements (children of its own
``<mujoco>``) stood in its place; a file name is relative to the main file's folder.
`cspace` splices the files itself, each read once per include and as safely as the main
file, and builds the model from the spliced document, so no parser opens any file
again. Every ``<worldbody>`` is merged into the first (as MuJoCo merges them).

What an include may read is bounded:

- only files inside the allowed folders (the main file's folder, and folders the user
  names), after following symbolic links: a committed link to ``/etc/passwd`` or to a
  FIFO elsewhere is refused unread;
- only regular files (see :func:`cspace.xmlio.read_source`);
- the run's :class:`~cspace.xmlio.ReadBudget`: files, bytes and tags in all, counted
  each time a file is included, so fan-out cannot multiply them.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from lxml import etree

from .errors import FileUnreadableError, InvalidElementError
from .xmlio import ReadBudget, allowed_folders, line_of, parse_xml, read_source, within

MAX_INCLUDE_DEPTH = 16
"""Includes nested deeper than this are refused (a file that includes itself is refused
at once)."""


def _fail(path: str, problem: str, element: etree._Element, code: str = "bad-include") -> None:
    raise InvalidElementError(path, problem, code=code, line=line_of(element))


class _Splicer:
    def __init__(self, path: str, folder: str, allowed: Sequence[str], budget: ReadBudget):
        self.path = path
        self.folder = folder
        self.allowed = tuple(allowed)
        self.budget = budget

    def splice(self, root: etree._Element, chain: tuple[str, ...]) -> None:
        for include in list(root.iter("include")):
            name = include.get("file", "").strip()
            if not name:
                _fail(self.path, "<include> has no 'file' attribute", include)
            target = os.path.realpath(os.path.join(self.folder, name))
            if not within(target, self.allowed):
                _fail(
                    self.path,
                    f'<include file="{name}"> is outside the folders cspace may read '
                    f"({', '.join(self.allowed)}); name a wider folder with --allow-dir "
                    "if it is meant",
                    include,
                    code="outside-tree",
                )
            if target in chain:
                _fail(self.path, f'<include file="{name}"> includes itself', include)
            if len(chain) >= MAX_INCLUDE_DEPTH:
                _fail(self.path, f"<include> nested more than {MAX_INCLUDE_DEPTH} deep", include)
            try:
                source = read_source(target, budget=self.budget)._replace(path=name)
            except FileUnreadableError as exc:  # named where the include stands
                raise FileUnreadableError(
                    self.path,
                    f'<include file="{name}">: {exc.problem}',
                    line=line_of(include),
                    element="include",
                    code=exc.code,
                ) from None
            included = parse_xml(source)
            if included.tag != "mujoco":
                _fail(
                    self.path, f"included file '{name}' is <{included.tag}>, not <mujoco>", include
                )
            self.splice(included, (*chain, target))
            parent = include.getparent()
            if parent is None:  # pragma: no cover - the root is never an <include>
                continue
            at = parent.index(include)
            for offset, child in enumerate(list(included)):
                parent.insert(at + offset, child)
            parent.remove(include)


def splice_includes(
    path: str,
    root: etree._Element,
    file: str | None,
    *,
    budget: ReadBudget,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
) -> etree._Element:
    """The document with its includes spliced in and its world bodies merged.

    Args:
        path: The main file, for messages.
        root: Its parsed ``<mujoco>`` element, spliced in place (no copy: a large
            document is not held twice).
        file: The main file on disk (include names are relative to its folder), or None
            when it was read from standard input.
        budget: The run's budget, already charged with the main file.
        allow_dirs: Folders, besides the main file's own, that includes may come from.

    Returns:
        ``root``, now without ``<include>`` and with one ``<worldbody>``.

    Raises:
        InvalidElementError: An include without a file, outside the allowed folders, in a
            cycle or too deep; an included file that is not MJCF; includes on standard
            input.
        RobotFileError: An included file cannot be read or parsed, or the run's budget
            is spent.
    """
    first = root.find(".//include")
    if first is not None:
        if file is None:
            _fail(
                path, "<include> needs the file's folder: give the file, not standard input", first
            )
        folder = os.path.dirname(os.path.abspath(str(file)))
        allowed = allowed_folders(str(file), allow_dirs)
        _Splicer(path, folder, allowed, budget).splice(root, (os.path.realpath(str(file)),))
    worldbodies = root.findall("worldbody")
    for extra in worldbodies[1:]:
        for child in list(extra):
            worldbodies[0].append(child)
        root.remove(extra)
    return root


_FRAME = ("pos", "quat", "axisangle", "xyaxes", "zaxis", "euler")
KINEMATICS = {
    "mujoco": ("compiler", "default", "worldbody"),
    "default": ("default", "joint"),
    "worldbody": ("body", "frame"),
    "body": ("body", "frame", "joint", "freejoint", "inertial"),
    "frame": ("body", "frame"),
}
"""What Pinocchio's MJCF parser is given, by parent: the kinematic tree and its joints'
defaults. Geometry, sites, assets, actuators, sensors and the rest change no joint and
no q/v layout; dropped, they cost Pinocchio's parser no memory (200,000 geoms: 800 MiB)
and cannot trip it (it refuses height fields, for one)."""

ATTRIBUTES = {
    "mujoco": ("model",),
    "compiler": ("angle", "eulerseq", "autolimits"),
    "default": ("class",),
    "worldbody": ("childclass",),
    "body": ("name", "childclass", *_FRAME),
    "frame": ("name", "childclass", *_FRAME),
    "joint": ("name", "class", "type", "axis", "pos", "range", "limited", "ref"),
    "freejoint": ("name",),
    "inertial": ("mass", "diaginertia", "fullinertia", *_FRAME),
}
"""The attributes kept on each element given to Pinocchio. Its parser copies a default
class's attributes down every level of nesting: 250 nested classes of 250 attributes
each took it 9 s and 2.5 GiB; kept to these, the same file takes it a moment."""


def kinematics_only(root: etree._Element) -> bytes:
    """The spliced document pruned to what Pinocchio needs for the model, as bytes.

    Args:
        root: The spliced ``<mujoco>`` element (pruned in place).
    """
    for element in list(root.iter(tag=etree.Element)):
        parent = element.getparent()
        tag = str(element.tag)
        if parent is not None and tag not in KINEMATICS.get(str(parent.tag), ()):
            parent.remove(element)
            continue
        kept = ATTRIBUTES.get(tag, ())
        for key in [k for k in element.attrib if k not in kept]:
            del element.attrib[key]
    return etree.tostring(root)
