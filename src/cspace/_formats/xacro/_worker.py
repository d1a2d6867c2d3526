"""The process that expands one xacro document, confined (run as ``python -I -m``).

xacro evaluates the Python expressions in ``${...}`` with ``eval``, which is no sandbox:
a document can reach any Python object. So expansion never runs in `cspace`'s own
process. The parent (`xacro._sandbox`) starts this module with an empty
environment and sends one JSON request on standard input; this process then, before it
reads the document:

1. caps itself with resource limits: CPU seconds, address space, file size (its output
   goes to a file the parent opened, so this caps the output), 64 open files, no core;
2. imports everything expansion needs (nothing can be imported later);
3. gives up every capability, and installs a seccomp filter (`seccomp`):
   no socket of any kind, no new process, no program started, no ``memfd``, no
   ``ptrace``, no ``io_uring``;
4. confines itself with Landlock (`landlock`) to reading the allowed folders:
   no other file, no writing, no TCP, no signal to another process;
5. installs an audit hook that refuses, at the Python level too, starting programs,
   forking, sockets, ``ctypes``, frame access, imports, writing, and opening anything
   but a regular file inside the allowed folders, and counts the files and bytes xacro
   includes. It is never switched off.

The kernel layers (3, 4) are what holds. The audit hook gives clearer messages for
what a document tries in plain sight, but code that gets out of xacro's ``eval`` can
reach and rewrite any Python object, the hook's included: it is no boundary.

It writes its answer to standard output: ``U`` and the URDF's UTF-8 bytes, or ``E`` and
a one-line message.
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import stat
import sys
from collections.abc import Sequence
from typing import Any

from cspace._confine.sandbox import confine_to_reading, take_request, write_answer

_REFUSED_EVENTS = (
    "os.system",
    "os.exec",
    "os.posix_spawn",
    "os.spawn",
    "os.fork",
    "os.forkpty",
    "os.kill",
    "os.killpg",
    "os.putenv",
    "os.unsetenv",
    "os.remove",
    "os.rename",
    "os.rmdir",
    "os.mkdir",
    "os.symlink",
    "os.link",
    "os.chmod",
    "os.chown",
    "os.truncate",
    "os.utime",
    "os.setxattr",
    "os.removexattr",
    "os.chflags",
    "os.startfile",
    "subprocess.Popen",
    "socket.",
    "ctypes.",
    "shutil.",
    "sys.addaudithook",
    "sys._getframe",
    "sys._current_frames",
    "object.__getattr__",
    "function.__new__",
    "code.__new__",
    "object.__setattr__",
    "webbrowser.open",
    "urllib.Request",
    "http.client.connect",
    "ftplib.connect",
    "import",
)
"""Audit events refused once expansion starts (``import``: everything is imported
before; ``object.__setattr__`` on built-in types is how sandboxes get unpicked)."""


MAX_MESSAGE_CHARS = 4096
"""Longest error message the child sends back (the parent shortens it further)."""


class _Refused(PermissionError):
    """An operation the xacro sandbox does not allow (``strerror`` says why)."""

    def __init__(self, why: str, name: str = "") -> None:
        super().__init__(errno.EACCES, why, name)

    def __str__(self) -> str:
        return f"{self.strerror}: {self.filename}" if self.filename else str(self.strerror)


class _Guard:
    """The audit hook: what xacro may open, and how much."""

    def __init__(self, folders: Sequence[str], max_files: int, max_bytes: int) -> None:
        self.folders = tuple(folders)
        self.max_files = max_files
        self.max_bytes = max_bytes
        self.files = 0
        self.bytes = 0

    def __call__(
        self, event: str, args: tuple[Any, ...], refused: tuple[str, ...] = _REFUSED_EVENTS
    ) -> None:
        # ``refused`` is bound when the class is made: no module global to rewrite.
        if event == "open":
            self._open(args)
        elif event.startswith(refused):
            raise _Refused(f"xacro may not do this here ({event})")

    def _open(self, args: tuple[Any, ...]) -> None:
        target, mode, flags = args
        if isinstance(target, int):  # an already open descriptor
            return
        writing = (isinstance(mode, str) and any(c in mode for c in "wax+")) or (
            isinstance(flags, int) and flags & (os.O_WRONLY | os.O_RDWR | os.O_CREAT)
        )
        name = os.fsdecode(target)
        if writing:
            raise _Refused("xacro may not write files", name)
        real = os.path.realpath(name)
        if not any(_readable(real, folder) for folder in self.folders):
            raise _Refused("outside the files xacro may read", name)
        try:
            mode_bits = os.stat(real)
        except OSError:
            return  # opening it fails on its own, with its own message
        if stat.S_ISDIR(mode_bits.st_mode):
            return
        if not stat.S_ISREG(mode_bits.st_mode):
            raise _Refused("not a regular file", name)
        self.files += 1
        self.bytes += mode_bits.st_size
        if self.files > self.max_files or self.bytes > self.max_bytes:
            raise _Refused(
                f"xacro read more than {self.max_files:,} files or {self.max_bytes:,} bytes"
            )


def _readable(real: str, folder: str) -> bool:
    """``real`` is ``folder`` or lies in it, but not in a hidden entry at its top."""
    if os.path.commonpath((real, folder)) != folder:
        return False
    relative = os.path.relpath(real, folder)
    return relative == "." or not relative.startswith(".")


def _expand(request: dict[str, Any]) -> str:
    import xacro
    from xacrodoc import XacroDoc, packages

    packages.update_package_cache(dict(request["packages"]))  # found by the parent
    xacro.init_stacks(request["file"])
    printed = io.StringIO()
    with contextlib.redirect_stderr(printed), contextlib.redirect_stdout(printed):
        document = XacroDoc.from_string(
            request["text"], subargs=dict(request["args"]), resolve_packages=False
        )
        text: str = document.to_urdf_string()
    return text


_WARM_UP = """<robot name="w" xmlns:xacro="http://www.ros.org/wiki/xacro">
<xacro:property name="p" value="${radians(90) * 2}"/>
<xacro:macro name="m" params="n *b"><link name="${n}"><xacro:insert_block name="b"/></link>
</xacro:macro><xacro:m n="l${p}"><visual/></xacro:m><xacro:if value="${p > 0}"/></robot>"""
"""A small document that makes xacro import what it imports on first use."""


def _preload() -> None:
    """Import what expansion may import lazily: nothing can be imported afterwards."""
    import encodings.idna  # noqa: F401
    import xml.dom.expatbuilder
    import xml.dom.minidom  # noqa: F401

    import yaml  # type: ignore[import-untyped]
    from xacrodoc import XacroDoc, packages

    yaml.safe_load("a: [1, 2.5, {b: c}]")  # xacro.load_yaml
    packages.reset()  # its finder tries to import ROS 2's ament index: before, not after
    XacroDoc.from_string(_WARM_UP, resolve_packages=False).to_urdf_string()


def _reason(exc: BaseException, memory_bytes: int) -> str:
    """One line for what stopped xacro; xacro wraps the real cause in its own exception."""
    cause: BaseException | None = exc
    while cause is not None:
        if isinstance(cause, _Refused):
            return str(cause)
        if isinstance(cause, MemoryError):
            return f"xacro needed more than the {memory_bytes // 2**20:,} MiB of memory it may use"
        if isinstance(cause, RecursionError):
            return "xacro recursed too deep (a macro calling itself, or elements nested too deep)"
        cause = getattr(cause, "exc", None) or cause.__cause__ or cause.__context__
    try:
        said = str(exc)
        if len(said) > 2 * MAX_MESSAGE_CHARS:  # cut before anything copies it again
            said = f"{said[:MAX_MESSAGE_CHARS]} ... {said[-MAX_MESSAGE_CHARS:]}"
        return " ".join(said.split()) or type(exc).__name__
    except MemoryError:
        return f"xacro needed more than the {memory_bytes // 2**20:,} MiB of memory it may use"


def main() -> int:
    """Read the request, confine this process, expand, write the answer."""
    request = take_request()
    limits = request["limits"]
    _preload()
    folders = [os.path.realpath(f) for f in request["folders"]]
    confined = confine_to_reading(folders)
    if not confined and request["require_confinement"]:
        sys.stdout.buffer.write(
            b"Ethe kernel cannot confine xacro (Linux Landlock and seccomp are needed)"
        )
        return 0
    sys.addaudithook(_Guard(folders, int(limits["max_files"]), int(limits["max_bytes"])))
    try:
        answer = b"U" + _expand(request).encode("utf-8")
    except BaseException as exc:  # xacro raises its own, ValueError, KeyError, ...
        reason = _reason(exc, int(limits["memory_bytes"]))
        if len(reason) > MAX_MESSAGE_CHARS:  # a message, not a channel for the output
            half = MAX_MESSAGE_CHARS // 2
            reason = f"{reason[:half]} ... ({len(reason):,} characters) ... {reason[-half:]}"
        answer = b"E" + reason.encode("utf-8")
    write_answer(answer, int(limits["output_bytes"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
