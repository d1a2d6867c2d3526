"""A tool's vectors as a layout of the canonical ones: `DrakeLayout` and its making.

Drake's, Isaac's and PyBullet's vectors are each a `DrakeLayout`: names, the canonical
column each entry comes from, the followers, floating bodies and ball joints that need
more than a copy. `LayoutParts` makes one a joint at a time in the tool's order.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from cspace.space._conventions._joint_blocks import Follower, JointBlock

if TYPE_CHECKING:
    from cspace._findings import Diagnostic


@dataclass(frozen=True)
class DrakeLayout:
    """Where each Drake position and velocity comes from, in Drake's order.

    Attributes:
        position_names: Drake's name of each position (``GetPositionNames``).
        velocity_names: Its name of each velocity.
        columns: The canonical column of each position (-1: a mimic follower).
        tangent: The canonical tangent column of each velocity (-1: a follower).
        followers: (position, velocity, leader column, leader tangent column, multiplier,
            offset) of each mimic or locked joint (leader columns -1 when locked).
        floating: (first velocity, first canonical quaternion column, first canonical
            angular tangent column) of each floating body.
        balls: (first position, first velocity, first canonical quaternion column, first
            canonical tangent column) of each ball joint (Drake's roll, pitch, yaw).
        welded: The root links these vectors take welded to the world, which Drake's
            URDF and SDF parsers would float (``plant.WeldFrames`` before
            ``Finalize``, or give cspace a root joint).
        vectors: What errors call the positions and the velocities (another tool's
            layout of the same shape, Isaac's, says its own).
        findings: Where Drake's model of the file is not the file's own tool's: the
            ``drake-mjcf-differs`` findings of an MJCF file (bodies Drake's MJCF parser
            places otherwise than MuJoCo, or leaves out) and the ``drake-urdf-differs``
            ones of a URDF file (links Drake's URDF parser moves otherwise than
            Pinocchio), which a conversion to or from Drake's vectors says. These
            vectors still have Drake's names and order.
        origins: (first position, first velocity, the joint's frame in the world as
            x, y, z, qw, qx, qy, qz) of each floating body whose joint's frame is not
            the world's: Drake's q is the body's pose in the world, the canonical one
            its pose in that frame.
    """

    position_names: tuple[str, ...]
    velocity_names: tuple[str, ...]
    columns: tuple[int, ...]
    tangent: tuple[int, ...]
    followers: tuple[tuple[int, int, int, int, float, float], ...]
    floating: tuple[tuple[int, int, int], ...]
    balls: tuple[tuple[int, int, int, int], ...] = ()
    welded: tuple[str, ...] = ()
    vectors: tuple[str, str] = ("Drake's q", "Drake's v")
    findings: tuple[Diagnostic, ...] = ()
    origins: tuple[tuple[int, int, tuple[float, ...]], ...] = ()


def tie(
    follower: Follower, blocks: Mapping[str, JointBlock], q_at: int, v_at: int
) -> tuple[int, int, int, int, float, float]:
    """A follower's entry of `DrakeLayout.followers`, at position ``q_at`` and velocity ``v_at``."""
    leader = blocks.get(follower.leader) if follower.leader is not None else None
    return (
        q_at,
        v_at,
        leader.columns.start if leader is not None else -1,
        leader.tangent.start if leader is not None else -1,
        follower.multiplier,
        follower.offset,
    )


def xyzw_pose_columns(c: int, t: int) -> tuple[list[int], list[int]]:
    """A floating body's canonical columns as x, y, z, qx, qy, qz, qw, and its tangent's.

    ``c`` and ``t`` are its first canonical and tangent columns (canonical x y z qw qx
    qy qz; linear velocity, then angular). Isaac's and PyBullet's root pose is stored so.
    """
    return [c, c + 1, c + 2, c + 4, c + 5, c + 6, c + 3], [t, t + 1, t + 2, t + 3, t + 4, t + 5]


class LayoutParts:
    """A `DrakeLayout` made a joint at a time, in its tool's order.

    Attributes:
        q_names: The positions' names so far.
        v_names: The velocities' names so far.
        columns: Each position's canonical column (-1: a follower's).
        tangent: Each velocity's canonical tangent column (-1: a follower's).
        tied: The followers' entries (`tie`).
        floating: The floating bodies' entries (`DrakeLayout.floating`).
    """

    def __init__(self) -> None:
        self.q_names: list[str] = []
        self.v_names: list[str] = []
        self.columns: list[int] = []
        self.tangent: list[int] = []
        self.tied: list[tuple[int, int, int, int, float, float]] = []
        self.floating: list[tuple[int, int, int]] = []

    def follow(
        self,
        follower: Follower,
        blocks: Mapping[str, JointBlock],
        q: Sequence[str],
        v: Sequence[str],
    ) -> None:
        """A mimic or locked joint's entry, named ``q`` and ``v``, which follows its leader."""
        self.tied.append(tie(follower, blocks, len(self.q_names), len(self.v_names)))
        self.q_names += q
        self.v_names += v
        self.columns.append(-1)
        self.tangent.append(-1)

    def add(
        self, q: Sequence[str], v: Sequence[str], columns: Sequence[int], tangent: Sequence[int]
    ) -> None:
        """A joint's entries: their names and canonical columns."""
        self.q_names += q
        self.v_names += v
        self.columns += columns
        self.tangent += tangent

    def layout(self, **more: Any) -> DrakeLayout:
        """The layout made, with ``more`` of `DrakeLayout`'s fields."""
        return DrakeLayout(
            tuple(self.q_names),
            tuple(self.v_names),
            tuple(self.columns),
            tuple(self.tangent),
            tuple(self.tied),
            tuple(self.floating),
            **more,
        )
