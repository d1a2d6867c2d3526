"""MoveIt's joint_limits.yaml applied to a robot as MoveIt 2 applies it.

MoveIt 2's ``RobotModelLoader::configure`` (moveit_ros/planning/robot_model_loader)
starts from each variable's bounds as its ``RobotModel`` takes them from the URDF (a
revolute or prismatic joint with a ``<safety_controller>``: its soft limits within its
limits, `moveit_bounds`; a velocity its magnitude, no limit at 0) and, for each
variable ``NAME`` of the model, reads ``robot_description_planning.joint_limits.NAME.*``:

- ``max_position`` and ``min_position``, each on its own: where given, and where
  ``canSpecifyPosition`` allows (not a continuous joint, not a planar joint's angle nor
  a floating joint's rotation), the value replaces the URDF's, narrower or wider, and
  the variable is bounded; ``has_position_limits`` is not read;
- ``has_velocity_limits`` (acceleration, jerk): where given, it says whether the
  variable is bounded; where true, ``max_velocity`` replaces the URDF's (not given: an
  error is logged and the URDF's value, 0 for acceleration and jerk, stays).
- a value written as an integer is, to ``move_group`` (which declares the file's
  parameters as written), no double: the error is logged and neither it nor the joint's
  keys read after it are taken (`cspace._formats.joint_limits.reader.MOVEIT_ORDER`).

So the report's position limits are those: `apply_limits` gives the robot's
description with the YAML's positions put in (the analysis makes the C-space of them),
the report's ``limits_file`` (every limit with its origin) and the findings that compare
the two files. Only joints of one coordinate take limits here (a URDF's planar and
floating joints are MoveIt's ``NAME/x`` variables, which cspace does not bound).
"""

import math
import sys

from cspace._findings import Diagnostic, finding
from cspace._formats.joint_limits.reader import JointEntry, LimitsFile
from cspace._formats.shared.description import JointSpec, RobotDescription
from cspace._joint_kind import JointKind
from cspace._record import NamedTuple
from cspace._reports.limits import Bound, JointLimitsView, LimitsSummary

ONE_COORDINATE = (JointKind.REVOLUTE, JointKind.CONTINUOUS, JointKind.PRISMATIC)

DEGREE_TURNS = 2
"""A revolute position in the YAML beyond this many turns (4*pi, 12.57 rad) is degrees:
robots' multi-turn joints stay within two turns either way (a UR arm's +-2*pi, an
industrial wrist's +-450 degrees), while a limit in degrees from 13 up exceeds it."""

DEGREE_VELOCITY = 50.0
"""A revolute or continuous joint's ``max_velocity`` above this (rad/s, about 480 rpm) is
degrees a second: arms' joints move at up to about 2*pi rad/s and legged robots' at up
to about 30, while a speed in degrees a second (a UR's 180, a Panda's 150) exceeds it."""

MAX_LIMIT_FINDINGS = 200
"""Most findings one joint_limits.yaml adds to a report (the last says how many more)."""

POSITION_CODES = frozenset(
    {"limits-empty", "joint-locked", "revolute-ambiguous-range", "multi-turn", "limits-in-degrees"}
)
"""The analysis' findings about a joint's position limits: said on the YAML's line
when the YAML gave them."""


class Applied(NamedTuple):
    """A joint_limits.yaml applied to a robot.

    Attributes:
        description: The robot's description with MoveIt's position limits.
        summary: The report's ``limits_file``.
        findings: The file's own findings and those comparing it with the robot's.
        lines: For each joint whose position limits the YAML gave, the YAML's line.
    """

    description: RobotDescription
    summary: LimitsSummary
    findings: tuple[Diagnostic, ...]
    lines: dict[str, int]


def apply_limits(description: RobotDescription, robot: str, limits: LimitsFile) -> Applied:
    """Apply ``limits`` (read from its file) to the robot read from ``robot`` (see module)."""
    said = _Said(robot, limits.path)
    said.found.extend(limits.findings)
    entries = {e.name: e for e in limits.joints}
    joints, views, lines = [], [], {}
    for spec in map(moveit_bounds, description.joints):
        entry = entries.get(spec.name)
        if spec.kind not in ONE_COORDINATE:
            if entry is not None:
                said.unusable(spec, entry)
            joints.append(spec)
            continue
        applied, line = _positions(spec, entry, said)
        if line is not None:
            lines[spec.name] = line
        joints.append(applied)
        views.append(_view(spec, entry, said))
    named = {spec.name: spec for spec in description.joints}
    for entry in limits.joints:
        joint = entry.name.rpartition("/")[0]
        if entry.name not in named and joint in named:  # MoveIt's NAME/x of a planar joint
            said.unusable(named[joint], entry)
        elif entry.name not in named:
            said.add(
                "limits-file-unknown-joint",
                None,
                f"the joint limits name joint '{entry.name}', which the robot does not have: "
                "MoveIt skips it",
                entry.line,
            )
    scaling = limits.scaling
    velocity = scaling.get("default_velocity_scaling_factor")
    acceleration = scaling.get("default_acceleration_scaling_factor")
    summary = LimitsSummary(
        limits.path,
        None if velocity is None else velocity.value,
        None if acceleration is None else acceleration.value,
        tuple(views),
    )
    return Applied(description.replace(joints=tuple(joints)), summary, said.capped(), lines)


def moveit_bounds(spec: JointSpec) -> JointSpec:
    """The joint with the position bounds MoveIt's ``RobotModel`` gives it.

    A revolute or prismatic joint with a ``<safety_controller>`` is bounded by its soft
    limits within its limits (``jointBoundsFromURDF``): the larger lower bound, the
    smaller upper one.
    """
    if spec.soft is None or spec.kind not in (JointKind.REVOLUTE, JointKind.PRISMATIC):
        return spec
    if not spec.limited or len(spec.lower) != 1:
        return spec
    low, high = spec.soft
    return spec._replace(lower=(max(spec.lower[0], low),), upper=(min(spec.upper[0], high),))


def relocated(diagnostics: tuple[Diagnostic, ...], applied: Applied) -> tuple[Diagnostic, ...]:
    """The analysis' findings on position limits the YAML gave, put on the YAML's line.

    ``limits-in-degrees`` of a joint the YAML's ``limits-file-degrees`` covers is
    dropped: one finding says it.
    """
    degrees = {d.joint for d in applied.findings if d.code == "limits-file-degrees"}
    out = []
    for d in diagnostics:
        line = applied.lines.get(d.joint or "")
        if line is None or d.code not in POSITION_CODES:
            out.append(d)
        elif not (d.code == "limits-in-degrees" and d.joint in degrees):
            out.append(d._replace(line=line, file=applied.summary.file))
    return (*out, *applied.findings)


class _Said:
    """The findings made, each on its line in the YAML."""

    def __init__(self, robot: str, path: str) -> None:
        self.robot, self.path = robot, path
        self.found: list[Diagnostic] = []

    def add(self, code: str, joint: str | None, message: str, line: int | None) -> None:
        self.found.append(finding(code, joint, message, line, self.path))

    def capped(self) -> tuple[Diagnostic, ...]:
        if len(self.found) <= MAX_LIMIT_FINDINGS:
            return tuple(self.found)
        more = len(self.found) - MAX_LIMIT_FINDINGS + 1
        kept = self.found[: MAX_LIMIT_FINDINGS - 1]
        note = f"{more:,} more findings of the joint limits file are not listed"
        return (*kept, finding("findings-truncated", None, note, None, self.path))

    def unusable(self, spec: JointSpec, entry: JointEntry) -> None:
        why = (
            "a fixed joint has no variable in MoveIt"
            if spec.kind is JointKind.FIXED
            else f"MoveIt's variables of a {spec.type} joint are '{spec.name}/...', "
            "which cspace does not bound"
        )
        self.add(
            "limits-file-unusable",
            spec.name,
            f"the joint limits give {spec.type} joint '{spec.name}' limits: {why}",
            entry.line,
        )

    def compare(
        self, spec: JointSpec, what: str, urdf: float, yaml: float, line: int, wider: bool
    ) -> None:
        """A finding when the YAML's value ``yaml`` of ``what`` is not the URDF's."""
        if math.isclose(urdf, yaml, rel_tol=1e-12, abs_tol=1e-12):
            return
        code = "limits-file-widens" if wider else "limits-file-differs"
        verb = "allows more than" if wider else "narrows"
        where = f":{spec.limit_line}" if spec.limit_line is not None else ""
        self.add(
            code,
            spec.name,
            f"joint '{spec.name}': the joint limits' {what} {yaml:g} ({self.path}:{line}) "
            f"{verb} the robot file's {urdf:g} ({self.robot}{where}): MoveIt plans with "
            f"{yaml:g}, and controllers reading the robot file with {urdf:g}",
            line,
        )


def _positions(
    spec: JointSpec, entry: JointEntry | None, said: _Said
) -> tuple[JointSpec, int | None]:
    """The joint with MoveIt's position limits, and the YAML's line when it gave them."""
    if entry is None:
        return spec, None
    low, high = entry.taken("min_position"), entry.taken("max_position")
    if low is None and high is None:
        return spec, None
    line = (low or high).line  # type: ignore[union-attr]
    if spec.kind is JointKind.CONTINUOUS:
        said.add(
            "limits-file-unusable",
            spec.name,
            f"the joint limits give continuous joint '{spec.name}' position limits, which "
            "MoveIt refuses ('Cannot specify position limits for continuous joint'): it "
            "turns freely",
            line,
        )
        return spec, None
    if spec.kind is JointKind.REVOLUTE:
        for given in (low, high):
            if given is not None and abs(given.value) > DEGREE_TURNS * 2 * math.pi:
                said.add(
                    "limits-file-degrees",
                    spec.name,
                    f"joint '{spec.name}': position limit {given.value:g} is "
                    f"{abs(given.value) / (2 * math.pi):.1f} turns in rad: it looks like "
                    f"degrees ({math.radians(given.value):.4g} rad), and MoveIt reads rad",
                    given.line,
                )
    lower, upper = spec.lower, spec.upper
    if lower and len(lower) == len(upper) == 1:
        if low is not None:
            said.compare(spec, "min_position", lower[0], low.value, low.line, low.value < lower[0])
        if high is not None:
            said.compare(
                spec, "max_position", upper[0], high.value, high.line, high.value > upper[0]
            )
    new_lower = (low.value,) if low is not None else (lower[:1] or (-math.inf,))
    new_upper = (high.value,) if high is not None else (upper[:1] or (math.inf,))
    missing = tuple(
        b
        for b, given in (("lower", low), ("upper", high))
        if b in spec.bounds_missing and not given
    )
    return (
        spec._replace(
            lower=new_lower,
            upper=new_upper,
            limits_defaulted=spec.limits_defaulted and low is None and high is None,
            bounds_missing=missing,
        ),
        line,
    )


def _view(spec: JointSpec, entry: JointEntry | None, said: _Said) -> JointLimitsView:
    """The joint's limits and where each came from."""
    urdf_line = spec.limit_line

    def position(key: str, values: tuple[float, ...]) -> Bound:
        given = None if entry is None else entry.taken(key)
        if spec.kind is JointKind.CONTINUOUS:
            return Bound(None, "robot", None)
        own = (values[0], urdf_line) if values else (None, None)
        if given is not None:
            return Bound(given.value, "limits", given.line, own)
        return Bound(own[0], "robot", own[1])

    rates = dict(spec.rates)

    def rate(name: str) -> Bound:
        urdf = rates.get(name)
        taken = urdf if urdf is None or name != "velocity" else _moveit_velocity(urdf, entry)
        own = (taken, urdf_line if taken is not None else None)
        given = None if entry is None else entry.rate(name)
        if given is not None:
            turning = spec.kind in (JointKind.REVOLUTE, JointKind.CONTINUOUS)
            if name == "velocity" and turning and given.value > DEGREE_VELOCITY:
                said.add(
                    "limits-file-degrees",
                    spec.name,
                    f"joint '{spec.name}': max_velocity {given.value:g} rad/s is "
                    f"{given.value * 60 / (2 * math.pi):.0f} rpm: it looks like degrees a "
                    f"second ({math.radians(given.value):.4g} rad/s), and MoveIt reads rad/s",
                    given.line,
                )
            if urdf is not None and name in ("velocity", "effort"):
                urdf = abs(urdf)  # as ros2_control's getJointLimits reads it
                said.compare(spec, f"max_{name}", urdf, given.value, given.line, given.value > urdf)
            return Bound(given.value, "limits", given.line, own)
        off = None if entry is None else entry.switched_off(name)
        if off is not None:
            return Bound(None, "limits", off, own)
        return Bound(own[0], "robot", own[1])

    return JointLimitsView(
        spec.name,
        position("min_position", spec.lower),
        position("max_position", spec.upper),
        rate("velocity"),
        rate("acceleration"),
        rate("jerk"),
        rate("effort"),
    )


def _moveit_velocity(urdf: float, entry: JointEntry | None) -> float | None:
    """The URDF's velocity limit as MoveIt 2 takes it, or None for none.

    ``jointBoundsFromURDF`` keeps ``fabs(velocity)`` and bounds the variable only when
    that is above machine epsilon (a CAD exporter's ``velocity="0"`` is no limit to
    MoveIt, though ros2_control holds the joint to it); ``has_velocity_limits: true``
    without a ``max_velocity`` bounds it at that magnitude all the same.
    """
    speed = abs(urdf)
    if speed > sys.float_info.epsilon:
        return speed
    key = "has_velocity_limits"
    flag = None if entry is None or key in entry.unread else entry.flags.get(key)
    return speed if flag is not None and flag[0] else None
