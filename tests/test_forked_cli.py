"""The suite's forked `cspace` (``forked_cli``) is the command a user runs, to the byte.

Most tests run the command forked from a process that has imported cspace already
(``conftest.run_cli``). Here the same commands run both ways, forked and as the
installed script in a new interpreter, and must give the same exit status, standard
output and standard error: a report, an error, standard input, a usage error (which
names the program from ``sys.argv``), the environment (colour off, a terminal width),
the working folder, and a command that imports what the server did not (MuJoCo's
compile, in its confined child). A command that outlives its timeout is killed and
reported as ``subprocess.run`` reports it.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

import forked_cli
from conftest import REPO, ROBOTS, run_cli

ARM = str(ROBOTS / "arm7.urdf")

CASES = [
    ("inspect", ARM),
    ("inspect", ARM, "--format", "json"),
    ("inspect", "robots/arm7.urdf", "--format", "markdown"),  # relative to the folder
    ("inspect", str(ROBOTS / "mjcf_every_joint.xml"), "--format", "json"),
    ("inspect", "no-such-file.urdf"),
    ("inspect", ARM, "--no-such-option"),
    ("--version",),
    ("sample", ARM, "-n", "3", "--seed", "1", "--format", "csv"),
]


@pytest.mark.parametrize("args", CASES, ids=lambda args: " ".join(args)[-40:])
def test_a_forked_command_is_the_installed_script(args: tuple[str, ...]) -> None:
    forked = run_cli(*args)
    fresh = run_cli(*args, fresh=True)
    assert forked == fresh
    assert forked.stdout or forked.stderr  # something to compare


def test_standard_input_the_environment_and_the_folder_reach_it(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_bytes(Path(ARM).read_bytes())
    given = {"stdin": Path(ARM).read_bytes(), "env": {"COLUMNS": "50"}, "cwd": tmp_path}
    for args in (("inspect", "-"), ("inspect", "robot.urdf")):
        forked = run_cli(*args, **given)  # type: ignore[arg-type]
        assert forked.code == 0 and max(map(len, forked.stdout.splitlines())) <= 50
        assert forked == run_cli(*args, fresh=True, **given)  # type: ignore[arg-type]


def test_a_change_to_the_interpreters_start_up_is_not_forked() -> None:
    assert forked_cli.forkable(dict(forked_cli._server().env))
    assert not forked_cli.forkable({**forked_cli._server().env, "PYTHONIOENCODING": "ascii"})
    assert not forked_cli.forkable({**forked_cli._server().env, "LC_ALL": "C"})


def test_a_command_past_its_timeout_is_killed() -> None:
    with pytest.raises(subprocess.TimeoutExpired):
        forked_cli.run(["inspect", ARM], str(REPO), None, 0.001, {})
    assert run_cli("inspect", ARM).code == 0  # the server serves on
