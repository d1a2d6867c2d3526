"""An MJCF model's collision geometry and contact filters, as MuJoCo compiled them.

The compiling child reads them (`mjcf._geom_facts`); here its answer becomes records
kept in the `Reading` (``Reading.geometry``), read by the self-collision engine
(`cspace._model._collision_mjcf`). Nothing is read from disk here: the meshes' files
are named, not opened, and the lines of elements are found only when asked
(`Lines`), from the main file's bytes the reader already holds.

MuJoCo numbers an element's line in the document it was given (`_models.mujoco_document`,
the tree lxml read, serialised): for the main file, `Lines` maps that line back to the
file's. MuJoCo gives no line (0) to an element of an included file; a named one is
then found by its name in the file the pre-scan read it from. An attached
model's (``<attach>``) lines are its own file's, which MuJoCo does not say: with one, only
named elements get a line.
"""

import math
from collections.abc import Sequence
from typing import Any

from lxml import etree

from cspace._formats.mjcf._models import mujoco_document
from cspace._formats.mjcf._prescan import PreScan
from cspace._formats.shared.xmlio import SourceFile, line_of, parse_xml
from cspace._record import NamedTuple

GEOM_KINDS = ("plane", "hfield", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh", "sdf")
"""MuJoCo's geom types, by ``mjtGeom`` value."""

LINE_TAGS = ("geom", "exclude", "pair", "flag", "body")
"""The elements whose lines `Lines` maps."""

Vec3 = tuple[float, float, float]


class MjcfGeom(NamedTuple):
    """One geom, as MuJoCo compiled it.

    Attributes:
        body: Its MuJoCo body id.
        kind: Its type as the file gives it (`GEOM_KINDS`), ``"unknown"`` for another.
        size: MuJoCo's ``geom_size`` in m (a sphere's radius; a capsule's or cylinder's
            radius and half-length; a box's or ellipsoid's half-sizes); unused for a mesh.
        pos: Its frame's origin in its body's frame (m).
        quat: Its frame's orientation in its body's frame, (w, x, y, z).
        contype: MuJoCo's ``contype`` bits.
        conaffinity: MuJoCo's ``conaffinity`` bits.
        mesh: Its mesh's index in `MjcfGeometry.meshes`, or -1.
        fitted: A primitive MuJoCo fits to the mesh it names (not read).
        line: MuJoCo's line of it in the document it was given, 0 when none.
        name: Its name, or None.
    """

    body: int
    kind: str
    size: Vec3
    pos: Vec3
    quat: tuple[float, float, float, float]
    contype: int
    conaffinity: int
    mesh: int
    fitted: bool
    line: int
    name: str | None


class MjcfMesh(NamedTuple):
    """A mesh asset: where its vertices come from and how MuJoCo places them.

    MuJoCo's vertices of it, in the frame its geom's ``pos`` and ``quat`` give, are each
    file vertex ``v`` turned into ``scale * R(refquat)^T (v - refpos)`` (componentwise
    scale, measured against MuJoCo).

    Attributes:
        name: The asset's name.
        file: Its file name as MuJoCo keeps it (an included file's folder before it when
            MuJoCo found it there, see `mesh_candidates`), or None.
        meshdir: The ``meshdir`` (or ``assetdir``) of the model's ``<compiler>``.
        scale: Its ``scale``.
        refpos: Its ``refpos``.
        refquat: Its ``refquat`` (w, x, y, z), as written (normalised when used).
        maxhullvert: Its ``maxhullvert`` (-1: no bound).
        vertices: The vertices written inline (``vertex``), x, y, z after one another;
            None when there were too many to send (`_geom_facts.MAX_INLINE_NUMBERS`).
        plugin: A mesh a plugin makes (not read).
    """

    name: str
    file: str | None
    meshdir: str
    scale: Vec3
    refpos: Vec3
    refquat: tuple[float, float, float, float]
    maxhullvert: int
    vertices: tuple[float, ...] | None
    plugin: bool


class MjcfGeometry(NamedTuple):
    """An MJCF model's collision geometry and contact filters.

    Attributes:
        total: How many geoms the model has (``ngeom``).
        geoms: Each geom by MuJoCo id; () when `total` is past
            `_geom_facts.MAX_GEOMS`.
        meshes: The mesh assets.
        bodies: Each body's name as cspace gives it, by MuJoCo body id (0: the world).
        parent: Each body's parent's id (``body_parentid``).
        weld: Each body's ``body_weldid``.
        dofnum: Each body's ``body_dofnum``.
        excludes: Each ``<exclude>``: the two body ids, MuJoCo's line.
        pairs: Each ``<pair>``: the two geom ids, MuJoCo's line.
        disabled: ``"contact"`` or ``"constraint"`` when ``<flag>`` turns every contact
            off, else None.
        filterparent: Whether MuJoCo's parent-child filter is on.
        robot_file: The main file on disk (mesh names are relative to its folder), or
            None.
        allow_dirs: The folders besides the robot's that the run may read.
        source: The main file as read (its lines are found in it).
        own_lines: MuJoCo's nonzero lines are the main document's (no ``<attach>``).
        named: Of each named element of an included file: its name, file and line.
        documents: Each included file as MuJoCo was given it: the name the model uses,
            its text.
    """

    total: int
    geoms: tuple[MjcfGeom, ...]
    meshes: tuple[MjcfMesh, ...]
    bodies: tuple[str, ...]
    parent: tuple[int, ...]
    weld: tuple[int, ...]
    dofnum: tuple[int, ...]
    excludes: tuple[tuple[int, int, int], ...]
    pairs: tuple[tuple[int, int, int], ...]
    disabled: str | None
    filterparent: bool
    robot_file: str | None
    allow_dirs: tuple[str, ...]
    source: SourceFile
    own_lines: bool
    named: tuple[tuple[str, str, int], ...]
    documents: tuple[tuple[str, bytes], ...]


def _floats(values: Any, count: int) -> tuple[float, ...]:
    """``count`` numbers, or ValueError."""
    numbers = tuple(float(x) for x in values)
    if len(numbers) != count:
        raise ValueError("wrong count")
    return numbers


def _geom(row: Sequence[Any], nbody: int, nmesh: int) -> MjcfGeom:
    body, kind, size, pos, quat, contype, conaffinity, mesh, fitted, line, name = row
    if not 0 <= int(body) < nbody or not -1 <= int(mesh) < nmesh:
        raise ValueError("an id out of range")
    kind = int(kind)
    return MjcfGeom(
        int(body),
        GEOM_KINDS[kind] if 0 <= kind < len(GEOM_KINDS) else "unknown",
        _floats(size, 3),  # type: ignore[arg-type]
        _floats(pos, 3),  # type: ignore[arg-type]
        _floats(quat, 4),  # type: ignore[arg-type]
        int(contype),
        int(conaffinity),
        int(mesh),
        bool(fitted),
        int(line),
        None if name is None else str(name),
    )


def _mesh(row: Sequence[Any]) -> MjcfMesh:
    name, file, meshdir, scale, refpos, refquat, maxhullvert, vertices, plugin = row
    return MjcfMesh(
        str(name),
        str(file) or None,
        str(meshdir),
        _floats(scale, 3),  # type: ignore[arg-type]
        _floats(refpos, 3),  # type: ignore[arg-type]
        _floats(refquat, 4),  # type: ignore[arg-type]
        int(maxhullvert),
        None if vertices is None else tuple(float(x) for x in vertices),
        bool(plugin),
    )


def read_geometry(
    facts: dict[str, Any],
    bodies: Sequence[str],
    parents: Sequence[int],
    source: SourceFile,
    robot_file: str | None,
    allow_dirs: Sequence[Any],
    scan: PreScan,
) -> MjcfGeometry:
    """The records of the child's ``collision`` facts (`_geom_facts.collision_facts`).

    Args:
        facts: The facts.
        bodies: Each body's name as cspace gives it, by MuJoCo id.
        parents: Each body's parent id.
        source: The main file as read.
        robot_file: The main file on disk, or None.
        allow_dirs: The run's ``--allow-dir`` folders.
        scan: The pre-scan (included files, named elements' places).

    Raises:
        ValueError: The facts are malformed (TypeError, KeyError, IndexError too).
    """
    nbody = len(bodies)
    meshes = tuple(_mesh(row) for row in facts.get("meshes", ()))
    geoms = tuple(_geom(row, nbody, len(meshes)) for row in facts.get("geoms", ()))
    weld = tuple(int(b) for b in facts.get("weld", range(nbody)))
    dofnum = tuple(int(n) for n in facts.get("dofnum", [0] * nbody))
    if len(weld) != nbody or len(dofnum) != nbody or not all(0 <= b < nbody for b in weld):
        raise ValueError("bodies do not match")
    excludes = tuple((int(a), int(b), int(line)) for a, b, line in facts.get("excludes", ()))
    pairs = tuple((int(a), int(b), int(line)) for a, b, line in facts.get("pairs", ()))
    if not all(0 <= a < nbody and 0 <= b < nbody for a, b, _ in excludes) or not all(
        0 <= a < len(geoms) and 0 <= b < len(geoms) for a, b, _ in pairs
    ):
        raise ValueError("an id out of range")
    flags = facts.get("disabled", {})
    disabled = next((k for k in ("contact", "constraint") if flags.get(k)), None)
    by_name = {given: name for given, name in scan.given.items()}
    return MjcfGeometry(
        total=int(facts["ngeom"]),
        geoms=geoms,
        meshes=meshes,
        bodies=tuple(bodies),
        parent=tuple(int(p) for p in parents),
        weld=weld,
        dofnum=dofnum,
        excludes=excludes,
        pairs=pairs,
        disabled=disabled,
        filterparent=not flags.get("filterparent", False),
        robot_file=robot_file,
        allow_dirs=tuple(str(d) for d in allow_dirs),
        source=source,
        own_lines=not scan.attaches,
        named=tuple((name, file, line) for name, (file, line) in scan.where.items() if file),
        documents=tuple((by_name.get(k, k), v) for k, v in scan.includes.items()),
    )


def mesh_candidates(mesh: MjcfMesh, documents: Sequence[str]) -> list[str]:
    """The names, relative to the main file's folder, MuJoCo tries for a mesh's file.

    MuJoCo (``ResolveFilePath``) keeps a file name that its ``meshdir`` leads to, and
    otherwise puts the folder of the included file the ``<mesh>`` stands in before it;
    it then reads ``meshdir`` joined with that name (an absolute name alone). The child
    found no file (it is given none), so an included mesh's name comes with its
    include's folder: both places are tried, ``meshdir`` first, as MuJoCo does.

    Args:
        mesh: The mesh asset.
        documents: The included files' names as MuJoCo was given them.
    """
    file = mesh.file or ""
    if not file or file.startswith("/"):
        return [file] if file else []
    joined = f"{mesh.meshdir.rstrip('/')}/" if mesh.meshdir else ""
    for name in documents:
        folder = name.rsplit("/", 1)[0] + "/" if "/" in name else ""
        if folder and file.startswith(folder) and not folder.startswith("/"):
            return [joined + file[len(folder) :], file]
    return [joined + file]


def _parse(data: bytes) -> Any:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    return etree.fromstring(data, parser)


class Lines:
    """Where MuJoCo's elements stand in the robot's files, found on first use.

    Args:
        geometry: The model's geometry (its main file's bytes, its included files).
    """

    def __init__(self, geometry: MjcfGeometry) -> None:
        self.geometry = geometry
        self._root: Any = None
        self._main: dict[tuple[str, int], int] | None = None
        self._named = {name: (file, line) for name, file, line in geometry.named}
        self._documents = dict(geometry.documents)
        self._firsts: dict[str, dict[str, str]] = {}

    def root(self) -> Any:
        """The main file's root element, parsed again."""
        if self._root is None:
            self._root = parse_xml(self.geometry.source)
        return self._root

    def main(self) -> dict[tuple[str, int], int]:
        """``(tag, MuJoCo's line) -> the main file's line`` (`LINE_TAGS` only).

        Empty when MuJoCo's lines may be another file's (an ``<attach>``).
        """
        if self._main is None:
            self._main = {}
            if self.geometry.own_lines:
                root = self.root()
                again = _parse(mujoco_document(root).encode("utf-8"))
                # the same elements in the same order (`_models.original_line`)
                elements = root.iter(tag=etree.Element)
                for element, copy in zip(elements, again.iter(tag=etree.Element), strict=False):
                    line = line_of(element)
                    if copy.tag in LINE_TAGS and copy.sourceline and line is not None:
                        self._main.setdefault((str(copy.tag), int(copy.sourceline)), line)
        return self._main

    def at(self, tag: str, line: int, name: str | None = None) -> tuple[int | None, str | None]:
        """The line of ``<tag>`` at MuJoCo's ``line``, and its file when not the main one.

        An element of an included file (MuJoCo's line 0) is found by its ``name``: the
        pre-scan keeps the first place of each name, which is this element's when the
        first element of that name in that file is a ``<tag>``.

        Returns:
            The line (None when unknown) and the file as the model names it (None: the
            main file, or unknown).
        """
        if line > 0 and self.geometry.own_lines:
            return self.main().get((tag, line)), None
        place = self._named.get(name or "")
        if place is None:
            return None, None
        file, at = place
        firsts = self._firsts.get(file)
        if firsts is None:
            firsts = {}
            text = self._documents.get(file)
            if text is not None:
                for element in _parse(text).iter(tag=etree.Element):
                    firsts.setdefault(str(element.get("name")), str(element.tag))
            self._firsts[file] = firsts
        return (at, file) if firsts.get(name or "") == tag else (None, None)

    def flag(self, attribute: str) -> int | None:
        """The main file's line of the first ``<flag>`` that disables ``attribute``."""
        for flag in self.root().iter("flag"):
            if flag.get(attribute) == "disable":
                return line_of(flag)
        return None


def finite(values: Sequence[float]) -> bool:
    """Whether every number is finite."""
    return all(math.isfinite(x) for x in values)
