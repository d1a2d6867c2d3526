"""The names that tell an XML robot description, for the loader and for a folder's search.

Kept apart from the search (`_discover`, `_xml_look`), which the loader of one file
does not import. An SRDF is told by the same names (`_srdf_kind`, `_xml_srdf`).
"""

from __future__ import annotations

ROBOT_SUFFIXES = (".urdf", ".xacro", ".sdf")
"""Names that say a robot description whatever the root (xacro may wrap it), in any case."""

FRAGMENT_ROOTS = ("mujocoinclude",)
"""Root elements of files meant only to be included."""

MJCF_ROOTS = ("mujoco", *FRAGMENT_ROOTS)
XML_ROOTS = ("robot", "mujoco", "sdf")
"""Root elements of robot descriptions."""

SRDF_SUFFIXES = (".srdf", ".srdf.xacro")
"""Names that say an SRDF whatever the content, in any case."""


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
    }
)
"""The elements of an SRDF (srdfdom's and Pinocchio's), none of which a URDF has."""

URDF_ELEMENTS = frozenset({"link", "joint"})
"""A URDF's own elements: one outside the SRDF elements makes a file no SRDF."""

XACRO_QUIET = frozenset({"macro", "property", "arg", "if", "unless"})
"""xacro elements that make nothing of their own (their content is looked into)."""

XACRO_NAMESPACE = "http://www.ros.org/wiki/xacro"
"""xacro's namespace (xacro itself goes by the ``xacro:`` prefix of a name)."""

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
