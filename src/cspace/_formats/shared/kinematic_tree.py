"""A kinematic tree with frames, independent of the format and of Pinocchio.

A format reader whose parser gives frames (MJCF through MuJoCo's compiler) describes the
robot as bodies, each placed in its parent's frame, and joints, each acting on its body
at an anchor, in order; `build_tree_model` turns it into a
Pinocchio model whose forward kinematics are the file's.

Conventions: lengths in m, angles in rad, quaternions ``(w, x, y, z)``.
"""

from cspace._record import NamedTuple

Vector = tuple[float, float, float]
QuaternionWxyz = tuple[float, float, float, float]


class TreeBody(NamedTuple):
    """One body.

    Attributes:
        name: The body's name.
        parent: Index of the parent body in `KinematicTree.bodies` (-1 for the world).
        position: The body frame's origin in the parent body's frame, before its joints act.
        quaternion_wxyz: The body frame's orientation in the parent body's frame.
    """

    name: str
    parent: int
    position: Vector
    quaternion_wxyz: QuaternionWxyz


class TreeJoint(NamedTuple):
    """One joint acting on a body.

    Attributes:
        name: The joint's name.
        body: Index of the body it moves.
        model: ``"revolute"``, ``"prismatic"``, ``"spherical"`` or ``"floating"`` (a
            floating joint places its body in the world directly, its body's own
            position and orientation being the joint's starting value).
        anchor: The point it acts at, in the body's frame (m).
        axis: Unit axis in the body's frame (revolute, prismatic).
        reference: The joint value at which the body sits at its declared frame (rad or
            m; MuJoCo's ``ref``).
        lower: Lower position limit (rad or m), -inf when none.
        upper: Upper position limit (rad or m), +inf when none.
    """

    name: str
    body: int
    model: str
    anchor: Vector = (0.0, 0.0, 0.0)
    axis: Vector = (0.0, 0.0, 1.0)
    reference: float = 0.0
    lower: float = float("-inf")
    upper: float = float("inf")


class KinematicTree(NamedTuple):
    """A robot's bodies and joints with their frames.

    Attributes:
        name: The robot's name.
        bodies: Every body, the world first (index 0), each after its parent.
        joints: Every moving joint in configuration order; a body's joints are
            consecutive and act in that order.
    """

    name: str
    bodies: tuple[TreeBody, ...]
    joints: tuple[TreeJoint, ...]
