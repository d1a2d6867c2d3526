"""A count on standard error during long runs: on a terminal only, never in the output.

The command runs with its standard error on a pseudo-terminal of 80 columns (what a
person at a terminal gives it) and its standard output in a file; without a terminal,
nothing is added (the rest of the suite's byte-for-byte tests run that way).
"""

from __future__ import annotations

import fcntl
import os
import pty
import struct
import subprocess
import tempfile
import termios
from pathlib import Path

import numpy as np
import pytest

from conftest import ROBOTS, cspace_command, run_cli

URDFS = sorted(str(p) for p in ROBOTS.glob("*.urdf"))


def _on_a_terminal(*args: str, progress: str) -> tuple[int, bytes, bytes]:
    """Exit code, standard output and what the terminal on standard error received."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
    env = {**os.environ, "NO_COLOR": "1", "CSPACE_PROGRESS": progress}
    with tempfile.TemporaryFile() as out:
        started = subprocess.Popen([*cspace_command(), *args], stdout=out, stderr=slave, env=env)
        os.close(slave)
        seen = b""
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:  # the command has closed the terminal
                break
            if not data:
                break
            seen += data
        os.close(master)
        code = started.wait(timeout=120)
        out.seek(0)
        return code, out.read(), seen


def test_many_files_are_counted_on_a_terminal_and_the_output_is_unchanged() -> None:
    names = [*URDFS * 3, "/nonexistent/robot.urdf"]
    code, out, seen = _on_a_terminal("inspect", *names, "--format", "jsonl", progress="0")
    plain = run_cli("inspect", *names, "--format", "jsonl")
    assert code == plain.code == 2
    assert out.decode() == plain.stdout  # the count is on the terminal only
    total = len(names)
    assert f"{total}/{total}".encode() in seen and b"file/s" in seen
    # The error is written around the count: a line of its own, whole.
    error = b"cspace: error: /nonexistent/robot.urdf: no such file [file-unreadable]"
    assert any(line.rstrip(b"\r").split(b"\r")[-1] == error for line in seen.split(b"\n"))
    assert b"file/s" not in plain.stderr.encode()  # not a terminal: no count


@pytest.mark.bounded
def test_a_short_run_and_a_count_turned_off_show_nothing(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # A run shorter than its delay shows nothing: here a delay of an hour, which no run
    # reaches however busy the machine (one may take the default's second there).
    for progress in ("3600", "off"):  # "off" never shows
        code, _, seen = _on_a_terminal(
            "inspect", *URDFS[:3], "--format", "jsonl", progress=progress
        )
        assert code == 0 and seen == b"", (progress, seen)
    from cspace._cli import progress as _progress

    for asked in ("", " ", "soon", "-1", "nan"):  # unset or unreadable: the default
        monkeypatch.setenv("CSPACE_PROGRESS", asked)
        assert _progress._delay() == 1.0, asked
    monkeypatch.setenv("CSPACE_PROGRESS", "OFF")
    assert _progress._delay() is None


def test_rows_written_to_a_file_are_counted(tmp_path: Path) -> None:
    counted = tmp_path / "counted.npy"
    plain = tmp_path / "plain.npy"
    args = ("sample", URDFS[0], "-n", "300000", "--seed", "3", "--format", "npy", "-o")
    code, _, seen = _on_a_terminal(*args, str(counted), progress="0")
    assert code == 0 and run_cli(*args, str(plain)).code == 0
    assert counted.read_bytes() == plain.read_bytes()
    assert b"/300k [" in seen and b"row/s" in seen
    assert np.load(counted).shape[0] == 300_000
