"""Saved JSON reports are untrusted: checked against the schema before diff or check uses them.

A crafted report (a key missing, a wrong type, NaN, a 5,000-digit integer, a list nested
100,000 deep, a negative index, a huge string, not an object, ...) ends in exit 2 and one
line ``cspace: error: FILE: problem at /json/pointer [bad-report]``; never a traceback.
Every report cspace writes (the golden ones included) passes the same check. Hypothesis
(derandomized, no database) mutates reports and generates schema-valid ones: diffing them
ends in a diff or a :class:`cspace.errors.ReportFileError`, nothing else.
"""

from __future__ import annotations

import copy
import json
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cspace
from cspace._manifold import NormalForm
from cspace._render.markdown import render_diff_markdown
from cspace._render.text import render_diff_text
from cspace._reports.diff import diff_reports
from cspace._reports.savedreport import read_report_document

from conftest import REPO, ROBOTS, manifold_section, run_cli, run_cli_many

GOOD = cspace.inspect(str(ROBOTS / "mobile_manipulator.urdf")).to_dict()
GOOD_TEXT = json.dumps(GOOD, indent=2, ensure_ascii=False)


def changed(edit: Any) -> bytes:
    """The good report, edited by ``edit(document)``, as JSON bytes."""
    document = copy.deepcopy(GOOD)
    edit(document)
    return json.dumps(document, allow_nan=True).encode()


def with_text(old: str, new: str) -> bytes:
    """The good report's text with ``old`` (which must be there) replaced by ``new``."""
    assert old in GOOD_TEXT
    return GOOD_TEXT.replace(old, new, 1).encode()


def setter(*path: Any, value: Any) -> Any:
    def edit(document: Any) -> None:
        for key in path[:-1]:
            document = document[key]
        document[path[-1]] = value

    return edit


def deleter(*path: Any) -> Any:
    def edit(document: Any) -> None:
        for key in path[:-1]:
            document = document[key]
        del document[path[-1]]

    return edit


DEEP = "[" * 100_000 + "]" * 100_000
CRAFTED: dict[str, tuple[bytes, str]] = {
    "missing-nq": (changed(deleter("nq")), "'nq' is a required property at the top level"),
    "missing-joint-key": (changed(deleter("joints", 1, "q_index")), "at /joints/1"),
    "missing-manifold": (changed(deleter("manifold")), "not a cspace report"),
    "nq-string": (changed(setter("nq", value="3")), "found '3' at /nq"),
    "nq-float": (changed(setter("nq", value=3.0)), "found 3.0 at /nq"),
    "q-index-bool": (changed(setter("joints", 1, "q_index", value=True)), "/joints/1/q_index"),
    "joints-object": (changed(setter("joints", value={})), "at /joints"),
    "joint-number": (changed(setter("joints", 0, value=5)), "at /joints/0"),
    "limits-string": (
        changed(setter("joints", 2, "limits", "lower", 0, value="-1")),
        "at /joints/2/limits/lower/0",
    ),
    "limits-lengths": (
        changed(setter("joints", 2, "limits", "upper", value=[1.0, 2.0])),
        "2 upper bounds for 1 lower bounds at /joints/2/limits/upper",
    ),
    "negative-q-index": (
        changed(setter("joints", 2, "q_index", value=-5)),
        "-5 is below the minimum 0 at /joints/2/q_index",
    ),
    "negative-nv": (changed(setter("nv", value=-1)), "at /nv"),
    "huge-index": (changed(setter("joints", 2, "v_index", value=10**300)), "/joints/2/v_index"),
    "nan": (changed(setter("joints", 2, "limits", "lower", 0, value=float("nan"))), "NaN"),
    "infinity": (changed(setter("nq", value=float("inf"))), "Infinity is not a JSON number"),
    "minus-infinity": (changed(setter("nq", value=float("-inf"))), "-Infinity is not a JSON"),
    "1e400": (with_text('"nq": ', '"nq": 1e400, "x": '), "1e400 is beyond any double"),
    "5000-digits": (with_text('"nq": ', '"nq": ' + "9" * 5000 + ', "x": '), "5,000 digits"),
    "deep-list": (with_text('"nq": ', f'"x": {DEEP}, "nq": '), "nested too deeply"),
    "deep-joints": (with_text('"joints": ', f'"joints": {DEEP}, "y": '), "nested too deeply"),
    "huge-name": (changed(setter("robot", value="x" * 100_000)), "100,000 characters"),
    "huge-array": (changed(setter("diagnostics", value=[None] * 100_001)), "/diagnostics"),
    "array": (b"[]", "not a cspace report (no joints, no manifold) at the top level"),
    "nested-arrays": (b" [1, [2]]", "not a cspace report"),
    "string": (b'"report"', "not a cspace report"),
    "number": (b"42", "not a cspace report"),
    "null": (b"null", "not a cspace report"),
    "version-2": (changed(setter("schema_version", value=2)), "schema_version 2;"),
    "version-string": (changed(setter("schema_version", value="1")), "schema_version '1';"),
    "version-float": (changed(setter("schema_version", value=1.0)), "at /schema_version"),
    "duplicate-key": (with_text('"nq": ', '"nq": 1, "nq": '), "'nq' appears twice"),
    "not-utf8": (b'{"robot": "\xff"}', "not UTF-8"),
    "truncated": (GOOD_TEXT[:-40].encode(), "not a JSON report"),
    "notation": (changed(setter("manifold", "notation", value="R^9")), "/manifold/notation"),
    "notation-newline": (
        changed(setter("manifold", "notation", value=GOOD["manifold"]["notation"] + "\n")),
        "at /manifold/notation",
    ),
    "dimension": (changed(setter("dimension", value=99)), "contradicts the factors"),
    "joint-space": (changed(setter("joints", 2, "manifold", value="S^2")), "/joints/2/manifold"),
    "root-joint": (changed(setter("root_joint", value="spinning")), "at /root_joint"),
    "kind": (changed(setter("joints", 2, "kind", value="wormhole")), "at /joints/2/kind"),
    "path-number": (changed(setter("source", "path", value=7)), "at /source/path"),
    "diagnostic-code": (
        changed(setter("diagnostics", value=[{"severity": "info", "code": "A B"}])),
        "at /diagnostics/0",
    ),
}


@pytest.fixture(scope="session")
def crafted_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("crafted")
    for name, (data, _) in CRAFTED.items():
        (folder / f"{name}.json").write_bytes(data)
    (folder / "good.json").write_text(GOOD_TEXT, encoding="utf-8")
    return folder


def assert_bad_report(run: Any, name: str, fragment: str) -> None:
    assert run.code == 2, run
    assert run.stdout == ""
    assert run.stderr.count("\n") == 1, run.stderr
    assert run.stderr.startswith(f"cspace: error: {name}.json"), run.stderr
    assert run.stderr.endswith(" [bad-report]\n"), run.stderr
    assert fragment in run.stderr, run.stderr
    assert len(run.stderr) < 800


def test_every_crafted_report_is_one_line_exit_2(crafted_dir: Path) -> None:
    names = sorted(CRAFTED)
    commands = [
        ("diff", str(crafted_dir / f"{n}.json"), str(crafted_dir / "good.json")) for n in names
    ]
    commands += [("check", str(crafted_dir / f"{n}.json"), "--dimension", "1") for n in names]
    runs = run_cli_many(commands)
    for name, diff_run, check_run in zip(
        names, runs[: len(names)], runs[len(names) :], strict=True
    ):
        path = str(crafted_dir / name)
        assert_bad_report(diff_run, path, CRAFTED[name][1])
        assert_bad_report(check_run, path, CRAFTED[name][1])


def test_the_error_carries_path_and_pointer() -> None:
    data = changed(setter("joints", 2, "q_index", value=-5))
    with pytest.raises(cspace.errors.ReportFileError) as raised:
        read_report_document("old.json", data)
    error = raised.value
    assert (error.path, error.pointer, error.code) == (
        "old.json",
        "/joints/2/q_index",
        "bad-report",
    )
    assert isinstance(error, cspace.RobotFileError)
    assert str(error) == (
        "old.json: not a valid cspace report: -5 is below the minimum 0 at /joints/2/q_index"
    )


def test_the_good_report_itself_diffs(crafted_dir: Path) -> None:
    good = str(crafted_dir / "good.json")
    run = run_cli("diff", good, str(ROBOTS / "mobile_manipulator.urdf"))
    assert (run.code, run.stderr) == (0, "")


def every_report() -> list[tuple[str, bytes]]:
    """The golden reports, and a report of every teaching robot written by the command.

    The goldens are the command's ``--format json`` of each robot (indented; as it writes
    them today, `test_robots` says); the command writes the others in one run of all the
    robots, a line of JSON Lines each (the same report, without the indentation).
    """
    golden = [(p.name, p.read_bytes()) for p in sorted((REPO / "tests" / "golden").glob("*.json"))]
    robots = sorted(p for p in ROBOTS.iterdir() if p.suffix in (".urdf", ".xml", ".sdf"))
    run = run_cli("inspect", "--format", "jsonl", "--", *(str(p) for p in robots))
    lines = run.stdout.splitlines()
    assert len(lines) == len(robots), run.stderr
    written = [(p.name, line.encode()) for p, line in zip(robots, lines, strict=True)]
    return golden + written


def test_every_report_cspace_writes_passes_the_strict_check() -> None:
    reports = every_report()
    assert len(reports) > 20
    for name, data in reports:
        document = read_report_document(name, data)
        assert not diff_reports(document, document).differs


def test_inspect_never_imports_jsonschema_and_diff_of_a_report_does() -> None:
    """In one new interpreter, one command after another (what one imports stays for the
    next): after each, whether jsonschema was imported, on standard error."""
    probe = (
        "import json, sys\nfrom cspace._cli.main import main\n"
        "for args in json.loads(sys.argv[1]):\n"
        "    try:\n        main(args)\n    except SystemExit:\n        pass\n"
        "    print('jsonschema' in sys.modules, file=sys.stderr, flush=True)"
    )
    arm = str(ROBOTS / "arm7.urdf")
    saved = REPO / "tests" / "golden" / "arm7.json"
    bad = json.loads(saved.read_text())
    bad["nq"] = -1
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "bad.json").write_text(json.dumps(bad))
        commands = [
            ["inspect", arm, "--format", "json"],
            ["diff", str(saved), arm],
            ["diff", str(Path(folder) / "bad.json"), arm],
        ]
        done = subprocess.run(
            [sys.executable, "-c", probe, json.dumps(commands)],
            capture_output=True,
            text=True,
            check=False,
        )
    said = done.stderr.splitlines()
    # inspect, then a diff of a valid report: proved valid without jsonschema
    assert said[:2] == ["False", "False"], done.stderr
    # a diff of a bad report: its one line, jsonschema saying what is wrong with it
    assert len(said) == 4 and said[2].endswith("[bad-report]"), done.stderr
    assert said[3] == "True", done.stderr


# Fuzzing: through the library's entry points (read, diff, render), then the command.

ODD = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**20), 10**20),
    st.sampled_from([10**400, -(10**400), 2**31, -1, 0, 1.5, -0.0, 1e308]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8),
    st.sampled_from(["R^1", "S^1", "point", "R^2 × S^1", "\x1b[31m", "\u202e", "a" * 1000]),
    st.lists(st.integers(0, 3), max_size=3),
    st.dictionaries(st.sampled_from(["lower", "upper", "unit"]), st.integers(), max_size=3),
)


def nodes(value: Any, path: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """The path of every value inside ``value`` (the root excluded)."""
    found = []
    children = (
        value.items()
        if isinstance(value, dict)
        else enumerate(value)
        if isinstance(value, list)
        else ()
    )
    for key, child in children:
        found.append((*path, key))
        found += nodes(child, (*path, key))
    return found


@st.composite
def mutated_reports(draw: st.DrawFn) -> bytes:
    """A report with one to four values deleted, replaced or duplicated; sometimes cut short."""
    document = copy.deepcopy(GOOD)
    for _ in range(draw(st.integers(1, 4))):
        paths = nodes(document)
        if not paths:
            break
        path = paths[draw(st.integers(0, len(paths) - 1))]
        parent = document
        for key in path[:-1]:
            parent = parent[key]
        operation = draw(st.sampled_from(["delete", "replace", "duplicate"]))
        if operation == "delete":
            del parent[path[-1]]
        elif operation == "replace":
            parent[path[-1]] = draw(ODD)
        elif isinstance(parent, list):
            parent.insert(path[-1], copy.deepcopy(parent[path[-1]]))
    data = json.dumps(document, allow_nan=True).encode()
    if draw(st.integers(0, 7)) == 0:
        data = data[: draw(st.integers(0, len(data)))]
    return data


NAMES = st.text(min_size=1, max_size=6) | st.sampled_from(["j1", "j2", "\x1b]8;;x\x07", "a|`b"])
NUMBER = st.none() | st.floats(-1e308, 1e308, allow_nan=False) | st.integers(-(10**300), 10**300)
INDEX = st.none() | st.integers(0, 2**31 - 1)
COUNT = st.integers(0, 2**31 - 1)
SPACES = ["point", "R^1", "S^1", "R^2 × S^1", "RP^3", "R^3 × RP^3", "R^3", "T^2"]


@st.composite
def valid_reports(draw: st.DrawFn) -> bytes:
    """A report the schema accepts, with arbitrary names, numbers, indices and limits."""
    document = copy.deepcopy(GOOD)
    joints = []
    names = draw(st.lists(NAMES, max_size=5, unique=True))  # a chain: one joint a link
    for k, name in enumerate(names):
        size = draw(st.integers(1, 3))
        limits = draw(
            st.none()
            | st.fixed_dictionaries(
                {
                    "lower": st.lists(NUMBER, min_size=size, max_size=size),
                    "upper": st.lists(NUMBER, min_size=size, max_size=size),
                    "unit": st.sampled_from(["rad", "m"]),
                }
            )
        )
        joint = {**GOOD["joints"][2], "name": name, "limits": limits}
        joint.update(parent_link=f"link{k}", child_link=f"link{k + 1}")
        joint.update(q_index=draw(INDEX), nq=draw(COUNT), v_index=draw(INDEX), nv=draw(COUNT))
        joint.update(manifold=draw(st.sampled_from(SPACES)), dimension=draw(COUNT))
        joints.append(joint)
    form = NormalForm(*(draw(st.integers(0, 2**20)) for _ in range(3)))
    document.update(joints=joints, nq=draw(COUNT), nv=draw(COUNT), dimension=form.dimension)
    document["root_joint"] = draw(st.sampled_from([None, "floating", "planar"]))
    document["source"]["path"] = draw(NAMES)
    document["manifold"] = manifold_section(form)
    return json.dumps(document).encode()


def diff_saved(old: bytes, new: bytes, tolerance: float = 1e-6) -> None:
    """The library's contract: a ReportFileError, or a diff that renders safely."""
    try:
        documents = read_report_document("old.json", old), read_report_document("new.json", new)
    except cspace.errors.ReportFileError as error:
        message = str(error)
        assert "\n" not in message and message.isprintable() and error.code == "bad-report"
        return
    diff = diff_reports(*documents, tolerance=tolerance)
    for text in (render_diff_text(diff), render_diff_markdown(diff), diff.to_json()):
        assert all(line.isprintable() for line in text.split("\n"))
    assert json.loads(diff.to_json())["changed"] is diff.changed


FUZZ = settings(
    max_examples=300,
    derandomize=True,
    database=None,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)


@FUZZ
@given(mutated_reports(), mutated_reports())
def test_mutated_reports_diff_or_are_refused(old: bytes, new: bytes) -> None:
    diff_saved(old, new)


@FUZZ
@given(valid_reports(), valid_reports(), st.sampled_from([0.0, 1e-6, 1.0, float("inf")]))
def test_schema_valid_reports_always_diff(old: bytes, new: bytes, tolerance: float) -> None:
    read_report_document("old.json", old)  # valid by construction: no error
    diff_saved(old, new, tolerance)


@settings(max_examples=12, derandomize=True, database=None, deadline=None)
@given(mutated_reports() | valid_reports(), st.sampled_from(["text", "markdown", "json"]))
def test_crafted_reports_through_the_command(data: bytes, fmt: str) -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "old.json").write_bytes(data)
        (Path(folder) / "new.json").write_text(GOOD_TEXT, encoding="utf-8")
        run = run_cli("diff", "old.json", "new.json", "--format", fmt, cwd=Path(folder))
    assert run.code in (0, 1, 2), run
    assert "Traceback" not in run.stderr and "internal error" not in run.stderr
    if run.code == 2:
        assert run.stdout == "" and run.stderr.count("\n") == 1
        assert run.stderr.startswith("cspace: error: old.json")
        # an empty file (a mutant cut to nothing) is unreadable before it is JSON
        assert run.stderr.endswith((" [bad-report]\n", ": file is empty [file-unreadable]\n"))
    else:
        assert run.stderr == ""


@pytest.mark.parametrize("name", ["robot.urdf", "robot.xml", "robot.SDF", "robot.urdf.xacro"])
def test_a_report_in_a_robot_files_place_is_no_robot(tmp_path: Path, name: str) -> None:
    """A saved report committed under a robot file's name (another robot's, whose
    C-space, limits and ros2_control it states) is refused by check --expect and diff,
    not read as what the file is; under a report's name it is read."""
    robot = ROBOTS / "arm7.urdf"
    report = run_cli("inspect", str(robot), "--format", "json").stdout
    (tmp_path / name).write_text(report)
    (tmp_path / "report.json").write_text(report)
    for args in (
        ("check", name, "--expect", "R^6 x S^1", "--dimension", "7"),
        ("diff", str(robot), name),
    ):
        run = run_cli(*args, cwd=tmp_path)
        assert run.code == 2 and run.stdout == "", run.stdout
        assert run.stderr.startswith(f"cspace: error: {name}: is JSON, not a robot description")
    assert run_cli("check", "report.json", "--expect", "R^6 x S^1", cwd=tmp_path).code == 0
    assert run_cli("diff", str(robot), "report.json", cwd=tmp_path).code == 0
