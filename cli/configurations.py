"""What the configuration commands (sample, distance, interpolate) share.

Configurations on the command line are JSON objects ``{joint: value}`` (a number, or a
list for a multi-coordinate joint: planar [x, y, theta], floating
[x, y, z, qw, qx, qy, qz], spherical [qw, qx, qy, qz]), given inline or as ``@FILE``.
Output: canonical configurations with a header naming the coordinates, as JSON or CSV;
numbers in Python's shortest round-trip form, so the same input gives the same bytes.
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cspace import ConfigurationError
from cspace.safetext import json_text, printable

from . import output

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from cspace.space import ConfigurationSpace

ROOT_JOINTS = ("floating", "planar")


def add_robot_arguments(parser: argparse.ArgumentParser) -> None:
    """The robot file and ``--root-joint``."""
    parser.add_argument("robot", help="robot file (URDF, MJCF, SDF, xacro)")
    parser.add_argument(
        "--root-joint",
        choices=ROOT_JOINTS,
        default=None,
        help="add a root joint above the root link (mobile and legged robots)",
    )


def add_format_argument(parser: argparse.ArgumentParser) -> None:
    """``--format json|csv``."""
    parser.add_argument(
        "--format",
        choices=("json", "csv"),
        default="json",
        help="json: {coordinates: [names], configurations: [[...]]} (default); csv: a "
        "header row of coordinate names, then one row per configuration",
    )


def load_space(args: argparse.Namespace) -> ConfigurationSpace:
    """The configuration space of ``args.robot``."""
    import cspace

    return cspace.load(args.robot, root_joint=args.root_joint)


def parse_pairs(items: Sequence[str], option: str) -> dict[str, str]:
    """``NAME=VALUE`` items as a mapping; one-line errors for anything else."""
    pairs: dict[str, str] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise ConfigurationError(f"{option} takes NAME=VALUE, got '{item}'")
        pairs[name] = value
    return pairs


def parse_configuration(
    space: ConfigurationSpace, text: str, label: str, partial: bool
) -> NDArray[np.float64]:
    """A canonical configuration from a JSON object (or ``@FILE``), checked against limits."""
    source = text
    if text.startswith("@"):
        path = Path(text[1:])
        try:
            source = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise ConfigurationError(f"{label}: cannot read {path}: {exc}") from None
    try:
        values = json.loads(source)
    except json.JSONDecodeError as exc:
        raise ConfigurationError(f"{label} is not valid JSON: {exc}") from None
    if not isinstance(values, dict):
        raise ConfigurationError(f"{label} must be a JSON object {{joint: value}}")
    try:
        x = space.from_dict(values, default=space.neutral() if partial else None)
        space.check(x)
    except ConfigurationError as exc:
        raise ConfigurationError(f"{label}: {exc}") from None
    return x


def _number(value: float) -> str:
    return repr(float(value))


def write_configurations(
    space: ConfigurationSpace, rows: NDArray[np.float64], fmt: str, extra: dict[str, Any]
) -> None:
    """Write configurations (N, n) with their coordinate names."""
    if fmt == "csv":
        lines = [",".join(printable(name, limit=None) for name in space.names)]
        lines.extend(",".join(_number(v) for v in row) for row in rows)
        output.write("\n".join(lines))
        return
    document = {
        "robot": space.robot,
        **extra,
        "coordinates": list(space.names),
        "configurations": [[float(v) for v in row] for row in rows],
    }
    output.write(json_text(document))
