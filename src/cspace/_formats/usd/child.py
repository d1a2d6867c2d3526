"""The confined OpenUSD child of this process, reused from one stage to the next.

Starting ``python -I`` with OpenUSD costs about 0.3 s; reading a small stage, a few
milliseconds. So each process keeps one serving child (`kept.KeptChild`, running
`usd._worker`) and sends it every stage and every batch of layers to list, one at a time.
Its Landlock rules are the folders of the request that started it, or the folders of the
run (`within`: the folders of every file `inspect_many` was given, and ``--allow-dir``)
when those cover the request; each request is still checked in the child against its
own allowed folders (the stage's folder and ``--allow-dir``) before anything is opened:
Landlock is the second wall, as for a child of its own.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Sequence
from typing import Any

from cspace._confine.kept import KeptChild, pruned
from cspace._confine.sandbox import ChildLimits
from cspace._confine.serving import ServingChild

__all__ = ["KEPT", "LIMITS", "ServingChild", "ask", "close", "live_pid", "within"]

LIMITS = ChildLimits(cpu_seconds=6, wall_seconds=8.0, memory_bytes=2**31, output_bytes=2**26)
"""Each request's bounds, and the child's memory. A stage of 99,990 prims takes 2.3 s of
the child's CPU, 5,000 joints 0.8 s; on a core another process keeps busy, a request
OpenUSD cannot finish ends within 8 s, and the whole command within 10. An answer is at
most 64 MiB: collision meshes' arrays come 48 MiB an answer (`usd._colliders`)."""

KEPT = KeptChild("cspace._formats.usd._worker", LIMITS, "OpenUSD")
"""This process's OpenUSD child."""

_scope: tuple[str, ...] = ()
_given: tuple[str, ...] = ()


def within(folders: Iterable[str]) -> None:
    """Let this process's next OpenUSD child read ``folders`` (those of the run).

    A stage is still read only from its own allowed folders (checked in the child);
    this lets one child serve the stages of many folders.
    """
    global _scope, _given
    given = tuple(folders)
    if given != _given:  # each task of a run gives the same folders
        _given = given
        _scope = pruned(f for f in given if os.path.isdir(f))


def ask(request: dict[str, Any], allowed: Sequence[str]) -> bytes:
    """The child's answer to ``request``, whose files are in the ``allowed`` folders.

    Raises:
        ChildRefused: The child refused the request, passed its bounds, or died.
    """
    folders = pruned(allowed)
    return KEPT.ask({**request, "allowed": list(folders)}, folders, _scope)


def live_pid() -> int | None:
    """The process id of this process's live child, if any (for tests)."""
    return KEPT.live_pid()


def close() -> None:
    """End this process's child, if any."""
    KEPT.close()
