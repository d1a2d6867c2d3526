"""``cspace distance ROBOT A B``: the distance between two configurations."""

from __future__ import annotations

import argparse
from typing import Any

from cspace import ConfigurationError
from cspace._safetext import json_text

from .. import exit_codes, output
from ..configurations import add_robot_arguments, load_space, parse_configuration, parse_pairs
from . import add


def add_pair_arguments(parser: argparse.ArgumentParser) -> None:
    """A, B and ``--partial`` (shared with ``interpolate``)."""
    parser.add_argument("a", metavar="A", help="configuration as JSON {joint: value}, or @FILE")
    parser.add_argument("b", metavar="B", help="configuration as JSON {joint: value}, or @FILE")
    parser.add_argument(
        "--partial",
        action="store_true",
        help="joints missing from A or B take their neutral value (default: an error)",
    )


def register(sub: Any) -> None:
    """Add the ``distance`` command."""
    parser = add(
        sub,
        "distance",
        description="Print the product-metric distance between two configurations: "
        "sqrt of the sum of squared factor distances, each weighted by its joint; R^1 "
        "|b - a|, S^1 the shortest way round, SO(3) the rotation angle (h and -h alike).",
    )
    add_robot_arguments(parser)
    add_pair_arguments(parser)
    parser.add_argument(
        "--weight",
        action="append",
        default=[],
        metavar="NAME=W",
        help="metric weight of a joint or factor (default 1); repeatable",
    )
    parser.add_argument(
        "--format", choices=("text", "json"), default="text", help="text: the number alone"
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Compute and print the distance."""
    space = load_space(args)
    weights = {}
    for name, text in parse_pairs(args.weight, "--weight").items():
        try:
            weights[name] = float(text)
        except ValueError:
            raise ConfigurationError(f"--weight {name}: '{text}' is not a number") from None
    space = space.with_weights(weights)
    a = parse_configuration(space, args.a, "A", args.partial)
    b = parse_configuration(space, args.b, "B", args.partial)
    d = float(space.distance(a, b))
    if args.format == "json":
        output.write(json_text({"robot": space.robot, "distance": d}))
    else:
        output.write(repr(d))
    return exit_codes.OK
