"""Robot descriptions found by what they are: folders searched, fragments left to their models.

A folder argument stands for the robot files in it; an MJCF ``<mujocoinclude>`` file,
and a file another one includes (MJCF ``<include>``/``<model>``, ``<xacro:include>``), is
checked as part of what includes it, never refused on its own.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

from conftest import REPO, run_cli

ARM = (
    '<robot name="a"><link name="b"/><link name="c"/><joint name="j" type="revolute">'
    '<parent link="b"/><child link="c"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
    "</joint></robot>"
)


def _rows(stdout: str) -> dict[str, str]:
    """Path -> status of a summary table."""
    lines = stdout.splitlines()[2:]
    rows = [line.split() for line in lines[: lines.index("")]]
    return {row[0]: row[-1] if row[-1] != "report" else "no report" for row in rows}


def test_the_repositorys_robots_folder_reads_whole() -> None:
    run = run_cli("inspect", "robots", "--width", "400", cwd=REPO)
    rows = _rows(run.stdout)
    assert run.code == 0 and set(rows.values()) == {"ok"}, run.stdout + run.stderr
    assert "robots/mjcf_mujocoinclude/scene.xml" in rows
    assert "robots/mjcf_mujocoinclude/gripper.xml" not in rows  # <mujocoinclude>
    assert "robots/mjcf_include/arm.xml" not in rows  # included by scene.xml
    assert "robots/xacro_demo/urdf/macros.xacro" not in rows  # $(find ...)/urdf/macros.xacro
    urdf = {str(p.relative_to(REPO)) for p in (REPO / "robots").glob("*.urdf")}
    assert urdf <= set(rows)


def test_a_fragment_named_on_its_own_is_a_note_not_an_error() -> None:
    path = "robots/mjcf_mujocoinclude/gripper.xml"
    one = run_cli("inspect", path, cwd=REPO)
    assert one.code == 0 and one.stdout == ""
    assert one.stderr.startswith(f"cspace: note: {path}:") and "[mjcf-fragment]" in one.stderr
    several = run_cli("inspect", path, "robots/mjcf_mujocoinclude/scene.xml", cwd=REPO)
    assert several.code == 0
    assert _rows(several.stdout)[path] == "fragment"
    assert "1 MJCF fragments left to their models" in several.stdout


def test_the_adroit_fragments_a_ci_script_finds_with_grep_fail_nothing() -> None:
    spec = importlib.util.find_spec("gymnasium_robotics")
    assert spec is not None and spec.submodule_search_locations
    folder = Path(next(iter(spec.submodule_search_locations)))
    fragments = [p for p in folder.rglob("*.xml") if b"<mujocoinclude" in p.read_bytes()[:4096]]
    assert len(fragments) >= 3
    run = run_cli("inspect", *map(str, fragments))
    assert run.code == 0 and set(_rows(run.stdout).values()) == {"fragment"}
    whole = run_cli("inspect", str(folder), "--width", "400")
    assert whole.code == 0 and set(_rows(whole.stdout).values()) == {"ok"}


def test_hidden_and_linked_folders_are_not_searched(tmp_path: Path) -> None:
    (tmp_path / "arm.urdf").write_text(ARM)
    (tmp_path / ".git").mkdir()
    (tmp_path / ".git" / "old.urdf").write_text("<robot")
    outside = tmp_path.parent / f"{tmp_path.name}-outside"
    outside.mkdir()
    (outside / "broken.urdf").write_text("<robot")
    os.symlink(outside, tmp_path / "linked")
    (tmp_path / "notes.xml").write_text("<notes/>")  # not a robot: not picked
    (tmp_path / "named.data").write_text(ARM)  # a <robot> root whatever the name
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    assert run.code == 0, run.stdout + run.stderr
    assert sorted(_rows(run.stdout)) == [str(tmp_path / "arm.urdf"), str(tmp_path / "named.data")]


def test_a_folder_without_robot_files_says_so(tmp_path: Path) -> None:
    run = run_cli("inspect", str(tmp_path))
    assert run.code == 2 and "is a directory" in run.stderr


def test_finding_the_root_takes_one_pass() -> None:
    """Comments one after another once took exponential time (a 281-byte file hung)."""
    import time

    from cspace._formats._discover import root_tag

    started = time.perf_counter()
    assert root_tag(b"<!---->" * 20_000 + b"!") is None
    assert time.perf_counter() - started < 1.0
    assert root_tag(b'<?xml version="1.0"?>\n<!-- licence -->\n<mujoco/>') == "mujoco"
    assert root_tag(b"\xef\xbb\xbf<!DOCTYPE x>\n<robot name='r'/>") == "robot"


def test_nothing_in_a_comment_or_another_file_type_hides_a_robot(tmp_path: Path) -> None:
    broken = '<mujoco><worldbody><body><joint bogus="1"/></body></worldbody></mujoco>'
    (tmp_path / "broken.xml").write_text(broken)
    (tmp_path / "good.xml").write_text('<mujoco><!-- <include file="broken.xml"/> --></mujoco>')
    (tmp_path / "README.md").write_text('<xacro:include filename="$(find p)/urdf/r.urdf.xacro"/>')
    (tmp_path / "urdf").mkdir()
    (tmp_path / "urdf" / "r.urdf.xacro").write_text(  # a named robot calling its own macro
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:macro name="m"><link name="a"/></xacro:macro><xacro:m/></robot>'
    )
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    rows = _rows(run.stdout)
    assert run.code == 2 and rows[str(tmp_path / "broken.xml")] == "no report"
    assert set(rows) == {str(tmp_path / n) for n in ("broken.xml", "good.xml", "urdf/r.urdf.xacro")}


def test_a_folder_of_fragments_only_is_a_note(tmp_path: Path) -> None:
    (tmp_path / "gripper.xml").write_text("<mujocoinclude><body/></mujocoinclude>")
    run = run_cli("inspect", str(tmp_path))
    assert run.code == 0 and "left to the files that include them" in run.stderr


def test_a_folder_of_two_robots_cannot_be_one_picture(tmp_path: Path) -> None:
    for name in ("a.urdf", "b.urdf"):
        (tmp_path / name).write_text(ARM)
    run = run_cli("inspect", str(tmp_path), "--format", "html")
    assert run.code == 2 and "draws one robot" in run.stderr
    (tmp_path / "b.urdf").unlink()
    assert run_cli("inspect", str(tmp_path), "--format", "svg").stdout.startswith("<svg")


def test_a_searched_folder_never_blocks_or_follows_a_link_out(tmp_path: Path) -> None:
    """A FIFO would block a read, a device would never end, a link would lead outside:
    the search peeks at regular files of the folder only."""
    folder = tmp_path / "repo"
    folder.mkdir()
    (folder / "arm.urdf").write_text(ARM)
    os.mkfifo(folder / "pipe.urdf")
    os.symlink("/dev/zero", folder / "zero.xml")
    outside = tmp_path / "outside.urdf"
    outside.write_text("<robot")  # broken: reading it would fail the run
    os.symlink(outside, folder / "link.urdf")
    nested = folder
    for depth in range(60):  # deep folders: the walk is a loop, not a recursion
        nested = nested / f"d{depth}"
    nested.mkdir(parents=True)
    (nested / "deep.urdf").write_text(ARM)
    run = run_cli("inspect", str(folder), "--width", "4000", timeout=60)
    assert run.code == 0, run.stdout + run.stderr
    assert sorted(_rows(run.stdout)) == sorted(
        [str(folder / "arm.urdf"), str(nested / "deep.urdf")]
    )


def test_a_fragment_cannot_hide_a_file_outside_the_folder(tmp_path: Path) -> None:
    """Includes that lead out of the folder hide nothing and read nothing there."""
    (tmp_path / "a.xml").write_text('<mujoco><include file="../../etc/passwd"/></mujoco>')
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    assert str(tmp_path / "a.xml") in _rows(run.stdout)
    assert "passwd" not in run.stdout


def _usd_folder(folder: Path) -> None:
    """A URDF, and a USD robot in two layers (the root references the physics layer)."""
    (folder / "arm.urdf").write_text(ARM)
    (folder / "payload").mkdir()
    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    (folder / "payload" / "physics.usda").write_text(physics)
    (folder / "robot.usda").write_text(
        '#usda 1.0\n(\n    defaultPrim = "robot"\n)\n'
        'def Xform "robot" (\n    references = @./payload/physics.usda@</robot>\n)\n{\n}\n'
    )


def test_a_usd_robot_in_a_folder_and_the_layers_it_composes(tmp_path: Path) -> None:
    """A USD stage is a robot file; a layer another one composes is left to it."""
    _usd_folder(tmp_path)
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    rows = _rows(run.stdout)
    assert run.code == 0, run.stdout + run.stderr
    assert rows == {str(tmp_path / "arm.urdf"): "ok", str(tmp_path / "robot.usda"): "ok"}
    assert f"left to the files that include them: {tmp_path / 'payload' / 'physics.usda'}" in (
        run.stderr
    )


def test_only_what_a_usd_layer_composes_is_left_to_it(tmp_path: Path) -> None:
    """An asset path in a comment or in metadata composes nothing; a layer that composes
    itself, or two that compose each other, are read (their reader says what is wrong);
    a binary (crate) layer's sublayers are read by OpenUSD, in a confined child."""
    from pxr import Sdf

    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    (tmp_path / "arm.urdf").write_text(ARM)
    (tmp_path / "hand.usda").write_text(physics)
    (tmp_path / "note.usda").write_text(
        physics.replace(
            "(\n",
            "(\n    customLayerData = {\n        asset source = @arm.urdf@\n"
            "    }\n    # formerly referenced @hand.usda@\n",
            1,
        )
    )
    (tmp_path / "self.usda").write_text(
        physics.replace("(\n", "(\n    subLayers = [@./self.usda@]\n", 1)
    )
    for one, other in (("a", "b"), ("b", "a")):
        (tmp_path / f"{one}.usda").write_text(
            physics.replace("(\n", f"(\n    subLayers = [@./{other}.usda@]\n", 1)
        )
    (tmp_path / "crate").mkdir()
    (tmp_path / "crate" / "physics.usda").write_text(physics)
    root = Sdf.Layer.CreateNew(str(tmp_path / "crate" / "robot.usd"))  # a crate file
    root.subLayerPaths.append("./physics.usda")
    root.Save()
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    rows = _rows(run.stdout)
    expected = ["a.usda", "arm.urdf", "b.usda", "crate/robot.usd", "hand.usda", "note.usda"]
    expected.append("self.usda")
    assert sorted(str(Path(p).relative_to(tmp_path)) for p in rows) == expected, run.stderr
    assert f"{tmp_path / 'crate' / 'physics.usda'}" in run.stderr  # left to robot.usd


def test_usd_layers_named_relatively_and_beyond_openusds_bounds(tmp_path: Path) -> None:
    """A folder named relatively finds what its crate layer composes as an absolute one
    does; a layer whose arcs OpenUSD cannot list within its bounds is read on its own,
    and a note says so."""
    from pxr import Sdf

    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    (tmp_path / "crate").mkdir()
    (tmp_path / "crate" / "physics.usda").write_text(physics)
    root = Sdf.Layer.CreateNew(str(tmp_path / "crate" / "robot.usd"))
    root.subLayerPaths.append("./physics.usda")
    root.Save()
    run = run_cli("inspect", ".", "--width", "400", cwd=tmp_path / "crate")
    assert list(_rows(run.stdout)) == ["robot.usd"], run.stdout + run.stderr
    flood = Sdf.Layer.CreateNew(str(tmp_path / "flood.usd"))  # 18 MB of arcs to list
    flood.subLayerPaths = [f"./{i:04d}{'x' * 4000}.usda" for i in range(4500)]
    flood.Save()
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    said = "OpenUSD could not list what these USD layers compose (beyond its bounds), so "
    assert f"{said}each is read as a robot: {tmp_path / 'flood.usd'}\n" in run.stderr
    assert str(tmp_path / "crate" / "physics.usda") not in _rows(run.stdout)  # its batch retried
    assert "Traceback" not in run.stderr
