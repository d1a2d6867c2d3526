"""MoveIt's SRDF: the semantic description beside a URDF, read as written.

An SRDF names what a URDF does not: the virtual joint that holds the robot to the world
(``<virtual_joint type="fixed|floating|planar">``), the joints a planner must not move
(``<passive_joint>``), planning groups (``<group>`` of joints, links, chains and other
groups) and the poses stored for them (``<group_state>``). This reader only parses: the
names are resolved against the robot by the model layer (`cspace._model.groups`).
The collision elements (``<disable_collisions>``, ``<enable_collisions>``,
``<disable_default_collisions>``) are kept as written, as srdfdom reads them, for the
self-collision check; end effectors and Pinocchio's own extras (``<rotor_params>``,
``<specificities>``) do not bear on the C-space and are skipped.

SRDF files are untrusted like robot files: read once and bounded in bytes and XML tags
(`read_source`), and here in groups (`MAX_GROUPS`), members (`MAX_MEMBERS`), states
(`MAX_STATES`), numbers (`MAX_NUMBERS`) and collision elements
(`_collisions.MAX_COLLISION_ELEMENTS`). A value that is not a number is refused; NaN and
infinities are kept, for the checks to name as poses outside the space.
"""

from collections.abc import Iterable

from lxml import etree

from cspace._formats.shared.robot_size import check_name
from cspace._formats.shared.xmlio import SourceFile, line_of, parse_xml
from cspace._formats.srdf._collisions import (
    COLLISION_TAGS,
    CollisionPair,
    CollisionReader,
    NoDefault,
    unknown_links,
)
from cspace._formats.urdf.numbers import parse_number
from cspace._record import NamedTuple
from cspace.errors import InvalidElementError, NotARobotError

MAX_GROUPS = 1_000
"""Most ``<group>`` elements read (example-robot-data's largest SRDF has 27)."""

MAX_MEMBERS = 10_000
"""Most joints, links, chains and subgroups named by all groups together (a chain costs
the tree's depth, up to 1,000 links, to resolve)."""

MAX_STATES = 5_000
"""Most ``<group_state>`` elements read (as many as MJCF keyframes)."""

MAX_NUMBERS = 200_000
"""Most numbers all group states hold together (as MJCF keyframes)."""

MAX_VALUES = 7
"""Most numbers one joint's value holds (a floating joint's x y z qx qy qz qw)."""

VIRTUAL_TYPES = ("fixed", "floating", "planar")
"""The types of ``<virtual_joint>`` SRDF defines."""


class Named(NamedTuple):
    """A name an element gives and the element's line."""

    name: str
    line: int | None


class Chain(NamedTuple):
    """``<chain base_link tip_link>``: the joints on the path between two links."""

    base: str
    tip: str
    line: int | None


class Group(NamedTuple):
    """One ``<group>`` as written.

    Attributes:
        name: The group's name.
        joints: Its ``<joint>`` members.
        links: Its ``<link>`` members (each stands for the joint above the link).
        chains: Its ``<chain>`` members.
        subgroups: Its ``<group>`` members (other groups, all of whose joints it has).
        line: The group's line.
    """

    name: str
    joints: tuple[Named, ...]
    links: tuple[Named, ...]
    chains: tuple[Chain, ...]
    subgroups: tuple[Named, ...]
    line: int | None


class JointValue(NamedTuple):
    """One ``<joint name value>`` of a group state: the numbers as written."""

    joint: str
    values: tuple[float, ...]
    line: int | None


class GroupState(NamedTuple):
    """One ``<group_state name group>``: a named pose of a group.

    ``group`` is None when the element gives none (MoveIt refuses that; Pinocchio, which
    ignores groups, reads it, and example-robot-data ships such states): a pose of the
    whole robot.
    """

    name: str
    group: str | None
    values: tuple[JointValue, ...]
    line: int | None


class VirtualJoint(NamedTuple):
    """``<virtual_joint name type parent_frame child_link>``."""

    name: str
    type: str
    parent_frame: str
    child_link: str
    line: int | None


class Srdf(NamedTuple):
    """An SRDF file as written (names not yet resolved against the robot).

    Attributes:
        path: The file as the user named it.
        robot: The ``name`` of its ``<robot>``.
        virtual_joints: Its virtual joints.
        passive: Its passive joints.
        groups: Its groups, in file order.
        states: Its group states, in file order.
        sha256: The file's hash.
        notes: What was read but skipped, as MoveIt and Pinocchio skip it: ``(line,
            problem)`` (a state given twice, a joint given twice in one state).
        collision_pairs: Its ``<disable_collisions>`` and ``<enable_collisions>``, in
            file order.
        no_default: Its ``<disable_default_collisions link>``: links disabled against
            every other, except the pairs ``<enable_collisions>`` names.
        collision_notes: The collision elements srdfdom skips with an error (no
            ``link1``, ``link2`` or ``link``), as ``(line, problem)``: kept apart from
            ``notes``, which a report shows.
    """

    path: str
    robot: str
    virtual_joints: tuple[VirtualJoint, ...]
    passive: tuple[Named, ...]
    groups: tuple[Group, ...]
    states: tuple[GroupState, ...]
    sha256: str = ""
    notes: tuple[tuple[int | None, str], ...] = ()
    collision_pairs: tuple[CollisionPair, ...] = ()
    no_default: tuple[NoDefault, ...] = ()
    collision_notes: tuple[tuple[int | None, str], ...] = ()


def parse_srdf(source: SourceFile) -> Srdf:
    """Read an SRDF document from its file's bytes (the module docstring says what is kept).

    Raises:
        XmlSyntaxError: Not well-formed XML.
        NotARobotError: Its root is not ``<robot>``, or it holds a URDF's links or joints.
        InvalidElementError: A missing attribute, a value that is not numbers, a name
            given twice, or more elements than the limits above.
    """
    root = parse_xml(source)
    if root.tag != "robot":
        raise NotARobotError(
            source.path,
            f"root element <{root.tag}> is not an SRDF description (expected <robot>)",
            line=line_of(root),
            element=str(root.tag),
        )
    urdf = next(root.iterchildren("link", "joint"), None)
    if urdf is not None:
        raise NotARobotError(
            source.path,
            f"<robot> holds a <{urdf.tag}>: a URDF, not an SRDF (which names groups and "
            "states of a URDF's joints)",
            line=line_of(urdf),
            element=str(urdf.tag),
        )
    reader = _Reader(source.path)
    virtual, passive, groups, states = [], [], [], []
    for element in root.iterchildren(tag=etree.Element):
        tag = element.tag
        if tag == "virtual_joint":
            virtual.append(reader.virtual_joint(element))
        elif tag == "passive_joint":
            passive.append(Named(reader.attribute(element, "name"), line_of(element)))
        elif tag == "group":
            groups.append(reader.group(element))
        elif tag == "group_state":
            states.append(reader.state(element))
        elif tag in COLLISION_TAGS:
            reader.collisions.read(element)
    reader.unique("group", [Named(g.name, g.line) for g in groups])
    kept: dict[str, GroupState] = {}
    for state in states:  # Pinocchio keeps the first of a name; MoveIt a group's first
        label = state.name if state.group is None else f"{state.group}/{state.name}"
        if label in kept:
            reader.notes.append((state.line, f"group state '{label}' is given twice (first "
                                 f"on line {kept[label].line}): this one is skipped"))  # fmt: skip
        else:
            kept[label] = state
    reader.unique("virtual_joint", [Named(v.name, v.line) for v in virtual])
    return Srdf(
        path=source.path,
        robot=str(root.get("name", "")),
        virtual_joints=tuple(virtual),
        passive=tuple(passive),
        groups=tuple(groups),
        states=tuple(kept.values()),
        sha256=source.sha256,
        notes=tuple(reader.notes),
        collision_pairs=tuple(reader.collisions.pairs),
        no_default=tuple(reader.collisions.no_default),
        collision_notes=tuple(reader.collisions.notes),
    )


def with_links(srdf: Srdf, links: Iterable[str]) -> Srdf:
    """``srdf`` with each collision pair's links the robot lacks named (`CollisionPair.unknown`).

    Args:
        srdf: The SRDF as read.
        links: The names of the robot's links.
    """
    return srdf._replace(collision_pairs=unknown_links(srdf.collision_pairs, links))


class _Reader:
    """Reads the elements of one SRDF file, counting them against the limits."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.groups = self.members = self.states = self.numbers = 0
        self.notes: list[tuple[int | None, str]] = []
        self.collisions = CollisionReader(path)

    def fail(self, element: etree._Element, problem: str, code: str) -> InvalidElementError:
        return InvalidElementError(
            self.path, problem, line=line_of(element), element=str(element.tag), code=code
        )

    def attribute(self, element: etree._Element, name: str) -> str:
        value = element.get(name)
        if value is None or not value.strip():
            raise self.fail(
                element, f"<{element.tag}> has no '{name}' attribute", "missing-attribute"
            )
        if name != "value":  # a name: a report holds it
            check_name(self.path, value.strip(), line_of(element), f"<{element.tag}> {name}")
        return value.strip()

    def count(self, element: etree._Element, what: str, used: int, limit: int) -> int:
        if used >= limit:
            raise self.fail(
                element,
                f"more than {limit:,} {what}: more than cspace reads from an SRDF file",
                "too-many-elements",
            )
        return used + 1

    def virtual_joint(self, element: etree._Element) -> VirtualJoint:
        kind = self.attribute(element, "type")
        name = self.attribute(element, "name")
        if kind not in VIRTUAL_TYPES:
            raise self.fail(
                element,
                f"virtual joint '{name}' has type '{kind}' (SRDF's are {', '.join(VIRTUAL_TYPES)})",
                "unknown-joint-type",
            )
        return VirtualJoint(
            name,
            kind,
            self.attribute(element, "parent_frame"),
            self.attribute(element, "child_link"),
            line_of(element),
        )

    def group(self, element: etree._Element) -> Group:
        self.groups = self.count(element, "groups", self.groups, MAX_GROUPS)
        joints: list[Named] = []
        links: list[Named] = []
        subgroups: list[Named] = []
        chains: list[Chain] = []
        for member in element.iterchildren(tag=etree.Element):
            tag = member.tag
            if tag not in ("joint", "link", "chain", "group"):
                continue
            self.members = self.count(member, "group members", self.members, MAX_MEMBERS)
            line = line_of(member)
            if tag == "chain":
                base = self.attribute(member, "base_link")
                chains.append(Chain(base, self.attribute(member, "tip_link"), line))
            else:
                named = Named(self.attribute(member, "name"), line)
                {"joint": joints, "link": links, "group": subgroups}[str(tag)].append(named)
        return Group(
            self.attribute(element, "name"),
            tuple(joints),
            tuple(links),
            tuple(chains),
            tuple(subgroups),
            line_of(element),
        )

    def state(self, element: etree._Element) -> GroupState:
        self.states = self.count(element, "group states", self.states, MAX_STATES)
        name, group = self.attribute(element, "name"), element.get("group")
        if group is not None:
            check_name(self.path, group, line_of(element), "<group_state> group")
        values = []
        for joint in element.iterchildren(tag="joint"):
            values.append(self.value(joint, name))
        last = {v.joint: v for v in values}  # MoveIt and Pinocchio keep the last value
        for value in values:
            if last[value.joint] is not value:
                self.notes.append((value.line, f"state '{name}' gives joint '{value.joint}' "
                                   "twice: the last value is read"))  # fmt: skip
        return GroupState(name, group, tuple(last.values()), line_of(element))

    def value(self, element: etree._Element, state: str) -> JointValue:
        joint = self.attribute(element, "name")
        words = self.attribute(element, "value").split(None, MAX_VALUES)  # no more copies
        if len(words) > MAX_VALUES:
            raise self.fail(
                element,
                f"state '{state}' gives joint '{joint}' more than {MAX_VALUES} numbers; a "
                f"joint takes at most {MAX_VALUES}",
                "bad-number",
            )
        self.numbers += len(words)
        if self.numbers > MAX_NUMBERS:
            raise self.fail(
                element,
                f"the group states hold more than {MAX_NUMBERS:,} numbers: more than "
                "cspace reads from an SRDF file",
                "too-many-elements",
            )
        numbers = []
        for word in words:
            number = parse_number(word)  # C-locale decimals: no 1_0, as a C++ stream
            if number is None:
                shown = word if len(word) <= 40 else word[:40] + "..."
                raise self.fail(
                    element,
                    f"state '{state}' gives joint '{joint}' the value '{shown}', not a number",
                    "bad-number",
                )
            numbers.append(number)
        return JointValue(joint, tuple(numbers), line_of(element))

    def unique(self, what: str, named: list[Named], where: str = "") -> None:
        seen: dict[str, int | None] = {}
        for name, line in named:
            if name in seen:
                first = f" (first on line {seen[name]})" if seen[name] is not None else ""
                raise InvalidElementError(
                    self.path,
                    f"{what} '{name}' is given twice{where}{first}",
                    line=line,
                    element=name,
                    code="duplicate-name",
                )
            seen[name] = line
