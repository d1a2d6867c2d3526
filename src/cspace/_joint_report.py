"""One joint of a report: its limits, its mimic relation, its record.

Shared by every layer, as the joint kinds are: the model makes these records, the
report (`_reports.report`) holds them, and the tables that read a joint
(`_joint_table`, `_slots`, `_drake_order`) and the space import them from here, below
all of those. It imports only the joint kinds and the normal form.
"""

import math
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._joint_kind import JointKind
from cspace._manifold import NormalForm
from cspace._record import NamedTuple

LIMIT_UNITS = {JointKind.PRISMATIC: "m"}
"""Units of the limits of each kind that is not measured in rad."""


class Limits(NamedTuple):
    """Position limits as the file gives them (rad for rotations, m for translations).

    Attributes:
        lower: One lower bound per limited coordinate.
        upper: One upper bound per limited coordinate.
        unit: ``"rad"`` or ``"m"``.
    """

    lower: tuple[float, ...]
    upper: tuple[float, ...]
    unit: str

    def to_dict(self) -> dict[str, Any]:
        """JSON form; a non-finite number (not valid JSON) becomes null."""
        return {
            "lower": _finite_or_none(self.lower),
            "upper": _finite_or_none(self.upper),
            "unit": self.unit,
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Limits":
        """The limits of a JSON form (a null bound, a non-finite one, is NaN)."""
        return cls(_floats(document["lower"]), _floats(document["upper"]), str(document["unit"]))


def kept_limits(
    kind: JointKind, lower: tuple[float, ...], upper: tuple[float, ...]
) -> Limits | None:
    """The limits a report keeps of a joint's bounds as its file gives them, NaN included.

    None when the file gives none, and for a continuous joint: URDF ignores its limits,
    and so does cspace.
    """
    if lower and kind is not JointKind.CONTINUOUS:
        return Limits(lower, upper, LIMIT_UNITS.get(kind, "rad"))
    return None


class MimicRelation(NamedTuple):
    """``joint value = multiplier * leader value + offset``."""

    joint: str
    multiplier: float
    offset: float

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        multiplier, offset = _finite_or_none((self.multiplier, self.offset))
        return {"joint": self.joint, "multiplier": multiplier, "offset": offset}

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "MimicRelation":
        """The relation of a JSON form (a null number, a non-finite one, is NaN)."""
        multiplier, offset = _floats([document["multiplier"], document["offset"]])
        return cls(str(document["joint"]), multiplier, offset)


class JointReport(NamedTuple):
    """One joint of the robot, fixed and mimic joints included.

    Attributes:
        name: Joint name.
        kind: Its kind.
        parent_link: Parent link, or None for a root joint added above the root link.
        child_link: Child link.
        space: The joint's own space.
        limits: Position limits, or None when the joint has none.
        q_index: First index in Pinocchio's q, or None when the joint has no coordinates.
        nq: Number of q entries.
        v_index: First index in Pinocchio's v, or None.
        nv: Number of v entries.
        mimic: The mimic relation, or None.
        pinocchio_model: Pinocchio's joint model (``shortname()``), or None for fixed joints.
        line: Line of the joint in the file, or None.
        qposadr: For an MJCF file, the joint's first index in MuJoCo's ``qpos``
            (``jnt_qposadr``, quaternions w first); None for other formats, fixed joints
            and a root joint `cspace` added.
        dofadr: For an MJCF file, the joint's first index in MuJoCo's ``qvel``
            (``jnt_dofadr``); None as for ``qposadr``.
        mujoco_type: For an MJCF file, MuJoCo's joint type (``hinge``, ``slide``,
            ``ball``, ``free``; a mimic joint's too); None as for ``qposadr``.
        at_world_origin: For the root joint (the first joint with coordinates, floating
            or planar, or each of the slides and hinge MuJoCo's converter writes for a
            planar one): True when its coordinates are its child link's pose in the
            world, as a root joint cspace adds is placed; False when the file places it
            elsewhere; None for other joints, and when cspace cannot place the joints.
        origin: For a floating joint whose parent is the world (a URDF ``<origin>`` on
            it): its frame in the world, (x, y, z, qw, qx, qy, qz), in which its value
            is a pose (a URDF joint's child's pose in the world is this frame times its
            value, and that is Drake's q of the child); None where it is the identity,
            and for other joints.
    """

    name: str
    kind: JointKind
    parent_link: str | None
    child_link: str
    space: NormalForm
    limits: Limits | None = None
    q_index: int | None = None
    nq: int = 0
    v_index: int | None = None
    nv: int = 0
    mimic: MimicRelation | None = None
    pinocchio_model: str | None = None
    line: int | None = None
    qposadr: int | None = None
    dofadr: int | None = None
    mujoco_type: str | None = None
    at_world_origin: bool | None = None
    origin: tuple[float, ...] | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this joint (``at_world_origin``, ``origin`` only when set)."""
        document: dict[str, Any] = {
            "name": self.name,
            "kind": self.kind.value,
            "parent_link": self.parent_link,
            "child_link": self.child_link,
            "manifold": self.space.notation,
            "dimension": self.space.dimension,
            "limits": None if self.limits is None else self.limits.to_dict(),
            "q_index": self.q_index,
            "nq": self.nq,
            "v_index": self.v_index,
            "nv": self.nv,
            "mimic": None if self.mimic is None else self.mimic.to_dict(),
            "pinocchio_model": self.pinocchio_model,
            "line": self.line,
            "qposadr": self.qposadr,
            "dofadr": self.dofadr,
            "mujoco_type": self.mujoco_type,
        }
        if self.at_world_origin is not None:
            document["at_world_origin"] = self.at_world_origin
        if self.origin is not None:
            document["origin"] = list(self.origin)
        return document

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "JointReport":
        """The joint of a JSON form.

        ``qposadr``, ``dofadr``, ``mujoco_type`` and ``at_world_origin`` may be absent
        (older reports; ``at_world_origin`` is absent where it is unknown, too), and
        ``origin`` where it is the identity (a saved report's is checked by
        `savedreport`: seven finite numbers, a unit quaternion).
        """
        limits, mimic, origin = document["limits"], document["mimic"], document.get("origin")
        return cls(
            name=str(document["name"]),
            kind=JointKind(document["kind"]),
            parent_link=document["parent_link"],
            child_link=str(document["child_link"]),
            space=_space(str(document["manifold"])),
            limits=None if limits is None else Limits.from_dict(limits),
            q_index=document["q_index"],
            nq=int(document["nq"]),
            v_index=document["v_index"],
            nv=int(document["nv"]),
            mimic=None if mimic is None else MimicRelation.from_dict(mimic),
            pinocchio_model=document["pinocchio_model"],
            line=document["line"],
            qposadr=document.get("qposadr"),
            dofadr=document.get("dofadr"),
            mujoco_type=document.get("mujoco_type"),
            at_world_origin=document.get("at_world_origin"),
            origin=None if origin is None else tuple(float(v) for v in origin),
        )


def _finite_or_none(values: tuple[float, ...]) -> list[float | None]:
    return [v if math.isfinite(v) else None for v in values]


def _floats(values: Sequence[float | None]) -> tuple[float, ...]:
    return tuple(math.nan if v is None else float(v) for v in values)


def _space(notation: str) -> NormalForm:
    from cspace.notation import parse_notation  # only when a report is read back

    return parse_notation(notation)
