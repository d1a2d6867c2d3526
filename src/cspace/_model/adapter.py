"""The one place that talks to Pinocchio.

It builds a Pinocchio model: from a URDF with Pinocchio's parser (mimic joints kept
dependent; what its C++ parser prints is silenced and kept), from an MJCF file's
kinematic tree as MuJoCo compiled it (`tree_model`), and joint by joint for SDF and
OpenUSD (`build_model`). It returns our own records (`PinModel`), so that nothing
else in `cspace` depends on Pinocchio's types.

Pinocchio's conventions, which `PinModel` keeps as they are: configuration
vector ``q`` of length ``nq`` (a quaternion stored as (x, y, z, w); a continuous joint
as (cos, sin)), tangent vector ``v`` of length ``nv``; angles in rad, lengths in m.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
import pinocchio as pin

from cspace._formats._pose import Pose
from cspace._formats.description import JointToAdd, MimicSpec, RobotDescription
from cspace._formats.kinematic_tree import KinematicTree, TreeJoint
from cspace._formats.reading import JointList, LinkFrame, Reading
from cspace._joint_kind import JointKind
from cspace._model.native import BUILD_STACK_BYTES as BUILD_STACK_BYTES  # its old home
from cspace._model.native import on_own_stack, parser_messages, quietly
from cspace.errors import InvalidRootJointError, ModelBuildError

ROOT_JOINT_NAME = "root_joint"
"""The name given to a root joint that `cspace` adds to a file that has none."""

_ROOT_JOINT_MODELS: dict[str, Callable[[], Any]] = {
    "floating": pin.JointModelFreeFlyer,
    "planar": pin.JointModelPlanar,
}
ROOT_JOINTS = tuple(_ROOT_JOINT_MODELS)
"""The root joints a user may add: ``floating`` (SE(3)) or ``planar`` (SE(2))."""


class PinMimic(NamedTuple):
    """A mimic joint's relation: ``value = scaling * leader + offset``."""

    leader: str
    scaling: float
    offset: float


class PinJoint(NamedTuple):
    """One joint of a Pinocchio model.

    Attributes:
        name: Joint name.
        model: Pinocchio's ``shortname()``, e.g. ``"JointModelRZ"``.
        idx_q: First index in ``q``.
        nq: Number of ``q`` entries.
        idx_v: First index in ``v``.
        nv: Number of ``v`` entries.
        lower: Pinocchio's lower position limits for its ``nq`` entries.
        upper: Pinocchio's upper position limits for its ``nq`` entries.
        mimic: The mimic relation, or None.
    """

    name: str
    model: str
    idx_q: int
    nq: int
    idx_v: int
    nv: int
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    mimic: PinMimic | None = None


class PinModel(NamedTuple):
    """What `cspace` needs of a Pinocchio model.

    Attributes:
        name: The model's name.
        nq: Length of the configuration vector.
        nv: Length of the tangent vector.
        joints: Every joint but Pinocchio's ``universe``, in Pinocchio's order.
        parser_messages: What the C++ parser printed while loading (kept, not shown).
        mimic_fallback: Why mimic joints could not be kept dependent, or None. When
            set, the model was built with every mimic joint as a free joint of its own
            (it has q and v entries, which a user must fill from its leader).
        pinocchio: The ``pinocchio.Model`` itself, or None.
    """

    name: str
    nq: int
    nv: int
    joints: tuple[PinJoint, ...]
    parser_messages: tuple[str, ...] = ()
    mimic_fallback: str | None = None
    pinocchio: Any = None


def _root_joint_model(root_joint: str) -> Any:
    try:
        return _ROOT_JOINT_MODELS[root_joint]()
    except KeyError:
        raise InvalidRootJointError(root_joint, ROOT_JOINTS) from None


def build(path: str, reading: Reading, root_joint: str | None) -> PinModel:
    """The Pinocchio model of any reader's `Reading`.

    Args:
        path: The file, for messages.
        reading: What the format reader found, with its recipe.
        root_joint: None, ``"floating"`` or ``"planar"``.

    Raises:
        ModelBuildError: Pinocchio refused the model.
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    recipe, description = reading.recipe, reading.description
    if isinstance(recipe, KinematicTree):
        mimics = {j.name: j.mimic for j in description.joints if j.mimic is not None}
        return build_tree_model(recipe, root_joint, mimics)
    if isinstance(recipe, JointList):
        mimics = {j.name: j.mimic for j in description.joints if j.mimic is not None}
        return build_model(description.name, recipe.joints, root_joint, mimics, recipe.links)
    has_mimic = any(j.mimic is not None for j in description.joints)
    return build_urdf_model(
        path, recipe.text, root_joint, has_mimic=has_mimic, description=description
    )


def build_urdf_model(
    path: str,
    text: str,
    root_joint: str | None,
    *,
    has_mimic: bool = False,
    description: RobotDescription | None = None,
) -> PinModel:
    """Build a Pinocchio model from URDF text, mimic joints kept dependent.

    Pinocchio keeps a mimic joint dependent only when its leader comes earlier in its
    joint order; when it refuses for that reason, the model is built again with mimic
    joints as free joints, and ``mimic_fallback`` says why.

    Args:
        path: The file, for messages.
        text: The URDF document.
        root_joint: None, ``"floating"`` or ``"planar"``: a joint added above the root link.
        has_mimic: The file declares mimic joints (enables the fallback).
        description: The file as our reader read it: when Pinocchio refuses it, the
            joint or link its message names gives the error its line.

    Returns:
        The model's joints and sizes.

    Raises:
        ModelBuildError: Pinocchio refused the file; its messages are kept.
        InvalidRootJointError: ``root_joint`` is not a supported name.
    """
    args: tuple[Any, ...] = ()
    if root_joint is not None:
        args = (_root_joint_model(root_joint), ROOT_JOINT_NAME)

    def build(mimic: bool) -> Callable[[], Any]:
        return lambda: pin.buildModelFromXML(text, *args, mimic=mimic)

    swaps = _swaps(description)  # mimic joints made dependent after the swap, if any
    model, error, printed = on_own_stack(lambda: quietly(build(not swaps)))
    messages = parser_messages(printed)
    fallback = None
    if error is not None and has_mimic:
        model, second_error, printed = on_own_stack(lambda: quietly(build(False)))
        if second_error is None:
            fallback = _error_text(error, messages)
            messages = parser_messages(printed)
    if model is None:
        said = _error_text(error, messages)
        named = " ".join((said, *messages))  # the element may be named by a later message
        line, element = (None, None) if description is None else description.locate(named)
        raise ModelBuildError(
            path,
            f"Pinocchio's URDF parser refused the file: {said}",
            messages,
            line=line,
            element=element,
        )
    if swaps and description is not None:
        from cspace._model._swap import swap_joints

        mimics = {j.name: j.mimic for j in description.joints if j.mimic is not None}
        model, fallback = _dependent(swap_joints(model, swaps), mimics)
    return record_of(model, messages, fallback)


_SWAPPED = {JointKind.SPHERICAL: "spherical", JointKind.UNIVERSAL: "universal"}
"""The kinds of ``<drake:joint>`` Pinocchio's URDF parser is given as floating joints."""


def _swaps(description: RobotDescription | None) -> dict[str, str]:
    """The joints whose models `swap_joints` puts in place, by name."""
    if description is None:
        return {}
    return {
        j.name: _SWAPPED[j.kind]
        for j in description.joints
        if j.type.startswith("drake:") and j.kind in _SWAPPED
    }


def _error_text(error: BaseException | None, messages: tuple[str, ...]) -> str:
    if messages:
        return messages[0]
    if error is None:
        return "unknown error"
    return exception_text(str(error)) or type(error).__name__


def exception_text(text: str) -> str:
    """What a Pinocchio C++ exception says, on one line, without its source location.

    Pinocchio's checks raise ``From file: ... in function: <template signature> at
    line: N message: <what> hint: <why>``; only the message and the hint are about the
    robot file.
    """
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    if "message:" in lines:
        kept = lines[lines.index("message:") + 1 :]
        return "; ".join(line.removeprefix("hint: ") for line in kept)
    return " ".join(lines)


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
            0, _root_joint_model(root_joint), pin.SE3.Identity(), ROOT_JOINT_NAME
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
    model, fallback = _dependent(tree_model(tree, root_joint), mimics or {})
    return record_of(model, mimic_fallback=fallback)


MIMIC_WORK = 2_000_000
"""Most joints Pinocchio copies making mimic joints dependent: each relation copies the
model (``transformJointIntoMimic``), 13.6 ms for a 5,000-joint model, so 4,999 followers
took over a minute. Within it, 400 followers of a 5,000-joint model (5.4 s), or every
follower of a 1,400-joint one; the others keep their entries (``mimic-kept-free``)."""


def _dependent(model: Any, mimics: Mapping[str, MimicSpec]) -> tuple[Any, str | None]:
    """``model`` with the joints of ``mimics`` made mimic joints, and what was kept free.

    Pinocchio keeps a follower dependent only when its leader comes earlier in its joint
    order; the others keep their q and v entries, and the text returned says so.
    """
    later: list[str] = []
    refused: list[str] = []
    beyond: list[str] = []
    budget = MIMIC_WORK // max(model.njoints, 1)  # each copies the model
    for name, mimic in mimics.items():
        follower, leader = model.getJointId(name), model.getJointId(mimic.joint)
        if leader >= follower:
            later.append(name)
            continue
        if budget <= 0:
            beyond.append(name)
            continue
        budget -= 1
        try:
            model = pin.transformJointIntoMimic(
                model, leader, follower, mimic.multiplier, mimic.offset
            )
        except (ValueError, RuntimeError):  # another kind, or a leader that follows
            refused.append(name)
    said = []
    if later:
        said.append(f"{', '.join(later)} follow(s) a joint that comes later in the tree")
    if refused:
        said.append(
            f"Pinocchio cannot make {', '.join(refused)} follow its leader (a joint of "
            "another kind, one that turns freely, or one that follows another)"
        )
    if beyond:
        said.append(
            f"{len(beyond):,} more followers than Pinocchio makes dependent in bounded "
            f"time ({MIMIC_WORK:,} joints copied in all): {', '.join(beyond[:5])}"
            + (", ..." if len(beyond) > 5 else "")
        )
    return model, "; ".join(said) or None


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
            0, _root_joint_model(root_joint), pin.SE3.Identity(), ROOT_JOINT_NAME
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
    model, fallback = _dependent(model, mimics or {})
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


def record_of(
    model: Any, messages: tuple[str, ...] = (), mimic_fallback: str | None = None
) -> PinModel:
    """Copy what `cspace` needs out of a ``pinocchio.Model``.

    Pinocchio's per-joint vectors (``idx_qs``, ``nqs``, ``idx_vs``, ``nvs``, ``names``,
    the limits) are read whole, once: a call into Pinocchio per joint and attribute
    cost ten times as much on large robots.
    """
    names = [str(name) for name in model.names]
    idx_qs, nqs = list(model.idx_qs), list(model.nqs)
    # A mimic joint shares its leader's q index. (Pinocchio keeps mimicking_joints and
    # mimicked_joints each sorted on its own: zipped, two crossing pairs swap leaders.)
    mimicking = {int(i) for i in model.mimicking_joints}
    owner = {idx_qs[i]: i for i in range(1, len(nqs)) if nqs[i] and i not in mimicking}
    mimic_of = {i: owner[idx_qs[i]] for i in mimicking}
    idx_vs, nvs = list(model.idx_vs), list(model.nvs)
    lower: list[float] = model.lowerPositionLimit.tolist()
    upper: list[float] = model.upperPositionLimit.tolist()
    joints = []
    for index, joint in enumerate(model.joints):
        if index == 0:  # Pinocchio's universe
            continue
        mimic = None
        first, nq = int(idx_qs[index]), int(nqs[index])
        span = slice(first, first + nq)
        if index in mimic_of:
            detail = joint.extract()
            mimic = PinMimic(
                leader=names[mimic_of[index]],
                scaling=float(detail.scaling),
                offset=float(detail.offset),
            )
            span = slice(0, 0)  # a mimic joint has no coordinates of its own
        joints.append(
            PinJoint(
                name=names[index],
                model=str(joint.shortname()),
                idx_q=first,
                nq=nq,
                idx_v=int(idx_vs[index]),
                nv=int(nvs[index]),
                lower=tuple(lower[span]),
                upper=tuple(upper[span]),
                mimic=mimic,
            )
        )
    return PinModel(
        name=str(model.name),
        nq=int(model.nq),
        nv=int(model.nv),
        joints=tuple(joints),
        parser_messages=messages,
        mimic_fallback=mimic_fallback,
        pinocchio=model,
    )
