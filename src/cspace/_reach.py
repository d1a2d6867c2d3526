"""Where a path leads, looking at nothing outside the folders it may lead to.

A path that only an untrusted file names (a baseline's entry, an SRDF that ``--srdf
auto`` would pick) must not make cspace look outside the folders it was asked to read:
not open a file there, and not even find out whether one exists, for a report that
differs with what exists would tell it. `Folders.reach` follows such a path as the
kernel does (each link where it stands, ``..`` from where the walk has got to), one
name at a time, and looks (``lstat``) only at names inside the folders or on the way
down to one of them; a step to anywhere else ends the walk: the path leads outside,
and nothing there was looked at. Past a name that is not there, nothing more is looked
at: the rest of the path is folded as written (it names no file). With ``last=False``
the last name written is not followed when it is a link: the path leads to the link
itself (a baseline's entry is the file of its path, whatever the link leads to).

What was looked at is kept in a tree of names, so a baseline of 10,000 paths 2,000
folders deep costs one ``lstat`` per folder and a few dictionary lookups per name.
"""

import os
import stat
from collections.abc import Iterable

from cspace._record import NamedTuple

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
        within: The folders that hold it, the outermost first.
    """

    real: str | None
    exists: bool
    within: tuple[str, ...] = ()


OUTSIDE = Reached(None, False)
"""A path that leads outside the folders."""


class _Name:
    """A real path looked at: what is there (once looked), and the names below it."""

    __slots__ = ("below", "folder", "path", "seen")

    def __init__(self, path: str, folder: bool, seen: str | bool | None = None) -> None:
        self.path = path
        self.folder = folder  # one of the folders
        self.seen = seen  # None: not looked at; True: there; False: not; str: a link's target
        self.below: dict[str, _Name] = {}


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
        self._top = _Name("/", "/" in self.folders, True)

    def holding(self, real: str, outermost: bool = False) -> str | None:
        """The folder ``real`` (a real absolute path) lies in (itself included), or None.

        The innermost of those that hold it, or with ``outermost`` the outermost.
        """
        path, found = real, None
        while True:
            if path in self.folders:
                found = path
                if not outermost:
                    return found
            parent = os.path.dirname(path)
            if parent == path:
                return found
            path = parent

    def reach(self, base: str, rest: str, last: bool = True) -> Reached:
        """Where ``rest`` leads from the real folder ``base`` (``rest`` absolute: from ``/``).

        Nothing is looked at outside the folders but names on the way down to them, so
        the answer for a path that leads outside never depends on what is there. With
        ``last=False`` a link that is the last name of ``rest`` is where the path leads
        (``real`` is the link's path), not followed.
        """
        if "\0" in rest or len(rest) > MAX_PATH_CHARS or not self.folders:
            return OUTSIDE
        walk = _Walk(self, [] if rest.startswith("/") else os.path.normpath(base).split("/"))
        todo = rest.split("/")[::-1]  # a stack: the next name last
        final = -1  # todo's index of the last name written, when it is not followed
        if not last:
            final = next((i for i, n in enumerate(todo) if n not in ("", ".")), -1)
            if final >= 0 and todo[final] == "..":
                final = -1
        links = 0
        while todo:
            name = todo.pop()
            if name in ("", "."):
                continue
            if name == "..":
                walk.up()
                continue
            if walk.missing:  # past a name that is not there: nothing more is looked at
                if walk.root is None:
                    return OUTSIDE
                walk.missing.append(name)
                continue
            node = walk.trail[-1].below.get(name)
            if walk.root is not None and node is not None and node.seen is True:
                walk.trail.append(node)  # inside, and looked at before
                continue
            target = walk.down(name, follow=len(todo) != final)
            if target is OUTSIDE:
                return OUTSIDE
            if isinstance(target, str):  # a link: its target, from where it stands
                links += 1
                if links > MAX_LINKS or len(target) > MAX_PATH_CHARS:
                    return OUTSIDE
                todo.extend(target.split("/")[::-1])
                if target.startswith("/"):
                    walk = _Walk(self, [])
        return walk.end()


class _Walk:
    """Where a walk has got to.

    The real names from ``/``, then the names past one that is not there (folded as
    written), and the outermost folder it lies in.
    """

    def __init__(self, folders: Folders, names: list[str]) -> None:
        self.folders = folders
        self.trail = [folders._top]
        for name in filter(None, names):  # a real folder: taken as there, not looked at
            here = self.trail[-1]
            node = here.below.get(name)
            if node is None:
                path = os.path.join(here.path, name)
                node = here.below[name] = _Name(path, path in folders.folders)
            self.trail.append(node)
        self.missing: list[str] = []  # names past one that is not there
        self.root: int | None = None  # the index in trail of the outermost folder
        for index, node in enumerate(self.trail):
            if node.folder:
                self.root = index
                break

    def up(self) -> None:
        """``..``: back one name (``/`` stays ``/``)."""
        if self.missing:
            self.missing.pop()
        elif len(self.trail) > 1:
            self.trail.pop()
            if self.root is not None and len(self.trail) <= self.root:
                self.root = None  # the folder's parent: on the way down to it

    def down(self, name: str, follow: bool = True) -> str | Reached | None:
        """Step to ``name``: None, a link's target, or `OUTSIDE` (nothing looked at).

        Only from a name that is there (`Folders.reach` keeps the names past one that is
        not). A link not to ``follow`` is stepped to as a name that is there.
        """
        here = self.trail[-1]
        node = here.below.get(name)
        if node is None:
            path = os.path.join(here.path, name)
            folder = path in self.folders.folders
            if self.root is None and not folder and path not in self.folders.above:
                return OUTSIDE  # not looked at, not kept
            node = here.below[name] = _Name(path, folder)
        elif self.root is None and not node.folder and node.path not in self.folders.above:
            return OUTSIDE
        path = node.path
        if self.root is None and node.folder:
            self.root = len(self.trail)
        if node.seen is None:
            node.seen = _look(path)
        if node.seen is True or (not follow and isinstance(node.seen, str)):
            self.trail.append(node)
            return None
        if self.root == len(self.trail):  # not entered (a folder is real, and there)
            self.root = None
        if node.seen is False:
            self.missing.append(name)
            return None
        return node.seen  # a link: followed from its folder

    def end(self) -> Reached:
        """Where the walk ends: inside a folder, or `OUTSIDE`."""
        if self.root is None:
            return OUTSIDE  # on the way down: above every folder
        here = self.trail[-1].path
        within = tuple(n.path for n in self.trail[self.root :] if n.folder)
        if self.missing:
            return Reached("/".join([here.rstrip("/"), *self.missing]), False, within)
        return Reached(here, True, within)


def _look(path: str) -> str | bool:
    """A link's target, True for anything else that is there, False for nothing."""
    try:
        if stat.S_ISLNK(os.lstat(path).st_mode):
            return os.readlink(path)
    except (OSError, ValueError):
        return False
    return True
