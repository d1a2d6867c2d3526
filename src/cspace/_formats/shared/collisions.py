"""What every reader of collision shapes shares: their bounds, their count, their loop.

A URDF's or an SDF's ``<collision>`` elements (xacro's output is a URDF) are counted against
`MAX_COLLISIONS` and read one by one (`read_shapes`), an unreadable one kept with its line
and problem (`Unread`); a mesh's file name is kept up to `MAX_MESH_NAME` characters.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TypeVar

from lxml import etree

from cspace._formats.shared.xmlio import line_of
from cspace.errors import InvalidElementError

MAX_COLLISIONS = 50_000
"""Most ``<collision>`` elements (or SDF ``<collision>``s) read from one robot file. Real
robots have a few hundred (example-robot-data's talos_reduced, 52); the file's 250,000
tags admit as many empty ones."""

MAX_MESH_NAME = 4096
"""Longest mesh file name kept, in characters (Linux's PATH_MAX)."""

SHOWN_CHARS = 40
"""Most characters of a file's text quoted in a problem (`shown`)."""

_Shape = TypeVar("_Shape")


class Unread(Exception):
    """A collision element read no further: its problem, one line."""


def shown(text: str) -> str:
    """``text`` for a problem: its first `SHOWN_CHARS` characters, then ``...``."""
    return text if len(text) <= SHOWN_CHARS else text[:SHOWN_CHARS] + "..."


class CollisionCounter:
    """Counts a file's collision elements against `MAX_COLLISIONS`."""

    def __init__(self, path: str) -> None:
        self.path = path
        self.count = 0

    def add(self, element: etree._Element) -> bool:
        """Count one more: whether it is within the limit (the first past it raises).

        Raises:
            InvalidElementError: ``too-many-elements``, once.
        """
        self.count += 1
        if self.count == MAX_COLLISIONS + 1:
            raise InvalidElementError(
                self.path,
                f"the robot has more than {MAX_COLLISIONS:,} <collision> elements: more "
                "than cspace reads",
                code="too-many-elements",
                line=line_of(element),
                element="collision",
            )
        return self.count <= MAX_COLLISIONS


def read_shapes(
    collisions: Iterable[etree._Element],
    link: str,
    counter: CollisionCounter,
    read: Callable[[etree._Element], _Shape],
) -> tuple[tuple[_Shape, ...], tuple[tuple[int | None, str], ...]]:
    """Each of a link's ``<collision>`` elements read, counted by ``counter``.

    Args:
        collisions: The link's ``<collision>`` elements.
        link: The link's name, for the problems.
        counter: The file's count of collision elements.
        read: Reads one element, or raises `Unread`.

    Returns:
        The shapes read, and (line, ``link 'NAME': problem``) of each element not read.

    Raises:
        InvalidElementError: ``too-many-elements`` (`CollisionCounter.add`).
    """
    shapes: list[_Shape] = []
    unread: list[tuple[int | None, str]] = []
    for collision in collisions:
        if not counter.add(collision):
            break
        try:
            shapes.append(read(collision))
        except Unread as problem:
            unread.append((line_of(collision), f"link '{link}': {problem}"))
    return tuple(shapes), tuple(unread)
