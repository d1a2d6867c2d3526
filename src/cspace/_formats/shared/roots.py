"""The names that tell an XML robot description, for the loader and for a folder's search.

Kept apart from the search (`discovery.search`, `discovery._look`), which the loader of one file
does not import. An SRDF is told by its content, and by its name only where the content
holds neither a robot's elements nor an SRDF's (`srdf.kind`, `srdf.bytes_scan`).
"""

from __future__ import annotations

from cspace._formats.table import robot_suffixes, xml_roots

ROBOT_SUFFIXES = robot_suffixes()
"""Names that say a robot description whatever the root (xacro may wrap it), in any case."""

FRAGMENT_ROOTS = ("mujocoinclude",)
"""Root elements of files meant only to be included."""

MJCF_ROOTS = ("mujoco", *FRAGMENT_ROOTS)
XML_ROOTS = xml_roots()
"""Root elements of robot descriptions."""

SRDF_SUFFIXES = (".srdf", ".srdf.xacro")
"""Names that say SRDF, in any case: they decide only a ``<robot>`` whose content holds
neither a robot's elements nor an SRDF's (`srdf.kind`)."""

SRDF_CODE = "srdf-not-robot"
"""The code of the refusal of an SRDF read as a robot (a search's caller notes it)."""


def named_srdf(path: str) -> bool:
    """Whether ``path``'s name says SRDF (`SRDF_SUFFIXES`, in any case)."""
    return path.rpartition("/")[2].lower().endswith(SRDF_SUFFIXES)


SRDF_ELEMENTS = frozenset(
    {
        "group",
        "group_state",
        "virtual_joint",
        "passive_joint",
        "end_effector",
        "disable_collisions",
        "enable_collisions",
        "disable_default_collisions",
        "link_sphere_approximation",
        "joint_property",
        "rotor_params",  # Pinocchio's own, in example-robot-data's SRDF files
        "specificities",
        "gripper",  # HPP's (hpp-manipulation), in example-robot-data's: a link and joint in it
        "handle",
        "contact",
    }
)
"""The elements of an SRDF (srdfdom's, Pinocchio's and HPP's), none of which a URDF has."""

URDF_ELEMENTS = frozenset({"link", "joint"})
"""A URDF's own elements: one outside the SRDF elements makes a file no SRDF."""

XACRO_QUIET = frozenset({"macro", "property", "arg", "if", "unless"})
"""xacro elements that make nothing of their own (their content is looked into)."""

_STEM_SUFFIXES = (".srdf.xacro", ".urdf.xacro", ".srdf", ".xacro", ".urdf", ".xml")
"""What `file_stem` takes off a name (the longest first), in any case."""


def file_stem(path: str) -> str:
    """A robot's or SRDF's file name without its folder and kind.

    ``panda.urdf.xacro``, ``panda.srdf`` and ``robot.xml`` give ``panda``, ``panda`` and
    ``robot``.
    """
    name = path.rpartition("/")[2]
    lower = name.lower()
    for suffix in _STEM_SUFFIXES:
        if lower.endswith(suffix) and len(name) > len(suffix):
            return name[: -len(suffix)]
    return name
