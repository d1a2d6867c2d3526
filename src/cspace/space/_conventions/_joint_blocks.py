"""Each joint's block in every vector the conventions use, found once per space.

A joint with coordinates has a block of canonical columns, a block of tangent columns,
and (from the report) its entries in Pinocchio's q and v. A joint without coordinates
of its own may still follow another: a mimic joint (``value = multiplier * leader +
offset``), or a locked joint (its one value). The conventions read these blocks instead
of walking the report again.
"""

from typing import TYPE_CHECKING

from cspace._joint_kind import JointKind
from cspace._joint_table import locked
from cspace._record import NamedTuple

if TYPE_CHECKING:
    from cspace.space._data import SpaceData


class JointBlock(NamedTuple):
    """Where one joint with coordinates sits.

    Attributes:
        name: The joint.
        kind: Its kind.
        columns: Its canonical coordinates.
        tangent: Its tangent coordinates.
        v_index: Its first entry in Pinocchio's v.
    """

    name: str
    kind: JointKind
    columns: slice
    tangent: slice
    v_index: int


class Follower(NamedTuple):
    """A joint without coordinates whose value follows from others.

    ``value = multiplier * leader + offset``; a locked joint has no leader (its value is
    ``offset``). Its velocity is ``multiplier * leader velocity`` (0 when locked).

    Attributes:
        name: The joint.
        leader: The leader joint (a one-coordinate joint), or None when locked.
        multiplier: Dimensionless.
        offset: In the joint's units.
        cos_sin: True when Pinocchio's q stores it as (cos, sin).
        v_index: Its first entry in Pinocchio's v, or None when it has none.
    """

    name: str
    leader: str | None
    multiplier: float
    offset: float
    cos_sin: bool
    v_index: int | None


def joint_blocks(data: "SpaceData") -> tuple[dict[str, JointBlock], dict[str, Follower]]:
    """The blocks of the joints with coordinates and the followers, by name, in tree order."""
    tangent: dict[str, slice] = {}
    for slot in data.slots:
        start = tangent[slot.joint].start if slot.joint in tangent else slot.tangent_column
        tangent[slot.joint] = slice(start, slot.tangent_column + slot.factor.dimension)
    columns = data.layout.joint_columns
    blocks: dict[str, JointBlock] = {}
    followers: dict[str, Follower] = {}
    for joint in data.report_joints:
        if joint.name in columns:
            v_index = joint.v_index if joint.v_index is not None else 0
            blocks[joint.name] = JointBlock(
                joint.name, joint.kind, columns[joint.name], tangent[joint.name], v_index
            )
        elif joint.mimic is not None:
            m = joint.mimic
            followers[joint.name] = Follower(
                joint.name, m.joint, m.multiplier, m.offset, joint.nq == 2, joint.v_index
            )
        elif locked(joint.limits) and joint.limits is not None:
            value = joint.limits.lower[0]
            followers[joint.name] = Follower(
                joint.name, None, 0.0, value, joint.nq == 2, joint.v_index
            )
    return blocks, followers
