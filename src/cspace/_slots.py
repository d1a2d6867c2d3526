"""Each joint's slots in each convention: canonical, Pinocchio, MuJoCo (no NumPy).

One robot's configuration is stored differently by each tool (``docs/cspace-math.md``
section 6). Per joint, by the factors of `_joint_table`:

============================  ==================  ====================  ====================
joint                         canonical           Pinocchio q           MuJoCo qpos
============================  ==================  ====================  ====================
revolute, prismatic, helical  ``j``               ``j``                 ``j`` (hinge, slide)
continuous                    ``j`` in [-pi, pi)  ``j.cos``, ``j.sin``  ``j`` (any angle)
spherical                     ``j.qw .. j.qz``    ``j.qx .. j.qz, j.qw``  ``j.qw .. j.qz`` (ball)
floating                      x, y, z, qw..qz     x, y, z, qx..qz, qw   x, y, z, qw..qz (free)
planar                        x, y, theta         x, y, theta.cos/sin   none: no such joint
============================  ==================  ====================  ====================

Velocities: the canonical tangent holds, per factor, the rate of a line or angle and, for
a rotation, the angular velocity in the body's own frame (``j.wx .. j.wz``). MuJoCo's
qvel is the same, joint by joint (a free joint's linear part in the world frame, its
angular part in the body frame). Pinocchio's v differs for floating and planar joints: its
linear part is in the body frame (``base.vx .. base.vz``), so mapping it needs the
configuration, not only a reordering.
"""

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

from cspace._factor_kinds import FactorKind, FactorSpec
from cspace._formats.table import by_name
from cspace._joint_kind import JointKind
from cspace._joint_table import JointFactors, dotted, joint_factors
from cspace._record import NamedTuple
from cspace.errors import JointMatchError

if TYPE_CHECKING:
    from cspace._actuators import Actuator
    from cspace._findings import Diagnostic
    from cspace._joint_report import JointReport


class _Source(Protocol):
    @property
    def path(self) -> str: ...

    @property
    def format(self) -> str: ...


class _Report(Protocol):
    """What `MujocoLayout.from_report` reads of a report (`Report` is one)."""

    @property
    def joints(self) -> "Sequence[JointReport]": ...

    @property
    def source(self) -> _Source: ...

    @property
    def diagnostics(self) -> "Sequence[Diagnostic]": ...

    @property
    def actuators(self) -> "Sequence[Actuator]": ...


MUJOCO_JOINTS = {
    JointKind.REVOLUTE: "hinge",
    JointKind.CONTINUOUS: "hinge",
    JointKind.HELICAL: "hinge",
    JointKind.PRISMATIC: "slide",
    JointKind.SPHERICAL: "ball",
    JointKind.FLOATING: "free",
}
"""The MuJoCo joint type that holds each kind of joint.

The other kinds (planar, translation, universal) are several MuJoCo joints, not one."""

_ANGLES = (JointKind.REVOLUTE, JointKind.CONTINUOUS, JointKind.HELICAL)
_BODY_FRAME = (JointKind.FLOATING, JointKind.PLANAR)
"""Kinds whose Pinocchio v has its linear part in the body frame."""


def canonical_names(joint: str, factors: JointFactors) -> list[str]:
    """Names of a joint's canonical coordinates (``base.x``, ``base.qw``, ``elbow``).

    The names `coordinates_of` gives its coordinates, without
    making them: a rotation has four, other factors one.
    """
    return [
        dotted(joint, name)
        for spec in factors.factors
        for name in (spec.coordinates if spec.kind is FactorKind.ROTATION else spec.coordinates[:1])
    ]


def tangent_names(joint: str, factors: JointFactors) -> list[str]:
    """Names of a joint's tangent coordinates (canonical velocities)."""
    names: list[str] = []
    for spec in factors.factors:
        if spec.kind is FactorKind.ROTATION:
            names += [f"{joint}.w{a}" for a in "xyz"]
        else:
            names.append(dotted(joint, spec.suffix))
    return names


def _pinocchio_q(joint: str, spec: FactorSpec) -> list[str]:
    if spec.encoding == "xyzw":
        return [dotted(joint, c) for c in ("qx", "qy", "qz", "qw")]
    if spec.encoding == "euler_zyx":
        return [dotted(joint, c) for c in ("rz", "ry", "rx")]
    name = dotted(joint, spec.suffix)
    return [f"{name}.cos", f"{name}.sin"] if spec.encoding == "cos_sin" else [name]


def pinocchio_names(
    report: "JointReport", found: JointFactors | None = None
) -> tuple[list[str], list[str]]:
    """Names of a joint's entries in Pinocchio's q and v.

    A joint with q entries but no coordinates of its own (locked, or a mimic joint that
    Pinocchio keeps free) names them after itself. ``found``: its factors, when known.
    """
    found = joint_factors(report) if found is None else found
    joint = report.name
    if not found.factors:
        q = [joint] if report.nq == 1 else [f"{joint}.cos", f"{joint}.sin"][: report.nq]
        return q, [joint] * min(report.nv, 1)
    q = [name for spec in found.factors for name in _pinocchio_q(joint, spec)]
    v = tangent_names(joint, found)
    if report.kind in _BODY_FRAME:  # its linear velocity is in the body frame
        linear = 2 if report.kind is JointKind.PLANAR else 3
        v = [f"{joint}.v{a}" for a in "xyz"[:linear]] + v[linear:]
    return q, v


def mujoco_names(
    report: "JointReport", found: JointFactors | None = None
) -> tuple[list[str], list[str]] | None:
    """Names of a joint's entries in MuJoCo's qpos and qvel.

    None when no single MuJoCo joint holds it (planar, translation, universal) or it has
    no coordinates. ``found``: its factors, when known.
    """
    found = joint_factors(report) if found is None else found
    if report.kind not in MUJOCO_JOINTS or not found.factors or found.unsupported:
        return None
    return canonical_names(report.name, found), tangent_names(report.name, found)


def joint_slots(report: "JointReport", column: int, tangent: int) -> dict[str, Any] | None:
    """The JSON ``slots`` of a joint: where each convention keeps it, with names.

    Args:
        report: The joint.
        column: Its first canonical coordinate (a column of a configuration).
        tangent: Its first tangent coordinate.

    Returns:
        ``{convention: {"index": first, "names": [...]}}`` for ``canonical``,
        ``tangent``, ``pinocchio_q``, ``pinocchio_v`` and, when the report knows MuJoCo's
        layout (MJCF), ``mujoco_qpos`` and ``mujoco_qvel`` (only those for an MJCF mimic
        joint: its entries, set from its leader); None for a joint stored nowhere (fixed,
        a mimic joint of another format).
    """
    mimic_entry = None  # an MJCF mimic joint keeps its one qpos and qvel entry
    if report.kind is JointKind.MIMIC and report.qposadr is not None and report.dofadr is not None:
        mimic_entry = {
            "mujoco_qpos": {"index": report.qposadr, "names": [report.name]},
            "mujoco_qvel": {"index": report.dofadr, "names": [report.name]},
        }
    if report.q_index is None:
        return mimic_entry
    found = joint_factors(report)  # once, for every convention below
    q, v = pinocchio_names(report, found)
    slots: dict[str, Any] = {}
    if found.factors and found.unsupported is None:
        slots["canonical"] = {"index": column, "names": canonical_names(report.name, found)}
        slots["tangent"] = {"index": tangent, "names": tangent_names(report.name, found)}
    slots["pinocchio_q"] = {"index": report.q_index, "names": q}
    slots["pinocchio_v"] = {"index": report.v_index, "names": v}
    in_mujoco = report.qposadr is not None and report.dofadr is not None
    mujoco = mujoco_names(report, found) if in_mujoco else None
    if mujoco is not None and report.qposadr is not None and report.dofadr is not None:
        slots["mujoco_qpos"] = {"index": report.qposadr, "names": mujoco[0]}
        slots["mujoco_qvel"] = {"index": report.dofadr, "names": mujoco[1]}
    return slots | (mimic_entry or {})


def stored_as(report: "JointReport", storage: str) -> tuple[str, ...]:
    """The parts of a joint's stored position in a tool's vector, without the joint name.

    ``("qx", "qy", "qz", "qw")`` for a ball in Pinocchio's q, ``("cos", "sin")`` for a
    continuous joint there, ``("angle",)`` or ``("value",)`` for one number.

    Args:
        report: The joint.
        storage: ``"pinocchio"`` (its q) or ``"mujoco"`` (its qpos).
    """
    if storage == "mujoco":
        mujoco = mujoco_names(report)
        names = mujoco[0] if mujoco is not None else []
    else:
        names = pinocchio_names(report)[0] if report.q_index is not None else []
    prefix = report.name + "."
    one = "angle" if report.kind in _ANGLES else "value"
    return tuple(one if n == report.name else n.removeprefix(prefix) for n in names)


MUJOCO_SIZES = {"free": (7, 6), "ball": (4, 3), "slide": (1, 1), "hinge": (1, 1)}
"""(qpos entries, qvel entries) of each MuJoCo joint type."""

_MUJOCO_TYPES = ("free", "ball", "slide", "hinge")
"""MuJoCo's ``mjtJoint`` values, in order."""


def _mujoco_type(joint: "JointReport") -> str:
    """MuJoCo's type of an MJCF joint (a report of an earlier version: from its kind)."""
    if joint.mujoco_type in MUJOCO_SIZES:
        return joint.mujoco_type
    if joint.kind is JointKind.MIMIC:  # one number: slide or hinge, stored alike
        return "slide" if joint.limits is not None and joint.limits.unit == "m" else "hinge"
    return MUJOCO_JOINTS[joint.kind]


class MujocoJoint(NamedTuple):
    """One joint of a MuJoCo model.

    Attributes:
        name: Its name.
        type: ``free``, ``ball``, ``slide`` or ``hinge``.
        qposadr: Its first entry in qpos.
        dofadr: Its first entry in qvel.
    """

    name: str
    type: str
    qposadr: int
    dofadr: int


class MujocoLayout(NamedTuple):
    """Where a MuJoCo model keeps each joint in qpos and qvel.

    Attributes:
        joints: Every joint, in MuJoCo's order.
        nq: Length of qpos.
        nv: Length of qvel.
        drake: The report's ``drake-mjcf-differs`` findings: what Drake's MJCF parser
            builds otherwise than MuJoCo from the file (none of a ``mujoco.MjModel``),
            which the Drake convention says.
        actuators: Each actuator, in ctrl order (the ``mujoco-ctrl`` convention's).
    """

    joints: tuple[MujocoJoint, ...]
    nq: int
    nv: int
    drake: "tuple[Diagnostic, ...]" = ()
    actuators: "tuple[Actuator, ...]" = ()

    @classmethod
    def from_report(cls, report: _Report) -> "MujocoLayout":
        """The layout of an MJCF file's report (its joints' ``qposadr``, ``dofadr``).

        A mimic joint (an MJCF linear joint equality) keeps its entry. qpos and qvel end
        with the last joint's entries.

        Raises:
            JointMatchError: The report is not of an MJCF file, or its joints are not
                laid out one after another as MuJoCo lays them out (a saved report edited).
        """
        joints = tuple(
            MujocoJoint(j.name, _mujoco_type(j), j.qposadr, j.dofadr)
            for j in report.joints
            if j.qposadr is not None
            and j.dofadr is not None
            and (j.kind in MUJOCO_JOINTS or j.kind is JointKind.MIMIC)
        )
        if by_name(report.source.format).stores != "mujoco":
            raise JointMatchError(
                f"'{report.source.path}' is a {report.source.format} file: MuJoCo's layout "
                "comes from an MJCF file (or a mujoco.MjModel)"
            )
        nq = nv = 0  # MuJoCo lays its joints out one after another, in order
        for joint in joints:
            if (joint.qposadr, joint.dofadr) != (nq, nv):
                raise JointMatchError(
                    f"'{report.source.path}': joint '{joint.name}' is at qpos {joint.qposadr} "
                    f"and qvel {joint.dofadr}, but MuJoCo would place it at {nq} and {nv}",
                    joints=[joint.name],
                )
            nq, nv = nq + MUJOCO_SIZES[joint.type][0], nv + MUJOCO_SIZES[joint.type][1]
        drake = tuple(d for d in report.diagnostics if d.code == "drake-mjcf-differs")
        return cls(joints, nq, nv, drake, tuple(report.actuators))

    @classmethod
    def from_model(cls, model: Any) -> "MujocoLayout":
        """The layout of a ``mujoco.MjModel`` (joints without a name are refused).

        Raises:
            JointMatchError: A joint has no name, or a type MuJoCo does not define.
        """
        joints: list[MujocoJoint] = []
        for i in range(int(model.njnt)):
            name, kind = str(model.joint(i).name), int(model.jnt_type[i])
            if not name or not 0 <= kind < len(_MUJOCO_TYPES):
                raise JointMatchError(
                    f"MuJoCo joint {i} has no name (or an unknown type {kind}): name every "
                    "joint to map configurations by name",
                    joints=[name],
                )
            qposadr, dofadr = int(model.jnt_qposadr[i]), int(model.jnt_dofadr[i])
            joints.append(MujocoJoint(name, _MUJOCO_TYPES[kind], qposadr, dofadr))
        from cspace._actuators import model_actuators

        return cls(tuple(joints), int(model.nq), int(model.nv), (), model_actuators(model))

    def qpos_names(self) -> list[str]:
        """A name for each entry of qpos (``base.x`` .. ``base.qz``, ``elbow``)."""
        names = [""] * self.nq
        for joint in self.joints:
            parts = {"free": (*"xyz", "qw", "qx", "qy", "qz"), "ball": ("qw", "qx", "qy", "qz")}
            for k, part in enumerate(parts.get(joint.type, ("",))):
                names[joint.qposadr + k] = dotted(joint.name, part)
        return names

    def qvel_names(self) -> list[str]:
        """A name for each entry of qvel (``base.x`` .. ``base.wz``, ``elbow``)."""
        names = [""] * self.nv
        for joint in self.joints:
            parts = {"free": (*"xyz", "wx", "wy", "wz"), "ball": ("wx", "wy", "wz")}
            for k, part in enumerate(parts.get(joint.type, ("",))):
                names[joint.dofadr + k] = dotted(joint.name, part)
        return names
