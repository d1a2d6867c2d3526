"""Linux Landlock: a process confines itself to reading a few folders, for good.

Landlock is an unprivileged Linux security module (kernel 5.13 and later). A process
builds a ruleset ("these accesses are handled; these folders get these of them") and
restricts itself; from then on the kernel refuses every handled access not granted,
whatever code runs in the process, and the restriction is inherited and cannot be lifted.
`cspace` uses it in the process that expands xacro (see `xacro._worker`):
read-only access beneath the allowed folders, and nothing else: no writing, no running
a program, no TCP (ABI 4 and later), no signals or abstract Unix sockets outside the
process (ABI 6 and later).

The system calls are reached through ``ctypes`` (their numbers are the same on every
architecture); nothing is installed.
"""

from __future__ import annotations

import ctypes
import os
from collections.abc import Sequence

_CREATE_RULESET, _ADD_RULE, _RESTRICT_SELF = 444, 445, 446
_CREATE_RULESET_VERSION = 1 << 0
_RULE_PATH_BENEATH = 1
_PR_SET_NO_NEW_PRIVS = 38

_READ_FILE, _READ_DIR = 1 << 2, 1 << 3
_FS_ACCESS_BY_ABI = {1: (1 << 13) - 1, 2: (1 << 14) - 1, 3: (1 << 15) - 1, 5: (1 << 16) - 1}
"""Every filesystem access each ABI version handles (execute, write, read, make, ...)."""
_NET_ALL = (1 << 0) | (1 << 1)  # bind and connect TCP (ABI 4)
_SCOPE_ALL = (1 << 0) | (1 << 1)  # abstract Unix sockets and signals (ABI 6)


class _RulesetAttr(ctypes.Structure):
    _fields_ = (
        ("handled_access_fs", ctypes.c_uint64),
        ("handled_access_net", ctypes.c_uint64),
        ("scoped", ctypes.c_uint64),
    )


class _PathBeneathAttr(ctypes.Structure):
    _pack_ = 1
    _fields_ = (("allowed_access", ctypes.c_uint64), ("parent_fd", ctypes.c_int32))


def _libc() -> ctypes.CDLL:
    return ctypes.CDLL(None, use_errno=True)


def _allow(libc: ctypes.CDLL, ruleset: int, path: str, access: int) -> None:
    fd = os.open(path, os.O_PATH | os.O_CLOEXEC | os.O_NOFOLLOW)  # a link swapped in fails
    try:
        rule = _PathBeneathAttr(access, fd)
        if libc.syscall(_ADD_RULE, ruleset, _RULE_PATH_BENEATH, ctypes.byref(rule), 0):
            raise OSError(ctypes.get_errno(), f"landlock_add_rule failed for {path}")
    finally:
        os.close(fd)


def abi_version() -> int:
    """The Landlock ABI version the kernel offers; 0 when it has none (or not Linux)."""
    if not hasattr(os, "sched_getaffinity"):  # not Linux
        return 0
    version = _libc().syscall(_CREATE_RULESET, None, ctypes.c_size_t(0), _CREATE_RULESET_VERSION)
    return max(int(version), 0)


def readable_entries(folder: str) -> list[str]:
    """What of ``folder`` may be read: every entry at its top but hidden ones and links.

    ``.git`` (whose ``config`` holds a CI checkout's token), ``.github``, ``.env`` and the
    like are left out: a robot file's package needs none of them. So are links: a rule
    is put on what a path leads to, and a committed ``root -> /`` would open everything.
    (A link further down is harmless: the kernel checks where it leads.) Nor is anything
    but a file or a folder: a FIFO or a socket committed beside the robot file is read by
    nobody, and Landlock takes no rule on it.
    """
    with os.scandir(folder) as entries:
        return sorted(
            e.path
            for e in entries
            if not e.name.startswith(".")
            and not e.is_symlink()
            and (e.is_file(follow_symlinks=False) or e.is_dir(follow_symlinks=False))
        )


def restrict_to_reading(folders: Sequence[str]) -> int:
    """Confine this process, for good, to reading files beneath ``folders``.

    The entries at the top of each folder, but the hidden ones and links (see
    `readable_entries`), may be read and listed, with everything beneath. The
    folder itself is not listed: a listing right there would reach beneath the hidden
    entries too (``.git/refs`` names branches).

    Args:
        folders: Folders whose files (and subfolders) stay readable; each must exist.

    Returns:
        The ABI version applied, or 0 when the kernel offers no Landlock (nothing was
        restricted: the caller decides whether to go on).

    Raises:
        OSError: The kernel refused a step (the process is then not restricted).
    """
    return restrict_to_entries([e for folder in folders for e in readable_entries(folder)])


def restrict_to_entries(entries: Sequence[str]) -> int:
    """Confine this process, for good, to reading ``entries`` and what is beneath them.

    Args:
        entries: Files and folders, as `readable_entries` lists them.

    Returns:
        The ABI version applied, or 0 when the kernel offers no Landlock.

    Raises:
        OSError: The kernel refused a step (the process is then not restricted).
    """
    abi = abi_version()
    if abi == 0:
        return 0
    libc = _libc()
    fs = _FS_ACCESS_BY_ABI[max(v for v in _FS_ACCESS_BY_ABI if v <= abi)]
    attr = _RulesetAttr(fs, _NET_ALL if abi >= 4 else 0, _SCOPE_ALL if abi >= 6 else 0)
    size = ctypes.sizeof(_RulesetAttr) if abi >= 6 else (16 if abi >= 4 else 8)
    ruleset = libc.syscall(_CREATE_RULESET, ctypes.byref(attr), ctypes.c_size_t(size), 0)
    if ruleset < 0:
        raise OSError(ctypes.get_errno(), "landlock_create_ruleset failed")
    try:
        for entry in entries:
            regular = os.path.isfile(entry) and not os.path.islink(entry)
            _allow(libc, ruleset, entry, _READ_FILE if regular else _READ_FILE | _READ_DIR)
        if libc.prctl(_PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0):
            raise OSError(ctypes.get_errno(), "prctl(PR_SET_NO_NEW_PRIVS) failed")
        if libc.syscall(_RESTRICT_SELF, ruleset, 0):
            raise OSError(ctypes.get_errno(), "landlock_restrict_self failed")
    finally:
        os.close(ruleset)
    return abi
