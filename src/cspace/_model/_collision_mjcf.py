"""An MJCF robot's collision shapes, and which pairs of its bodies MuJoCo checks.

`mjcf_collision` takes a robot read from MJCF (the loader's ``_Built``) and gives what
the self-collision engine (`cspace._model._collision_pairs.SelfCollision`) needs:

- **Shapes**, one coal object per collision geom as MuJoCo compiled it (the reader's
  confined child sends the compiled facts, `cspace._formats.mjcf._geometry`), on the
  ``BODY`` frame of its MuJoCo body in the Pinocchio model cspace builds, placed by
  ``geom_pos`` and ``geom_quat``: spheres, capsules, cylinders, boxes and ellipsoids as
  coal's primitives of MuJoCo's sizes (half-lengths doubled), meshes as MuJoCo collides
  them, the convex hull of the mesh's vertices (`_collision_hulls`), a coal ``Convex``.
  A link is a MuJoCo body. The world body's own geoms are the environment, not the
  robot: they are left out. Other bodies welded to the world (static) are links. A geom
  with ``contype`` and ``conaffinity`` both 0 that no ``<pair>`` names is visual, never
  collided: left out. Planes, height fields, SDFs, primitives MuJoCo fits to a mesh and
  meshes that cannot be had are `GeomProblem`s.
- **Filters**, for every pair of bodies with shapes: whether MuJoCo tests at least one
  geom pair of them for contact (`PairFilter`), and the rule that decides, in the order
  ``mj_collision`` applies them (``engine_collision_driver.c``): ``<flag contact>`` or
  ``<flag constraint>`` disabled turns every contact off; an explicit ``<pair>`` is
  checked whatever else holds; a body whose geoms all have ``contype`` and
  ``conaffinity`` 0 is never checked; two bodies of one weld body (welded together) are
  not; two bodies whose weld bodies both have no degree of freedom (static, mocap) are
  not; a weld body and its parent weld body are not, unless ``<flag filterparent>`` is
  disabled or either is the world; then the bodies' ``contype``/``conaffinity`` bits,
  ``<contact><exclude>``, and the bits geom by geom (``contype1 & conaffinity2`` or
  ``contype2 & conaffinity1``). Sleeping bodies and a ``mjcb_contactfilter`` callback
  are no part of a file.

A checked pair of which MuJoCo tests only some pairs of shapes (an explicit ``<pair>``
between bodies the other rules filter, or geoms of one body with other bits) is named in
`MjcfCollision.partial` with the shape pairs it tests.
"""

from collections.abc import Mapping
from typing import Any

import numpy as np

from cspace._formats.mjcf._geom_facts import MAX_GEOMS
from cspace._formats.mjcf._geometry import (
    Lines,
    MjcfGeom,
    MjcfGeometry,
    finite,
    mesh_candidates,
)
from cspace._model._collision_hulls import convex_geometry, convex_hulls, placed, rotation
from cspace._model._collision_pairs import LinkPair, link_pair
from cspace._model._collision_shapes import Shapes, check_shape_count
from cspace._record import NamedTuple
from cspace._reports.collisions import MUJOCO_PARENT

CONTACT_OFF = "contacts disabled"
PAIR = "<pair>"
BITS = "contype/conaffinity"
SAME_WELD = "same body weld"
STATIC = "both static"
PARENT = MUJOCO_PARENT
EXCLUDE = "<exclude>"
REASONS = (CONTACT_OFF, PAIR, BITS, SAME_WELD, STATIC, PARENT, EXCLUDE)
"""Every `PairFilter.reason`; a checked pair's is `PAIR` or `BITS`."""

PRIMITIVES = ("sphere", "capsule", "cylinder", "box", "ellipsoid")


class PairFilter(NamedTuple):
    """Whether MuJoCo checks two bodies for contact, and why.

    Attributes:
        checked: MuJoCo tests at least one geom pair of the two bodies for contact.
        reason: The rule that decides (one of `REASONS`).
        line: The line of the element that decides (the ``<flag>``, ``<pair>``,
            ``<exclude>``, the geom whose bits decide, the child body, the body welded),
            when known.
        file: The file of that line when it is an included file, else None.
    """

    checked: bool
    reason: str
    line: int | None
    file: str | None = None


class GeomProblem(NamedTuple):
    """A collision geom cspace does not check.

    Attributes:
        body: Its body.
        line: Its ``<geom>`` element's line in the main file, when known there.
        problem: Why, in one line (ending ``(in FILE, line N)`` for a geom of an
            included file whose line is known).
    """

    body: str
    line: int | None
    problem: str


class MjcfCollision(NamedTuple):
    """An MJCF robot's collision shapes and MuJoCo's filters of its body pairs.

    Attributes:
        shapes: The shapes on the Pinocchio model's ``BODY`` frames (objects named
            ``<body>/<k>``, the k-th shape of the body).
        filters: Every pair of bodies with shapes (names sorted) -> its `PairFilter`.
        problems: The collision geoms not checked, in MuJoCo's geom order.
        geoms: MuJoCo's geom id of each object of ``shapes.geometry``.
        partial: The checked pairs of which MuJoCo tests only some pairs of shapes ->
            those pairs, as object indices (smaller first).
    """

    shapes: Shapes
    filters: "Mapping[LinkPair, PairFilter]"
    problems: tuple[GeomProblem, ...]
    geoms: tuple[int, ...]
    partial: "Mapping[LinkPair, tuple[tuple[int, int], ...]]"


def mjcf_collision(built: Any, *, limits: Any = None) -> MjcfCollision:
    """The collision shapes and MuJoCo's filters of a robot read from MJCF.

    Args:
        built: The loader's ``_Built`` of an MJCF file.
        limits: The mesh parser's bounds (`cspace._formats.meshes.load.MeshLimits`;
            default its defaults).

    Raises:
        ValueError: Not an MJCF robot, no geometry read (the compiling child could not
            read it), no Pinocchio model, or more than
            `cspace._formats.mjcf._geom_facts.MAX_GEOMS` geoms (one line each);
            `TooManyShapes`, a subclass, past
            `cspace._model._collision_shapes.MAX_SHAPES` collision geoms.
        FileUnreadableError: An ``--allow-dir`` folder reached through a link out of it.
    """
    import pinocchio as pin

    geometry = built.reading.geometry
    model = built.model.pinocchio
    if built.format != "mjcf":
        raise ValueError("MuJoCo's geoms and contact filters are read from an MJCF robot only")
    if not isinstance(geometry, MjcfGeometry):
        raise ValueError("MuJoCo's compiler gave no collision geometry cspace can read")
    if model is None:
        raise ValueError("the robot has no Pinocchio model to place its geoms on")
    if len(geometry.geoms) != geometry.total:
        raise ValueError(
            f"the model has {geometry.total:,} geoms, more than the {MAX_GEOMS:,} cspace "
            "reads of one MJCF model"
        )
    lines = Lines(geometry)
    paired = {g for a, b, _ in geometry.pairs for g in (a, b)}
    wanted = [
        (g, geom)
        for g, geom in enumerate(geometry.geoms)
        if geom.body != 0 and (geom.contype or geom.conaffinity or g in paired)
    ]
    check_shape_count(len(wanted))  # before any hull is made
    hulls = _hulls(geometry, [geom for _, geom in wanted], limits)
    problems: list[GeomProblem] = []
    objects = pin.GeometryModel()
    names: list[str] = []
    ids: list[int] = []
    counts: dict[str, int] = {}
    for g, geom in wanted:
        body = geometry.bodies[geom.body]
        solid = _solid(geometry, geom, hulls)
        if isinstance(solid, str) or not model.existFrame(body, pin.BODY):
            why = solid if isinstance(solid, str) else f"body '{body}' is no body of the model"
            line, file = _geom_line(lines, geom)
            if file is not None:
                why, line = f"{why} (in {file}, line {line})", None
            problems.append(GeomProblem(body, line, why))
            continue
        frame_id = model.getFrameId(body, pin.BODY)
        frame = model.frames[frame_id]
        at = pin.SE3(rotation(geom.quat), np.asarray(geom.pos, dtype=float))
        k = counts[body] = counts.get(body, -1) + 1
        objects.addGeometryObject(
            pin.GeometryObject(
                f"{body}/{k}", frame.parentJoint, frame_id, frame.placement * at, solid
            )
        )
        names.append(body)
        ids.append(g)
    with_geometry = tuple(dict.fromkeys(geometry.bodies[geometry.geoms[g].body] for g in ids))
    shapes = Shapes(objects, tuple(names), with_geometry)
    filters, partial = _filters(geometry, ids, lines, built.reading.description)
    return MjcfCollision(shapes, filters, tuple(problems), tuple(ids), partial)


def _geom_line(lines: Lines, geom: MjcfGeom) -> tuple[int | None, str | None]:
    return lines.at("geom", geom.line, geom.name)


def _mesh_name(geometry: MjcfGeometry, geom: MjcfGeom) -> str:
    return geometry.meshes[geom.mesh].name if geom.mesh >= 0 else "?"


def _solid(geometry: MjcfGeometry, geom: MjcfGeom, hulls: dict[int, Any]) -> Any:
    """The coal geometry of a geom in its own frame, or why there is none."""
    import pinocchio as pin

    coal = pin.coal
    if geom.fitted:
        return f"a {geom.kind} MuJoCo fits to mesh '{_mesh_name(geometry, geom)}' (not read)"
    if geom.kind == "mesh":
        hull = hulls.get(geom.mesh, "it names no mesh")
        return hull if not isinstance(hull, str) else f"mesh '{_mesh_name(geometry, geom)}': {hull}"
    if geom.kind not in PRIMITIVES:
        return f"a {geom.kind} geom, which cspace does not check"
    size = geom.size
    if not (finite(size) and finite(geom.pos) and finite(geom.quat)) or min(size) < 0:
        return f"a {geom.kind} of size {size} or frame not finite"
    if geom.kind == "sphere":
        return coal.Sphere(size[0])
    if geom.kind == "capsule":
        return coal.Capsule(size[0], 2.0 * size[1])
    if geom.kind == "cylinder":
        return coal.Cylinder(size[0], 2.0 * size[1])
    if geom.kind == "box":
        return coal.Box(2.0 * size[0], 2.0 * size[1], 2.0 * size[2])
    return coal.Ellipsoid(size[0], size[1], size[2])


def _hulls(geometry: MjcfGeometry, geoms: list[MjcfGeom], limits: Any) -> dict[int, Any]:
    """Each mesh the geoms use (by index) -> its coal ``Convex``, or why there is none."""
    from cspace._formats.meshes.load import MeshFile, load_meshes, problem_of
    from cspace._formats.shared import mesh_paths
    from cspace.errors import RobotFileError

    used = sorted({g.mesh for g in geoms if g.kind == "mesh" and not g.fitted and g.mesh >= 0})
    found: dict[int, Any] = {}
    files: dict[str, list[int]] = {}
    written: dict[str, str] = {}  # each file's name as the model writes it
    allowed: tuple[str, ...] = ()
    if geometry.robot_file is not None and any(geometry.meshes[k].file for k in used):
        allowed = mesh_paths.folders(geometry.robot_file, {}, geometry.allow_dirs)
    clouds: dict[int, Any] = {}
    for k in used:
        mesh = geometry.meshes[k]
        if mesh.plugin:
            found[k] = "a mesh a plugin makes (not read)"
        elif mesh.file:
            tried = mesh_candidates(mesh, [name for name, _ in geometry.documents])
            places = [mesh_paths.place(n, geometry.robot_file, {}, allowed) for n in tried]
            place = next((p for p in places if p.path is not None), places[0])
            if place.path is None:
                found[k] = f"'{place.name}': {place.reason}"
            else:
                files.setdefault(place.path, []).append(k)
                written.setdefault(place.path, place.name)
        elif mesh.vertices is None:
            found[k] = "more numbers written inline (vertex) than cspace reads"
        elif len(mesh.vertices) % 3 or not mesh.vertices:
            found[k] = "no file, and no whole vertices written inline"
        else:
            clouds[k] = np.asarray(mesh.vertices, dtype=float).reshape(-1, 3)
    read = load_meshes([MeshFile(p) for p in files], allow_dirs=allowed, limits=limits)
    for (path, ks), result in zip(files.items(), read, strict=True):
        for k in ks:
            if isinstance(result, RobotFileError):
                found[k] = f"'{written[path]}': {problem_of(result)}"
            else:
                clouds[k] = result.vertices
    order = sorted(clouds)
    made = convex_hulls(
        [
            (
                placed(clouds[k], m.scale, m.refpos, m.refquat),
                m.maxhullvert,
            )
            for k in order
            for m in (geometry.meshes[k],)
        ]
    )
    for k, hull in zip(order, made, strict=True):
        found[k] = hull if isinstance(hull, str) else convex_geometry(hull)
    return found


class _Body:
    """What the filters need of a body with shapes: its id, geoms and distinct bits."""

    def __init__(self, body: int) -> None:
        self.id = body
        self.geoms: list[int] = []  # geom ids (of shapes)
        self.masks: dict[tuple[int, int], int] = {}  # (contype, conaffinity) -> first geom

    def add(self, g: int, geom: MjcfGeom) -> None:
        self.geoms.append(g)
        self.masks.setdefault((geom.contype, geom.conaffinity), g)


class _Where:
    """The lines of bodies, geoms and contact elements, found on first use."""

    def __init__(self, geometry: MjcfGeometry, lines: Lines, description: Any) -> None:
        self.geometry = geometry
        self.lines = lines
        self.known = {link.name: link.line for link in description.links}

    def body(self, b: int) -> tuple[int | None, str | None]:
        name = self.geometry.bodies[b]
        line = self.known.get(name)
        return (line, None) if line is not None else self.lines.at("body", 0, name)

    def geom(self, g: int) -> tuple[int | None, str | None]:
        return _geom_line(self.lines, self.geometry.geoms[g])

    def element(self, tag: str, line: int) -> tuple[int | None, str | None]:
        return self.lines.at(tag, line)


def _filters(
    geometry: MjcfGeometry, ids: list[int], lines: Lines, description: Any
) -> tuple[dict[LinkPair, PairFilter], dict[LinkPair, tuple[tuple[int, int], ...]]]:
    """Every pair of bodies with shapes -> its filter; the partial pairs' shape pairs."""
    geoms = geometry.geoms
    bodies: dict[int, _Body] = {}
    for g in ids:
        bodies.setdefault(geoms[g].body, _Body(geoms[g].body)).add(g, geoms[g])
    index = {g: i for i, g in enumerate(ids)}
    where = _Where(geometry, lines, description)
    explicit: dict[tuple[int, int], list[tuple[int, int, int]]] = {}
    for g1, g2, line in geometry.pairs:
        if g1 in index and g2 in index:
            b1, b2 = sorted((geoms[g1].body, geoms[g2].body))
            explicit.setdefault((b1, b2), []).append((g1, g2, line))
    excluded = {(min(b1, b2), max(b1, b2)): line for b1, b2, line in geometry.excludes}
    off = None
    if geometry.disabled is not None:
        off = PairFilter(False, CONTACT_OFF, lines.flag(geometry.disabled))
    filters: dict[LinkPair, PairFilter] = {}
    partial: dict[LinkPair, tuple[tuple[int, int], ...]] = {}
    order = list(bodies.values())
    for i, one in enumerate(order):
        for other in order[i + 1 :]:
            pair = link_pair(geometry.bodies[one.id], geometry.bodies[other.id])
            a, b = (one, other) if pair[0] == geometry.bodies[one.id] else (other, one)
            ab = (min(a.id, b.id), max(a.id, b.id))
            if off is not None:
                filters[pair] = off
                continue
            decided = _default(geometry, a, b, excluded.get(ab), where)
            listed = explicit.get(ab, [])
            tested = {(index[g1], index[g2]) for g1, g2, _ in listed}
            if decided.checked:
                tested |= {
                    (index[g1], index[g2])
                    for g1 in a.geoms
                    for g2 in b.geoms
                    if _meets(geoms[g1], geoms[g2])
                }
            if listed:
                decided = PairFilter(True, PAIR, *where.element("pair", listed[0][2]))
            filters[pair] = decided
            if decided.checked and len(tested) < len(a.geoms) * len(b.geoms):
                partial[pair] = tuple(sorted((min(p), max(p)) for p in tested))
    return filters, partial


def _meets(one: MjcfGeom, other: MjcfGeom) -> bool:
    """MuJoCo's bitmask test: either geom's contype meets the other's conaffinity."""
    return bool(one.contype & other.conaffinity or other.contype & one.conaffinity)


def _default(
    geometry: MjcfGeometry, a: _Body, b: _Body, excluded: int | None, where: _Where
) -> PairFilter:
    """MuJoCo's rules for two bodies, but the flags and explicit pairs, in its order."""
    for body in (a, b):  # a body that can collide with nothing (its geoms' bits all 0)
        if set(body.masks) == {(0, 0)}:
            return PairFilter(False, BITS, *where.geom(body.geoms[0]))
    weld, parent = geometry.weld, geometry.parent
    wa, wb = weld[a.id], weld[b.id]
    if wa == wb:  # the one welded to the other, or the first
        welded = next((x for x in (a, b) if weld[x.id] != x.id), a)
        return PairFilter(False, SAME_WELD, *where.body(welded.id))
    if geometry.dofnum[wa] == 0 and geometry.dofnum[wb] == 0:
        return PairFilter(False, STATIC, *where.body(a.id))
    if geometry.filterparent and wa != 0 and wb != 0:
        if wa == weld[parent[wb]]:
            return PairFilter(False, PARENT, *where.body(wb))
        if wb == weld[parent[wa]]:
            return PairFilter(False, PARENT, *where.body(wa))
    ta = ca = tb = cb = 0
    for contype, conaffinity in a.masks:
        ta, ca = ta | contype, ca | conaffinity
    for contype, conaffinity in b.masks:
        tb, cb = tb | contype, cb | conaffinity
    if not (ta & cb or tb & ca):
        return PairFilter(False, BITS, *where.geom(a.geoms[0]))
    if excluded is not None:
        return PairFilter(False, EXCLUDE, *where.element("exclude", excluded))
    for g1 in a.masks.values():
        for g2 in b.masks.values():
            if _meets(geometry.geoms[g1], geometry.geoms[g2]):
                return PairFilter(True, BITS, *where.geom(g1))
    return PairFilter(False, BITS, *where.geom(a.geoms[0]))
