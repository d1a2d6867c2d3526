"""The one reader contract: what every format reader gives the model layer.

A reader turns a file's bytes into a `Reading`: the format-free description
(joints in cspace's words, limits as written, lines, the reader's own findings) and a
recipe saying how Pinocchio should build the model. The recipe is one of three, by what
the format needs:

- `UrdfText`: a URDF document for Pinocchio's own URDF parser (URDF and
  expanded xacro);
- `JointList`: moving joints to assemble through Pinocchio's model API (SDF,
  whose parser this Pinocchio lacks);
- `KinematicTree`: bodies and joints with their
  frames, from MuJoCo's compiled model (MJCF).

`build` takes any reading; nothing else in the model layer
asks which format a robot came from.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import NamedTuple

from cspace._formats.description import JointToAdd, PoseSpec, RobotDescription
from cspace._formats.kinematic_tree import KinematicTree


class UrdfText(NamedTuple):
    """A URDF document for Pinocchio's URDF parser.

    Attributes:
        text: The document: the file as read, with what Pinocchio's parser would refuse
            but the report can still describe rewritten.
    """

    text: str


class JointList(NamedTuple):
    """Moving joints to assemble through Pinocchio's model API, each after its parent.

    Attributes:
        joints: The joints (placements are identities: a model for the configuration
            space, not for kinematics).
    """

    joints: tuple[JointToAdd, ...]


Recipe = UrdfText | JointList | KinematicTree
"""How Pinocchio builds a reading's model."""


class Reading(NamedTuple):
    """What a format reader found.

    Attributes:
        description: The checked description, joints in the order Pinocchio's model
            will have them.
        recipe: How to build the Pinocchio model.
        addresses: For MJCF, each moving joint's MuJoCo ``(qposadr, dofadr, type)`` by name;
            None for other formats.
        poses: The poses the file stores (MJCF keyframes that write qpos).
    """

    description: RobotDescription
    recipe: Recipe
    addresses: Mapping[str, tuple[int, int, str]] | None = None
    poses: tuple[PoseSpec, ...] = ()


def joint_list(description: RobotDescription, to_add: Mapping[str, JointToAdd]) -> JointList:
    """The moving joints to assemble, in tree order, each under the moving joint above it.

    Fixed joints are frames, not joints: a joint below one hangs from the moving joint
    above that.

    Args:
        description: The checked description (joints depth-first from the root link).
        to_add: Each moving joint's model, by name (fixed joints have none).
    """
    moving_parent: dict[str, str | None] = {description.root_link: None}
    ordered: list[JointToAdd] = []
    for spec in description.joints:
        above = moving_parent[spec.parent]
        add = to_add.get(spec.name)
        if add is None:
            moving_parent[spec.child] = above
        else:
            ordered.append(add._replace(parent=above))
            moving_parent[spec.child] = spec.name
    return JointList(tuple(ordered))
