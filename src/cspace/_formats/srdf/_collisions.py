"""An SRDF's collision elements, read as srdfdom reads them (``model.cpp``).

srdfdom reads ``<disable_collisions link1 link2 [reason]>`` and ``<enable_collisions
link1 link2 [reason]>`` (``loadCollisionPairs``) and ``<disable_default_collisions
link>`` (``loadCollisionDefaults``), each link's name trimmed; an element without its
links is skipped with an error it prints, and a pair naming a link the URDF lacks is
dropped with a warning. Here the first are kept as notes apart from the SRDF's other
notes (a report shows those), and the second are kept with the links named, for the
finding that says so (`CollisionPair.unknown`). Names are bounded as the SRDF's
others, and the elements by `MAX_COLLISION_ELEMENTS`.
"""

from collections.abc import Iterable

from lxml import etree

from cspace._formats.shared.robot_size import check_name
from cspace._formats.shared.xmlio import line_of
from cspace._record import NamedTuple
from cspace.errors import InvalidElementError

MAX_COLLISION_ELEMENTS = 100_000
"""Most ``<disable_collisions>``, ``<enable_collisions>`` and
``<disable_default_collisions>`` elements read together (example-robot-data's talos.srdf
has 459; every pair of 450 links with collision shapes is about 100,000)."""

COLLISION_TAGS = ("disable_collisions", "enable_collisions", "disable_default_collisions")
"""The SRDF elements read here."""

_TRIMMED = " \t\n\v\f\r"
"""What srdfdom trims from a link's name (``boost::trim``, the C locale's white space)."""


class CollisionPair(NamedTuple):
    """``<disable_collisions>`` or ``<enable_collisions link1 link2 reason>``, as written.

    Attributes:
        disable: True for ``<disable_collisions>``, False for ``<enable_collisions>``.
        link1: The first link, trimmed as srdfdom trims it.
        link2: The second link.
        reason: The ``reason`` as written (MoveIt's ``Adjacent``, ``Never``...), or None
            when the element gives none (MoveIt then reads the pair as ``User``).
        line: The element's line.
        unknown: The pair's links the robot does not have (`unknown_links` sets it);
            srdfdom drops such a pair with a warning.
    """

    disable: bool
    link1: str
    link2: str
    reason: str | None
    line: int | None
    unknown: tuple[str, ...] = ()


class NoDefault(NamedTuple):
    """``<disable_default_collisions link>``: the link and the element's line."""

    name: str
    line: int | None


class CollisionReader:
    """Reads one SRDF file's collision elements, counting them."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.pairs: list[CollisionPair] = []
        self.no_default: list[NoDefault] = []
        self.notes: list[tuple[int | None, str]] = []
        self.elements = 0

    def read(self, element: etree._Element) -> None:
        """Read one of `COLLISION_TAGS`.

        Raises:
            InvalidElementError: More than `MAX_COLLISION_ELEMENTS` (``too-many-elements``).
            RobotStructureError: A link's name longer than a report holds.
        """
        tag, line = str(element.tag), line_of(element)
        self.elements += 1
        if self.elements > MAX_COLLISION_ELEMENTS:
            raise InvalidElementError(
                self.path,
                f"more than {MAX_COLLISION_ELEMENTS:,} collision elements: more than cspace "
                "reads from an SRDF file",
                line=line,
                element=tag,
                code="too-many-elements",
            )
        keys = ("link",) if tag == "disable_default_collisions" else ("link1", "link2")
        names = []
        for key in keys:
            value = element.get(key)
            if value is None:
                self.notes.append((line, f"<{tag}> has no '{key}' attribute"))
                return
            name = value.strip(_TRIMMED)
            check_name(self.path, name, line, f"<{tag}> {key}")
            names.append(name)
        if tag == "disable_default_collisions":
            self.no_default.append(NoDefault(names[0], line))
        else:
            disable = tag == "disable_collisions"
            reason = element.get("reason")
            if reason is not None:
                check_name(self.path, reason, line, f"<{tag}> reason")
            self.pairs.append(CollisionPair(disable, names[0], names[1], reason, line))


def unknown_links(
    pairs: Iterable[CollisionPair], links: Iterable[str]
) -> tuple[CollisionPair, ...]:
    """``pairs``, each with the links among its two that ``links`` lacks named."""
    known = set(links)
    return tuple(
        pair._replace(unknown=tuple(n for n in (pair.link1, pair.link2) if n not in known))
        for pair in pairs
    )
