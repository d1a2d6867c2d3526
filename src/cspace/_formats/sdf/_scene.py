"""An SDF document's models, as SDFormat scopes them: links, joints and frames by name.

SDFormat (1.4 to 1.11) puts one ``<model>`` at the top of a document, or any number in
a ``<world>``, and a model may nest models. Names are scoped: a link ``l`` of a nested
model ``inner`` is ``inner::l`` from the model around it. A joint's ``<parent>`` and
``<child>`` (and a ``<frame attached_to>``) name a link, a frame (which is attached to
a link in the end), a nested model (its canonical link), ``__model__`` (the model's own
frame, on its canonical link) or ``world``.

Names in a report are scoped from the document's top: a document of one model names
its links and joints as the file does (``l``, ``inner::l``); a world of several models
prefixes each with its model's name (``arm::l``), as SDFormat scopes them, so that two
models may hold a link of one name.

The walk is iterative: no recursion on a file's nesting.
"""

from collections.abc import Mapping
from typing import NoReturn

from lxml import etree

from cspace._formats.shared.robot_size import MAX_NAME
from cspace._formats.shared.xmlio import line_of
from cspace._record import NamedTuple
from cspace.errors import InvalidElementError, NotARobotError, RobotStructureError

WORLD = "world"
"""The world frame's reserved name."""

MODEL_FRAME = "__model__"
"""A model's own frame: on its canonical link."""

SEPARATOR = "::"


class SdfLink(NamedTuple):
    """A link, scoped.

    Attributes:
        name: Its scoped name.
        element: Its ``<link>``.
        static: True when its model (or a model around it) is static.
        model: The scoped name of its model ('' for the document's only model).
        scope: Its model's scope: the prefix of its scoped name ('' or ``inner::``).
    """

    name: str
    element: etree._Element
    static: bool
    model: str
    scope: str = ""


class SdfJoint(NamedTuple):
    """A joint, scoped, with what its parent and child name resolved to links.

    Attributes:
        name: Its scoped name.
        element: Its ``<joint>``.
        parent: The parent link's scoped name, or ``world``.
        child: The child link's scoped name, or ``world``.
        static: True when its model is static.
        of_world: True for a joint of the ``<world>`` itself (between its models).
        scope: Its model's scope ('' or ``inner::``; '' for a joint of the world).
        child_frame: What its ``<child>`` names, as written (a link, a frame, a model...).
    """

    name: str
    element: etree._Element
    parent: str
    child: str
    static: bool
    of_world: bool = False
    scope: str = ""
    child_frame: str = ""


class SdfModel(NamedTuple):
    """A model, with the scope its names are written in.

    Attributes:
        element: Its ``<model>``.
        scope: Its own scope: the prefix of its elements' scoped names ('' for the
            document's only model, ``arm::`` in a world of several, ``arm::inner::``).
        outer: The scope of the model around it, or None for a model of the document
            or of its world.
    """

    element: etree._Element
    scope: str
    outer: str | None


class SdfScene(NamedTuple):
    """Every link and joint of an SDF document.

    Attributes:
        name: The model's name (the world's, for several models).
        links: Links in document order.
        joints: Joints in document order.
        element: The element the robot is read from (``<model>`` or ``<world>``).
        models: Every model, each before the models it holds.
        kinds: What each scoped name is: ``link``, ``joint``, ``frame`` or ``model``
            (a model's scoped name, without its ``::``, when it has a prefix).
    """

    name: str
    links: tuple[SdfLink, ...]
    joints: tuple[SdfJoint, ...]
    element: etree._Element
    models: tuple[SdfModel, ...] = ()
    kinds: Mapping[str, str] = {}


def _fail(path: str, code: str, problem: str, element: etree._Element) -> NoReturn:
    raise InvalidElementError(path, problem, code=code, line=line_of(element))


def _name(path: str, element: etree._Element, scope: str = "") -> str:
    """The element's name, checked; its scoped name (``scope`` + name) is a name too."""
    name = element.get("name", "").strip()
    if not name:
        _fail(path, "missing-attribute", f"<{element.tag}> has no name", element)
    if len(scope) + len(name) > MAX_NAME:  # before any longer scoped name is built
        raise RobotStructureError(
            path,
            f"<{element.tag}> has a scoped name of {len(scope) + len(name):,} characters, "
            f"more than the {MAX_NAME} cspace reads",
            code="name-too-long",
            line=line_of(element),
            element=element.tag,
        )
    if name == WORLD or (name.startswith("__") and name.endswith("__")):
        _fail(
            path,
            "reserved-name",
            f"<{element.tag}> is named '{name}', a name SDFormat reserves (the world, "
            "__model__ and other __names__); Drake refuses it too",
            element,
        )
    if SEPARATOR in name:
        _fail(path, "reserved-name", f"<{element.tag}> name '{name}' holds '::'", element)
    return name


def _is_static(model: etree._Element, outer: bool) -> bool:
    """A model's own ``<static>``, else its outer model's (as Drake reads nesting)."""
    flag = model.find("static")
    if flag is None:
        return outer
    return (flag.text or "").strip().lower() in ("1", "true")


def _top_models(path: str, root: etree._Element) -> tuple[etree._Element, list[etree._Element]]:
    worlds = list(root.iterchildren("world"))
    models = list(root.iterchildren("model"))
    if len(worlds) > 1 or (worlds and models):
        raise NotARobotError(
            path,
            "<sdf> holds several worlds or a world beside a model; cspace reads one",
            line=line_of(root),
            element="sdf",
        )
    holder = worlds[0] if worlds else root
    if worlds:
        models = list(holder.iterchildren("model"))
    for tag in ("include",):
        include = holder.find(tag) if worlds else None
        if include is not None:
            _include_refused(path, include)
    if not models:
        raise NotARobotError(path, "<sdf> holds no <model>", line=line_of(root), element="sdf")
    return holder, models


def _include_refused(path: str, include: etree._Element) -> NoReturn:
    _fail(
        path,
        "unsupported-element",
        "an <include> (a model:// or file URI) is not read: cspace reads one "
        "self-contained document",
        include,
    )


class _Scopes:
    """The names of each model scope: links, frames, nested models, canonical link."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.kind: dict[str, str] = {}  # scoped name -> "link", "joint", "frame", "model"
        # frame -> (what it is attached to, its scope); a joint's frame is on its child
        self.attached: dict[str, tuple[str, str]] = {}
        self.canonical: dict[str, str] = {}  # model scope ('' or 'a::') -> canonical link
        self.ends: dict[str, str] = {}  # frame -> the link it ends on, once resolved

    def add(self, scoped: str, kind: str, element: etree._Element) -> None:
        if scoped in self.kind:
            where = "one model" if SEPARATOR in scoped or kind != "model" else "the world"
            raise RobotStructureError(
                self.path,
                f"two elements are named '{scoped}' in {where} (a {self.kind[scoped]} and "
                f"a {kind}); SDFormat names must be unique there, and Drake refuses it too",
                code="duplicate-name",
                line=line_of(element),
                element=element.tag,
            )
        self.kind[scoped] = kind

    def resolve(self, name: str, scope: str, element: etree._Element) -> str:
        """The link (or ``world``) that ``name``, written in ``scope``, ends on.

        Each frame is followed once: the frames on the way remember where they end, so
        that many joints on a long chain of frames cost the chain once, not each time.
        """
        chain: list[str] = []
        on_chain: set[str] = set()
        while True:
            if name == WORLD:
                end = WORLD
            elif name == MODEL_FRAME:
                end = self.canonical.get(scope, WORLD)
            elif name.endswith(SEPARATOR + MODEL_FRAME):  # a nested model's own frame
                inner = scope + name.removesuffix(MODEL_FRAME)
                end = self.canonical.get(inner, inner + MODEL_FRAME)
            else:
                scoped = scope + name
                kind = self.kind.get(scoped)
                if scoped in self.ends:
                    end = self.ends[scoped]
                elif kind in ("link", None):
                    end = scoped  # an unknown name: the structure check says so, with its line
                elif kind == "model":
                    end = self.canonical.get(scoped + SEPARATOR, scoped)
                else:
                    if scoped in on_chain:
                        _fail(
                            self.path, "cycle", f"frame '{scoped}' is attached to itself", element
                        )
                    chain.append(scoped)
                    on_chain.add(scoped)
                    name, scope = self.attached[scoped]
                    continue
            for frame in chain:
                self.ends[frame] = end
            return end


def read_scene(path: str, root: etree._Element) -> SdfScene:
    """Every model of an ``<sdf>`` document, its links and joints scoped.

    Raises:
        NotARobotError: No model, or several worlds.
        InvalidElementError: A reserved or missing name, an ``<include>``, a moving joint
            in a static model (SDFormat and Drake refuse it).
        RobotStructureError: Two elements of one name in one scope.
    """
    holder, top = _top_models(path, root)
    in_world = holder.tag == "world"
    # a world of several models, or one whose own joints and frames name its models'
    # links (``m::base``): every name is scoped by its model
    prefix_top = len(top) > 1 or (
        in_world and (holder.find("joint") is not None or holder.find("frame") is not None)
    )
    scopes = _Scopes(path)
    links: list[SdfLink] = []
    models: list[SdfModel] = []
    joint_elements: list[tuple[etree._Element, str, bool, bool]] = []
    stack = [(m, "", False, prefix_top) for m in reversed(top)]
    while stack:
        model, outer, static_outer, prefixed = stack.pop()
        name = _name(path, model, outer)
        scope = f"{outer}{name}{SEPARATOR}" if prefixed else outer
        if prefixed:
            scopes.add(f"{outer}{name}", "model", model)
        models.append(SdfModel(model, scope, outer if model.getparent() is not holder else None))
        static = _is_static(model, static_outer)
        include = model.find("include")
        if include is not None:
            _include_refused(path, include)
        own_links = []
        for link in model.iterchildren("link"):
            scoped = scope + _name(path, link, scope)
            scopes.add(scoped, "link", link)
            own_links.append(scoped)
            links.append(SdfLink(scoped, link, static, scope.removesuffix(SEPARATOR), scope))
        for frame in model.iterchildren("frame"):
            scoped = scope + _name(path, frame, scope)
            scopes.add(scoped, "frame", frame)
            scopes.attached[scoped] = (frame.get("attached_to", "").strip() or MODEL_FRAME, scope)
        canonical = model.get("canonical_link", "").strip()
        nested = list(model.iterchildren("model"))
        if canonical:
            scopes.canonical[scope] = scope + canonical
        elif own_links:
            scopes.canonical[scope] = own_links[0]
        elif nested:  # the first nested model's canonical link, once it is read
            scopes.canonical[scope] = f"{scope}{nested[0].get('name', '').strip()}"
        for joint in model.iterchildren("joint"):  # one namespace with links and frames
            scopes.add(scope + _name(path, joint, scope), "joint", joint)
            scopes.attached[scope + _name(path, joint, scope)] = (child_text(joint, "child"), scope)
            joint_elements.append((joint, scope, static, False))
        stack += [(m, scope, static, True) for m in reversed(nested)]
    for scope, target in list(scopes.canonical.items()):  # a nested model's canonical link
        for _ in range(len(scopes.canonical)):  # models nest as a tree: this ends
            if scopes.kind.get(target) != "model":
                break
            target = scopes.canonical.get(target + SEPARATOR, WORLD)
        scopes.canonical[scope] = target
    for frame in holder.iterchildren("frame") if in_world else ():
        scopes.add(_name(path, frame), "frame", frame)
        scopes.attached[_name(path, frame)] = (frame.get("attached_to", "").strip() or WORLD, "")
    if in_world:
        joint_elements += [(j, "", False, True) for j in holder.iterchildren("joint")]
    joints = []
    for element, scope, static, of_world in joint_elements:
        name = scope + _name(path, element, scope)
        parent = scopes.resolve(child_text(element, "parent"), scope, element)
        written = child_text(element, "child")
        child = scopes.resolve(written, scope, element)
        joints.append(SdfJoint(name, element, parent, child, static, of_world, scope, written))
    model_name = top[0].get("name", "") if len(top) == 1 else holder.get("name", "")
    return SdfScene(
        model_name,
        tuple(links),
        tuple(joints),
        top[0] if len(top) == 1 else holder,
        tuple(models),
        scopes.kind,
    )


def child_text(element: etree._Element, tag: str) -> str:
    """The stripped text of ``element``'s first ``tag`` child ('' when it has none)."""
    child = element.find(tag)
    return "" if child is None or child.text is None else child.text.strip()
