"""Hostile ``<ros2_control>`` elements: bounded, refused in one line, or read as ros2_control does.

Thousands of joints or interfaces, names too long, numbers ros2_control's ``stod``
refuses (NaN, 1e400, a comma) beside those it takes (``+1.5``, white space), elements
where ros2_control does not look (inside a link, in a mimic's place, nested deep), and
every name and number a workflow command with a bidi override: held to `test_ci_log`'s
rule in every format of ``inspect`` and ``diff`` and in ``check --baseline``'s
annotations.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_ci_log import CARRIED, EVIL, run_safely

import cspace

from conftest import run_cli

ARM = """<robot name="r">
  <link name="base"/><link name="l1"/><link name="l2"/>
  <joint name="{j1}" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{inside}</joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
  {control}
</robot>
"""


def _control(joints: str, name: str = "hw", plugin: str = "mock_components/GenericSystem") -> str:
    return (
        f'<ros2_control name="{name}" type="system"><hardware><plugin>{plugin}</plugin>'
        f"</hardware>{joints}</ros2_control>"
    )


def _joint(name: str, low: str = "-1", high: str = "1", interface: str = "position") -> str:
    return (
        f'<joint name="{name}"><command_interface name="{interface}">'
        f'<param name="min">{low}</param><param name="max">{high}</param>'
        "</command_interface></joint>"
    )


def _write(folder: Path, name: str, control: str, j1: str = "j1", inside: str = "") -> Path:
    path = folder / name
    path.write_text(ARM.format(j1=j1, inside=inside, control=control))
    return path


@pytest.mark.parametrize("many", ["joints", "interfaces"])
def test_thousands_are_refused_in_one_line(tmp_path: Path, many: str) -> None:
    if many == "joints":
        control = _control("".join(_joint(f"x{i}") for i in range(5001)))
    else:
        interfaces = '<state_interface name="position"/>' * 20_001
        control = _control(f'<joint name="j1">{interfaces}</joint>')
    path = _write(tmp_path, "many.urdf", control)
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stdout == "", run.stderr
    assert run.stderr.count("\n") == 1 and "[too-many-joints]" in run.stderr, run.stderr
    assert f"<ros2_control> {many}" in run.stderr


def test_five_thousand_unknown_joints_are_bounded(tmp_path: Path) -> None:
    control = _control("".join(_joint(f"x{i}") for i in range(5000)))
    report = cspace.inspect(_write(tmp_path, "five.urdf", control))
    assert len(report.ros2_control[0].joints) == 5000
    assert sum(d.code == "ros2-control-unknown-joint" for d in report.diagnostics) == 5000


def test_a_name_too_long_is_refused_in_one_line(tmp_path: Path) -> None:
    path = _write(tmp_path, "long.urdf", _control(_joint("j1"), name="n" * 300))
    run = run_cli("inspect", str(path))
    assert run.code == 2 and run.stderr.count("\n") == 1 and "[name-too-long]" in run.stderr


@pytest.mark.parametrize(
    ("low", "valid"),
    [
        ("nan", False),
        ("-inf", False),
        ("-1e400", False),
        ("-1e-400", False),  # from_chars: out of range, as 1e400 is, not 0
        ("-2e-324", False),
        ("-4.9e-324", True),  # the least double
        ("-0,5", False),
        ("0x1p-1", False),
        ("-" + "1" * 100, False),
        ("++0.5", False),
        ("+-0.5", True),  # stod skips one leading +, then from_chars reads -0.5
        ("+0.5", True),
        (" \n-0.5\t", True),
        ("-.5e0", True),
    ],
)
def test_numbers_are_read_as_stod_reads_them(tmp_path: Path, low: str, valid: bool) -> None:
    report = cspace.inspect(_write(tmp_path, "n.urdf", _control(_joint("j1", low=low))))
    codes = [d.code for d in report.diagnostics]
    if valid:
        assert codes == ["ros2-control-bounds-differ"], codes
    else:
        assert codes == ["ros2-control-number-invalid"], codes
    kept = report.ros2_control[0].joints[0].command[0].min
    assert kept is not None and len(kept) <= 64


def test_an_empty_param_is_none_and_a_nameless_one_refused(tmp_path: Path) -> None:
    joint = _joint("j1", low="", high="").replace("<param name", "<param/><param name", 1)
    report = cspace.inspect(_write(tmp_path, "empty.urdf", _control(joint)))
    assert [d.code for d in report.diagnostics] == ["ros2-control-invalid"]
    interface = report.ros2_control[0].joints[0].command[0]
    assert (interface.min, interface.max) == (None, None)


def test_an_interface_a_second_component_exports_too_is_refused(tmp_path: Path) -> None:
    """ros2_control's resource manager throws on a second ``j1/position`` command
    interface: the wider bounds of a second component (or entry) never apply."""
    first, wider = _control(_joint("j1")), _control(_joint("j1", "-9", "9"), name="again")
    two = _write(tmp_path, "two.urdf", first + "\n" + wider)
    report = cspace.inspect(two)
    refused = [d for d in report.diagnostics if d.code == "ros2-control-invalid"]
    assert [(d.joint, d.severity.value) for d in refused] == [("j1", "error")]
    assert "'again' gives joint 'j1' a position command interface that 'hw' gives" in (
        refused[0].message
    )
    lines = two.read_text().splitlines()
    assert refused[0].line == next(i for i, t in enumerate(lines, 1) if "again" in t)
    run = run_cli("inspect", str(two), "--format", "github")
    assert run.code == 1 and "::error file=" in run.stdout
    # one component naming the joint twice; another interface of it elsewhere is legal
    report = cspace.inspect(_write(tmp_path, "twice.urdf", _control(_joint("j1") * 2)))
    assert [d.code for d in report.diagnostics].count("ros2-control-invalid") == 1
    velocity = _control(_joint("j1", interface="velocity"), name="speed")
    report = cspace.inspect(_write(tmp_path, "both.urdf", first + velocity))
    assert "ros2-control-invalid" not in [d.code for d in report.diagnostics]


def test_limits_turned_off_leave_the_joint_unbounded_to_ros2_control(tmp_path: Path) -> None:
    joint = _joint("j1", low="-5").replace(
        "</command_interface>", '<limits enable="false"/></command_interface>'
    )
    report = cspace.inspect(_write(tmp_path, "off.urdf", _control(joint)))
    # ros2_control then holds the joint to no position limits, not even the URDF's
    assert [d.code for d in report.diagnostics] == ["ros2-control-bounds-exceed"]
    assert "turns off" in report.diagnostics[0].message
    on_joint = _joint("j1").replace(
        "<command_interface", '<limits enable="false"/><command_interface'
    )
    report = cspace.inspect(_write(tmp_path, "joint_off.urdf", _control(on_joint)))
    assert [d.code for d in report.diagnostics] == ["ros2-control-bounds-exceed"]
    velocity = _joint("j1", interface="velocity").replace(
        "</command_interface>", '<limits enable="false"/></command_interface>'
    )
    report = cspace.inspect(_write(tmp_path, "velocity_off.urdf", _control(velocity)))
    assert report.diagnostics == ()  # its velocity limits off: no position bound at stake
    broken = joint.replace('enable="false"', 'enable="no"')
    report = cspace.inspect(_write(tmp_path, "bad.urdf", _control(broken)))
    codes = [d.code for d in report.diagnostics]  # ros2_control refuses; cspace checks on
    assert codes == ["ros2-control-invalid", "ros2-control-bounds-exceed"]


@pytest.mark.parametrize(
    "inside",
    [
        _control(_joint("j1", low="-9")),  # inside a joint
        "<mimic joint='j2'>" + _control(_joint("j1", low="-9")) + "</mimic>",
    ],
)
def test_elements_where_ros2_control_does_not_look_are_not_read(
    tmp_path: Path, inside: str
) -> None:
    report = cspace.inspect(_write(tmp_path, "in.urdf", "", inside=inside))
    assert report.ros2_control == ()
    assert not any(d.code.startswith("ros2-control") for d in report.diagnostics)


def test_deep_nesting_inside_is_not_walked(tmp_path: Path) -> None:
    deep = "<gpio name='g'>" + "<x>" * 200 + "</x>" * 200 + "</gpio>"
    report = cspace.inspect(_write(tmp_path, "deep.urdf", _control(_joint("j1") + deep)))
    assert report.ros2_control[0].gpios == 1
    assert [j.name for j in report.ros2_control[0].joints] == ["j1"]


def test_unknown_children_and_missing_names(tmp_path: Path) -> None:
    control = (
        '<ros2_control type="system"><hardware/><bogus/><joint><state_interface/></joint>'
        "</ros2_control>"
    )
    report = cspace.inspect(_write(tmp_path, "bad.urdf", control))
    found = [(d.code, d.line) for d in report.diagnostics]
    assert [code for code, _ in found] == ["ros2-control-invalid"] * 5, found
    assert all(line == 7 for _, line in found)


# --- every name a workflow command ---------------------------------------------------


@pytest.fixture(scope="module")
def pr(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A pull request whose ros2_control names and numbers are workflow commands."""
    root = tmp_path_factory.mktemp("ros2_control")
    joints = (
        _joint(f"{EVIL}j1", low="-0.5")
        + _joint(f"{EVIL}gone", interface=f"{EVIL}position")
        + _joint("j2", low=f"{EVIL}")
    )
    old = _control(joints, name=f"{EVIL}hw", plugin=f"{EVIL}plugin")
    _write(root, "old.urdf", old, j1=f"{EVIL}j1")
    new = old.replace('"min">-0.5<', '"min">-0.25<').replace(f'"min">{EVIL}<', f'"min">{EVIL}2<')
    _write(root, "new.urdf", new, j1=f"{EVIL}j1")
    return root


@pytest.mark.parametrize(
    "fmt", ["text", "markdown", "json", "jsonl", "sarif", "github", "html", "svg"]
)
def test_names_in_every_format(pr: Path, fmt: str) -> None:
    code, out, err = run_safely(pr, "inspect", "--format", fmt, "old.urdf", ours=fmt == "github")
    assert code == 1 and (err == "") == (fmt not in ("github", "sarif")), err
    if fmt == "json":
        document = json.loads(out)
        assert (
            document["ros2_control"][0]["name"]
            == EVIL.replace("&#10;", "\n")
            .replace("&#x202e;", "\u202e")
            .replace("&#x85;", "\x85")
            .replace("&#x9b;", "\x9b")
            + "hw"
        )
        assert {"ros2-control-unknown-joint", "ros2-control-bounds-differ"} <= {
            d["code"] for d in document["diagnostics"]
        }
    elif fmt in ("text", "markdown", "html", "github", "sarif"):
        assert CARRIED[1] in out or "%23%23%5B" in out or "##\\\\x5b" in out, out


@pytest.mark.parametrize("fmt", ["text", "json", "markdown", "html"])
def test_a_bound_moved_in_every_diff(pr: Path, fmt: str) -> None:
    code, out, _ = run_safely(pr, "diff", "--format", fmt, "old.urdf", "new.urdf")
    assert code == 1 and "-0.25" in out, out
    if fmt == "json":  # the bound as written, kept exactly
        befores = [c["before"] for c in json.loads(out)["changes"] if c["joint"] == "j2"]
        assert len(befores) == 1 and "::error::y" in befores[0], out
    if fmt != "json":
        assert CARRIED[1] in out, out


def test_check_against_a_baseline_annotates_safely(pr: Path, tmp_path: Path) -> None:
    _, report, _ = run_safely(pr, "inspect", "--format", "jsonl", "old.urdf")
    baseline = tmp_path / "baseline.jsonl"
    baseline.write_text(report.replace('"old.urdf"', '"new.urdf"'))
    code, out, _ = run_safely(
        pr, "check", "--baseline", str(baseline), "--format", "github", "new.urdf", ours=True
    )
    assert code == 1 and "ros2_control bounds" in out, out
