"""Shared test helpers: where things are, and running the `cspace` command as a user does."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import inotify_simple
import pytest
from hypothesis import settings

# Every property test tries the same examples on every run and every machine: a failure
# in CI is reproducible, and no test passes or fails by the luck of the draw.
settings.register_profile("cspace", derandomize=True, database=None, deadline=None)
settings.load_profile("cspace")

REPO = Path(__file__).resolve().parent.parent
ROBOTS = REPO / "robots"


@dataclass(frozen=True)
class Run:
    """What one run of the `cspace` command did."""

    code: int
    stdout: str
    stderr: str


def cspace_command() -> list[str]:
    """The installed `cspace` script next to this interpreter (the one a user runs)."""
    script = Path(sys.executable).with_name("cspace")
    if script.exists():
        return [str(script)]
    found = shutil.which("cspace")
    if found is None:
        raise RuntimeError("the cspace command is not installed (run `make test`)")
    return [found]


def run_cli(
    *args: str,
    cwd: Path = REPO,
    stdin: bytes | None = None,
    timeout: float = 60,
    env: dict[str, str] | None = None,
) -> Run:
    """Run `cspace ARGS...` in a subprocess and capture its exit code and output."""
    full_env = {**os.environ, "NO_COLOR": "1", **(env or {})}
    done = subprocess.run(
        [*cspace_command(), *args],
        cwd=cwd,
        input=stdin,
        capture_output=True,
        timeout=timeout,
        env=full_env,
        check=False,
    )
    return Run(
        done.returncode,
        done.stdout.decode("utf-8", "replace"),
        done.stderr.decode("utf-8", "replace"),
    )


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


def run_cli_many(commands: list[tuple[str, ...]], timeout: float = 60) -> list[Run]:
    """Run several `cspace` commands, as many at a time as there are cores; results in order."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=max(1, os.cpu_count() or 1)) as pool:
        return list(pool.map(lambda args: run_cli(*args, timeout=timeout), commands))


# --- hostile input: bounded time and memory ------------------------------------------

SECONDS = 10.0
"""Wall-clock bound per case (they take 0.1-0.6 s on a 2-core machine)."""
PEAK_MIB = 600
"""Peak resident memory bound per case (importing Pinocchio alone takes about 90 MiB)."""

_MEASURE = """
import json, resource, subprocess, sys, time
start = time.perf_counter()
done = subprocess.run(sys.argv[1:], stdin=sys.stdin, capture_output=True, timeout=120)
print(json.dumps({
    "code": done.returncode,
    "seconds": time.perf_counter() - start,
    "peak_mib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024,
    "stdout": done.stdout.decode("utf-8", "replace"),
    "stderr": done.stderr.decode("utf-8", "replace"),
}))
"""


@dataclass(frozen=True)
class Measured:
    run: Run
    seconds: float
    peak_mib: float


def measured(
    *args: str, cwd: Path, env: dict[str, str] | None = None, stdin: bytes | None = None
) -> Measured:
    """Run `cspace ARGS...` and measure its wall time and peak memory (its children too)."""
    env = {**os.environ, "NO_COLOR": "1", **(env or {})}
    done = subprocess.run(
        [sys.executable, "-c", _MEASURE, *cspace_command(), *args],
        cwd=cwd,
        input=stdin if stdin is not None else b"",
        capture_output=True,
        timeout=180,
        env=env,
        check=True,
    )
    out = json.loads(done.stdout)
    return Measured(Run(out["code"], out["stdout"], out["stderr"]), out["seconds"], out["peak_mib"])


def assert_bounded_error(result: Measured, code: str) -> str:
    """Exit 2 with one line naming the error code, within the time and memory bounds."""
    assert result.seconds < SECONDS, result
    assert result.peak_mib < PEAK_MIB, result
    assert result.run.code == 2, result
    assert result.run.stdout == ""
    assert result.run.stderr.count("\n") == 1 and result.run.stderr.startswith("cspace: error: ")
    assert result.run.stderr.rstrip().endswith(f"[{code}]"), result.run.stderr
    return result.run.stderr


class OpenWatch:
    """Every open of a file in a folder, by any process, while the watch is on."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.inotify = inotify_simple.INotify()
        flags = inotify_simple.flags
        self.inotify.add_watch(folder, flags.OPEN | flags.ACCESS)

    def opened(self) -> list[str]:
        return [event.name for event in self.inotify.read(timeout=0)]

    def close(self) -> None:
        self.inotify.close()
