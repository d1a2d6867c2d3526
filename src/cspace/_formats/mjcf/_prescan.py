"""The MJCF pre-scan: every file MuJoCo would read, read once and bounded, before MuJoCo runs.

MuJoCo's parser opens files on its own: included files, attached models (``<model
file>``), and it looks up mesh, texture, height-field and skin files at parse time,
falling back to the disk (absolute paths and ``..`` included) for any name it is not
given. So `cspace` reads those files itself, as safely as the main file, and hands
MuJoCo everything in memory:

- ``<include file>`` and ``<model file>`` are read (each once) and parsed here: only
  regular files inside the allowed folders (the main file's project folder, see
  `cspace._project`, or its own folder, and the ``--allow-dir`` folders, after following
  links; never in a ``.git`` folder), charged to the run's `ReadBudget`.
  An include is relative to the main file's folder (nested ones too); an attached
  model's own includes are relative to its folder, as MuJoCo reads them. MuJoCo splices
  an ``<include>`` in whatever the case of its name (``<INCLUDE>``): any other case is
  refused.
- each ``<model>`` asset is named as MuJoCo names it, among the assets of the document
  it stands in (`mjcf._models`); two of one name are refused.
- MuJoCo is given no file's bytes but lxml's serialisation of what the pre-scan read
  (`mujoco_document`), so that both read one
  document; a file with a DOCTYPE or a namespace is refused, as MuJoCo's parser would
  read it otherwise (`check_plain`). MuJoCo finds
  the files it is given by base name, whatever the case: one such name for two files
  (``part.xml`` beside the main file and beside an attached model's) is refused.
- mesh, texture, height-field and skin files are never read: MuJoCo is given an empty
  placeholder under each file's base name, and the geometry is dropped before
  compiling (`mjcf._compile`); the files need not exist.
- a file name with a URL scheme or an archive (``.zip``, ``.mjz``, which MuJoCo opens
  from the disk itself) is refused.

The pre-scan also bounds what MuJoCo will build, before it builds it (MuJoCo's own parse
and compile have no limits, and ``<replicate>`` multiplies): see
`mjcf._count`. Every walk here is iterative: no file can make it
grow Python's stack.
"""

import os
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import NoReturn

from lxml import etree

from cspace._formats.mjcf._count import MAX_BODIES as MAX_BODIES
from cspace._formats.mjcf._count import MAX_BODY_DEPTH as MAX_BODY_DEPTH
from cspace._formats.mjcf._count import MAX_CONSTRAINTS as MAX_CONSTRAINTS
from cspace._formats.mjcf._count import MAX_ELEMENTS as MAX_ELEMENTS
from cspace._formats.mjcf._count import MAX_NESTING as MAX_NESTING
from cspace._formats.mjcf._count import Counter, Totals
from cspace._formats.mjcf._models import (
    ModelAsset,
    check_encoding,
    check_model_file,
    check_plain,
    effective_name,
    fail_in,
    file_key,
    model_folder,
    mujoco_document,
    namespaced,
    register,
)
from cspace._formats.shared.xmlio import (
    ReadBudget,
    line_of,
    parse_xml,
    read_source,
    within,
)
from cspace._paths import in_version_control
from cspace._project import include_folders
from cspace._record import NamedTuple
from cspace.errors import FileUnreadableError

MAX_INCLUDE_DEPTH = 16
"""Includes (and attached models) nested deeper than this are refused."""

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
        includes: Each included or attached file as MuJoCo is given it (lxml's
            serialisation of what was read, in UTF-8), by the name the document uses.
        placeholders: Base names of the geometry and texture files the documents name.
        lines: ``(tag, name)`` -> line in the main file, for named bodies, joints,
            keyframes, connects and welds, and actuators (tag ``actuator``).
        where: Every named element's name -> the file (as named in the document, None
            for the main file) and line it is first declared at, for MuJoCo's messages.
        allowed: The real folders files may be read from.
        given: Each name MuJoCo is given a file by, when it is not the document's name
            for it -> that name (two files of one base name).
        beyond: The first file read from outside the main file's own folder (within its
            project's folder or an ``--allow-dir``), as the document names it, or None.
        attaches: The document names model assets (``<model file>``), which ``<attach>``
            puts in with their own ``<compiler>``.
    """

    includes: dict[str, bytes] = field(default_factory=dict)
    placeholders: set[str] = field(default_factory=set)
    lines: dict[tuple[str, str], int] = field(default_factory=dict)
    where: dict[str, tuple[str | None, int]] = field(default_factory=dict)
    beyond: str | None = None
    allowed: tuple[str, ...] = ()
    given: dict[str, str] = field(default_factory=dict)
    attaches: bool = False


def _in_actuator(element: etree._Element) -> bool:
    """Whether ``element`` is an actuator: a child of ``<actuator>``."""
    parent = element.getparent()
    return parent is not None and parent.tag == "actuator"


class _Document(NamedTuple):
    """A document (or an included file) being walked, and what its names resolve from."""

    elements: Iterator[etree._Element]
    folder: str  # includes resolve from here
    chain: tuple[str, ...]  # the real paths of the files that led here
    file: str | None  # the file, as the document names it (None: the main file)
    assets: dict[str, ModelAsset]  # the model assets its <attach> may name


class _Scanner:
    def __init__(self, path: str, file: str | None, allowed: Sequence[str], budget: ReadBudget):
        self.path = path
        self.main_folder = os.path.dirname(os.path.abspath(file)) if file else None
        # its real path, once: an include read from outside it is reported (`beyond`)
        self.own_folder = os.path.realpath(self.main_folder) if self.main_folder else ""
        self.allowed = tuple(allowed)
        self.budget = budget
        self.found = PreScan(allowed=self.allowed)
        # <include> -> the included root and its file name. Keyed by the element itself,
        # which keeps its Python proxy alive: an id() of a proxy lxml has freed can come
        # back for another.
        self.parsed: dict[etree._Element, tuple[etree._Element, str]] = {}
        self.assets: dict[str, ModelAsset] = {}  # the main document's model assets
        self.models: list[ModelAsset] = []  # every model asset, in the order read
        # MuJoCo is given every file in memory, and finds one by its key (its lower-case
        # base name): each real file gets a name whose key no other file has, the name
        # the document uses when it can (robosuite names every robot file robot.xml).
        self.keys: dict[str, str] = {}  # key -> the real path of the file it stands for
        self.given: dict[str, str] = {}  # real path -> the name MuJoCo is given it by
        self.documents: dict[str, etree._Element] = {}  # that name -> the parsed file
        self.read_data: dict[str, bytes] = {}  # each real path -> the bytes read for it

    def file_name(self, element: etree._Element, where: str | None) -> str:
        """The ``file`` an include or model names, exactly as MuJoCo will look it up.

        A name with spaces at either end, or with control characters, is refused: MuJoCo
        looks up the name as written, and a name the pre-scan read differently would send
        it to the disk.
        """
        name = element.get("file") or ""
        if not name:
            raise fail_in(
                self.path, where, "bad-include", f"<{element.tag}> has no 'file' attribute", element
            )
        if name != name.strip() or not name.isprintable():
            raise fail_in(
                self.path,
                where,
                "bad-include",
                f"<{element.tag} file={name!r}>: a file name with spaces at its ends or "
                "control characters",
                element,
            )
        return name

    def read(
        self, element: etree._Element, name: str, document: _Document
    ) -> tuple[etree._Element, str]:
        """Read and parse the file ``name`` an include or model element names.

        Returns:
            Its root element and its real path.
        """
        tag, where = str(element.tag), document.file

        def refuse(code: str, problem: str) -> NoReturn:
            raise fail_in(self.path, where, code, problem, element)

        if self.main_folder is None:
            refuse(
                "bad-include", f"<{tag}> needs the file's folder: give the file, not standard input"
            )
        if _REFUSED_NAME.search(name):
            refuse("bad-include", f'<{tag} file="{name}">: cspace reads no URL or archive')
        # MuJoCo reads a backslash as a folder separator (metaworld: assets\table.xml)
        target = os.path.realpath(os.path.join(document.folder, name.replace("\\", "/")))
        if not within(target, self.allowed) or in_version_control(target, self.allowed):
            refuse(
                "outside-tree",
                f'<{tag} file="{name}"> is outside the folders cspace may read '
                f"({', '.join(self.allowed)}); name a wider folder with --allow-dir if it is meant",
            )
        if self.found.beyond is None and not within(target, (self.own_folder,)):
            self.found.beyond = name
        if target in document.chain:
            refuse("bad-include", f'<{tag} file="{name}"> includes itself')
        if len(document.chain) > MAX_INCLUDE_DEPTH:
            refuse("bad-include", f"<{tag}> nested more than {MAX_INCLUDE_DEPTH} deep")
        given = self.given_name(name, target)
        if given != name:
            element.set("file", given)  # in what MuJoCo is given; the messages say `name`
        try:
            source = read_source(target, budget=self.budget)._replace(path=name)
        except FileUnreadableError as exc:  # named where the include stands
            raise FileUnreadableError(
                self.path,
                f'<{tag} file="{name}">: {exc.problem}'
                + ("" if where is None else f" (in {where}, line {line_of(element)})"),
                line=line_of(element) if where is None else None,
                element=tag,
                code=exc.code,
            ) from None
        if self.read_data.setdefault(target, source.data) != source.data:
            refuse("bad-include", f'<{tag} file="{name}"> changed while cspace read it')
        root = parse_xml(source)
        check_encoding(self.path, name, root, source.data)
        check_plain(self.path, name, root, source.data)
        self.documents[given] = root  # serialised once its own names are given
        return root, target

    def given_name(self, name: str, target: str) -> str:
        """The name MuJoCo is given the real file ``target`` by.

        ``name`` when its key is free, else ``stem~K.ext``, a key no other file has: as
        MuJoCo reads two files of one base name from the disk, each from its own folder.
        """
        given = self.given.get(target)
        if given is None:
            given, key = name, file_key(name)
            stem, ext = os.path.splitext(key)
            k = 1
            while key in self.keys:
                k += 1
                given = key = f"{stem}~{k}{ext}"
            self.keys[key] = target
            self.given[target] = given
            if given != name:
                self.found.given[given] = name
        return given

    def gather(self, root: etree._Element, chain: tuple[str, ...]) -> None:
        """Read every file the main document ``root`` names, and the files they name.

        In document order, each included or attached file where it is named (a stack of
        the documents being walked, not recursion).
        """
        folder = self.main_folder or ""
        stack = [_Document(root.iter(tag=etree.Element), folder, chain, None, self.assets)]
        while stack:
            document = stack[-1]
            element = next(document.elements, None)
            if element is None:
                stack.pop()
                continue
            opened = self.visit(element, document)
            if opened is not None:
                stack.append(opened)
        for given, document_root in self.documents.items():
            self.found.includes[given] = mujoco_document(document_root).encode("utf-8")
        self.found.attaches = bool(self.models)

    def visit(self, element: etree._Element, document: _Document) -> _Document | None:
        """Note what ``element`` names; the document it opens (an include or a model), if any."""
        tag, where = str(element.tag), document.file
        if tag.startswith("{"):  # MuJoCo knows no namespaces
            raise namespaced(self.path, where, element)
        named = element.get("name")
        if named:
            self.found.where.setdefault(str(named), (where, line_of(element) or 0))
            if where is None and tag in ("body", "joint", "freejoint", "key", "connect", "weld"):
                self.found.lines.setdefault((tag, str(named)), line_of(element) or 0)
            elif where is None and _in_actuator(element):
                self.found.lines.setdefault(("actuator", str(named)), line_of(element) or 0)
        for key in GEOMETRY_FILES.get(tag, ()):
            value = element.get(key) or ""  # as MuJoCo will look it up
            if value:
                if _REFUSED_NAME.search(value):
                    raise fail_in(
                        self.path,
                        where,
                        "bad-include",
                        f'<{tag} {key}="{value}">: cspace reads no URL or archive',
                        element,
                    )
                self.found.placeholders.add(os.path.basename(value.replace("\\", "/")))
        if tag == "include":
            name = self.file_name(element, where)
            included, target = self.read(element, name, document)
            self.parsed[element] = (included, name)
            chain = (*document.chain, target)
            # MuJoCo splices in the included root's children: the root itself is nothing.
            children = included.iterdescendants(tag=etree.Element)
            return document._replace(elements=children, chain=chain, file=name)
        if tag.lower() == "include":
            raise fail_in(
                self.path,
                where,
                "bad-include",
                f"<{tag}>: MuJoCo splices in an <include> whatever the case of its name; "
                "write it <include>",
                element,
            )
        if tag == "model":
            name = self.file_name(element, where)
            root, target = self.read(element, name, document)
            check_model_file(self.path, where, element, name, root)
            model_name, how = effective_name(element, root)
            model = ModelAsset(element, root, name, where, model_name)
            register(self.path, document.assets, model, how)
            self.models.append(model)
            return _Document(
                root.iter(tag=etree.Element),
                model_folder(document.folder, name),
                (*document.chain, target),
                name,
                model.assets,
            )
        if tag == "flexcomp" and element.get("file"):
            raise fail_in(
                self.path,
                where,
                "unsupported-element",
                "<flexcomp file> makes bodies from a mesh cspace does not read",
                element,
            )
        return None

    def count(self, root: etree._Element) -> Totals:
        """Count every model asset, then the main document.

        Each asset is counted once, on its own (MuJoCo parses it, attached or not); the
        main document counts its attached copies and every asset's own elements. An
        asset's own assets stand in its file, which was read after it: counted in the
        reverse of the reading order, each is counted before the model that attaches it.
        """
        counter = Counter(self.path, self.parsed)
        parsed = 0
        for model in reversed(self.models):
            totals = counter.count(model.root, model.file, model.assets)
            counter.totals[model] = totals
            parsed += totals.elements
        return counter.count(root, None, self.assets, Totals(elements=parsed))


def prescan(
    path: str,
    root: etree._Element,
    file: str | None,
    *,
    budget: ReadBudget,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    data: bytes | None = None,
) -> PreScan:
    """Read every file an MJCF document needs, and bound what it expands to.

    Args:
        path: The main file, for messages.
        root: Its parsed ``<mujoco>`` element.
        file: The main file on disk (names are relative to its folder), or None when it
            was read from standard input (then it may name no include or model).
        budget: The run's budget, already charged with the main file.
        allow_dirs: Folders, besides the main file's own, that includes may come from.
        data: The main file's bytes, when at hand: one MuJoCo would read in another
            encoding than lxml did is refused.

    Returns:
        The included files, the placeholders and the main file's lines.

    Raises:
        UnsafeXmlError: A file with a DOCTYPE or an XML namespace.
        InvalidElementError: An include without a file, outside the allowed folders, in
            a cycle or too deep, a URL or archive name, two names of one base name or one
            name for two files (MuJoCo keys files by base name), a file that changed
            while read, two model assets of one name, a model file MuJoCo would not read
            as MJCF, a file not in UTF-8, or more than `MAX_CONSTRAINTS` equality
            constraints.
        RobotStructureError: The model expands to more bodies or joints than
            `MAX_BODIES` or `MAX_JOINTS`
            (``too-many-joints``), bodies deeper than `MAX_BODY_DEPTH` or elements
            deeper than `MAX_NESTING` (``too-deep``).
        FileUnreadableError: An included file cannot be read, the run's budget is spent,
            or the model expands to more than `MAX_ELEMENTS` elements
            (``too-much-input``).
        XmlSyntaxError: An included file is not well-formed.
    """
    if data is not None:
        check_encoding(path, None, root, data)
    check_plain(path, None, root, data)
    allowed = include_folders(file, allow_dirs) if file else ()
    scanner = _Scanner(path, file, allowed, budget)
    scanner.gather(root, (os.path.realpath(file),) if file else ())
    scanner.count(root)
    return scanner.found
