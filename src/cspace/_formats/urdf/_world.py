"""A URDF link named ``world`` that the file names but does not declare: the world.

Drake's URDF parser reads a link named ``world`` as its world body wherever a joint
names it, declared or not (``Acrobot.urdf``, which Drake ships, welds its base to an
undeclared ``world``). urdfdom, which ROS and Pinocchio use, refuses a joint that names
a link the file does not declare. cspace reads such a file as Drake does: the C-space is
the one the file would have with ``<link name="world"/>`` declared, and that declaration
is added to the document Pinocchio's parser is given (`urdf._recipe`). An
``world-undeclared`` info says so, since the file is not one that ROS can load.
"""

from __future__ import annotations

from collections.abc import Sequence

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import JointSpec, LinkSpec

WORLD = "world"
"""The link name Drake's URDF parser reads as its world body."""


def with_world(
    links: Sequence[LinkSpec], joints: Sequence[JointSpec]
) -> tuple[list[LinkSpec], Diagnostic | None]:
    """The links, with an undeclared ``world`` that a joint names added first.

    Nothing is added to a file that declares no link (it describes no robot, as it
    says) or that declares ``world`` itself.

    Returns:
        The links (``world`` first when added, so that it is the root it stands for)
        and the ``world-undeclared`` finding, or None when nothing was added.
    """
    if not links or any(link.name == WORLD for link in links):
        return list(links), None
    naming = [j for j in joints if WORLD in (j.parent, j.child)]
    if not naming:
        return list(links), None
    first = naming[0]
    role = "parent" if first.parent == WORLD else "child"
    others = f" (and {len(naming) - 1:,} more joint(s))" if len(naming) > 1 else ""
    said = finding(
        "world-undeclared",
        first.name,
        f"joint '{first.name}'{others} names {role} link 'world', which the file does not "
        "declare: cspace reads it as the world, as Drake does; urdfdom (ROS, Pinocchio's "
        'own parser) refuses the file: declare <link name="world"/> for them',
        first.line,
    )
    return [LinkSpec(WORLD, None), *links], said
