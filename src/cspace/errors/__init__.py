"""The exceptions `cspace` raises.

Every exception derives from :class:`CspaceError`. Each carries what it is about as
attributes (the file, the line, the joint or link), so callers can act on them without
parsing messages; ``str(error)`` is one line a person can read. The library never maps
errors to exit codes: that is the command-line front end's job.
"""

from __future__ import annotations

from cspace.errors.base import (
    MAX_PROBLEMS as MAX_PROBLEMS,
)
from cspace.errors.base import (
    CspaceError as CspaceError,
)
from cspace.errors.base import (
    RobotFileError as RobotFileError,
)
from cspace.errors.base import (
    RobotFileErrors as RobotFileErrors,
)
from cspace.errors.base import (
    did_you_mean as did_you_mean,
)
from cspace.errors.configurations import (
    ArgumentError as ArgumentError,
)
from cspace.errors.configurations import (
    ArgumentTypeError as ArgumentTypeError,
)
from cspace.errors.configurations import (
    ConfigurationError as ConfigurationError,
)
from cspace.errors.configurations import (
    ConfigurationShapeError as ConfigurationShapeError,
)
from cspace.errors.configurations import (
    InvalidRootJointError as InvalidRootJointError,
)
from cspace.errors.configurations import (
    JointMatchError as JointMatchError,
)
from cspace.errors.configurations import (
    JointValueError as JointValueError,
)
from cspace.errors.configurations import (
    MissingJointError as MissingJointError,
)
from cspace.errors.configurations import (
    NonFiniteValueError as NonFiniteValueError,
)
from cspace.errors.configurations import (
    NotARotationError as NotARotationError,
)
from cspace.errors.configurations import (
    NotUnitQuaternionError as NotUnitQuaternionError,
)
from cspace.errors.configurations import (
    OutOfLimitsError as OutOfLimitsError,
)
from cspace.errors.configurations import (
    RobotHasErrorsError as RobotHasErrorsError,
)
from cspace.errors.configurations import (
    SizeLimitError as SizeLimitError,
)
from cspace.errors.configurations import (
    UnboundedSamplingError as UnboundedSamplingError,
)
from cspace.errors.configurations import (
    UnknownJointError as UnknownJointError,
)
from cspace.errors.configurations import (
    UnsupportedConfigurationError as UnsupportedConfigurationError,
)
from cspace.errors.configurations import (
    ValueOverflowError as ValueOverflowError,
)
from cspace.errors.files import (
    ExampleRobotDataError as ExampleRobotDataError,
)
from cspace.errors.files import (
    FileUnreadableError as FileUnreadableError,
)
from cspace.errors.files import (
    InvalidElementError as InvalidElementError,
)
from cspace.errors.files import (
    ModelBuildError as ModelBuildError,
)
from cspace.errors.files import (
    MujocoError as MujocoError,
)
from cspace.errors.files import (
    NotARobotError as NotARobotError,
)
from cspace.errors.files import (
    ReportFileError as ReportFileError,
)
from cspace.errors.files import (
    RobotStructureError as RobotStructureError,
)
from cspace.errors.files import (
    UnknownJointTypeError as UnknownJointTypeError,
)
from cspace.errors.files import (
    UnsafeXmlError as UnsafeXmlError,
)
from cspace.errors.files import (
    UnsupportedJointModelError as UnsupportedJointModelError,
)
from cspace.errors.files import (
    WorkerDiedError as WorkerDiedError,
)
from cspace.errors.files import (
    XacroError as XacroError,
)
from cspace.errors.files import (
    XacroNotRequestedError as XacroNotRequestedError,
)
from cspace.errors.files import (
    XmlSyntaxError as XmlSyntaxError,
)

# The escaping lives in safetext, with the JSON escaping; imported from here as before.
from cspace.safetext import MAX_PROBLEM_CHARS as MAX_PROBLEM_CHARS
from cspace.safetext import printable as printable
