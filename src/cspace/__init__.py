"""cspace: the true shape of a robot's configuration space.

>>> import cspace
>>> report = cspace.inspect("robots/arm7.urdf")
>>> report.manifold.notation
'R^6 × S^1'
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cspace._version import __version__
from cspace.errors import (
    ArgumentError,
    ArgumentTypeError,
    ConfigurationError,
    ConfigurationShapeError,
    CspaceError,
    ExampleRobotDataError,
    FileUnreadableError,
    InternalError,
    InvalidElementError,
    InvalidRootJointError,
    JointMatchError,
    JointValueError,
    MissingJointError,
    ModelBuildError,
    MujocoError,
    NonFiniteValueError,
    NotARobotError,
    NotARotationError,
    NotUnitQuaternionError,
    OutOfLimitsError,
    OutputError,
    ReportFileError,
    RobotFileError,
    RobotFileErrors,
    RobotHasErrorsError,
    RobotStructureError,
    SizeLimitError,
    UnboundedSamplingError,
    UnknownJointError,
    UnknownJointTypeError,
    UnsafeXmlError,
    UnsupportedConfigurationError,
    UnsupportedJointModelError,
    ValueOverflowError,
    WorkerDiedError,
    XacroError,
    XacroNotRequestedError,
    XmlSyntaxError,
)
from cspace.findings import Diagnostic, Severity
from cspace.formats.xmlio import SourceFile, read_source, source_from_bytes
from cspace.joint_kind import JointKind
from cspace.manifold import NormalForm
from cspace.model.loader import inspect, inspect_source, pinocchio_model
from cspace.reports.report import JointReport, Limits, MimicRelation, Report, Source
from cspace.sizes import MAX_ARRAY_BYTES
from cspace.space import load

if TYPE_CHECKING:
    from cspace import diff as diff
    from cspace import factors as factors
    from cspace import markdown as markdown
    from cspace import rotations as rotations
    from cspace.formats.xacrofile import XacroOptions
    from cspace.model.many import Inspected, inspect_many
    from cspace.space.configuration_space import ConfigurationSpace


def __getattr__(name: str) -> Any:
    if name == "XacroOptions":  # xacro support is imported when it is used
        from cspace.formats.xacrofile import XacroOptions

        return XacroOptions
    if name in ("inspect_many", "Inspected"):  # many files: imported when used
        from cspace.model import many

        return getattr(many, name)
    if name == "ConfigurationSpace":
        from cspace.space.configuration_space import ConfigurationSpace

        return ConfigurationSpace
    if not name.startswith("_"):  # a submodule, imported on first use (cspace.notation)
        import importlib

        try:
            return importlib.import_module(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
    raise AttributeError(f"module 'cspace' has no attribute '{name}'")


__all__ = [
    "MAX_ARRAY_BYTES",
    "ArgumentError",
    "ArgumentTypeError",
    "ConfigurationError",
    "ConfigurationShapeError",
    "ConfigurationSpace",
    "CspaceError",
    "Diagnostic",
    "ExampleRobotDataError",
    "FileUnreadableError",
    "Inspected",
    "InternalError",
    "InvalidElementError",
    "InvalidRootJointError",
    "JointKind",
    "JointMatchError",
    "JointReport",
    "JointValueError",
    "Limits",
    "MimicRelation",
    "MissingJointError",
    "ModelBuildError",
    "MujocoError",
    "NonFiniteValueError",
    "NormalForm",
    "NotARobotError",
    "NotARotationError",
    "NotUnitQuaternionError",
    "OutOfLimitsError",
    "OutputError",
    "Report",
    "ReportFileError",
    "RobotFileError",
    "RobotFileErrors",
    "RobotHasErrorsError",
    "RobotStructureError",
    "Severity",
    "SizeLimitError",
    "Source",
    "SourceFile",
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
    "XacroOptions",
    "XmlSyntaxError",
    "__version__",
    "inspect",
    "inspect_many",
    "inspect_source",
    "load",
    "pinocchio_model",
    "read_source",
    "source_from_bytes",
]
