"""The names that tell an XML robot description, for the loader and for a folder's search.

Kept apart from the search (`_discover`, `_xml_look`), which the loader of one file
does not import.
"""

from __future__ import annotations

ROBOT_SUFFIXES = (".urdf", ".xacro", ".sdf")
"""Names that say a robot description whatever the root (xacro may wrap it), in any case."""

FRAGMENT_ROOTS = ("mujocoinclude",)
"""Root elements of files meant only to be included."""

MJCF_ROOTS = ("mujoco", *FRAGMENT_ROOTS)
XML_ROOTS = ("robot", "mujoco", "sdf")
"""Root elements of robot descriptions."""
