"""Hostile joint_limits.yaml files: refused in one line, fast and small, or escaped.

Each bound of the YAML loader (`cspace._formats.shared.yamlio`: nodes with aliases
counted as what they expand to, nesting, core tags, keys given twice) and of the reader
(`cspace._formats.joint_limits.reader`: size, numbers, names) is met here by a file an
attacker commits beside a robot, through the command line as CI runs it, the CPU time
and memory of the command measured; the file's names, as workflow commands and bidi
overrides, reach no CI log raw in any output.
"""

from __future__ import annotations

import html
import json
import os
from pathlib import Path

import pytest
from test_ci_log import CARRIED, EVIL, assert_no_command, assert_printable

from cspace._formats.joint_limits.reader import MAX_LIMITS_BYTES
from cspace._formats.shared.robot_size import MAX_NAME
from cspace._formats.shared.yamlio import MAX_NUMBER_TEXT, MAX_YAML_DEPTH, MAX_YAML_NODES

from conftest import ROBOTS, SECONDS, assert_bounded_error, measured, run_cli

ROBOT = ROBOTS / "arm7.urdf"

_LAUGHS = 'a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]\n' + "".join(
    f"{chr(98 + i)}: &{chr(98 + i)} [{', '.join([f'*{chr(97 + i)}'] * 9)}]\n" for i in range(9)
)
"""A billion laughs: ten lines, 9^10 strings once its aliases are expanded."""

HOSTILE: dict[str, tuple[str | bytes, str, str]] = {
    # name: (the file, the error code, what the one line says)
    "billion laughs": (_LAUGHS, "yaml-invalid", f"more than {MAX_YAML_NODES:,} YAML nodes"),
    "deep nesting": (
        "joint_limits: " + "[" * 50_000,
        "yaml-invalid",
        f"{MAX_YAML_DEPTH} collections",
    ),
    "deep block nesting": (
        "".join(f"{' ' * i}k{i}:\n" for i in range(200)) + " " * 200 + "v: 1\n",
        "yaml-invalid",
        "collections deep",
    ),
    "alias cycle": ("joint_limits: &a {j: *a}\n", "yaml-invalid", "(a cycle)"),
    "duplicate key": (
        "joint_limits:\n  shoulder_pan: {max_position: 1.0}\n  shoulder_pan: {}\n",
        "yaml-invalid",
        "gives key 'shoulder_pan' twice",
    ),
    "python tag": (
        "joint_limits: !!python/object/apply:os.system ['touch pwned']\n",
        "yaml-invalid",
        "only YAML's core tags",
    ),
    "local tag": ("joint_limits: !include /etc/passwd\n", "yaml-invalid", "the tag '!include'"),
    "nan": (
        "joint_limits:\n  shoulder_pan: {max_position: .nan}\n",
        "limits-file-invalid",
        "not a finite",
    ),
    "inf": (
        "joint_limits:\n  shoulder_pan: {min_position: -.inf}\n",
        "limits-file-invalid",
        "not a finite",
    ),
    "integer of 5,000 digits": (
        "joint_limits:\n  shoulder_pan: {max_position: 1" + "0" * 5000 + "}\n",
        "yaml-invalid",
        f"5,001 characters (at most {MAX_NUMBER_TEXT} are read)",
    ),
    "binary integer beyond a double": (
        "default_velocity_scaling_factor: 0b1" + "0" * 90 + "\njoint_limits: {}\n",
        "yaml-invalid",
        "beyond 64 bits",
    ),
    "sexagesimal integer": (  # YAML 1.1's base 60: 60^20, more than a 64-bit integer
        "joint_limits:\n  shoulder_pan: {max_velocity: 1" + ":59" * 20 + "}\n",
        "yaml-invalid",
        "beyond 64 bits",
    ),
    "core tag on no such value": (
        "joint_limits:\n  shoulder_pan: {has_velocity_limits: !!bool maybe, max_jerk: !!int ''}\n",
        "yaml-invalid",
        "'maybe', which is no YAML bool",
    ),
    "string for a number": (
        'joint_limits:\n  shoulder_pan: {max_position: "1.0"}\n',
        "limits-file-invalid",
        "'1.0', not a number",
    ),
    "bool for a number": (
        "joint_limits:\n  shoulder_pan: {max_velocity: yes}\n",
        "limits-file-invalid",
        "not a number",
    ),
    "string for a flag": (
        "joint_limits:\n  shoulder_pan: {has_velocity_limits: 'true'}\n",
        "limits-file-invalid",
        "not true or false",
    ),
    "a list": ("- joint_limits\n", "limits-file-invalid", "not a YAML mapping"),
    "no joint_limits": ("robot_description: x\n", "limits-file-invalid", "no 'joint_limits'"),
    "joint not a mapping": (
        "joint_limits:\n  shoulder_pan: 3\n",
        "limits-file-invalid",
        "not a mapping",
    ),
    "long name": (
        f"joint_limits:\n  {'j' * (MAX_NAME + 1)}: {{}}\n",
        "limits-file-invalid",
        f"more than {MAX_NAME} characters",
    ),
    "two documents": (
        "joint_limits: {}\n---\njoint_limits: {}\n",
        "yaml-invalid",
        "single document",
    ),
    "not utf-8": (b"joint_limits:\n  \xff\xfe: {}\n", "yaml-invalid", "not UTF-8"),
    "huge": (
        "joint_limits:\n" + "#" * MAX_LIMITS_BYTES + "\n",
        "file-unreadable",
        f"{MAX_LIMITS_BYTES:,}-byte limit",
    ),
}


@pytest.mark.bounded
@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_a_hostile_limits_file_is_refused_in_one_line(tmp_path: Path, name: str) -> None:
    body, code, said = HOSTILE[name]
    limits = tmp_path / "joint_limits.yaml"
    if isinstance(body, bytes):
        limits.write_bytes(body)
    else:
        limits.write_text(body)
    result = measured("inspect", str(ROBOT), "--limits", str(limits), cwd=tmp_path, forked=True)
    line = assert_bounded_error(result, code)
    assert str(limits) in line and said in line, line
    assert not (tmp_path / "pwned").exists()
    github = run_cli(
        "inspect", str(ROBOT), "--limits", str(limits), "--format", "github", cwd=tmp_path
    )
    assert f"::error file={limits}" in github.stdout, github.stdout  # on the YAML, not the URDF


@pytest.mark.bounded
def test_a_link_out_of_the_folder_and_a_fifo_are_not_read(tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.yaml").write_text("joint_limits: {TOKEN-secret: {}}\n")
    tree = tmp_path / "tree"
    tree.mkdir()
    (tree / "joint_limits.yaml").symlink_to(outside / "secret.yaml")
    os.mkfifo(tree / "pipe.yaml")
    for name, code in (("joint_limits.yaml", "outside-tree"), ("pipe.yaml", "file-unreadable")):
        result = measured("inspect", str(ROBOT), "--limits", name, cwd=tree, forked=True)
        line = assert_bounded_error(result, code)
        assert "TOKEN" not in line


def _evil_limits(folder: Path) -> Path:
    """A joint_limits.yaml whose joint names and keys are workflow commands."""
    name = json.dumps(html.unescape(EVIL))  # a YAML double-quoted scalar holds any character
    limits = folder / "joint_limits.yaml"
    limits.write_text(
        f"joint_limits:\n  {name}: {{max_velocity: 1.0, has_velocity_limits: true}}\n"
        f"  shoulder_pan: {{{name}: 1.0, max_position: 0.5}}\n"
    )
    return limits


@pytest.mark.parametrize("fmt", ["text", "markdown", "github", "sarif", "html", "json"])
def test_names_in_a_limits_file_reach_no_ci_log(tmp_path: Path, fmt: str) -> None:
    limits = _evil_limits(tmp_path)
    run = run_cli("inspect", str(ROBOT), "--limits", str(limits), "--format", fmt)
    assert run.code == 0, run.stderr
    for text in (run.stdout, run.stderr):
        assert_printable(text)
        assert_no_command(text, ours=fmt == "github")
    if fmt == "json":
        found = json.loads(run.stdout)["diagnostics"]
        joints = {d["joint"] for d in found if d["code"].startswith("limits-file-")}
        messages = [d["message"] for d in found if d["code"].startswith("limits-file-")]
        assert "shoulder_pan" in joints and len(messages) == 3
        assert all(m.isprintable() for m in messages)  # the line break and bidi escaped
    elif fmt != "sarif":  # SARIF, JSON: a JSON string holds it escaped, mid-line
        assert any(c in run.stdout for c in CARRIED), run.stdout


def test_names_in_a_limits_file_reach_no_diff_or_baseline_log(tmp_path: Path) -> None:
    limits = _evil_limits(tmp_path)
    for fmt in ("text", "markdown", "json"):
        run = run_cli("diff", str(ROBOT), str(ROBOT), "--new-limits", str(limits), "--format", fmt)
        assert run.code == 1, run.stderr
        assert_printable(run.stdout + run.stderr)
        assert_no_command(run.stdout + run.stderr)
    (tmp_path / "ok.urdf").write_bytes(ROBOT.read_bytes())
    base = run_cli("inspect", "ok.urdf", "--format", "jsonl", cwd=tmp_path)
    (tmp_path / "base.jsonl").write_text(base.stdout)
    check = run_cli(
        "check", "--baseline", "base.jsonl", "ok.urdf", "--limits", str(limits),
        "--format", "github", cwd=tmp_path,
    )  # fmt: skip
    assert check.code == 1
    assert_no_command(check.stdout + check.stderr, ours=True)


@pytest.mark.bounded
def test_many_unknown_joints_are_bounded_findings(tmp_path: Path) -> None:
    from cspace._model._limits_file import MAX_LIMIT_FINDINGS

    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n" + "".join(f"  j{i}: {{max_position: 1.0}}\n" for i in range(5_000))
    )
    result = measured(
        "inspect", str(ROBOT), "--limits", str(limits), "--format", "json", cwd=tmp_path,
        forked=True,
    )  # fmt: skip
    assert result.run.code == 0 and result.cpu_seconds < SECONDS, result.cpu_seconds
    found = [
        d for d in json.loads(result.run.stdout)["diagnostics"] if d.get("file") == str(limits)
    ]
    assert len(found) == MAX_LIMIT_FINDINGS
    assert found[-1]["code"] == "findings-truncated" and "4,801 more" in found[-1]["message"]


def test_a_nearer_joint_limits_yaml_hides_no_change_from_the_baseline(tmp_path: Path) -> None:
    """A copy of the accepted joint_limits.yaml added beside the URDF, the one MoveIt reads
    widened: ``--limits auto`` reads the nearer, and the baseline says it reads another."""
    workspace = tmp_path / "ws"
    (workspace / ".git").mkdir(parents=True)
    urdf = workspace / "arm_description" / "urdf"
    urdf.mkdir(parents=True)
    (urdf.parent / "package.xml").write_text("<package><name>arm_description</name></package>")
    (urdf / "arm.urdf").write_bytes(ROBOT.read_bytes())
    config = workspace / "arm_moveit_config" / "config"
    config.mkdir(parents=True)
    accepted = "joint_limits:\n  shoulder_pan: {max_position: 1.5, min_position: -1.5}\n"
    (config / "joint_limits.yaml").write_text(accepted)
    robot = "ws/arm_description/urdf/arm.urdf"
    options = ("--limits", "auto")
    baseline = run_cli("inspect", robot, *options, "--format", "jsonl", cwd=tmp_path)
    read = json.loads(baseline.stdout)["limits_file"]["file"]
    assert read == "ws/arm_description/urdf/../../arm_moveit_config/config/joint_limits.yaml"
    (tmp_path / "base.jsonl").write_text(baseline.stdout)
    check = ("check", "--baseline", "base.jsonl", robot, *options)
    assert run_cli(*check, cwd=tmp_path).code == 0
    (config / "joint_limits.yaml").write_text(accepted.replace("1.5", "3.5"))
    (urdf / "joint_limits.yaml").write_text(accepted)
    shadowed = run_cli(*check, "--format", "github", cwd=tmp_path)
    assert shadowed.code == 1, shadowed.stdout
    assert (
        f"::error file={robot},title=cspace baseline%3A limits::limits from "
        "ws/arm_description/urdf/../../arm_moveit_config/config/joint_limits.yaml in the "
        "baseline, limits from ws/arm_description/urdf/joint_limits.yaml now"
    ) in shadowed.stdout
    # read with no joint_limits.yaml where the baseline read one: a change too
    (urdf / "joint_limits.yaml").unlink()
    (config / "joint_limits.yaml").write_text(accepted)
    plain = run_cli("check", "--baseline", "base.jsonl", robot, cwd=tmp_path)
    assert plain.code == 1 and "differs:" in plain.stdout
    # moved beside a copy of the accepted file: not the same robot's move
    (config / "joint_limits.yaml").write_text(accepted.replace("1.5", "3.5"))
    elsewhere = workspace / "arm_description" / "robots"
    elsewhere.mkdir()
    (urdf / "arm.urdf").rename(elsewhere / "arm.urdf")
    (elsewhere / "joint_limits.yaml").write_text(accepted)
    folder = ("check", "--baseline", "base.jsonl", "ws", *options)
    moved = run_cli(*folder, cwd=tmp_path)
    assert moved.code == 1 and "moved:" not in moved.stdout, moved.stdout
    (elsewhere / "joint_limits.yaml").unlink()  # the one it read: a move
    (config / "joint_limits.yaml").write_text(accepted)
    assert "moved:" in run_cli(*folder, cwd=tmp_path).stdout


@pytest.mark.parametrize("fmt", ["text", "markdown"])
def test_each_widening_of_one_joint_is_said_in_the_human_formats(tmp_path: Path, fmt: str) -> None:
    """Three limits-file-widens of one joint (lower, upper, speed) are three lines, none
    folded behind the first as 'more joints like it'."""
    limits = tmp_path / "joint_limits.yaml"
    limits.write_text(
        "joint_limits:\n  shoulder_pan:\n    max_position: 9.0\n    min_position: -9.0\n"
        "    has_velocity_limits: true\n    max_velocity: 40.0\n"
    )
    run = run_cli("inspect", str(ROBOT), "--limits", str(limits), "--format", fmt)
    said = [line for line in run.stdout.splitlines() if "limits-file-widens" in line]
    assert len(said) == 3, run.stdout
    for key, line in zip(("min_position", "max_position", "max_velocity"), said, strict=True):
        assert key in line and "more joints like it" not in line
