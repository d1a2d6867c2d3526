"""SRDF group states, checked as configurations of the robot's C-space.

A group state gives each joint it names its value, as MoveIt reads it: one number for a
revolute, prismatic or continuous joint, ``x y theta`` for a planar joint, ``x y z qx
qy qz qw`` for a floating one. Pinocchio's ``loadReferenceConfigurations`` reads the same
but for a planar joint, whose nq numbers it takes (``x y cos sin``): both forms are read.
Any other count is neither tool's, and the state no configuration. The pose is the
whole robot's, the joints the state does not name at neutral, as Pinocchio's
``referenceConfigurations`` holds it. Only the first `MAX_POSE_NUMBERS` numbers of
states are assembled into configurations (5,000 states of a 3,000-joint robot would
be 15 million), so that the report is read back.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

from cspace._factor_kinds import Coordinates
from cspace._findings import Diagnostic, finding
from cspace._formats.srdf.reader import GroupState
from cspace._joint_kind import JointKind
from cspace._joint_report import JointReport
from cspace._model._srdf_groups import Resolved
from cspace._reports.poses import MAX_POSE_NUMBERS, StoredPose, assemble
from cspace._safetext import printable
from cspace.errors._base import did_you_mean

SLACK = 1e-4
"""How far past a bound a stored value may be (rad or m), as for MJCF keyframes: states
are written rounded (pi/2 as 1.5707)."""

UNIT_SLACK = 1e-3
"""How far a stored quaternion's (or cos-sin pair's) norm may be from 1."""

_SCALAR = (JointKind.REVOLUTE, JointKind.PRISMATIC, JointKind.HELICAL, JointKind.UNIVERSAL)
"""Kinds whose state values are their coordinates, each checked against its limits."""

Say = Callable[[str, str], None]
"""Records a finding: (code, problem)."""

_SIZES = {
    JointKind.REVOLUTE: (1,),
    JointKind.PRISMATIC: (1,),
    JointKind.HELICAL: (1,),
    JointKind.CONTINUOUS: (1,),
    JointKind.UNIVERSAL: (2,),
    JointKind.TRANSLATION: (3,),
    JointKind.SPHERICAL: (4,),
    JointKind.PLANAR: (3, 4),
    JointKind.FLOATING: (7,),
}
"""How many numbers a state may give each kind of joint: MoveIt's variables, and for a
planar joint Pinocchio's nq too (``x y cos sin``; Pinocchio refuses MoveIt's ``x y
theta``, and both take one angle for a continuous joint). Joints MoveIt does not know
take Pinocchio's nq: a universal joint's two angles, a ball joint's ``qx qy qz qw``."""


def state_findings(
    resolved: Resolved, joints: Sequence[JointReport], coordinates: Coordinates
) -> tuple[list[Diagnostic], list[StoredPose]]:
    """Each group state checked as a configuration, and the poses the states store.

    Findings, each naming the state, its group, the joint, the value, the bounds and
    the line (``srdf-unknown-name`` is an error raised by `resolve`, not a finding):

    - ``pose-out-of-limits`` (error): a value outside a limited joint's range (by more
      than `SLACK`), not finite, or the wrong count of numbers for the joint;
    - ``pose-not-unit`` (warning): a quaternion or cos-sin pair whose norm is off 1;
    - ``pose-mimic-inconsistent`` (warning): a mimic joint off its leader's relation;
    - ``pose-joint-outside-group`` (info): a value for a joint not in the group
      (MoveIt ignores it, Pinocchio sets it);
    - ``srdf-ignored`` (warning): a state of a group the SRDF lacks, or a value for a
      joint the robot lacks or that is fixed (skipped, as MoveIt and Pinocchio skip it).

    A state is a pose of the whole robot with the joints it does not name at their
    neutral values (as Pinocchio's ``referenceConfigurations`` holds it). Its
    configuration is None when a value is not finite or of the wrong count.
    """
    srdf = resolved.srdf
    by_name = {j.name: j for j in joints}
    groups = resolved.groups
    found: list[Diagnostic] = []
    poses: list[StoredPose] = []
    room, left = MAX_POSE_NUMBERS, 0  # states x coordinates: 5,000 states of 3,000 joints
    for state in srdf.states:
        if state.group is not None and state.group not in groups:
            problem = (
                f"group state '{state.name}' is of group '{state.group}', which the SRDF does "
                "not define" + did_you_mean(state.group, groups) + " (MoveIt skips it)"
            )
            found.append(finding("srdf-ignored", None, problem, state.line, srdf.path))
            continue
        if state.group is not None and state.group in resolved.broken:
            problem = (
                f"group state '{state.name}' is of group '{state.group}', which MoveIt does "
                f"not load ({resolved.broken[state.group]}): not checked"
            )
            found.append(finding("srdf-ignored", None, problem, state.line, srdf.path))
            continue
        values, ok = _state_values(resolved, state, by_name, found)
        room -= len(coordinates.entries)
        configuration = assemble(coordinates, values) if ok and room >= 0 else None
        if ok and room < 0:
            left += 1
        poses.append(StoredPose(state.name, "group_state", state.line, state.group, configuration))
    if left:
        found.append(
            finding(
                "poses-not-checked",
                None,
                f"{left:,} group states listed without their configuration: cspace lists "
                f"{MAX_POSE_NUMBERS:,} numbers of poses at most",
                None,
                srdf.path,
            )
        )
    return found, poses


def _state_values(
    resolved: Resolved,
    state: GroupState,
    by_name: Mapping[str, JointReport],
    found: list[Diagnostic],
) -> tuple[dict[str, tuple[float, ...]], bool]:
    """The canonical values a state gives (by joint), and whether all were usable."""
    srdf = resolved.srdf
    whole = {j.name for j in by_name.values()}
    in_group = whole if state.group is None else set(resolved.groups[state.group])
    canonical: dict[str, tuple[float, ...]] = {}
    written: dict[str, float] = {}
    ok = True
    of = "the robot" if state.group is None else f"group '{state.group}'"
    label = f"state '{state.name}' of {of}"
    for given in state.values:
        name = resolved.names.get(given.joint)
        if name == "":  # a virtual joint that is no joint of the robot (a fixed one)
            continue
        if name is None or by_name[name].kind is JointKind.FIXED:
            problem = (
                f"joint '{given.joint}', which the robot does not have"
                + did_you_mean(given.joint, resolved.names)
                if name is None
                else f"joint '{given.joint}', which is fixed"
            )
            found.append(
                finding(
                    "srdf-ignored",
                    name,
                    f"{label} gives a value to {problem} (skipped, as MoveIt and Pinocchio "
                    "skip it)",
                    given.line,
                    srdf.path,
                )
            )
            continue
        joint = by_name[name]

        def say(code: str, problem: str, name: str = name, line: int | None = given.line) -> None:
            found.append(finding(code, name, f"{label}: {problem}", line, srdf.path))

        numbers = given.values
        shown = " ".join(f"{v:.8g}" for v in numbers)
        if name not in in_group and joint.nq > 0 and state.group not in resolved.broken:
            say(
                "pose-joint-outside-group",
                f"joint '{given.joint}' is not in the group (MoveIt ignores its value; "
                "Pinocchio sets it)",
            )
        sizes = (1,) if joint.kind is JointKind.MIMIC else _SIZES.get(joint.kind)
        if sizes is None:
            say(
                "pose-out-of-limits",
                f"joint '{given.joint}' is {joint.kind.value}, for which SRDF has no values",
            )
            ok = False
            continue
        if len(numbers) not in sizes:
            counts = " or ".join(str(n) for n in sizes)
            say(
                "pose-out-of-limits",
                f"joint '{given.joint}' ({joint.kind.value}) takes {counts} number(s), "
                f"not {len(numbers)} ({shown})",
            )
            ok = False
            continue
        if not all(math.isfinite(v) for v in numbers):
            say("pose-out-of-limits", f"joint '{given.joint}' is {shown}: not finite")
            ok = False
            continue
        if joint.kind is JointKind.MIMIC:
            written[name] = numbers[0]
            continue
        written[name] = numbers[0]
        value = _canonical(joint.kind, numbers, say, given.joint)
        canonical[name] = value
        limits = joint.limits
        if limits is not None and joint.kind in _SCALAR:
            for low, high, number in zip(limits.lower, limits.upper, numbers, strict=False):
                if not (low - SLACK <= number <= high + SLACK):
                    say(
                        "pose-out-of-limits",
                        f"joint '{given.joint}' is {shown}, outside [{low:.8g}, {high:.8g}] "
                        f"{limits.unit}",
                    )
    _mimic_findings(resolved, state, by_name, written, found, label)
    return canonical, ok


def _canonical(
    kind: JointKind, numbers: tuple[float, ...], tell: Say, joint: str
) -> tuple[float, ...]:
    """A joint's canonical coordinates from the numbers a state gives it."""
    if kind in _SCALAR or kind in (JointKind.CONTINUOUS, JointKind.TRANSLATION):
        return numbers
    if kind is JointKind.SPHERICAL:  # Pinocchio's x y z w; a ball's range is not checked
        qx, qy, qz, qw = numbers
        _unit(qx, qy, qz, qw, tell, joint)
        return (qw, qx, qy, qz)
    if kind is JointKind.PLANAR:
        x, y, *rest = numbers
        angle = rest[0] if len(rest) == 1 else _angle(rest[0], rest[1], tell, joint)
        return (x, y, angle)
    x, y, z, qx, qy, qz, qw = numbers  # floating: MoveIt's and Pinocchio's order
    _unit(qx, qy, qz, qw, tell, joint)
    return (x, y, z, qw, qx, qy, qz)


def _unit(qx: float, qy: float, qz: float, qw: float, tell: Say, joint: str) -> None:
    """Say when a quaternion is zero (no rotation) or not unit."""
    norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    if norm == 0.0:
        tell("pose-out-of-limits", f"joint '{joint}' has quaternion (0, 0, 0, 0): no rotation")
    elif abs(norm - 1.0) > UNIT_SLACK:
        tell(
            "pose-not-unit",
            f"joint '{joint}' has quaternion (x {qx:g}, y {qy:g}, z {qz:g}, w {qw:g}) of norm "
            f"{norm:.6g}, not 1",
        )


def _angle(c: float, s: float, say: Say, joint: str) -> float:
    norm = math.hypot(c, s)
    if abs(norm - 1.0) > UNIT_SLACK:
        say("pose-not-unit", f"joint '{joint}' has (cos, sin) = ({c:g}, {s:g}) of norm {norm:.6g}")
    return math.atan2(s, c)


def _mimic_findings(
    resolved: Resolved,
    state: GroupState,
    by_name: Mapping[str, JointReport],
    written: Mapping[str, float],
    found: list[Diagnostic],
    label: str,
) -> None:
    lines = {resolved.names.get(v.joint): v.line for v in state.values}
    for name, value in written.items():
        mimic = by_name[name].mimic
        if mimic is None or mimic.joint not in written:
            continue
        wanted = mimic.multiplier * written[mimic.joint] + mimic.offset
        if math.isfinite(wanted) and abs(value - wanted) > SLACK:
            found.append(
                finding(
                    "pose-mimic-inconsistent",
                    name,
                    f"{label}: joint '{printable(name)}' is {value:.8g}, but it follows "
                    f"'{mimic.joint}' ({mimic.multiplier:g} x {written[mimic.joint]:.8g} + "
                    f"{mimic.offset:.8g} = {wanted:.8g})",
                    lines.get(name),
                    resolved.srdf.path,
                )
            )
