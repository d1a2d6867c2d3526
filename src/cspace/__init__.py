"""cspace: the true shape of a robot's configuration space.

>>> import cspace
>>> report = cspace.inspect("robots/arm7.urdf")
>>> report.manifold.notation
'R^6 × S^1'
"""

from ._version import __version__
from .errors import (
    CspaceError,
    FileUnreadableError,
    InvalidElementError,
    InvalidRootJointError,
    ModelBuildError,
    NotARobotError,
    RobotFileError,
    RobotStructureError,
    UnknownJointTypeError,
    UnsafeXmlError,
    UnsupportedJointModelError,
    XmlSyntaxError,
)
from .kinds import JointKind
from .loader import inspect, inspect_source
from .manifold import NormalForm
from .report import Diagnostic, JointReport, Limits, MimicRelation, Report, Severity, Source
from .xmlio import SourceFile, read_source, source_from_bytes

__all__ = [
    "CspaceError",
    "Diagnostic",
    "FileUnreadableError",
    "InvalidElementError",
    "InvalidRootJointError",
    "JointKind",
    "JointReport",
    "Limits",
    "MimicRelation",
    "ModelBuildError",
    "NormalForm",
    "NotARobotError",
    "Report",
    "RobotFileError",
    "RobotStructureError",
    "Severity",
    "Source",
    "SourceFile",
    "UnknownJointTypeError",
    "UnsafeXmlError",
    "UnsupportedJointModelError",
    "XmlSyntaxError",
    "__version__",
    "inspect",
    "inspect_source",
    "read_source",
    "source_from_bytes",
]
