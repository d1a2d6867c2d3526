"""Glob patterns given in quotes (as CI scripts do), expanded without following links.

``glob.glob(recursive=True)`` follows links to folders: a pull request that adds
``robots/up -> ..`` makes ``'robots/**/*.urdf'`` search forever, and ``robots/etc ->
/etc`` makes files outside the repository count as named by the user. Here the walk
never enters a linked folder, visits at most `MAX_FOLDERS` folders, and yields at
most `MAX_MATCHES` files; ``**`` matches any number of folders (none included),
``*``, ``?`` and ``[...]`` match within one name, and names starting with ``.`` are
matched only by a pattern that starts with ``.``, as in the shell. The walk is a loop over
a stack of its own, not a recursion: a pull request can commit a thousand nested folders.

A name with ``*``, ``?`` or ``[`` is a pattern, unless it is a `FileName` (given after
``--``); when a file or folder of that very name exists, it is named too, beside the
pattern's matches (a committed folder named ``**`` can neither stand in for the files a
CI pattern names nor hide behind them). In a relative pattern, the folders before the
first wildcard must not be links: ``robots -> /`` would make ``'robots/**/*.urdf'`` walk
the whole machine.
"""

from __future__ import annotations

import os
from fnmatch import fnmatchcase

from cspace._formats.shared.erd import ERD_PREFIX
from cspace.errors import FileUnreadableError

MAGIC = ("*", "?", "[")
MAX_MATCHES = 10_000
"""Most files one pattern may name."""
MAX_FOLDERS = 100_000
"""Most folders one pattern's walk may visit."""


class FileName(str):
    """A name given after ``--``: a file's (or folder's) path, whatever it is spelt like.

    Never a pattern, never ``erd:NAME``, never ``-`` for standard input. The command
    line marks each name after ``--`` so before parsing it (argparse keeps the string it
    was given), and what names robots keeps the mark.
    """

    __slots__ = ()


class Searched(FileName):
    """A robot description a search told (`found.in_folder`, `found.robots_among`).

    ``--robots-only`` keeps it without looking at it again. One whose reader finds an
    SRDF (`SRDF_CODE`: a file the search could not be sure of) is a note, not an error.
    """

    __slots__ = ()


def is_glob(name: str) -> bool:
    """True for a pattern: a name with a wildcard, not ``erd:NAME``, not a `FileName`."""
    if isinstance(name, FileName) or name.startswith(ERD_PREFIX):
        return False
    return any(m in name for m in MAGIC)


def expand_pattern(pattern: str, linked: list[str] | None = None) -> list[str]:
    """The files matching ``pattern``, sorted; none is reached through a linked folder.

    ``linked``, when given, gets the links to folders that a ``**`` met and did not enter
    (for a note: a folder's search skips nothing silently).

    Raises:
        FileUnreadableError: The pattern names more than `MAX_MATCHES` files or
            makes the walk visit more than `MAX_FOLDERS` folders.
    """
    parts = pattern.split("/")
    fixed = 0
    while fixed < len(parts) - 1 and not any(m in parts[fixed] for m in MAGIC):
        fixed += 1
    base = "/".join(parts[:fixed]) or ("/" if pattern.startswith("/") else "")
    if not pattern.startswith("/"):
        for depth in range(1, fixed + 1):
            folder = "/".join(parts[:depth])
            if os.path.islink(folder):
                raise FileUnreadableError(
                    pattern,
                    f"'{folder}' is a link; cspace does not follow links in a pattern's "
                    "folders (name the folder it leads to)",
                    code="outside-tree",
                )
    walk = _Walk(pattern)
    walk.run(base, parts[fixed:])
    if linked is not None:
        linked.extend(sorted(set(walk.linked)))
    return sorted(set(walk.found))


_VISIT, _BELOW, _ADD = "visit", "below", "add"
"""What a step of the walk does: match a folder's entries against the rest of the
pattern, descend a ``**`` into a folder's subfolders, or add a file."""

_Step = tuple[str, str, list[str]]
"""(what, folder or file, the rest of the pattern)."""


class _Walk:
    def __init__(self, pattern: str) -> None:
        self.pattern = pattern
        self.found: list[str] = []
        self.linked: list[str] = []  # links to folders a ``**`` did not enter
        self.folders = 0

    def _entries(self, folder: str) -> list[os.DirEntry[str]]:
        self.folders += 1
        if self.folders > MAX_FOLDERS:
            raise FileUnreadableError(
                self.pattern, f"the pattern walks more than {MAX_FOLDERS:,} folders"
            )
        try:
            with os.scandir(folder or ".") as entries:
                return sorted(entries, key=lambda e: e.name)
        except OSError:
            return []

    def _add(self, path: str) -> None:
        self.found.append(path)
        if len(self.found) > MAX_MATCHES:
            raise FileUnreadableError(
                self.pattern, f"the pattern names more than {MAX_MATCHES:,} files"
            )

    def run(self, folder: str, rest: list[str]) -> None:
        """Match ``rest`` (the pattern's names) from ``folder``, depth first.

        A stack of steps stands for the recursion (a step's followers are pushed in
        reverse, so they run in order): folders are listed and files found in the order
        a recursive walk would, whatever the depth.
        """
        stack: list[_Step] = [(_VISIT, folder, rest)]
        while stack:
            what, folder, rest = stack.pop()
            if what == _ADD:
                self._add(folder)
            elif what == _BELOW:  # ``**`` matching one folder more
                entries = [e for e in self._entries(folder) if not e.name.startswith(".")]
                stack.extend(
                    (_VISIT, _join(folder, entry.name), rest)
                    for entry in reversed(entries)
                    if _folder(entry)
                )
                self.linked += [_join(folder, e.name) for e in entries if _linked_folder(e)]
            elif rest[0] == "**":  # no folder at all first, then one more
                stack.append((_BELOW, folder, rest))
                stack.append((_VISIT, folder, rest[1:] or ["*"]))
            else:
                stack.extend(reversed(self._matches(folder, rest[0], rest[1:])))

    def _matches(self, folder: str, head: str, tail: list[str]) -> list[_Step]:
        """What follows from ``folder``'s entries named like ``head``, in order."""
        steps: list[_Step] = []
        for entry in self._entries(folder):
            if entry.name.startswith(".") and not head.startswith("."):
                continue
            if not fnmatchcase(entry.name, head):
                continue
            if tail:
                if _folder(entry):
                    steps.append((_VISIT, _join(folder, entry.name), tail))
            elif _file(entry):
                steps.append((_ADD, _join(folder, entry.name), []))
        return steps


def _join(folder: str, name: str) -> str:
    return os.path.join(folder, name) if folder else name


def _file(entry: os.DirEntry[str]) -> bool:
    """A file, or a link that cannot be followed (a loop, a name too long).

    Reading such a link then says what is wrong with it, and the other matches go on.
    """
    try:
        return entry.is_file(follow_symlinks=True)
    except OSError:
        return entry.is_symlink()


def _folder(entry: os.DirEntry[str]) -> bool:
    """A real folder, not a link to one."""
    return entry.is_dir(follow_symlinks=False)


def _linked_folder(entry: os.DirEntry[str]) -> bool:
    """A link to a folder (a link that cannot be followed is none)."""
    try:
        return entry.is_symlink() and entry.is_dir(follow_symlinks=True)
    except OSError:
        return False
