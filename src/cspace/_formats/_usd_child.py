"""The confined OpenUSD child of this process, reused from one stage to the next.

Starting ``python -I`` with OpenUSD costs about 0.3 s; reading a small stage, a few
milliseconds. So each process keeps one serving child (`serving.ServingChild`, running
`usd_worker`) and sends it every stage and every batch of layers to list, one at a time:

- the child's Landlock rules are fixed when it starts: the folders of the request that
  started it, or the folders of the run (`within`: the folders of every file
  `inspect_many` was given, and ``--allow-dir``) when those cover the request. A
  request that needs a folder the live child was not given starts a new one (the old
  one ends), and so does one whose files are newer than its rules (the child answers
  ``R``);
- each request is still checked in the child against its own allowed folders (the
  stage's folder and ``--allow-dir``) before anything is opened: Landlock is the second
  wall, as for a child of its own;
- each request is bounded in CPU and wall clock (`LIMITS`); a child past them is killed,
  and the next request starts a new one;
- a forked process never uses its parent's child (the pid is checked, and the pipes are
  closed after a fork); the child is killed when this process exits (``atexit``), and
  ends by itself when this process dies.
"""

from __future__ import annotations

import atexit
import os
import threading
from collections.abc import Iterable, Sequence
from typing import Any

from cspace._confine.sandbox import ChildLimits, ChildRefused
from cspace._confine.serving import ServingChild, TooNarrow

LIMITS = ChildLimits(cpu_seconds=6, wall_seconds=8.0, memory_bytes=2**31, output_bytes=2**24)
"""Each request's bounds, and the child's memory. A stage of 99,990 prims takes 2.3 s of
the child's CPU, 5,000 joints 0.8 s; on a core another process keeps busy, a request
OpenUSD cannot finish ends within 8 s, and the whole command within 10."""

MODULE = "cspace._formats.usd_worker"

_live: ServingChild | None = None
_live_folders: frozenset[str] = frozenset()
_scope: tuple[str, ...] = ()
_given: tuple[str, ...] = ()
_lock = threading.Lock()  # one request at a time on the child, whatever the thread


def within(folders: Iterable[str]) -> None:
    """Let this process's next OpenUSD child read ``folders`` (those of the run).

    A stage is still read only from its own allowed folders (checked in the child);
    this lets one child serve the stages of many folders.
    """
    global _scope, _given
    given = tuple(folders)
    if given != _given:  # each task of a run gives the same folders
        _given = given
        _scope = _pruned(os.path.realpath(f) for f in given if os.path.isdir(f))


def ask(request: dict[str, Any], allowed: Sequence[str]) -> bytes:
    """The child's answer to ``request``, whose files are in the ``allowed`` folders.

    Raises:
        ChildRefused: The child refused the request, passed its bounds, or died.
    """
    global _live
    folders = _pruned(os.path.realpath(a) for a in allowed)
    request = {**request, "allowed": list(folders)}
    with _lock:
        for fresh in (False, True):
            child = _child_for(folders, fresh)
            try:
                return child.ask(request)
            except TooNarrow:
                child.close()
                _live = None
    raise ChildRefused("OpenUSD could not be confined to the stage's folders")


def _child_for(folders: tuple[str, ...], fresh: bool) -> ServingChild:
    """The live child if it may read ``folders``, else a new one (which becomes the live one)."""
    global _live, _live_folders
    if _live is not None and _live.owner != os.getpid():  # inherited through a fork
        _live.forget()
        _live = None
    usable = _live is not None and not fresh and _live.alive()
    if usable and _live is not None and all(_covered(f, _live_folders) for f in folders):
        return _live
    if _live is not None:
        _live.close()
        _live = None
    scope = frozenset(_scope)
    wanted = _scope if _scope and all(_covered(f, scope) for f in folders) else folders
    _live = ServingChild(MODULE, list(wanted), LIMITS, "OpenUSD")
    _live_folders = frozenset(wanted)
    return _live


def live_pid() -> int | None:
    """The process id of this process's live child, if any (for tests)."""
    if _live is None or not _live.alive():
        return None
    return _live.child.pid


def close() -> None:
    """End this process's child, if any."""
    global _live
    if _live is not None:
        _live.close()
        _live = None


def _covered(folder: str, given: frozenset[str]) -> bool:
    """Whether a child confined to ``given`` may read ``folder``.

    Landlock's rules of a folder are on its entries but the hidden ones
    (`landlock.readable_entries`): a folder beneath a hidden entry is not covered.
    """
    return folder in given or _below(folder, given)


def _below(folder: str, given: frozenset[str]) -> bool:
    """Whether a folder above ``folder`` in ``given`` covers it."""
    parts = folder.rstrip("/").split("/")
    for k in range(len(parts) - 1, 0, -1):  # each folder above it, nearest first
        top = "/".join(parts[:k]) or "/"
        if top in given and not parts[k].startswith("."):
            return True
    return False


def _pruned(folders: Iterable[str]) -> tuple[str, ...]:
    """The folders, each once, less those another one covers (sorted)."""
    unique = frozenset(folders)
    return tuple(sorted(f for f in unique if not _below(f, unique)))


def _after_fork() -> None:
    """In a forked process: drop the parent's child (its pipes), never use it.

    The lock is made anew: another thread of the parent may have held it.
    """
    global _live, _lock
    _lock = threading.Lock()
    if _live is not None:
        _live.forget()
        _live = None


atexit.register(close)
os.register_at_fork(after_in_child=_after_fork)
