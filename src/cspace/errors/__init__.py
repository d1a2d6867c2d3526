"""The exceptions `cspace` raises.

Every exception derives from `CspaceError`. Each carries what it is about as
attributes (the file, the line, the joint or link), so callers can act on them without
parsing messages; ``str(error)`` is one line a person can read. The library never maps
errors to exit codes: that is the command-line front end's job.
"""

from __future__ import annotations

# The escaping lives in safetext, with the JSON escaping; imported from here as before.
from cspace._safetext import MAX_PROBLEM_CHARS, printable
from cspace.errors._base import (
    MAX_PROBLEMS,
    CspaceError,
    NotationError,
    RobotFileError,
    RobotFileErrors,
)
from cspace.errors._base import _restore as _restore  # what pickled errors name
from cspace.errors._configurations import (
    ArgumentError,
    ArgumentTypeError,
    ConfigurationError,
    ConfigurationShapeError,
    InvalidRootJointError,
    JointMatchError,
    JointValueError,
    MissingJointError,
    NonFiniteValueError,
    NotARotationError,
    NotUnitQuaternionError,
    OutOfLimitsError,
    RobotHasErrorsError,
    SizeLimitError,
    UnboundedSamplingError,
    UnknownJointError,
    UnsupportedConfigurationError,
    ValueOverflowError,
)
from cspace.errors._files import (
    ExampleRobotDataError,
    FileUnreadableError,
    InvalidElementError,
    ModelBuildError,
    MujocoError,
    NotARobotError,
    OutputError,
    ReportFileError,
    RobotStructureError,
    UnknownJointTypeError,
    UnsafeXmlError,
    UnsupportedJointModelError,
    WorkerDiedError,
    XacroError,
    XacroNotRequestedError,
    XmlSyntaxError,
)
from cspace.errors._internal import InternalError

__all__ = [
    "MAX_PROBLEMS",
    "MAX_PROBLEM_CHARS",
    "ArgumentError",
    "ArgumentTypeError",
    "ConfigurationError",
    "ConfigurationShapeError",
    "CspaceError",
    "ExampleRobotDataError",
    "FileUnreadableError",
    "InternalError",
    "InvalidElementError",
    "InvalidRootJointError",
    "JointMatchError",
    "JointValueError",
    "MissingJointError",
    "ModelBuildError",
    "MujocoError",
    "NonFiniteValueError",
    "NotARobotError",
    "NotARotationError",
    "NotUnitQuaternionError",
    "NotationError",
    "OutOfLimitsError",
    "OutputError",
    "ReportFileError",
    "RobotFileError",
    "RobotFileErrors",
    "RobotHasErrorsError",
    "RobotStructureError",
    "SizeLimitError",
    "UnboundedSamplingError",
    "UnknownJointError",
    "UnknownJointTypeError",
    "UnsafeXmlError",
    "UnsupportedConfigurationError",
    "UnsupportedJointModelError",
    "ValueOverflowError",
    "WorkerDiedError",
    "XacroError",
    "XacroNotRequestedError",
    "XmlSyntaxError",
    "printable",
]
"""Every public name of the errors (``_restore``, how errors unpickle, is here too)."""

# Every error class, and the function that restores a pickled one, is named where users
# import it from (cspace.errors.X), in reprs, tracebacks and pickles alike, whichever
# private module defines it.
for _class in [c for c in globals().values() if isinstance(c, type) and issubclass(c, Exception)]:
    _class.__module__ = __name__
del _class
_restore.__module__ = __name__
