"""One robot's configurations and velocities in every convention, and trajectories.

:meth:`ConfigurationSpace.conventions <cspace.space.ConfigurationSpace.conventions>`
returns a :class:`Conventions`: maps between

- canonical coordinates (cspace's own: angles in [-pi, pi), quaternions (w, x, y, z)
  with w >= 0) and their tangent vectors;
- Pinocchio's q and v (quaternions (x, y, z, w), a continuous joint as (cos, sin), the
  linear velocity of a floating or planar joint in the body frame);
- MuJoCo's qpos and qvel (for the robot's MJCF, or a MuJoCo model with the same joint
  names);
- values named by joint in a given order (a ROS ``JointState``),

batched over any leading shape, and the continuous lift of trajectories in any of them.
Each map and its inverse round-trip exactly on canonical input (a quaternion's sign is
resolved to w >= 0, angles to [-pi, pi)); wrong or missing names are a
:class:`~cspace.errors.JointMatchError` naming them.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Literal

from numpy.typing import ArrayLike

from cspace.conventions import MujocoLayout
from cspace.errors import JointMatchError
from cspace.space import mujoco_map, named, trajectory, velocity
from cspace.space.joint_blocks import Follower, JointBlock, joint_blocks
from cspace.space.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space.configuration_space import ConfigurationSpace

Convention = Literal["canonical", "pinocchio", "mujoco"]
CONVENTIONS: tuple[Convention, ...] = ("canonical", "pinocchio", "mujoco")


def mujoco_layout(mujoco: object) -> MujocoLayout:
    """A MuJoCo layout from an MJCF path, an MJCF report, a ``mujoco.MjModel`` or a layout.

    Raises:
        JointMatchError: ``mujoco`` is none of these (or a report of another format).
        RobotFileError: The MJCF file cannot be read.
    """
    from cspace.reports.report import Report

    if isinstance(mujoco, MujocoLayout):
        return mujoco
    if isinstance(mujoco, Report):
        return MujocoLayout.from_report(mujoco)
    if isinstance(mujoco, str | os.PathLike):
        from cspace.model.loader import inspect

        return MujocoLayout.from_report(inspect(mujoco))
    if hasattr(mujoco, "njnt") and hasattr(mujoco, "jnt_qposadr"):
        return MujocoLayout.from_model(mujoco)
    raise JointMatchError(
        f"mujoco must be an MJCF file, its report, a mujoco.MjModel or a MujocoLayout, "
        f"not {type(mujoco).__name__}"
    )


@dataclass(frozen=True)
class Conventions:
    """Maps between one robot's conventions (see the module docstring).

    Attributes:
        space: The robot's configuration space.
        mujoco: Its MuJoCo layout, or None when none is known.
    """

    space: ConfigurationSpace
    mujoco: MujocoLayout | None
    blocks: Mapping[str, JointBlock] = field(repr=False, compare=False)
    followers: Mapping[str, Follower] = field(repr=False, compare=False)
    _mujoco_map: mujoco_map.MujocoMap | None = field(repr=False, compare=False)

    @classmethod
    def of(cls, space: ConfigurationSpace, mujoco: object = None) -> Conventions:
        """The conventions of ``space``; ``mujoco`` as for ``space.conventions``."""
        layout = space.mujoco if mujoco is None else mujoco_layout(mujoco)
        blocks, followers = joint_blocks(space)
        plan = None if layout is None else mujoco_map.build_map(layout, blocks, followers)
        return cls(space, layout, MappingProxyType(blocks), MappingProxyType(followers), plan)

    def _plan(self) -> mujoco_map.MujocoMap:
        if self._mujoco_map is None:
            raise JointMatchError(
                f"robot '{self.space.robot}' was not read from MJCF: give MuJoCo's layout "
                "(conventions(mujoco=PATH_OR_MODEL))"
            )
        return self._mujoco_map

    # --- positions -------------------------------------------------------------------

    def to_pinocchio(self, x: ArrayLike) -> FloatArray:
        """Pinocchio's q (..., nq) of canonical configurations (..., n)."""
        return self.space.to_pinocchio(x)

    def from_pinocchio(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of Pinocchio's q (..., nq)."""
        return self.space.from_pinocchio(q)

    def to_mujoco(self, x: ArrayLike) -> FloatArray:
        """MuJoCo's qpos (..., nq) of canonical configurations (..., n)."""
        return mujoco_map.to_qpos(self.space, self._plan(), x)

    def from_mujoco(self, qpos: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of MuJoCo qpos (..., nq)."""
        return mujoco_map.from_qpos(self.space, self._plan(), qpos)

    def to_named(self, x: ArrayLike, names: Sequence[str]) -> FloatArray:
        """Values (..., len(names)) of configurations (..., n), in the order of ``names``."""
        return named.to_named(self.space, self.blocks, self.followers, x, names, False)

    def from_named(
        self, values: ArrayLike, names: Sequence[str], default: ArrayLike | None = None
    ) -> FloatArray:
        """Canonical configurations (..., n) of values (..., len(names)) named by joint.

        Args:
            values: One value per name (a continuous joint's may be any angle).
            names: The joint of each value (a ROS JointState's ``name``).
            default: One configuration the joints not named take their values from;
                None: every joint with coordinates must be named.
        """
        return named.from_named(
            self.space, self.blocks, self.followers, values, names, default, False
        )

    # --- velocities ------------------------------------------------------------------

    def to_pinocchio_velocity(self, x: ArrayLike, dx: ArrayLike) -> FloatArray:
        """Pinocchio's v (..., nv) of tangent vectors dx (..., dimension) at x (..., n)."""
        return velocity.to_v(self.space, self.blocks, self.followers, x, dx)

    def from_pinocchio_velocity(self, x: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of Pinocchio's v (..., nv) at x (..., n)."""
        return velocity.from_v(self.space, self.blocks, x, v)

    def to_mujoco_velocity(self, dx: ArrayLike) -> FloatArray:
        """MuJoCo's qvel (..., nv) of tangent vectors (..., dimension)."""
        return mujoco_map.to_qvel(self.space, self._plan(), dx)

    def from_mujoco_velocity(self, qvel: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of MuJoCo qvel (..., nv)."""
        return mujoco_map.from_qvel(self.space, self._plan(), qvel)

    def to_named_velocity(self, dx: ArrayLike, names: Sequence[str]) -> FloatArray:
        """Velocities (..., len(names)) of tangent vectors (..., dimension), by name."""
        return named.to_named(self.space, self.blocks, self.followers, dx, names, True)

    def from_named_velocity(
        self, values: ArrayLike, names: Sequence[str], default: ArrayLike | None = None
    ) -> FloatArray:
        """Tangent vectors (..., dimension) of velocities (..., len(names)) by name."""
        return named.from_named(
            self.space, self.blocks, self.followers, values, names, default, True
        )

    # --- trajectories ----------------------------------------------------------------

    def to_canonical(self, x: ArrayLike, convention: Convention) -> FloatArray:
        """Canonical configurations of configurations stored in ``convention``."""
        if convention == "pinocchio":
            return self.from_pinocchio(x)
        if convention == "mujoco":
            return self.from_mujoco(x)
        return self.space.canonicalize(x)

    def from_canonical(self, x: ArrayLike, convention: Convention) -> FloatArray:
        """Configurations stored in ``convention`` of canonical configurations."""
        if convention == "pinocchio":
            return self.to_pinocchio(x)
        if convention == "mujoco":
            return self.to_mujoco(x)
        return self.space.canonicalize(x)

    def unwrap(self, trajectory_: ArrayLike, convention: Convention = "canonical") -> FloatArray:
        """The continuous lift (..., T, n) of a trajectory (..., T, width) in ``convention``.

        The lift is in canonical coordinates (angles unwrapped, quaternions (w, x, y, z)
        with signs kept consistent from sample to sample), whatever the input convention:
        Pinocchio's (cos, sin) cannot hold an unwrapped angle. See
        :mod:`cspace.space.trajectory`.
        """
        return trajectory.unwrap(self.space, self.to_canonical(trajectory_, convention))

    def wrap(self, lift: ArrayLike, convention: Convention = "canonical") -> FloatArray:
        """A lifted trajectory (..., T, n) back in ``convention``: :meth:`unwrap`'s inverse."""
        return self.from_canonical(trajectory.wrap(self.space, lift), convention)
