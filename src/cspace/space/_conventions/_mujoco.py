"""Between canonical configurations and MuJoCo's qpos and qvel, joint by joint, by name.

Canonical coordinates and MuJoCo's qpos agree joint by joint (a hinge or slide as its
value, a ball as (w, x, y, z), a free joint as (x, y, z, qw, qx, qy, qz)), and so do the
canonical tangent and qvel (a free joint's linear velocity in the world frame, angular
velocities in the body frame). What differs is the order, which joints each side has,
and the planar joint MuJoCo does not have: its URDF converter writes planar joint ``P``
as slides ``P_TX``, ``P_TY`` and hinge ``P_RZ``, which are read as ``P``'s x, y and
theta. A canonical angle is in [-pi, pi); qpos may hold any angle (it is wrapped on the
way in).
"""

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from cspace._joint_kind import JointKind
from cspace._record import NamedTuple
from cspace._slots import MUJOCO_JOINTS, MUJOCO_SIZES, MujocoJoint, MujocoLayout
from cspace.errors import JointMatchError
from cspace.space._checks import as_rows, check_finite, check_overflow, output
from cspace.space._compute.engines import canonicalize
from cspace.space._conventions._joint_blocks import Follower, JointBlock
from cspace.space._conventions._maps import Robot
from cspace.space._geometry.rotations import FloatArray

if TYPE_CHECKING:
    from cspace.space._data import SpaceData

_PLANAR_PARTS = (("_TX", "slide"), ("_TY", "slide"), ("_RZ", "hinge"))


class Piece(NamedTuple):
    """Canonical columns and tangent columns that are a run of qpos and qvel."""

    columns: slice
    tangent: slice
    qpos: slice
    qvel: slice


class Following(NamedTuple):
    """A MuJoCo joint set from a leader (mimic) or to a constant (locked).

    ``qpos = multiplier * leader + offset``, ``qvel = multiplier * leader velocity``.
    """

    qposadr: int
    dofadr: int
    column: int | None  # the leader's canonical column (None: locked)
    tangent: int | None  # the leader's tangent column
    multiplier: float
    offset: float


class MujocoMap(NamedTuple):
    """How one robot's canonical vectors map to one MuJoCo model's.

    Attributes:
        layout: The MuJoCo model's layout.
        pieces: The runs that are copied.
        followers: MuJoCo joints that follow others (mimic, locked).
    """

    layout: MujocoLayout
    pieces: tuple[Piece, ...]
    followers: tuple[Following, ...]


def _span(start: int, size: int) -> slice:
    return slice(start, start + size)


def _pieces_of(block: JointBlock, by_name: dict[str, MujocoJoint]) -> list[Piece]:
    """The pieces of one robot joint, or JointMatchError."""
    joint = by_name.get(block.name)
    if joint is not None:
        expected = MUJOCO_JOINTS.get(block.kind)
        if joint.type != expected:
            raise JointMatchError(
                f"joint '{block.name}' is {block.kind.value}, but MuJoCo's joint of that name "
                f"is a {joint.type} joint" + ("" if expected else " (no single MuJoCo joint is)"),
                joints=[block.name],
            )
        nq, nv = MUJOCO_SIZES[joint.type]
        return [
            Piece(block.columns, block.tangent, _span(joint.qposadr, nq), _span(joint.dofadr, nv))
        ]
    parts = [by_name.get(block.name + suffix) for suffix, _ in _PLANAR_PARTS]
    if block.kind is JointKind.PLANAR and all(
        p is not None and p.type == kind for p, (_, kind) in zip(parts, _PLANAR_PARTS, strict=True)
    ):
        return [
            Piece(
                _span(block.columns.start + k, 1),
                _span(block.tangent.start + k, 1),
                _span(p.qposadr, 1),
                _span(p.dofadr, 1),
            )
            for k, p in enumerate(parts)
            if p is not None
        ]
    raise JointMatchError(
        f"MuJoCo's model has no joint '{block.name}' ({block.kind.value})", joints=[block.name]
    )


def build_map(
    layout: MujocoLayout, blocks: Mapping[str, JointBlock], followers: Mapping[str, Follower]
) -> MujocoMap:
    """Match a robot's joints with a MuJoCo model's, by name.

    A floating root joint of the robot that MuJoCo's model lacks by name (the one
    ``--root-joint floating`` adds, ``root_joint``) is the model's free joint at qpos 0.

    Raises:
        JointMatchError: A joint with coordinates is missing from the MuJoCo model or of
            another type there, or the MuJoCo model has joints the robot does not.
    """
    by_name = {j.name: j for j in layout.joints}
    root = next(iter(blocks.values()), None)
    top = next((j for j in layout.joints if j.qposadr == 0), None)
    if (
        root is not None
        and top is not None
        and root.name not in by_name
        and root.columns.start == 0
        and MUJOCO_JOINTS.get(root.kind) == top.type == "free"
        and top.name not in blocks
    ):  # the root joint cspace added to a URDF is the MJCF's own free joint
        by_name[root.name] = top
    pieces = [piece for block in blocks.values() for piece in _pieces_of(block, by_name)]
    used = {p.qpos.start for p in pieces}
    follow: list[Following] = []
    for j in layout.joints:
        f = followers.get(j.name)
        if f is None or j.type not in ("hinge", "slide"):
            continue
        leader = blocks.get(f.leader) if f.leader is not None else None
        column = None if leader is None else leader.columns.start
        tangent = None if leader is None else leader.tangent.start
        multiplier, offset = f.multiplier, f.offset
        locked = followers.get(f.leader) if f.leader is not None else None
        if leader is None and locked is not None:  # a mimic of a locked joint
            multiplier, offset = 0.0, f.multiplier * locked.offset + f.offset
        follow.append(Following(j.qposadr, j.dofadr, column, tangent, multiplier, offset))
        used.add(j.qposadr)
    extra = [j.name for j in layout.joints if j.qposadr not in used]
    if extra:
        raise JointMatchError(
            f"MuJoCo's model has joint(s) the robot does not: {', '.join(extra[:10])}"
            + (f", ... ({len(extra)} in all)" if len(extra) > 10 else ""),
            joints=extra,
        )
    return MujocoMap(layout, tuple(pieces), tuple(follow))


def to_qpos(data: "SpaceData", plan: MujocoMap, x: ArrayLike) -> FloatArray:
    """MuJoCo's qpos (..., nq) of configurations (..., n), canonicalized first.

    Raises:
        ValueOverflowError: A follower's ``multiplier * leader + offset`` overflows.
    """
    canonical = canonicalize(data, x, None)
    lead = canonical.shape[:-1]
    rows = canonical.reshape(math.prod(lead), data.size)
    qpos = output(None, (len(rows), plan.layout.nq))
    qpos[:] = 0.0
    for piece in plan.pieces:
        qpos[:, piece.qpos] = rows[:, piece.columns]
    for f in plan.followers:
        leader = 0.0 if f.column is None else rows[:, f.column]
        with np.errstate(over="ignore", invalid="ignore"):
            qpos[:, f.qposadr] = f.multiplier * leader + f.offset
    check_overflow(qpos, "MuJoCo's qpos", lead)
    return qpos.reshape(*lead, plan.layout.nq)


def from_qpos(data: "SpaceData", plan: MujocoMap, qpos: ArrayLike) -> FloatArray:
    """Canonical configurations (..., n) of MuJoCo qpos (..., nq).

    Angles are wrapped, quaternions put on the upper hemisphere; a quaternion's norm
    must be 1 within the space's tolerance (``space.tolerance``, 1e-6 by default: a qpos
    written with 4 digits needs a wider one, ``dataclasses.replace(space, tolerance=...)``).
    """
    rows, lead = as_rows(qpos, plan.layout.nq, f"MuJoCo qpos of robot '{data.robot}'")
    check_finite(rows, plan.layout.qpos_names(), lead)
    x = output(None, (len(rows), data.size))
    for piece in plan.pieces:
        x[:, piece.columns] = rows[:, piece.qpos]
    return canonicalize(data, x.reshape(*lead, data.size), None)


def to_qvel(data: "SpaceData", plan: MujocoMap, dx: ArrayLike) -> FloatArray:
    """MuJoCo's qvel (..., nv) of tangent vectors (..., dimension).

    Raises:
        ValueOverflowError: A follower's ``multiplier * leader velocity`` overflows.
    """
    rows, lead = as_rows(dx, data.dimension, f"a tangent vector of robot '{data.robot}'")
    check_finite(rows, data.tangent_names, lead)
    qvel = np.zeros((len(rows), plan.layout.nv))
    for piece in plan.pieces:
        qvel[:, piece.qvel] = rows[:, piece.tangent]
    for f in plan.followers:
        if f.tangent is not None:
            with np.errstate(over="ignore", invalid="ignore"):
                qvel[:, f.dofadr] = f.multiplier * rows[:, f.tangent]
    check_overflow(qvel, "MuJoCo's qvel", lead)
    return qvel.reshape(*lead, plan.layout.nv)


def from_qvel(data: "SpaceData", plan: MujocoMap, qvel: ArrayLike) -> FloatArray:
    """Tangent vectors (..., dimension) of MuJoCo qvel (..., nv)."""
    rows, lead = as_rows(qvel, plan.layout.nv, f"MuJoCo qvel of robot '{data.robot}'")
    check_finite(rows, plan.layout.qvel_names(), lead)
    dx = np.zeros((len(rows), data.dimension))
    for piece in plan.pieces:
        dx[:, piece.tangent] = rows[:, piece.qvel]
    return dx.reshape(*lead, data.dimension)


class Maps:
    """MuJoCo's `Maps <cspace.space._conventions._maps.Maps>`: qpos and qvel of the robot's layout.

    Raises:
        JointMatchError: No MuJoCo layout is known, or it does not match the robot.
    """

    def __init__(self, robot: Robot) -> None:
        if robot.mujoco is None:
            raise JointMatchError(
                f"robot '{robot.data.robot}' was not read from MJCF: give MuJoCo's layout "
                "(mujoco=... in Python, --mujoco MJCF on the command line)"
            )
        self.data = robot.data
        self.plan = build_map(robot.mujoco, robot.blocks, robot.followers)

    def names(self, velocity: bool) -> tuple[str, ...]:
        """MuJoCo's name of each qpos (``base.qw``) or qvel entry."""
        layout = self.plan.layout
        return tuple(layout.qvel_names() if velocity else layout.qpos_names())

    def to_tool(self, x: ArrayLike) -> FloatArray:
        """MuJoCo's qpos (..., nq) of canonical configurations (..., n)."""
        return to_qpos(self.data, self.plan, x)

    def from_tool(self, q: ArrayLike) -> FloatArray:
        """Canonical configurations (..., n) of MuJoCo qpos (..., nq)."""
        return from_qpos(self.data, self.plan, q)

    def to_velocity(self, at: ArrayLike, dx: ArrayLike) -> FloatArray:
        """MuJoCo's qvel (..., nv) of tangent vectors (``at`` is not needed)."""
        return to_qvel(self.data, self.plan, dx)

    def from_velocity(self, at: ArrayLike, v: ArrayLike) -> FloatArray:
        """Tangent vectors (..., dimension) of MuJoCo qvel (``at`` is not needed)."""
        return from_qvel(self.data, self.plan, v)
