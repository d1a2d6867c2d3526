"""What one tool's maps are: the protocol each convention module's ``Maps`` class meets.

A convention module (``_pinocchio``, ``_mujoco``, ``_drake``, ``_canonical``) holds the
tool's maps between cspace's canonical vectors and the tool's own, and ends in a class
``Maps`` built from a `Robot` (what `Conventions` holds: the space's data, its joints'
blocks and followers, the MuJoCo layout if any). `Conventions` finds the module through the
registry (``Tool.module``) and imports it on first use, so a tool's code (and any
library it needs) is loaded only when that tool is asked for.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from numpy.typing import ArrayLike

from cspace.space._checks import as_rows, broadcast_rows, broadcast_shapes
from cspace.space._compute.engines import canonicalize
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace._slots import MujocoLayout
    from cspace.space._conventions._joint_blocks import Follower, JointBlock
    from cspace.space._data import SpaceData


@dataclass(frozen=True)
class Robot:
    """What a tool's maps are built from (`Conventions` makes it once).

    Attributes:
        data: The robot's configuration space's data.
        mujoco: MuJoCo's layout of the robot, or None when none is known.
        blocks: Each joint with coordinates: its canonical columns and tangent entries.
        followers: Each mimic or locked joint: what it follows.
    """

    data: SpaceData
    mujoco: MujocoLayout | None
    blocks: Mapping[str, JointBlock]
    followers: Mapping[str, Follower]


class Maps(Protocol):
    """One tool's vectors: their names and the maps to and from canonical ones.

    Shapes: configurations (..., n) canonical and (..., nq) the tool's; tangent vectors
    (..., dimension) and the tool's velocities (..., nv); ``at`` canonical configurations
    (..., n) that broadcast with the velocities (ignored by a tool whose velocities are
    in the canonical tangent's frames).
    """

    def names(self, velocity: bool) -> tuple[str, ...]:
        """A name for each entry of the tool's configuration (or velocity) vector."""

    def to_tool(self, x: ArrayLike) -> FloatArray:
        """The tool's configurations of canonical ones."""

    def from_tool(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations of the tool's."""

    def to_velocity(self, at: ArrayLike, dx: ArrayLike) -> FloatArray:
        """The tool's velocities of tangent vectors ``dx`` at ``at``."""

    def from_velocity(self, at: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors of the tool's velocities ``v`` at ``at``."""


def rows_at(
    data: SpaceData, x: ArrayLike, d: ArrayLike, width: int, what: str
) -> tuple[FloatArray, FloatArray, tuple[int, ...]]:
    """Configurations and vectors as rows of one broadcast leading shape.

    Canonical configurations ``x`` (..., n) and vectors ``d`` (..., width) become
    (M, n) and (M, width) rows, with that leading shape.

    Raises:
        The errors of `canonicalize`; ConfigurationShapeError: ``d`` is not ``width``
        wide (``what`` names it); ConfigurationError: the shapes do not broadcast.
    """
    canonical = canonicalize(data, x, None)
    xs, lead_x = as_rows(canonical, data.size, f"a configuration of robot '{data.robot}'")
    ds, lead_d = as_rows(d, width, what)
    full = broadcast_shapes(lead_x, lead_d)
    return broadcast_rows(xs, lead_x, full), broadcast_rows(ds, lead_d, full), full
