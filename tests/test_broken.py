"""Broken robot files: one precise line, exit code 2, never a traceback or C++ noise.

Each file in tests/broken/ is written by hand and says in an XML comment what is wrong
with it. The table gives, for each, the error code, the line and the element the error
must name, and a fragment of the message; every file is run through the installed
`cspace` command as a user runs it, and through the library.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pytest

import cspace

from conftest import REPO, Run, run_cli, run_cli_many

BROKEN = REPO / "tests" / "broken"


@dataclass(frozen=True)
class Case:
    """What one broken file must produce."""

    file: str
    code: str
    line: int | None
    element: str | None
    fragment: str
    error: type[cspace.RobotFileError] = cspace.errors.RobotStructureError


E = cspace.errors.InvalidElementError
X = cspace.errors.XmlSyntaxError

CASES = (
    Case(
        "missing_child_link.urdf",
        "missing-link",
        13,
        "elbow",
        "joint 'elbow' names child link 'forarm', which does not exist (did you mean 'forearm'?)",
    ),
    Case(
        "missing_parent_link.urdf",
        "missing-link",
        10,
        "shoulder",
        "names parent link 'pedestal', which does not exist",
    ),
    Case(
        "two_parents.urdf",
        "two-parents",
        17,
        "tool_mount",
        "link 'tool' has two parent joints, 'wrist' (line 13) and 'tool_mount'",
    ),
    Case("cycle.urdf", "cycle", 8, "ab", "cycle through links b -> c -> a -> b"),
    Case("cycle_everywhere.urdf", "cycle", 10, "ba", "cycle through links a -> b -> a"),
    Case("self_loop.urdf", "cycle", 10, "spin", "joint 'spin' connects link 'wheel' to itself"),
    Case(
        "several_roots.urdf",
        "several-roots",
        6,
        "camera",
        "2 links have no parent joint ('base', 'camera')",
    ),
    Case(
        "duplicate_joint.urdf",
        "duplicate-joint",
        12,
        "shoulder",
        "joint 'shoulder' is defined twice (first at line 7)",
    ),
    Case(
        "duplicate_link.urdf",
        "duplicate-link",
        6,
        "upper_arm",
        "link 'upper_arm' is defined twice (first at line 5)",
    ),
    Case(
        "unknown_joint_type.urdf",
        "unknown-joint-type",
        6,
        "shoulder",
        "joint 'shoulder' has unknown type 'ball' (valid: continuous, fixed, floating, planar, "
        "prismatic, revolute)",
        cspace.errors.UnknownJointTypeError,
    ),
    Case(
        "mimic_unknown_joint.urdf",
        "mimic-unknown-joint",
        13,
        "right_finger",
        "mimics joint 'left_fingr', which does not exist (did you mean 'left_finger'?)",
    ),
    Case(
        "mimic_cycle.urdf",
        "mimic-cycle",
        7,
        "left_finger",
        "mimic joints follow each other in a circle: left_finger -> right_finger -> left_finger",
    ),
    Case("mimic_self.urdf", "mimic-cycle", 6, "finger", "joint 'finger' mimics itself"),
    Case(
        "revolute_without_limit.urdf",
        "missing-limit",
        6,
        "elbow",
        "joint 'elbow' is revolute but has no <limit> element (URDF requires one)",
        E,
    ),
    Case(
        "prismatic_without_limit.urdf",
        "missing-limit",
        6,
        "lift",
        "joint 'lift' is prismatic but has no <limit> element",
        E,
    ),
    Case(
        "limit_without_effort.urdf",
        "missing-attribute",
        10,
        "elbow",
        "joint 'elbow': <limit> has no 'effort' attribute",
        E,
    ),
    Case("bad_number.urdf", "bad-number", 10, "elbow", '<limit upper="1,5"> is not a number', E),
    Case("empty_number.urdf", "bad-number", 10, "elbow", '<limit lower=""> is empty', E),
    Case(
        "hex_number.urdf", "bad-number", 10, "elbow", '<limit velocity="0x10"> is not a number', E
    ),
    Case(
        "underscore_number.urdf",
        "bad-number",
        10,
        "lift",
        '<limit upper="1_000"> is not a number',
        E,
    ),
    Case(
        "non_ascii_digit_number.urdf",
        "bad-number",
        10,
        "lift",
        '<limit upper="\u0661"> is not a number',
        E,
    ),
    Case(
        "dotless_i_infinity.urdf",
        "bad-number",
        10,
        "lift",
        '<limit upper="\u0131nf"> is not a number',
        E,
    ),
    Case(
        "axis_two_numbers.urdf",
        "bad-number",
        9,
        "elbow",
        '<axis xyz="0 1"> is not three numbers',
        E,
    ),
    Case(
        "axis_without_xyz.urdf",
        "missing-attribute",
        9,
        "elbow",
        "joint 'elbow': <axis> has no 'xyz' attribute",
        E,
    ),
    Case(
        "origin_bad.urdf",
        "bad-number",
        7,
        "elbow",
        "joint 'elbow': <origin rpy=\"0 0 pi/2\"> is not three numbers",
        E,
    ),
    Case(
        "dynamics_empty.urdf",
        "missing-attribute",
        11,
        "elbow",
        "<dynamics> has neither 'damping' nor 'friction'",
        E,
    ),
    Case(
        "safety_without_k_velocity.urdf",
        "missing-attribute",
        11,
        "elbow",
        "<safety_controller> has no 'k_velocity' attribute",
        E,
    ),
    Case("joint_without_name.urdf", "missing-attribute", 12, None, "<joint> has no 'name'", E),
    Case("joint_without_type.urdf", "missing-attribute", 6, "shoulder", "<joint> has no 'type'", E),
    Case(
        "joint_without_parent.urdf",
        "missing-element",
        6,
        "shoulder",
        "joint 'shoulder' has no <parent> element",
        E,
    ),
    Case("link_without_name.urdf", "missing-attribute", 5, None, '<link name=""> is empty', E),
    Case(
        "robot_without_name.urdf",
        "missing-attribute",
        3,
        "robot",
        "<robot> has no 'name' attribute",
        E,
    ),
    Case("no_links.urdf", "no-links", 3, None, "has no links: the file describes no robot"),
    Case(
        "not_a_robot.urdf",
        "not-a-robot",
        3,
        "launch",
        "root element <launch> is not a robot description",
        cspace.errors.NotARobotError,
    ),
    Case("truncated.urdf", "xml-syntax", 10, None, "the file is truncated", X),
    Case("not_xml.urdf", "xml-syntax", 2, None, "not XML", X),
    Case("comment_only.urdf", "xml-syntax", 3, None, "no XML element", X),
    Case("undefined_entity.urdf", "xml-syntax", 9, None, "Entity 'pi' not defined", X),
    Case(
        "latin1_undeclared.urdf",
        "xml-syntax",
        6,
        None,
        "not in the encoding it declares",
        X,
    ),
    Case(
        "entity_declared.urdf",
        "xml-unsafe",
        4,
        "limit",
        "declares the XML entity 'limit'",
        cspace.errors.UnsafeXmlError,
    ),
    Case(
        "dtd_attribute_default.urdf",
        "xml-unsafe",
        4,
        "joint",
        "declares <!ATTLIST joint> in a DTD",
        cspace.errors.UnsafeXmlError,
    ),
)


def _relative(name: str) -> str:
    return f"tests/broken/{name}"


@pytest.fixture(scope="session")
def cli_runs() -> dict[str, Run]:
    """Every broken file through the CLI, two at a time (one process per file)."""
    runs = run_cli_many([("inspect", _relative(c.file)) for c in CASES])
    return {c.file: run for c, run in zip(CASES, runs, strict=True)}


def _assert_one_error_line(run: Run, prefix: str) -> str:
    """Exit 2, nothing on stdout, exactly one line on stderr, ours."""
    assert run.code == 2, run
    assert run.stdout == ""
    assert run.stderr.endswith("\n") and run.stderr.count("\n") == 1, run.stderr
    assert run.stderr.startswith(f"cspace: error: {prefix}"), run.stderr
    assert "Traceback" not in run.stderr
    return run.stderr.rstrip("\n")


def test_every_file_in_the_corpus_has_a_case_and_says_what_is_wrong() -> None:
    files = sorted(p.name for p in BROKEN.iterdir())
    assert files == sorted(c.file for c in CASES)
    for path in BROKEN.iterdir():
        assert b"<!-- Broken: " in path.read_bytes()[:300], path.name


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.file)
def test_cli_names_file_line_and_problem(case: Case, cli_runs: dict[str, Run]) -> None:
    where = _relative(case.file) + ("" if case.line is None else f":{case.line}")
    message = _assert_one_error_line(cli_runs[case.file], f"{where}:")
    assert case.fragment in message
    assert message.endswith(f"[{case.code}]")


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.file)
def test_library_raises_the_error_with_its_attributes(
    case: Case, capfd: pytest.CaptureFixture[str]
) -> None:
    path = str(BROKEN / case.file)
    with pytest.raises(case.error) as caught:
        cspace.inspect(path)
    error = caught.value
    assert (error.code, error.line, error.path) == (case.code, case.line, path)
    assert error.element == case.element
    assert case.fragment in error.problem
    assert "\n" not in str(error)
    assert capfd.readouterr() == ("", "")  # nothing from Pinocchio's C++ parser


def test_missing_file(tmp_path: Path) -> None:
    run = run_cli("inspect", str(tmp_path / "nope.urdf"))
    message = _assert_one_error_line(run, f"{tmp_path / 'nope.urdf'}: ")
    assert message.endswith("no such file [file-unreadable]")


def test_empty_and_blank_files(tmp_path: Path) -> None:
    (tmp_path / "empty.urdf").write_bytes(b"")
    (tmp_path / "blank.urdf").write_bytes(b"  \n\t\n")
    for name in ("empty.urdf", "blank.urdf"):
        run = run_cli("inspect", name, cwd=tmp_path)
        assert _assert_one_error_line(run, f"{name}: ").endswith("file is empty [file-unreadable]")


def test_a_directory(tmp_path: Path) -> None:
    run = run_cli("inspect", ".", cwd=tmp_path)
    assert "is a directory, not a robot file [file-unreadable]" in _assert_one_error_line(run, ".")


def test_binary_file(tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_bytes(bytes(range(256)) * 4)
    run = run_cli("inspect", "robot.urdf", cwd=tmp_path)
    assert "[xml-syntax]" in _assert_one_error_line(run, "robot.urdf:1:")


def test_unreadable_path(tmp_path: Path) -> None:
    # A path through a regular file cannot be opened, whoever runs the tool (root too).
    (tmp_path / "robot.urdf").write_text("<robot/>")
    run = run_cli("inspect", "robot.urdf/inner.urdf", cwd=tmp_path)
    line = _assert_one_error_line(run, "robot.urdf/inner.urdf: ")
    assert "cannot read: Not a directory [file-unreadable]" in line


def test_pinocchio_refusal_names_the_joint_and_its_line() -> None:
    # Given the file as it is, Pinocchio's parser refuses lower="nan" with a message that
    # names no line; the adapter's error points at the joint the message names.
    from cspace._formats.shared.xmlio import parse_xml, read_source
    from cspace._formats.urdf.reader import read_urdf
    from cspace._model.adapter import build_urdf_model

    source = read_source(str(REPO / "tests" / "findings" / "limits_nan.urdf"))
    description = read_urdf(source.path, parse_xml(source), source.text).description
    with pytest.raises(cspace.errors.ModelBuildError) as caught:
        build_urdf_model(source.path, source.text, None, description=description)
    assert (caught.value.line, caught.value.element) == (13, "elbow")
    assert "lower value (nan)" in caught.value.problem
    assert caught.value.parser_messages  # Pinocchio's own words are kept


def test_an_added_root_joint_may_not_take_a_name_the_file_uses(tmp_path: Path) -> None:
    # Pinocchio would hold two joints called root_joint, and the report would be wrong.
    (tmp_path / "robot.urdf").write_text(
        '<robot name="r">\n<link name="base"/><link name="arm"/>\n'
        '<joint name="root_joint" type="continuous"><parent link="base"/>'
        '<child link="arm"/></joint>\n</robot>\n'
    )
    assert run_cli("inspect", "robot.urdf", cwd=tmp_path).code == 0
    run = run_cli("inspect", "robot.urdf", "--root-joint", "floating", cwd=tmp_path)
    message = _assert_one_error_line(run, "robot.urdf:3: ")
    assert "the file has a joint named 'root_joint'" in message
    assert message.endswith("[duplicate-joint]")


def test_debug_shows_the_traceback_and_nothing_else_does() -> None:
    path = _relative("cycle.urdf")
    quiet = run_cli("inspect", path)
    assert "Traceback" not in quiet.stderr
    loud = run_cli("--debug", "inspect", path)
    assert loud.code == quiet.code == 2  # the exit code is kept
    assert "Traceback (most recent call last)" in loud.stderr
    assert "RobotStructureError" in loud.stderr


def test_unknown_option_values_are_one_line_usage_errors() -> None:
    run = run_cli("inspect", "robots/arm7.urdf", "--ignore", "no-such-code")
    message = _assert_one_error_line(run, "")
    assert "no-such-code" in message
