"""A format is one reader module and one row of the format table.

A toy format from outside the package (``<toyrobot>``: a URDF under another root, read
by a module in a scratch folder) is added to `cspace._formats.table.FORMATS` by a script
that then runs the command line, as a plugin would; it is found wherever cspace lists
or tells formats: the loader, a folder's search, the report and its schema, saved reports
read back, the help, the refusals that list the formats.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

TOY_READER = '''
"""A toy reader: a URDF written under <toyrobot>, read by cspace's URDF reader."""
from dataclasses import replace

from lxml import etree

from cspace._formats.urdf.reader import read_urdf


def read(request):
    text = request.source.text.replace("<toyrobot", "<robot", 1)
    text = text.replace("</toyrobot>", "</robot>")
    reading = read_urdf(request.path, etree.fromstring(text.encode()), text)
    return reading._replace(description=replace(reading.description, format="toy"))
'''

TOY_CLI = """
import sys

from cspace._formats import table

table.FORMATS.append(
    table.Format("toy", "Toy", "toyformat", root="toyrobot", suffixes=(".toy",))
)
from cspace._cli.main import main

sys.exit(main(sys.argv[1:]))
"""


@pytest.fixture(scope="module")
def toy(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A scratch folder with the toy format's reader, its command line and robots."""
    folder = tmp_path_factory.mktemp("toy")
    (folder / "toyformat.py").write_text(TOY_READER)
    (folder / "toy_cspace.py").write_text(TOY_CLI)
    urdf = (REPO / "robots" / "arm7.urdf").read_text()
    toy = urdf.replace("<robot", "<toyrobot", 1).replace("</robot>", "</toyrobot>")
    robots = folder / "robots"
    robots.mkdir()
    (robots / "arm.toy").write_text(toy)
    (robots / "arm.xml").write_text(toy)  # told by its root, whatever its name
    (robots / "notes.txt").write_text("not a robot\n")
    (folder / "other.xml").write_text("<other/>\n")
    return folder


def _run(toy: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(toy / "toy_cspace.py"), *args],
        cwd=toy,
        capture_output=True,
        text=True,
        timeout=120,
        env={"PYTHONPATH": str(toy), "PATH": "/usr/bin:/bin", "NO_COLOR": "1"},
    )


def test_a_toy_format_is_read_and_reported(toy: Path) -> None:
    urdf = _run(toy, "inspect", str(REPO / "robots" / "arm7.urdf"), "--format", "json")
    run = _run(toy, "inspect", "robots/arm.toy", "--format", "json")
    assert run.returncode == 0, run.stderr
    report, original = json.loads(run.stdout), json.loads(urdf.stdout)
    assert report["source"]["format"] == "toy"
    assert report["manifold"] == original["manifold"]
    assert [j["name"] for j in report["joints"]] == [j["name"] for j in original["joints"]]


def test_a_folder_search_finds_the_toy_format(toy: Path) -> None:
    run = _run(toy, "inspect", "robots", "--format", "jsonl")
    assert run.returncode == 0, run.stderr
    read = sorted(json.loads(line)["source"]["path"] for line in run.stdout.splitlines())
    assert read == ["robots/arm.toy", "robots/arm.xml"]


def test_the_schema_and_saved_reports_know_the_toy_format(toy: Path) -> None:
    schema = json.loads(_run(toy, "schema").stdout)
    assert "toy" in schema["properties"]["source"]["properties"]["format"]["enum"]
    saved = toy / "arm.json"
    saved.write_text(_run(toy, "inspect", "robots/arm.toy", "--format", "json").stdout)
    run = _run(toy, "diff", "arm.json", "robots/arm.xml")
    assert run.returncode == 0, run.stdout + run.stderr


def test_help_and_refusals_list_the_toy_format(toy: Path) -> None:
    assert "Toy" in _run(toy, "inspect", "--help").stdout
    assert "Toy" in _run(toy, "sample", "--help").stdout
    run = _run(toy, "inspect", "other.xml")
    assert run.returncode == 2 and "<toyrobot> (TOY)" in run.stderr, run.stderr
    run = _run(toy, "inspect", "robots/arm.toy", "--srdf", "x.srdf")
    assert run.returncode == 2 and "this robot is TOY [srdf-format]" in run.stderr, run.stderr


def test_the_package_schema_file_lists_the_package_formats() -> None:
    """The shipped file is the schema for the package's own table (no format added)."""
    from cspace._formats.table import names
    from cspace._schema import REPORT_SCHEMA_FILE, report_schema, report_schema_text

    text = (REPO / "src" / "cspace" / "_schema" / REPORT_SCHEMA_FILE).read_text()
    assert report_schema_text() == text
    source = report_schema()["properties"]["source"]["properties"]
    assert source["format"]["enum"] == list(names())
