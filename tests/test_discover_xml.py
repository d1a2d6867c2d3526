"""A folder's search, and --robots-only's names, leave out no robot its readers read.

Each broken robot here is one a reader takes for a robot (MuJoCo, urdfdom, lxml, xacro;
the tests ask them where they can), where a search that reads less than they do would
miss it without a word: junk before its root, which tinyxml2 reads. Each is inspected
and fails (exit 2), in a folder's search and among the names a pull request changes
(``--robots-only -- NAMES``).
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import mujoco
import pinocchio

from conftest import Run, run_cli

ARM = (
    '<robot name="a"><link name="b"/><link name="c"/><joint name="j" type="revolute">'
    '<parent link="b"/><child link="c"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
    "</joint></robot>"
)
BROKEN_URDF = ARM.replace('lower="-1" upper="1"', 'lower="2" upper="1"')
"""A URDF whose limits are reversed: an error finding (``findings``)."""
MJCF = (
    '<mujoco model="arm"><worldbody><body name="b"><joint name="j" type="hinge"/>'
    '<geom size="0.1"/></body></worldbody></mujoco>'
)
BROKEN_MJCF = MJCF.replace('type="hinge"', 'type="hinge" range="2 1" limited="true"')
"""An MJCF model MuJoCo refuses (``range[0] should be smaller``): no report."""
XACRO = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def _rows(stdout: str) -> dict[str, str]:
    """Path -> status of a summary table."""
    lines = stdout.splitlines()[2:]
    rows = [line.split() for line in lines[: lines.index("")]] if "" in lines else []
    return {row[0]: row[-1] if row[-1] != "report" else "no report" for row in rows}


def _both(root: Path) -> list[Run]:
    """``cspace inspect --robots-only`` of the folder, and of the names of its files
    (links too), as the pre-commit hook and the Action pass them."""
    names = sorted(
        str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() or p.is_symlink()
    )
    options = ("inspect", "--robots-only", "--width", "400")
    return [run_cli(*options, ".", cwd=root), run_cli(*options, "--", *names, cwd=root)]


def _mujoco_reads(data: bytes) -> bool:
    """Whether MuJoCo compiles a file of these bytes (as ``MjModel.from_xml_path``)."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "model.xml"
        path.write_bytes(data)
        try:
            mujoco.MjModel.from_xml_path(str(path))
        except ValueError:
            return False
        return True


def _urdfdom_reads(text: str) -> bool:
    """Whether Pinocchio's URDF parser (urdfdom, on tinyxml2) builds a model of ``text``."""
    try:
        pinocchio.buildModelFromXML(text)
    except (RuntimeError, ValueError):
        return False
    return True


def test_a_robot_after_what_tinyxml2_reads_before_a_root_is_inspected(tmp_path: Path) -> None:
    """tinyxml2 (MuJoCo's parser, urdfdom's, sdformat's) reads text before the root, a
    ``<`` and white space before its name, CDATA, and (urdfdom, sdformat) elements before
    a top-level ``<robot>``: each such file is a robot to them, and inspected (lxml then
    refuses it); so is one whose junk goes on past the first 64 KiB. A file tinyxml2
    refuses (its text runs to its end, as in a README or a Python file holding a model;
    a NUL byte before the root) is no robot, and stays out."""
    robots = {
        "text.xml": b"A model of the arm.\n" + BROKEN_MJCF.encode(),
        "spaced.xml": b"< " + BROKEN_MJCF.encode()[1:],
        "cdata.xml": b"<![CDATA[<x>]]>" + BROKEN_MJCF.encode(),
        "long.xml": b"junk " * 20_000 + BROKEN_MJCF.encode(),
        "before.xml": b"<notes/>\n" + BROKEN_URDF.encode(),
    }
    for name, data in robots.items():
        (tmp_path / name).write_bytes(data)
        good = data.replace(b' range="2 1" limited="true"', b"").replace(
            b'lower="2"', b'lower="-1"'
        )
        assert _mujoco_reads(good) or _urdfdom_reads(good.decode()), name  # a robot to them
    others = {
        "README.md": f"# Arm\n\n```xml\n{MJCF}\n```\n\nIts one joint.\n".encode(),
        "model.py": f'MODEL = """{ARM}"""\nprint(MODEL)\n'.encode(),
        "nul.xml": b"x\0" + MJCF.encode(),
    }
    for name, data in others.items():
        (tmp_path / name).write_bytes(data)
        assert not _mujoco_reads(data) and not _urdfdom_reads(data.decode()), name
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == dict.fromkeys(robots, "no report"), run.stdout + run.stderr
        assert "text.xml:1:1: not XML (Start tag expected, '<' not found) [xml-syntax]\n" in (
            run.stderr
        )
