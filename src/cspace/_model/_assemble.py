"""Pinocchio models assembled through its model API, for formats whose parser it lacks.

`tree_model` builds an MJCF file's kinematic tree as MuJoCo compiled it (bodies with
frames, joints with anchors); `build_model` builds SDF's and OpenUSD's placed joint
lists (`cspace._formats.shared.reading.JointList`). Both give every link a ``BODY`` frame
where the file puts it, so that forward kinematics are the format's own tool's.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import pinocchio as pin

from cspace._formats.shared.description import JointToAdd, MimicSpec
from cspace._formats.shared.kinematic_tree import KinematicTree, TreeJoint
from cspace._formats.shared.pose import Pose
from cspace._formats.shared.reading import LinkFrame
from cspace._model._records import (
    ROOT_JOINT_NAME,
    PinModel,
    dependent,
    record_of,
    root_joint_model,
)


def tree_model(tree: KinematicTree, root_joint: str | None = None) -> Any:
    """A ``pinocchio.Model`` of a kinematic tree with frames (MJCF through MuJoCo).

    Each body is a Pinocchio ``BODY`` frame at its MuJoCo frame. A body's joints are
    Pinocchio joints in a chain: the first placed at the body's frame moved to its
    anchor, each next one relative to the previous anchor, the body at minus the last
    anchor, so that forward kinematics are MuJoCo's. A joint's ``reference`` is folded
    into its placement, so that Pinocchio's ``q`` of a revolute or prismatic joint is
    MuJoCo's ``qpos`` (a quaternion stored x-y-z-w, where MuJoCo stores w first).

    Args:
        tree: The bodies and joints.
        root_joint: None, ``"floating"`` or ``"planar"``: a joint added under the world,
            carrying every top-level body.

    Raises:
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    model = pin.Model()
    model.name = tree.name
    support, frame = 0, 0
    if root_joint is not None:
        support = model.addJoint(
            0, root_joint_model(root_joint), pin.SE3.Identity(), ROOT_JOINT_NAME
        )
        frame = model.addJointFrame(support, 0)
    supports = [support]  # each body's supporting joint
    in_joint = [pin.SE3.Identity()]  # each body's frame in its supporting joint's frame
    frames = [frame]
    by_body: dict[int, list[TreeJoint]] = {}
    for joint in tree.joints:
        by_body.setdefault(joint.body, []).append(joint)
    for index, body in enumerate(tree.bodies[1:], start=1):
        w, x, y, z = body.quaternion_wxyz
        rotation = pin.Quaternion(w, x, y, z).normalized().matrix()
        placement = in_joint[body.parent] * pin.SE3(rotation, np.array(body.position))
        support = supports[body.parent]
        for joint in by_body.get(index, []):
            place, after = _joint_placement(joint, placement, in_joint[body.parent])
            support = model.addJoint(support, *_tree_joint(joint, place))
            model.addJointFrame(support, frames[body.parent])
            placement = after
        supports.append(support)
        in_joint.append(placement)
        frames.append(
            model.addFrame(
                pin.Frame(body.name, support, frames[body.parent], placement, pin.FrameType.BODY)
            )
        )
    return model


def _joint_placement(joint: TreeJoint, body: Any, parent: Any) -> tuple[Any, Any]:
    """Where a joint sits in its parent joint's frame, and its body in the joint's frame."""
    if joint.model == "floating":  # MuJoCo's free joint: the body's pose is the joint's value
        return parent, pin.SE3.Identity()
    anchor = np.array(joint.anchor)
    axis = np.array(joint.axis)
    zero = pin.SE3(np.eye(3), anchor)
    if joint.model == "revolute" and joint.reference != 0.0:
        zero = zero * pin.SE3(pin.AngleAxis(-joint.reference, axis).matrix(), np.zeros(3))
    elif joint.model == "prismatic" and joint.reference != 0.0:
        zero = zero * pin.SE3(np.eye(3), -joint.reference * axis)
    return body * zero, pin.SE3(np.eye(3), -anchor)


def _tree_joint(joint: TreeJoint, place: Any) -> tuple[Any, ...]:
    """``addJoint``'s arguments after the parent: model, placement, name, limits."""
    model = _joint_model(JointToAdd(joint.name, None, joint.model, joint.axis))
    if model.nq != 1:
        return model, place, joint.name
    big = np.array([np.finfo(float).max])
    return model, place, joint.name, big, big, np.array([joint.lower]), np.array([joint.upper])


def build_tree_model(
    tree: KinematicTree, root_joint: str | None, mimics: Mapping[str, MimicSpec] | None = None
) -> PinModel:
    """What `cspace` needs of `tree_model`'s Pinocchio model, mimic joints made dependent.

    Args:
        tree: The bodies and joints.
        root_joint: None, ``"floating"`` or ``"planar"``.
        mimics: The joints that follow others (an MJCF file's linear joint equalities),
            by name. Pinocchio keeps a follower dependent only when its leader comes
            earlier in its joint order; the others keep their q and v entries, and
            ``mimic_fallback`` says so.

    Raises:
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    model, fallback = dependent(tree_model(tree, root_joint), mimics or {})
    return record_of(model, mimic_fallback=fallback)


def _aligned(axis: tuple[float, float, float]) -> str | None:
    for letter, unit in zip(
        "XYZ", ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), strict=True
    ):
        if axis == unit:
            return letter
    return None


def _joint_model(joint: JointToAdd) -> Any:
    axis = np.array(joint.axis, dtype=float)
    letter = _aligned(joint.axis)
    builders: dict[str, Callable[[], Any]] = {
        "revolute": lambda: (
            getattr(pin, f"JointModelR{letter}")()
            if letter
            else pin.JointModelRevoluteUnaligned(axis)
        ),
        "continuous": lambda: getattr(pin, f"JointModelRUB{letter or 'Z'}")(),  # see _turn
        "prismatic": lambda: (
            getattr(pin, f"JointModelP{letter}")()
            if letter
            else pin.JointModelPrismaticUnaligned(axis)
        ),
        "helical": lambda: pin.JointModelHelicalUnaligned(axis, joint.pitch),
        "spherical": pin.JointModelSpherical,
        "universal": lambda: pin.JointModelUniversal(axis, np.array(joint.axis2, dtype=float)),
        "floating": pin.JointModelFreeFlyer,
        "planar": pin.JointModelPlanar,
        "translation": pin.JointModelTranslation,
    }
    return builders[joint.model]()


def build_model(
    name: str,
    joints: Sequence[JointToAdd],
    root_joint: str | None,
    mimics: Mapping[str, MimicSpec] | None = None,
    links: Sequence[LinkFrame] = (),
) -> PinModel:
    """Assemble a Pinocchio model joint by joint (for formats whose parser this Pinocchio lacks).

    The joint models, their order and the q/v layout are Pinocchio's; each joint at its
    ``placement``, each link a ``BODY`` frame (a fixed joint's child also a
    ``FIXED_JOINT`` frame), as Pinocchio's URDF parser makes them. A continuous joint
    about an axis off x, y and z (Pinocchio's Python API cannot give one an axis) is
    turned so that its axis is its z, its children placed in the turned frame.

    Args:
        name: Model name.
        joints: Moving joints, each after its parent.
        root_joint: None, ``"floating"`` or ``"planar"``.
        mimics: The joints that follow others, by name, made dependent as in
            `build_tree_model`.
        links: Every link in its carrying joint's frame (`joint_list`).

    Returns:
        The model's joints and sizes.

    Raises:
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    model = pin.Model()
    model.name = name
    ids: dict[str | None, int] = {None: 0}
    turned: dict[str | None, Any] = {None: pin.SE3.Identity()}  # joint frame in Pinocchio's
    if root_joint is not None:
        ids[None] = model.addJoint(
            0, root_joint_model(root_joint), pin.SE3.Identity(), ROOT_JOINT_NAME
        )
    for joint in joints:
        turn = _turn(joint)
        place = turned[joint.parent].actInv(_se3(joint.placement)) * turn
        ids[joint.name] = model.addJoint(ids[joint.parent], _joint_model(joint), place, joint.name)
        turned[joint.name] = turn
    frames: dict[str | None, int] = {}
    for owner in (None, *(j.name for j in joints)):
        frames[owner] = 0 if ids[owner] == 0 else model.addJointFrame(ids[owner], 0)
    for link in links:
        place = turned[link.joint].actInv(_se3(link.pose))
        parent = frames[link.joint]
        if link.via is not None:
            parent = model.addFrame(
                pin.Frame(link.via, ids[link.joint], parent, place, pin.FrameType.FIXED_JOINT)
            )
        model.addFrame(pin.Frame(link.name, ids[link.joint], parent, place, pin.FrameType.BODY))
    model, fallback = dependent(model, mimics or {})
    return record_of(model, mimic_fallback=fallback)


def _se3(pose: Pose) -> Any:
    w, x, y, z = pose.rotation_wxyz
    return pin.SE3(pin.Quaternion(w, x, y, z).normalized().matrix(), np.array(pose.position))


def _turn(joint: JointToAdd) -> Any:
    """The rotation taking z to a continuous joint's axis off x, y and z (else identity)."""
    if joint.model != "continuous" or _aligned(joint.axis):
        return pin.SE3.Identity()
    axis = np.array(joint.axis, dtype=float)
    rotation = pin.Quaternion.FromTwoVectors(np.array([0.0, 0.0, 1.0]), axis).matrix()
    return pin.SE3(rotation, np.zeros(3))
