"""SARIF and GitHub annotations: findings where a reviewer looks, and nothing injected.

The SARIF log is checked against the SARIF 2.1.0 schema (tests/sarif/, OASIS's own
``sarif-schema-2.1.0.json`` from the sarif-spec repository: specification data, read
from disk). The annotations are checked line by line against GitHub's workflow-command
grammar: a robot file whose names hold newlines, ``::`` and bidi characters must give
exactly one command per finding, each on its own line.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from urllib.parse import unquote

import jsonschema
import pytest
from test_safe_output import NAME, PATH_NAME, assert_safe, robot, run

import cspace
from cspace._findings import CODES, MEANINGS
from cspace._safetext import printable

from conftest import REPO

SARIF_SCHEMA = json.loads((REPO / "tests" / "sarif" / "sarif-schema-2.1.0.json").read_text())
LEVEL = {"error": "error", "warning": "warning", "info": "note"}
COMMAND = re.compile(
    r"::(error|warning|notice) file=([^,:\r\n]*)(?:,line=(\d+))?,title=([^,:\r\n]*)::([^\r\n]*)"
)


def sarif_of(*args: str, cwd: Path) -> tuple[int, dict]:
    code, out, _ = run("inspect", *args, "--format", "sarif", cwd=cwd)
    log = json.loads(assert_safe(out))
    jsonschema.Draft4Validator(SARIF_SCHEMA).validate(log)
    return code, log


def test_every_finding_code_has_a_meaning() -> None:
    assert set(MEANINGS) == set(CODES)


def test_a_sarif_result_per_finding_on_its_file_and_line(tmp_path: Path) -> None:
    report = cspace.inspect(REPO / "tests" / "mistakes" / "quadruped_copy.urdf")
    code, log = sarif_of("tests/mistakes/quadruped_copy.urdf", cwd=REPO)
    (run_,) = log["runs"]
    results = run_["results"]
    assert code == 0 and len(results) == len(report.diagnostics) == 10
    for result, found in zip(results, report.diagnostics, strict=True):
        assert result["ruleId"] == found.code
        assert result["level"] == LEVEL[found.severity.value]
        location = result["locations"][0]["physicalLocation"]
        assert location["artifactLocation"]["uri"] == "tests/mistakes/quadruped_copy.urdf"
        assert location.get("region", {}).get("startLine") == found.line
        rule = run_["tool"]["driver"]["rules"][result["ruleIndex"]]
        assert rule["id"] == found.code and rule["shortDescription"]["text"] == MEANINGS[found.code]


def test_a_file_without_a_report_is_an_error_result_at_its_line(tmp_path: Path) -> None:
    (tmp_path / "ok.urdf").write_text(robot("plain_name"))
    (tmp_path / "bad.urdf").write_text(robot("j", upper="1,5"))
    code, log = sarif_of("ok.urdf", "bad.urdf", cwd=tmp_path)
    results = log["runs"][0]["results"]
    assert code == 2
    bad = [
        r
        for r in results
        if r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == "bad.urdf"
    ]
    assert [r["ruleId"] for r in bad] == ["bad-number"] and bad[0]["level"] == "error"
    assert bad[0]["locations"][0]["physicalLocation"]["region"]["startLine"] == 1
    ok = cspace.inspect(tmp_path / "ok.urdf")
    assert [r["ruleId"] for r in results if r not in bad] == [d.code for d in ok.diagnostics]


def test_hostile_names_stay_text_in_sarif(tmp_path: Path) -> None:
    (tmp_path / PATH_NAME).write_text(robot(NAME))
    _, log = sarif_of(PATH_NAME, cwd=tmp_path)
    results = log["runs"][0]["results"]
    uri = results[0]["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
    assert unquote(uri) == PATH_NAME  # percent-encoded, every character kept
    assert all(
        printable(NAME) in r["message"]["text"] or "plain" in r["message"]["text"] for r in results
    )


def test_annotations_one_command_per_finding_and_nothing_injected(tmp_path: Path) -> None:
    (tmp_path / PATH_NAME).write_text(robot(NAME + "\n::error::injected%0A::w,a:", upper="-2"))
    (tmp_path / "bad,:file.urdf").write_text("<robot")
    code, out, _ = run("inspect", PATH_NAME, "bad,:file.urdf", "--format", "github", cwd=tmp_path)
    lines = assert_safe(out).splitlines()
    assert code == 2
    matched = [COMMAND.fullmatch(line) for line in lines]
    assert all(matched), [line for line, m in zip(lines, matched, strict=True) if not m]
    report = cspace.inspect(tmp_path / PATH_NAME)
    assert len(lines) == 1 + len(report.diagnostics) + 1  # C-space notice, findings, bad file
    kinds = [m.group(1) for m in matched if m]
    assert kinds[0] == "notice" and kinds[-1] == "error"
    last = matched[-1]
    assert last is not None and last.group(2) == "bad%2C%3Afile.urdf"
    assert last.group(4) == "cspace xml-syntax"
    text = out.decode()
    assert "injected%250A" in text and "\n::error::injected" not in text
    assert sum("::error::injected" in line for line in lines) == 1  # within one message


def test_github_annotation_lines_are_the_findings_lines() -> None:
    report = cspace.inspect(REPO / "tests" / "mistakes" / "quadruped_copy.urdf")
    path = "tests/mistakes/quadruped_copy.urdf"
    code, out, _ = run("inspect", path, "--format", "github", cwd=REPO)
    commands = [COMMAND.fullmatch(line) for line in out.decode().splitlines()]
    assert code == 0 and all(commands)
    found = [(m.group(1), m.group(3)) for m in commands[1:] if m]
    kind = {"error": "error", "warning": "warning", "info": "notice"}
    assert found == [
        (kind[d.severity.value], None if d.line is None else str(d.line))
        for d in report.diagnostics
    ]


@pytest.mark.parametrize("fmt", ["sarif", "github"])
def test_the_formats_come_from_one_table(fmt: str) -> None:
    from cspace._render.formats import FORMATS

    assert fmt in FORMATS
    assert FORMATS[fmt].module in ("cspace._render.sarif", "cspace._render.annotations")
    code, out, _ = run("inspect", "--help", cwd=REPO)
    assert code == 0 and fmt in out.decode()


@pytest.mark.parametrize("fmt", ["sarif", "github"])
def test_one_broken_file_still_gives_its_format(tmp_path: Path, fmt: str) -> None:
    """A lone file without a report is a result (an annotation), not an empty output."""
    (tmp_path / "bad.urdf").write_text(robot("j", upper="1,5"))
    code, out, _ = run("inspect", "bad.urdf", "--format", fmt, cwd=tmp_path)
    assert code == 2
    if fmt == "sarif":
        log = json.loads(out)
        jsonschema.Draft4Validator(SARIF_SCHEMA).validate(log)
        assert [r["ruleId"] for r in log["runs"][0]["results"]] == ["bad-number"]
    else:
        assert out.decode().startswith("::error file=bad.urdf,line=1,title=cspace bad-number::")


def test_absolute_paths_are_file_uris(tmp_path: Path) -> None:
    (tmp_path / "a b#%.urdf").write_text(robot("j", upper="-2"))
    _, log = sarif_of(str(tmp_path / "a b#%.urdf"), cwd=tmp_path)
    uri = log["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"][
        "uri"
    ]
    assert uri.startswith("file:///") and unquote(uri[len("file://") :]) == str(
        tmp_path / "a b#%.urdf"
    )
