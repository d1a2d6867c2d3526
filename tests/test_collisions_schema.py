"""The collisions report's JSON Schema (``cspace schema --collisions``), held to real reports.

``cspace collisions --format json`` of robots with an SRDF (ur5, panda), of MuJoCo's
filters (an MJCF robot) and of a robot without collision shapes is valid under the
schema, read by ``jsonschema`` as written (Draft 2020-12) and as cspace reads a saved
collisions report (strictly, with the consistency the schema cannot say); ``--format
jsonl`` is the same document on one line. A saved document that breaks what the schema
or the consistency says is refused in one line, at its JSON Pointer.
"""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest

from conftest import REPO, ROBOTS, run_cli

ROBOTS_DRAWN = {
    "ur5-srdf": ("erd:ur5", "--srdf", "auto", "-n", "300"),
    "panda-srdf": ("erd:panda", "--srdf", "auto", "-n", "200"),
    "mjcf-filters": (str(ROBOTS / "mjcf_every_joint.xml"), "-n", "100"),
    "no-shapes": (str(ROBOTS / "arm7.urdf"), "-n", "50"),
    "boxes": (str(REPO / "docs" / "examples" / "boxes_arm.urdf"), "-n", "200", "--seed", "7"),
}
"""Robots and how they are drawn: an SRDF's matrix, MuJoCo's, none, and no shapes."""


@pytest.fixture(scope="module")
def documents() -> dict[str, dict[str, Any]]:
    out = {}
    for name, args in ROBOTS_DRAWN.items():
        run = run_cli("collisions", *args, "--format", "json")
        assert run.code in (0, 1), run.stderr
        out[name] = json.loads(run.stdout)
    return out


def _schema() -> dict[str, Any]:
    run = run_cli("schema", "--collisions")
    assert run.code == 0, run.stderr
    schema: dict[str, Any] = json.loads(run.stdout)
    return schema


def test_the_schema_is_a_draft_2020_12_schema_of_the_collisions_kind() -> None:
    schema = _schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    assert schema["properties"]["kind"]["const"] == "collisions"
    assert schema["properties"]["schema_version"] == {"const": 1}
    assert run_cli("schema").stdout != run_cli("schema", "--collisions").stdout


def test_the_schema_bounds_what_the_command_takes() -> None:
    import importlib

    import cspace
    from cspace._formats.table import names
    from cspace._reports.collisions import COLLISIONS_SCHEMA_VERSION, PAIR_KINDS
    from cspace._schema import COLLISIONS_SCHEMA_FILE, collisions_schema_text

    max_samples = importlib.import_module(cspace.collisions.__module__).MAX_SAMPLES
    schema = _schema()
    shipped = (REPO / "src" / "cspace" / "_schema" / COLLISIONS_SCHEMA_FILE).read_text()
    assert collisions_schema_text() == shipped  # the package's formats are the table's
    props, defs = schema["properties"], schema["$defs"]
    assert props["source"]["properties"]["format"]["enum"] == list(names())
    assert props["samples"]["maximum"] == max_samples == 1_000_000
    assert defs["share"]["properties"]["samples"]["maximum"] == max_samples
    assert props["schema_version"]["const"] == COLLISIONS_SCHEMA_VERSION
    assert defs["pair"]["properties"]["kind"]["enum"] == list(PAIR_KINDS)
    assert (defs["unit"]["minimum"], defs["unit"]["maximum"]) == (0, 1)


@pytest.mark.parametrize("name", sorted(ROBOTS_DRAWN))
def test_every_report_is_valid_and_consistent(
    name: str, documents: dict[str, dict[str, Any]]
) -> None:
    from cspace._reports._collisions_check import check_collisions_document

    document = documents[name]
    jsonschema.Draft202012Validator(_schema()).validate(document)
    check_collisions_document(name, document)  # strictly, as a saved report is read
    for pair in document["pairs"]:
        share = pair["collisions"]
        if share is not None:
            assert 0 <= share["low"] <= share["share"] <= share["high"] <= 1


def test_the_reports_hold_every_kind_of_value(documents: dict[str, dict[str, Any]]) -> None:
    """The robots drawn exercise the schema: rules, null shares, witnesses, no shapes."""
    ur5, mjcf, bare = documents["ur5-srdf"], documents["mjcf-filters"], documents["no-shapes"]
    assert ur5["matrix"] == "srdf" and ur5["srdf"].endswith("ur5.srdf")
    assert {p["kind"] for p in ur5["pairs"]} >= {"adjacent", "never", "sometimes"}
    assert any(p["collisions"] is None for p in ur5["pairs"])  # adjacent, not sampled
    assert any(p["rule"] and p["rule"]["line"] for p in ur5["pairs"])
    assert {d["severity"] for d in ur5["diagnostics"]} == {"error"}
    assert mjcf["matrix"] == "mjcf" and mjcf["srdf"] is None
    assert any(p["witness"] for p in mjcf["pairs"])
    assert bare["links"] == [] and bare["pairs"] == [] and bare["matrix"] == "none"
    assert documents["boxes"]["seed"] == 7


def test_jsonl_is_the_same_document_on_one_line(tmp_path: Path) -> None:
    robot = str(REPO / "docs" / "examples" / "boxes_arm.urdf")
    both = [run_cli("collisions", robot, "-n", "100", "--format", f) for f in ("json", "jsonl")]
    assert [r.code for r in both] == [0, 0], both[1].stderr
    assert both[1].stdout.count("\n") == 1
    assert json.loads(both[1].stdout) == json.loads(both[0].stdout)


def _refused(document: dict[str, Any]) -> str:
    from cspace._reports.savedreport import read_saved_document
    from cspace.errors import ReportFileError

    data = json.dumps(document).encode()
    with pytest.raises(ReportFileError) as caught:
        read_saved_document("b.jsonl:3", data)
    said = str(caught.value)
    assert "\n" not in said and said.startswith("b.jsonl:3"), said
    return said


@pytest.mark.parametrize(
    ("where", "value", "said"),
    [
        (("samples",), 10**9, "above the maximum 1000000"),
        (("seed",), -1, "below the minimum 0"),
        (("kind",), "collision", "not a cspace report"),
        (("matrix",), "moveit", "is not one of"),
        (("pairs", 0, "kind"), "often", "is not one of"),
        (("pairs", 0, "collisions", "share"), 0.5, "is not 1 / 300"),
        (("pairs", 0, "collisions", "low"), 0.9, "not low <= share <= high"),
        (("pairs", 0, "kind"), "never", "a never pair in collision in 1 of 300 samples"),
        (("pairs", 0, "collisions", "hits"), 301, "301 hits of 300 samples"),
        (("pairs", 0, "link1"), "zz", "are not two links, sorted"),
        (("pairs", 1), None, "expected an object"),
        (("srdf",), None, "an SRDF not read with matrix srdf"),
        (("free", "samples"), 30, "30 samples in a report of 300"),
        (("pairs", 0, "witness", "configuration", "elbow_joint"), [0.0, 1.0], "expected a number"),
        (("pairs", 0, "witness", "sample"), 300, "a witness beyond the samples"),
    ],
)
def test_a_forged_document_is_refused_in_one_line(
    documents: dict[str, dict[str, Any]], where: tuple[str | int, ...], value: Any, said: str
) -> None:
    document = copy.deepcopy(documents["ur5-srdf"])
    assert document["pairs"][0]["collisions"]["hits"] == 1  # base_link-ee_link, sometimes
    target: Any = document
    for step in where[:-1]:
        target = target[step]
    target[where[-1]] = value
    assert said in _refused(document)


def test_a_collisions_report_is_no_c_space_report_for_diff(
    tmp_path: Path, documents: dict[str, dict[str, Any]]
) -> None:
    (tmp_path / "collisions.json").write_text(json.dumps(documents["no-shapes"]))
    run = run_cli("diff", "collisions.json", str(ROBOTS / "arm7.urdf"), cwd=tmp_path)
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "a cspace collisions report, not a C-space report" in run.stderr
