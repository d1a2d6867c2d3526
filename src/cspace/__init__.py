"""cspace: the true shape of a robot's configuration space.

>>> import cspace
>>> report = cspace.inspect("robots/arm7.urdf")
>>> report.manifold.notation
'R^6 × S^1'
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from cspace._findings import Diagnostic, Severity
from cspace._formats.shared.xmlio import SourceFile, read_source, source_from_bytes
from cspace._joint_kind import JointKind
from cspace._manifold import NormalForm
from cspace._model.loader import inspect, inspect_source, pinocchio_model
from cspace._reports.poses import GroupView, SrdfSummary, StoredPose
from cspace._reports.report import JointReport, Limits, MimicRelation, Report, Source
from cspace._sizes import MAX_ARRAY_BYTES
from cspace._slots import MujocoLayout
from cspace._version import __version__
from cspace.errors import (
    ConfigurationError,
    CspaceError,
    ExampleRobotDataError,
    InternalError,
    InvalidRootJointError,
    JointMatchError,
    NotationError,
    OutputError,
    RobotFileError,
    RobotHasErrorsError,
    UnsupportedConfigurationError,
)
from cspace.space import load

if TYPE_CHECKING:
    from cspace import conventions as conventions
    from cspace import diff as diff
    from cspace import errors as errors
    from cspace import factors as factors
    from cspace import files as files
    from cspace import markdown as markdown
    from cspace import notation as notation
    from cspace import rotations as rotations
    from cspace import space as space
    from cspace._actuators import Actuator
    from cspace._formats.xacro.expand import XacroOptions
    from cspace._model.many import Inspected, inspect_many
    from cspace._reports.collisions import (
        CollidingRange,
        CollisionReport,
        FileRule,
        PairReport,
        PoseCollision,
        Share,
        Witness,
    )
    from cspace._ros2_control import ControlHardware, ControlInterface, ControlJoint
    from cspace.space._collisions.run import collisions
    from cspace.space._configuration_space import ConfigurationSpace
    from cspace.space._conventions._conventions import Conventions

PUBLIC_MODULES = (
    "conventions",
    "diff",
    "errors",
    "factors",
    "files",
    "markdown",
    "notation",
    "rotations",
    "space",
)
"""The modules of the public API (``cspace.<name>``); every other module is private."""

_LAZY = {
    "Actuator": "cspace._actuators",  # MuJoCo's actuators: imported when an MJCF has some
    "ControlHardware": "cspace._ros2_control",  # a URDF's <ros2_control>: imported when used
    "ControlJoint": "cspace._ros2_control",
    "ControlInterface": "cspace._ros2_control",
    "XacroOptions": "cspace._formats.xacro.expand",  # xacro support: imported when it is used
    "inspect_many": "cspace._model.many",  # many files: imported when used
    "collisions": "cspace.space._collisions.run",  # self-collision: coal, imported when used
    "CollisionReport": "cspace._reports.collisions",
    "PairReport": "cspace._reports.collisions",
    "Share": "cspace._reports.collisions",
    "Witness": "cspace._reports.collisions",
    "FileRule": "cspace._reports.collisions",
    "CollidingRange": "cspace._reports.collisions",
    "PoseCollision": "cspace._reports.collisions",
    "Inspected": "cspace._model.many",
    "ConfigurationSpace": "cspace.space._configuration_space",  # NumPy: imported when used
    "Conventions": "cspace.space._conventions._conventions",
}


def __getattr__(name: str) -> Any:
    import importlib

    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in PUBLIC_MODULES:  # a public module, imported on first use (cspace.notation)
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'cspace' has no attribute '{name}'")


def __dir__() -> list[str]:  # what a user may reach: tab completion offers it
    dunders = {name for name in globals() if name.startswith("__")}
    return sorted({*dunders, *__all__, *PUBLIC_MODULES, "PUBLIC_MODULES"})


__all__ = [
    "MAX_ARRAY_BYTES",
    "Actuator",
    "CollidingRange",
    "CollisionReport",
    "ConfigurationError",
    "ConfigurationSpace",
    "ControlHardware",
    "ControlInterface",
    "ControlJoint",
    "Conventions",
    "CspaceError",
    "Diagnostic",
    "ExampleRobotDataError",
    "FileRule",
    "GroupView",
    "Inspected",
    "InternalError",
    "InvalidRootJointError",
    "JointKind",
    "JointMatchError",
    "JointReport",
    "Limits",
    "MimicRelation",
    "MujocoLayout",
    "NormalForm",
    "NotationError",
    "OutputError",
    "PairReport",
    "PoseCollision",
    "Report",
    "RobotFileError",
    "RobotHasErrorsError",
    "Severity",
    "Share",
    "Source",
    "SourceFile",
    "SrdfSummary",
    "StoredPose",
    "UnsupportedConfigurationError",
    "Witness",
    "XacroOptions",
    "__version__",
    "collisions",
    "inspect",
    "inspect_many",
    "inspect_source",
    "load",
    "pinocchio_model",
    "read_source",
    "source_from_bytes",
]
"""The public names: the functions and records, and the root errors (every error is in
`cspace.errors`)."""
