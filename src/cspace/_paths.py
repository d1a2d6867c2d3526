"""Where a path a user names may lead: links only within their folder, never into ``.git``.

The rules `cspace.files` opens every file under, for the path itself: a file that is a
symbolic link must lead to a file in the folder the link stands in (or in an allowed
folder); every folder of a relative path (or of an absolute one below the current
folder, as CI scripts write them) that is a link must lead inside the folder it stands
in; no link may lead into a version-control folder (``.git``, ``.hg``, ``.svn``) the
path does not name; a chain of links too long to follow, a path longer than
`MAX_PATH_CHARS` and a NUL are refused. Nothing here opens a file.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from cspace.errors import FileUnreadableError

MAX_PATH_CHARS = 4096
"""Longest path cspace opens (Linux's ``PATH_MAX``)."""


def real_path(path: str, name: str | None = None) -> str:
    """``os.path.realpath(path)``; a chain of links too long to follow is refused.

    Python's ``realpath`` follows a link by recursing, so 1,200 links in a row would be
    a ``RecursionError``; the kernel itself follows at most 40.

    Raises:
        FileUnreadableError: The chain is too long (named ``name``, else ``path``).
    """
    try:
        return os.path.realpath(path)
    except (RecursionError, OSError):
        raise FileUnreadableError(
            name or path, "leads through too many links in a row", code="outside-tree"
        ) from None


def allowed_folders(
    file: str, allow_dirs: Sequence[str | os.PathLike[str]] = ()
) -> tuple[str, ...]:
    """Where ``file``'s links may lead, real: its folder and ``allow_dirs``.

    (An MJCF file's includes may reach its project's folder: `cspace._project`.)

    Raises:
        FileUnreadableError: An allowed folder is reached through a link out of its
            folder (see `check_granted_folder`).
    """
    folder = os.path.dirname(os.path.abspath(file))
    granted = [os.fspath(d) for d in allow_dirs]
    for given in granted:
        check_granted_folder(given)
    return tuple(real_path(d) for d in (folder, *granted))


def within(target: str, folders: Sequence[str]) -> bool:
    """True when the real path ``target`` lies in one of the real folders ``folders``."""
    return any(os.path.commonpath((target, folder)) == folder for folder in folders)


VCS_FOLDERS = (".git", ".hg", ".svn")
"""Version-control folders: nothing in one is ever read (a CI checkout's ``.git/config``
holds its token)."""


def in_version_control(target: str, folders: Sequence[str]) -> bool:
    """True when ``target`` (real) lies in a version-control folder below ``folders``.

    The folder's name in any case (``.GIT`` is ``.git`` on macOS and Windows).
    """
    for folder in folders:
        if os.path.commonpath((target, folder)) == folder:
            parts = os.path.relpath(target, folder).split(os.sep)
            if any(part.lower() in VCS_FOLDERS for part in parts[:-1]):
                return True
    return False


def _unnamed_version_control(name: str, real: str) -> bool:
    """True when ``real`` (where ``name`` leads) is in a VCS folder ``name`` does not name.

    A version-control folder is ``.git``, ``.hg`` or ``.svn``. Links (the file's own, or
    those among its folders) may lead into one although they stay within their folders
    (``g -> .git``, then ``g/config``): only a version-control folder written in the
    path (followed to its real path, and with no ``..`` after it) is the user's to read.
    """
    parts = real.split(os.sep)
    entered = {os.sep.join(parts[: i + 1]) for i, p in enumerate(parts[:-1]) if _vcs(p)}
    if not entered:
        return False
    written = os.path.join(os.getcwd(), name).split(os.sep)
    ups = [i for i, p in enumerate(written) if p == ".."]
    named = {
        real_path(os.sep.join(written[: i + 1]), name)
        for i, p in enumerate(written[:-1])
        if _vcs(p) and i > max(ups, default=-1)
    }
    return not entered <= named


def _vcs(name: str) -> bool:
    """Whether a folder's name is a version-control folder's (in any case)."""
    return name.lower() in VCS_FOLDERS


def check_links(name: str, allow_dirs: Sequence[str | os.PathLike[str]] = ()) -> None:
    """Refuse a path whose links lead out of the folders they stand in, or into ``.git``.

    The file itself may be a link only to a file in its own folder (after every link is
    followed) or in ``allow_dirs``; the folders of the path are checked by
    `check_folder_links`. No link, the file's own or a folder's of its path, may lead
    into a version-control folder (``.git``, ``.hg``, ``.svn``) that the path as written
    does not name: a committed ``g -> .git`` stays within its folder, yet ``g/config``
    is where a CI checkout keeps its token.

    Raises:
        FileUnreadableError: ``outside-tree``, naming the path (never the link's target).
    """
    check_folder_links(name, allow_dirs)
    real, allowed = real_path(name), allowed_folders(name, allow_dirs)
    if not within(real, allowed):
        raise FileUnreadableError(
            name,
            "is a link to a file outside its folder; cspace follows links only within the "
            "folder (name the target, or a wider folder with --allow-dir)",
            code="outside-tree",
        )
    if _unnamed_version_control(name, real):
        folder = os.path.dirname(os.path.abspath(name))
        what = (
            "a folder of this path is a link"
            if _unnamed_version_control(folder + os.sep + "x", os.path.join(allowed[0], "x"))
            else "is a link"
        )
        raise FileUnreadableError(
            name,
            f"{what} into a version-control folder (.git, .hg, .svn), which cspace never reads",
            code="outside-tree",
        )


def check_granted_folder(folder: str) -> None:
    """Refuse a folder the user grants (``--allow-dir``, ``--package-path``) through a link.

    The folder itself and every folder of its relative path (or of its path below the
    current folder) must not be a link out of the folder it stands in.

    Raises:
        FileUnreadableError: ``outside-tree``, naming the folder.
    """
    try:
        check_folder_links(os.path.join(folder, "x"))
    except FileUnreadableError as exc:
        raise FileUnreadableError(folder, exc.problem, code=exc.code) from None


def current_folder_spellings() -> list[str]:
    """The current folder as ``os.getcwd()`` spells it, and as ``$PWD`` does.

    ``$PWD`` only when it names the same folder (CI scripts write
    ``$GITHUB_WORKSPACE/...``, perhaps through links).
    """
    bases = [os.getcwd()]
    logical = os.environ.get("PWD", "")
    if os.path.isabs(logical) and logical not in bases:
        try:
            if os.path.samefile(logical, "."):
                bases.append(logical)
        except OSError:
            pass
    return bases


def _below_current_folder(name: str) -> tuple[str, list[str]] | None:
    """(base, parts) of a path whose folders are checked; None for other absolute paths.

    A relative path's parts from ``.``; an absolute path's parts below the current
    folder (as ``os.getcwd()`` or ``$PWD`` spells it: CI scripts write
    ``$GITHUB_WORKSPACE/...``).
    """
    if not os.path.isabs(name):
        return "", name.split(os.sep)
    for base in current_folder_spellings():
        base = base.rstrip(os.sep)
        if base and name.startswith(base + os.sep):
            return base, name[len(base) + 1 :].split(os.sep)
    return None


def check_folder_links(name: str, allow_dirs: Sequence[str | os.PathLike[str]] = ()) -> None:
    """Refuse a path with a folder that is a link out of the folder it stands in.

    Each folder named in a relative path (or in an absolute path below the current
    folder, as CI scripts name files in their checkout) that is a link must lead inside
    the folder it stands in (or into ``allow_dirs``), so a committed ``data -> ~`` does
    not turn ``data/traj.csv`` into ``~/traj.csv``. Other absolute prefixes (``/tmp`` is
    a link on some systems) and ``..`` are the user's to trust.

    Raises:
        FileUnreadableError: A NUL in the path, a path longer than
            `MAX_PATH_CHARS`, or a link out (``outside-tree``).
    """
    if "\0" in name:
        raise FileUnreadableError(name, "the path contains a NUL character")
    if len(name) > MAX_PATH_CHARS:
        raise FileUnreadableError(
            name[:200] + "...", f"the path is longer than {MAX_PATH_CHARS:,} characters"
        )
    below = _below_current_folder(name)
    if below is None:
        return
    base, parts = below
    extra = tuple(real_path(os.fspath(d)) for d in allow_dirs)
    for depth in range(1, len(parts)):
        if parts[depth - 1] in ("", ".", ".."):
            continue
        folder = os.path.join(base, *parts[:depth])
        if parts[depth] == ".." and os.path.islink(folder):
            raise FileUnreadableError(
                name,
                f"'..' follows the link '{os.path.join(*parts[:depth])}' in this path, and "
                "leads where the path does not say; cspace refuses it",
                code="outside-tree",
            )
        if os.path.islink(folder):
            outer = real_path(os.path.dirname(os.path.abspath(folder)), name)
            if not within(real_path(folder, name), (outer, *extra)):
                shown = os.path.join(*parts[:depth])
                raise FileUnreadableError(
                    name,
                    f"the folder '{shown}' in this path is a link out of its folder; "
                    "cspace follows links only within the folder they stand in",
                    code="outside-tree",
                )
