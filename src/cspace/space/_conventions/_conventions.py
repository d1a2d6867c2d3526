"""One robot's configurations and velocities in every convention, and trajectories.

`ConfigurationSpace.conventions <cspace.space.ConfigurationSpace.conventions>`
returns a `Conventions`: maps between

- canonical coordinates (cspace's own: angles in [-pi, pi), quaternions (w, x, y, z)
  with w >= 0) and their tangent vectors;
- Pinocchio's q and v (quaternions (x, y, z, w), a continuous joint as (cos, sin), the
  linear velocity of a floating or planar joint in the body frame);
- MuJoCo's qpos and qvel (for the robot's MJCF, or a MuJoCo model with the same joint
  names);
- Drake's q and v (its parser's joint order, a floating body's velocities in the world
  frame);
- Isaac's joint_pos and joint_vel (PhysX's breadth-first order, after a floating
  root's pose and velocity);
- PyBullet's positions and velocities (``p.loadURDF``'s joint indices, after a free
  base's pose and velocity);
- MuJoCo's ctrl: the targets of its position actuators (``mujoco-ctrl``);
- values named by joint in a given order (a ROS ``JointState``),

each tool's maps in a module of its own (named by the registry, `TOOLS`), and
batched over any leading shape, and the continuous lift of trajectories in any of them.
Each map and its inverse round-trip exactly on canonical input (a quaternion's sign is
resolved to w >= 0, angles to [-pi, pi)); wrong or missing names are a
`JointMatchError` naming them.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal, cast, get_args

from numpy.typing import ArrayLike

from cspace._slots import MujocoLayout
from cspace._tools import TOOLS
from cspace.errors import ArgumentError, JointMatchError
from cspace.space._conventions import _named as named
from cspace.space._conventions._joint_blocks import Follower, JointBlock, joint_blocks
from cspace.space._conventions._maps import Maps, Robot
from cspace.space._conventions._mujoco_layout import mujoco_layout
from cspace.space._data import neutral
from cspace.space._geometry import trajectory
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._conventions import _drake, _mujoco_ctrl, _pybullet
    from cspace.space._conventions._layout import DrakeLayout
    from cspace.space._conventions._pybullet import PybulletOrder
    from cspace.space._data import SpaceData

Convention = Literal[
    "canonical", "pinocchio", "mujoco", "drake", "isaac", "pybullet", "mujoco-ctrl"
]
"""The conventions of whole vectors (the registry's, `cspace.conventions.TOOLS`)."""
CONVENTIONS: tuple[Convention, ...] = get_args(Convention)

Named = Literal[
    "canonical", "pinocchio", "mujoco", "drake", "isaac", "pybullet", "mujoco-ctrl", "named"
]
"""A convention, or ``named``: values by joint in a given order."""
NAMED: tuple[Named, ...] = get_args(Named)


def _check(convention: object, allowed: tuple[str, ...]) -> None:
    """Refuse a convention that is not one of ``allowed`` (``"MuJoCo"`` is not ``"mujoco"``).

    Raises:
        ArgumentError: It is not.
    """
    if convention not in allowed:
        raise ArgumentError(
            f"convention must be one of {', '.join(allowed)}, not {convention!r}",
            argument="convention",
        )


@dataclass(frozen=True)
class Conventions:
    """Maps between one robot's conventions (see the module docstring).

    Attributes:
        space: The robot's configuration space (a `ConfigurationSpace`).
        mujoco: Its MuJoCo layout, or None when none is known.
    """

    space: Any
    mujoco: MujocoLayout | None
    blocks: Mapping[str, JointBlock] = field(repr=False, compare=False)
    followers: Mapping[str, Follower] = field(repr=False, compare=False)
    _robot: Robot = field(repr=False, compare=False, kw_only=True)
    _maps: dict[str, Any] = field(default_factory=dict, init=False, repr=False, compare=False)

    @classmethod
    def of(cls, space: Any, mujoco: object = None) -> Conventions:
        """The conventions of ``space``; ``mujoco`` as for ``space.conventions``.

        A MuJoCo layout given here is matched with the robot at once (its errors are
        raised here); the robot's own MJCF layout only when a MuJoCo map is first used
        (a root joint cspace added to an MJCF robot has no place in its qpos).
        """
        return cast("Conventions", space.conventions(mujoco))

    def maps(self, convention: Convention) -> Maps:
        """The maps of one convention (its module's ``Maps``), built on first use.

        The registry (`cspace.conventions.TOOLS`) names each tool's module; it is
        imported here, so a tool's code is loaded only when the tool is used.

        Raises:
            ArgumentError: Not a convention.
            JointMatchError: The tool cannot store this robot (no MuJoCo layout, a
                joint Drake stores in coordinates cspace does not map).
        """
        _check(convention, CONVENTIONS)
        found = self._maps.get(convention)
        if found is None:
            name = TOOLS[convention].module
            module = importlib.import_module(f"cspace.space._conventions.{name}")
            found = self._maps[convention] = module.Maps(self._robot)
        return cast("Maps", found)

    @property
    def drake(self) -> DrakeLayout:
        """Drake's layout of this robot: its joint order and names (built on first use).

        Raises:
            JointMatchError: A joint Drake stores in coordinates cspace does not map.
        """
        return cast("_drake.Maps", self.maps("drake")).layout

    @property
    def pybullet(self) -> PybulletOrder:
        """The robot as ``p.loadURDF`` numbers it (built on first use).

        Its base, every joint's index (fixed ones too) with its ``qIndex`` and
        ``uIndex``, and where PyBullet's C-space is not the file's (``findings``).

        Raises:
            JointMatchError: A joint PyBullet stores in coordinates cspace does not map.
        """
        return cast("_pybullet.Maps", self.maps("pybullet")).order

    # --- positions -------------------------------------------------------------------

    def to_pinocchio(self, x: ArrayLike) -> FloatArray:
        """Pinocchio's q (..., nq) of canonical configurations (..., n)."""
        return self.maps("pinocchio").to_tool(x)

    def from_pinocchio(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of Pinocchio's q (..., nq)."""
        return self.maps("pinocchio").from_tool(q)

    def to_mujoco(self, x: ArrayLike) -> FloatArray:
        """MuJoCo's qpos (..., nq) of canonical configurations (..., n)."""
        return self.maps("mujoco").to_tool(x)

    def from_mujoco(self, qpos: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of MuJoCo qpos (..., nq)."""
        return self.maps("mujoco").from_tool(qpos)

    def to_drake(self, x: ArrayLike) -> FloatArray:
        """Drake's q (..., nq) of canonical configurations (..., n), in its parser's order."""
        return self.maps("drake").to_tool(x)

    def from_drake(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of Drake's q (..., nq)."""
        return self.maps("drake").from_tool(q)

    def to_isaac(self, x: ArrayLike) -> FloatArray:
        """Isaac's vectors (..., nq) of canonical configurations (..., n).

        A floating root's pose (x, y, z, qx, qy, qz, qw), then joint_pos in PhysX's order.
        """
        return self.maps("isaac").to_tool(x)

    def from_isaac(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of Isaac's vectors (..., nq)."""
        return self.maps("isaac").from_tool(q)

    def to_pybullet(self, x: ArrayLike) -> FloatArray:
        """PyBullet's vectors (..., nq) of canonical configurations (..., n).

        A free base's pose (x, y, z, qx, qy, qz, qw), then each moving joint's positions
        by joint index (`pybullet`).
        """
        return self.maps("pybullet").to_tool(x)

    def from_pybullet(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of PyBullet's vectors (..., nq)."""
        return self.maps("pybullet").from_tool(q)

    def to_mujoco_ctrl(self, x: ArrayLike) -> FloatArray:
        """MuJoCo's ctrl (..., nu) of canonical configurations (..., n).

        Each position actuator's target, ``gear * qpos`` of its joint; 0 for every other
        actuator.
        """
        return self.maps("mujoco-ctrl").to_tool(x)

    def from_mujoco_ctrl(self, ctrl: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of MuJoCo ctrl (..., nu).

        Each position actuator's joint at ctrl / gear; every other joint neutral.
        """
        return self.maps("mujoco-ctrl").from_tool(ctrl)

    def to_named(self, x: ArrayLike, names: Sequence[str]) -> FloatArray:
        """Values (..., len(names)) of configurations (..., n), in the order of ``names``."""
        return named.to_named(self._robot.data, self.blocks, self.followers, x, names, False)

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
            self._robot.data, self.blocks, self.followers, values, names, default, False
        )

    def check_names(self, names: Sequence[str]) -> None:
        """Refuse names that a named vector cannot hold, before any value is read.

        Raises:
            JointMatchError: A name is repeated, unknown, a fixed joint's, or a joint
                with several coordinates.
        """
        named.check_names(self._robot.data, self.blocks, self.followers, names)

    # --- velocities ------------------------------------------------------------------

    def to_pinocchio_velocity(self, x: ArrayLike, dx: ArrayLike) -> FloatArray:
        """Pinocchio's v (..., nv) of tangent vectors dx (..., dimension) at x (..., n)."""
        return self.maps("pinocchio").to_velocity(x, dx)

    def from_pinocchio_velocity(self, x: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of Pinocchio's v (..., nv) at x (..., n)."""
        return self.maps("pinocchio").from_velocity(x, v)

    def to_mujoco_velocity(self, dx: ArrayLike) -> FloatArray:
        """MuJoCo's qvel (..., nv) of tangent vectors (..., dimension)."""
        return self.maps("mujoco").to_velocity(neutral(self._robot.data), dx)

    def from_mujoco_velocity(self, qvel: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of MuJoCo qvel (..., nv)."""
        return self.maps("mujoco").from_velocity(neutral(self._robot.data), qvel)

    def to_drake_velocity(self, x: ArrayLike, dx: ArrayLike) -> FloatArray:
        """Drake's v (..., nv) of tangent vectors dx (..., dimension) at x (..., n).

        A floating body's angular velocity is in the world frame in Drake, in the body
        frame in cspace's tangent: the map needs the configuration.
        """
        return self.maps("drake").to_velocity(x, dx)

    def from_drake_velocity(self, x: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of Drake's v (..., nv) at x (..., n)."""
        return self.maps("drake").from_velocity(x, v)

    def to_isaac_velocity(self, x: ArrayLike, dx: ArrayLike) -> FloatArray:
        """Isaac's velocities (..., nv) of tangent vectors dx (..., dimension) at x (..., n).

        A floating root's linear and angular velocity in the world frame, then joint_vel.
        """
        return self.maps("isaac").to_velocity(x, dx)

    def from_isaac_velocity(self, x: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of Isaac's velocities (..., nv) at x (..., n)."""
        return self.maps("isaac").from_velocity(x, v)

    def to_pybullet_velocity(self, x: ArrayLike, dx: ArrayLike) -> FloatArray:
        """PyBullet's velocities (..., nv) of tangent vectors dx (..., dimension) at x (..., n).

        A free base's linear and angular velocity in the world frame, then the joints'.
        """
        return self.maps("pybullet").to_velocity(x, dx)

    def from_pybullet_velocity(self, x: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of PyBullet's velocities (..., nv) at x (..., n)."""
        return self.maps("pybullet").from_velocity(x, v)

    def to_mujoco_ctrl_velocity(self, dx: ArrayLike) -> FloatArray:
        """The rates of MuJoCo's ctrl (..., nu) of tangent vectors (..., dimension)."""
        return self.maps("mujoco-ctrl").to_velocity(neutral(self._robot.data), dx)

    def from_mujoco_ctrl_velocity(self, rates: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of the rates of MuJoCo's ctrl (..., nu)."""
        return self.maps("mujoco-ctrl").from_velocity(neutral(self._robot.data), rates)

    def to_named_velocity(self, dx: ArrayLike, names: Sequence[str]) -> FloatArray:
        """Velocities (..., len(names)) of tangent vectors (..., dimension), by name."""
        return named.to_named(self._robot.data, self.blocks, self.followers, dx, names, True)

    def from_named_velocity(
        self, values: ArrayLike, names: Sequence[str], default: ArrayLike | None = None
    ) -> FloatArray:
        """Tangent vectors (..., dimension) of velocities (..., len(names)) by name."""
        return named.from_named(
            self._robot.data, self.blocks, self.followers, values, names, default, True
        )

    # --- trajectories ----------------------------------------------------------------

    def to_canonical(self, x: ArrayLike, convention: Convention) -> FloatArray:
        """Canonical configurations of configurations stored in ``convention``."""
        return self.maps(convention).from_tool(x)

    def from_canonical(self, x: ArrayLike, convention: Convention) -> FloatArray:
        """Configurations stored in ``convention`` of canonical configurations."""
        return self.maps(convention).to_tool(x)

    def unwrap(
        self,
        trajectory_: ArrayLike,
        convention: Convention = "canonical",
        start: ArrayLike | None = None,
    ) -> FloatArray:
        """The continuous lift (..., T, n) of a trajectory (..., T, width) in ``convention``.

        The lift is in canonical coordinates (angles unwrapped, quaternions (w, x, y, z)
        with signs kept consistent from sample to sample), whatever the input convention:
        Pinocchio's (cos, sin) cannot hold an unwrapped angle. ``start``: the lifted
        sample before the first, to continue a lift chunk by chunk. See
        `_trajectory`.
        """
        canonical = self.to_canonical(trajectory_, convention)
        return trajectory.unwrap(self._robot.data, canonical, start)

    def wrap(self, lift: ArrayLike, convention: Convention = "canonical") -> FloatArray:
        """A lifted trajectory (..., T, n) back in ``convention``: `unwrap`'s inverse.

        MuJoCo's ctrl (``mujoco-ctrl``) keeps the lift's angles: a position actuator's
        target of a continuous hinge is its lifted angle times the gear, since MuJoCo
        does not wrap the joint's qpos and would turn it the other way to a wrapped one.
        """
        canonical = trajectory.wrap(self._robot.data, lift)
        if convention == "mujoco-ctrl":
            return cast("_mujoco_ctrl.Maps", self.maps(convention)).lifted(lift, canonical)
        return self.from_canonical(canonical, convention)

    # --- names and whole conversions -----------------------------------------------

    def names(self, convention: Convention, velocity: bool = False) -> tuple[str, ...]:
        """A name for each entry of a vector in ``convention`` (``base.qx``, ``elbow``).

        Args:
            convention: ``canonical``, ``pinocchio``, ``mujoco``, ``drake``, ``isaac`` or
                ``pybullet``.
            velocity: Name the velocity vector (tangent, v, qvel, Drake's v, joint_vel)
                instead.

        Raises:
            JointMatchError: ``mujoco`` without a MuJoCo layout.
            ArgumentError: Not one of these conventions.
        """
        return self.maps(convention).names(velocity)

    def convert(
        self,
        values: ArrayLike,
        source: Named,
        target: Named,
        *,
        velocity: bool = False,
        at: ArrayLike | None = None,
        source_names: Sequence[str] = (),
        target_names: Sequence[str] = (),
        default: ArrayLike | None = None,
    ) -> FloatArray:
        """Vectors (..., width) from one convention to another, through canonical ones.

        Args:
            values: Configurations (or velocities) stored in ``source``.
            source: ``canonical``, ``pinocchio``, ``mujoco``, ``drake`` or ``named``.
            target: The same choices.
            velocity: The vectors are velocities.
            at: Canonical configurations (..., n), for velocities to or from Pinocchio or
                Drake.
            source_names: For ``named`` input, the joint of each value.
            target_names: For ``named`` output, the joints in order.
            default: For ``named`` input, the configuration (or, for velocities, the
                tangent vector) joints not named take their values from.

        Raises:
            JointMatchError: Names missing or unknown, no MuJoCo layout, or no ``at``
                for Pinocchio velocities.
            ArgumentError: ``source`` or ``target`` is not a convention.
        """
        _check(source, NAMED)
        _check(target, NAMED)
        if not velocity:
            if source == "named":
                x = self.from_named(values, source_names, default)
            else:
                x = self.to_canonical(values, source)
            if target == "named":
                return self.to_named(x, target_names)
            return self.from_canonical(x, target)
        from cspace._tools import TOOLS

        for side in (source, target):
            if side != "named" and TOOLS[side].velocity_needs_at and at is None:
                raise JointMatchError(
                    f"{TOOLS[side].label(True)} needs the configurations it is taken at "
                    "(at=...): a floating or planar joint's velocity is in another frame"
                )
        where = neutral(self._robot.data) if at is None else at
        if source == "named":
            tangent = self.from_named_velocity(values, source_names, default)
        else:
            tangent = self.maps(source).from_velocity(where, values)
        if target == "named":
            return self.to_named_velocity(tangent, target_names)
        return self.maps(target).to_velocity(where, tangent)


def conventions_of(space: object, data: SpaceData, mujoco: object = None) -> Conventions:
    """`ConfigurationSpace.conventions`: the conventions of a space, from its data.

    Args:
        space: The `ConfigurationSpace`, which the result names (`Conventions.space`)
            and never calls.
        data: Its data, which every map works on.
        mujoco: As for `ConfigurationSpace.conventions`.

    Raises:
        JointMatchError: The MuJoCo model's joints do not match the robot's.
    """
    layout = data.mujoco if mujoco is None else mujoco_layout(mujoco)
    blocks, followers = joint_blocks(data)
    robot = Robot(data, layout, MappingProxyType(blocks), MappingProxyType(followers))
    conventions = Conventions(space, layout, robot.blocks, robot.followers, _robot=robot)
    if mujoco is not None:
        conventions.maps("mujoco")
    return conventions
