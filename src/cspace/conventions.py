"""How other tools store a configuration, and the maps between them and cspace's.

`Conventions` (what ``ConfigurationSpace.conventions()`` returns) maps a configuration,
a velocity or a path between cspace's canonical vector and Pinocchio's q and v or
MuJoCo's qpos and qvel;
`MujocoLayout` is where a MuJoCo model keeps each joint in qpos and qvel.
``Conventions`` needs NumPy and is imported on first use.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cspace._slots import MujocoJoint, MujocoLayout

if TYPE_CHECKING:
    from cspace.space._conventions import Conventions

__all__ = ["Conventions", "MujocoJoint", "MujocoLayout"]


def __getattr__(name: str) -> Any:
    if name == "Conventions":
        from cspace.space._conventions import Conventions

        return Conventions
    raise AttributeError(f"module 'cspace.conventions' has no attribute {name!r}")
