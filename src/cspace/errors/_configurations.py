"""What can be wrong with configurations, arguments and the requests made of a robot."""

from __future__ import annotations

from collections.abc import Sequence

from cspace._safetext import printable
from cspace.errors._base import CspaceError


class ConfigurationError(CspaceError, ValueError):
    """A configuration (or a batch of them) given to a `ConfigurationSpace` is wrong.

    Attributes:
        coordinate: The coordinate (or joint) it is about, or None.
        row: Index of the offending configuration in a batch (row-major), or None.
    """

    code = "bad-configuration"

    def __init__(self, message: str, *, coordinate: str | None = None, row: int | None = None):
        self.coordinate = coordinate
        self.row = row
        where = "" if row is None else f" (configuration {row})"
        super().__init__(message + where)


class ConfigurationShapeError(ConfigurationError):
    """An array has the wrong shape: its last axis must hold ``expected`` coordinates.

    Attributes:
        expected: Number of coordinates per configuration.
        shape: The shape given.
    """

    code = "configuration-shape"

    def __init__(self, message: str, *, expected: int, shape: tuple[int, ...]) -> None:
        self.expected = expected
        self.shape = shape
        super().__init__(message)


class NonFiniteValueError(ConfigurationError):
    """A coordinate is NaN or infinite."""

    code = "non-finite-value"


class NotUnitQuaternionError(ConfigurationError):
    """A quaternion's norm differs from 1 by more than the tolerance.

    Attributes:
        norm: The norm found.
        tolerance: The tolerance allowed on the norm.
    """

    code = "not-unit-quaternion"

    def __init__(
        self, message: str, *, norm: float, tolerance: float, coordinate: str, row: int | None
    ) -> None:
        self.norm = norm
        self.tolerance = tolerance
        super().__init__(message, coordinate=coordinate, row=row)


class NotARotationError(ConfigurationError):
    """A matrix is not a rotation (not finite, not orthonormal, or a reflection)."""

    code = "not-a-rotation"


class UnknownJointError(ConfigurationError):
    """A name is not a joint with coordinates.

    Attributes:
        valid: The names accepted, in tree order.
    """

    code = "unknown-joint"

    def __init__(self, message: str, *, name: str, valid: Sequence[str]) -> None:
        self.valid = tuple(valid)
        super().__init__(f"{message} (valid: {', '.join(self.valid)})", coordinate=name)


class MissingJointError(ConfigurationError):
    """A mapping lacks joints that have coordinates.

    Attributes:
        missing: The joints missing, in tree order.
    """

    code = "missing-joint"

    def __init__(self, missing: Sequence[str]) -> None:
        self.missing = tuple(missing)
        super().__init__(f"configuration has no value for joint(s): {', '.join(self.missing)}")


class JointValueError(ConfigurationError):
    """A joint's value in a mapping has the wrong form (not a number, wrong length).

    Attributes:
        value: The value given.
    """

    code = "bad-joint-value"

    def __init__(self, message: str, *, joint: str, value: object) -> None:
        self.value = value
        super().__init__(message, coordinate=joint)


class OutOfLimitsError(ConfigurationError):
    """A coordinate lies outside its joint's limits.

    Attributes:
        joint: The joint.
        value: The coordinate's value.
        lower: Its lower bound.
        upper: Its upper bound.
    """

    code = "out-of-limits"

    def __init__(
        self,
        *,
        coordinate: str,
        joint: str,
        value: float,
        lower: float,
        upper: float,
        row: int | None,
    ) -> None:
        self.joint = joint
        self.value = value
        self.lower = lower
        self.upper = upper
        super().__init__(
            f"coordinate '{coordinate}' of joint '{joint}' is {value!r}, outside its limits "
            f"[{lower!r}, {upper!r}]",
            coordinate=coordinate,
            row=row,
        )


class UnboundedSamplingError(ConfigurationError):
    """A coordinate without finite bounds cannot be sampled uniformly.

    Attributes:
        joint: The joint the coordinate belongs to.
    """

    code = "unbounded-sampling"

    def __init__(self, *, coordinate: str, joint: str) -> None:
        self.joint = joint
        super().__init__(
            f"cannot sample joint '{joint}' uniformly: coordinate '{coordinate}' has no finite "
            "bounds; give bounds for it",
            coordinate=coordinate,
        )


class ArgumentError(ConfigurationError):
    """An argument of a configuration operation (or a xacro argument) has a wrong value.

    A count, the interpolation parameter ``t``, a tolerance, a weight, sampling bounds,
    an ``out=`` array that overlaps an input, or a xacro ``NAME:=VALUE`` without ``:=``.

    Attributes:
        argument: The parameter it is about (``"n"``, ``"t"``, ``"tolerance"``, ...), or None.
    """

    code = "bad-argument"

    def __init__(
        self, message: str, *, argument: str | None = None, coordinate: str | None = None
    ) -> None:
        self.argument = argument
        super().__init__(message, coordinate=coordinate)


class ArgumentTypeError(ArgumentError, TypeError):
    """An argument has the wrong type.

    Not a number, not a ``numpy.random.Generator``, not a mapping, or an array whose
    dtype is not real numbers (strings, objects, complex, bool). Also a ``TypeError``.
    """

    code = "bad-argument-type"


class SizeLimitError(ArgumentError, MemoryError):
    """An operation would allocate an array larger than ``cspace.MAX_ARRAY_BYTES``.

    Raised before anything is allocated. Also a ``MemoryError``.

    Attributes:
        what: What asked for the array, e.g. ``"sample(1,000,000,000)"``.
        requested: Bytes the array would take.
        limit: Bytes allowed (``cspace.MAX_ARRAY_BYTES``).
    """

    code = "too-large"

    def __init__(self, what: str, *, requested: int, limit: int) -> None:
        self.what = what
        self.requested = requested
        self.limit = limit
        super().__init__(
            f"{what} would need {_bytes(requested)}, more than the {_bytes(limit)} cspace "
            "allocates at once; ask for fewer or in chunks"
        )


def _bytes(n: int) -> str:
    """A byte count in GiB (or MiB below 1 GiB), one decimal."""
    return f"{n / 2**30:.1f} GiB" if n >= 2**30 else f"{n / 2**20:.1f} MiB"


class ValueOverflowError(ConfigurationError, OverflowError):
    """Finite inputs whose result overflows a double (beyond about 1.8e308).

    Such as a coordinate near 1e308 plus another, or a squared distance of coordinates
    or weights beyond about 1e154. Also an ``OverflowError``.
    """

    code = "value-overflow"


class UnsupportedConfigurationError(CspaceError):
    """A joint whose coordinates the configuration operations do not handle.

    Attributes:
        joint: The joint.
        joint_model: Pinocchio's joint model.
    """

    code = "unsupported-configuration"

    def __init__(self, joint: str, joint_model: str, reason: str) -> None:
        self.joint = joint
        self.joint_model = joint_model
        super().__init__(f"joint '{joint}' ({joint_model}) has no canonical coordinates: {reason}")


class JointMatchError(CspaceError, ValueError):
    """The joints of two sides cannot be matched by name.

    The sides are two robots (``cspace diff --map``) or a robot and another tool's layout
    (a MuJoCo model, a ROS ``JointState`` name list): a name is missing on one side, is
    extra, or names a joint that the other convention cannot hold.

    Attributes:
        joints: The joints it is about, in the order given.
    """

    code = "joint-match"

    def __init__(self, message: str, *, joints: Sequence[str] = ()) -> None:
        self.joints = tuple(joints)
        super().__init__(printable(message))


class InvalidRootJointError(CspaceError):
    """The requested root joint is not one of the supported names.

    Attributes:
        root_joint: What was asked for.
        valid: The accepted names.
    """

    code = "invalid-root-joint"

    def __init__(self, root_joint: str, valid: Sequence[str]) -> None:
        self.root_joint = root_joint
        self.valid = tuple(valid)
        super().__init__(f"unknown root joint '{root_joint}' (valid: {', '.join(self.valid)})")


class RobotHasErrorsError(CspaceError):
    """A configuration space was asked of a report with error-level findings.

    Attributes:
        findings: The codes of the error-level findings.
    """

    code = "robot-has-errors"

    def __init__(self, robot: str, message: str, findings: Sequence[str]) -> None:
        self.findings = tuple(findings)
        super().__init__(printable(f"robot '{robot}' has no configuration space: {message}"))
