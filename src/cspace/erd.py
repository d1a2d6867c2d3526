"""Where the ``example-robot-data`` package keeps its robot files.

The package installs its robots as data under ``cmeel.prefix/share`` in site-packages;
it has no Python module to ask, so the installed distribution's metadata is asked.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, distribution
from pathlib import Path

from .errors import CspaceError

_ROBOTS = "cmeel.prefix/share/example-robot-data/robots"


def robots_dir() -> Path:
    """The folder that holds example-robot-data's robot descriptions.

    Raises:
        CspaceError: The package is not installed, or its robot folder is missing.
    """
    try:
        path = Path(str(distribution("example-robot-data").locate_file(_ROBOTS)))
    except PackageNotFoundError:
        raise CspaceError("the example-robot-data package is not installed") from None
    if not path.is_dir():
        raise CspaceError(f"example-robot-data has no robot folder at {path}")
    return path


def urdf_files() -> list[Path]:
    """Every URDF file example-robot-data installs, sorted by path."""
    return sorted(robots_dir().rglob("*.urdf"))
