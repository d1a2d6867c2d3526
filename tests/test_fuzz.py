"""Fuzzing: mutated robot files end in a report or a clear error, never anything else.

Valid URDFs from robots/ (and an MJCF and an SDF file) are mutated (elements dropped,
duplicated and renamed; attributes dropped, renamed and given odd values; characters
injected; the text cut short). Every mutant goes through the library in-process, where
the only exceptions allowed are :class:`cspace.CspaceError` with a one-line message
naming the file, and a report must serialise to schema-valid JSON; a smaller sample goes
through the `cspace` command, which must exit 0, 1 or 2 with exactly one line on stderr
for 2. Hypothesis runs derandomized and without a database, so every run tries the same
cases.
"""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

import jsonschema
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

import cspace
from cspace._schema import report_schema

from conftest import ROBOTS, cpu_of

SEEDS = {
    path.name: etree.tostring(
        etree.parse(str(path), etree.XMLParser(remove_comments=True)).getroot()
    )
    for path in sorted([*ROBOTS.glob("*.urdf"), *ROBOTS.glob("*_every_joint.*")])
}
TAGS = ("link", "joint", "parent", "child", "limit", "axis", "mimic", "origin", "robot", "x")
ATTRIBUTES = ("name", "type", "link", "lower", "upper", "xyz", "joint", "effort", "velocity")
ODD_VALUES = (
    "nan",
    "-inf",
    "inf",
    "1e400",
    "-1e400",
    "0x10",
    "",
    " ",
    "1,5",
    "1_0",
    "\u0661",
    "-0",
    "1e-400",
    "\t2\n",
    "+.5e1",
    "9" * 400,
    "0 0 0",
    "nan 0 1",
    "1 1",
    "1 0 0 0",
    "3.14159265",
    "-3.14159265",
    "6.2831853",
    "revolute",
    "continuous",
    "prismatic",
    "planar",
    "floating",
    "fixed",
    "ball",
    "\u00e4\u00df\u4e2d",
    "<&>\"'",
    "-1",
    "-3.0",
    "0",
    "2",
)
NUMBERS = ("nan", "inf", "-inf", "1e400", "-0", "1e-400", " 2 ", "+.5e1", "-1", "0", "2")
NUMBERS += ("3.14159265", "-3.14159265", "9.42477796", "0x10", "")
VECTORS = ("0 0 0", "nan 0 1", "0 0 2", "0 1 0", "1e400 0 0", " 0  1 0 ", "1 1", "0 0 -1")
OPERATIONS = ("drop", "duplicate", "rename", "drop-attr", "rename-attr", "odd", "swap", "number")
NUMERIC_TAGS = ("limit", "axis", "origin", "mimic", "dynamics")
INJECTIONS = (b"<", b">", b"&", b"\x00", b"\xff\xfe", b"]]>", b'"', b"<!ENTITY x 'y'>", b"&#0;")
VALIDATOR = jsonschema.Draft202012Validator(report_schema())
SECONDS_PER_CASE = 5.0
"""CPU seconds a mutant may cost in this process (through the command: 5 more, start-up)."""


@st.composite
def mutants(draw: st.DrawFn) -> bytes:
    """A seed robot file with one to four mutations."""
    root = etree.fromstring(SEEDS[draw(st.sampled_from(sorted(SEEDS)))])
    numbers_only = draw(st.booleans())  # half the mutants keep their structure
    for _ in range(draw(st.integers(1, 4))):
        elements = list(root.iter())
        target = elements[draw(st.integers(0, len(elements) - 1))]
        operation = "number" if numbers_only else draw(st.sampled_from(OPERATIONS))
        parent = target.getparent()
        keys = sorted(target.attrib)
        if operation == "drop" and parent is not None:
            parent.remove(target)
        elif operation == "duplicate" and parent is not None:
            parent.insert(parent.index(target) + 1, etree.fromstring(etree.tostring(target)))
        elif operation == "rename":
            target.tag = draw(st.sampled_from(TAGS))
        elif operation == "drop-attr" and keys:
            del target.attrib[draw(st.sampled_from(keys))]
        elif operation == "rename-attr" and keys:
            key = draw(st.sampled_from(keys))
            target.set(draw(st.sampled_from(ATTRIBUTES)), target.attrib.pop(key))
        elif operation == "odd":
            target.set(
                draw(st.sampled_from((*keys, *ATTRIBUTES))), draw(st.sampled_from(ODD_VALUES))
            )
        elif operation == "number":  # an odd value where the file has a number
            numeric = [e for e in elements if e.tag in NUMERIC_TAGS and e.attrib]
            if numeric:
                chosen = numeric[draw(st.integers(0, len(numeric) - 1))]
                key = draw(st.sampled_from(sorted(chosen.attrib)))
                vector = chosen.tag in ("axis", "origin")
                chosen.set(key, draw(st.sampled_from(VECTORS if vector else NUMBERS)))
        elif operation == "swap" and keys:
            donor = elements[draw(st.integers(0, len(elements) - 1))]
            values = sorted(donor.attrib.values())
            if values:
                target.set(draw(st.sampled_from(keys)), draw(st.sampled_from(values)))
    data = etree.tostring(root)
    if draw(st.booleans()) and draw(st.booleans()):  # a quarter: damage the bytes too
        at = draw(st.integers(0, len(data)))
        if draw(st.booleans()):
            data = data[:at]
        else:
            data = data[:at] + draw(st.sampled_from(INJECTIONS)) + data[at:]
    return data


def check_in_process(data: bytes) -> None:
    """The library's contract on one mutant (see the module docstring)."""
    start = time.process_time()
    try:
        report = cspace.inspect_source(cspace.source_from_bytes("fuzz.urdf", data))
    except cspace.CspaceError as error:
        message = str(error)
        assert message.startswith("fuzz.urdf") and "\n" not in message, message
        if isinstance(error, cspace.RobotFileError):
            assert error.code and error.problem
    else:
        document = report.to_dict()
        VALIDATOR.validate(document)
        json.dumps(document, allow_nan=False)
        assert report.dimension == sum(j.space.dimension for j in report.joints)
        # The joints tile Pinocchio's q and v, and the C-space is no larger than v.
        assert sum(j.nq for j in report.joints) == report.nq
        assert sum(j.nv for j in report.joints) == report.nv
        assert report.dimension <= report.nv
        # A mimic joint with coordinates of its own must say why it has them.
        if any(j.kind is cspace.JointKind.MIMIC and j.nq for j in report.joints):
            assert any(d.code == "mimic-kept-free" for d in report.diagnostics)
    assert time.process_time() - start < SECONDS_PER_CASE


@pytest.mark.bounded
@settings(
    max_examples=400,
    derandomize=True,
    database=None,
    deadline=None,  # the time bound is asserted per case, against CPU time
    suppress_health_check=[HealthCheck.too_slow],
)
@given(mutants())
def test_mutants_in_process_end_in_a_report_or_a_clear_error(data: bytes) -> None:
    check_in_process(data)


@pytest.mark.bounded
@settings(max_examples=16, derandomize=True, database=None, deadline=None)
@given(mutants())
def test_mutants_through_the_command(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "fuzz.urdf").write_bytes(data)
        run, cpu = cpu_of("inspect", "fuzz.urdf", "--format", "json", cwd=Path(folder))
        assert cpu < SECONDS_PER_CASE + 5
    assert run.code in (0, 1, 2), run
    assert "Traceback" not in run.stderr
    if run.code == 2:  # one line per problem (several when several joints are broken)
        assert run.stdout == ""
        lines = run.stderr.splitlines()
        assert lines and run.stderr.endswith("\n"), run.stderr
        assert all(line.startswith("cspace: error: fuzz.urdf") for line in lines), run.stderr
        assert all(line.endswith("]") for line in lines), run.stderr
    else:
        assert run.stderr == ""
        document = json.loads(run.stdout)
        has_errors = any(d["severity"] == "error" for d in document["diagnostics"])
        assert run.code == (1 if has_errors else 0)


def test_the_seeds_themselves_are_valid() -> None:
    assert len(SEEDS) >= 5
    for data in SEEDS.values():
        report = cspace.inspect_source(cspace.source_from_bytes("seed.urdf", data))
        assert not report.has(cspace.Severity.ERROR)
