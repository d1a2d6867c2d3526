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
