"""Findings: what a robot file can still be analysed with, each with a stable code.

The record (`Diagnostic`), its severity, and the one table of codes
(`CODES`), used by every layer that finds something: the format readers, the
analysis (`diagnostics` lists every code and its meaning) and the
report.
"""

from enum import Enum
from typing import Any

from cspace._record import NamedTuple
from cspace.errors import printable


class Severity(str, Enum):
    """How serious a finding is. Errors make ``cspace inspect`` exit 1."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


class Diagnostic(NamedTuple):
    """One finding about a file that could still be analysed.

    Attributes:
        severity: error, warning or info.
        code: Stable identifier, e.g. ``"joint-locked"``; usable with ``--ignore``.
        joint: The joint it is about, or None for the whole robot.
        message: One sentence a person understands.
        line: The line of the element it is about in the file (the ``<limit>`` or the
            ``<axis>`` when it is about one, else the joint's), or None.
        file: The file ``line`` is in when it is not the robot file (an SRDF), or None.
    """

    severity: Severity
    code: str
    joint: str | None
    message: str
    line: int | None = None
    file: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of this finding."""
        return {
            "severity": self.severity.value,
            "code": self.code,
            "joint": self.joint,
            "message": self.message,
            "line": self.line,
        } | ({} if self.file is None else {"file": self.file})


CODES: dict[str, Severity] = {
    "limits-empty": Severity.ERROR,
    "limits-not-finite": Severity.ERROR,
    "axis-invalid": Severity.ERROR,
    "number-invalid": Severity.ERROR,
    "joint-locked": Severity.WARNING,
    "continuous-has-limits": Severity.WARNING,
    "mimic-limits-contradict": Severity.WARNING,
    "mimic-not-periodic": Severity.WARNING,
    "mimic-ignored": Severity.WARNING,
    "revolute-ambiguous-range": Severity.WARNING,
    "axis-normalized": Severity.WARNING,
    "multi-turn": Severity.INFO,
    "euler-coordinates": Severity.INFO,
    "axis-default": Severity.INFO,
    "root-joint-added": Severity.INFO,
    "mimic-kept-free": Severity.INFO,
    "ball-range-whole": Severity.INFO,
    "parser-message": Severity.INFO,
    "findings-truncated": Severity.INFO,
    "equality-joint": Severity.INFO,
    "equality-mimic": Severity.INFO,
    "equality-weld": Severity.INFO,
    "equality-connect": Severity.INFO,
    "equality-tendon": Severity.INFO,
    "name-made-up": Severity.INFO,
    "xml-version": Severity.INFO,
    "limits-in-degrees": Severity.WARNING,
    "limits-sentinel": Severity.WARNING,
    "pose-out-of-limits": Severity.ERROR,
    "pose-not-unit": Severity.WARNING,
    "pose-ctrl-out-of-range": Severity.WARNING,
    "pose-mimic-inconsistent": Severity.WARNING,
    "pose-joint-outside-group": Severity.INFO,
    "pose-equality-violated": Severity.WARNING,
    "pose-partial": Severity.WARNING,
    "srdf-ignored": Severity.WARNING,
    "joint-left-out": Severity.WARNING,
    "srdf-virtual-joint": Severity.INFO,
    "srdf-not-found": Severity.INFO,
    "srdf-other-robot": Severity.WARNING,
    "joint-passive": Severity.INFO,
    "poses-not-checked": Severity.INFO,
    "limits-unset": Severity.WARNING,
    "range-looks-like-radians": Severity.WARNING,
    "limit-bound-missing": Severity.WARNING,
    "root-joint-suggested": Severity.INFO,
    "planar-root": Severity.INFO,
    "spatial-root": Severity.INFO,
    "sdf-link-floats": Severity.INFO,
    "read-beyond-folder": Severity.INFO,
    "xml-lenient": Severity.INFO,
    "world-undeclared": Severity.INFO,
    "drake-mjcf-differs": Severity.INFO,
    "drake-urdf-differs": Severity.INFO,
    "closure-grubler-differs": Severity.INFO,
    "closure-singular": Severity.INFO,
    "closure-rigid": Severity.WARNING,
    "closure-shaky": Severity.WARNING,
    "closure-limits-ignored": Severity.WARNING,
    "closure-partial": Severity.WARNING,
    "closure-not-assembled": Severity.ERROR,
    "closure-invalid": Severity.ERROR,
    "closure-not-analysed": Severity.WARNING,
    "closure-chart-invalid": Severity.WARNING,
    "closure-chart-singular": Severity.INFO,
    "closure-whole-robot": Severity.INFO,
    "pose-not-closed": Severity.WARNING,
    "actuator-ctrlrange-exceeds": Severity.WARNING,
    "actuator-joint-unlimited": Severity.WARNING,
    "actuator-order": Severity.INFO,
    "pybullet-mimic-free": Severity.WARNING,
    "pybullet-floating-fixed": Severity.WARNING,
    "ros2-control-unknown-joint": Severity.ERROR,
    "ros2-control-fixed-joint": Severity.ERROR,
    "ros2-control-mimic-commanded": Severity.ERROR,
    "ros2-control-invalid": Severity.ERROR,
    "ros2-control-number-invalid": Severity.ERROR,
    "ros2-control-bounds-exceed": Severity.WARNING,
    "ros2-control-bounds-differ": Severity.WARNING,
    "ros2-control-continuous-bounded": Severity.WARNING,
    "limits-file-differs": Severity.INFO,
    "limits-file-widens": Severity.WARNING,
    "limits-file-unknown-joint": Severity.WARNING,
    "limits-file-unusable": Severity.WARNING,
    "limits-file-negative": Severity.ERROR,
    "limits-file-missing-value": Severity.WARNING,
    "limits-file-degrees": Severity.WARNING,
    "limits-file-ignored": Severity.INFO,
    "limits-file-integer": Severity.WARNING,
    "limits-file-scaling": Severity.WARNING,
    "limits-file-not-found": Severity.INFO,
    "collision-disabled-but-reachable": Severity.ERROR,
    "collision-always": Severity.ERROR,
    "collision-at-default": Severity.WARNING,
    "collision-unknown-link": Severity.WARNING,
    "collision-filter-always": Severity.WARNING,
    "collision-filtered-reachable": Severity.WARNING,
    "collision-pose": Severity.WARNING,
    "collision-skipped": Severity.ERROR,
    "collision-held": Severity.WARNING,
}
"""Every diagnostic code and its severity."""

POSE_CODES = frozenset(
    {
        "pose-out-of-limits",
        "pose-not-unit",
        "pose-ctrl-out-of-range",
        "pose-mimic-inconsistent",
        "pose-joint-outside-group",
        "pose-equality-violated",
        "pose-partial",
        "pose-not-closed",
    }
)
"""Findings about a pose the file stores, not about its C-space: an error among them
fails ``cspace check`` but leaves the space defined (``ConfigurationSpace`` is built)."""

CONTROL_CODES = frozenset(code for code in CODES if code.startswith("ros2-control-"))
"""Findings on what a URDF's ``<ros2_control>`` says of the robot's joints, not on its
C-space: as for `POSE_CODES`, an error among them fails ``cspace check`` but leaves the
space defined."""

LIMITS_FILE_CODES = frozenset(code for code in CODES if code.startswith("limits-file-"))
"""Findings on a joint_limits.yaml's own entries (a negative velocity, a key MoveIt does not
read), not on the C-space, whose position limits the analysis judges: as for `POSE_CODES`,
an error among them fails ``cspace check`` but leaves the space defined."""

BESIDE_CODES = POSE_CODES | CONTROL_CODES | LIMITS_FILE_CODES
"""Findings beside the C-space (stored poses, ``<ros2_control>``, joint_limits.yaml): an
error among them fails ``cspace check`` but leaves the space defined."""

COLLISION_CODES = frozenset(code for code in CODES if code.startswith("collision-"))
"""Findings of ``cspace collisions`` (self-collision against the SRDF's, MuJoCo's or
PhysX's matrix), made only by that command: never in an ``inspect`` report."""

DRAKE_CODES = frozenset({"drake-mjcf-differs", "drake-urdf-differs"})
"""Findings on where Drake's model of the file is not its own tool's: the Drake
convention carries them (``DrakeLayout.findings``) and ``cspace convert`` repeats them."""

MEANINGS: dict[str, str] = {
    "limits-empty": "lower > upper: the joint's interval is empty",
    "limits-not-finite": "a limit (or mimic number) is NaN or infinite",
    "axis-invalid": "the joint axis is zero or not finite",
    "number-invalid": "another number is NaN, infinite, or a negative magnitude",
    "joint-locked": "lower == upper: the joint cannot move (dimension 0)",
    "continuous-has-limits": "a continuous joint gives limits, which URDF ignores",
    "mimic-limits-contradict": "the leader's range, mapped, leaves the mimic's limits",
    "mimic-not-periodic": "a mimic of a joint turning freely, by a multiplier not whole",
    "mimic-ignored": "a <mimic> on a joint that is not one-coordinate (ignored)",
    "revolute-ambiguous-range": "limits exactly ±pi or spanning exactly 2*pi",
    "axis-normalized": "the axis is not a unit vector (it is normalised)",
    "multi-turn": "a revolute joint's limits span more than one turn",
    "euler-coordinates": "Pinocchio keeps this joint in Euler angles (singular)",
    "axis-default": "no axis given: (1, 0, 0) assumed, as URDF specifies",
    "root-joint-added": "a root joint was added above the root link",
    "mimic-kept-free": "Pinocchio could not keep mimic joints dependent",
    "ball-range-whole": "a ball joint's range reaches pi: it limits no rotation",
    "parser-message": "Pinocchio's parser printed something while loading",
    "findings-truncated": "more than 10,000 findings: the least severe are not listed",
    "equality-joint": "MJCF <equality><joint>: a joint held, or tied by a polynomial",
    "equality-mimic": "MJCF <equality><joint>, linear: a mimic joint, as URDF's <mimic>",
    "equality-weld": "MJCF <equality><weld>: two bodies welded, a closed chain",
    "equality-connect": "MJCF <equality><connect>: two bodies joined at a point",
    "equality-tendon": "MJCF <equality><tendon>: tendon lengths coupled",
    "name-made-up": "MJCF: joints or bodies without a name, named by cspace",
    "xml-version": "the file declares an XML version other than 1.0 (read as 1.0)",
    "limits-in-degrees": "revolute limits beyond 2*pi that look like degrees",
    "limits-sentinel": "a limit of magnitude 1e4 or more: a stand-in for 'no limit'",
    "pose-out-of-limits": "a stored pose (keyframe, SRDF state, ...) outside the space",
    "pose-not-unit": "a stored pose's quaternion (or cos-sin pair) is not unit",
    "pose-ctrl-out-of-range": "a keyframe's ctrl outside an actuator's ctrlrange (clamped)",
    "pose-mimic-inconsistent": "a keyframe's mimic follower off its leader's relation",
    "pose-joint-outside-group": "an SRDF group state gives a joint not in its group",
    "pose-equality-violated": "a keyframe off a joint equality (one held, or a polynomial)",
    "pose-partial": "a keyframe writes fewer qpos numbers than nq: MuJoCo fills from qpos0",
    "srdf-ignored": "an SRDF name the robot lacks, or a value for a fixed joint: skipped",
    "joint-left-out": "USD: a joint of a body to itself, or closing a loop as no cut can, left out",
    "srdf-virtual-joint": "the SRDF's virtual joint is the root joint cspace adds",
    "srdf-not-found": "--srdf auto found no SRDF of the robot: where it looked",
    "joint-passive": "the SRDF marks the joint passive: held in every group's C-space",
    "poses-not-checked": "stored poses beyond what cspace checks (or lists), counted",
    "limits-unset": "lower == upper == 0 on a moving joint: a stand-in for 'not given'",
    "range-looks-like-radians": "MJCF: a range in degrees (the default) that looks like rad",
    "limit-bound-missing": "a <limit> gives one bound, not the other, which URDF reads as 0",
    "srdf-other-robot": "the SRDF read names another robot than the URDF",
    "root-joint-suggested": "legs or wheels on a root link bolted to the world",
    "planar-root": "two slides and a hinge that together give a body a pose in a plane",
    "spatial-root": "three slides and a ball (or three hinges) that give a body a pose",
    "sdf-link-floats": "SDF: a link no joint holds, in a model not static, floats",
    "read-beyond-folder": "MJCF: files read beyond the file's folder, within its project",
    "xml-lenient": "not XML, but urdfdom reads it: a late declaration, NULs after",
    "world-undeclared": "URDF: a joint names link 'world', undeclared: Drake's world",
    "drake-mjcf-differs": "MJCF: Drake's parser places bodies with several joints elsewhere",
    "drake-urdf-differs": "URDF: Drake's parser moves a planar or floating joint otherwise",
    "closure-grubler-differs": "closed chains: dependent equations; Grübler's count is wrong",
    "closure-singular": "closed chains: a configuration where the constraints' rank drops",
    "closure-rigid": "closed chains: the loops leave the mechanism no motion (mobility 0)",
    "closure-shaky": "closed chains: motions to first order that the mechanism does not make",
    "closure-limits-ignored": "closed chains: a joint that closes a loop has limits, not held",
    "closure-partial": "closed chains: MJCF joint or tendon equalities the closure does not hold",
    "closure-not-assembled": "closed chains: no configuration tried closes every loop",
    "closure-invalid": "closed chains: a constraint that cannot be evaluated (left out)",
    "closure-not-analysed": "closed chains: too large, or no model, to look for configurations",
    "closure-chart-invalid": "closed chains: the actuated joints are not coordinates of it",
    "closure-chart-singular": "closed chains: actuated joints fail as coordinates at some samples",
    "closure-whole-robot": "closed chains: reported for the whole robot, not for an SRDF group",
    "pose-not-closed": "a stored pose that does not close the mechanism's loops",
    "actuator-ctrlrange-exceeds": "MJCF: a position actuator's ctrlrange exceeds its joint's range",
    "actuator-joint-unlimited": "MJCF: a position actuator's ctrlrange limits an unlimited joint",
    "actuator-order": "MJCF: the actuators (ctrl) are not in the order of their joints (qpos)",
    "pybullet-mimic-free": "PyBullet ignores <mimic>: the follower moves freely there",
    "pybullet-floating-fixed": "PyBullet's URDF importer makes a floating joint fixed",
    "ros2-control-unknown-joint": "<ros2_control> names a joint the URDF lacks: it will not start",
    "ros2-control-fixed-joint": "<ros2_control> names a fixed joint: ros2_control refuses to start",
    "ros2-control-mimic-commanded": "<ros2_control> gives a URDF mimic joint command interfaces",
    "ros2-control-invalid": "a <ros2_control> element ros2_control refuses (no name, unknown tag)",
    "ros2-control-number-invalid": "a <ros2_control> min, max or initial_value that is no number",
    "ros2-control-bounds-exceed": "<ros2_control> position bounds beyond the URDF's limits",
    "ros2-control-bounds-differ": "<ros2_control> position bounds narrower than the URDF's limits",
    "ros2-control-continuous-bounded": "<ros2_control> position bounds on a continuous joint",
    "limits-file-differs": "joint_limits.yaml narrows the URDF's limit: MoveIt plans with it",
    "limits-file-widens": "joint_limits.yaml allows more than the URDF: planner, controller differ",
    "limits-file-unknown-joint": "joint_limits.yaml names a joint the robot lacks: MoveIt skips it",
    "limits-file-unusable": "position limits MoveIt refuses (continuous) or cannot hold (fixed)",
    "limits-file-negative": "a negative max_velocity, max_acceleration, max_jerk or max_effort",
    "limits-file-missing-value": "has_*_limits: true without its max_* value",
    "limits-file-degrees": "a position over two turns or a speed over 50 rad/s: degrees, not rad",
    "limits-file-ignored": "a key of joint_limits.yaml MoveIt 2 does not read",
    "limits-file-integer": "an integer value, which MoveIt 2 refuses for a double parameter",
    "limits-file-scaling": "a default scaling factor outside (0, 1]",
    "limits-file-not-found": "--limits auto found no joint_limits.yaml: where it looked",
    "collision-disabled-but-reachable": "the SRDF disables a link pair that collides in samples",
    "collision-always": "a link pair in collision in 95% of samples or more is checked",
    "collision-at-default": "a checked link pair is in collision at the default configuration",
    "collision-unknown-link": "an SRDF or PhysX filter names a link the robot lacks: it is dropped",
    "collision-filter-always": "MuJoCo or PhysX checks a body pair in contact in 95% of samples",
    "collision-filtered-reachable": "MuJoCo's or PhysX's filters skip a pair that collides",
    "collision-pose": "a stored pose has links in collision",
    "collision-skipped": "collision shapes cspace cannot check: their pairs are left out",
    "collision-held": "a coordinate without finite limits held at neutral: its motion unsampled",
}
"""What each finding code means, in a line (the rules of SARIF output)."""


def finding(
    code: str, joint: str | None, message: str, line: int | None = None, file: str | None = None
) -> Diagnostic:
    """A diagnostic with the severity its code carries; its message is one printable line.

    ``file``: the file ``line`` is in, when not the robot file (an SRDF).
    """
    return Diagnostic(CODES[code], code, joint, printable(message), line, file)
