"""The pre-commit hook (``.pre-commit-hooks.yaml``), run for real.

A pre-commit configuration names a git copy of this checkout at its commit, as a user's
names cspace's repository at a tag; ``pre-commit run`` installs the hook's environment
from that copy as a user's ``pre-commit`` would (dependencies from pip's cache; pip
byte-compiles nothing, ``PIP_COMPILE=false``, and Python compiles what the hook imports
when it runs, without ``PYTHONDONTWRITEBYTECODE``, as in a user's shell), once
into the test's own ``PRE_COMMIT_HOME`` (``pre-commit try-repo`` would install it again
for each run), and runs the hook on a scratch repository: robot files that pass, then
broken files named like options and patterns, holding a NUL byte, named ``.URDF`` or
``.world``, or reached through a link, which fail it.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml
from test_action import BROKEN, LOCKED, _repository

from conftest import checkout_copy, environment_folder


@pytest.fixture
def pre_commit_home(tmp_path: Path) -> Iterator[Path]:
    """Where pre-commit clones the hook's repository and installs its environment (in
    memory where there is room: ``conftest.environment_folder``)."""
    with environment_folder(tmp_path) as folder:
        yield folder / "pre-commit-home"


def test_the_pre_commit_hook_runs_from_the_repository(
    tmp_path: Path, pre_commit_home: Path
) -> None:
    hooks = checkout_copy(tmp_path / "cspace")
    for args in (
        ["init", "-q"],
        ["add", "."],
        ["-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "c"],
    ):
        subprocess.run(["git", *args], cwd=hooks, check=True)
    commit = subprocess.run(
        ["git", "rev-parse", "HEAD"], cwd=hooks, capture_output=True, text=True, check=True
    ).stdout.strip()
    config = tmp_path / "pre-commit-config.yaml"
    config.write_text(
        yaml.safe_dump(
            {"repos": [{"repo": str(hooks), "rev": commit, "hooks": [{"id": "cspace"}]}]}
        )
    )
    repo = _repository(tmp_path)
    env = {**os.environ, "PRE_COMMIT_HOME": str(pre_commit_home), "PIP_COMPILE": "false"}
    env.pop("VIRTUAL_ENV", None)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    pre_commit = [str(Path(sys.executable).parent / "pre-commit"), "run", "--config", str(config)]

    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [*pre_commit, *args], cwd=repo, env=env, capture_output=True, text=True, timeout=900
        )

    ok = run("--all-files")
    assert ok.returncode == 0, ok.stdout + ok.stderr
    assert "Passed" in ok.stdout
    # A warning (strict), and broken files named like options and like a pattern beside
    # the file the pattern would match, one holding a NUL byte (binary to pre-commit),
    # names no suffix list holds, and a link (to a hidden file beside it): each inspected
    # under its own name, the pattern's match once.
    (repo / "locked.urdf").write_text(LOCKED)
    (repo / "robots").mkdir()
    shutil.copy(repo / "arm7.urdf", repo / "robots" / "x.urdf")
    hostile = ["--arg=x:=1.urdf", "--allow-dir=y.urdf", "robots/[x].urdf", "ARM.URDF", "w.world"]
    for name in [*hostile, "robots/.arm.dat"]:
        (repo / name).write_text(BROKEN)
    (repo / "robots" / "arm.urdf").symlink_to(".arm.dat")
    (repo / "nul.urdf").write_text(BROKEN.replace("<link", "<!-- \0 --><link"))
    subprocess.run(["git", "add", "."], cwd=repo, check=True)
    failed = run("--all-files")  # the environment installed by the first run
    assert failed.returncode == 1 and "Failed" in failed.stdout, failed.stdout
    for name in [*hostile, "nul.urdf", "robots/arm.urdf", "robots/.arm.dat"]:
        assert f"cspace: error: {name}:1:" in failed.stdout, name
    rows = [line.split() for line in failed.stdout.splitlines()]
    assert [row[-1] for row in rows if row[:1] == ["locked.urdf"]] == ["findings"]
    assert [row[-1] for row in rows if row[:1] == ["robots/x.urdf"]] == ["ok"]
    assert "8 without a report; 0 error and 1 warning findings in all" in failed.stdout
