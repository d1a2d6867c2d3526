"""A confined child that serves many requests in turn, each bounded in CPU and wall clock.

`sandbox.RunningChild` starts a child for one job: ``python -I`` and a library's imports
cost a few hundred milliseconds, a hundred times the job for a small USD stage. A
`ServingChild` is started once, confines itself once, and then takes requests one at a
time over a pipe (`usd._worker` is the example):

- frames: a 4-byte big-endian length, then the bytes. The parent sends a setup (JSON:
  the limits, the folders the child may read, the parent's pid) as it starts the child,
  and does not wait for it (the child imports its library while the parent works on);
  then one request at a time; the child answers ``ready`` once confined (read before the
  first request), then each request with ``+`` or ``-`` (it goes on, or it ends after
  this answer) and ``U`` with the result, ``E`` with a one-line message, ``M`` with one
  saying it ran out of memory (`OutOfMemory`), or ``R``: the request needs a file this
  child may not read (a new child, confined to the request's folders, must take it);
- each request is bounded twice: the parent reads the child's CPU clock while it waits
  and kills it past the request's CPU or wall-clock bound, and the child raises its own
  soft ``RLIMIT_CPU`` before each request to what it has used plus the bound (the hard
  limit is its lifetime budget: it retires before reaching it); a request interrupted
  in the parent (Ctrl-C) ends the child, whose answer would go to the next one;
- memory is bounded per child (``RLIMIT_AS``); the child retires itself (``-``) after an
  answer when its resident memory is past `RETIRE_RSS` or its address space past 3/4 of
  its bound (read from ``/proc/self/statm``, opened before it confines itself: the peak
  ``getrusage`` gives counts the parent's from before ``exec``), or after
  `RETIRE_REQUESTS` requests;
- a killed or retired child is gone: the next request starts a new one;
- the child ends with its parent: end of file on its requests, and
  ``PR_SET_PDEATHSIG``.
"""

from __future__ import annotations

import contextlib
import json
import os
import resource
import select
import struct
import sys
import time
from typing import IO, TYPE_CHECKING, Any

from cspace._confine.sandbox import (
    ChildLimits,
    ChildRefused,
    OutOfMemory,
    death,
    kill,
    limit_resource,
)

if TYPE_CHECKING:
    import subprocess

LIFETIME_CPU_SECONDS = 600
"""A serving child's hard ``RLIMIT_CPU``: it retires before a request could reach it."""

START_SECONDS = 30.0
"""Wall clock a child may take to import its library and confine itself (trusted code)."""

RETIRE_RSS = 768 << 20
"""A child whose resident memory is past this after an answer retires."""

RETIRE_REQUESTS = 2_000
"""A child retires after this many requests (what a library caches for good, its
interned names, grows with what it read)."""

_POLL_SECONDS = 0.05
"""How often the parent reads the child's CPU time while it waits."""

_HEADER = struct.Struct(">I")

_MEMORY_DEATHS = (-9, -6, -11)
"""Exit statuses of a child that ran out of memory (killed, or aborted or crashed in a C
library that could not allocate); the parent's own kills say why where they happen."""

_memory: dict[str, int] = {}
"""The child's ``/proc/self/statm`` descriptor (``statm``) and its peak at start
(``start_peak``, KiB: what ``exec`` kept of its parent's), once `take_setup` ran."""


class TooNarrow(Exception):
    """The child may not read a file the request needs (its folders were fixed at start)."""


class ServingChild:
    """A child process that serves requests in turn (see the module docstring).

    Args:
        module: The worker module (run as ``python -I -m module``).
        folders: What the child confines itself to (sent in its setup).
        limits: Each request's CPU and wall clock, the child's memory, each answer's size.
        what: What runs, for messages (``"OpenUSD"``).
        env: The child's whole environment (default: empty).

    Raises:
        ChildRefused: The child could not be started; or (from the first `ask`) it was
            not ready within `START_SECONDS`, or died starting.
    """

    def __init__(
        self,
        module: str,
        folders: list[str],
        limits: ChildLimits,
        what: str,
        env: dict[str, str] | None = None,
    ) -> None:
        import subprocess

        self.limits = limits
        self.what = what
        self.folders = folders
        self.served = 0  # requests answered
        self.ready = False
        self.owner = os.getpid()  # a forked process inherits this object, not the child
        self.child: subprocess.Popen[bytes] = subprocess.Popen(
            [sys.executable, "-I", "-m", module],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            env=env or {},
            cwd="/",
            start_new_session=True,
        )
        if self.child.stdin is None or self.child.stdout is None:  # pragma: no cover - PIPE
            raise ChildRefused(f"{what} could not start")
        self._in: IO[bytes] = self.child.stdin
        self._out: IO[bytes] = self.child.stdout
        os.set_blocking(self._in.fileno(), False)
        setup = {"limits": limits._asdict(), "folders": folders, "parent": os.getpid()}
        self._started = time.monotonic()
        try:  # a few hundred bytes: the pipe takes them at once
            self._send(json.dumps(setup).encode("utf-8"), self._started + START_SECONDS)
        except BaseException:  # refused (it is then ended), or interrupted
            self.close()
            raise

    def _wait_ready(self) -> None:
        """Wait for the child's ``ready`` (its library imported, itself confined)."""
        try:
            ready = self._receive(self._started + START_SECONDS, None)
        except BaseException:  # refused (it is then ended), or interrupted
            self.close()
            raise
        if ready != b"ready":
            self.close()
            raise ChildRefused(f"{self.what} could not start")
        self.ready = True

    def alive(self) -> bool:
        """Whether the child can take a request (it runs, and belongs to this process)."""
        return self.owner == os.getpid() and self.child.poll() is None

    def ask(self, request: dict[str, Any]) -> bytes:
        """The child's result for ``request``, within the request's bounds.

        Raises:
            ChildRefused: The child answered with a message, passed a bound (it is then
                killed), or died; `OutOfMemory` when it ran out of memory.
            TooNarrow: The request needs a file the child may not read.
        """
        if not self.ready:
            self._wait_ready()
        deadline = time.monotonic() + self.limits.wall_seconds
        started = self._cpu()
        try:
            self._send(json.dumps(request).encode("utf-8"), deadline, started)
            answer = self._receive(deadline, started)
        except ChildRefused:
            raise
        except BaseException:  # interrupted (Ctrl-C): its answer would go to the next request
            self.close()
            raise
        status, kind = answer[:1], answer[1:2]
        if status not in (b"+", b"-") or kind not in (b"U", b"E", b"M", b"R"):
            self.close()
            raise ChildRefused(f"{self.what} answered what it may not")
        self.served += 1
        if status == b"-":  # retired: it exits after this answer
            self.close()
        if kind == b"R":
            raise TooNarrow(self.what)
        if kind in (b"E", b"M"):
            said = answer[2:].decode("utf-8", errors="replace")
            raise OutOfMemory(said) if kind == b"M" else ChildRefused(said)
        return answer[2:]

    def close(self) -> None:
        """End the child (killed: it holds nothing worth finishing) and reap it."""
        if self.owner != os.getpid():
            self.forget()
            return
        for stream in (self._in, self._out):
            with contextlib.suppress(OSError):
                stream.close()
        if self.child.poll() is None:
            kill(self.child)

    def forget(self) -> None:
        """Drop an inherited child's pipes in a forked process, leaving it to its owner."""
        for stream in (self._in, self._out):  # this process's copies of the pipes
            with contextlib.suppress(OSError):
                stream.close()
        self.child.returncode = 0  # not this process's to wait for

    def _refuse(self, message: str) -> ChildRefused:
        self.close()
        return ChildRefused(message)

    def _cpu(self) -> float | None:
        """The child's CPU time so far (user and system), or None where it cannot be read.

        Linux's clock of the process (``clock_getcpuclockid``: ``~pid << 3 | 2``).
        """
        try:
            return time.clock_gettime((~self.child.pid << 3) | 2)
        except (OSError, OverflowError):
            return None

    def _wait(self, fd: int, writing: bool, deadline: float, started: float | None) -> None:
        """Wait until ``fd`` is ready, killing the child past its bounds."""
        limits = self.limits
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise self._refuse(
                    f"{self.what} took longer than {limits.wall_seconds:g} s and was stopped"
                    if started is not None
                    else f"{self.what} did not start within {START_SECONDS:g} s"
                )
            wanted = ([], [fd]) if writing else ([fd], [])
            ready = select.select(*wanted, [], min(_POLL_SECONDS, left))
            if ready[0] or ready[1]:
                return
            used = self._cpu() if started is not None else None
            if started is not None and used is not None and used - started > limits.cpu_seconds:
                raise self._refuse(
                    f"{self.what} used more than {limits.cpu_seconds} s of CPU and was stopped"
                )

    def _send(self, data: bytes, deadline: float, started: float | None = None) -> None:
        frame = memoryview(_HEADER.pack(len(data)) + data)
        fd = self._in.fileno()
        while frame:
            self._wait(fd, True, deadline, started)
            try:
                frame = frame[os.write(fd, frame) :]
            except BlockingIOError:
                continue
            except (BrokenPipeError, ConnectionResetError):
                raise self._died() from None

    def _receive(self, deadline: float, started: float | None) -> bytes:
        header = self._read(_HEADER.size, deadline, started)
        (size,) = _HEADER.unpack(header)
        if size > self.limits.output_bytes + 2:
            raise self._refuse(
                f"{self.what}'s output is larger than the {self.limits.output_bytes:,}-byte limit"
            )
        return self._read(size, deadline, started)

    def _read(self, size: int, deadline: float, started: float | None) -> bytes:
        data = bytearray()
        fd = self._out.fileno()
        while len(data) < size:
            self._wait(fd, False, deadline, started)
            chunk = os.read(fd, min(size - len(data), 1 << 20))
            if not chunk:
                raise self._died()
            data += chunk
        return bytes(data)

    def _died(self) -> ChildRefused:
        """Why the child stopped answering (it closed its pipe: it ended, or soon will)."""
        import subprocess

        try:
            code = self.child.wait(timeout=2)
        except subprocess.TimeoutExpired:
            code = -9
        self.close()
        if code in _MEMORY_DEATHS:
            return OutOfMemory(death(code, self.limits, self.what))
        return ChildRefused(death(code, self.limits, self.what))


# --- the child's side ---------------------------------------------------------------


def take_setup() -> dict[str, Any]:
    """Read the setup, end with the parent, and cap this process (see the docstring).

    Returns:
        The setup: ``limits``, ``folders`` and ``parent``.
    """
    setup: dict[str, Any] = json.loads(_read_frame(sys.stdin.buffer) or b"{}")
    _memory["start_peak"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with contextlib.suppress(OSError):  # before Landlock: a descriptor read again later
        _memory["statm"] = os.open("/proc/self/statm", os.O_RDONLY | os.O_CLOEXEC)
    import ctypes

    prctl = getattr(ctypes.CDLL(None, use_errno=True), "prctl", None)  # Linux's
    if prctl is not None:
        prctl(1, 9, 0, 0, 0)  # PR_SET_PDEATHSIG, SIGKILL: killed when its parent ends
    if os.getppid() != setup.get("parent"):  # the parent ended before the line above
        os._exit(0)
    limits = setup["limits"]
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    top = LIFETIME_CPU_SECONDS
    if hard != resource.RLIM_INFINITY:
        top = min(hard, top)
    resource.setrlimit(resource.RLIMIT_CPU, (min(int(limits["cpu_seconds"]) + 1, top), top))
    limit_resource(resource.RLIMIT_AS, int(limits["memory_bytes"]))
    limit_resource(resource.RLIMIT_FSIZE, int(limits["output_bytes"]) + 4096)  # answers go by pipe
    limit_resource(resource.RLIMIT_CORE, 0)
    limit_resource(resource.RLIMIT_NOFILE, 64)
    return setup


def next_request(limits: dict[str, Any]) -> dict[str, Any] | None:
    """The next request (None when the parent is gone), its CPU bound set on this process.

    The soft ``RLIMIT_CPU`` becomes what this process has used plus the request's bound
    (``SIGXCPU`` past it), under the lifetime's hard limit.
    """
    data = _read_frame(sys.stdin.buffer)
    if data is None:
        return None
    used = resource.getrusage(resource.RUSAGE_SELF)
    spent = int(used.ru_utime + used.ru_stime) + 1
    _, hard = resource.getrlimit(resource.RLIMIT_CPU)
    resource.setrlimit(resource.RLIMIT_CPU, (min(spent + int(limits["cpu_seconds"]), hard), hard))
    request: dict[str, Any] = json.loads(data)
    return request


def should_retire(limits: dict[str, Any], served: int) -> bool:
    """Whether this child ends after its answer: memory, requests, or CPU budget spent."""
    used = resource.getrusage(resource.RUSAGE_SELF)
    spent = used.ru_utime + used.ru_stime
    mapped, resident = _memory_now(used.ru_maxrss)
    return (
        resident > RETIRE_RSS
        or 4 * mapped > 3 * int(limits["memory_bytes"])
        or served >= RETIRE_REQUESTS
        or spent + 2 * int(limits["cpu_seconds"]) + 2 > LIFETIME_CPU_SECONDS
    )


def _memory_now(peak_kib: int) -> tuple[int, int]:
    """This process's address space and resident memory in bytes, now.

    Without ``/proc``: no address space, and as resident memory its peak, once the peak
    has grown past what it was at start (the peak of the process it was forked from,
    which ``exec`` keeps).
    """
    statm = _memory.get("statm")
    if statm is not None:
        with contextlib.suppress(OSError, ValueError, IndexError):
            size, resident = os.pread(statm, 128, 0).split()[:2]
            page = os.sysconf("SC_PAGE_SIZE")
            return int(size) * page, int(resident) * page
    return 0, (peak_kib * 1024 if peak_kib > _memory.get("start_peak", 0) else 0)


def send(out: IO[bytes], answer: bytes, output_bytes: int, retire: bool = False) -> None:
    """Write one answer (``U``, ``E``, ``M`` or ``R`` and what follows, or ``ready``).

    An answer larger than ``output_bytes`` is replaced by a message saying so.
    """
    if len(answer) > output_bytes + 1:
        answer = f"E{_too_large(len(answer) - 1, output_bytes)}".encode()
    if answer != b"ready":
        answer = (b"-" if retire else b"+") + answer
    out.write(_HEADER.pack(len(answer)) + answer)
    out.flush()


def _too_large(size: int, limit: int) -> str:
    return f"the output ({size:,} bytes) is larger than the {limit:,}-byte limit"


def _read_frame(stream: IO[bytes]) -> bytes | None:
    header = stream.read(_HEADER.size)
    if len(header) < _HEADER.size:
        return None
    (size,) = _HEADER.unpack(header)
    data = stream.read(size)
    return data if len(data) == size else None
