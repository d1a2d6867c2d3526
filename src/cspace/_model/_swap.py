"""Joint models Pinocchio's URDF parser cannot make, put in place once the model is built.

A URDF ``<drake:joint type="ball">`` or ``type="universal"`` (Drake's extension) is given
to Pinocchio's parser as a ``floating`` joint with the same name, parent, child and
origin (see `cspace._formats.urdf.reader`); `swap_joints` then rebuilds the model with a
``JointModelSpherical`` or a ``JointModelUniversal`` about the joint frame's x and then
y axis (Drake's universal joint) in its place: same joints in the same order, same
placements, bodies and frames, so that forward kinematics are the file's.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pinocchio as pin

_MODELS = {
    "spherical": pin.JointModelSpherical,
    "universal": lambda: pin.JointModelUniversal(np.array([1.0, 0, 0]), np.array([0, 1.0, 0])),
}
"""The joint model of each kind put in place."""


def swap_joints(model: Any, swaps: Mapping[str, str]) -> Any:
    """``model`` rebuilt with the joints named in ``swaps`` of the kind given there.

    Args:
        model: A ``pinocchio.Model`` without mimic joints.
        swaps: Joint name -> ``"spherical"`` or ``"universal"``.

    Returns:
        A new ``pinocchio.Model``; the other joints keep their models and position limits.
    """
    built = pin.Model()
    built.name = model.name
    for index in range(1, model.njoints):
        joint, name = model.joints[index], model.names[index]
        kind = swaps.get(name)
        placement = model.jointPlacements[index]
        parent = model.parents[index]
        if kind is None:
            q = slice(joint.idx_q, joint.idx_q + joint.nq)
            v = slice(joint.idx_v, joint.idx_v + joint.nv)
            added = built.addJoint(
                parent,
                joint,
                placement,
                name,
                model.effortLimit[v],
                model.velocityLimit[v],
                model.lowerPositionLimit[q],
                model.upperPositionLimit[q],
            )
        else:
            added = built.addJoint(parent, _MODELS[kind](), placement, name)
        built.appendBodyToJoint(added, model.inertias[index], pin.SE3.Identity())
        if kind is None:  # what addJoint does not take: the joint's dynamics
            into = slice(built.joints[added].idx_v, built.joints[added].idx_v + joint.nv)
            for field in _PER_VELOCITY:
                getattr(built, field)[into] = getattr(model, field)[v]
    built.inertias[0] = model.inertias[0]
    for frame in list(model.frames)[1:]:  # the universe's frame is there already
        built.addFrame(pin.Frame(frame), False)
    return built


_PER_VELOCITY = ("damping", "friction", "armature", "rotorInertia", "rotorGearRatio")
"""The model's per-velocity vectors a joint kept as it was carries over."""
