"""``cspace convert ROBOT#POSE --to B``: a pose the robot file stores, in any convention.

POSE is an MJCF keyframe's name or an SRDF group state's (``group/name`` when two
groups have a state of that name). The pose is read as the report lists it (its
canonical configuration, the joints it does not give at neutral) and written as one
vector in the ``--to`` convention.
"""

from __future__ import annotations

import argparse
import os

from cspace._formats.shared.erd import ERD_PREFIX
from cspace._reports.poses import StoredPose, pick

from .. import exit_codes
from ..patterns import FileName
from ..vectors import VectorFileError


def split_pose(robot: str) -> tuple[str, str | None]:
    """``ROBOT#POSE`` as (ROBOT, POSE); (ROBOT, None) when no pose is named.

    A file whose own name holds ``#`` is that file. Otherwise the robot is the first part
    before a ``#`` that names a file (so a pose's name may hold ``#`` too), or an
    ``erd:`` name up to its first ``#`` (not after ``--``: a `FileName` stays one).
    """
    if "#" not in robot or os.path.lexists(robot):
        return robot, None
    keep = FileName if isinstance(robot, FileName) else str
    if robot.startswith(ERD_PREFIX) and keep is str:
        path, _, pose = robot.partition("#")
        return path, pose
    index = robot.find("#")
    while index >= 0:
        if os.path.lexists(robot[:index]):
            return keep(robot[:index]), robot[index + 1 :]
        index = robot.find("#", index + 1)
    path, _, pose = robot.partition("#")  # no such file: the error names it
    return keep(path), pose


def find_pose(path: str, poses: tuple[StoredPose, ...], wanted: str) -> StoredPose:
    """The pose called ``wanted`` (a name, or ``group/name``), or a one-line error."""
    try:
        return pick(poses, wanted)
    except LookupError as exc:
        raise VectorFileError(path, None, str(exc)) from None


def run_pose(args: argparse.Namespace, robot: str, wanted: str) -> int:
    """Write the stored pose ``wanted`` of ``robot`` in the ``--to`` convention."""
    import numpy as np

    from cspace.space import ConfigurationSpace

    from ..robots import load_report
    from ..vectors import VectorWriter

    for option, value in (("FILE", args.file), ("--from", args.source), ("--at", args.at)):
        if value is not None:
            raise VectorFileError(robot, None, f"{option} does not apply to a stored pose")
    for option, flag in (("--velocity", args.velocity), ("--partial", args.partial)):
        if flag:
            raise VectorFileError(robot, None, f"{option} does not apply to a stored pose")
    report = load_report(robot, args)
    pose = find_pose(robot, report.poses, wanted)
    space = ConfigurationSpace.from_report(report)
    conventions = space.conventions(mujoco=args.mujoco)
    if args.target == "drake":
        from ._drake_notes import say_drake

        say_drake(robot, conventions)
    x = np.asarray([pose.configuration], dtype=np.float64)
    if args.target == "named":
        from ..vectors import named_targets

        names = named_targets(robot, space, conventions, args.names)
        out = conventions.convert(x, "canonical", "named", target_names=names)
    else:
        names = list(conventions.names(args.target))
        out = conventions.convert(x, "canonical", args.target)
    fmt = args.format or "csv"
    VectorWriter(
        fmt, names, "position" if fmt == "jsonl" and args.target == "named" else None
    ).write(out)
    return exit_codes.OK
