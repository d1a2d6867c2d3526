"""Files that can still be analysed: the report carries findings with stable codes.

Each file in tests/findings/ says in an XML comment what it has. The table gives the
exact findings (code and severity) the report must carry, the exit code of
``cspace inspect``, and the exit code under ``--strict``. Some of these files are
refused by Pinocchio's own URDF parser (NaN, infinities, ``1e400``, a trailing space):
the report must still be produced, with the file's own values in its findings, and the
q/v layout Pinocchio gives the same file with ordinary numbers in their place.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

import jsonschema
import pinocchio as pin
import pytest

import cspace
from cspace._cli.main import main
from cspace._findings import CODES
from cspace._schema import report_schema

from conftest import REPO, Run, run_cli_many

FINDINGS = REPO / "tests" / "findings"
ERROR, WARNING, INFO = "error", "warning", "info"


@dataclass(frozen=True)
class Case:
    """What one file's report must carry."""

    file: str
    findings: tuple[tuple[str, str], ...]
    code: int
    strict_code: int
    manifold: str
    message: str = ""
    repaired: tuple[tuple[str, str], ...] = ()  # (as written, an ordinary number) pairs


CASES = (
    Case(
        "limits_empty.urdf",
        (("limits-empty", ERROR),),
        1,
        1,
        "R^2",
        "lower limit 2 > upper limit -2",
    ),
    Case(
        "limits_nan.urdf",
        (("limits-not-finite", ERROR),),
        1,
        1,
        "R^1 × S^1",
        "joint 'elbow' has lower limit nan: not a finite number; the joint is reported as if "
        "it had no limits",
        (('lower="nan"', 'lower="-2"'),),
    ),
    Case(
        "limits_infinite.urdf",
        (("limits-not-finite", ERROR),),
        1,
        1,
        "R^1 × S^1",
        "lower limit -inf, upper limit inf",
        (('lower="-inf" upper="inf"', 'lower="-2" upper="2"'),),
    ),
    Case(
        "limits_overflow.urdf",
        (("limits-not-finite", ERROR),),
        1,
        1,
        "R^1 × S^1",
        "upper limit inf",
        (('upper="1e400"', 'upper="2"'),),
    ),
    Case(
        "mimic_multiplier_nan.urdf",
        (("limits-not-finite", ERROR),),
        1,
        1,
        "R^1",
        "mimic multiplier nan",
        (('multiplier="NaN"', 'multiplier="1"'),),
    ),
    Case(
        "axis_zero.urdf",
        (("axis-invalid", ERROR),),
        1,
        1,
        "R^2",
        "has axis (0 0 0), which is zero",
    ),
    Case(
        "axis_not_finite.urdf",
        (("axis-invalid", ERROR),),
        1,
        1,
        "R^2",
        "has axis (nan 1 0), which is not finite",
        (('xyz="nan 1 0"', 'xyz="0 0 0"'),),
    ),
    Case(
        "effort_infinite.urdf",
        (("number-invalid", ERROR),),
        1,
        1,
        "R^2",
        '<limit effort="inf"> is not a finite number',
        (('effort="inf"', 'effort="10"'),),
    ),
    Case(
        "velocity_negative.urdf",
        (("number-invalid", ERROR),),
        1,
        1,
        "R^2",
        '<limit velocity="-1"> is negative',
        (('velocity="-1"', 'velocity="1"'),),
    ),
    Case(
        "fixed_joint_limit_nan.urdf",
        (("number-invalid", ERROR),),
        1,
        1,
        "R^1",
        "joint 'tool_mount': <limit lower=\"nan\"> is not a finite number",
        (('lower="nan"', 'lower="0"'),),
    ),
    Case(
        "origin_nan.urdf",
        (("number-invalid", ERROR),),
        1,
        1,
        "R^2",
        '<origin xyz="0 0 nan"> is not finite; the C-space does not depend on it',
        (('xyz="0 0 nan"', 'xyz="0 0 0"'),),
    ),
    Case(
        "joint_locked.urdf",
        (("joint-locked", WARNING),),
        0,
        1,
        "R^1",
        "lower == upper == 0.5: it is locked and contributes dimension 0",
    ),
    Case(
        "limits_unset.urdf",
        (("limits-unset", WARNING),),
        0,
        1,
        "point",
        "which files write for 'limits not given': it is read as locked (dimension 0)",
    ),
    Case(
        "limits_sentinel.urdf",
        (("limits-sentinel", WARNING),),
        0,
        1,
        "R^1",
        "a magnitude of 10000 or more usually stands for 'no limit'. It is read as 318,310 "
        "turns, an interval (R^1); if it turns freely, say so: a continuous joint (URDF)",
    ),
    Case(
        "range_looks_like_radians.xml",
        (("range-looks-like-radians", WARNING),),
        0,
        1,
        "R^2",
        "hinge 'knee' has range -2.79, -0.03 in degrees",
    ),
    Case(
        "keyframe_outside.xml",
        (
            ("pose-not-unit", WARNING),
            ("pose-out-of-limits", ERROR),
            ("pose-ctrl-out-of-range", WARNING),
        ),
        1,
        1,
        "R^4 × RP^3",
        "keyframe 'home': joint 'knee' is 2, outside [-1, 1] rad",
    ),
    Case(
        "continuous_with_limits.urdf",
        (("continuous-has-limits", WARNING),),
        0,
        1,
        "R^1 × S^1",
        "gives limits [-1, 1], which URDF ignores",
    ),
    Case(
        "mimic_limits_contradict.urdf",
        (("mimic-limits-contradict", WARNING),),
        0,
        1,
        "R^1",
        "follows 'shoulder' into [-3, 3], outside its own limits [-1, 1]",
    ),
    Case(
        "mimic_on_planar.urdf",
        (("mimic-ignored", WARNING),),
        0,
        1,
        "R^3 × S^1",
        "planar joint 'base_xy' has a <mimic> element",
    ),
    Case(
        "mimic_of_fixed.urdf",
        (("mimic-ignored", WARNING),),
        0,
        1,
        "R^1",
        "joint 'finger' mimics 'mount', a fixed joint",
    ),
    Case(
        "mimic_of_planar.urdf",
        (("mimic-ignored", WARNING),),
        0,
        1,
        "R^3 × S^1",
        "joint 'turret' mimics 'base_xy', a planar joint",
    ),
    Case(
        "revolute_plus_minus_pi.urdf",
        (("revolute-ambiguous-range", WARNING),),
        0,
        1,
        "R^2",
        "exactly one turn",
    ),
    Case(
        "axis_not_unit.urdf",
        (("axis-normalized", WARNING),),
        0,
        1,
        "R^2",
        "of length 2; it is used normalised",
    ),
    Case(
        "multi_turn.urdf",
        (("multi-turn", INFO),),
        0,
        0,
        "R^2",
        "spans 3.00 turns",
    ),
    Case(
        "axis_default.urdf",
        (("axis-default", INFO),),
        0,
        0,
        "R^2",
        "(1, 0, 0) assumed",
    ),
    Case(
        "broken_inertia.urdf",
        (("parser-message", INFO), ("parser-message", INFO)),
        0,
        0,
        "R^1",
        "Could not parse inertial element for Link [base]",
    ),
    Case(
        "odd_but_valid_numbers.urdf",
        (),
        0,
        0,
        "R^2",
        "",
        (('lower="-2 "', 'lower="-2"'), ("0&#9;0 0.3", "0 0 0.3"), ('xyz="0 1 0 "', 'xyz="0 1 0"')),
    ),
)
VALIDATOR = jsonschema.Draft202012Validator(report_schema())


@pytest.fixture(scope="session")
def json_runs() -> dict[str, Run]:
    runs = run_cli_many([("inspect", str(FINDINGS / c.file), "--format", "json") for c in CASES])
    return {c.file: run for c, run in zip(CASES, runs, strict=True)}


def test_every_file_has_a_case_and_every_finding_code_is_known() -> None:
    assert sorted(p.name for p in FINDINGS.iterdir()) == sorted(c.file for c in CASES)
    for case in CASES:
        for code, severity in case.findings:
            assert CODES[code].value == severity
        assert b"<!-- " in (FINDINGS / case.file).read_bytes()[:300]


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.file)
def test_report_carries_exactly_the_findings(case: Case, json_runs: dict[str, Run]) -> None:
    run = json_runs[case.file]
    assert run.code == case.code, run.stderr
    assert run.stderr == ""
    document = json.loads(run.stdout)
    VALIDATOR.validate(document)
    found = tuple((d["code"], d["severity"]) for d in document["diagnostics"])
    assert found == case.findings
    assert document["manifold"]["notation"] == case.manifold
    if case.message:
        assert any(case.message in d["message"] for d in document["diagnostics"])
    names = {joint["name"] for joint in document["joints"]}
    for d in document["diagnostics"]:
        assert d["joint"] is None or d["joint"] in names  # a finding names a real joint


def _cli(args: list[str], capsys: pytest.CaptureFixture[str]) -> int:
    code = main(args)
    capsys.readouterr()
    return code


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.file)
def test_strict_makes_warnings_fail(case: Case, capsys: pytest.CaptureFixture[str]) -> None:
    assert _cli(["inspect", str(FINDINGS / case.file), "--strict"], capsys) == case.strict_code


@pytest.mark.parametrize("case", [c for c in CASES if c.findings], ids=lambda c: c.file)
def test_ignore_silences_a_finding_by_its_code(
    case: Case, capsys: pytest.CaptureFixture[str]
) -> None:
    codes = sorted({code for code, _ in case.findings})
    args = ["inspect", str(FINDINGS / case.file), "--format", "json", "--strict"]
    for code in codes:
        args += ["--ignore", code]
    assert main(args) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["diagnostics"] == []


def test_ignoring_one_code_keeps_the_others(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    text = (FINDINGS / "joint_locked.urdf").read_text().replace('xyz="0 1 0"', 'xyz="0 3 0"')
    path = tmp_path / "two_findings.urdf"
    path.write_text(text)
    assert {d.code for d in cspace.inspect(str(path)).diagnostics} == {
        "joint-locked",
        "axis-normalized",
    }
    assert (
        main(["inspect", str(path), "--format", "json", "--strict", "--ignore", "joint-locked"])
        == 1
    )
    kept = json.loads(capsys.readouterr().out)["diagnostics"]
    assert [d["code"] for d in kept] == ["axis-normalized"]
    args = [
        "inspect",
        str(path),
        "--strict",
        "--ignore",
        "joint-locked",
        "--ignore",
        "axis-normalized",
    ]
    assert main(args) == 0
    capsys.readouterr()


@pytest.mark.parametrize("case", [c for c in CASES if c.repaired], ids=lambda c: c.file)
def test_pinocchio_refuses_the_file_but_the_layout_is_pinocchios(
    case: Case, tmp_path: Path
) -> None:
    text = (FINDINGS / case.file).read_text()
    with pytest.raises(ValueError):
        pin.buildModelFromXML(text)
    for written, ordinary in case.repaired:
        assert written in text
        text = text.replace(written, ordinary)
    repaired = pin.buildModelFromXML(text, mimic=True)
    report = cspace.inspect(str(FINDINGS / case.file))
    assert (report.nq, report.nv) == (repaired.nq, repaired.nv)
    layout = [(j.name, j.q_index, j.nq) for j in report.joints if j.q_index is not None]
    expected = [
        (str(repaired.names[i]), repaired.joints[i].idx_q, repaired.joints[i].nq)
        for i in range(1, repaired.njoints)
        if repaired.joints[i].idx_q >= 0 and i not in set(repaired.mimicking_joints)
    ]
    assert layout == expected


def test_the_report_keeps_the_files_values_not_the_stand_ins() -> None:
    report = cspace.inspect(str(FINDINGS / "mimic_multiplier_nan.urdf"))
    elbow = next(j for j in report.joints if j.name == "elbow")
    assert elbow.mimic is not None and elbow.mimic.joint == "shoulder"
    assert str(elbow.mimic.multiplier) == "nan"
    assert elbow.to_dict()["mimic"]["multiplier"] is None  # JSON has no NaN
    overflow = cspace.inspect(str(FINDINGS / "limits_overflow.urdf"))
    assert re.search(r"upper limit inf\b", overflow.diagnostics[0].message)


@pytest.mark.parametrize(
    ("first", "second", "code", "axis"),
    [((1, -1), (-1, 1), "limits-empty", 1), ((-1, 1), (1, -1), "limits-empty", 2),
     ((0.5, 0.5), (-1, 1), "joint-locked", 1)],
)  # fmt: skip
def test_each_axis_of_a_joint_of_several_is_checked(
    tmp_path: Path, first: tuple[float, float], second: tuple[float, float], code: str, axis: int
) -> None:
    """An SDF universal joint: an empty interval on either axis empties the space; a
    locked axis is named, with what cspace counts for it."""
    limits = [
        f"<limit><lower>{lo}</lower><upper>{hi}</upper></limit>" for lo, hi in (first, second)
    ]
    robot = tmp_path / "u.sdf"
    robot.write_text(
        '<?xml version="1.0"?><sdf version="1.9"><model name="m"><link name="a"/>'
        '<link name="b"/><joint name="u" type="universal"><parent>a</parent><child>b</child>'
        f"<axis><xyz>1 0 0</xyz>{limits[0]}</axis><axis2><xyz>0 1 0</xyz>{limits[1]}</axis2>"
        "</joint></model></sdf>"
    )
    found = [d for d in cspace.inspect(robot).diagnostics if d.code == code]
    assert len(found) == 1 and found[0].message.startswith(f"axis {axis} of joint 'u'")
