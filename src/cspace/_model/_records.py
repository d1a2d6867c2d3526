"""What `cspace` keeps of a Pinocchio model, and the steps every builder shares.

`PinModel` and its joints are our own records, so that nothing else in `cspace`
depends on Pinocchio's types; `record_of` copies them out of a ``pinocchio.Model``.
`dependent` makes mimic joints follow their leaders, within a bounded amount of work.

Pinocchio's conventions, which `PinModel` keeps as they are: configuration vector
``q`` of length ``nq`` (a quaternion stored as (x, y, z, w); a continuous joint as
(cos, sin)), tangent vector ``v`` of length ``nv``; angles in rad, lengths in m.
"""

from collections.abc import Callable, Mapping
from typing import Any

import pinocchio as pin

from cspace._formats.shared.description import MimicSpec
from cspace._record import NamedTuple
from cspace.errors import InvalidRootJointError

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
        origin: A free-flyer joint's frame in the world (x, y, z, qw, qx, qy, qz) when
            the world (Pinocchio's universe) is its parent and the frame is not the
            identity (a URDF ``<origin>``); None otherwise.
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
    origin: tuple[float, ...] | None = None


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


def root_joint_model(root_joint: str) -> Any:
    try:
        return _ROOT_JOINT_MODELS[root_joint]()
    except KeyError:
        raise InvalidRootJointError(root_joint, ROOT_JOINTS) from None


MIMIC_WORK = 2_000_000
"""Most joints Pinocchio copies making mimic joints dependent: each relation copies the
model (``transformJointIntoMimic``), 13.6 ms for a 5,000-joint model, so 4,999 followers
would take over a minute. Within it, 400 followers of a 5,000-joint model (5.4 s), or every
follower of a 1,400-joint one; the others keep their entries (``mimic-kept-free``)."""


def dependent(model: Any, mimics: Mapping[str, MimicSpec]) -> tuple[Any, str | None]:
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
    parents = list(model.parents)
    joints = []
    for index, joint in enumerate(model.joints):
        if index == 0:  # Pinocchio's universe
            continue
        shortname = str(joint.shortname())
        origin = None
        if shortname == "JointModelFreeFlyer" and parents[index] == 0:
            origin = _pose_of(model.jointPlacements[index])
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
                model=shortname,
                idx_q=first,
                nq=nq,
                idx_v=int(idx_vs[index]),
                nv=int(nvs[index]),
                lower=tuple(lower[span]),
                upper=tuple(upper[span]),
                mimic=mimic,
                origin=origin,
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


def _pose_of(placement: Any) -> tuple[float, ...] | None:
    """A ``pinocchio.SE3`` as (x, y, z, qw, qx, qy, qz); None for the identity."""
    if placement.isIdentity(0.0):
        return None
    x, y, z = (float(c) for c in placement.translation)
    turn = pin.Quaternion(placement.rotation)
    return (x, y, z, float(turn.w), float(turn.x), float(turn.y), float(turn.z))
