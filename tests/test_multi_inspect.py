"""``cspace inspect`` on several files: JSON Lines, a summary table, the worst exit code."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

import cspace
from cspace._render.markdown import render_markdown
from cspace._render.text import render_text
from cspace._schema import report_schema_text

from conftest import ROBOTS, run_cli

ARM7 = "robots/arm7.urdf"
MJCF = "robots/mjcf_every_joint.xml"
SDF = "robots/sdf_every_joint.sdf"

JOINT = (
    '<joint name="{name}" type="revolute"><parent link="a"/><child link="b"/>'
    '<axis xyz="0 0 1"/><limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/></joint>'
)


def _urdf(path: Path, lower: str, upper: str) -> str:
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/>'
        + JOINT.format(name="j", lower=lower, upper=upper)
        + "</robot>"
    )
    return str(path)


@pytest.fixture
def empty_interval(tmp_path: Path) -> str:
    """A robot whose joint has lower > upper: an error-level finding."""
    return _urdf(tmp_path / "empty.urdf", "1", "-1")


@pytest.fixture
def locked(tmp_path: Path) -> str:
    """A robot whose joint has lower == upper: a warning-level finding."""
    return _urdf(tmp_path / "locked.urdf", "0.5", "0.5")


def test_summary_table_one_row_per_file() -> None:
    run = run_cli("inspect", ARM7, MJCF, SDF)
    assert (run.code, run.stderr) == (0, "")
    lines = run.stdout.splitlines()
    assert lines[0].split() == [
        "robot",
        "format",
        "C-space",
        "dim",
        "nq/nv",
        "err",
        "warn",
        "status",
    ]
    rows = [line.split("  ") for line in lines[2:5]]
    cells = [[c.strip() for c in row if c.strip()] for row in rows]
    assert cells == [
        [ARM7, "urdf", "R^6 × S^1", "7", "8/7", "0", "0", "ok"],
        [MJCF, "mjcf", "R^10 × S^1 × (RP^3)^2", "17", "20/17", "0", "0", "ok"],
        [SDF, "sdf", "R^5 × T^2 × RP^3", "10", "13/10", "0", "0", "ok"],
    ]
    assert lines[-1] == (
        "3 robot files: 3 ok, 0 failing, 0 without a report; 0 error and 0 warning findings in all"
    )


def test_json_lines_one_valid_report_per_line() -> None:
    run = run_cli("inspect", "--format", "json", ARM7, MJCF, SDF)
    assert run.code == 0
    lines = run.stdout.splitlines()
    assert len(lines) == 3
    schema = json.loads(report_schema_text())
    documents = [json.loads(line) for line in lines]
    for document in documents:
        jsonschema.validate(document, schema)
    assert [d["source"]["path"] for d in documents] == [ARM7, MJCF, SDF]
    assert documents[0] == cspace.inspect(ARM7).to_dict() | {"source": documents[0]["source"]}


def test_keeps_going_past_a_broken_file_and_exits_with_the_worst_code(
    tmp_path: Path, empty_interval: str
) -> None:
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='r'><link name='a'>")
    run = run_cli("inspect", "--format", "json", ARM7, str(broken), empty_interval, SDF)
    assert run.code == 2  # no report for one file: the worst
    paths = [json.loads(line)["source"]["path"] for line in run.stdout.splitlines()]
    assert paths == [ARM7, empty_interval, SDF]
    assert run.stderr.count("cspace: error:") == 2  # the broken file, the empty interval
    assert str(broken) in run.stderr and "[xml-syntax]" in run.stderr
    assert f"cspace: error: {empty_interval}:" in run.stderr and "[limits-empty]" in run.stderr


def test_findings_and_strict_decide_the_code(empty_interval: str, locked: str) -> None:
    """Each finding that fails the run is said on standard error with its file, line and
    code (a CI log shows it: the table has only counts); one that does not fail it is
    not."""
    warned = run_cli("inspect", ARM7, locked)
    assert warned.code == 0 and warned.stderr == ""  # the footer counts the warning
    assert warned.stdout.splitlines()[-1].endswith("; 0 error and 1 warning findings in all")
    strict = run_cli("inspect", "--strict", ARM7, locked, empty_interval)
    assert strict.code == 1
    lines = strict.stderr.splitlines()
    assert [line.split(": ", 2)[:2] for line in lines] == [
        ["cspace", "warning"],
        ["cspace", "error"],
    ], strict.stderr
    assert lines[0].startswith(f"cspace: warning: {locked}:") and lines[0].endswith(
        "[joint-locked]"
    )
    assert lines[1].startswith(f"cspace: error: {empty_interval}:") and lines[1].endswith(
        "[limits-empty]"
    )
    line = int(lines[1].split(f"{empty_interval}:", 1)[1].split(":", 1)[0])
    assert "<limit" in Path(empty_interval).read_text().splitlines()[line - 1]
    run = run_cli("inspect", ARM7, empty_interval)
    assert run.code == 1 and run.stderr.count("cspace: error:") == 1
    assert "2 robot files: 1 ok, 1 failing, 0 without a report; 1 error" in run.stdout


def test_an_error_of_a_run_of_several_is_said_once(tmp_path: Path) -> None:
    broken = tmp_path / "broken.urdf"
    broken.write_text("<robot name='r'><link name='a'>")
    for fmt in ("text", "markdown"):
        run = run_cli("inspect", ARM7, str(broken), "--format", fmt)
        assert run.code == 2 and run.stderr.count(str(broken)) == 1
        said = run.stdout.count(str(broken))
        assert said == (1 if fmt == "text" else 2)  # its row; Markdown's list says why once


def test_quoted_glob_is_expanded_and_gives_json_lines_even_for_one_match() -> None:
    run = run_cli("inspect", "--format", "json", "robots/*.sdf")
    assert run.code == 0
    assert len(run.stdout.splitlines()) == 1
    assert json.loads(run.stdout)["source"]["path"] == SDF
    run = run_cli("inspect", "robots/**/*.urdf.xacro")
    assert run.code == 0 and "robots/xacro_demo/urdf/arm.urdf.xacro" in run.stdout
    run = run_cli("inspect", "robots/*.nothing", ARM7)
    assert run.code == 2 and "no file matches" in run.stderr


def test_standard_input_among_several_files() -> None:
    run = run_cli(
        "inspect",
        "--format",
        "json",
        ARM7,
        "-",
        stdin=(ROBOTS / "sdf_every_joint.sdf").read_bytes(),
    )
    assert run.code == 0
    formats = [json.loads(line)["source"]["format"] for line in run.stdout.splitlines()]
    assert formats == ["urdf", "sdf"]


def test_markdown_summary(tmp_path: Path) -> None:
    run = run_cli("inspect", "--format", "markdown", ARM7, "missing.urdf")
    assert run.code == 2
    assert run.stdout.splitlines()[:4] == [
        "### cspace: robot files",
        "",
        "| robot | format | C-space | dim | nq/nv | err | warn | status |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    assert f"| `{ARM7}` | urdf | `R^6 × S^1` | 7 | 8/7 | 0 | 0 | ok |" in run.stdout
    assert "| `missing.urdf` | - | - | - | - | - | - | no report |" in run.stdout
    assert "- `missing.urdf: no such file`" in run.stdout  # the path once


def test_one_file_keeps_the_single_report_outputs() -> None:
    report = cspace.inspect(ARM7)
    assert run_cli("inspect", ARM7).stdout == render_text(report)
    assert run_cli("inspect", "--format", "json", ARM7).stdout == report.to_json() + "\n"
    markdown = run_cli("inspect", "--format", "markdown", ARM7)
    assert markdown.stdout == render_markdown(report)
    assert markdown.stdout.startswith(f"### cspace: `{ARM7}`\n\n**C = `R^6 × S^1`**")
    assert "| `wrist_roll` | continuous | S^1 | - | 6..7 | 6 |" in markdown.stdout


def test_markdown_escapes_what_comes_from_the_file(tmp_path: Path) -> None:
    path = tmp_path / "pipe.urdf"
    path.write_text(
        '<robot name="r|x"><link name="a"/><link name="b"/>'
        + JOINT.format(name="j|`k", lower="-1", upper="1")
        + "</robot>"
    )
    out = run_cli("inspect", "--format", "markdown", str(path)).stdout
    assert "| ``j\\|`k`` | revolute |" in out  # a longer fence keeps the backtick
    assert "Robot `r|x` (urdf)." in out  # outside a table a pipe needs no escape
