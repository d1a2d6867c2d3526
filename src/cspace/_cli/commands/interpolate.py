"""``cspace interpolate ROBOT A B --steps K``: configurations along the shortest path."""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from .. import exit_codes
from ..configurations import (
    add_format_argument,
    add_robot_arguments,
    chunk_rows,
    count,
    load_space,
    parse_configuration,
    spans,
    write_configurations,
)
from . import add
from .distance import add_pair_arguments

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray


def register(sub: Any) -> None:
    """Add the ``interpolate`` command."""
    parser = add(
        sub,
        "interpolate",
        description="Print K configurations evenly spaced in t from A (t = 0) to B "
        "(t = 1) along the shortest path: straight on R^1, the shorter way round on S^1 "
        "(across pi ~ -pi when shorter), slerp on SO(3).",
    )
    add_robot_arguments(parser)
    add_pair_arguments(parser)
    parser.add_argument(
        "--steps",
        type=count(2),
        default=2,
        metavar="K",
        help="configurations, A and B included (>= 2; default 2: A and B); computed and "
        "written in chunks",
    )
    add_format_argument(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Interpolate and print, a chunk of t at a time."""
    import numpy as np

    space = load_space(args)
    a = parse_configuration(space, args.a, "A", args.partial)
    b = parse_configuration(space, args.b, "B", args.partial)
    step = chunk_rows(space)

    def parameters() -> Iterator[NDArray[np.float64]]:
        """T = k / (K - 1) for k = 0 .. K - 1, as numpy.linspace(0, 1, K) computes it."""
        delta = 1.0 / (args.steps - 1)
        for start, stop in spans(args.steps, step):
            t = np.arange(start, stop, dtype=np.float64) * delta
            if stop == args.steps:
                t[-1] = 1.0
            yield t

    rows = (space.interpolate(a, b, t) for t in parameters())
    write_configurations(space, rows, args, args.steps, {}, {"t": parameters})
    return exit_codes.OK
