"""A file is left to what includes it only when that reader really reads it as it is.

A fragment is never inspected on its own, so a broken robot would pass CI without a
word if the file said to include it did not read it, or read it otherwise than it reads
itself (its own includes from elsewhere): xacro skips an ``optional`` include it may
not read (its sandbox reads only the root's package, or folder), MuJoCo reads a
fragment's includes from its model's folder, and a nameless xacro "library" that
includes a robot expands to a robot of its own. Each case is run as CI runs it: a
folder's search and the names of its files (``--robots-only``), and the readers
themselves (xacro, MuJoCo) say what the premise is.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import xacro

from conftest import Run, run_cli
from conftest import mujoco_compiles as _mujoco_compiles
from conftest import robots_only_both_ways as _both
from conftest import summary_rows as _rows

XACRO = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
JOINT = (
    '<link name="x"/><link name="y"/><joint name="j" type="revolute"><parent link="x"/>'
    '<child link="y"/><limit lower="LOWER" upper="1" effort="1" velocity="1"/>'
    '<axis xyz="0 0 1"/></joint>'
)
BROKEN_XACRO = f'<robot name="b" {XACRO}>{JOINT.replace("LOWER", "5")}</robot>'
"""A xacro robot whose joint limits are reversed: an error finding."""
BODY = (
    '<worldbody><body name="b"><joint name="j" type="hinge"{}/><geom size="0.1"/></body>'
    "</worldbody>"
)
GOOD_BODY = BODY.format("")
BROKEN_BODY = BODY.format(' range="2 1" limited="true"')
"""A body MuJoCo refuses (``range[0] should be smaller``)."""


def _left(run: Run) -> set[str]:
    """The files a run's note says it left to the files that include them."""
    said = "cspace: note: left to the files that include them: "
    lines = [line for line in run.stderr.splitlines() if line.startswith(said)]
    return {name.removeprefix("./") for line in lines for name in line[len(said) :].split(", ")}


def _joints(path: Path) -> list[str]:
    """The ``<limit lower>`` of each joint xacro (unconfined, reading any file) makes."""
    document = xacro.process_file(str(path))
    return [limit.getAttribute("lower") for limit in document.getElementsByTagName("limit")]


def test_an_include_xacros_sandbox_cannot_read_leaves_out_nothing(tmp_path: Path) -> None:
    """xacro may read only the root's package (its folder, when it has none) and skips
    an ``optional`` include it cannot read: ``../E/b.xacro`` from ``D`` is not read, so
    the broken ``E/b.xacro`` is inspected, with ``package.xml`` files or without, and so
    is ``nested/b.xacro`` beside the package ``nested/sub`` of its includer, found on
    disk as xacro finds it when the names given leave its ``package.xml`` out (and name
    the one of ``nested``)."""
    include = '<xacro:include filename="{}" optional="true"/>'
    robot = f'<robot name="a" {XACRO}>{include}<link name="base"/></robot>'
    for top in ("alone", "packages"):
        for folder in ("D", "E"):
            (tmp_path / top / folder).mkdir(parents=True)
        (tmp_path / top / "D" / "a.xacro").write_text(robot.format("../E/b.xacro"))
        (tmp_path / top / "E" / "b.xacro").write_text(BROKEN_XACRO)
    (tmp_path / "nested" / "sub").mkdir(parents=True)
    (tmp_path / "nested" / "sub" / "a.xacro").write_text(robot.format("../b.xacro"))
    (tmp_path / "nested" / "b.xacro").write_text(BROKEN_XACRO)
    for name in ("packages/D", "packages/E", "nested", "nested/sub"):
        (tmp_path / name / "package.xml").write_text(
            f'<package format="3"><name>{name.replace("/", "_")}</name></package>'
        )
    assert _joints(tmp_path / "alone" / "D" / "a.xacro") == ["5"]  # xacro reads it when it may
    alone = run_cli("inspect", "--format", "jsonl", "alone/D/a.xacro", cwd=tmp_path)
    assert alone.code == 0 and '"dimension":0' in alone.stdout.replace(" ", ""), alone.stdout
    robots = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*.xacro"))
    options = ("inspect", "--robots-only", "--width", "400", "--")
    for run in (*_both(tmp_path), run_cli(*options, *robots, "nested/package.xml", cwd=tmp_path)):
        assert run.code == 1, run.stdout + run.stderr  # error findings
        assert _rows(run.stdout) == {
            "alone/D/a.xacro": "ok",
            "alone/E/b.xacro": "findings",
            "nested/b.xacro": "findings",
            "nested/sub/a.xacro": "ok",
            "packages/D/a.xacro": "ok",
            "packages/E/b.xacro": "findings",
        }, run.stdout + run.stderr
        assert not _left(run), run.stderr


def test_an_optional_include_leaves_out_nothing(tmp_path: Path) -> None:
    """xacro drops what an ``optional`` include splices in when any read in it fails
    (here an include of a missing file), so the file it names is inspected."""
    (tmp_path / "a.xacro").write_text(
        f'<robot name="a" {XACRO}><xacro:include filename="b.xacro" optional="true"/>'
        '<link name="base"/></robot>'
    )
    (tmp_path / "b.xacro").write_text(
        BROKEN_XACRO.replace("<link", '<xacro:include filename="missing.xacro"/><link', 1)
    )
    assert _joints(tmp_path / "a.xacro") == []  # b.xacro dropped whole
    for run in _both(tmp_path):
        assert run.code == 2 and _rows(run.stdout) == {"a.xacro": "ok", "b.xacro": "no report"}


def test_an_include_mujoco_reads_from_elsewhere_leaves_out_nothing(tmp_path: Path) -> None:
    """MuJoCo reads a fragment's includes from its model's folder: ``sub/x.xml``'s
    ``y.xml`` is ``y.xml``, so the cycle ``sub/x.xml``, ``sub/y.xml`` is not read through
    ``r.xml``, and ``sub/y.xml`` is inspected; ``part/arm.xml``, which ``r2.xml``
    includes, reads ``part/body.xml`` when compiled alone, not ``body.xml``: it is a
    model of its own, and inspected."""
    for folder in ("sub", "part"):
        (tmp_path / folder).mkdir()
    files = {
        "r.xml": f'<mujoco model="r"><include file="sub/x.xml"/>{GOOD_BODY}</mujoco>',
        "sub/x.xml": '<mujocoinclude><include file="y.xml"/></mujocoinclude>',
        "y.xml": "<mujocoinclude><worldbody/></mujocoinclude>",
        "sub/y.xml": f'<mujoco model="y"><include file="x.xml"/>{BROKEN_BODY}</mujoco>',
        "r2.xml": '<mujoco model="r2"><include file="part/arm.xml"/></mujoco>',
        "part/arm.xml": '<mujoco><include file="body.xml"/></mujoco>',
        "body.xml": f"<mujocoinclude>{GOOD_BODY}</mujocoinclude>",
        "part/body.xml": f"<mujocoinclude>{BROKEN_BODY}</mujocoinclude>",
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    assert _mujoco_compiles(tmp_path / "r.xml") and _mujoco_compiles(tmp_path / "r2.xml")
    assert not _mujoco_compiles(tmp_path / "sub" / "y.xml")
    assert not _mujoco_compiles(tmp_path / "part" / "arm.xml")
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        assert _rows(run.stdout) == {
            "part/arm.xml": "no report",
            "r.xml": "ok",
            "r2.xml": "ok",
            "sub/y.xml": "no report",
        }, run.stdout + run.stderr
        assert _left(run) == {"sub/x.xml", "y.xml", "body.xml", "part/body.xml"}, run.stderr


def test_a_nameless_file_that_includes_a_robot_is_inspected(tmp_path: Path) -> None:
    """xacro keeps the first default set for an argument, so a nameless file of
    ``<xacro:arg>`` and an include of a robot (directly, or through a library) expands
    to another robot than the one it includes: it is inspected (and refused, without a
    name), and what it includes is left to it. A library that includes only libraries
    stays out."""
    arg = '<xacro:arg name="lower" default="{}"/>'
    arm = f'<robot name="arm" {XACRO}>{arg.format(-1)}{JOINT.replace("LOWER", "$(arg lower)")}'
    files = {
        "robot.xacro": f'<robot {XACRO}>{arg.format(5)}<xacro:include filename="arm.xacro"/>',
        "arm.xacro": arm,
        "top.xacro": f'<robot {XACRO}>{arg.format(5)}<xacro:include filename="mid.xacro"/>',
        "mid.xacro": f'<robot {XACRO}><xacro:include filename="arm2.xacro"/>',
        "arm2.xacro": arm.replace('"arm"', '"arm2"'),
        "lib.xacro": f'<robot {XACRO}><xacro:include filename="lib2.xacro"/>',
        "lib2.xacro": f'<robot {XACRO}><xacro:macro name="m"><link name="l"/></xacro:macro>',
    }
    for name, text in files.items():
        (tmp_path / name).write_text(f"{text}</robot>")
    assert _joints(tmp_path / "arm.xacro") == ["-1"]
    assert _joints(tmp_path / "robot.xacro") == _joints(tmp_path / "top.xacro") == ["5"]
    for run in _both(tmp_path):
        assert run.code == 2, run.stdout + run.stderr
        rows = _rows(run.stdout)
        assert rows == {"robot.xacro": "no report", "top.xacro": "no report"}, run.stdout
        for name in rows:
            assert f"{name} (expanded by xacro):2: <robot> has no 'name'" in run.stderr
        assert _left(run) == {"arm.xacro", "mid.xacro", "arm2.xacro", "lib.xacro", "lib2.xacro"}


@pytest.mark.bounded
def test_files_reached_by_many_links_are_decided_once(tmp_path: Path) -> None:
    """Files that read alike (one real path, read from one folder) are one node of the
    includes: 400 links beside a ``<mujocoinclude>`` of 256 includes of itself cost the
    search at most 3 times what 400 copies of it cost (measured: about 1; each link was
    a node with an edge to every other, 256 times: 54 s and 342 MB for 400)."""
    from conftest import cpu_of as _cpu_of

    part = "<mujocoinclude>" + '<include file="part.xml"/>' * 256 + "</mujocoinclude>"
    links, copies = tmp_path / "links", tmp_path / "copies"
    for folder in (links, copies):
        folder.mkdir()
        (folder / "part.xml").write_text(part)
        (folder / "broken.xml").write_text(f"<mujoco>{BROKEN_BODY}</mujoco>")
    for k in range(400):
        (links / f"l{k}.xml").symlink_to("part.xml")
        (copies / f"l{k}.xml").write_text(part.replace("part.xml", f"l{k}.xml"))
    options = ("inspect", "--robots-only", "--width", "400", ".")
    _, reference = _cpu_of(*options, cwd=copies)
    run, cpu = _cpu_of(*options, cwd=links)
    assert run.code == 2 and _rows(run.stdout) == {"broken.xml": "no report"}, run
    assert cpu < 3 * reference, (cpu, reference)
