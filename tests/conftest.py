"""Shared test helpers: where things are, and running the `cspace` command as a user does."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

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
