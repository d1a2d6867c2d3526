"""What ``check --baseline`` may look at: the folders being checked, one key per file.

**The folders being checked** are the folders named on the command line, each with its
subfolders, and the folder of each file named (with its subfolders too; for a pattern,
the folder before its first wildcard), links followed. A folder reached through a link
out of the folder it stands in (`cspace.files.check_granted_folder`) is none of them.

**A baseline entry** is the file its path names as written, relative to the current
folder (where ``cspace inspect`` wrote the baseline: in CI, the repository's root).
Where it lies is decided first on the path as written (``.``, ``..`` and repeated ``/``
folded, links not followed), looking at nothing: outside the folders being checked
(`OUTSIDE`), or hidden in them (`HIDDEN`: a name below the folder that starts with
``.``), it is not read (unless it is named). Then the path is followed by
`cspace._reach`, its folders' links followed inside the folders and the last name not
followed: an entry that is there (a link too) is a `FILE`, read by its path as written
(`Place.path`) through `cspace.files.open_input`, which follows a link only within its
folder; one whose folders lead out of the folders being checked through a link in them
is `LINKED`: never opened, nor looked at past the link; one whose folders' links lead
into a version-control folder (``g/config`` with ``g -> .git``) is `VCS`: hidden,
never opened (`open_input` would refuse it as well).

**Its key**, one string per file: the path relative to the current folder, its folders'
links followed and the last name as written. Every spelling of one file has one key,
so a baseline holds one report per file and a robot named ``./a.urdf`` finds the
report of ``a.urdf``; a link is a file of its own, keyed by its own name (a baseline
written before a robot was made a link keeps finding it). ``-`` and ``erd:NAME`` are
robots, not files: keys of their own.
"""

import os
from collections.abc import Sequence

from cspace._formats.shared.erd import ERD_PREFIX
from cspace._paths import check_granted_folder, in_version_control, real_path
from cspace._reach import MAX_PATH_CHARS, Folders
from cspace._record import NamedTuple
from cspace.errors import FileUnreadableError

_WILDCARDS = ("*", "?", "[")

FILE, OUTSIDE, HIDDEN, LINKED, ROBOT_NAME = "file", "outside", "hidden", "linked", "name"
"""Where an entry lies: in the folders checked, outside them, hidden in them (a name
below the folder that starts with ``.``: ``.git``, or a ``.env`` a CI step wrote; a
folder's search never lists it), in them but behind a link out of them, or no file at
all (``-``, ``erd:NAME``)."""

VCS = "vcs"
"""Where an entry lies: hidden in the folders checked, as its folders' links lead
(into ``.git``, ``.hg`` or ``.svn``) though not as its path is written."""


class Place(NamedTuple):
    """A baseline entry's (or a robot's) key, and where it lies.

    Attributes:
        key: One string per file (see the module).
        where: `FILE`, `OUTSIDE`, `HIDDEN`, `VCS`, `LINKED` or `ROBOT_NAME`.
        exists: A file, a link or anything is there; False when not looked at.
        walked: It lies in a folder named (as written, or where its folders' links
            lead), whose robots a walk found: a file there that the walk left out is
            checked all the same.
        path: The path to read it by: as written, ``.`` and repeated ``/`` folded.
    """

    key: str
    where: str
    exists: bool = False
    walked: bool = False
    path: str = ""


class Scope:
    """The folders being checked, from the names on the command line."""

    def __init__(self, names: Sequence[str]) -> None:
        """The folders ``names`` (files, folders, patterns, ``erd:NAME``, ``-``) check."""
        self.cwd = real_path(os.getcwd())
        walked: list[str] = []
        folders: list[str] = []
        for name in names:
            named = os.path.isdir(name) and not os.path.islink(name)
            folder = _real_folder(name if named else _folder_of(name))
            if folder is not None:
                (walked if named else folders).append(folder)
        self.walked = frozenset(walked)
        self.folders = Folders([*walked, *folders])
        self._depths = sorted(
            {1 if f == os.sep else len(f.split(os.sep)) for f in self.folders.folders}
        )
        self._places: dict[str, Place] = {}

    def key(self, path: str) -> str:
        """The key of the file ``path`` names (see the module)."""
        return self.place(path).key

    def place(self, path: str) -> Place:
        """``path``'s key and where it lies, looking at nothing outside the folders."""
        found = self._places.get(path)
        if found is None:
            found = self._places[path] = self._find(path)
        return found

    def _find(self, path: str) -> Place:
        if path == "-" or path.startswith(ERD_PREFIX):
            return Place(path, ROBOT_NAME, path=path)
        spelt = _below_current_folder(path)
        written = os.path.normpath(os.path.join(self.cwd, spelt))  # as written: no link
        holders = self._holding(written)
        if not holders or "\0" in path or len(path) > MAX_PATH_CHARS:
            return Place(written, OUTSIDE, path=path)
        read = _as_file(_folded(spelt))
        reached = self.folders.reach(self.cwd, spelt, last=False)
        key = read if reached.real is None else self._relative(reached.real)
        if f"{os.sep}." in written[len(holders[-1].rstrip(os.sep)) :]:  # a name below it: .x
            return Place(key, HIDDEN, path=read)
        walked = not self.walked.isdisjoint(holders)  # as written, or where its links lead
        if reached.real is None:  # through a link in the folders: not looked at past it
            return Place(key, LINKED, walked=walked, path=read)
        if in_version_control(reached.real, reached.within[:1]) and not in_version_control(
            written, holders[:1]
        ):
            return Place(key, VCS, path=read)
        walked = walked or not self.walked.isdisjoint(reached.within)
        return Place(key, FILE, reached.exists, walked, read)

    def _relative(self, real: str) -> str:
        """A real path relative to the current folder (a key)."""
        below = real.startswith(self.cwd) and real[len(self.cwd) : len(self.cwd) + 1] == os.sep
        return _as_file(real[len(self.cwd) + 1 :] if below else os.path.relpath(real, self.cwd))

    def _holding(self, path: str) -> list[str]:
        """The folders being checked that hold the absolute path ``path``, outermost first.

        As written: a prefix of ``path``, no link followed (in time linear in its length).
        """
        names = path.split(os.sep)
        depths = (d for d in self._depths if d <= len(names))
        return [
            p
            for p in (os.sep.join(names[:d]) or os.sep for d in depths)
            if p in self.folders.folders
        ]


def _folded(path: str) -> str:
    """``path`` with ``.`` and repeated ``/`` folded (``..`` kept: links decide it)."""
    names = [n for n in path.split(os.sep) if n not in ("", ".")]
    return (os.sep if path.startswith(os.sep) else "") + os.sep.join(names) or "."


def _as_file(path: str) -> str:
    """A path spelt so that it names the file (``./-``, ``./erd:x``, ``./@x``)."""
    if path == "-" or path.startswith((ERD_PREFIX, "@")):
        return os.path.join(".", path)
    return path


def _folder_of(name: str) -> str | None:
    """The folder a file or pattern named lies in (None: no file, ``-`` or ``erd:NAME``)."""
    if not os.path.lexists(name):
        if name == "-" or name.startswith(ERD_PREFIX):
            return None
        parts = name.split(os.sep)
        fixed = next((i for i, p in enumerate(parts) if any(w in p for w in _WILDCARDS)), None)
        if fixed is not None:  # a pattern: the folder before its first wildcard
            return os.sep.join(parts[:fixed]) or (os.sep if name.startswith(os.sep) else ".")
    return os.path.dirname(name) or "."


def _real_folder(folder: str | None) -> str | None:
    """The real path of a folder named, unless it is none or reached through a link out."""
    if folder is None or not os.path.isdir(folder):
        return None
    try:
        check_granted_folder(folder)
        return real_path(folder)
    except FileUnreadableError:
        return None


def _below_current_folder(path: str) -> str:
    """``path``, relative to the current folder when it is an absolute path below it.

    As the current folder is spelt by ``os.getcwd()`` or ``$PWD`` (CI scripts write
    ``$GITHUB_WORKSPACE/...``); any other absolute path is followed from ``/``.
    """
    if not os.path.isabs(path):
        return path
    from cspace._paths import current_folder_spellings

    for base in current_folder_spellings():
        base = base.rstrip(os.sep)
        if path == base:
            return "."
        if path.startswith(base + os.sep):
            return path[len(base) + 1 :]
    return path
