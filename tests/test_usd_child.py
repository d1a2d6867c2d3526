"""The OpenUSD child a process keeps (`_usd_child`): reused from one stage to the next,
never by a forked process, never outliving its process, never serving a stale layer.

Hostile stages against the child (bombs, bounds, what a stage may read while the child
serves others) are in ``tests/test_usd_hostile.py``.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import cspace
from cspace._formats.usd import child as _usd_child

from conftest import HANG_SECONDS

CONVERTED = Path(__file__).parent / "usd" / "converted"

_SCRIPT = """
import os, sys, cspace
from cspace._formats.usd import child as _usd_child

def read():
    assert cspace.inspect(sys.argv[1]).manifold.notation == "R^6 × S^1"
    print(_usd_child.live_pid(), flush=True)

read()
read()  # the same child
forked = os.fork()
if forked == 0:  # a child of its own, never the parent's
    read()
    os._exit(0)
os.waitpid(forked, 0)
read()  # the parent's child, untouched by the fork
if sys.argv[2] == "wait":
    sys.stdin.read()
"""


def _ended(pid: int) -> bool:
    """Whether the process is gone (or a zombie, waiting for a reaper: it runs no more)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as stat:
            return stat.read().rsplit(b")", 1)[1].split()[0] in (b"Z", b"X")
    except FileNotFoundError:
        return True


def _is_usd_child(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as cmdline:
            return b"cspace._formats.usd._worker" in cmdline.read()
    except FileNotFoundError:
        return False


def _script(tmp_path: Path, how: str) -> subprocess.Popen[str]:
    stage = shutil.copy(CONVERTED / "arm7.usda", tmp_path / "arm.usda")
    return subprocess.Popen(
        [sys.executable, "-c", _SCRIPT, str(stage), how],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )


def test_one_child_serves_a_process_and_a_fork_starts_its_own(tmp_path: Path) -> None:
    script = _script(tmp_path, "exit")
    out, _ = script.communicate(timeout=120)
    first, again, forked, after = map(int, out.split())
    assert script.returncode == 0
    assert first == again == after and forked != first
    assert _ended(first)  # killed and reaped when its process exited


@pytest.mark.bounded
def test_a_child_ends_when_its_process_is_killed(tmp_path: Path) -> None:
    script = _script(tmp_path, "wait")
    assert script.stdout is not None
    pids = [int(script.stdout.readline()) for _ in range(4)]
    assert _is_usd_child(pids[0]) and not _ended(pids[0])
    script.send_signal(signal.SIGKILL)  # no atexit: the child sees its parent die
    script.wait()
    # It dies at once (PR_SET_PDEATHSIG); its reaper may lag, the more on a busy
    # machine: the deadline is only a guard against a child that never ends.
    deadline = time.monotonic() + HANG_SECONDS
    while not _ended(pids[0]) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert _ended(pids[0])


def test_a_changed_or_new_file_is_read_anew_by_a_live_child(tmp_path: Path) -> None:
    """No layer is kept between stages; a file added after the child started (its
    Landlock rules name a folder's entries as they were) is read by a new child."""
    stage = tmp_path / "robot.usda"
    shutil.copy(CONVERTED / "arm7.usda", stage)
    _usd_child.close()
    try:
        assert cspace.inspect(stage).manifold.notation == "R^6 × S^1"
        served = _usd_child.live_pid()
        shutil.copy(CONVERTED / "gripper_mimic.usda", stage)
        assert cspace.inspect(stage).manifold.notation == "R^1"
        assert _usd_child.live_pid() == served
        added = shutil.copy(CONVERTED / "arm7.usda", tmp_path / "added.usda")
        assert cspace.inspect(added).manifold.notation == "R^6 × S^1"
        assert _usd_child.live_pid() not in (None, served)
    finally:
        _usd_child.close()


def test_a_folder_walk_reads_its_folders_with_one_child_a_process(tmp_path: Path) -> None:
    """Ten robots in ten folders, in this process: one child, confined to the folders of
    the run, serves them all."""
    for i in range(10):
        (tmp_path / f"r{i}").mkdir()
        shutil.copy(CONVERTED / "arm7.usda", tmp_path / f"r{i}" / "robot.usda")
    _usd_child.close()
    started = []
    original = _usd_child.ServingChild.__init__

    def counted(self: _usd_child.ServingChild, *args: object) -> None:
        started.append(args[1])
        original(self, *args)  # type: ignore[arg-type]

    _usd_child.ServingChild.__init__ = counted  # type: ignore[method-assign]
    try:
        files = sorted(str(p) for p in tmp_path.glob("*/robot.usda"))
        done = list(cspace.inspect_many(files, jobs=1))
    finally:
        _usd_child.ServingChild.__init__ = original  # type: ignore[method-assign]
        _usd_child.within(())
        _usd_child.close()
    assert all(d.report is not None for d in done)
    folder = os.path.realpath(tmp_path)
    assert started == [[os.path.join(folder, f"r{i}") for i in range(10)]]


def test_a_large_process_keeps_its_child() -> None:
    """A child started by a process of 900 MiB is not taken for one that grew past its
    memory bound (``exec`` keeps the parent's peak in ``getrusage``): it serves on."""
    script = (
        "import sys, cspace\n"
        "from cspace._formats.usd import child as _usd_child\n"
        "ballast = bytearray(900 << 20)\n"
        "ballast[::4096] = b'x' * len(ballast[::4096])\n"
        "pids = []\n"
        "for _ in range(3):\n"
        "    cspace.inspect(sys.argv[1])\n"
        "    pids.append(_usd_child.live_pid())\n"
        "print(pids)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script, str(CONVERTED / "arm7.usda")],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    pids = eval(done.stdout)  # a list of three ints, printed by the script above
    assert pids[0] is not None and pids == [pids[0]] * 3
