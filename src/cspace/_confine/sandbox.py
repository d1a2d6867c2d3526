"""Confined child processes with hard limits: the parent's side and the limits a child sets.

Two jobs run outside `cspace`'s own process because they cannot be bounded inside it:
xacro's expansion (it runs the document's Python, `xacro._worker`) and
MuJoCo's compiler (its time and memory grow with the model and it cannot be
interrupted, `mjcf._worker`). Each child is started as ``python -I -m
MODULE`` with an empty environment and no stderr, reads one JSON request on stdin,
caps itself (`limit_self`), and writes its answer to an anonymous file whose size
its own ``RLIMIT_FSIZE`` caps: ``U`` and the result's bytes, or ``E`` and a one-line
message. The parent kills it when it outlives the wall-clock limit.
"""

import contextlib
import json
import os
import resource
import sys
from collections.abc import Callable, Sequence
from typing import IO, TYPE_CHECKING, Any

from cspace._record import NamedTuple

if TYPE_CHECKING:  # subprocess loads only when a child runs
    import subprocess


class ChildLimits(NamedTuple):
    """The bounds of one child process.

    Attributes:
        cpu_seconds: CPU time the child may use (``RLIMIT_CPU``).
        wall_seconds: Wall-clock time before the child is killed.
        memory_bytes: Address space the child may map (``RLIMIT_AS``).
        output_bytes: Largest answer the child may write.
    """

    cpu_seconds: int
    wall_seconds: float
    memory_bytes: int
    output_bytes: int


MAX_ERROR_BYTES = 16 * 1024
"""Most bytes of a child's error message the parent reads."""


class ChildRefused(Exception):
    """The child gave no result; the message says why (one line)."""


class OutOfMemory(ChildRefused):
    """The child ran out of the memory it may use.

    A serving child may have run out only for what earlier requests left mapped: a fresh
    child is asked again (`kept.KeptChild`).
    """


def limit_self(limits: dict[str, Any]) -> None:
    """Cap this (child) process: CPU, address space, file size, no core, 64 open files.

    Args:
        limits: ``cpu_seconds``, ``memory_bytes`` and ``output_bytes``, as the parent
            sent them.
    """
    limit_resource(resource.RLIMIT_CPU, int(limits["cpu_seconds"]), grace=1)  # SIGXCPU, SIGKILL
    limit_resource(resource.RLIMIT_AS, int(limits["memory_bytes"]))
    limit_resource(resource.RLIMIT_FSIZE, int(limits["output_bytes"]) + 4096)  # a backstop
    limit_resource(resource.RLIMIT_CORE, 0)
    limit_resource(resource.RLIMIT_NOFILE, 64)


def limit_resource(kind: int, value: int, grace: int = 0) -> None:
    """Cap a resource at ``value`` (soft), and ``value + grace`` (hard)."""
    _, hard = resource.getrlimit(kind)
    top = value + grace if hard == resource.RLIM_INFINITY else min(value + grace, hard)
    resource.setrlimit(kind, (min(value, top), top))


class RunningChild:
    """A started child: `answer` waits for it (the parent may work meanwhile).

    The request is handed over as a file, so starting a child never waits on it.
    """

    def __init__(
        self,
        module: str,
        request: dict[str, Any],
        limits: ChildLimits,
        what: str,
        cwd: str = "/",
        env: dict[str, str] | None = None,
    ) -> None:
        import subprocess
        import tempfile

        self.limits = limits
        self.what = what
        self.out: IO[bytes] = tempfile.TemporaryFile()  # noqa: SIM115 - closed by answer()
        request = {**request, "limits": {**request.get("limits", {}), **limits._asdict()}}
        with tempfile.TemporaryFile() as given:  # a file, not a pipe: the parent never waits
            given.write(json.dumps(request).encode("utf-8"))
            given.seek(0)
            self.child = subprocess.Popen(
                [sys.executable, "-I", "-m", module],
                stdin=given,
                stdout=self.out,
                stderr=subprocess.DEVNULL,
                env=env or {},
                cwd=cwd,
                start_new_session=True,
            )

    def answer(self) -> bytes:
        """The child's result.

        Raises:
            ChildRefused: The child answered with a message, hit a limit, or died.
        """
        import subprocess

        limits = self.limits
        with self.out:
            try:
                self.child.wait(timeout=limits.wall_seconds)
            except subprocess.TimeoutExpired:
                kill(self.child)
                raise ChildRefused(
                    f"{self.what} took longer than {limits.wall_seconds:g} s and was stopped"
                ) from None
            self.out.seek(0)
            answer = self.out.read(limits.output_bytes + 2)
        if self.child.returncode != 0 or answer[:1] not in (b"U", b"E"):
            raise ChildRefused(death(self.child.returncode, limits, self.what))
        if answer[:1] == b"E":  # a message: a few KiB at most, whatever the child wrote
            text = answer[1 : MAX_ERROR_BYTES + 1].decode("utf-8", errors="replace")
            too_big = text.startswith("the output is ")
            raise ChildRefused(
                f"{self.what}'s output is larger than the {limits.output_bytes:,}-byte limit"
                if too_big
                else text
            )
        if len(answer) > limits.output_bytes + 1:
            raise ChildRefused(
                f"{self.what}'s output is larger than the {limits.output_bytes:,}-byte limit"
            )
        return answer[1:]


def run_child(
    module: str, request: dict[str, Any], limits: ChildLimits, what: str, cwd: str = "/"
) -> bytes:
    """Run ``python -I -m module`` on ``request`` and return its result's bytes.

    Args:
        module: The worker module.
        request: The JSON request (``limits`` are added to it).
        limits: CPU, wall-clock, memory and output bounds.
        what: What runs, for messages (``"xacro"``).
        cwd: The child's working folder.

    Raises:
        ChildRefused: The child answered with a message, hit a limit, or died.
    """
    return RunningChild(module, request, limits, what, cwd).answer()


def write_answer(answer: bytes, output_bytes: int, out: IO[bytes] | None = None) -> None:
    """Write a child's answer (``U...`` or ``E...``), refusing one too large.

    Args:
        answer: The answer.
        output_bytes: The largest result the parent reads.
        out: Where to write it (default: standard output).
    """
    if len(answer) > output_bytes + 1:
        answer = f"Ethe output is {len(answer) - 1:,} bytes".encode()
    stream = out or sys.stdout.buffer
    stream.write(answer)
    stream.flush()


def kill(child: "subprocess.Popen[bytes]") -> None:
    import signal

    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        child.kill()
    child.wait()


def death(code: int, limits: ChildLimits, what: str) -> str:
    """Why the child died, from its exit status."""
    import signal

    reasons = {
        -signal.SIGXCPU: f"{what} used more than {limits.cpu_seconds} s of CPU and was stopped",
        -signal.SIGKILL: f"{what} was killed (out of memory or CPU time)",
        -signal.SIGXFSZ: f"{what}'s output is larger than the {limits.output_bytes:,}-byte limit",
        0: f"{what} stopped without an answer",
        -signal.SIGSEGV: f"{what} crashed (its memory limit reached inside a C library?)",
        -signal.SIGABRT: f"{what} aborted (its memory limit reached inside a C library?)",
    }
    return reasons.get(code, f"{what} stopped with exit status {code}")


def take_request() -> dict[str, Any]:
    """A child's request (JSON on standard input), with its limits applied to itself."""
    request: dict[str, Any] = json.loads(sys.stdin.buffer.read())
    limit_self(request["limits"])
    return request


def answer_reading_nothing(
    warm: Callable[[], None], compute: Callable[[dict[str, Any]], bytes], what: str
) -> int:
    """A child's whole run: take its request, warm up, give up every read, answer.

    Args:
        warm: The libraries' first use (their imports and data files), before the child
            confines itself to reading no file.
        compute: The answer of the request (its bytes, as `write_answer` writes them).
        what: What the child does, for the one line of a child out of memory
            (``parsing the meshes``).

    Returns:
        0, the child's exit status.
    """
    request = take_request()
    warm()
    with contextlib.suppress(OSError):  # the resource limits hold without the kernel layers
        confine_to_entries([])
    try:
        answer = compute(request)
    except MemoryError:
        answer = f"E{what} needed more memory than cspace allows".encode()
    write_answer(answer, int(request["limits"]["output_bytes"]))
    return 0


def quiet_stdout() -> IO[bytes]:
    """Standard output kept for the answer alone; what a library prints goes nowhere."""
    out = os.fdopen(os.dup(1), "wb")
    os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
    return out


def confine_to_entries(entries: Sequence[str]) -> int:
    """Give up capabilities and escaping system calls, then every read but of ``entries``.

    Args:
        entries: Files and folders (`landlock.readable_entries`) that stay readable.

    Returns:
        The Landlock ABI in force (0: none; the seccomp filter may be, see `seccomp`).
    """
    from cspace._confine.landlock import restrict_to_entries
    from cspace._confine.seccomp import deny_escapes, drop_capabilities

    drop_capabilities()
    deny_escapes()
    return restrict_to_entries(entries)


def confine_to_reading(folders: Sequence[str]) -> bool:
    """Give up capabilities and escaping system calls, then every read outside ``folders``.

    Returns:
        Whether both kernel layers are in force (seccomp and Landlock).
    """
    from cspace._confine.landlock import restrict_to_reading
    from cspace._confine.seccomp import deny_escapes, drop_capabilities

    drop_capabilities()
    filtered = deny_escapes()
    return restrict_to_reading(folders) > 0 and filtered
