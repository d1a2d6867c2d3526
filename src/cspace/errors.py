"""The exceptions `cspace` raises.

Every exception derives from :class:`CspaceError`. Each carries what it is about as
attributes (the file, the line, the joint or link), so callers can act on them without
parsing messages; ``str(error)`` is one line a person can read. The library never maps
errors to exit codes: that is the command-line front end's job.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

# The escaping lives in safetext, with the JSON escaping; imported from here as before.
from cspace.safetext import MAX_PROBLEM_CHARS as MAX_PROBLEM_CHARS
from cspace.safetext import printable as printable


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``known`` to a misspelt ``name``, or ``""``.

    Used by every "unknown name" message (links, mimic leaders, joint types, ``erd:``
    names). difflib is imported only on this error path; past 10,000 candidates no
    suggestion is worth a slow error.
    """
    candidates = list(known)
    if len(candidates) > 10_000:
        return ""
    import difflib

    close = difflib.get_close_matches(name, candidates, n=1, cutoff=0.75)
    return f" (did you mean '{close[0]}'?)" if close else ""


class CspaceError(Exception):
    """Root of every error raised by `cspace`.

    Attributes:
        code: A stable short identifier of the kind of error; every subclass has its own.
    """

    code = "cspace"

    def __reduce__(self) -> tuple[Any, ...]:
        """Pickle as class, message and attributes (subclasses' ``__init__`` differ).

        Errors cross process boundaries: :func:`cspace.inspect_many` on a process pool
        or a cluster sends each file's error back to the caller.
        """
        return (_restore, (type(self), self.args, dict(self.__dict__)))


def _restore(cls: type[CspaceError], args: tuple[Any, ...], state: dict[str, Any]) -> CspaceError:
    """An error of class ``cls`` with these ``args`` and attributes, ``__init__`` not run."""
    error = cls.__new__(cls)
    error.args = args
    error.__dict__.update(state)
    return error


class RobotFileError(CspaceError):
    """A robot file cannot be turned into a model.

    Attributes:
        path: The file, as the caller named it.
        line: 1-based line number of the offending element, or None when unknown.
        element: Name of the offending joint or link (or XML tag), or None.
        problem: What is wrong, without the location, as one printable line (see
            :func:`printable`).
        code: A stable short identifier of the kind of problem, e.g. ``"missing-link"``;
            each subclass has its own, and a caller may give a more specific one.
    """

    code = "robot-file"

    def __init__(
        self,
        path: str,
        problem: str,
        *,
        line: int | None = None,
        element: str | None = None,
        code: str | None = None,
    ) -> None:
        if code is not None:
            self.code = code
        self.path = path
        self.problem = printable(problem)
        self.line = line
        self.element = element
        super().__init__(self._one_line())

    def _one_line(self) -> str:
        path = printable(self.path)  # a file name can hold anything but NUL and /
        where = path if self.line is None else f"{path}:{self.line}"
        return f"{where}: {self.problem}"


MAX_PROBLEMS = 100
"""Most problems of one robot file reported in one run (the last says how many more)."""


class RobotFileErrors(RobotFileError):
    """Several problems in one robot file, all found in one run (in file order).

    It reads as its first problem (``path``, ``line``, ``element``, ``problem`` and
    ``code`` are the first's); ``errors`` holds every one, so that a reviewer sees all
    of them at once instead of one per run.

    At most :data:`MAX_PROBLEMS` are kept: a hostile file of 5,000 broken joints gets the
    first 99 and one line that says how many more there were, not 5,000 lines.

    Attributes:
        errors: Each problem, in file order (by line).
    """

    code = "several-problems"  # an instance carries its first problem's code

    def __init__(self, errors: Sequence[RobotFileError]) -> None:
        ordered = sorted(errors, key=lambda e: (e.line is None, e.line or 0))
        if len(ordered) > MAX_PROBLEMS:
            left = len(ordered) - (MAX_PROBLEMS - 1)
            more = RobotFileError(
                ordered[0].path, f"{left:,} more problems are not listed", code="more-problems"
            )
            ordered = [*ordered[: MAX_PROBLEMS - 1], more]
        self.errors = tuple(ordered)
        first = ordered[0]
        super().__init__(
            first.path, first.problem, line=first.line, element=first.element, code=first.code
        )

    @staticmethod
    def of(errors: Sequence[RobotFileError]) -> RobotFileError:
        """The one error, or the errors together when there are several."""
        flat = [
            e
            for err in errors
            for e in (err.errors if isinstance(err, RobotFileErrors) else (err,))
        ]
        return flat[0] if len(flat) == 1 else RobotFileErrors(flat)


class FileUnreadableError(RobotFileError):
    """The file is missing, empty, a directory, too large, or cannot be read."""

    code = "file-unreadable"


class XmlSyntaxError(RobotFileError):
    """The file is not well-formed XML (truncated, not XML at all, ...).

    Attributes:
        column: 1-based column of the syntax error, or None.
    """

    code = "xml-syntax"

    def __init__(self, path: str, problem: str, *, line: int | None, column: int | None) -> None:
        self.column = column
        super().__init__(path, problem, line=line)

    def _one_line(self) -> str:
        if self.line is not None and self.column is not None:
            return f"{printable(self.path)}:{self.line}:{self.column}: {self.problem}"
        return super()._one_line()


class UnsafeXmlError(RobotFileError):
    """The XML uses entity declarations, which `cspace` never expands."""

    code = "xml-unsafe"


class NotARobotError(RobotFileError):
    """Well-formed XML whose root element is not a robot description."""

    code = "not-a-robot"


class RobotStructureError(RobotFileError):
    """The kinematic structure is invalid: unknown links, cycles, duplicates, several roots.

    Attributes:
        code: Which structural rule was broken: ``no-links``, ``duplicate-link``,
            ``duplicate-joint``, ``missing-link``, ``two-parents``, ``cycle``,
            ``several-roots``, ``mimic-unknown-joint``, ``mimic-cycle``, ``too-deep``,
            ``too-many-joints``, ``too-many-dofs`` or ``name-too-long``.
    """

    code = "bad-structure"  # each raise names the rule: see the docstring


class UnknownJointTypeError(RobotFileError):
    """A joint's type is not one the format defines.

    Attributes:
        joint_type: The type the file gives.
        valid_types: The types the format allows, sorted.
    """

    code = "unknown-joint-type"

    def __init__(
        self,
        path: str,
        *,
        joint: str,
        joint_type: str,
        valid_types: Sequence[str],
        line: int | None,
    ) -> None:
        self.joint_type = joint_type
        self.valid_types = tuple(sorted(valid_types))
        problem = (
            f"joint '{joint}' has unknown type '{joint_type}' "
            f"(valid: {', '.join(self.valid_types)})"
            + did_you_mean(joint_type.lower(), self.valid_types)
        )
        super().__init__(path, problem, line=line, element=joint)


class ModelBuildError(RobotFileError):
    """Pinocchio refused a file that passed our own checks; its own words are kept.

    Attributes:
        parser_messages: What Pinocchio's C++ parser printed, one message per entry.
    """

    code = "pinocchio-rejected"

    def __init__(
        self,
        path: str,
        problem: str,
        parser_messages: Sequence[str],
        *,
        line: int | None = None,
        element: str | None = None,
    ) -> None:
        self.parser_messages = tuple(parser_messages)
        super().__init__(path, problem, line=line, element=element)


class UnsupportedJointModelError(RobotFileError):
    """Pinocchio produced a joint model that `cspace` does not know how to classify.

    Attributes:
        joint_model: Pinocchio's ``shortname()`` of the joint model.
        known_models: The joint models `cspace` classifies, sorted.
    """

    code = "unsupported-joint-model"

    def __init__(
        self, path: str, *, joint: str, joint_model: str, known_models: Sequence[str]
    ) -> None:
        self.joint_model = joint_model
        self.known_models = tuple(sorted(known_models))
        super().__init__(
            path,
            f"joint '{joint}' is a Pinocchio {joint_model}, which cspace does not classify",
            element=joint,
        )


class ReportFileError(RobotFileError):
    """A saved JSON report (given where a robot is expected) cannot be used.

    Not UTF-8 JSON, not strict JSON (NaN, an infinity, an integer or a number too large
    for a double, a duplicated key, nesting too deep), not a cspace report, another
    ``schema_version``, or a value the report's JSON Schema does not allow.

    Attributes:
        pointer: JSON Pointer (RFC 6901) of the offending value, e.g.
            ``/joints/3/q_index`` (``""`` for the whole document), or None when the text
            is not JSON at all (``line`` then says where, when known).
    """

    code = "bad-report"

    def __init__(
        self, path: str, problem: str, *, pointer: str | None = None, line: int | None = None
    ) -> None:
        self.pointer = pointer
        super().__init__(path, problem, line=line)

    def _one_line(self) -> str:
        if self.pointer is None:
            return super()._one_line()
        where = printable(self.pointer) if self.pointer else "the top level"
        return f"{super()._one_line()} at {where}"


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


class InvalidElementError(RobotFileError):
    """One element of the file is malformed: a missing attribute, child or limit, a bad number.

    Attributes:
        code: ``missing-attribute``, ``missing-element``, ``missing-limit`` or ``bad-number``.
    """

    code = "invalid-element"  # each raise names the rule: see the docstring


class ConfigurationError(CspaceError, ValueError):
    """A configuration (or a batch of them) given to a :class:`ConfigurationSpace` is wrong.

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


class XacroError(RobotFileError):
    """A xacro file cannot be expanded (unknown package, missing include, bad argument)."""

    code = "xacro-failed"


class XacroNotRequestedError(RobotFileError):
    """A ``<robot>`` file uses xacro, but expansion was not asked for.

    xacro runs the expressions in a file, so `cspace` expands only files named
    ``*.xacro`` or given with ``--xacro`` (``force_xacro=True``); it never reads such a
    file as plain URDF either, which would silently drop its macros.
    """

    code = "xacro-not-requested"


class MujocoError(RobotFileError):
    """MuJoCo's compiler refused an MJCF model (its own reason, one line), or hit a limit."""

    code = "mujoco-refused"


class WorkerDiedError(RobotFileError):
    """The worker process inspecting the file died (a crash in a parser, or killed).

    Only :func:`cspace.inspect_many`'s own process pool reports this: the file is run
    again alone in a new worker, and only a file that kills its worker alone gets it.
    """

    code = "worker-died"


class ExampleRobotDataError(CspaceError):
    """An ``erd:NAME`` robot cannot be found: an unknown name, or the package is missing."""

    code = "unknown-erd-robot"


class RobotHasErrorsError(CspaceError):
    """A configuration space was asked of a report with error-level findings.

    Attributes:
        findings: The codes of the error-level findings.
    """

    code = "robot-has-errors"

    def __init__(self, robot: str, message: str, findings: Sequence[str]) -> None:
        self.findings = tuple(findings)
        super().__init__(printable(f"robot '{robot}' has no configuration space: {message}"))
