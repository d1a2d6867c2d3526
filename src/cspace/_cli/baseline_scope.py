"""What ``check --baseline`` may look at: the folders being checked, one key per file.

**The folders being checked** are the folders named on the command line, each with its
subfolders, and the folder of each file named (with its subfolders too; for a pattern,
the folder before its first wildcard), links followed. A folder reached through a link
out of the folder it stands in (`cspace.files.check_granted_folder`) is none of them.

**A baseline entry's key** is its file's path as `cspace.files.open_input` reads it:
relative to the current folder (where ``cspace inspect`` wrote the baseline: in CI, the
repository's root), with ``.``, ``..`` and repeated ``/`` folded and links followed.
Every spelling of one file has one key, so a baseline holds one report per file, and a
robot named ``./a.urdf`` finds the report of ``a.urdf``. The path is followed by
`cspace._reach`: one that leads outside the folders being checked is looked at no further
than the way there, and neither opened nor found to exist or not (an ``outside``
entry); one hidden in them (`HIDDEN`) is not read either, unless it is named. ``-`` and
``erd:NAME`` are robots, not files: keys of their own.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import NamedTuple

from cspace._reach import Folders
from cspace.errors import FileUnreadableError
from cspace.files import check_granted_folder, real_path

_WILDCARDS = ("*", "?", "[")

FILE, OUTSIDE, HIDDEN, ROBOT_NAME = "file", "outside", "hidden", "name"
"""Where an entry lies: in the folders checked, outside them, hidden in them (a name
below the folder that starts with ``.``: ``.git``, or a ``.env`` a CI step wrote; a
folder's search never lists it), or no file at all (``-``, ``erd:NAME``)."""


class Place(NamedTuple):
    """A baseline entry's (or a robot's) key, and where it lies.

    Attributes:
        key: One string per file (see the module).
        where: `FILE`, `OUTSIDE`, `HIDDEN` or `ROBOT_NAME`.
        exists: A file (or anything) is there; False when not looked at.
        walked: It lies in a folder named, whose robots a walk found: a file there
            that the walk left out is checked all the same.
    """

    key: str
    where: str
    exists: bool = False
    walked: bool = False


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
        if path == "-" or path.startswith("erd:"):
            return Place(path, ROBOT_NAME)
        reached = self.folders.reach(self.cwd, _below_current_folder(path))
        if reached.real is None:
            return Place(os.path.normpath(os.path.join(self.cwd, path)), OUTSIDE)
        real = reached.real
        below = real.startswith(self.cwd) and real[len(self.cwd) : len(self.cwd) + 1] == os.sep
        key = real[len(self.cwd) + 1 :] if below else os.path.relpath(real, self.cwd)
        if key == "-" or key.startswith(("erd:", "@")):  # a file of that name, not the robot
            key = os.path.join(".", key)
        if f"{os.sep}." in real[len(reached.within[-1]) :]:  # a name below it starts with .
            return Place(key, HIDDEN)
        walked = any(folder in self.walked for folder in reached.within)
        return Place(key, FILE, reached.exists, walked)


def _folder_of(name: str) -> str | None:
    """The folder a file or pattern named lies in (None: no file, ``-`` or ``erd:NAME``)."""
    if not os.path.lexists(name):
        if name == "-" or name.startswith("erd:"):
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
    bases = [os.getcwd()]
    logical = os.environ.get("PWD", "")
    if os.path.isabs(logical) and logical not in bases:
        try:
            if os.path.samefile(logical, "."):
                bases.append(logical)
        except OSError:
            pass
    for base in bases:
        base = base.rstrip(os.sep)
        if path == base:
            return "."
        if path.startswith(base + os.sep):
            return path[len(base) + 1 :]
    return path
