"""``cspace interpolate ROBOT A B --steps K``: configurations along the shortest path."""

from __future__ import annotations

import argparse
from typing import Any

from cspace import ConfigurationError

from .. import exit_codes
from ..configurations import (
    add_format_argument,
    add_robot_arguments,
    load_space,
    parse_configuration,
    write_configurations,
)
from .distance import add_pair_arguments


def register(sub: Any) -> None:
    """Add the ``interpolate`` command."""
    parser = sub.add_parser(
        "interpolate",
        help="print configurations along the shortest path from A to B",
        description="Print K configurations evenly spaced in t from A (t = 0) to B "
        "(t = 1) along the shortest path: straight on R^1, the shorter way round on S^1 "
        "(across pi ~ -pi when shorter), slerp on SO(3).",
    )
    add_robot_arguments(parser)
    add_pair_arguments(parser)
    parser.add_argument(
        "--steps", type=int, default=2, metavar="K", help="configurations, A and B included (>= 2)"
    )
    add_format_argument(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Interpolate and print."""
    import numpy as np

    if args.steps < 2:
        raise ConfigurationError(f"--steps must be >= 2 (A and B included), got {args.steps}")
    space = load_space(args)
    a = parse_configuration(space, args.a, "A", args.partial)
    b = parse_configuration(space, args.b, "B", args.partial)
    t = np.linspace(0.0, 1.0, args.steps)
    rows = space.interpolate(a, b, t)
    write_configurations(space, rows, args.format, {"t": [float(v) for v in t]})
    return exit_codes.OK
