"""A robot file's project: the folder its includes may reach without flags.

A package ships its robot files beside the files they include (metaworld's scenes
include ``../objects/...``), so an MJCF file's includes and attached models may come
from anywhere in its project's folder: the nearest folder above the file, its own
included, that holds a version-control root (``.git``, ``.hg``) or a ROS
``package.xml``, or else the top of the Python package the file lies in (the highest
folder of a chain holding ``__init__.py``, which stops at a folder with a marker).

Never a home folder (``$HOME``, the user's own from the password database, or any
folder directly in ``/home``), the file system's root, or a folder above a home: a file
with no project below them is read with its own folder only. Nothing in a project's
version-control folder (``.git``, ``.hg``, ``.svn``) is ever read.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from cspace._paths import allowed_folders, real_path

PROJECT_MARKERS = (".git", ".hg", "package.xml")
"""What marks a project's top folder: a version-control root, a ROS package."""

MAX_PROJECT_CLIMB = 64
"""Most folders climbed from a file to find its project."""


def _homes() -> tuple[str, ...]:
    homes = {os.path.expanduser("~")}
    try:
        import pwd

        homes.add(pwd.getpwuid(os.getuid()).pw_dir)
    except (ImportError, KeyError, OSError):
        pass
    return tuple(real_path(h) for h in homes if h and os.path.isabs(h))


def _refused(folder: str, homes: Sequence[str]) -> bool:
    """The root, a home folder, a folder above one, or a folder directly in /home."""
    if os.path.dirname(folder) in ("/", "/home", "/Users") or folder == "/":
        return True
    return any(os.path.commonpath((home, folder)) == folder for home in homes)


def _marked(folder: str) -> bool:
    return any(os.path.lexists(os.path.join(folder, m)) for m in PROJECT_MARKERS)


def project_folder(file: str) -> str | None:
    """The real folder of the project ``file`` belongs to, or None (see the module)."""
    homes = _homes()
    folder = real_path(os.path.dirname(os.path.abspath(file)))
    package_top: str | None = None
    for _ in range(MAX_PROJECT_CLIMB):
        if _refused(folder, homes):
            return package_top
        if _marked(folder):
            return folder
        if os.path.isfile(os.path.join(folder, "__init__.py")):
            package_top = folder
        elif package_top is not None:
            return package_top
        parent = os.path.dirname(folder)
        if parent == folder:
            break
        folder = parent
    return package_top


def include_folders(
    file: str, allow_dirs: Sequence[str | os.PathLike[str]] = ()
) -> tuple[str, ...]:
    """Where an MJCF file's includes and attached models may come from, real folders.

    Its project's folder (its own when it belongs to none) and ``allow_dirs``.

    Raises:
        FileUnreadableError: An ``allow_dirs`` folder is reached through a link out of
            its folder.
    """
    own = allowed_folders(file, allow_dirs)
    project = project_folder(file)
    return own if project is None else (project, *own[1:])
