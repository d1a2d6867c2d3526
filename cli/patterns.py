"""Glob patterns given in quotes (as CI scripts do), expanded without following links.

``glob.glob(recursive=True)`` follows links to folders: a pull request that adds
``robots/up -> ..`` makes ``'robots/**/*.urdf'`` search forever, and ``robots/etc ->
/etc`` makes files outside the repository count as named by the user. Here the walk
never enters a linked folder, visits at most :data:`MAX_FOLDERS` folders, and yields at
most :data:`MAX_MATCHES` files; ``**`` matches any number of folders (none included),
``*``, ``?`` and ``[...]`` match within one name, and names starting with ``.`` are
matched only by a pattern that starts with ``.``, as in the shell.

A name with ``*``, ``?`` or ``[`` is a pattern, even when a file of that very name
exists, as long as the pattern matches any other file (a committed folder named ``**``
must not stand in for the files a CI pattern names); the name of an existing file that
matches nothing else as a pattern is that file. In a relative pattern, the folders
before the first wildcard must not be links: ``robots -> /`` would make
``'robots/**/*.urdf'`` walk the whole machine.
"""

from __future__ import annotations

import os
from fnmatch import fnmatchcase

from cspace import FileUnreadableError

MAGIC = ("*", "?", "[")
MAX_MATCHES = 10_000
"""Most files one pattern may name."""
MAX_FOLDERS = 100_000
"""Most folders one pattern's walk may visit."""


def is_glob(name: str) -> bool:
    """True for a pattern: a name with a wildcard, not ``erd:NAME``, not only a file's name.

    Raises:
        FileUnreadableError: As :func:`expand_pattern`, for a name that could be both.
    """
    if name.startswith("erd:") or not any(m in name for m in MAGIC):
        return False
    return not os.path.lexists(name) or expand_pattern(name) not in ([], [name])


def expand_pattern(pattern: str) -> list[str]:
    """The files matching ``pattern``, sorted; none is reached through a linked folder.

    Raises:
        FileUnreadableError: The pattern names more than :data:`MAX_MATCHES` files or
            makes the walk visit more than :data:`MAX_FOLDERS` folders.
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
    walk.visit(base, parts[fixed:])
    return sorted(set(walk.found))


class _Walk:
    def __init__(self, pattern: str) -> None:
        self.pattern = pattern
        self.found: list[str] = []
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

    def visit(self, folder: str, rest: list[str]) -> None:
        head, tail = rest[0], rest[1:]
        if head == "**":
            self.visit(folder, tail or ["*"])  # no folder at all
            for entry in self._entries(folder):
                if _folder(entry) and not entry.name.startswith("."):
                    self.visit(_join(folder, entry.name), rest)
            return
        for entry in self._entries(folder):
            if entry.name.startswith(".") and not head.startswith("."):
                continue
            if not fnmatchcase(entry.name, head):
                continue
            if tail:
                if _folder(entry):
                    self.visit(_join(folder, entry.name), tail)
            elif entry.is_file(follow_symlinks=True):
                self._add(_join(folder, entry.name))


def _join(folder: str, name: str) -> str:
    return os.path.join(folder, name) if folder else name


def _folder(entry: os.DirEntry[str]) -> bool:
    """A real folder, not a link to one."""
    return entry.is_dir(follow_symlinks=False)
