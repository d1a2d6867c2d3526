"""Whether a file's root joint sits where a root joint cspace adds would.

A root joint cspace adds (``--root-joint``, an SRDF's virtual joint) is placed at the
world's origin, its child link at the joint's frame: its coordinates are that link's
pose in the world. A file's own floating or planar joint is that joint only when it
moves its child link the same way for every value: a URDF ``<origin>`` off the identity
(or a fixed joint above that moves it) puts the link elsewhere for the same q, a
turned planar joint moves it in another plane. MuJoCo's free joint is always in the
world's frame (its body's ``pos``/``quat`` is its starting value, not its placement);
the two slides and the hinge MuJoCo's URDF converter writes for a planar joint are that
joint only when their body sits at the world's origin, the slides along x and y and the
hinge about z through the body's origin, the hinge last.

`at_world_origin` tells by forward kinematics of the model cspace built (the one
`cspace.pinocchio_model` returns), so that every format's own placement rules count.
The report keeps the answer on the root joint's record (``at_world_origin``), so that a
saved report diffs as its file does.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pinocchio as pin

from cspace._joint_kind import JointKind
from cspace._joint_report import JointReport
from cspace._reports.matching import SPLIT_PLANAR, split_planar_parts

TOLERANCE = 1e-9
"""Largest difference (m, or of a rotation matrix's entries) still the same placement:
rounding, not a placement anyone writes."""

_SAMPLES: dict[JointKind, tuple[tuple[float, ...], ...]] = {
    # (x, y, z, qx, qy, qz, qw): zero, and two turns about axes apart, so that only the
    # identity placement puts the link where a joint at the world's origin would
    JointKind.FLOATING: (
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0),
        (0.3, -0.7, 1.1, 0.5, 0.1, -0.2, 0.8),
        (-1.3, 0.4, 0.2, -0.3, 0.6, 0.4, 0.5),
    ),
    # (x, y, theta)
    JointKind.PLANAR: ((0.0, 0.0, 0.0), (0.3, -0.7, 0.9), (-1.3, 0.4, -2.1)),
}


def _reference(kind: JointKind, sample: tuple[float, ...]) -> Any:
    """Where a root joint of ``kind`` at the world's origin puts its link at ``sample``."""
    if kind is JointKind.FLOATING:
        x, y, z, qx, qy, qz, qw = sample
        rotation = pin.Quaternion(qw, qx, qy, qz).normalized().matrix()
        return pin.SE3(rotation, np.array([x, y, z]))
    x, y, theta = sample
    return pin.SE3(pin.utils.rotate("z", theta), np.array([x, y, 0.0]))


def _values(kind: JointKind, nq: int, sample: tuple[float, ...]) -> list[float] | None:
    """A joint's Pinocchio q for its part of ``sample`` (None: not a joint of that size)."""
    if kind is JointKind.FLOATING and nq == 7:
        x, y, z, qx, qy, qz, qw = sample
        norm = float(np.linalg.norm([qx, qy, qz, qw]))
        return [x, y, z, qx / norm, qy / norm, qz / norm, qw / norm]
    if kind is JointKind.PLANAR and nq == 4:
        x, y, theta = sample
        return [x, y, float(np.cos(theta)), float(np.sin(theta))]
    return None


def _group(joints: Sequence[JointReport]) -> tuple[JointKind, list[JointReport]] | None:
    """The root joint (or MuJoCo's three joints of one), when the first in q is one."""
    first = next((j for j in joints if j.q_index is not None), None)
    if first is None or first.q_index != 0:
        return None
    if first.kind in (JointKind.FLOATING, JointKind.PLANAR):
        return first.kind, [first]
    suffix = next((s for s, _ in SPLIT_PLANAR if first.name.endswith(s)), None)
    if suffix is None:
        return None
    parts = split_planar_parts({j.name: j for j in joints}, first.name.removesuffix(suffix))
    return None if parts is None else (JointKind.PLANAR, parts)


def _support(model: Any, frame: int) -> list[int]:
    """The moving joints between a frame and the world, the world's first."""
    joint = int(model.frames[frame].parentJoint)
    chain = []
    while joint != 0:
        chain.append(joint)
        joint = int(model.parents[joint])
    return chain[::-1]


def _chain_model(model: Any, chain: list[int]) -> Any:
    """A model of ``chain``'s joints alone, each placed as in ``model``.

    Forward kinematics of the whole model would need its ``Data``, which holds matrices
    of 6 by nv per joint: 1.2 GB for 5,000 joints. The link's pose needs only these.
    """
    alone = pin.Model()
    parent = 0
    for joint in chain:
        name = str(model.names[joint])
        parent = alone.addJoint(parent, model.joints[joint], model.jointPlacements[joint], name)
    return alone


def _fill(model: Any, q: Any, kind: JointKind, ids: list[int], sample: tuple[float, ...]) -> bool:
    """Set the group's entries of ``q`` to ``sample``; False when its joints do not fit."""
    starts, sizes = model.idx_qs, model.nqs
    if len(ids) == 1:
        values = _values(kind, int(sizes[ids[0]]), sample)
        if values is None:
            return False
        q[starts[ids[0]] : starts[ids[0]] + len(values)] = values
        return True
    x, y, theta = sample  # the slides' and the hinge's values, in SPLIT_PLANAR's order
    for joint, value in ((ids[0], x), (ids[1], y)):
        if sizes[joint] != 1:
            return False
        q[starts[joint]] = value
    hinge, size = ids[2], int(sizes[ids[2]])
    if size == 2:  # an unbounded hinge: (cos, sin)
        q[starts[hinge] : starts[hinge] + 2] = [np.cos(theta), np.sin(theta)]
    elif size == 1:
        q[starts[hinge]] = theta
    else:
        return False
    return True


def at_world_origin(joints: Sequence[JointReport], model: Any) -> dict[str, bool]:
    """Whether the root joint's coordinates are its child link's pose in the world.

    Args:
        joints: The report's joints, in tree order.
        model: The ``pinocchio.Model`` cspace built, with a ``BODY`` frame per link,
            every joint placed where the file puts it.

    Returns:
        The answer for each joint it is about: the first joint with coordinates when it
        is floating or planar (a root joint cspace added: True), or each of MuJoCo's
        three joints of a planar joint when they come first; empty when there is none,
        or the model has no frame for its child link.
    """
    found = _group(joints)
    if found is None:
        return {}
    kind, group = found
    if group[0].parent_link is None:  # added by cspace, at the world's origin
        return {j.name: True for j in group}
    child = group[0].child_link
    if not model.existFrame(child, pin.FrameType.BODY):
        return {}
    frame = model.getFrameId(child, pin.FrameType.BODY)
    ids = [int(model.getJointId(j.name)) for j in group]
    if any(i <= 0 or i >= model.njoints for i in ids):
        return {}
    chain = _support(model, frame)
    if sorted(chain) != sorted(ids):  # another joint moves the link too
        return {j.name: False for j in group}
    alone = _chain_model(model, chain)
    mine = [chain.index(i) + 1 for i in ids]  # each joint's id in ``alone``
    link = model.frames[frame].placement  # in the frame of the last joint of the chain
    data = alone.createData()
    placed = True
    for sample in _SAMPLES[kind]:
        q = pin.neutral(alone)
        if not _fill(alone, q, kind, mine, sample):
            placed = False
            break
        pin.forwardKinematics(alone, data, q)
        where = data.oMi[len(chain)] * link
        expected = _reference(kind, sample)
        if not np.allclose(where.homogeneous, expected.homogeneous, rtol=0.0, atol=TOLERANCE):
            placed = False
            break
    return {j.name: placed for j in group}
