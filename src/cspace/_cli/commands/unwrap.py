"""``cspace unwrap ROBOT FILE``: the continuous lift of a trajectory, and back.

FILE holds configurations in time order (CSV with a header row, or JSON Lines) in one
convention (``--convention``: one of the registry's, `cspace.conventions.TOOLS`). The
output is the lift in canonical coordinates: continuous angles unwrapped (no jump of 2
pi at the wrap), quaternions (w, x, y, z) whose sign is kept from one sample to the
next. With ``--inverse``, FILE holds a lift and the output is the trajectory in the
convention. Rows are read, lifted and written in chunks: memory stays bounded however
long the file.
"""

from __future__ import annotations

import argparse
from typing import Any

from cspace._tools import TOOLS

from .. import exit_codes
from ..configurations import add_robot_arguments
from ..vectors import VectorReader, VectorWriter, check_header, open_input
from . import add
from .convert import add_vector_arguments, conventions_of, run_chunk


def register(sub: Any) -> None:
    """Add the ``unwrap`` command."""
    parser = add(
        sub,
        "unwrap",
        description="Write the continuous lift of a trajectory (rows in time order): each "
        "continuous angle unwrapped, each quaternion's sign kept nearest the previous "
        "sample's; --inverse writes a lift back in the convention.",
    )
    add_robot_arguments(parser)
    add_vector_arguments(parser)
    parser.add_argument(
        "--convention",
        choices=tuple(TOOLS),
        default="canonical",
        help="how FILE stores the configurations (with --inverse: how to write them)",
    )
    parser.add_argument(
        "--inverse", action="store_true", help="FILE is a lift: write it back in the convention"
    )
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Lift (or wrap) FILE, a chunk at a time, each chunk continuing the last."""
    space, conventions = conventions_of(args)
    convention = args.convention
    source = "canonical" if args.inverse else convention
    target = convention if args.inverse else "canonical"
    stream, path = open_input(args.file)
    with stream:
        reader = VectorReader(stream, path)
        expected = conventions.names(source)
        if reader.header is not None:
            what = "a lift (canonical names)" if args.inverse else f"{source} of {space.robot}"
            check_header(path, reader.header, expected, what)
        writer = VectorWriter(args.format or reader.kind, conventions.names(target))
        last: Any = None
        for chunk in reader.chunks(len(expected)):
            if args.inverse:
                out = run_chunk(path, chunk, lambda rows: conventions.wrap(rows, convention))
            else:

                def lift(rows: Any, start: Any = last) -> Any:
                    return conventions.unwrap(rows, convention, start)

                out = run_chunk(path, chunk, lift)
                last = out[-1]
            writer.write(out)
    return exit_codes.OK
