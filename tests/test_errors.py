"""The error taxonomy: every error has its own stable code, every class is exported, and
a configuration space is refused, clearly, for a robot whose report has errors."""

from __future__ import annotations

import inspect
import pickle

import pytest

import cspace
import cspace.errors

from conftest import REPO, run_cli

ERRORS = [
    cls
    for cls in vars(cspace.errors).values()
    if inspect.isclass(cls) and issubclass(cls, cspace.CspaceError)
]
EMPTY = REPO / "tests" / "findings" / "limits_empty.urdf"


def test_every_error_class_is_exported_with_a_code_of_its_own() -> None:
    assert len(ERRORS) >= 30
    for cls in ERRORS:
        assert cls.__name__ in cspace.errors.__all__, cls.__name__
    codes = [cls.code for cls in ERRORS]
    assert len(set(codes)) == len(codes), sorted(codes)
    assert all(code and code == code.lower() and " " not in code for code in codes)


def test_a_report_with_errors_has_no_configuration_space() -> None:
    report = cspace.inspect(EMPTY)
    assert any(d.severity is cspace.Severity.ERROR for d in report.diagnostics)
    with pytest.raises(cspace.RobotHasErrorsError) as refused:
        cspace.load(EMPTY)
    assert refused.value.code == "robot-has-errors"
    assert "limits-empty" in refused.value.findings
    for command in ("sample", "distance", "interpolate"):
        extra = {"sample": ["-n", "1"], "distance": ["0", "0"], "interpolate": ["0", "0"]}
        run = run_cli(command, str(EMPTY), *extra[command])
        assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
        assert "has no configuration space" in run.stderr
        assert run.stderr.rstrip().endswith("[robot-has-errors]")


def test_an_unknown_example_robot_data_name_is_its_own_error() -> None:
    with pytest.raises(cspace.ExampleRobotDataError) as unknown:
        cspace.inspect("erd:nope")
    assert unknown.value.code == "unknown-erd-robot" and "talos" in str(unknown.value)
    run = run_cli("inspect", "erd:nope")
    assert run.code == 2 and run.stderr.rstrip().endswith("[unknown-erd-robot]")


def test_errors_pickle_as_they_did_before_the_errors_package() -> None:
    # Before cspace.errors became a package, every class and the function that restores
    # them lived in the module cspace.errors: pickles still name them so (protocol 2
    # writes the names as text), so that older and newer versions read each other's.
    error = cspace.errors.OutOfLimitsError(
        coordinate="arm_left_1_joint",
        joint="arm_left_1_joint",
        value=4.0,
        lower=-1.0,
        upper=1.0,
        row=3,
    )
    data = pickle.dumps(error, protocol=2)
    assert b"ccspace.errors\n_restore\n" in data
    assert b"ccspace.errors\nOutOfLimitsError\n" in data and b"cspace.errors." not in data
    again = pickle.loads(data)
    assert type(again) is cspace.errors.OutOfLimitsError and str(again) == str(error)
    assert again.__dict__ == error.__dict__


def test_a_wrong_erd_name_lists_every_name_the_package_has() -> None:
    # the list is cspace's own: it is printed whole; the name given is what is cut
    from cspace._formats.shared import erd

    run = run_cli("inspect", "erd:nope")
    assert run.code == 2 and run.stderr.count("\n") == 1
    assert all(f" {name}," in run.stderr or f" {name})" in run.stderr for name in erd.available())
    huge = run_cli("inspect", "erd:" + "x" * 5_000)
    assert huge.code == 2 and len(huge.stderr) < 2_000 and "characters)" in huge.stderr
