"""One way in and one way out: how cspace opens every file it reads and writes.

Every file cspace reads is untrusted: robot files and their includes, saved reports,
vector files, ``@FILE`` configurations, and whatever a pull request commits beside them.
They are all opened by `open_input`, under the same rules:

- **no link out of its folder**: the file, if it is a symbolic link, must lead to a file
  inside the folder the link stands in (or one of the allowed folders); and in a
  relative path (or an absolute one below the current folder, as CI scripts write
  them), every folder that is a link must lead inside the folder it stands in, so a
  committed ``data -> ~`` does not turn ``data/traj.csv`` into ``~/traj.csv``; a chain
  of links too long to follow and a path longer than 4,096 characters are refused;
- **regular files only**: the file is opened without blocking and checked through the
  open descriptor (``fstat``), so a FIFO, a device or a socket is refused at once,
  never read, and what is read is what was checked;
- **a size cap** for each kind of file, checked before reading and while reading;
- **nothing quoted from a refused file**: a refused file is not read, so no message
  can show its content.

Every file cspace writes goes through `open_output`: never through a link, never
over anything but a regular file; the bytes go to a new file beside the target (made
with ``O_EXCL``; mode ``0o666`` less the umask, or the read and write bits of the file
it replaces, so never an exec bit), which replaces the target by an atomic rename only
once everything is written. A run that fails leaves the old file as it was.
"""

from __future__ import annotations

import contextlib
import os
import stat
from collections.abc import Iterator, Sequence
from typing import IO, Any

from cspace.errors import FileUnreadableError, OutputError

__all__ = [
    "MAX_PATH_CHARS",
    "MAX_READ_BYTES",
    "open_input",
    "open_output",
    "read_input",
]
"""The public names; the other functions here are the checks they are made of."""

MAX_READ_BYTES = 64 * 1024 * 1024
"""Default size cap of a file read whole (64 MiB, the robot file's)."""

_OPEN_FLAGS = os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | os.O_NOCTTY


def path_text(path: object, what: str = "a robot file's path") -> str:
    """A path given as ``str`` or ``os.PathLike[str]``, as text.

    Raises:
        ArgumentTypeError: Anything else (None, a number, bytes).
    """
    from cspace.errors import ArgumentTypeError

    try:
        name = os.fspath(path)  # type: ignore[call-overload]
    except TypeError:
        name = None
    if not isinstance(name, str):
        raise ArgumentTypeError(
            f"{what} must be a str or os.PathLike[str], not {type(path).__name__}",
            argument="path",
        )
    return name


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


def file_kind(mode: int) -> str:
    """What a non-regular file is, in words (``FIFO (named pipe)``, ``socket``, ...)."""
    kinds = (
        (stat.S_ISDIR, "directory"),
        (stat.S_ISFIFO, "FIFO (named pipe)"),
        (stat.S_ISCHR, "character device"),
        (stat.S_ISBLK, "block device"),
        (stat.S_ISSOCK, "socket"),
        (stat.S_ISLNK, "symbolic link"),
    )
    return next((kind for test, kind in kinds if test(mode)), "special file")


def open_input(
    path: str | os.PathLike[str],
    *,
    max_bytes: int | None = MAX_READ_BYTES,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    what: str = "file",
) -> IO[bytes]:
    """Open an untrusted file for reading, under the rules of the module's docstring.

    Args:
        path: The file, as the user named it.
        max_bytes: Refuse a file larger than this (None: no cap, for files read a line
            at a time in bounded memory).
        allow_dirs: Folders, besides the file's own, that links may lead into.
        what: What the file is, for messages (``robot file``, ``vector file``, ...).

    Returns:
        A binary stream of the regular file, positioned at its start (the caller closes
        it); reading more than ``max_bytes`` from it is the caller's to refuse, see
        `read_input`.

    Raises:
        FileUnreadableError: Missing, a link out of its folder, not a regular file, too
            large, or unreadable (``file-unreadable`` or ``outside-tree``).
    """
    name = path_text(path, f"a {what}'s path")
    check_links(name, allow_dirs)
    try:
        fd = os.open(name, _OPEN_FLAGS)
    except FileNotFoundError:
        raise FileUnreadableError(name, "no such file") from None
    except OSError as exc:
        raise FileUnreadableError(name, f"cannot read: {exc.strerror or exc}") from None
    try:
        mode = os.fstat(fd)
        if stat.S_ISDIR(mode.st_mode):
            raise FileUnreadableError(name, f"is a directory, not a {what}")
        if not stat.S_ISREG(mode.st_mode):
            raise FileUnreadableError(
                name,
                f"is a {file_kind(mode.st_mode)}, not a regular file; cspace reads only files",
            )
        if max_bytes is not None and mode.st_size > max_bytes:
            raise FileUnreadableError(
                name,
                f"{what} is {mode.st_size:,} bytes, larger than the {max_bytes:,}-byte limit",
            )
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_input(
    path: str | os.PathLike[str],
    *,
    max_bytes: int = MAX_READ_BYTES,
    allow_dirs: Sequence[str | os.PathLike[str]] = (),
    what: str = "file",
) -> bytes:
    """The bytes of an untrusted file, read once (see `open_input`).

    Raises:
        FileUnreadableError: As `open_input`, or the file grew past
            ``max_bytes`` while it was read.
    """
    name = path_text(path, f"a {what}'s path")
    with open_input(name, max_bytes=max_bytes, allow_dirs=allow_dirs, what=what) as stream:
        try:
            data = stream.read(max_bytes + 1)
        except OSError as exc:
            raise FileUnreadableError(name, f"cannot read: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise FileUnreadableError(name, f"{what} is larger than the {max_bytes:,}-byte limit")
    return data


def open_output(path: str, binary: bool) -> contextlib.AbstractContextManager[IO[Any]]:
    """A file to write (bytes, or UTF-8 text), put in place of ``path`` once it is whole.

    The target must not be a symbolic link, nor anything but a regular file (a FIFO, a
    device, a folder); a folder of the path that is a link must lead inside the folder it
    stands in, as for inputs. The stream writes a new file beside the target (created
    with ``O_EXCL | O_NOFOLLOW``; mode ``0o666`` less the umask, or the read and write
    bits of the file it replaces: never an exec bit), renamed over the target when the
    block ends; on an error it is removed, and the target is untouched.

    Raises:
        OutputError: The target is a link or not a regular file, its folder is a link out
            of its folder, or the file cannot be written (``bad-output``).
    """
    return _atomic(path, binary)


@contextlib.contextmanager
def _atomic(path: str, binary: bool) -> Iterator[IO[Any]]:
    target = path_text(path, "an output's path")
    old_mode = _check_target(target)
    folder = os.path.dirname(os.path.abspath(target))
    temporary = os.path.join(folder, f".cspace-{os.urandom(6).hex()}.tmp")  # any name length
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC
    try:
        fd = os.open(temporary, flags, 0o666)
    except OSError as exc:
        raise OutputError(target, f"cannot write: {exc.strerror or exc}") from None
    done = False
    try:
        with os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding="utf-8") as stream:
            if old_mode is not None:  # the file it replaces: its read and write bits only
                os.fchmod(stream.fileno(), stat.S_IMODE(old_mode) & 0o666)
            yield stream
        _check_target(target)  # nothing was put in its place meanwhile
        os.replace(temporary, target)
        done = True
    except OSError as exc:
        raise OutputError(target, f"cannot write: {exc.strerror or exc}") from None
    finally:
        if not done:
            with contextlib.suppress(OSError):
                os.unlink(temporary)


def _check_target(target: str) -> int | None:
    """The mode of the regular file ``target`` replaces (None: no file there yet).

    Raises:
        OutputError: A link, or not a regular file, or a folder on the way a link out.
    """
    try:
        check_folder_links(target)
    except FileUnreadableError as exc:
        raise OutputError(target, exc.problem) from None
    try:
        mode = os.lstat(target).st_mode
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise OutputError(target, f"cannot write: {exc.strerror or exc}") from None
    if stat.S_ISLNK(mode):
        raise OutputError(
            target, "is a symbolic link; cspace never writes through a link (remove it first)"
        )
    if not stat.S_ISREG(mode):
        raise OutputError(
            target,
            f"is a {file_kind(mode)}, not a regular file; cspace writes only regular files "
            "(for standard output, give -)",
        )
    return mode
