"""The serving child a process keeps for one worker module, reused from request to request.

Starting ``python -I`` with a library (OpenUSD, MuJoCo) costs about 0.3 s; a request, a
few milliseconds. So a process keeps one `serving.ServingChild` a worker module
(`KeptChild`) and sends it its requests one at a time:

- the child's Landlock rules are fixed when it starts: the folders of the request that
  started it, or wider ones the caller names (the folders of a whole run) when those
  cover the request's. A request that needs a folder the live child was not given starts
  a new one (the old one ends), and so does one the child answers it cannot read (a file
  newer than its rules);
- each request is bounded in CPU and wall clock (the child's limits); a child past them
  is killed, and the next request starts a new one;
- a request a used child could not finish for want of memory (`OutOfMemory`: what
  earlier requests left mapped counts against its address space) is asked again of a
  fresh child, with its whole bounds, so that an answer never depends on what came
  before (nor on ``--jobs``, which decides which child takes what): a model that runs
  out of memory may so cost twice its bounds in a batch, never more;
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

from cspace._confine.sandbox import ChildLimits, ChildRefused, OutOfMemory
from cspace._confine.serving import ServingChild, TooNarrow


class KeptChild:
    """One serving child of ``module`` for this process (see the module docstring).

    Args:
        module: The worker module (`serving` protocol).
        limits: Each request's CPU and wall clock, the child's memory, each answer's size.
        what: What runs, for messages (``"OpenUSD"``).
        env: The child's whole environment (default: empty).
    """

    def __init__(
        self, module: str, limits: ChildLimits, what: str, env: dict[str, str] | None = None
    ) -> None:
        self.module, self.limits, self.what, self.env = module, limits, what, env
        self._live: ServingChild | None = None
        self._folders: frozenset[str] = frozenset()
        self._lock = threading.Lock()  # one request at a time, whatever the thread
        atexit.register(self.close)
        os.register_at_fork(after_in_child=self._after_fork)

    def start(self, folders: Sequence[str] = (), wider: Sequence[str] = ()) -> None:
        """Have a child for requests in ``folders`` start now, not waited for.

        Its library loads while this process works on; the first `ask` waits for it.
        """
        with self._lock:
            self._child_for(pruned(folders), pruned(wider), fresh=False)

    def ask(
        self, request: dict[str, Any], folders: Sequence[str] = (), wider: Sequence[str] = ()
    ) -> bytes:
        """The child's answer to ``request``, whose files are in ``folders``.

        Args:
            request: The request (JSON).
            folders: The folders the request reads (none: a child that reads nothing).
            wider: Folders a new child may be confined to instead, when they cover
                ``folders`` (so that it serves the requests of all of them).

        Raises:
            ChildRefused: The child refused the request, passed its bounds, or died.
        """
        needed, scope = pruned(folders), pruned(wider)
        with self._lock:
            for attempt in range(3):
                child = self._child_for(needed, scope, fresh=attempt > 0)
                used = child.served > 0
                try:
                    return child.ask(request)
                except TooNarrow:
                    child.close()
                except OutOfMemory:
                    child.close()
                    if not used:
                        raise
        raise ChildRefused(f"{self.what} could not be confined to the request's folders")

    def live_pid(self) -> int | None:
        """The process id of the live child, if any (for tests)."""
        live = self._live
        return live.child.pid if live is not None and live.alive() else None

    def close(self) -> None:
        """End the live child, if any."""
        if self._live is not None:
            self._live.close()
            self._live = None

    def _child_for(
        self, folders: tuple[str, ...], scope: tuple[str, ...], fresh: bool
    ) -> ServingChild:
        """The live child if it may read ``folders``, else a new one (then the live one)."""
        live = self._live
        if live is not None and live.owner != os.getpid():  # inherited through a fork
            live.forget()
            live = self._live = None
        usable = live is not None and not fresh and live.alive()
        if live is not None and usable and all(covered(f, self._folders) for f in folders):
            return live
        self.close()
        wide = frozenset(scope)
        wanted = scope if scope and all(covered(f, wide) for f in folders) else folders
        self._live = ServingChild(self.module, list(wanted), self.limits, self.what, self.env)
        self._folders = frozenset(wanted)
        return self._live

    def _after_fork(self) -> None:
        """In a forked process: drop the parent's child (its pipes), never use it.

        The lock is made anew: another thread of the parent may have held it.
        """
        self._lock = threading.Lock()
        if self._live is not None:
            self._live.forget()
            self._live = None


def covered(folder: str, given: frozenset[str]) -> bool:
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


def pruned(folders: Iterable[str]) -> tuple[str, ...]:
    """The folders' real paths, each once, less those another one covers (sorted)."""
    unique = frozenset(os.path.realpath(f) for f in folders)
    return tuple(sorted(f for f in unique if not _below(f, unique)))
