"""What a reviewer needs from one run: realistic mistakes found, named, and readable.

tests/mistakes/ holds copies of robots with the mistakes people make (limits typed in
degrees, a forgotten lower bound, pybullet's lower > upper, an unprocessed substitution,
a legged robot bolted to the world, XML version 0.0); each file's findings are pinned
exactly, in order, as the JSON report gives them.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

import cspace

from conftest import REPO, run_cli

MISTAKES = REPO / "tests" / "mistakes"

EXPECTED = {
    "panda_copy.urdf": [
        ("warning", "limits-in-degrees", "joint1"),
        ("warning", "limit-bound-missing", "joint2"),
        ("error", "limits-empty", "joint3"),
        ("warning", "continuous-has-limits", "joint4"),
        ("warning", "axis-normalized", "joint5"),
        ("warning", "limits-in-degrees", "joint6"),
    ],
    "quadruped_copy.urdf": [
        *[
            ("info", "multi-turn", f"{leg}_{part}")
            for leg in ("fl", "fr", "hl", "hr")
            for part in ("hip_joint", "knee")
        ],
        ("info", "root-joint-suggested", None),
        ("info", "xml-version", None),
    ],
}


def test_every_mistake_file_is_pinned() -> None:
    assert {p.name for p in MISTAKES.glob("*.urdf")} == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_every_mistake_is_found_in_one_run(name: str) -> None:
    run = run_cli("inspect", str(MISTAKES / name), "--format", "json")
    found = [(d["severity"], d["code"], d["joint"]) for d in json.loads(run.stdout)["diagnostics"]]
    assert found == EXPECTED[name]
    errors = any(severity == "error" for severity, _, _ in EXPECTED[name])
    assert run.code == (1 if errors else 0)


def test_degree_limits_fail_strict_and_can_be_silenced(tmp_path: Path) -> None:
    path = tmp_path / "arm.urdf"
    text = (MISTAKES / "panda_copy.urdf").read_text()
    for joint in ("joint2", "joint3", "joint4", "joint5"):  # keep only the degrees mistakes
        start = text.index(f'<joint name="{joint}"')
        end = text.index("</joint>", start) + len("</joint>")
        text = text[:start] + text[end:]
    text = text.replace('<link name="link2"/>', "").replace('<link name="link3"/>', "")
    text = text.replace('<link name="link4"/><link name="link5"/>', "")
    text = text.replace('<parent link="link5"/><child link="link6"/>',
                        '<parent link="link1"/><child link="link6"/>')  # fmt: skip
    path.write_text(text)
    assert run_cli("inspect", str(path)).code == 0
    strict = run_cli("inspect", str(path), "--strict")
    assert strict.code == 1 and "look like degrees (in rad: [-2.897, 2.897] rad)" in strict.stdout
    silenced = run_cli("inspect", str(path), "--strict", "--ignore", "limits-in-degrees")
    assert silenced.code == 0


@pytest.mark.parametrize(
    ("lower", "upper", "degrees"),
    [
        (-166, 166, True),  # Panda's joint 1, in degrees
        (-90, 90, True),
        (-2.9, 2.9, False),
        (-10, 10, False),  # Solo's +-10 rad: a multi-turn allowance, not degrees
        (-12.566, 12.566, False),  # 4 pi: two turns each way
        (0, 45, True),
        (-100, 100, True),
        (-1000, 1000, False),  # beyond two turns of degrees: not a degree value
    ],
)
def test_what_looks_like_degrees(tmp_path: Path, lower: float, upper: float, degrees: bool) -> None:
    path = tmp_path / "j.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute">'
        '<parent link="a"/><child link="b"/><axis xyz="0 0 1"/>'
        f'<limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/></joint></robot>'
    )
    codes = {d.code for d in cspace.inspect(path).diagnostics}
    assert ("limits-in-degrees" in codes) == degrees


def test_a_substitution_left_in_a_urdf_is_an_error_that_says_so(tmp_path: Path) -> None:
    path = tmp_path / "husky.urdf"  # husky.urdf keeps $(optenv ...) in an origin
    path.write_text(
        '<robot name="husky"><link name="a"/><link name="b"/><joint name="j" type="fixed">'
        '<parent link="a"/><child link="b"/><origin xyz="$(optenv HUSKY_X 0) 0 0"/></joint>'
        "</robot>"
    )
    run = run_cli("inspect", str(path))
    assert run.code == 2
    assert "attribute 'xyz' of <origin> still holds the substitution '$(optenv HUSKY_X 0)'" in (
        run.stderr
    )
    assert "meant to be processed by xacro (or roslaunch) first" in run.stderr


def test_a_misspelt_joint_type_gets_a_suggestion(tmp_path: Path) -> None:
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolut">'
        '<parent link="a"/><child link="b"/></joint></robot>'
    )
    run = run_cli("inspect", str(path))
    assert run.code == 2 and "did you mean 'revolute'?" in run.stderr


def test_a_markdown_file_is_not_xml(tmp_path: Path) -> None:
    path = tmp_path / "README.md"
    path.write_text("# A robot\n\nSee robot.urdf.\n")
    run = run_cli("inspect", str(path))
    assert run.code == 2 and "not XML" in run.stderr and "entity" not in run.stderr


def test_repeated_findings_are_one_line_in_text_and_markdown() -> None:
    text = run_cli("inspect", str(MISTAKES / "quadruped_copy.urdf")).stdout
    lines = [line for line in text.splitlines() if "multi-turn" in line]
    assert len(lines) == 1 and "(and 7 more joints like it: fl_knee, fr_hip_joint" in lines[0]
    markdown = run_cli("inspect", str(MISTAKES / "quadruped_copy.urdf"), "--format", "markdown")
    assert sum("multi-turn" in line for line in markdown.stdout.splitlines()) == 1
    report = json.loads(run_cli("inspect", str(MISTAKES / "quadruped_copy.urdf"), "--format",
                                "json").stdout)  # fmt: skip
    assert sum(d["code"] == "multi-turn" for d in report["diagnostics"]) == 8  # JSON: all


def test_erd_names_are_suggested_and_only_those_installed_listed() -> None:
    run = run_cli("inspect", "erd:pand")
    assert run.code == 2 and "did you mean 'panda'?" in run.stderr
    assert run.stderr.strip().endswith("[unknown-erd-robot]")


def test_debug_keeps_the_exit_code() -> None:
    run = run_cli("--debug", "inspect", "erd:pand")
    assert run.code == 2 and "Traceback" in run.stderr


@pytest.mark.parametrize("columns", [80, 200])
def test_text_report_fits_the_terminal(columns: int) -> None:
    """Golden text output of talos (63 joints, 27 fixed) at 80 and 200 columns."""
    golden = REPO / "tests" / "golden" / f"talos.hide-fixed.{columns}.txt"
    run = run_cli("inspect", "erd:talos", "--hide-fixed", "--width", str(columns))
    assert run.code == 0
    assert max(len(line) for line in run.stdout.splitlines()[:50]) <= columns
    body = run.stdout.split("\n", 2)[2]  # without the source line (its sha256 and path)
    if os.environ.get("CSPACE_UPDATE_GOLDEN") == "1":
        golden.write_text(body)
    assert body == golden.read_text()
    assert "(27 fixed joints not shown)" in body


def test_columns_is_honoured_in_a_pipe_as_a_ci_log_sets_it() -> None:
    # a CI log is no terminal, and talos's table ran 63 lines past 80 columns there
    piped = run_cli("inspect", "erd:talos", env={"COLUMNS": "80"})
    assert piped.code == 0 and max(len(line) for line in piped.stdout.splitlines()) <= 80
    same = run_cli("inspect", "erd:talos", "--width", "80")
    assert piped.stdout == same.stdout
    for junk in ("abc", "0", "-5", "10" * 10, "８０"):  # ignored: no fitting in a pipe
        run = run_cli("inspect", "erd:talos", env={"COLUMNS": junk})
        assert run.code == 0 and max(len(line) for line in run.stdout.splitlines()) > 80


def test_every_structural_problem_in_one_run(tmp_path: Path) -> None:
    """A misspelt link, a missing <limit> and a misspelt type: three lines, file order."""
    path = tmp_path / "arm.urdf"
    path.write_text(
        '<?xml version="1.0"?>\n<robot name="r">\n'
        '  <link name="base"/><link name="upper_arm"/><link name="forearm"/>\n'
        '  <joint name="shoulder" type="revolute"><parent link="base"/>'
        '<child link="uper_arm"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
        "</joint>\n"
        '  <joint name="elbow" type="revolute"><parent link="upper_arm"/>'
        '<child link="forearm"/></joint>\n'
        '  <joint name="wrist" type="revolut"><parent link="forearm"/><child link="hand"/>'
        "</joint>\n</robot>\n"
    )
    run = run_cli("inspect", str(path))
    assert run.code == 2
    lines = run.stderr.splitlines()
    assert [line.rsplit("[", 1)[1] for line in lines] == [
        "missing-link]",
        "missing-limit]",
        "unknown-joint-type]",
    ]
    assert [line.split(f"{path}:")[1].split(":")[0] for line in lines] == ["4", "5", "6"]
    assert "did you mean 'upper_arm'?" in lines[0] and "did you mean 'revolute'?" in lines[2]
    with pytest.raises(cspace.errors.RobotFileErrors) as caught:
        cspace.inspect(path)
    assert [e.code for e in caught.value.errors] == [
        "missing-link",
        "missing-limit",
        "unknown-joint-type",
    ]
    assert caught.value.code == "missing-link" and caught.value.line == 4


def test_the_multi_file_summary_fits_80_columns() -> None:
    robots = sorted(str(p.relative_to(REPO)) for p in (REPO / "robots").glob("*.urdf"))
    run = run_cli("inspect", *robots, "--width", "80")
    table = run.stdout.split("\n\n")[0].splitlines()
    assert len(table) == 2 + len(robots)
    assert max(len(line) for line in table) <= 80
    assert any(line.startswith("…") and ".urdf " in line for line in table)  # ends kept


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_each_finding_points_at_the_element_it_is_about(name: str) -> None:
    lines = (MISTAKES / name).read_text().splitlines()
    report = cspace.inspect(MISTAKES / name)
    for d in report.diagnostics:
        if d.joint is None:
            assert d.line is None, d
            continue
        assert d.line is not None, d
        text = lines[d.line - 1]
        if d.code.startswith("axis"):
            assert "<axis" in text, (d.code, text)
        else:  # a limit finding: its <limit> element
            assert "<limit" in text, (d.code, text)


def test_panda_copy_findings_lines() -> None:
    report = cspace.inspect(MISTAKES / "panda_copy.urdf")
    assert [d.line for d in report.diagnostics] == [14, 19, 24, 29, 33, 39]
    text = run_cli("inspect", str(MISTAKES / "panda_copy.urdf")).stdout
    assert "limits-in-degrees (line 14):" in text


def test_every_command_that_reads_a_robot_takes_the_same_options() -> None:
    import argparse

    from cspace._cli.main import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    shared = {"--root-joint", "--package-path", "--arg", "--xacro", "--allow-dir", "--color"}
    readers = [n for n in sub.choices if n not in ("schema", "completion")]
    assert len(readers) == 9  # inspect, diff, check, sample, distance, interpolate, convert,
    # collisions, unwrap
    for name in readers:
        options = {o for a in sub.choices[name]._actions for o in a.option_strings}
        assert shared <= options, (name, shared - options)


def test_every_problem_of_an_sdf_in_one_run(tmp_path: Path) -> None:
    path = tmp_path / "m.sdf"
    path.write_text(
        '<?xml version="1.0"?>\n<sdf version="1.7">\n  <model name="m">\n'
        '    <link name="base"/><link name="arm"/><link name="hand"/>\n'
        '    <joint name="shoulder" type="revolut"><parent>base</parent><child>arm</child>'
        "</joint>\n"
        '    <joint name="wrist" type="revolute"><parent>arm</parent><child>hnd</child>'
        "<axis><xyz>0 0 1</xyz></axis></joint>\n  </model>\n</sdf>\n"
    )
    run = run_cli("inspect", str(path))
    assert run.code == 2
    lines = run.stderr.splitlines()
    assert len(lines) == 2
    assert f"{path}:5: joint 'shoulder' has unknown type 'revolut'" in lines[0]
    assert f"{path}:6: joint 'wrist' names child link 'hnd'" in lines[1]


def test_sdf_findings_point_at_the_limit_and_axis(tmp_path: Path) -> None:
    path = tmp_path / "m.sdf"
    path.write_text(
        '<?xml version="1.0"?>\n<sdf version="1.7">\n  <model name="m">\n'
        '    <link name="base"/><link name="arm"/>\n'
        '    <joint name="shoulder" type="revolute">\n'
        "      <parent>base</parent><child>arm</child>\n"
        "      <axis>\n"
        "        <xyz>0 0 2</xyz>\n"
        "        <limit><lower>-166</lower><upper>166</upper></limit>\n"
        "      </axis>\n    </joint>\n  </model>\n</sdf>\n"
    )
    found = {d.code: d.line for d in cspace.inspect(path).diagnostics}
    # nothing holds the base: it floats, and the finding points at its <link>
    assert found == {"axis-normalized": 7, "limits-in-degrees": 9, "sdf-link-floats": 4}
