"""``cspace sample ROBOT -n N``: uniformly distributed canonical configurations."""

from __future__ import annotations

import argparse
from typing import Any

from cspace.errors import ConfigurationError, UnboundedSamplingError

from .. import exit_codes
from ..configurations import (
    add_format_argument,
    add_robot_arguments,
    chunk_rows,
    count,
    load_space,
    parse_pairs,
    spans,
    write_configurations,
)
from . import add


def register(sub: Any) -> None:
    """Add the ``sample`` command."""
    parser = add(
        sub,
        "sample",
        description="Print N configurations drawn uniformly: within the limits on R^1 "
        "coordinates, on the whole circle for S^1, Haar-uniform on SO(3). Canonical "
        "coordinates; the same seed gives the same output, and the first K of N "
        "configurations are those -n K prints. Drawn and written in chunks: memory stays "
        "bounded for any N.",
    )
    add_robot_arguments(parser)
    parser.add_argument(
        "-n", type=count(1), default=1, metavar="N", help="how many, >= 1 (default 1)"
    )
    parser.add_argument(
        "--seed", type=count(0), default=0, metavar="S", help="random seed, >= 0 (default 0)"
    )
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
    """Sample and print, a chunk at a time.

    ``sample`` draws each configuration's random numbers in turn from the generator,
    so chunk after chunk gives the same configurations as one call for all N.
    """
    import numpy as np

    space = load_space(args)
    bounds = _bounds(args.bounds)
    rng = np.random.default_rng(args.seed)
    try:
        space.sample(0, rng, bounds=bounds)  # the bounds are checked before any output
    except UnboundedSamplingError as exc:
        raise ConfigurationError(
            f"{exc} (--bounds {exc.coordinate}=LOWER:UPPER)", coordinate=exc.coordinate
        ) from None
    step = chunk_rows(space)
    chunks = (space.sample(stop - start, rng, bounds=bounds) for start, stop in spans(args.n, step))
    write_configurations(space, chunks, args, args.n, {"seed": args.seed})
    return exit_codes.OK
