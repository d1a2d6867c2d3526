"""Where an SDF document puts each link, joint and frame: SDFormat's pose graph.

Every element with a ``<pose>`` is a frame placed in another (its ``relative_to``), as
libsdformat builds the graph that Drake resolves:

- a link's pose is in its model's frame (``__model__``), a joint's in its child frame
  (what ``<child>`` names), a frame's in the frame it is attached to (``attached_to``,
  itself ``__model__`` by default, the world's for a frame of the ``<world>``), a nested
  model's in the frame of the model around it; ``relative_to`` names another frame of
  the same scope (``inner::link`` reaches into a nested model, ``__model__`` is the
  model's own frame, ``inner`` a nested model's);
- a model's ``placement_frame`` makes its ``<pose>`` that frame's pose, not its own;
- the document's top model is placed in the world by its ``<pose>``, which may not be
  ``relative_to`` anything (Drake refuses it);
- ``<pose>`` is x y z roll pitch yaw (``degrees="true"``: the angles in degrees) or,
  with ``rotation_format="quat_xyzw"``, x y z and a quaternion (x, y, z, w);
- an axis ``<xyz>`` is in the joint's frame, or in the one ``expressed_in`` names;
- SDFormat 1.4 to 1.6 as libsdformat converts them: ``<pose frame>`` is
  ``relative_to``; an axis with ``<use_parent_model_frame>`` true is in the model's
  frame, and so is every axis of a joint of the document's top models in 1.4.

A pose the graph cannot resolve (a name no frame has, a cycle, a malformed or
unnormalisable pose, an SDFormat version cspace does not know) is None: the joints it
would place are left unplaced (`JointSpec.origin` None), and `cspace.pinocchio_model`
refuses the model rather than return a wrong one. The C-space does not depend on it.

A quaternion is kept as written, not normalised, and a joint is placed as libsdformat
resolves its poses for Drake, in gz-math's arithmetic (`sdf._gz_pose`: a quaternion off unit
moves the joints placed relative to its frame off where rigid transforms put them, by
about twice its norm's error times the distance); one whose norm is outside
`QUATERNION_NORMS` (or a product of them along a chain) is taken for a mistake.

Every walk is iterative and each frame is resolved once.
"""

import math
import re
from collections.abc import Callable, Iterable

from lxml import etree

from cspace._formats.sdf._gz_pose import chained, invert, rigid, then, turn, usable
from cspace._formats.sdf._scene import (
    MODEL_FRAME,
    SEPARATOR,
    WORLD,
    SdfJoint,
    SdfLink,
    SdfScene,
    child_text,
)
from cspace._formats.shared.pose import (
    IDENTITY,
    Pose,
    Vector,
    compose,
    from_rpy,
    inverse,
)
from cspace._formats.urdf.numbers import parse_number
from cspace._record import NamedTuple

KNOWN_VERSIONS = ((1, 4), (1, 12))
"""The SDFormat versions whose pose rules are these (from, to, inclusive)."""

PLACEMENT_STEPS = 100_000
"""How many frames the walks to models' placement frames may step through in all."""

_VERSION = re.compile(r"\s*(\d{1,3})\.(\d{1,3})\s*")
_XML_SPACE = " \t\n\r"
_SPACES = re.compile(r"[ \t\n\r]+")  # what libsdformat's stream splits a pose's numbers at
_TRUE = ("true", "1")
_FALSE = ("false", "0")
_MODEL_AXIS = ("true", "True", "TRUE", "1")  # libsdformat's use_parent_model_frame values


class Placement(NamedTuple):
    """A joint placed as the file places it.

    Attributes:
        origin: The joint frame in its parent link's frame.
        child_in_joint: The child link's frame in the joint frame.
        axes: The axes asked for (``<axis>``, ``<axis2>``), each in the joint frame.
    """

    origin: Pose
    child_in_joint: Pose
    axes: tuple[Vector, ...]


def version_of(root: etree._Element) -> tuple[int, int] | None:
    """The ``<sdf version>`` as (major, minor), or None when cspace does not know it."""
    found = _VERSION.fullmatch(root.get("version", ""))
    if found is None:
        return None
    version = (int(found.group(1)), int(found.group(2)))
    return version if KNOWN_VERSIONS[0] <= version <= KNOWN_VERSIONS[1] else None


def read_pose(element: etree._Element | None, version: tuple[int, int]) -> tuple[str, Pose] | None:
    """The ``relative_to`` name ('' by default) and the pose of a ``<pose>`` element.

    None when libsdformat would refuse it, or would read it otherwise than as written
    (a number it reads by a prefix), or a quaternion whose norm is outside
    `QUATERNION_NORMS`. The quaternion is kept as written.
    """
    if element is None:
        return "", IDENTITY
    attributes = element.attrib
    if version < (1, 7) and "frame" in attributes:
        relative_to = str(attributes["frame"])
    elif "frame" in attributes:
        return None  # not an attribute of SDFormat 1.7 and later: Drake refuses it
    else:
        relative_to = str(attributes.get("relative_to", ""))
    degrees = str(attributes.get("degrees", "false")).strip().lower()
    rotation = str(attributes.get("rotation_format", "euler_rpy")).strip()
    if degrees not in _TRUE + _FALSE or rotation not in ("euler_rpy", "quat_xyzw"):
        return None
    if rotation == "quat_xyzw" and degrees in _TRUE:
        return None
    words = _SPACES.split((element.text or "").strip(_XML_SPACE))
    if words == [""]:
        return relative_to.strip(), IDENTITY
    numbers = [parse_number(word) for word in words]
    values = [n for n in numbers if n is not None and math.isfinite(n)]
    if len(values) != len(words) or len(values) != (7 if rotation == "quat_xyzw" else 6):
        return None
    position = (values[0], values[1], values[2])
    if rotation == "quat_xyzw":
        x, y, z, w = values[3:]
        if not usable((w, x, y, z)):
            return None
        return relative_to.strip(), Pose(position, (w, x, y, z))
    angles = [math.radians(a) for a in values[3:]] if degrees in _TRUE else values[3:]
    return relative_to.strip(), Pose(position, from_rpy(angles[0], angles[1], angles[2]))


class _Edge(NamedTuple):
    """A frame's pose in another: ``parent`` (a vertex, None when unresolved) and the pose."""

    parent: str | None
    pose: Pose | None


class PoseGraph:
    """Every frame of an SDF document, each placed in another; resolved in the world.

    Vertices are scoped names: links, joints and frames as the scene names them, a
    model's own frame as its scope followed by ``__model__``, the world as ``world``.
    A link's, joint's or frame's ``<pose>`` is read when a placement needs it; models'
    are read first, each inside model before the one around it (a placement frame may
    be in a model inside).
    """

    def __init__(self, scene: SdfScene, root: etree._Element) -> None:
        self.kinds = scene.kinds
        version = version_of(root)
        self.known = version is not None
        self.version = version or KNOWN_VERSIONS[1]
        self.edges: dict[str, _Edge] = {}
        self.in_world: dict[str, Pose | None] = {WORLD: IDENTITY}  # rigid
        self.in_roots: dict[str, dict[str, Pose | None]] = {}  # as libsdformat, from a root
        self.steps = PLACEMENT_STEPS
        self.unread: dict[str, SdfLink | SdfJoint] = {}  # poses not read yet
        # the element holding each scope's <frame>s (None: the world's), and those read
        world = root.find("world")
        self.holders: dict[str | None, etree._Element] = {m.scope: m.element for m in scene.models}
        self.holders.update({} if world is None else {None: world})
        self.frames: dict[str | None, dict[str, etree._Element]] = {}
        if not self.known:
            return
        self.unread.update((link.name, link) for link in scene.links)
        self.unread.update((joint.name, joint) for joint in scene.joints)
        top_in_world = world is not None
        for model in reversed(scene.models):
            self._add_model(model.element, model.scope, model.outer, top_in_world)

    def _edge(self, vertex: str) -> _Edge | None:
        """Where ``vertex`` is placed (None for the world and for names of nothing)."""
        edge = self.edges.get(vertex)
        if edge is not None:
            return edge
        item = self.unread.pop(vertex, None)
        scope: str | None
        if isinstance(item, SdfLink):
            element, scope, default = item.element, item.scope, MODEL_FRAME
        elif isinstance(item, SdfJoint):  # in its child frame
            scope = None if item.of_world else item.scope
            element, default = item.element, item.child_frame
        elif self.kinds.get(vertex) == "frame":  # in the frame it is attached to
            element, scope = self._frame(vertex)
            default = element.get("attached_to", "").strip() or _own(scope)
        else:
            return None
        read = read_pose(element.find("pose"), self.version)
        if read is None:
            edge = _Edge(None, None)
        else:
            edge = _Edge(self.vertex(read[0] or default, scope), read[1])
        self.edges[vertex] = edge
        return edge

    def _frame(self, vertex: str) -> tuple[etree._Element, str | None]:
        """A ``<frame>``'s element and scope, its scope's frames indexed on first need."""
        scope: str | None
        if SEPARATOR in vertex:
            scope, _, name = vertex.rpartition(SEPARATOR)
            scope += SEPARATOR
        else:  # the document's only model's, or the world's when its models are prefixed
            scope, name = ("" if "" in self.holders else None), vertex
        if scope not in self.frames:
            frames = self.holders[scope].iterchildren("frame")
            self.frames[scope] = {f.get("name", "").strip(): f for f in frames}
        return self.frames[scope][name], scope

    def _add_model(
        self, element: etree._Element, scope: str, outer: str | None, in_world: bool
    ) -> None:
        vertex = scope + MODEL_FRAME
        read = read_pose(element.find("pose"), self.version)
        if read is None or (outer is None and not in_world and read[0]):
            self.edges[vertex] = _Edge(None, None)  # Drake refuses a top model's relative_to
            return
        relative_to, written = read
        parent = self.vertex(relative_to or _own(outer), outer)
        placement = element.get("placement_frame", "").strip()
        pose: Pose | None = written
        if placement:  # the pose is that frame's: the model's own is what puts it there
            inside = self._relative(self.vertex(placement, scope), vertex)
            pose = None if inside is None else chained(written, invert(inside))
        self.edges[vertex] = _Edge(parent, pose)

    def vertex(self, name: str, scope: str | None) -> str | None:
        """The vertex a frame ``name`` written in ``scope`` (None: the world's) names."""
        if scope is None and name == WORLD:
            return WORLD
        if scope is not None and name == MODEL_FRAME:
            return scope + MODEL_FRAME
        scoped = (scope or "") + name
        if scoped.endswith(SEPARATOR + MODEL_FRAME):
            inner = scoped.removesuffix(SEPARATOR + MODEL_FRAME)
            return scoped if self.kinds.get(inner) == "model" else None
        kind = self.kinds.get(scoped)
        if kind == "model":
            return scoped + SEPARATOR + MODEL_FRAME
        return scoped if kind in ("link", "joint", "frame") else None

    def _relative(self, start: str | None, stop: str) -> Pose | None:
        """``start``'s pose in ``stop``, one of the frames it is placed in (else None).

        As libsdformat composes it: the quaternions' product, not normalised.
        """
        pose = IDENTITY
        seen = set()
        vertex = start
        while vertex != stop:
            self.steps -= 1
            edge = None if vertex is None else self._edge(vertex)
            if edge is None or edge.pose is None or vertex in seen or self.steps < 0:
                return None
            seen.add(vertex)
            step = chained(edge.pose, pose)
            if step is None:
                return None
            pose, vertex = step, edge.parent
        return pose

    def world(self, vertex: str | None) -> Pose | None:
        """The pose of ``vertex`` in the world (rigid), or None when the file does not resolve it.

        Drake's too: it composes the poses of models, each resolved from its outer
        model's frame, and of links from their model's, as rigid transforms.
        """
        return self._resolve(vertex, self.in_world, lambda a, b: _after(a, rigid(b)))

    def _from_root(self, vertex: str | None, root: str) -> Pose | None:
        """The pose of ``vertex`` from ``root`` as libsdformat resolves it, or None.

        The quaternion is the product of those on the way (its norm in
        `QUATERNION_NORMS`); None too when ``root`` is not on ``vertex``'s way to the world.
        """
        return self._resolve(vertex, self.in_roots.setdefault(root, {root: IDENTITY}), chained)

    def _resolve(
        self,
        vertex: str | None,
        resolved: dict[str, Pose | None],
        step: Callable[[Pose, Pose], Pose | None],
    ) -> Pose | None:
        """``vertex``'s pose from a frame ``resolved`` holds, each frame on the way added."""
        chain: list[str] = []
        on_chain: set[str] = set()
        while vertex is not None and vertex not in resolved:
            if vertex in on_chain:  # a cycle of relative_to
                break
            chain.append(vertex)
            on_chain.add(vertex)
            edge = self._edge(vertex)
            vertex = None if edge is None else edge.parent
        placed = resolved.get(vertex) if vertex is not None and vertex not in on_chain else None
        for frame in reversed(chain):
            edge = self.edges.get(frame)
            if placed is not None and edge is not None and edge.pose is not None:
                placed = step(placed, edge.pose)
            else:
                placed = None
            resolved[frame] = placed
        return placed

    def joint(self, joint: SdfJoint, axes: Iterable[tuple[str, Vector]]) -> Placement | None:
        """The joint's origin, its child's frame in it and its axes in it, or None.

        As Drake places it: the joint's frame resolved by libsdformat relative to its
        parent link and to its child link in the pose graph of the joint's model, from
        that model's frame (the world's for a joint of the ``<world>``), each made rigid;
        relative to the world, the model's pose in the world and the joint's in its model.

        Args:
            joint: The joint, its parent and child resolved to links.
            axes: The axes to turn into the joint frame: each one's tag (``axis``,
                ``axis2``) and its ``<xyz>`` as written.
        """
        if not self.known:
            return None
        root = WORLD if joint.of_world else joint.scope + MODEL_FRAME
        at = self._from_root(joint.name, root)
        if at is None:
            return None
        origin = self._seen_from(joint.parent, joint.name, at, root)
        child = self._seen_from(joint.child, joint.name, at, root)
        if origin is None or child is None:
            return None
        turned: list[Vector] = []
        for tag, xyz in axes:
            named = self._axis_frame(joint, tag)
            if named == joint.name:
                turned.append(xyz)
                continue
            frame = None if named is None else self._from_root(named, root)
            if frame is None:
                return None
            turned.append(turn(then(invert(at), frame).rotation_wxyz, xyz))
        return Placement(origin, _inverse(child), tuple(turned))

    def _seen_from(self, link: str, vertex: str, at: Pose, root: str) -> Pose | None:
        """Drake's pose of ``vertex`` (``at`` from ``root``) in ``link``'s frame, or None."""
        if link == WORLD:
            return self.world(vertex)
        base = self._from_root(link, root)
        seen = None if base is None else chained(invert(base), at)
        return None if seen is None else rigid(seen)

    def _axis_frame(self, joint: SdfJoint, tag: str) -> str | None:
        """The vertex of the frame an axis is expressed in (the joint's by default), or None."""
        axis = joint.element.find(tag)
        xyz = None if axis is None else axis.find("xyz")
        scope = None if joint.of_world else joint.scope
        if axis is None:
            return joint.name
        named = "" if xyz is None else xyz.get("expressed_in", "").strip()
        if self.version < (1, 5):  # 1.4 puts a top model's axes in its frame, over expressed_in
            if axis.find("use_parent_model_frame") is not None:
                return None  # libsdformat adds its own beside it: which one counts is unclear
            if scope is not None and not _is_nested(joint.element):
                named = MODEL_FRAME
        elif self.version < (1, 7) and child_text(axis, "use_parent_model_frame") in _MODEL_AXIS:
            named = MODEL_FRAME
        if named and xyz is None:
            return None  # libsdformat writes expressed_in on an <xyz> of no value: Drake refuses
        return self.vertex(named, scope) if named else joint.name

    def link(self, link: SdfLink) -> Pose | None:
        """The link's pose in the world, or None."""
        return self.world(link.name) if self.known else None


def _own(scope: str | None) -> str:
    """The name of a scope's own frame: ``__model__`` in a model, ``world`` in the world."""
    return WORLD if scope is None else MODEL_FRAME


def _after(a: Pose, b: Pose) -> Pose:
    """``compose(a, b)``, without arithmetic when either is the identity (most poses are)."""
    if b == IDENTITY:
        return a
    return b if a == IDENTITY else compose(a, b)


def _inverse(a: Pose) -> Pose:
    """``inverse(a)``, without arithmetic for the identity."""
    return a if a == IDENTITY else inverse(a)


def _is_nested(joint: etree._Element) -> bool:
    """Whether a joint's model is inside another model (SDFormat 1.4's rule skips those)."""
    model = joint.getparent()
    outer = None if model is None else model.getparent()
    return outer is not None and outer.tag == "model"
