"""``cspace sample ROBOT -n N``: uniformly distributed canonical configurations."""

from __future__ import annotations

import argparse
from typing import Any

from cspace import ConfigurationError, UnboundedSamplingError

from .. import exit_codes
from ..configurations import (
    add_format_argument,
    add_robot_arguments,
    load_space,
    parse_pairs,
    write_configurations,
)


def register(sub: Any) -> None:
    """Add the ``sample`` command."""
    parser = sub.add_parser(
        "sample",
        help="print uniformly sampled configurations",
        description="Print N configurations drawn uniformly: within the limits on R^1 "
        "coordinates, on the whole circle for S^1, Haar-uniform on SO(3). Canonical "
        "coordinates; the same seed gives the same output.",
    )
    add_robot_arguments(parser)
    parser.add_argument("-n", type=int, default=1, metavar="N", help="how many (default 1)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument(
        "--bounds",
        action="append",
        default=[],
        metavar="COORD=LOWER:UPPER",
        help="bounds of a coordinate without finite limits (e.g. root_joint.x=-1:1); repeatable",
    )
    add_format_argument(parser)
    parser.set_defaults(run=run)


def _bounds(items: list[str]) -> dict[str, tuple[float, float]]:
    bounds = {}
    for name, text in parse_pairs(items, "--bounds").items():
        low, sep, high = text.partition(":")
        try:
            bounds[name] = (float(low), float(high))
        except ValueError:
            sep = ""
        if not sep:
            raise ConfigurationError(f"--bounds takes COORD=LOWER:UPPER, got '{name}={text}'")
    return bounds


def run(args: argparse.Namespace) -> int:
    """Sample and print."""
    import numpy as np

    if args.n < 0:
        raise ConfigurationError(f"-n must be >= 0, got {args.n}")
    if args.seed < 0:
        raise ConfigurationError(f"--seed must be >= 0, got {args.seed}")
    space = load_space(args)
    try:
        rows = space.sample(args.n, np.random.default_rng(args.seed), bounds=_bounds(args.bounds))
    except UnboundedSamplingError as exc:
        raise ConfigurationError(
            f"{exc} (--bounds {exc.coordinate}=LOWER:UPPER)", coordinate=exc.coordinate
        ) from None
    write_configurations(space, rows, args.format, {"seed": args.seed})
    return exit_codes.OK
