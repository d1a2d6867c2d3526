"""The suite's forked `cspace` (``forked_cli``) is the command a user runs, to the byte.

Most tests run the command forked from a process that has imported cspace already
(``conftest.run_cli``). Here the same commands run both ways, forked and as the
installed script in a new interpreter, and must give the same exit status, standard
output and standard error: a report, an error, standard input, a usage error (which
names the program from ``sys.argv``), the environment (colour off, a terminal width),
the working folder, every command's help (each imports its own module), and a command
that imports what the server did not (MuJoCo's compile, in its confined child). A
command that outlives its timeout is killed and reported as ``subprocess.run`` reports
it. A forked command's CPU time and peak memory are its own, without the start-up. It
leaves as the script does when its standard output cannot be written, and only once
its exit handlers have run (they reap the children it keeps).
"""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

import pytest

from cspace._cli.commands import COMMANDS

import forked_cli
from conftest import (
    HANG_SECONDS,
    PEAK_MIB,
    REPO,
    ROBOTS,
    Run,
    command_env,
    cspace_command,
    measured,
    run_cli,
)

ARM = str(ROBOTS / "arm7.urdf")
MJCF = str(ROBOTS / "mjcf_every_joint.xml")

CASES = [
    ("inspect", ARM),
    ("inspect", ARM, "--format", "json"),
    ("inspect", "robots/arm7.urdf", "--format", "markdown"),  # relative to the folder
    ("inspect", str(ROBOTS / "mjcf_every_joint.xml"), "--format", "json"),
    ("inspect", "no-such-file.urdf"),
    ("inspect", ARM, "--no-such-option"),
    ("--version",),
    ("sample", ARM, "-n", "3", "--seed", "1", "--format", "csv"),
    *((name, "--help") for name in COMMANDS),
]


def _forked(*args: str, cwd: Path = REPO, stdin: bytes | None = None, **env: str) -> Run:
    full_env = command_env(env)
    assert forked_cli.forkable(full_env)  # else run_cli would not fork it
    code, out, err = forked_cli.run(list(args), str(cwd), stdin, 60, full_env)
    return Run(code, out.decode(), err.decode())


@pytest.mark.parametrize("args", CASES, ids=lambda args: " ".join(args)[-40:])
def test_a_forked_command_is_the_installed_script(args: tuple[str, ...]) -> None:
    forked = _forked(*args)
    assert forked == run_cli(*args, fresh=True)
    assert forked.stdout or forked.stderr  # something to compare


def test_standard_input_the_environment_and_the_folder_reach_it(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_bytes(Path(ARM).read_bytes())
    robot = Path(ARM).read_bytes()
    for args in (("inspect", "-"), ("inspect", "robot.urdf")):
        forked = _forked(*args, cwd=tmp_path, stdin=robot, COLUMNS="50")
        assert forked.code == 0 and max(map(len, forked.stdout.splitlines())) <= 50
        fresh = run_cli(*args, cwd=tmp_path, stdin=robot, env={"COLUMNS": "50"}, fresh=True)
        assert forked == fresh


def test_what_importing_cspace_sets_does_not_stop_forking() -> None:
    import cspace._cli.main  # noqa: F401  (it sets OPENBLAS_NUM_THREADS in this process too)

    assert forked_cli.forkable(command_env())
    for changed in ({"PYTHONIOENCODING": "ascii"}, {"LC_ALL": "C"}, {"OPENBLAS_NUM_THREADS": "2"}):
        assert not forked_cli.forkable({**os.environ, **changed}), changed


@pytest.mark.bounded
def test_a_command_past_its_timeout_is_killed() -> None:
    endless = ["sample", ARM, "-n", "100000000", "--format", "csv"]  # minutes of rows
    with pytest.raises(subprocess.TimeoutExpired) as raised:
        forked_cli.run(endless, str(REPO), None, 0.5, {**os.environ})
    assert isinstance(raised.value, forked_cli.Killed)
    deadline = time.monotonic() + 60  # a guard against a hang, not a bound
    with pytest.raises(ProcessLookupError):  # killed and reaped: no such process
        while time.monotonic() < deadline:
            os.kill(raised.value.pid, 0)
            time.sleep(0.01)
    assert run_cli("inspect", ARM).code == 0  # the server serves on


@pytest.mark.bounded
def test_a_forked_command_is_measured_without_its_start_up() -> None:
    fresh = measured("inspect", ARM, cwd=REPO)
    forked = measured("inspect", ARM, cwd=REPO, forked=True)
    assert forked.run == fresh.run and forked.run.code == 0
    # the command's own figures: its work, without importing cspace and Pinocchio
    assert 0 < forked.cpu_seconds < fresh.cpu_seconds, (forked, fresh)
    assert 0 < forked.peak_mib < PEAK_MIB, forked  # in MiB, as the fresh run's


@pytest.mark.bounded
@pytest.mark.parametrize("args", [("--version",), ("inspect", ARM, "--format", "json")])
def test_an_output_that_cannot_be_written_ends_it_as_it_ends_the_script(
    args: tuple[str, ...],
) -> None:
    # standard output on a full disk: the same status and words, forked or not
    with open("/dev/full", "wb") as full:
        forked = forked_cli.run(
            list(args), str(REPO), None, HANG_SECONDS, command_env(), full.fileno()
        )
        script = subprocess.run(
            [*cspace_command(), *args],
            cwd=REPO,
            env=command_env(),
            stdout=full,
            stderr=subprocess.PIPE,
            timeout=HANG_SECONDS,
        )
    assert (forked[0], forked[2]) == (script.returncode, script.stderr)


@pytest.mark.bounded
def test_it_leaves_once_its_exit_handlers_have_reaped_its_children() -> None:
    # MuJoCo's compile runs in a kept child that an exit handler stops and reaps: the
    # child's CPU (its start-up, about 0.4 s) counts in the command's only if the command
    # left after that handler, as the script does
    mjcf = forked_cli.measure(["inspect", MJCF], str(REPO), None, HANG_SECONDS, command_env())
    urdf = forked_cli.measure(["inspect", ARM], str(REPO), None, HANG_SECONDS, command_env())
    assert mjcf.code == urdf.code == 0
    assert mjcf.cpu_seconds > 4 * urdf.cpu_seconds, (mjcf.cpu_seconds, urdf.cpu_seconds)
