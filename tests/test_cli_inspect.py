"""`cspace inspect`, `cspace schema` and `cspace --version`, run as a user runs them."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest

import cspace
from cspace._cli.output import use_color

from conftest import run_cli


def test_text_report_shows_the_space_at_a_glance() -> None:
    run = run_cli("inspect", "robots/arm7.urdf")
    assert run.code == 0
    assert run.stderr == ""
    lines = run.stdout.splitlines()
    assert lines[0].split() == ["robot", "arm7"]
    assert "C = R^6 × S^1" in run.stdout
    assert "dimension          7" in run.stdout
    assert "nq / nv            8 / 7" in run.stdout
    assert "fundamental group  Z" in run.stdout
    rows = {line.split()[0]: line.split() for line in lines if line.startswith(("wrist", "elbow"))}
    assert rows["wrist_roll"][1:3] == ["continuous", "S^1"]
    assert rows["wrist_roll"][-2:] == ["6..7", "6"]
    assert rows["elbow"][1:3] == ["revolute", "R^1"]
    assert "[-3, 0.1] rad" in run.stdout
    assert "\x1b[" not in run.stdout  # not a terminal: plain text


def test_colour_only_when_asked_or_on_a_terminal() -> None:
    assert "\x1b[1m" in run_cli("inspect", "robots/arm7.urdf", "--color", "always").stdout
    assert "\x1b[" not in run_cli("inspect", "robots/arm7.urdf", "--color", "never").stdout


class _Terminal:
    def isatty(self) -> bool:
        return True


def test_no_color_and_dumb_terminals_are_respected(monkeypatch: pytest.MonkeyPatch) -> None:
    terminal: Any = _Terminal()
    monkeypatch.delenv("NO_COLOR", raising=False)
    monkeypatch.delenv("TERM", raising=False)
    assert use_color("auto", terminal)
    monkeypatch.setenv("NO_COLOR", "1")
    assert not use_color("auto", terminal)
    monkeypatch.delenv("NO_COLOR")
    monkeypatch.setenv("TERM", "dumb")
    assert not use_color("auto", terminal)


def test_json_is_the_library_report() -> None:
    run = run_cli("inspect", "robots/mobile_manipulator.urdf", "--format", "json")
    report = cspace.inspect("robots/mobile_manipulator.urdf")
    assert json.loads(run.stdout) == report.to_dict()
    assert run.stdout == report.to_json() + "\n"


def test_root_joint_option() -> None:
    run = run_cli("inspect", "robots/quadruped_nobase.urdf", "--root-joint", "floating")
    assert run.code == 0
    assert "C = R^11 × RP^3" in run.stdout
    assert "root_joint" in run.stdout
    bad = run_cli("inspect", "robots/quadruped_nobase.urdf", "--root-joint", "spherical")
    assert bad.code == 2
    assert bad.stdout == ""
    assert len(bad.stderr.splitlines()) == 1
    assert "invalid choice: 'spherical'" in bad.stderr


def test_missing_file_is_one_line_and_exit_2() -> None:
    run = run_cli("inspect", "robots/no_such_robot.urdf")
    assert run.code == 2
    assert run.stdout == ""
    assert run.stderr == (
        "cspace: error: robots/no_such_robot.urdf: no such file [file-unreadable]\n"
    )


def test_schema_command_prints_a_valid_json_schema() -> None:
    run = run_cli("schema")
    assert run.code == 0
    schema = json.loads(run.stdout)
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["properties"]["schema_version"] == {"const": 1}


def test_version() -> None:
    run = run_cli("--version")
    assert run.code == 0
    assert run.stdout.strip() == f"cspace {cspace.__version__}"


def test_no_command_is_a_usage_error() -> None:
    run = run_cli()
    assert run.code == 2
    assert "Traceback" not in run.stderr


def test_names_cannot_break_or_forge_lines_of_the_text_report(tmp_path: Path) -> None:
    # Character references put line breaks and C1 controls into names.
    (tmp_path / "evil.urdf").write_text(
        '<robot name="r&#10;diagnostics  none"><link name="a"/><link name="b"/>'
        '<joint name="j&#10;x&#133;z&#8232;w&#155;31m" type="revolute"><parent link="a"/>'
        '<child link="b"/><axis xyz="0 0 1"/>'
        '<limit lower="1" upper="-1" effort="1" velocity="1"/></joint></robot>'
    )
    run = run_cli("inspect", "evil.urdf", cwd=tmp_path)
    assert run.code == 1
    assert all(ch.isprintable() for line in run.stdout.splitlines() for ch in line)
    lines = run.stdout.splitlines()
    assert lines[0] == "robot   r\\ndiagnostics  none"
    assert "diagnostics  none" not in lines
    report = json.loads(run_cli("inspect", "evil.urdf", "--format", "json", cwd=tmp_path).stdout)
    assert report["joints"][0]["name"] == "j\nx\x85z\u2028w\x9b31m"  # JSON keeps the name


@pytest.mark.parametrize("before", [["--help"], ["-h"], ["--he"], ["--debug", "--help"]])
def test_the_main_help_lists_every_command_whatever_command_follows(before: list[str]) -> None:
    # a run of one command builds only its parser; the help of `cspace` lists them all
    from cspace._cli.commands import COMMANDS

    whole = run_cli("--help")
    run = run_cli(*before, "inspect", "robots/arm7.urdf")
    assert (run.code, run.stdout, run.stderr) == (0, whole.stdout, "")
    listed = [line.split()[0] for line in run.stdout.splitlines() if line.startswith("    ")]
    assert [name for name in listed if name in COMMANDS] == list(COMMANDS)


@pytest.mark.parametrize(
    "args",
    [
        ["::error::pwned\n##[group]x"],  # where the command goes
        ["--debug", "\n::warning::y", "robots/arm7.urdf"],
        ["inspect", "::error file=a::b\n##[error]c.urdf"],  # one parser only
        ["--debug", "inspect", "::error file=a::b\n##[error]c.urdf"],  # and a traceback
        ["--help", "::notice::z"],
    ],
)
def test_hostile_names_around_the_command_print_no_workflow_command(args: list[str]) -> None:
    run = run_cli(*args)
    assert run.code in (0, 2), run
    for text in (run.stdout, run.stderr):
        assert "##[" not in text
        assert not any(line.lstrip().startswith("::") for line in text.splitlines()), text
    if run.code == 2 and "--debug" not in args:  # refused in one line
        assert run.stdout == "" and run.stderr.count("\n") == 1, run
