"""What every reader of collision shapes shares: their bounds and their count.

A URDF's or an SDF's ``<collision>`` elements (xacro's output is a URDF) are counted against
`MAX_COLLISIONS`; a mesh's file name is kept up to `MAX_MESH_NAME` characters.
"""

from __future__ import annotations

from lxml import etree

from cspace._formats.shared.xmlio import line_of
from cspace.errors import InvalidElementError

MAX_COLLISIONS = 50_000
"""Most ``<collision>`` elements (or SDF ``<collision>``s) read from one robot file. Real
robots have a few hundred (example-robot-data's talos_reduced, 52); the file's 250,000
tags admit as many empty ones."""

MAX_MESH_NAME = 4096
"""Longest mesh file name kept, in characters (Linux's PATH_MAX)."""


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
