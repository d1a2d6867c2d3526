"""Where a path leads, looking at nothing outside the folders it may lead to.

A path that only an untrusted file names (a baseline's entry, an SRDF that ``--srdf
auto`` would pick) must not make cspace look outside the folders it was asked to read:
not open a file there, and not even find out whether one exists, for a report that
differs with what exists would tell it. `Folders.reach` follows such a path as the
kernel does (each link where it stands, ``..`` from where the walk has got to), one
name at a time, and looks (``lstat``) only at names inside the folders or on the way
down to one of them; a step to anywhere else ends the walk: the path leads outside,
and nothing there was looked at.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable
from typing import NamedTuple

MAX_LINKS = 40
"""Most links followed in one path (Linux's own bound, ``MAXSYMLINKS``)."""

MAX_PATH_CHARS = 4096
"""Longest path followed (Linux's ``PATH_MAX``); a longer one leads nowhere cspace reads."""


class Reached(NamedTuple):
    """Where a path leads.

    Attributes:
        real: The real path (every link followed) inside the folders, or None when the
            path leads outside them (or through more than `MAX_LINKS` links).
        exists: Whether a file or folder is there (False outside: not looked at).
    """

    real: str | None
    exists: bool


OUTSIDE = Reached(None, False)
"""A path that leads outside the folders."""


class Folders:
    """Real folders a path may lead into, and the folders on the way down to them."""

    def __init__(self, folders: Iterable[str]) -> None:
        """Hold ``folders``: absolute real paths (`cspace.files.real_path`)."""
        self.folders = frozenset(os.path.normpath(f) for f in folders)
        self.above: set[str] = set()
        for folder in self.folders:
            parent = os.path.dirname(folder)
            while parent not in self.above and parent != folder:
                self.above.add(parent)
                folder, parent = parent, os.path.dirname(parent)
        self._looked: dict[str, str | bool] = {}

    def holding(self, real: str) -> str | None:
        """The folder ``real`` (a real absolute path) lies in (itself included), or None."""
        path = real
        while path not in self.folders:
            parent = os.path.dirname(path)
            if parent == path:
                return None
            path = parent
        return path

    def reach(self, base: str, rest: str) -> Reached:
        """Where ``rest`` leads from the real folder ``base`` (``rest`` absolute: from ``/``).

        Nothing is looked at outside the folders but names on the way down to them, so
        the answer for a path that leads outside never depends on what is there.
        """
        if "\0" in rest or len(rest) > MAX_PATH_CHARS or not self.folders:
            return OUTSIDE
        here = "/" if rest.startswith("/") else os.path.normpath(base)
        todo = rest.split("/")[::-1]  # a stack: the next name last
        links, exists = 0, True
        while todo:
            name = todo.pop()
            if name in ("", "."):
                continue
            if name == "..":
                here = os.path.dirname(here)
                continue
            step = os.path.join(here, name)
            if step not in self.above and self.holding(step) is None:
                return OUTSIDE  # not looked at
            seen = self._look(step) if exists else False
            if isinstance(seen, str):  # a link: its target, from where it stands
                links += 1
                if links > MAX_LINKS or len(seen) > MAX_PATH_CHARS:
                    return OUTSIDE
                todo.extend(seen.split("/")[::-1])
                if seen.startswith("/"):
                    here = "/"
                continue
            exists = exists and seen is True
            here = step
        if self.holding(here) is None:
            return OUTSIDE  # on the way down: above every folder
        return Reached(here, exists)

    def _look(self, path: str) -> str | bool:
        """A link's target, True for anything else that is there, False for nothing."""
        if path not in self._looked:
            try:
                mode = os.lstat(path).st_mode
                self._looked[path] = os.readlink(path) if stat.S_ISLNK(mode) else True
            except (OSError, ValueError):
                self._looked[path] = False
        return self._looked[path]
