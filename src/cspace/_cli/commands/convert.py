"""``cspace convert ROBOT FILE --from A --to B``: configurations between conventions.

Conventions: those of the registry (`cspace.conventions.TOOLS`: ``canonical``,
``pinocchio``, ``mujoco`` for the robot's MJCF or ``--mujoco MJCF`` with the same joint
names, ``drake``) and ``named`` (values by joint, as a ROS JointState holds them). With
``--velocity`` the vectors are velocities: the canonical tangent, Pinocchio's or Drake's
v (which need the configurations, ``--at FILE``), MuJoCo's qvel, named velocities.
FILE is CSV with a header row (checked against the ``--from`` convention's names) or
JSON Lines; ``-`` reads standard input.
"""

from __future__ import annotations

import argparse
from typing import Any

from cspace._tools import TOOLS

from .. import exit_codes
from ..configurations import add_robot_arguments, load_space
from ..vectors import (
    Chunk,
    VectorFileError,
    VectorReader,
    VectorWriter,
    check_header,
    checked_names,
    named_targets,
    open_input,
    split_names,
)
from . import add

CONVENTIONS = (*TOOLS, "named")
AT = tuple(name for name, tool in TOOLS.items() if tool.velocity_needs_at)
"""The conventions whose velocities need the configurations (``--at``)."""


def add_vector_arguments(parser: argparse.ArgumentParser, pose: bool = False) -> None:
    """FILE, ``--mujoco``, ``--format``: what convert and unwrap share.

    ``pose``: FILE may be left out, for ``ROBOT#POSE`` (convert).
    """
    parser.add_argument(
        "file",
        nargs="?" if pose else None,
        default=None,
        help="CSV (with a header row) or JSON Lines; - for stdin"
        + ("; left out for ROBOT#POSE, a pose the robot file stores" if pose else ""),
    )
    parser.add_argument(
        "--mujoco",
        metavar="MJCF",
        default=None,
        help="MuJoCo's layout from this MJCF file (same joint names), for a robot not "
        "read from MJCF",
    )
    parser.add_argument(
        "--format",
        choices=("csv", "jsonl"),
        default=None,
        help="output format (default: the input's)",
    )


def register(sub: Any) -> None:
    """Add the ``convert`` command."""
    parser = add(
        sub,
        "convert",
        description="Read vectors stored in one convention and write them in another: "
        + ", ".join(f"{n} ({t.positions}, {t.velocities})" for n, t in TOOLS.items())
        + ", named (by joint, any order).",
    )
    add_robot_arguments(parser)
    add_vector_arguments(parser, pose=True)
    parser.add_argument(
        "--from",
        dest="source",
        choices=CONVENTIONS,
        default=None,
        help="how FILE stores them (needed with FILE)",
    )
    parser.add_argument(
        "--to", dest="target", choices=CONVENTIONS, required=True, help="how to write them"
    )
    parser.add_argument(
        "--velocity",
        action="store_true",
        help="the vectors are velocities (canonical tangent, v, qvel, named velocities)",
    )
    parser.add_argument(
        "--at",
        metavar="FILE",
        default=None,
        help=f"with --velocity to or from {' or '.join(AT)}: the canonical configurations, "
        "one per row of FILE (their velocities of a floating or planar joint are in "
        "another frame)",
    )
    parser.add_argument(
        "--names",
        default=None,
        metavar="A,B,...",
        help="--to named: the joints, in order (default: every one-coordinate joint in tree order)",
    )
    parser.add_argument(
        "--partial",
        action="store_true",
        help="--from named: joints not named take their neutral value (0 within the "
        "limits; velocities 0) instead of being an error",
    )
    parser.add_argument(
        "--input-names",
        default=None,
        metavar="A,B,...",
        help="--from named with JSON Lines arrays: the joint of each value (a CSV header "
        'or JSON Lines objects {"name": [...], "position": [...]} name them themselves)',
    )
    parser.set_defaults(run=run)


def conventions_of(args: argparse.Namespace) -> Any:
    """The robot's space and its conventions (with ``--mujoco`` when given)."""
    given = (("ROBOT", "robot"), ("FILE", "file"), ("--at", "at"))
    stdin = [label for label, name in given if getattr(args, name, None) == "-"]
    if len(stdin) > 1:
        both = " and ".join(stdin)
        raise VectorFileError("-", None, f"{both} cannot both be standard input")
    space = load_space(args)
    return space, space.conventions(mujoco=args.mujoco)


def run_chunk(path: str, chunk: Chunk, convert: Any) -> Any:
    """``convert(chunk.rows)``, its errors naming the file and the line of the vector."""
    from cspace import ConfigurationError, CspaceError

    try:
        return convert(chunk.rows)
    except ConfigurationError as exc:
        message = str(exc).rsplit(" (configuration ", 1)[0]
        raise VectorFileError(path, chunk.line(exc.row), message, exc.code) from None
    except CspaceError as exc:
        raise VectorFileError(path, chunk.line(None), str(exc), exc.code) from None


class _Rows:
    """The canonical configurations of ``--at FILE``, taken k at a time."""

    def __init__(self, name: str, conventions: Any) -> None:
        stream, self.path = open_input(name)
        self.stream = stream
        reader = VectorReader(stream, self.path)
        if reader.header is not None:
            expected = conventions.names("canonical")
            check_header(self.path, reader.header, expected, "canonical configurations")
        self.space = conventions.space
        self.chunks = reader.chunks(conventions.space.size)
        self.rows: Any = None  # canonical rows read and not yet taken: rows[start:]
        self.start = 0

    def take(self, count: int, path: str, line: int) -> Any:
        """The next ``count`` configurations, canonical (errors name this file's line)."""
        import numpy as np

        while self._left() < count:  # what is left is copied once a chunk read: linear
            chunk = next(self.chunks, None)
            if chunk is None:
                raise VectorFileError(
                    self.path,
                    None,
                    f"has fewer configurations than {path} has vectors (none for its line {line})",
                )
            more = run_chunk(self.path, chunk, self.space.canonicalize)
            left = [] if self.rows is None else [self.rows[self.start :]]
            self.rows, self.start = np.concatenate([*left, more]), 0
        taken = self.rows[self.start : self.start + count]
        self.start += count
        return taken

    def _left(self) -> int:
        return 0 if self.rows is None else len(self.rows) - self.start

    def finish(self, path: str) -> None:
        """Refuse configurations left over: the two files do not go together."""
        if self._left() or next(self.chunks, None) is not None:
            raise VectorFileError(
                self.path, None, f"has more configurations than {path} has vectors"
            )
        self.stream.close()


def _options(args: argparse.Namespace) -> None:
    """Refuse options that do not apply to this conversion (they would be ignored)."""
    named_in, named_out = args.source == "named", args.target == "named"
    for option, value, applies in (
        ("--names", args.names, named_out),
        ("--input-names", args.input_names, named_in),
        ("--partial", args.partial, named_in),
        ("--at", args.at, args.velocity and {args.source, args.target} & set(AT)),
    ):
        if value and not applies:
            raise VectorFileError(args.file, None, f"{option} does not apply to this conversion")
    needing = [TOOLS[side].title for side in (args.source, args.target) if side in AT]
    if args.velocity and needing and args.at is None:
        raise VectorFileError(
            args.file, None, f"{needing[0]} velocities need --at FILE (the configurations)"
        )


def run(args: argparse.Namespace) -> int:
    """Convert the vectors of FILE, a chunk at a time (or the stored pose ROBOT#POSE)."""
    import numpy as np

    from ._stored_pose import run_pose, split_pose

    robot, pose = split_pose(args.robot)
    if pose is not None:
        return run_pose(args, robot, pose)
    if args.file is None or args.source is None:
        missing = "FILE" if args.file is None else "--from"
        raise VectorFileError(
            args.robot, None, f"{missing} is needed (or ROBOT#POSE, a stored pose)"
        )
    _options(args)
    space, conventions = conventions_of(args)
    velocity, source, target = args.velocity, args.source, args.target
    field = "velocity" if velocity else "position"
    if target == "named":
        target_names = named_targets(args.file, space, conventions, args.names)
        out_names = target_names
    else:
        target_names, out_names = [], list(conventions.names(target, velocity))
    if "drake" in (source, target):
        from ._drake_notes import say_drake

        say_drake(args.robot, conventions)
    if "pybullet" in (source, target):
        from ._pybullet_notes import say_pybullet

        say_pybullet(args.robot, conventions)
    clamps = None
    if target == "mujoco-ctrl" and not velocity:  # MuJoCo clamps ctrl to a ctrlrange
        from ._ctrl_notes import CtrlClamps

        clamps = CtrlClamps(conventions)
    at = None if args.at is None else _Rows(args.at, conventions)
    default = None
    if args.partial:  # joints not named: neutral, or at rest
        default = np.zeros(space.dimension) if velocity else space.neutral()
    stream, path = open_input(args.file)
    with stream:
        reader = VectorReader(stream, path)
        source_names = split_names(args.input_names)
        width: int | None = None
        check = None
        if source == "named":
            source_names = reader.header if reader.header is not None else source_names
            if source_names is not None:
                checked_names(path, conventions.check_names, source_names, "the names")
            width = None if source_names is None else len(source_names)
            check = conventions.check_names
        else:
            expected = conventions.names(source, velocity)
            if reader.header is not None:
                check_header(path, reader.header, expected, f"{source} of {space.robot}")
            width = len(expected)
        fmt = args.format or reader.kind
        objects = fmt == "jsonl" and target == "named"  # JointState-like lines
        writer = VectorWriter(fmt, out_names, field if objects else None)
        for chunk in reader.chunks(width, field, check):
            names = chunk.names if chunk.names is not None else source_names or ()
            where = None if at is None else at.take(len(chunk.rows), path, chunk.line(None))

            def convert(rows: Any, names: Any = names, where: Any = where) -> Any:
                return conventions.convert(
                    rows,
                    source,
                    target,
                    velocity=velocity,
                    at=where,
                    source_names=names,
                    target_names=target_names,
                    default=default,
                )

            converted = run_chunk(path, chunk, convert)
            writer.write(converted)
            if clamps is not None:
                clamps.add(converted, chunk.lines)
    if at is not None:
        at.finish(path)
    if clamps is not None:
        clamps.say(path)
    return exit_codes.OK
