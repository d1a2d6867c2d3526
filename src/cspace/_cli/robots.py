"""What inspect, diff and check share: naming robots on the command line and loading them.

A robot is a file (of any format of `cspace._formats.table`, told by its content), a
folder (the robot files in it), a glob pattern (expanded here too, for quoted patterns in
CI), ``erd:NAME`` or ``-`` (standard input). ``diff`` and ``check`` also take saved JSON
reports. A name after ``--`` (a `FileName`) is always the file or folder of that name;
before ``--``, ``-`` and ``erd:NAME`` that also name an existing file are refused
(`robot_name`), and a pattern names its matches and the file of its very name, if any.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

import cspace
from cspace._formats.shared.erd import ERD_PREFIX

from .found import in_folder
from .found import robots_among as robots_among  # inspect --robots-only's, from here too
from .patterns import FileName, Searched, expand_pattern, is_glob

if TYPE_CHECKING:
    from cspace._model.options import LoadOptions

ROOT_JOINTS = ("floating", "planar")


def add_loading_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of every command that reads a robot: how to load it, and ``--color``."""
    parser.add_argument(
        "--root-joint",
        choices=ROOT_JOINTS,
        default=None,
        help="add a root joint above the root link (mobile and legged robots)",
    )
    parser.add_argument(
        "--package-path",
        action="append",
        default=[],
        metavar="DIR",
        help="xacro: a folder searched for ROS packages for $(find PKG) (repeatable); "
        "package.xml files above the xacro file are found anyway",
    )
    parser.add_argument(
        "--arg",
        action="append",
        default=[],
        metavar="NAME:=VALUE",
        help="xacro: set a <xacro:arg> (repeatable)",
    )
    parser.add_argument(
        "--xacro",
        action="store_true",
        help="expand the robot files as xacro whatever their names (xacro runs code: it is "
        "done in a confined process; files named *.xacro are expanded without this flag)",
    )
    parser.add_argument(
        "--xacro-unconfined",
        action="store_true",
        help="expand xacro even where the kernel cannot confine it (no Linux Landlock or "
        "seccomp): with CPU, memory and output limits and an audit hook only",
    )
    parser.add_argument(
        "--allow-dir",
        action="append",
        default=[],
        metavar="DIR",
        help="MJCF: a folder, besides the robot file's own, that <include> files may be read "
        "from (repeatable)",
    )
    add_srdf_arguments(parser)
    parser.add_argument(
        "--color",
        choices=("auto", "always", "never"),
        default="auto",
        help="colour text output (auto: on a terminal, unless NO_COLOR)",
    )


def add_findings_arguments(parser: argparse.ArgumentParser, codes: Iterable[str]) -> None:
    """``--strict`` and ``--ignore CODE`` (one of ``codes``): which findings fail a run."""
    parser.add_argument(
        "--strict", action="store_true", help="exit 1 on warnings too, not only on errors"
    )
    parser.add_argument(
        "--ignore",
        action="append",
        default=[],
        metavar="CODE",
        choices=sorted(codes),
        help="drop findings with this code (repeatable)",
    )


def add_srdf_arguments(parser: argparse.ArgumentParser) -> None:
    """``--srdf``, ``--group``, ``--hold``: MoveIt's SRDF read with a URDF."""
    parser.add_argument(
        "--srdf",
        metavar="FILE",
        default=None,
        help="URDF: MoveIt's SRDF (groups, group states, virtual and passive joints); "
        "'auto': the robot's own from its project (NAME.srdf or one naming the robot, "
        "beside the URDF, in ../srdf, config/ or a *_moveit_config package), when there is "
        "one",
    )
    parser.add_argument(
        "--limits",
        metavar="FILE",
        default=None,
        help="URDF: MoveIt's joint_limits.yaml (its min/max_position replace the URDF's "
        "limits as MoveIt applies them; velocity, acceleration, jerk shown); 'auto': "
        "config/joint_limits.yaml where --srdf auto looks, when there is one",
    )
    parser.add_argument(
        "--group",
        metavar="NAME",
        default=None,
        help="report this SRDF group's own C-space (the other joints held)",
    )
    parser.add_argument(
        "--hold",
        metavar="POSE",
        default=None,
        help="with --group: hold the other joints at this stored pose (default: neutral)",
    )


def xacro_options(args: argparse.Namespace) -> Any:
    """The xacro options of the command line; None when they are xacro's defaults.

    Raises:
        ValueError: An ``--arg`` is not ``NAME:=VALUE``.
    """
    if not (args.package_path or args.arg or args.xacro_unconfined):
        return None  # the library's defaults: xacro's module loads only for a xacro file
    from cspace._formats.xacro.expand import XacroOptions

    return XacroOptions.from_cli(
        args.package_path, args.arg, require_confinement=not args.xacro_unconfined
    )


def load_options(
    args: argparse.Namespace, root_joint: str | None = None, limits: str | None = None
) -> LoadOptions:
    """How the command line loads its robots, as the library takes it (one record).

    ``root_joint`` defaults to ``--root-joint``, ``limits`` to ``--limits``; ``--srdf
    auto`` and ``--limits auto`` are True (the robot's own file, looked for).

    Raises:
        ValueError: An ``--arg`` is not ``NAME:=VALUE``.
    """
    from cspace._model.options import LoadOptions

    srdf = getattr(args, "srdf", None)
    limits = limits or getattr(args, "limits", None)
    return LoadOptions(
        root_joint or args.root_joint,
        xacro_options(args),
        args.xacro,
        tuple(args.allow_dir),
        True if srdf == "auto" else srdf,
        getattr(args, "group", None),
        getattr(args, "hold", None),
        True if limits == "auto" else limits,
    )


def refuses_xacro_options(args: argparse.Namespace) -> bool:
    """Say on standard error why the xacro options are wrong, and whether they are.

    The check every command that reads robots makes first (an ``--arg`` without ``:=``).
    """
    from . import output

    try:
        xacro_options(args)
    except ValueError as exc:
        output.error(str(exc))
        return True
    return False


def robot_name(name: str) -> str:
    """How a name on the command line is read: ``name``, or the file it names, spelt so.

    A `FileName` (given after ``--``) comes back as a `FileName` that names the file
    (``./-``, ``./erd:x``); any other name as it is, unless it is ``-`` or ``erd:NAME``
    and a file of that name exists, which is refused: standard input or a bundled robot
    is never silently taken for a committed file, nor the file for them.

    Raises:
        FileUnreadableError: ``-`` or ``erd:NAME`` before ``--``, and a file of that name.
    """
    if isinstance(name, FileName):
        return FileName(_as_file(name))
    bundled = name.startswith(ERD_PREFIX)
    special = "standard input" if name == "-" else "a bundled robot" if bundled else ""
    if special and os.path.lexists(name):
        raise cspace.errors.FileUnreadableError(
            name,
            f"names a file here as well as {special}: put -- before file names to read the "
            f"file (cspace COMMAND [OPTIONS] -- FILE...)",
            code="ambiguous-name",
        )
    return name


def expand_patterns(names: list[str]) -> list[str]:
    """The files the names stand for, in the order named (see `robot_name`).

    A folder stands for the robot descriptions in it (`robot_files`); a pattern (before
    ``--``) for its matches, sorted (see `.patterns`), and for the file or folder of its
    very name when there is one, each file once. A pattern that matches nothing (and a
    folder without robot files) is kept, so that loading it reports the problem. Each
    file comes back a `FileName`; ``-`` and ``erd:NAME`` as they are. The files named
    after ``--`` are each named once, under their first name (``a.urdf``, ``./a.urdf``
    and ``.//a.urdf`` are one file); a name repeated before ``--`` is inspected again.

    Raises:
        FileUnreadableError: A pattern names too many files or walks too many folders;
            a name is ambiguous (`robot_name`).
    """
    out: list[str] = []
    after: set[str] = set()  # the files named after --
    for given in names:
        name = robot_name(given)
        if not isinstance(name, FileName) and (name == "-" or name.startswith(ERD_PREFIX)):
            out.append(name)
            continue
        found: list[str] = []
        if is_glob(name):
            found = [FileName(_as_file(m)) for m in expand_pattern(name)]
        if not found or os.path.lexists(name):
            found += _named(name, pattern=is_glob(name))
        seen = after if isinstance(given, FileName) else set()
        for path in found:
            key = _same_file(path)
            if key not in seen:
                out.append(path)
                seen.add(key)
    return out


def _named(name: str, pattern: bool) -> list[str]:
    """What the file or folder of this very name stands for (a missing one: itself)."""
    if os.path.isdir(name) and not os.path.islink(name):  # the robot files in it
        robots, fragments = in_folder(name)
        if not (robots or fragments):  # none: its error
            return [FileName(_as_file(name))]
        return [Searched(_as_file(os.path.normpath(m))) for m in robots]
    if pattern and not os.path.lexists(name):  # a pattern that matched nothing: its error
        return [name]
    return [FileName(_as_file(name))]


def _same_file(path: str) -> str:
    """One spelling of every name of one file: absolute, without ``.`` and repeated ``/``.

    ``..`` is kept: ``link/..`` need not be the folder it seems (and the file rules
    refuse such a path), so no error is folded into another name's report.
    """
    full = path if path.startswith("/") else os.path.join(os.getcwd(), path)
    return "/" + "/".join(p for p in full.split("/") if p not in ("", "."))


def _as_file(match: str) -> str:
    """A file's name, spelt so that it names the file (``./-``, ``./erd:x``)."""
    if match == "-" or match.startswith((ERD_PREFIX, "@")):
        return os.path.join(".", match)
    return match


def read_stdin() -> cspace.SourceFile:
    """Standard input as a source file named ``-`` (read up to the size limit, no further)."""
    from cspace._formats.shared.xmlio import MAX_FILE_BYTES

    return cspace.source_from_bytes("-", sys.stdin.buffer.read(MAX_FILE_BYTES + 1))


def load_report(
    name: str,
    args: argparse.Namespace,
    source: cspace.SourceFile | None = None,
    root_joint: str | None = None,
    limits: str | None = None,
) -> cspace.Report:
    """The report of one robot; ``source`` when its bytes are already read.

    ``-`` reads standard input (unless ``source`` is given), unless it is a `FileName`
    (see `robot_name`). ``root_joint`` defaults to ``--root-joint``, ``limits`` to
    ``--limits``.
    """
    from cspace._model.loader import inspect_with, report_of

    name = robot_name(name)
    options = load_options(args, root_joint, limits)
    if name == "-" or source is not None:
        source = source if source is not None else read_stdin()
        return report_of(source, options, file=None if name == "-" else name)
    if is_glob(name) and not os.path.lexists(name):  # a pattern that matched nothing
        raise cspace.errors.FileUnreadableError(name, "no file matches this pattern")
    return inspect_with(name, options)


def _named_robot(name: str) -> bool:
    """Whether a file's name says robot description (``.urdf``, ``.xml``, a USD name, ...)."""
    from cspace._formats.table import FORMATS

    suffixes = (".xml", *(suffix for row in FORMATS for suffix in row.suffixes))
    return name != "-" and str(name).lower().endswith(suffixes)


def load_document(
    name: str,
    args: argparse.Namespace,
    root_joint: str | None = None,
    *,
    reports: bool = True,
    limits: str | None = None,
) -> dict[str, Any]:
    """The JSON report document of a robot, or of a saved JSON report.

    A saved report is checked against the report's JSON Schema before it is used (and
    keeps the root joint it was made with). ``root_joint`` defaults to ``--root-joint``,
    ``limits`` to ``--limits`` (a saved report keeps the limits it was made with: one given
    for it alone, ``--old-limits`` or ``--new-limits``, is refused, ``limits-format``). A
    name is read as `robot_name` says. With ``reports=False`` (``check --baseline``)
    a file is read as a robot description only: JSON is refused (``not-a-robot``).
    """
    from cspace._reports.savedreport import looks_like_json, read_report_document

    name = robot_name(name)
    if name.startswith(ERD_PREFIX):
        return load_report(name, args, root_joint=root_joint, limits=limits).to_dict()
    source = read_stdin() if name == "-" else cspace.read_source(name, allow_dirs=args.allow_dir)
    if looks_like_json(source.data):
        if not reports:
            raise cspace.errors.NotARobotError(
                name,
                "is JSON, not a robot description (check --baseline reads robot files, "
                "never saved reports)",
            )
        if _named_robot(name):  # a saved report in a robot file's place says what it likes
            raise cspace.errors.NotARobotError(
                name,
                "is JSON, not a robot description: a file named as a robot file is read as "
                "one (a saved report is read under another name, such as report.json)",
            )
        if limits is not None:
            raise cspace.errors.NotARobotError(
                name,
                "is a saved report, which keeps the joint_limits.yaml it was made with: "
                "a joint_limits.yaml goes with a robot file",
                code="limits-format",
            )
        return read_report_document(name, source.data)
    return load_report(name, args, source, root_joint, limits).to_dict()
