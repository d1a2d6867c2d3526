"""How other tools store a configuration, and the maps between them and cspace's.

`TOOLS` is the registry: each tool a configuration crosses (cspace's canonical
coordinates, Pinocchio, MuJoCo, Drake, Isaac, PyBullet), what it calls its vectors, how it orders
joints and stores each factor. `Conventions` (what ``ConfigurationSpace.conventions()``
returns) maps a configuration, a velocity or a path between cspace's canonical vector
and each tool's (Pinocchio's q and v, MuJoCo's qpos and qvel, Drake's q and v, Isaac's
joint_pos and joint_vel, PyBullet's q and u), and values named by joint (``named``, as
a ROS JointState);
`MujocoLayout` is where a MuJoCo model keeps each joint in qpos and qvel.
``Conventions`` needs NumPy and is imported on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cspace._slots import MujocoJoint, MujocoLayout
from cspace._tools import TOOLS, Tool

if TYPE_CHECKING:
    from cspace.space._conventions._conventions import Conventions

__all__ = ["TOOLS", "Conventions", "MujocoJoint", "MujocoLayout", "Tool"]


def __getattr__(name: str) -> Any:
    if name == "Conventions":
        from cspace.space._conventions._conventions import Conventions

        return Conventions
    raise AttributeError(f"module 'cspace.conventions' has no attribute {name!r}")
