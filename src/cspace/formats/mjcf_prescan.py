"""The MJCF pre-scan: every file MuJoCo would read, read once and bounded, before MuJoCo runs.

MuJoCo's parser opens files on its own: included files, attached models (``<model
file>``), and it looks up mesh, texture, height-field and skin files at parse time,
falling back to the disk (absolute paths and ``..`` included) for any name it is not
given. So `cspace` reads those files itself, as safely as the main file, and hands
MuJoCo everything in memory:

- ``<include file>`` and ``<model file>`` are read (each once) and parsed here: only
  regular files inside the allowed folders (the main file's folder and ``--allow-dir``
  folders, after following links), charged to the run's :class:`~cspace.formats.xmlio.ReadBudget`.
  An include is relative to the main file's folder (nested ones too); an attached
  model's own includes are relative to its folder, as MuJoCo reads them.
- mesh, texture, height-field and skin files are never read: MuJoCo is given an empty
  placeholder under each file's base name, and the geometry is dropped before
  compiling (:mod:`cspace.formats.mjcf_compile`); the files need not exist.
- a file name with a URL scheme or an archive (``.zip``, ``.mjz``, which MuJoCo opens
  from the disk itself) is refused.

The pre-scan also bounds what MuJoCo will build, before it builds it (MuJoCo's own parse
and compile have no limits, and ``<replicate>`` multiplies): the bodies, joints and
elements after ``<replicate>`` and ``<attach>`` are counted (a replicated element
``count`` times over), and so is the depth of the body tree.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field

from lxml import etree

from cspace.errors import FileUnreadableError, InvalidElementError, RobotStructureError
from cspace.formats.structure import MAX_JOINTS
from cspace.formats.xmlio import (
    MAX_TAGS,
    ReadBudget,
    allowed_folders,
    fail_at,
    line_of,
    parse_xml,
    read_source,
    within,
)

MAX_INCLUDE_DEPTH = 16
"""Includes (and attached models) nested deeper than this are refused."""

MAX_BODIES = MAX_JOINTS + 1
"""Most bodies after ``<replicate>`` and ``<attach>`` (the world not counted)."""

MAX_BODY_DEPTH = 1000
"""Most MJCF bodies on one path from the world (through includes: one file's XML nests
at most 256 deep). MuJoCo's compile time grows about with the cube of the depth (1,000
deep: 2-3 s, within its CPU limit); Pinocchio's part is iterative here, not recursive."""

MAX_ELEMENTS = MAX_TAGS
"""Most elements after ``<replicate>`` and ``<attach>``, each copy counted."""

GEOMETRY_FILES = {
    "mesh": ("file",),
    "hfield": ("file",),
    "skin": ("file",),
    "texture": ("file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback"),
}
"""Elements naming files the configuration space does not depend on, and the attributes
that name them: MuJoCo gets empty placeholders for these."""

_REFUSED_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:|\.(zip|mjz)([/\\]|$)", re.IGNORECASE)
"""A URL scheme (``http:``, ``file:``, a drive letter) or a path through an archive."""


@dataclass
class PreScan:
    """Everything MuJoCo needs besides the main document, and where things stand.

    Attributes:
        includes: Each included or attached file's bytes, by the name the document uses.
        placeholders: Base names of the geometry and texture files the documents name.
        lines: ``(tag, name)`` -> line in the main file, for named bodies and joints.
        where: Every named element's name -> the file (as named in the document, None
            for the main file) and line it is first declared at, for MuJoCo's messages.
    """

    includes: dict[str, bytes] = field(default_factory=dict)
    placeholders: set[str] = field(default_factory=set)
    lines: dict[tuple[str, str], int] = field(default_factory=dict)
    where: dict[str, tuple[str | None, int]] = field(default_factory=dict)


MAX_CONSTRAINTS = 1000
"""Most ``<equality>`` constraints. Real models have a few dozen; MuJoCo's compile of
60,000 took more than 1 GiB, and each weld or connect is a walk through the tree."""


@dataclass
class _Totals:
    bodies: int = 0
    joints: int = 0
    elements: int = 0
    depth: int = 0
    constraints: int = 0


class _Scanner:
    def __init__(self, path: str, file: str | None, allowed: Sequence[str], budget: ReadBudget):
        self.path = path
        self.main_folder = os.path.dirname(os.path.abspath(file)) if file else None
        self.allowed = tuple(allowed)
        self.budget = budget
        self.found = PreScan()
        # <include> -> the included root. Keyed by the element itself, which keeps its
        # Python proxy alive: an id() of a proxy lxml has freed can come back for another.
        self.parsed: dict[etree._Element, etree._Element] = {}
        self.models: dict[str, etree._Element] = {}  # <model name> -> its root
        self.base_names: dict[str, str] = {}  # lower-case base name -> the name used
        self.totals: dict[str, _Totals] = {}

    def file_name(self, element: etree._Element) -> str:
        """The ``file`` an include or model names, exactly as MuJoCo will look it up.

        A name with spaces at either end, or with control characters, is refused: MuJoCo
        looks up the name as written, and a name the pre-scan read differently would send
        it to the disk.
        """
        name = element.get("file") or ""
        if not name:
            fail_at(self.path, "bad-include", f"<{element.tag}> has no 'file' attribute", element)
        if name != name.strip() or not name.isprintable():
            fail_at(
                self.path,
                "bad-include",
                f"<{element.tag} file={name!r}>: a file name with spaces at its ends or "
                "control characters",
                element,
            )
        return name

    def read(
        self, element: etree._Element, name: str, folder: str, chain: tuple[str, ...]
    ) -> tuple[etree._Element, str]:
        """Read and parse the file ``name`` an include or model element names.

        Returns:
            Its root element and its real path.
        """
        tag = str(element.tag)
        if self.main_folder is None:
            fail_at(
                self.path,
                "bad-include",
                f"<{tag}> needs the file's folder: give the file, not standard input",
                element,
            )
        if _REFUSED_NAME.search(name):
            fail_at(
                self.path,
                "bad-include",
                f'<{tag} file="{name}">: cspace reads no URL or archive',
                element,
            )
        target = os.path.realpath(os.path.join(folder, name))
        if not within(target, self.allowed):
            fail_at(
                self.path,
                "outside-tree",
                f'<{tag} file="{name}"> is outside the folders cspace may read '
                f"({', '.join(self.allowed)}); name a wider folder with --allow-dir if it is meant",
                element,
            )
        if target in chain:
            fail_at(self.path, "bad-include", f'<{tag} file="{name}"> includes itself', element)
        if len(chain) > MAX_INCLUDE_DEPTH:
            fail_at(
                self.path,
                "bad-include",
                f"<{tag}> nested more than {MAX_INCLUDE_DEPTH} deep",
                element,
            )
        base = os.path.basename(name).lower()
        if self.base_names.setdefault(base, name) != name:
            fail_at(
                self.path,
                "bad-include",
                f'<{tag} file="{name}"> and "{self.base_names[base]}" have the same base name, '
                "which MuJoCo cannot tell apart",
                element,
            )
        try:
            source = read_source(target, budget=self.budget)._replace(path=name)
        except FileUnreadableError as exc:  # named where the include stands
            raise FileUnreadableError(
                self.path,
                f'<{tag} file="{name}">: {exc.problem}',
                line=line_of(element),
                element=tag,
                code=exc.code,
            ) from None
        self.found.includes[name] = source.data
        return parse_xml(source), target

    def gather(
        self, root: etree._Element, folder: str, chain: tuple[str, ...], file: str | None
    ) -> None:
        """Read every file ``root`` (``file``, None for the main one) names.

        Includes resolve from ``folder``.
        """
        for element in root.iter(tag=etree.Element):
            tag = str(element.tag)
            named = element.get("name")
            if named:
                self.found.where.setdefault(str(named), (file, line_of(element) or 0))
                if file is None and tag in ("body", "joint", "freejoint"):
                    self.found.lines.setdefault((tag, str(named)), line_of(element) or 0)
            if tag == "include":
                name = self.file_name(element)
                included, target = self.read(element, name, folder, chain)
                self.parsed[element] = included
                self.gather(included, folder, (*chain, target), name)
            elif tag == "model":
                name = self.file_name(element)
                model, target = self.read(element, name, folder, chain)
                # MuJoCo names an unnamed <model> after the file's own <mujoco model>.
                key = element.get("name") or model.get("model") or ""
                self.models[key] = model
                inner = os.path.dirname(os.path.join(folder, name))
                self.gather(model, inner, (*chain, target), name)
            elif tag == "flexcomp" and element.get("file"):
                fail_at(
                    self.path,
                    "unsupported-element",
                    "<flexcomp file> makes bodies from a mesh cspace does not read",
                    element,
                )
            for key in GEOMETRY_FILES.get(tag, ()):
                value = element.get(key) or ""  # as MuJoCo will look it up
                if value:
                    if _REFUSED_NAME.search(value):
                        fail_at(
                            self.path,
                            "bad-include",
                            f'<{tag} {key}="{value}">: cspace reads no URL or archive',
                            element,
                        )
                    self.found.placeholders.add(os.path.basename(value.replace("\\", "/")))

    def count(
        self,
        element: etree._Element,
        multiplier: int,
        depth: int,
        into: _Totals,
        models: tuple[str, ...],
    ) -> None:
        """Add what ``element``'s children expand to (times ``multiplier``) to ``into``."""
        for child in _children(element, self.parsed):
            tag = str(child.tag)
            into.elements += multiplier
            if tag == "replicate":
                count = _count_attribute(self.path, child)
                self.count(child, multiplier * count, depth, into, models)
            elif tag == "body":
                into.bodies += multiplier
                into.depth = max(into.depth, depth + 1)
                self.count(child, multiplier, depth + 1, into, models)
            elif tag in ("joint", "freejoint") and depth > 0:
                into.joints += multiplier
            elif tag == "flexcomp":  # a body (with up to 3 slides) per point
                inline = len(str(child.get("point", "")).split()) // 3
                points = max(_count_attribute(self.path, child, 3), inline)
                into.bodies += multiplier * points
                into.joints += multiplier * points * 3
                into.elements += multiplier * points
            elif tag == "equality":
                into.constraints += multiplier * sum(1 for _ in _children(child, self.parsed))
            elif tag == "attach":
                name = child.get("model", "")
                if name not in self.models:  # a body of this file, or a model not read
                    fail_at(
                        self.path,
                        "unsupported-element",
                        f'<attach model="{name}">: cspace attaches only a <model> asset '
                        "read from its file",
                        child,
                    )
                if name in models:
                    fail_at(
                        self.path, "bad-include", f'<attach model="{name}"> attaches itself', child
                    )
                part = self.model_totals(name, (*models, name))
                into.bodies += multiplier * part.bodies
                into.joints += multiplier * part.joints
                into.elements += multiplier * part.elements
                into.depth = max(into.depth, depth + part.depth)
            else:
                self.count(child, multiplier, depth, into, models)
            self.check(into, child)

    def model_totals(self, name: str, models: tuple[str, ...]) -> _Totals:
        if name not in self.totals:
            totals = _Totals()
            self.count(self.models[name], 1, 0, totals, models)
            self.totals[name] = totals
        return self.totals[name]

    def check(self, totals: _Totals, element: etree._Element) -> None:
        over = (
            (
                totals.bodies > MAX_BODIES,
                f"more than {MAX_BODIES:,} bodies",
                RobotStructureError,
                "too-many-joints",
            ),
            (
                totals.joints > MAX_JOINTS,
                f"more than {MAX_JOINTS:,} joints",
                RobotStructureError,
                "too-many-joints",
            ),
            (
                totals.depth > MAX_BODY_DEPTH,
                f"bodies nested more than {MAX_BODY_DEPTH:,} deep",
                RobotStructureError,
                "too-deep",
            ),
            (
                totals.elements > MAX_ELEMENTS,
                f"more than {MAX_ELEMENTS:,} elements",
                FileUnreadableError,
                "too-much-input",
            ),
            (
                totals.constraints > MAX_CONSTRAINTS,
                f"more than {MAX_CONSTRAINTS:,} equality constraints",
                InvalidElementError,
                "too-many-constraints",
            ),
        )
        for hit, what, error, code in over:
            if hit:
                raise error(
                    self.path,
                    f"the model expands (<replicate>, <attach>, <include>) to {what}, "
                    "more than cspace gives MuJoCo's compiler",
                    line=line_of(element),
                    element=str(element.tag),
                    code=code,
                )


def _children(
    element: etree._Element, parsed: dict[etree._Element, etree._Element]
) -> Iterator[etree._Element]:
    """``element``'s child elements, an include standing for the included file's children."""
    for child in element.iterchildren(tag=etree.Element):
        included = parsed.get(child)
        if included is None:
            yield child
        else:
            yield from _children(included, parsed)


_WHOLE = re.compile(r"[+-]?[0-9]+")


def _count_attribute(path: str, element: etree._Element, numbers: int = 1) -> int:
    """The product of the (first ``numbers``) whole numbers of ``count``, at least 1.

    Raises:
        InvalidElementError: A word that is not a whole number as MuJoCo reads one
            (an optional sign, then digits): cspace could not bound what it makes.
    """
    product = 1
    for word in str(element.get("count", "1")).split()[:numbers]:
        if not _WHOLE.fullmatch(word):
            fail_at(
                path,
                "bad-number",
                f'<{element.tag} count="{element.get("count")}">: "{word}" is not a whole number',
                element,
            )
        product *= max(1, int(word))
    return product


def prescan(
    path: str,
    root: etree._Element,
    file: str | None,
    *,
    budget: ReadBudget,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
) -> PreScan:
    """Read every file an MJCF document needs, and bound what it expands to.

    Args:
        path: The main file, for messages.
        root: Its parsed ``<mujoco>`` element.
        file: The main file on disk (names are relative to its folder), or None when it
            was read from standard input (then it may name no include or model).
        budget: The run's budget, already charged with the main file.
        allow_dirs: Folders, besides the main file's own, that includes may come from.

    Returns:
        The included files, the placeholders and the main file's lines.

    Raises:
        InvalidElementError: An include without a file, outside the allowed folders, in
            a cycle or too deep, a URL or archive name, two files of one base name, or
            more than :data:`MAX_CONSTRAINTS` equality constraints.
        RobotStructureError: The model expands to more bodies or joints than
            :data:`MAX_BODIES` or :data:`~cspace.formats.structure.MAX_JOINTS`
            (``too-many-joints``), or deeper than :data:`MAX_BODY_DEPTH` (``too-deep``).
        FileUnreadableError: An included file cannot be read, the run's budget is spent,
            or the model expands to more than :data:`MAX_ELEMENTS` elements
            (``too-much-input``).
        XmlSyntaxError: An included file is not well-formed.
    """
    allowed = allowed_folders(file, allow_dirs) if file else ()
    scanner = _Scanner(path, file, allowed, budget)
    chain = (os.path.realpath(file),) if file else ()
    scanner.gather(root, scanner.main_folder or "", chain, None)
    totals = _Totals()
    scanner.count(root, 1, 0, totals, ())
    return scanner.found
