"""Linux seccomp: a process gives up the system calls it must never make, for good.

Landlock (`landlock`) confines files, TCP and (from ABI 6) signals, but not
UDP, Unix sockets, new processes, System V IPC or other processes' resource limits. The
process that expands xacro (see `xacro._worker`) therefore also installs a
seccomp filter that makes these system calls fail with ``EPERM``:

- every socket call; ``fork``, ``vfork``, ``clone`` (no process and no thread: the
  worker needs neither), ``execve``;
- signals to any process (``kill``, ``tgkill``, ``pidfd_*``), ``ptrace`` and
  cross-process memory access, ``prlimit64`` on another process (on itself it is how
  the C library sets limits);
- memory and files outside the limits: ``memfd_create``, System V shared memory,
  semaphores and message queues, POSIX message queues, ``fallocate`` and ``ftruncate``
  (which would grow the output file past ``RLIMIT_FSIZE``), ``userfaultfd``;
- what could do the rest behind the filter's back or watch the machine: ``io_uring``,
  ``bpf``, ``perf_event_open``, ``inotify``, ``fanotify``, namespaces, key rings, file
  handles.

``clone3`` fails with ``ENOSYS`` (the C library then tries ``clone``, refused too). A
system call of another architecture's numbering (32-bit calls on x86-64, x32) kills the
process. The filter is classic BPF written here; it needs no library. It is defined for
x86-64 and AArch64; elsewhere `deny_escapes` returns False and installs nothing.
`drop_capabilities` also gives up every capability, so that a process running as
root cannot reboot, mount, load modules or change the clock either.
"""

from __future__ import annotations

import ctypes
import errno
import platform
import struct

_AUDIT_ARCH = {"x86_64": 0xC000003E, "aarch64": 0xC00000B7}
_PRLIMIT64 = {"x86_64": 302, "aarch64": 261}
_FCNTL = {"x86_64": 72, "aarch64": 25}
_FCNTL_REFUSED = (8, 15, 10, 1024, 1026)
"""F_SETOWN, F_SETOWN_EX, F_SETSIG (a signal to any process of the same user, through
``O_ASYNC``), F_SETLEASE, F_NOTIFY."""
_CLONE3 = 435
_DENIED = {
    "x86_64": (
        41, 42, 43, 44, 45, 46, 47, 49, 50, 53, 288, 299, 307,  # sockets
        56, 57, 58, 59, 322,  # clone, fork, vfork, execve, execveat
        62, 200, 234, 129, 297, 424, 434, 438,  # kill .. pidfd_open, pidfd_getfd
        101, 310, 311, 312, 440,  # ptrace, process_vm_*, kcmp, process_madvise
        319, 447, 323,  # memfd_create, memfd_secret, userfaultfd
        29, 30, 31, 67, 64, 65, 66, 220, 68, 69, 70, 71,  # System V IPC
        240, 241, 242, 243, 244, 245,  # POSIX message queues
        285, 77,  # fallocate, ftruncate
        425, 426, 427, 321, 298, 253, 254, 294, 300,  # io_uring .. inotify, fanotify
        272, 308, 248, 249, 250, 303, 304,  # unshare .. open_by_handle_at
        90, 91, 92, 93, 94, 260, 268, 452, 132, 235, 261, 280, 76,  # chmod .. truncate
        188, 189, 190, 191, 192, 193, 194, 195, 196, 197, 198, 199, 463, 466,  # xattrs
        141, 142, 144, 203, 314, 251, 256, 279, 238, 237, 450, 103,  # priorities .. syslog
    ),
    "aarch64": (
        198, 199, 200, 201, 202, 203, 204, 205, 206, 207, 208, 209, 210, 211, 212, 242, 243, 269,
        220, 221, 281,  # clone, execve, execveat
        129, 130, 131, 138, 240, 424, 434, 438,
        117, 270, 271, 272, 440,
        279, 447, 282,
        186, 187, 188, 189, 190, 191, 192, 193, 194, 195, 196, 197,
        180, 181, 182, 183, 184, 185,
        47, 46,
        425, 426, 427, 280, 241, 26, 27, 262,
        97, 268, 217, 218, 219, 264, 265,
        52, 53, 54, 55, 452, 88, 45,
        5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 463, 466,
        140, 118, 119, 122, 274, 30, 238, 239, 237, 235, 450, 116,
    ),
}  # fmt: skip
"""System calls refused with ``EPERM``, by architecture (from the kernel's tables)."""

_X32_BIT = 0x40000000

_LD_W_ABS, _JEQ_K, _JGE_K, _RET_K = 0x20, 0x15, 0x35, 0x06
_RET_ALLOW, _RET_KILL_PROCESS = 0x7FFF0000, 0x80000000
_RET_EPERM, _RET_ENOSYS = 0x00050000 | errno.EPERM, 0x00050000 | errno.ENOSYS
_NR, _ARCH, _ARG0, _ARG1 = 0, 4, 16, 24  # offsets in struct seccomp_data (little-endian)
_PR_SET_NO_NEW_PRIVS, _PR_SET_SECCOMP, _SECCOMP_MODE_FILTER = 38, 22, 2


def _program(machine: str) -> list[tuple[int, int, int, int]]:
    """The filter's instructions: (code, jump if true, jump if false, constant)."""
    denied = _DENIED[machine]
    body: list[tuple[int, int, int, int]] = [
        (_LD_W_ABS, 0, 0, _ARCH),
        (_JEQ_K, 1, 0, _AUDIT_ARCH[machine]),
        (_RET_K, 0, 0, _RET_KILL_PROCESS),  # another architecture's numbering
        (_LD_W_ABS, 0, 0, _NR),
        (_JGE_K, 0, 1, _X32_BIT),
        (_RET_K, 0, 0, _RET_KILL_PROCESS),  # x32
        (_JEQ_K, 0, 1, _CLONE3),
        (_RET_K, 0, 0, _RET_ENOSYS),
        (_JEQ_K, 0, 4, _PRLIMIT64[machine]),  # not prlimit64: on to fcntl
        (_LD_W_ABS, 0, 0, _ARG0),
        (_JEQ_K, 0, 1, 0),
        (_RET_K, 0, 0, _RET_ALLOW),  # its own limits
        (_RET_K, 0, 0, _RET_EPERM),  # another process's
    ]
    refused = _FCNTL_REFUSED
    body.append((_JEQ_K, 0, len(refused) + 3, _FCNTL[machine]))  # not fcntl: on to the table
    body.append((_LD_W_ABS, 0, 0, _ARG1))
    for k, command in enumerate(refused):  # equal: jump to the EPERM after the ALLOW
        body.append((_JEQ_K, len(refused) - k, 0, command))
    body.append((_RET_K, 0, 0, _RET_ALLOW))
    body.append((_RET_K, 0, 0, _RET_EPERM))
    for k, number in enumerate(denied):  # equal: jump to the EPERM after the table
        body.append((_JEQ_K, len(denied) - k, 0, number))
    body.append((_RET_K, 0, 0, _RET_ALLOW))
    body.append((_RET_K, 0, 0, _RET_EPERM))
    return body


class _Filter(ctypes.Structure):
    _fields_ = (
        ("code", ctypes.c_uint16),
        ("jt", ctypes.c_uint8),
        ("jf", ctypes.c_uint8),
        ("k", ctypes.c_uint32),
    )


class _Program(ctypes.Structure):
    _fields_ = (("len", ctypes.c_ushort), ("filter", ctypes.POINTER(_Filter)))


def supported() -> bool:
    """Whether `deny_escapes` has a filter for this machine (Linux on x86-64, AArch64)."""
    return platform.system() == "Linux" and platform.machine() in _DENIED


def deny_escapes() -> bool:
    """Install the filter in this process (and every thread and child it would make).

    Returns:
        True when installed; False on a machine it is not defined for.

    Raises:
        OSError: The kernel refused the filter.
    """
    if not supported():
        return False
    machine = platform.machine()
    if struct.pack("=I", 1)[0] != 1:  # pragma: no cover - both are little-endian
        return False
    program = _program(machine)
    filters = (_Filter * len(program))(*(_Filter(*op) for op in program))
    fprog = _Program(len(program), filters)
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.prctl(_PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0):
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_NO_NEW_PRIVS) failed")
    if libc.prctl(_PR_SET_SECCOMP, _SECCOMP_MODE_FILTER, ctypes.byref(fprog), 0, 0):
        raise OSError(ctypes.get_errno(), "prctl(PR_SET_SECCOMP) failed")
    return True


_CAPABILITY_VERSION_3 = 0x20080522
_PR_CAPBSET_DROP = 24


def drop_capabilities() -> None:
    """Give up every capability of this process, for good (root keeps its uid, no powers).

    Raises:
        OSError: The kernel refused.
    """
    libc = ctypes.CDLL(None, use_errno=True)
    for capability in range(64):  # the bounding set, so that nothing can regain them
        if libc.prctl(_PR_CAPBSET_DROP, capability, 0, 0, 0) and ctypes.get_errno() not in (
            errno.EINVAL,  # no such capability on this kernel
            errno.EPERM,  # not ours to drop (not root): we do not have it either
        ):
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) failed")
    header = (ctypes.c_uint32 * 2)(_CAPABILITY_VERSION_3, 0)
    data = (ctypes.c_uint32 * 6)()  # effective, permitted, inheritable: twice, all zero
    if libc.capset(ctypes.byref(header), ctypes.byref(data)):
        raise OSError(ctypes.get_errno(), "capset failed")
