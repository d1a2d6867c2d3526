"""Running xacro in a confined child process with hard limits (the parent's side).

See :mod:`cspace.xacro_worker` for what the child does to itself. Here, the child is
started with an empty environment (so ``$(env ...)`` and ``$(optenv ...)`` see nothing
of the user's), its output goes to an anonymous file whose size the child's own
``RLIMIT_FSIZE`` caps, and it is killed when it outlives the wall-clock limit. Whatever
the child says is only ever a URDF text or a message for a one-line error.
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, NamedTuple

from .xmlio import MAX_FILE_BYTES, MAX_FILES

if TYPE_CHECKING:  # subprocess, tempfile and ctypes load only when xacro runs
    import subprocess


class XacroLimits(NamedTuple):
    """The bounds of one xacro expansion.

    Attributes:
        cpu_seconds: CPU time the child may use (``RLIMIT_CPU``).
        wall_seconds: Wall-clock time before the child is killed.
        memory_bytes: Address space the child may map (``RLIMIT_AS``); the Python
            interpreter and xacro take about 60 MB of it before any document.
        output_bytes: Largest URDF text the child may write.
        max_files: Most files xacro may open (includes, YAML), each time counted.
        max_bytes: Most bytes in all the files xacro opens.
    """

    cpu_seconds: int = 4
    wall_seconds: float = 5.0
    memory_bytes: int = 512 * 1024 * 1024
    output_bytes: int = MAX_FILE_BYTES
    max_files: int = MAX_FILES
    max_bytes: int = MAX_FILE_BYTES


MAX_ERROR_BYTES = 16 * 1024
"""Most bytes of the child's error message the parent reads."""


class XacroRefused(Exception):
    """The child could not expand the document; the message says why (one line)."""


def run_xacro(
    text: str,
    *,
    file: str,
    folders: Sequence[str],
    packages: Mapping[str, str],
    args: Mapping[str, str],
    limits: XacroLimits,
    require_confinement: bool,
) -> str:
    """Expand ``text`` in a confined child process.

    Args:
        text: The xacro document.
        file: The absolute path xacro resolves relative includes from.
        folders: The only folders the child may read (real paths).
        packages: Every package ``$(find NAME)`` may name -> its folder.
        args: ``<xacro:arg>`` values.
        limits: CPU, wall-clock, memory and output bounds.
        require_confinement: Refuse to expand when the kernel cannot confine the child
            (Landlock and seccomp).

    Returns:
        The URDF text.

    Raises:
        XacroRefused: Expansion failed, hit a limit, or tried what the sandbox refuses.
    """
    import subprocess
    import tempfile

    request = {
        "text": text,
        "file": file,
        "folders": list(folders),
        "packages": dict(packages),
        "args": dict(args),
        "require_confinement": require_confinement,
        "limits": {
            "cpu_seconds": limits.cpu_seconds,
            "memory_bytes": limits.memory_bytes,
            "output_bytes": limits.output_bytes,
            "max_files": limits.max_files,
            "max_bytes": limits.max_bytes,
        },
    }
    with tempfile.TemporaryFile() as out:
        child = subprocess.Popen(
            [sys.executable, "-I", "-m", "cspace.xacro_worker"],
            stdin=subprocess.PIPE,
            stdout=out,
            stderr=subprocess.DEVNULL,
            env={},
            cwd=folders[0] if folders else "/",
            start_new_session=True,
        )
        try:
            child.communicate(json.dumps(request).encode("utf-8"), timeout=limits.wall_seconds)
        except subprocess.TimeoutExpired:
            _kill(child)
            raise XacroRefused(
                f"xacro took longer than {limits.wall_seconds:g} s and was stopped"
            ) from None
        out.seek(0)
        answer = out.read(limits.output_bytes + 2)
    if child.returncode != 0 or answer[:1] not in (b"U", b"E"):
        raise XacroRefused(_death(child.returncode, limits))
    if answer[:1] == b"E":  # a message: a few KiB at most, whatever the child wrote
        answer = answer[: MAX_ERROR_BYTES + 1]
    text = answer[1:].decode("utf-8", errors="replace")
    if answer[:1] == b"E":
        too_big = text.startswith("xacro's output is ")
        raise XacroRefused(
            f"{text}, larger than the {limits.output_bytes:,}-byte limit" if too_big else text
        )
    if len(answer) > limits.output_bytes + 1:
        raise XacroRefused(f"xacro's output is larger than the {limits.output_bytes:,}-byte limit")
    return text


def _kill(child: subprocess.Popen[bytes]) -> None:
    import signal

    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        child.kill()
    child.wait()


def _death(code: int, limits: XacroLimits) -> str:
    """Why the child died, from its exit status."""
    import signal

    reasons = {
        -signal.SIGXCPU: f"xacro used more than {limits.cpu_seconds} s of CPU and was stopped",
        -signal.SIGKILL: "xacro was killed (out of memory or CPU time)",
        -signal.SIGXFSZ: f"xacro's output is larger than the {limits.output_bytes:,}-byte limit",
        0: "xacro stopped without an answer",
        -signal.SIGSEGV: "xacro crashed (its memory limit reached inside a C library?)",
    }
    return reasons.get(code, f"xacro stopped with exit status {code}")
