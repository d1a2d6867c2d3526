"""Every file a name list holds is inspected, whatever its name (issue 37).

A list of names that a tool makes (``git ls-files``, pre-commit, a CI input) goes after
``--``: each name is then that file, never an option, a pattern, ``-`` or ``erd:NAME``.
Before ``--`` a name with a wildcard is a pattern that names the file of its very name
too; an option, ``-`` or ``erd:NAME`` that is also a file is refused in one line; and a
file named twice is inspected once. Run through the installed command, with real git and
xargs where a CI script uses them.
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import ROBOTS, Run, cspace_command, run_cli

BROKEN = '<robot name="b"><link name="a"/><joint name="j"/></robot>'
"""A URDF whose joint has no type: one line, ``missing-attribute``."""
HOSTILE = ("--arg=x:=1.urdf", "--allow-dir=y.urdf", "robots/[x].urdf", "-", "erd:ur5")
"""Broken files named like an option, a pattern, standard input and a bundled robot."""


@pytest.fixture
def checkout(tmp_path: Path) -> Path:
    """A git checkout: a good ``robots/x.urdf`` and a broken file under each hostile name."""
    root = tmp_path / "checkout"
    (root / "robots").mkdir(parents=True)
    shutil.copy(ROBOTS / "arm7.urdf", root / "robots" / "x.urdf")
    for name in HOSTILE:
        (root / name).write_text(BROKEN)
    subprocess.run(["git", "init", "-q"], cwd=root, check=True)
    subprocess.run(["git", "add", "."], cwd=root, check=True)
    return root


def _git_list(root: Path, cspace: str) -> subprocess.CompletedProcess[str]:
    """``git ls-files -z | xargs -0 CSPACE`` in ``root``, as a CI script runs it."""
    command = " ".join(cspace_command()) + " " + cspace
    return subprocess.run(
        ["bash", "-o", "pipefail", "-c", f"git ls-files -z | xargs -0 -r {command}"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_a_name_list_after_the_separator_has_every_file_inspected(checkout: Path) -> None:
    done = _git_list(checkout, "inspect --robots-only --format jsonl --")
    assert done.returncode == 123, done.stderr  # xargs: cspace exited 2
    (report,) = [json.loads(line) for line in done.stdout.splitlines()]
    assert report["source"]["path"] == "robots/x.urdf"  # once, not twice
    errors = done.stderr.splitlines()
    # each broken file, under its own name ("-" spelt ./- and erd:ur5 ./erd:ur5)
    named = sorted(line.split(":1: ")[0] for line in errors)
    assert named == sorted(
        f"cspace: error: {'./' if n in ('-', 'erd:ur5') else ''}{n}" for n in HOSTILE
    ), done.stderr
    assert all(line.endswith("[missing-attribute]") for line in errors)


def test_a_name_list_without_the_separator_fails_in_one_line(checkout: Path) -> None:
    done = _git_list(checkout, "inspect --robots-only")
    assert done.returncode == 123 and done.stdout == ""
    assert done.stderr == (
        "cspace: error: '--allow-dir=y.urdf' is an option, and a file here: put -- before "
        "file names (cspace COMMAND [OPTIONS] -- FILE...)\n"
    )


@pytest.mark.parametrize(
    "command",
    [
        ("inspect", "--strict", "robots/x.urdf"),  # a whole option
        ("inspect", "--allow=y.urdf", "robots/x.urdf"),  # argparse reads it as --allow-dir
        ("diff", "--root-joint=floating", "robots/x.urdf", "robots/x.urdf"),
    ],
)
def test_an_option_that_is_also_a_file_is_refused(checkout: Path, command: tuple[str, ...]) -> None:
    (checkout / command[1]).write_text(BROKEN)
    done = run_cli(*command, cwd=checkout)
    assert done.code == 2 and done.stdout == ""
    assert done.stderr.startswith(f"cspace: error: '{command[1]}' is an option, and a file")
    assert done.stderr.count("\n") == 1


def test_standard_input_or_a_bundled_robot_that_is_also_a_file_is_refused(
    checkout: Path,
) -> None:
    good = (ROBOTS / "arm7.urdf").read_bytes()
    for command in (("inspect", "-"), ("inspect", "erd:ur5"), ("sample", "-"), ("diff", "-")):
        extra = ("robots/x.urdf",) if command[0] == "diff" else ()
        done = run_cli(*command, *extra, cwd=checkout, stdin=good)
        assert done.code == 2, (command, done)
        assert done.stderr.count("\n") == 1
        assert done.stderr.startswith(f"cspace: error: {command[1]}: names a file here as well")
        assert done.stderr.rstrip().endswith("[ambiguous-name]")
    # after --, the file of that name
    done = run_cli("check", "--dimension", "7", "--", "-", cwd=checkout, stdin=good)
    assert done.code == 2 and done.stderr.startswith("cspace: error: ./-:1: joint 'j'")
    (checkout / "-").write_bytes(good)
    assert run_cli("sample", "-n", "1", "--", "-", cwd=checkout, stdin=b"").code == 0
    done = run_cli("diff", "--", "-", "robots/x.urdf", cwd=checkout, stdin=b"")
    assert done.code == 0, done.stderr


def test_a_pattern_names_the_file_of_its_very_name_too(checkout: Path) -> None:
    shutil.copy(ROBOTS / "arm7.urdf", checkout / "robots" / "[x].urdf")
    done = run_cli("inspect", "--format", "jsonl", "robots/[x].urdf", cwd=checkout)
    assert _paths(done) == ["robots/x.urdf", "robots/[x].urdf"]  # its match, and itself
    done = run_cli("inspect", "--format", "jsonl", "--", "robots/[x].urdf", cwd=checkout)
    assert _paths(done) == ["robots/[x].urdf"]  # after --, that file only
    done = run_cli("inspect", "--", "robots/[y].urdf", cwd=checkout)
    assert done.code == 2 and "no file matches" not in done.stderr  # no pattern either
    assert done.stderr.rstrip().endswith("[file-unreadable]")


def test_a_file_named_several_times_after_the_separator_is_inspected_once(
    checkout: Path,
) -> None:
    shutil.copy(ROBOTS / "arm7.urdf", checkout / "robots" / "y.urdf")
    (checkout / "robots" / "[x].urdf").unlink()
    names = ("robots/x.urdf", "./robots/x.urdf", "robots//y.urdf", "robots", "robots/")
    done = run_cli("inspect", "--format", "jsonl", "--", *names, cwd=checkout)
    assert done.code == 0, done.stderr
    assert _paths(done) == ["robots/x.urdf", "robots//y.urdf"]  # each under its first name


def _paths(done: Run) -> list[str]:
    """The source paths of the JSON Lines reports written."""
    return [json.loads(line)["source"]["path"] for line in done.stdout.splitlines()]
