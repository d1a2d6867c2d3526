"""Pinocchio's C++ parsers, run so that they can neither print nor crash on depth.

Pinocchio's URDF parser prints through C++ streams that Python cannot redirect: what
it prints is caught at the file-descriptor level and kept (`quietly`). It
recurses once per joint of depth: it runs on a thread of its own with a stack of
`BUILD_STACK_BYTES` (`on_own_stack`), whatever the caller's thread. Threads and locks
come from `_thread`, the layer `threading` is built on: `threading` itself costs every
start-up half a millisecond, and nothing here needs more than a thread and a lock.
"""

from __future__ import annotations

import _thread
import os
import sys
import warnings
from collections.abc import Callable
from typing import IO, TypeVar

_T = TypeVar("_T")


def _sink() -> IO[bytes]:
    """An anonymous file to catch what C++ prints: in memory where Linux offers one."""
    if hasattr(os, "memfd_create"):
        return os.fdopen(os.memfd_create("cspace-parser-output"), "w+b")
    import tempfile  # not on the start-up path where memfd exists

    return tempfile.TemporaryFile()


BUILD_STACK_BYTES = 16 << 20
"""Stack of the thread that runs Pinocchio's URDF parser (16 MiB of address space; only
the pages used are memory). The parser recurses once per joint of depth, about 2.2 KiB
a level; measured, it crashed the process (SIGSEGV) 3,765 joints deep on an 8 MiB main
thread, 937 deep on the 2 MiB threads glibc gives when ``ulimit -s`` is unlimited, and
7,538 deep on 16 MiB. A thread of our own makes the depth it takes independent of the
caller's thread and limits (see `MAX_DEPTH`)."""

_QUIET = _thread.allocate_lock()
"""One capture at a time: redirecting descriptors is process-wide (threads would mix
their captures, and restore each other's descriptors)."""

if hasattr(os, "register_at_fork"):  # a child forked during a capture starts unlocked
    os.register_at_fork(after_in_child=_QUIET._at_fork_reinit)  # type: ignore[attr-defined]


_STACK = _thread.allocate_lock()
"""Setting the stack size of new threads is process-wide: one build thread at a time."""

if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_STACK._at_fork_reinit)  # type: ignore[attr-defined]


def on_own_stack(call: Callable[[], _T]) -> _T:
    """``call()`` on a new thread with a `BUILD_STACK_BYTES` stack; its result.

    What ``call`` raises is raised here, on the caller's thread.
    """
    outcome: list[tuple[_T | None, BaseException | None]] = []
    done = _thread.allocate_lock()
    done.acquire()  # released by the thread when it has put its outcome

    def run() -> None:
        try:
            outcome.append((call(), None))
        except BaseException as exc:  # handed to the caller, who raises it
            outcome.append((None, exc))
        finally:
            done.release()

    with _STACK:  # no other thread sets, then restores, the size in between
        previous = _thread.stack_size(BUILD_STACK_BYTES)  # for threads made from now on
        try:
            _thread.start_new_thread(run, ())
        finally:
            _thread.stack_size(previous)
    done.acquire()  # the thread's end (interruptible, as a join is)
    result, error = outcome[0]
    if error is not None:
        raise error
    return result  # type: ignore[return-value]


def quietly(call: Callable[[], _T]) -> tuple[_T | None, BaseException | None, str]:
    """Run ``call`` with the process's stdout and stderr captured at the file-descriptor level.

    Pinocchio's parsers print through C++ streams that Python cannot redirect; only the
    descriptors can be. What they printed is returned, never shown. One call at a time
    in the process (`_QUIET`).
    """
    with _QUIET:
        return _captured(call)


def _captured(call: Callable[[], _T]) -> tuple[_T | None, BaseException | None, str]:
    sys.stdout.flush()
    sys.stderr.flush()
    saved = (os.dup(1), os.dup(2))
    with _sink() as sink, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Pinocchio's Python deprecation notices
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        result: _T | None = None
        error: BaseException | None = None
        try:
            result = call()
        except Exception as exc:  # Pinocchio raises ValueError, RuntimeError, ...
            error = exc
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
        sink.seek(0)
        printed = sink.read().decode("utf-8", errors="replace")
    return result, error, printed


def parser_messages(printed: str) -> tuple[str, ...]:
    """The messages in what a C++ parser printed, without source locations.

    urdfdom prints ``Error:   <message>`` followed by ``at line N in <its own source>``;
    the second line is about urdfdom's code, not the robot file, so it is dropped.
    """
    messages = []
    for raw in printed.splitlines():
        line = raw.strip()
        if not line or (line.startswith("at line ") and " in " in line):
            continue
        for prefix in ("Error:", "Warning:", "Info:", "Debug:"):
            if line.startswith(prefix):
                line = line[len(prefix) :].strip()
                break
        messages.append(line)
    return tuple(messages)
