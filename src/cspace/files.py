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

from cspace._paths import MAX_PATH_CHARS as MAX_PATH_CHARS
from cspace._paths import check_folder_links, check_links
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
