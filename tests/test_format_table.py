"""A format is one reader module and one row of the format table.

Two toy formats from outside the package, read by a module in a scratch folder, are
added to `cspace._formats.table.FORMATS` by a script that then runs the command line,
as a plugin would: ``toy`` (``<toyrobot>``: a URDF under another root, and files named
``.toy``) and ``bytoy``, told by its first bytes (``#bytoy``, then a URDF). Each is
found wherever cspace lists or tells formats: the loader, a folder's search (by root,
by name, by bytes), the report and its schema, saved reports read back, the help, the
refusals that list the formats.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from cspace._formats.shared.description import RobotDescription

from conftest import REPO, ROBOTS

TOY_READER = '''
"""A toy reader: a URDF written under <toyrobot>, read by cspace's URDF reader."""

from lxml import etree

from cspace._formats.urdf.reader import read_urdf


def read(request):
    if request.root is None:  # bytoy: "#bytoy" and a URDF
        text = request.source.text.partition("\\n")[2]
        reading = read_urdf(request.path, etree.fromstring(text.encode()), text)
        return reading._replace(description=reading.description.replace(format="bytoy"))
    text = request.source.text.replace("<toyrobot", "<robot", 1)
    text = text.replace("</toyrobot>", "</robot>")
    reading = read_urdf(request.path, etree.fromstring(text.encode()), text)
    return reading._replace(description=reading.description.replace(format="toy"))
'''

TOY_CLI = """
import sys

from cspace._formats import table

table.FORMATS.append(
    table.Format("toy", "Toy", "toyformat", root="toyrobot", suffixes=(".toy",))
)
table.FORMATS.append(
    table.Format("bytoy", "ByToy", "toyformat", magic=(b"#bytoy",), suffixes=(".bytoy",))
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
    (robots / "arm.data").write_text("#bytoy\n" + urdf)  # told by its bytes
    (robots / "broken.toy").write_text("<other/>\n")  # a robot by its name: refused
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
    assert run.returncode == 2 and "robots/broken.toy" in run.stderr, run.stderr
    read = {
        json.loads(line)["source"]["path"]: json.loads(line)["source"]["format"]
        for line in run.stdout.splitlines()
    }
    assert read == {"robots/arm.toy": "toy", "robots/arm.xml": "toy", "robots/arm.data": "bytoy"}


def test_the_schema_and_saved_reports_know_the_toy_format(toy: Path) -> None:
    schema = json.loads(_run(toy, "schema").stdout)
    formats = schema["properties"]["source"]["properties"]["format"]["enum"]
    assert {"toy", "bytoy"} <= set(formats)
    saved = toy / "arm.json"
    saved.write_text(_run(toy, "inspect", "robots/arm.toy", "--format", "json").stdout)
    run = _run(toy, "diff", "arm.json", "robots/arm.xml")
    assert run.returncode == 0, run.stdout + run.stderr


def test_help_and_refusals_list_the_toy_format(toy: Path) -> None:
    for command in ("inspect", "sample"):  # the help's words, however argparse wraps them
        assert "Toy, ByToy)" in " ".join(_run(toy, command, "--help").stdout.split())
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


def test_a_text_usd_layer_counts_its_tags_and_a_crate_does_not(tmp_path: Path) -> None:
    """Only the binary files of a format told by its bytes skip the XML tag count."""
    from conftest import run_cli

    text = tmp_path / "big.usda"
    text.write_text((REPO / "tests/usd/converted/arm7.usda").read_text() + "# " + "<" * 250_001)
    run = run_cli("inspect", str(text))
    assert run.code == 2 and "XML tags" in run.stderr, run.stderr
    crate = tmp_path / "big.usdc"
    crate.write_bytes(b"PXR-USDC" + b"<" * 250_001)
    run = run_cli("inspect", str(crate))
    assert run.code == 2 and "XML tags" not in run.stderr, run.stderr


def test_an_srdf_for_an_xml_format_without_one_is_refused_once_the_file_is_read(
    tmp_path: Path,
) -> None:
    """A broken SDF file says what is wrong with it first; a sound one is refused the SRDF."""
    from conftest import run_cli

    srdf = str(REPO / "docs" / "examples" / "mobile_arm.srdf")
    broken = tmp_path / "broken.sdf"
    broken.write_text(
        '<sdf version="1.9"><model name="x"><link name="a"/><joint name="j" type="bogus">'
        "<parent>world</parent><child>a</child></joint></model></sdf>"
    )
    run = run_cli("inspect", str(broken), "--srdf", srdf)
    assert run.code == 2 and "[unknown-joint-type]" in run.stderr, run.stderr
    run = run_cli("inspect", str(REPO / "robots" / "sdf_every_joint.sdf"), "--srdf", srdf)
    assert run.code == 2 and "this robot is SDF [srdf-format]" in run.stderr, run.stderr


NO_LIBRARY_CLI = """
import sys

from cspace._formats import table

table.FORMATS.append(
    table.Format(
        "bytoy", "ByToy", "toyformat", magic=(b"#bytoy",), suffixes=(".bytoy",),
        extra="bytoy", library="cspace_no_such_library",
    )
)
from cspace._cli.main import main

sys.exit(main(sys.argv[1:]))
"""


def test_files_of_a_format_without_its_library_are_left_out_and_named_safely(
    toy: Path, tmp_path: Path
) -> None:
    """A folder's files of a format whose library is missing are said in one note; their
    names, however hostile, print as no workflow command and no control character."""
    (toy / "no_library_cspace.py").write_text(NO_LIBRARY_CLI)
    folder = tmp_path / "pr"
    folder.mkdir()
    urdf = (REPO / "robots" / "arm7.urdf").read_text()
    (folder / "arm.urdf").write_text(urdf)
    for name in ("::error::forged.bytoy", "##[group]hidden.bytoy", "bell\a\u202e.bytoy"):
        (folder / name).write_text("#bytoy\n" + urdf)
    done = subprocess.run(
        [sys.executable, str(toy / "no_library_cspace.py"), "inspect", str(folder)],
        cwd=toy,
        capture_output=True,
        text=True,
        timeout=120,
        env={"PYTHONPATH": str(toy), "PATH": "/usr/bin:/bin", "NO_COLOR": "1"},
    )
    assert done.returncode == 0, done.stderr  # the URDF is read; the others left out
    assert "BYTOY files left out, as ByToy is not installed" in done.stderr
    assert "pip install 'cspace[bytoy]'" in done.stderr
    for text in (done.stdout, done.stderr):
        assert "##[" not in text and "\a" not in text and "\u202e" not in text
        assert not any(line.lstrip().startswith("::") for line in text.splitlines())


def test_a_description_is_an_immutable_value_and_replace_reindexes_its_joints() -> None:
    # what every reader hands the model: equal when read twice, never changed in place
    from cspace._formats.shared.xmlio import parse_xml, read_source
    from cspace._formats.urdf.reader import read_urdf

    def described() -> RobotDescription:
        source = read_source(str(ROBOTS / "arm7.urdf"))
        return read_urdf(source.path, parse_xml(source), source.text).description

    first, second = described(), described()
    assert first == second and hash(first) == hash(second) and first is not second
    assert repr(first).startswith("RobotDescription(name='arm7', format='urdf'")
    for change in (lambda: setattr(first, "joints", ()), lambda: delattr(first, "name")):
        with pytest.raises(AttributeError, match="immutable"):
            change()
    kept = first.joints[1:]
    fewer = first.replace(joints=kept, format="toy")
    assert fewer.joint(first.joints[0].name) is None  # the index is the new joints'
    assert fewer.joint(kept[0].name) == kept[0] and fewer.format == "toy"
    assert fewer != first and first == second  # the original is unchanged
