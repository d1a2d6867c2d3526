"""The report's ``limits_file``: the limits MoveIt plans with, each with where it came from.

Present only when a joint_limits.yaml was read with the robot (``--limits``). For each
joint of one coordinate (revolute, continuous, prismatic, and mimic joints of them), in
the report's joint order: its lower and upper position limits (those of the report's
joint, which MoveIt plans with) and its velocity, acceleration, jerk and effort limits,
each a `Bound`: the value (None: no limit), ``"robot"`` (the robot file) or
``"limits"`` (the YAML), and the line in that file.
"""

from collections.abc import Mapping
from typing import Any

from cspace._record import NamedTuple

KINDS = ("lower", "upper", "velocity", "acceleration", "jerk", "effort")
"""The limits of each joint, in order."""

ORIGINS = ("robot", "limits")
"""Where a limit comes from: the robot file, or the joint_limits.yaml."""


class Bound(NamedTuple):
    """One limit.

    Attributes:
        value: Its value (None: no limit).
        origin: Where it comes from (`ORIGINS`).
        line: Its line there, or None.
        replaced: For a limit the joint_limits.yaml gives (or switches off), the robot
            file's it replaces, as (value, line) (a value None: the robot file has none);
            None otherwise.
    """

    value: float | None
    origin: str
    line: int | None
    replaced: tuple[float | None, int | None] | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON form (``replaced`` only for a limit from the joint_limits.yaml)."""
        out: dict[str, Any] = {"value": self.value, "from": self.origin, "line": self.line}
        if self.replaced is not None:
            out["replaced"] = {"value": self.replaced[0], "line": self.replaced[1]}
        return out

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "Bound":
        """The bound of a JSON form."""
        value, replaced = document["value"], document.get("replaced")
        was = None
        if replaced is not None:
            number = replaced["value"]
            was = (None if number is None else float(number), replaced["line"])
        number = None if value is None else float(value)
        return cls(number, str(document["from"]), document["line"], was)

    def robot_file(self) -> "Bound":
        """The robot file's own limit: this one, or the one it replaces."""
        if self.origin == "robot" or self.replaced is None:
            return self
        return Bound(self.replaced[0], "robot", self.replaced[1])


class JointLimitsView(NamedTuple):
    """One joint's limits as MoveIt plans with them (see the module).

    Each a `Bound`, in SI units of the joint's coordinate: a revolute or continuous
    joint's in rad, rad/s, rad/s^2, rad/s^3 and N m, a prismatic joint's in m, m/s,
    m/s^2, m/s^3 and N (a mimic joint's as its own type's). ``velocity`` is a magnitude,
    as MoveIt reads it (the same bound both ways).

    Attributes:
        joint: The joint's name.
        lower: Its lower position limit.
        upper: Its upper position limit.
        velocity: Its speed limit.
        acceleration: Its acceleration limit.
        jerk: Its jerk limit.
        effort: Its effort (torque or force) limit.
    """

    joint: str
    lower: Bound
    upper: Bound
    velocity: Bound
    acceleration: Bound
    jerk: Bound
    effort: Bound

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"joint": self.joint} | {k: getattr(self, k).to_dict() for k in KINDS}

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "JointLimitsView":
        """The joint's limits of a JSON form."""
        bounds = [Bound.from_dict(document[k]) for k in KINDS]
        return cls(str(document["joint"]), *bounds)


class LimitsSummary(NamedTuple):
    """The joint_limits.yaml read with the robot, and every joint's limits.

    Attributes:
        file: The YAML, as named.
        velocity_scaling: Its ``default_velocity_scaling_factor``, or None.
        acceleration_scaling: Its ``default_acceleration_scaling_factor``, or None.
        joints: Each joint of one coordinate, in the report's order.
    """

    file: str
    velocity_scaling: float | None
    acceleration_scaling: float | None
    joints: tuple[JointLimitsView, ...]

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {
            "file": self.file,
            "velocity_scaling": self.velocity_scaling,
            "acceleration_scaling": self.acceleration_scaling,
            "joints": [j.to_dict() for j in self.joints],
        }

    @classmethod
    def from_dict(cls, document: Mapping[str, Any]) -> "LimitsSummary":
        """The summary of a JSON form."""

        def scale(key: str) -> float | None:
            value = document[key]
            return None if value is None else float(value)

        return cls(
            str(document["file"]),
            scale("velocity_scaling"),
            scale("acceleration_scaling"),
            tuple(JointLimitsView.from_dict(j) for j in document["joints"]),
        )

    def by_joint(self) -> dict[str, JointLimitsView]:
        """Each joint's limits by name."""
        return {j.joint: j for j in self.joints}
