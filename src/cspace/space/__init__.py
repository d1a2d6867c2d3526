"""The configuration space of a robot: `ConfigurationSpace` and `load`.

``ConfigurationSpace`` and ``Conventions`` are imported on first use: NumPy stays out of
``import cspace``. The modules beside this one are private: the factors and rotations are
public as `cspace.factors` and `cspace.rotations`.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from cspace._formats.xacro.expand import XacroOptions
    from cspace.space._closure import Closure
    from cspace.space._configuration_space import ConfigurationSpace
    from cspace.space._conventions._conventions import Conventions
    from cspace.space._ompl import OmplSpace
    from cspace.space._ompl_constrained import ConstrainedOmplSpace

__all__ = [
    "Closure",
    "ConfigurationSpace",
    "ConstrainedOmplSpace",
    "Conventions",
    "OmplSpace",
    "load",
]


def __getattr__(name: str) -> Any:
    if name == "Closure":
        from cspace.space._closure import Closure

        return Closure
    if name == "ConfigurationSpace":
        from cspace.space._configuration_space import ConfigurationSpace

        return ConfigurationSpace
    if name == "Conventions":
        from cspace.space._conventions._conventions import Conventions

        return Conventions
    if name == "ConstrainedOmplSpace":
        from cspace.space._ompl_constrained import ConstrainedOmplSpace

        return ConstrainedOmplSpace
    if name == "OmplSpace":
        from cspace.space._ompl import OmplSpace

        return OmplSpace
    raise AttributeError(f"module 'cspace.space' has no attribute {name!r}")


def load(
    path: str | os.PathLike[str],
    root_joint: str | None = None,
    *,
    xacro: XacroOptions | None = None,
    force_xacro: bool = False,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    srdf: str | os.PathLike[str] | bool | None = None,
    group: str | None = None,
    hold: str | None = None,
    limits: str | os.PathLike[str] | bool | None = None,
) -> ConfigurationSpace:
    """The configuration space of the robot file at ``path``.

    The robot is read as `cspace.inspect` reads it (the same options). For a mechanism
    with loops, the space's ``closure`` (a `Closure`) holds its loop-closure
    constraints (built once, with the tree's Pinocchio model); with ``group`` it is None.

    Args:
        path: A robot file (URDF, xacro, MJCF, SDF, OpenUSD) or ``erd:NAME``, as ``str``
            or ``os.PathLike``.
        root_joint: As for `cspace.inspect`.
        xacro: As for `cspace.inspect`.
        force_xacro: As for `cspace.inspect`.
        allow_dirs: As for `cspace.inspect`.
        srdf: As for `cspace.inspect`.
        group: As for `cspace.inspect`: the SRDF group whose own C-space to load.
        hold: As for `cspace.inspect`.
        limits: As for `cspace.inspect`.

    Raises:
        RobotFileError: The file cannot be read or is not a valid robot description.
        RobotHasErrorsError: The report has error-level findings.
        UnsupportedConfigurationError: A joint has no canonical coordinates.
    """
    from dataclasses import replace

    from cspace._model.loader import inspect_with_loops
    from cspace._model.options import LoadOptions
    from cspace.space._configuration_space import ConfigurationSpace

    options = LoadOptions(root_joint, xacro, force_xacro, allow_dirs, srdf, group, hold, limits)
    report, loops = inspect_with_loops(path, options)
    space = ConfigurationSpace.from_report(report)
    return space if loops is None else replace(space, loops=loops)
