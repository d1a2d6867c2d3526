"""The files read beside a robot file: its SRDF and MoveIt's joint_limits.yaml.

Each is the file an option names (``--srdf FILE``, ``--limits FILE``) or the one
``auto`` finds in the robot's project; the loader imports this module only when one is
asked for.
"""

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

from cspace._findings import Diagnostic, finding
from cspace._formats.shared.description import RobotDescription
from cspace._formats.shared.erd import ERD_PREFIX
from cspace._model.options import LoadOptions
from cspace.errors import NotARobotError
from cspace.files import path_text

if TYPE_CHECKING:
    from cspace._formats.table import Format
    from cspace._model._limits_file import Applied


def refuse_srdf_for(srdf: str | os.PathLike[str] | bool | None, row: "Format", path: str) -> None:
    """Refuse an SRDF named for a robot of a format no SRDF goes with.

    (``--srdf auto`` finds none for such a robot.)

    Raises:
        NotARobotError: ``srdf`` names a file and ``row`` takes no SRDF (``srdf-format``).
    """
    if not row.srdf and srdf is not None and not isinstance(srdf, bool):
        raise NotARobotError(
            path,
            f"an SRDF goes with a URDF, and this robot is {row.name.upper()}",
            code="srdf-format",
        )


def srdf_to_read(
    srdf: str | os.PathLike[str] | bool | None,
    row: "Format",
    on_disk: str | None,
    path: str,
    allow_dirs: Sequence[str | os.PathLike[str]],
    description: RobotDescription,
) -> "tuple[str | None, Sequence[str | os.PathLike[str]], Diagnostic | None]":
    """The SRDF to read (the one named, the one found, or None), its folders, a note.

    ``srdf=True`` (``--srdf auto``) looks in the robot's project for the SRDF of its
    robot (`cspace._model.semantics.find_srdf`); the one it finds may lead anywhere in
    the folders it may read, as MJCF includes do. When it finds none, the note
    (``srdf-not-found``) says where it looked.
    """
    refuse_srdf_for(srdf, row, path)
    if srdf is None or srdf is False or not row.srdf:
        return None, allow_dirs, None
    if srdf is True:
        from cspace._model._srdf_find import Search, srdf_folders
        from cspace._model.semantics import not_found, search

        if on_disk is None:
            nowhere = Search(None, (), "the robot is read from standard input, in no folder")
            return None, allow_dirs, not_found(nowhere, path, description.name)
        folders = srdf_folders(on_disk, allow_dirs)
        robot = path.removeprefix(ERD_PREFIX) if path.startswith(ERD_PREFIX) else None
        parts = frozenset(
            [*(link.name for link in description.links), *(j.name for j in description.joints)]
        )
        found = search(on_disk, robot, folders, description.name or None, parts)
        note = None if found.path else not_found(found, on_disk, description.name)
        return found.path, (*allow_dirs, *folders), note
    if path_text(srdf).lower().endswith(".xacro"):  # its groups are xacro's to make
        raise NotARobotError(
            path_text(srdf),
            "an SRDF that xacro makes: --srdf reads an SRDF file (expand this one with "
            "xacro, then give what it writes)",
            code="srdf-format",
        )
    return path_text(srdf), allow_dirs, None


def limits_of(
    options: LoadOptions,
    format_name: str,
    description: RobotDescription,
    srdf_path: str | None,
    file: str | os.PathLike[str] | None,
    path: str,
) -> "tuple[Applied | None, Diagnostic | None]":
    """The joint_limits.yaml ``options.limits`` names, applied (`limits_for`).

    Args:
        options: The load's options (``limits`` a path, or True for ``auto``).
        format_name: The robot's format (its row of the format table).
        description: The robot as its reader read it.
        srdf_path: The SRDF read with it, or None (``auto`` looks beside it first).
        file: The robot file's path on disk, or None (standard input).
        path: The robot's path as the report names it.

    Returns:
        The file applied and None; or None and, for ``auto`` finding none, a note of
        where it looked (None when ``options.limits`` asks for none).
    """
    if options.limits is None or options.limits is False:
        return None, None
    from cspace._formats.table import by_name
    from cspace._model._limits_file import Applied

    out = limits_for(
        options.limits,
        by_name(format_name).srdf,
        None if file is None else path_text(file),
        path,
        options.allow_dirs,
        description,
        srdf_path,
    )
    if isinstance(out, Applied):
        return out, None
    return None, out


LIMITS_NAME = "joint_limits.yaml"
"""The file ``--limits auto`` looks for (MoveIt Setup Assistant's ``config/`` file)."""


def find_limits(
    file: str, folders: tuple[str, ...], name: str | None, srdf: str | None
) -> tuple[str | None, Diagnostic | None]:
    """``--limits auto``: the robot's joint_limits.yaml, or None and where it looked.

    Beside the SRDF read with the robot first (MoveIt's ``config/`` holds both), then in
    the places ``--srdf auto`` looks (`cspace._model._srdf_find.moveit_places`: beside
    the URDF, ``config/``, ``../config``, each ``*_moveit_config`` package's ``config/``
    beside the robot's package), nearest first, inside ``folders`` only.
    """
    from cspace._model._srdf_find import found_in, moveit_places
    from cspace._paths import real_path

    places = moveit_places(file, folders, name)
    if srdf is not None:
        shown = os.path.dirname(srdf)
        places.insert(0, (shown, real_path(os.path.dirname(os.path.abspath(srdf)))))
    for shown, real in places:
        if found_in(real, LIMITS_NAME, folders) is not None:
            return os.path.join(shown, LIMITS_NAME), None
    looked = ", ".join(dict.fromkeys(shown or "." for shown, _ in places)) or "nowhere"
    note = finding(
        "limits-file-not-found",
        None,
        f"--limits auto found no {LIMITS_NAME} of the robot; looked in {looked}",
    )
    return None, note


def limits_for(
    limits: str | os.PathLike[str] | bool | None,
    takes_srdf: bool,
    file: str | None,
    robot: str,
    allow_dirs: Sequence[str | os.PathLike[str]],
    description: RobotDescription,
    srdf: str | None,
) -> "Applied | Diagnostic | None":
    """The ``limits`` option applied to a robot read from ``robot`` (``file`` on disk).

    A file named is read (links only inside its folder and ``allow_dirs``); True
    (``--limits auto``) looks for the robot's (`find_limits`), and gives the
    ``limits-file-not-found`` note when there is none, or when the one found names none
    of the robot's joints (another robot's); None and False read none, and so
    does True for a format MoveIt does not read (``takes_srdf`` False).

    Raises:
        NotARobotError: A file is named for a robot of another format than URDF
            (``limits-format``).
        FileUnreadableError: The file named or found cannot be read.
        InvalidElementError: It is no joint_limits.yaml (`read_limits`).
    """
    from cspace._formats.joint_limits.reader import read_limits
    from cspace._model._limits_file import apply_limits

    if limits is None or limits is False:
        return None
    if not takes_srdf:
        if limits is True:
            return None
        raise NotARobotError(
            robot, "MoveIt's joint_limits.yaml goes with a URDF", code="limits-format"
        )
    if limits is True:
        if file is None:
            return finding(
                "limits-file-not-found",
                None,
                f"--limits auto found no {LIMITS_NAME}: the robot is read from standard input",
            )
        from cspace._model._srdf_find import srdf_folders

        folders = srdf_folders(file, allow_dirs)
        found, note = find_limits(file, folders, description.name or None, srdf)
        if found is None:
            return note
        read = read_limits(found, (*allow_dirs, *folders))
        names = {spec.name for spec in description.joints}
        ours = [e for e in read.joints if e.name in names or e.name.rpartition("/")[0] in names]
        if read.joints and not ours:
            return finding(  # another robot's, beside this one's file: not taken
                "limits-file-not-found",
                None,
                f"--limits auto found {found}, which names none of the robot's joints: "
                "not read (--limits FILE reads it)",
            )
        return apply_limits(description, robot, read)
    named = path_text(limits, "a joint limits file's path")
    return apply_limits(description, robot, read_limits(named, allow_dirs))
