"""Where a collision mesh's file name leads, decided before anything is read.

A URDF ``<mesh filename>`` or an SDF ``<uri>`` is a name the file chose: it may be a
``package://PKG/...`` (the ROS package PKG, found as xacro's ``$(find PKG)`` finds it:
the robot file's own package and the ``--package-path`` folders,
`xacro.expand.ros_packages`), a ``model://NAME/...`` (SDF: the package or folder NAME
of the same), a ``file://`` path, a plain path (relative to the robot file's folder) or
a URL. A package is known by the name its ``package.xml`` gives or by its folder's
name, as Pinocchio's ``package_dirs`` find it (example-robot-data's files name
``package://example-robot-data``, whose ``package.xml`` says
``example_robot_descriptions``). `place` turns it into a file on disk, or says why it
cannot: an unknown package, a URL (cspace reads no network), a path that leads out of
the folders cspace may read (`folders`: the robot file's project, its packages and
``--allow-dir``; after every link is followed), into a version-control folder, or to no
file. It opens nothing; the mesh is read later through the one way in
(`cspace.files`), which checks it again.
"""

import os
import re
from collections.abc import Iterable, Mapping, Sequence

from cspace._formats.shared.collisions import shown
from cspace._paths import MAX_PATH_CHARS, in_version_control, real_path, within
from cspace._project import include_folders
from cspace._record import NamedTuple
from cspace.errors import FileUnreadableError

_SCHEME = re.compile(r"([A-Za-z][A-Za-z0-9+.-]*)://")
_PACKAGED = ("package", "model")


class MeshPlace(NamedTuple):
    """Where a mesh's name leads: ``path``, or ``reason`` it leads nowhere cspace reads.

    Attributes:
        name: The name as the file writes it.
        path: The real path of the file (every link followed), or None.
        reason: Why there is none (one line, the name not quoted), or None.
    """

    name: str
    path: str | None
    reason: str | None = None


def folders(
    robot_file: str, packages: Mapping[str, str], allow_dirs: Sequence[str] = ()
) -> tuple[str, ...]:
    """The real folders a robot's meshes may come from.

    Its project's folder (its own when it has none, `cspace._project`), its packages'
    folders and ``allow_dirs``.

    Raises:
        FileUnreadableError: An ``allow_dirs`` folder reached through a link out of its
            folder.
    """
    own = include_folders(robot_file, allow_dirs)
    return tuple(dict.fromkeys((*own, *(real_path(f) for f in packages.values()))))


def place(
    name: str,
    robot_file: str | None,
    packages: Mapping[str, str],
    allowed: Iterable[str],
) -> MeshPlace:
    """The file a mesh's ``name`` leads to, or why it leads to none (see the module).

    Args:
        name: The mesh's file name as written.
        robot_file: The robot file on disk (relative names are in its folder), or None
            (standard input: a relative name leads nowhere).
        packages: The ROS packages known, name to folder.
        allowed: The real folders meshes may come from (`folders`).
    """
    path, reason = _joined(name, robot_file, packages)
    if path is None:
        return MeshPlace(name, None, reason)
    try:
        real = real_path(path)
    except FileUnreadableError:
        return MeshPlace(name, None, "it leads through too many links in a row")
    granted = list(allowed)
    if not within(real, granted):
        return MeshPlace(
            name,
            None,
            "it leads out of the folders cspace reads (the robot's project, its packages "
            "and --allow-dir)",
        )
    if in_version_control(real, granted):
        return MeshPlace(name, None, "it leads into a version-control folder")
    if not os.path.isfile(real):
        return MeshPlace(name, None, "no such file (or not a regular file)")
    return MeshPlace(name, real)


def _joined(
    name: str, robot_file: str | None, packages: Mapping[str, str]
) -> tuple[str | None, str | None]:
    """The path ``name`` names, not yet followed, or None and why."""
    if not name.strip():
        return None, "the mesh's file name is empty"
    if "\0" in name or len(name) > MAX_PATH_CHARS:
        return None, "the mesh's file name is no path (a NUL, or too long)"
    scheme = _SCHEME.match(name)
    if scheme is not None:
        kind = scheme.group(1).lower()
        rest = name[scheme.end() :]
        if kind in _PACKAGED:
            package, _, inside = rest.partition("/")
            found = packages.get(package) or _by_folder(package, packages)
            if found is None:
                what = "package" if kind == "package" else "model"
                return None, (
                    f"{what} '{shown(package)}' is not known (give a folder that holds it "
                    "with --package-path, or put its package.xml above the robot file)"
                )
            return os.path.join(found, inside), None
        if kind != "file":
            return None, f"a {shown(kind)}:// URL: cspace reads no network"
        name = rest
    if os.path.isabs(name):
        return os.path.normpath(name), None
    if robot_file is None:
        return None, "a relative file name, and the robot file is read from standard input"
    return os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(robot_file)), name)), None


def _by_folder(package: str, packages: Mapping[str, str]) -> str | None:
    """The package whose folder is called ``package`` (Pinocchio's ``package_dirs`` rule)."""
    named = [folder for folder in packages.values() if os.path.basename(folder) == package]
    return named[0] if named else None
