"""What can be wrong with a robot file (or a saved report): each kind a class and a code."""

from __future__ import annotations

from collections.abc import Sequence

from cspace._safetext import printable
from cspace.errors._base import CspaceError, RobotFileError, did_you_mean


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


class InvalidElementError(RobotFileError):
    """One element of the file is malformed: a missing attribute, child or limit, a bad number.

    Attributes:
        code: ``missing-attribute``, ``missing-element``, ``missing-limit`` or ``bad-number``.
    """

    code = "invalid-element"  # each raise names the rule: see the docstring


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

    `cspace.inspect_many`'s own process pool reports this: the file is run again alone
    in a new worker, and only a file that kills its worker alone gets it. So does
    `cspace.collisions` with ``jobs`` > 1, when a worker sampling the robot dies.
    """

    code = "worker-died"


class ExampleRobotDataError(CspaceError):
    """An ``erd:NAME`` robot cannot be found: an unknown name, or the package is missing."""

    code = "unknown-erd-robot"
    message_chars = 4000  # the whole list of names (cspace's own); the name given is cut


class OutputError(CspaceError):
    """A file cspace was asked to write cannot be written safely.

    Outputs are never written through a symbolic link nor over anything but a regular
    file (see `cspace.files`).

    Attributes:
        path: The output, as the caller named it.
        problem: What is wrong, as one printable line.
    """

    code = "bad-output"

    def __init__(self, path: str, problem: str) -> None:
        self.path = path
        self.problem = printable(problem)
        super().__init__(f"{printable(path)}: {self.problem}")
