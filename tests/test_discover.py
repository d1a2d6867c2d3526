"""Robot descriptions found by what they are: folders searched, fragments left to their models.

A folder argument stands for the robot files in it; an MJCF ``<mujocoinclude>`` file,
and a file another one includes (MJCF ``<include>``/``<model>``, ``<xacro:include>``), is
checked as part of what includes it, never refused on its own.
"""

from __future__ import annotations

import importlib.util
import os
import shlex
import subprocess
from pathlib import Path

import pytest
import served_cli

from conftest import REPO, OpenWatch, Run, run_cli
from conftest import summary_rows as _rows

ARM = (
    '<robot name="a"><link name="b"/><link name="c"/><joint name="j" type="revolute">'
    '<parent link="b"/><child link="c"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
    "</joint></robot>"
)


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


@pytest.mark.bounded
def test_finding_the_root_takes_one_pass() -> None:
    """Comments one after another once took exponential time (a 281-byte file hung):
    20,000 of them cost less than a second of this process's CPU."""
    import time

    from cspace._formats.discovery.search import root_tag

    started = time.process_time()
    assert root_tag(b"<!---->" * 20_000 + b"!") is None
    assert time.process_time() - started < 1.0
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
    the search peeks at regular files of the folder only, and a link out named like a
    robot file is that file's error (``outside-tree``), unread."""
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
    assert run.code == 2, run.stdout + run.stderr
    assert _rows(run.stdout) == {
        str(folder / "arm.urdf"): "ok",
        str(nested / "deep.urdf"): "ok",
        str(folder / "link.urdf"): "no report",
    }
    assert run.stderr == (
        f"cspace: error: {folder / 'link.urdf'}: is a link to a file outside its folder; "
        "cspace follows links only within the folder (name the target, or a wider folder "
        "with --allow-dir) [outside-tree]\n"
    )


def test_a_fragment_cannot_hide_a_file_outside_the_folder(tmp_path: Path) -> None:
    """Includes that lead out of the folder hide nothing and read nothing there."""
    (tmp_path / "a.xml").write_text('<mujoco><include file="../../etc/passwd"/></mujoco>')
    run = run_cli("inspect", str(tmp_path), "--width", "400")
    assert str(tmp_path / "a.xml") in _rows(run.stdout)
    assert "passwd" not in run.stdout


BROKEN_URDF = ARM.replace('lower="-1" upper="1"', 'lower="2" upper="1"')
"""A URDF whose limits are reversed: an error finding (``findings``)."""
BROKEN_MJCF = (
    '<mujoco model="arm"><worldbody><body name="b"><joint name="j" type="hinge" '
    'range="2 1" limited="true"/><geom size="0.1"/></body></worldbody></mujoco>'
)
"""An MJCF model MuJoCo refuses (``range[0] should be smaller``): no report."""
XACRO = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def _as_ci(root: Path) -> list[Run]:
    """The two ways CI inspects a checkout of ``root``: the folder, and git's list of names.

    ``cspace inspect --strict --robots-only -- .`` and ``git ls-files -z | xargs -0
    cspace inspect --strict --robots-only --`` (xargs exits 123 when cspace fails).
    """
    subprocess.run(["git", "init", "-q"], cwd=root, check=True)
    subprocess.run(["git", "add", "."], cwd=root, check=True)
    return [run_cli(*CI_OPTIONS, ".", cwd=root), listed_by_git(root)]


CI_OPTIONS = ("inspect", "--strict", "--robots-only", "--width", "400", "--")
"""How CI inspects robots: strict, only robot descriptions, every name after ``--``."""


def listed_by_git(root: Path) -> Run:
    """``git ls-files -z | xargs -0 cspace inspect CI_OPTIONS``, as a CI script runs it.

    The ``cspace`` xargs starts is forked by the suite's command server (``served_cli``).
    """
    command = shlex.join([str(served_cli.script()), *CI_OPTIONS])
    listed = subprocess.run(
        ["bash", "-o", "pipefail", "-c", f"git ls-files -z | xargs -0 {command}"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "NO_COLOR": "1"},
        check=False,
    )
    return Run(listed.returncode, listed.stdout, listed.stderr)


def test_a_fragment_that_nothing_inspected_includes_hides_nothing(tmp_path: Path) -> None:
    """A file is a fragment only when an inspected file includes it, directly or through
    fragments: a ``<mujocoinclude>`` that nothing includes, or a macro library whose
    includes stand in a macro never called (``$(find anything)/arm.urdf`` once made every
    ``*/arm.urdf`` a fragment), hides nothing. MuJoCo reads an include from the folder of
    the model it compiles: ``sub/parts.xml``'s ``arm.xml`` is ``mjcf/arm.xml``, so the
    broken ``mjcf/sub/arm.xml`` beside it is inspected."""
    robots = tmp_path / "robots"
    robots.mkdir()
    (robots / "good.urdf").write_text(ARM)
    (robots / "parts.xml").write_text('<mujocoinclude><include file="arm.xml"/></mujocoinclude>')
    (robots / "arm.xml").write_text(BROKEN_MJCF)
    (robots / "arm.urdf").write_text(BROKEN_URDF)
    (robots / "notes.xacro").write_text(
        f'<robot {XACRO}><xacro:macro name="never_called">'
        '<xacro:include filename="$(find anything)/arm.urdf"/>'
        '<xacro:include filename="$(find anything)/arm.xml"/></xacro:macro></robot>'
    )
    mjcf = tmp_path / "mjcf"
    (mjcf / "sub").mkdir(parents=True)
    (mjcf / "scene.xml").write_text('<mujoco model="s"><include file="sub/parts.xml"/></mujoco>')
    (mjcf / "sub" / "parts.xml").write_text(
        '<mujocoinclude><include file="arm.xml"/></mujocoinclude>'
    )
    (mjcf / "arm.xml").write_text(
        '<mujoco><worldbody><body name="a"><joint name="x" type="hinge"/><geom size="0.1"/>'
        "</body></worldbody></mujoco>"
    )
    (mjcf / "sub" / "arm.xml").write_text(BROKEN_MJCF)
    folder, listed = _as_ci(tmp_path)
    assert (folder.code, listed.code) == (2, 123), folder.stderr + listed.stderr
    for run in (folder, listed):
        assert _rows(run.stdout) == {
            "mjcf/arm.xml": "ok",  # compiled alone too: what a fragment elsewhere names
            "mjcf/scene.xml": "ok",
            "mjcf/sub/arm.xml": "no report",
            "robots/arm.urdf": "findings",
            "robots/arm.xml": "no report",
            "robots/good.urdf": "ok",
        }, run.stdout + run.stderr
        for path in ("mjcf/sub/arm.xml", "robots/arm.xml"):
            assert f"cspace: error: {path}:1: MuJoCo refuses the model: " in run.stderr
        assert "robots/notes.xacro" in run.stderr and "robots/parts.xml" in run.stderr  # left


def test_a_xacro_file_is_left_out_only_when_surely_included_or_a_library(tmp_path: Path) -> None:
    """Only a ``<xacro:include>`` xacro surely follows makes a fragment: a child of the
    root of an inspected ``.xacro`` file (not in a macro never called, whose parameter
    ``x:=/>`` ends no tag, not under ``<xacro:if>``, not in a ``<gazebo>`` the URDF
    reader skips, with the robot it would splice in), of a ``.xacro`` file (a ``.urdf`` is
    a robot by its name), and ``$(find PKG)`` names the including file's own package,
    not any file whose path ends alike. A library holds no robot of its own: one that
    calls a macro at its top level and names itself with ``<xacro:attribute>`` is a
    robot."""
    pkg = tmp_path / "pkg"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text('<package format="3"><name>demo</name></package>')
    (pkg / "urdf" / "robot.urdf.xacro").write_text(
        f'<robot name="r" {XACRO}>'
        '<xacro:include filename="$(find demo)/urdf/macros.xacro"/>'
        '<xacro:if value="false"><xacro:include filename="cond.xacro"/></xacro:if>'
        '<gazebo><xacro:include filename="in_gazebo.xacro"/></gazebo>'  # the URDF skips it
        '<xacro:include filename="m&#97;cros.xacro"/>'  # macros.xacro, once more
        '<xacro:macro name="unused" params="x:=/>"><xacro:include filename="in_macro.xacro"/>'
        "</xacro:macro><xacro:arm/></robot>"
    )
    body = ARM[ARM.index("<link") : ARM.index("</robot>")]
    (pkg / "urdf" / "macros.xacro").write_text(  # the library includes a URDF, empty
        f'<robot {XACRO}><xacro:include filename="plain.urdf"/>'
        f'<xacro:macro name="arm">{body}</xacro:macro></robot>'
    )
    (pkg / "urdf" / "plain.urdf").write_text('<robot name="p"/>')  # no links: no report
    broken = BROKEN_URDF.replace("<robot ", f"<robot {XACRO} ")
    for name in ("cond.xacro", "in_macro.xacro", "in_gazebo.xacro", "m&#97;cros.xacro"):
        (pkg / "urdf" / name).write_text(broken)
    (tmp_path / "other" / "urdf").mkdir(parents=True)
    (tmp_path / "other" / "urdf" / "macros.xacro").write_text(broken)
    wrong = BROKEN_URDF[BROKEN_URDF.index("<link") : BROKEN_URDF.index("</robot>")]
    (pkg / "urdf" / "disguised.xacro").write_text(
        f'<robot {XACRO}><xacro:attribute name="name" value="arm"/>'
        f'<xacro:macro name="body">{wrong}</xacro:macro><xacro:body/></robot>'
    )
    folder, listed = _as_ci(tmp_path)
    assert (folder.code, listed.code) == (2, 123), folder.stderr + listed.stderr
    for run in (folder, listed):
        assert _rows(run.stdout) == {
            "other/urdf/macros.xacro": "findings",
            "pkg/urdf/cond.xacro": "findings",
            "pkg/urdf/disguised.xacro": "findings",
            "pkg/urdf/in_gazebo.xacro": "findings",
            "pkg/urdf/in_macro.xacro": "findings",
            "pkg/urdf/m&#97;cros.xacro": "findings",  # the name as written, not xacro's
            "pkg/urdf/plain.urdf": "no report",  # a URDF by its name, whoever includes it
            "pkg/urdf/robot.urdf.xacro": "ok",
        }, run.stdout + run.stderr
        assert "left to the files that include them: pkg/urdf/macros.xacro\n" in (
            run.stderr.replace("./", "")
        )


def test_a_long_prolog_hides_no_root(tmp_path: Path) -> None:
    """MuJoCo reads a ``<mujoco>`` after any amount of comment or white space, or after a
    document type with an internal subset: the search reads on as far as the prolog goes
    (past the first 64 KiB; a root's name cut where a read ends is read whole)."""
    from cspace._formats.discovery.search import PEEK_BYTES

    (tmp_path / "comment.xml").write_text(f"<!--{'x' * 70_000}-->\n{BROKEN_MJCF}")
    (tmp_path / "space.xml").write_text(" " * 70_000 + BROKEN_MJCF)
    comment = b"<!--" + b"x" * (PEEK_BYTES - 11) + b"-->"
    (tmp_path / "cut.xml").write_bytes(comment + BROKEN_MJCF.encode())  # <muj|oco at 64 KiB
    assert (tmp_path / "cut.xml").read_bytes()[PEEK_BYTES - 4 : PEEK_BYTES] == b"<muj"
    (tmp_path / "doctype.xml").write_text(f"<!DOCTYPE mujoco [<!ELEMENT a ANY>]>{BROKEN_MJCF}")
    (tmp_path / "good.urdf").write_text(ARM)
    folder, listed = _as_ci(tmp_path)
    assert (folder.code, listed.code) == (2, 123), folder.stderr + listed.stderr
    for run in (folder, listed):
        rows = _rows(run.stdout)
        assert rows == {
            "comment.xml": "no report",
            "cut.xml": "no report",
            "doctype.xml": "no report",
            "good.urdf": "ok",
            "space.xml": "no report",
        }, run.stdout + run.stderr


def test_a_link_in_a_folder_is_inspected_as_when_it_is_named(tmp_path: Path) -> None:
    """A link to a file in its folder is read as that file (a hidden one too, which the
    search would not list); a link out of its folder is never read: named like a robot
    file, it is that file's error (``outside-tree``); otherwise a note names it."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.urdf").write_text(ARM)
    (outside / "secret.xml").write_text(BROKEN_MJCF)
    root = tmp_path / "checkout"
    (root / "robots").mkdir(parents=True)
    (root / "robots" / ".arm.dat").write_text(BROKEN_URDF)
    (root / "robots" / "arm.urdf").symlink_to(".arm.dat")
    (root / "robots" / "model.xml").symlink_to(".arm.dat")  # an .xml inside: read as the file
    (root / "robots" / "out.urdf").symlink_to(outside / "secret.urdf")
    (root / "robots" / "out.xml").symlink_to("../../outside/secret.xml")
    (root / "good.urdf").write_text(ARM)
    watch = OpenWatch(outside)
    try:
        folder, listed = _as_ci(root)
        assert watch.opened() == []
    finally:
        watch.close()
    assert (folder.code, listed.code) == (2, 123), folder.stderr + listed.stderr
    for run in (folder, listed):
        rows = _rows(run.stdout)
        hidden = rows.pop("robots/.arm.dat", None)  # git lists it: named, it is inspected
        assert hidden in (None, "findings") and (run is listed) == (hidden is not None)
        assert rows == {
            "good.urdf": "ok",
            "robots/arm.urdf": "findings",
            "robots/model.xml": "findings",
            "robots/out.urdf": "no report",
        }, run.stdout + run.stderr
        assert "cspace: error: robots/out.urdf: is a link to a file outside its folder" in (
            run.stderr
        )
        assert (
            "cspace: note: links that lead out of their folder, not read (name the file they "
            "lead to, if it is a robot file): "
        ) in run.stderr
        assert "robots/out.xml\n" in run.stderr


def _parts() -> str:
    """A USD robot's layer of parts: its prims under ``over "robot"``, which another
    layer defines (as Isaac's physics layers are), so it is no robot on its own."""
    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    return physics.replace('def Xform "robot"', 'over "robot"', 1)


def _crate_root(path: Path, sublayer: str) -> None:
    """A binary (crate) USD layer that defines ``/robot`` and sublayers ``sublayer``."""
    from pxr import Sdf

    root = Sdf.Layer.CreateNew(str(path))
    root.subLayerPaths.append(sublayer)
    Sdf.PrimSpec(root.pseudoRoot, "robot", Sdf.SpecifierDef, "Xform")
    root.Save()


def _usd_folder(folder: Path) -> None:
    """A URDF, and a USD robot in two layers (the root references the physics layer)."""
    (folder / "arm.urdf").write_text(ARM)
    (folder / "payload").mkdir()
    (folder / "payload" / "physics.usda").write_text(_parts())
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
    (tmp_path / "crate" / "physics.usda").write_text(_parts())
    _crate_root(tmp_path / "crate" / "robot.usd", "./physics.usda")
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

    (tmp_path / "crate").mkdir()
    (tmp_path / "crate" / "physics.usda").write_text(_parts())
    _crate_root(tmp_path / "crate" / "robot.usd", "./physics.usda")
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


def _variants(name: str, selected: str, arcs: dict[str, str], more: str = "") -> str:
    """A layer whose prim ``name`` has a variant set ``v``, ``selected`` chosen: each
    variant of ``arcs`` holds its arc (``""``: none)."""
    variants = "".join(
        f'        "{v}" (\n            {arc}\n        ) {{\n        }}\n'
        if arc
        else f'        "{v}" {{\n        }}\n'
        for v, arc in arcs.items()
    )
    return (
        f'#usda 1.0\n(\n    defaultPrim = "{name}"\n)\ndef Xform "{name}" (\n{more}'
        f'    variants = {{\n        string v = "{selected}"\n    }}\n'
        f'    prepend variantSets = "v"\n)\n{{\n    variantSet "v" = {{\n{variants}    }}\n}}\n'
    )


def test_a_usd_layer_that_is_a_robot_on_its_own_is_read(tmp_path: Path) -> None:
    """A layer another one composes is left to it only when it is no robot on its own: a
    robot named only by a variant nobody selects, or by one its layer selects but the
    root that uses that layer overrides, is read (and fails here, its metersPerUnit 0),
    and so is the layer that selects it (a robot through it), in a folder walk and in a
    pull request's names (--robots-only -- NAMES); an Isaac-style interface's layers
    (parts under an ``over``, overs only) are left to it."""
    (tmp_path / "arm.urdf").write_text(ARM)
    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    broken = physics.replace("metersPerUnit = 1", "metersPerUnit = 0")
    (tmp_path / "robot.usda").write_text(broken)
    refer = "prepend references = @./robot.usda@"
    (tmp_path / "hide.usda").write_text(_variants("thing", "none", {"none": "", "never": refer}))
    (tmp_path / "nest").mkdir()
    (tmp_path / "nest" / "hidden.usda").write_text(broken)
    (tmp_path / "nest" / "mid.usda").write_text(
        _variants("robot", "a", {"a": "prepend payload = @./hidden.usda@", "b": ""})
    )
    (tmp_path / "nest" / "root.usda").write_text(
        '#usda 1.0\n(\n    defaultPrim = "robot"\n)\ndef Xform "robot" (\n'
        '    references = @./mid.usda@\n    variants = {\n        string v = "b"\n    }\n)\n'
        '{\n    def Xform "base" (prepend apiSchemas = ["PhysicsRigidBodyAPI"])\n    {\n'
        "    }\n}\n"
    )
    (tmp_path / "isaac").mkdir()
    (tmp_path / "isaac" / "base.usda").write_text(_parts())
    (tmp_path / "isaac" / "physx.usda").write_text(
        '#usda 1.0\n(\n    defaultPrim = "robot"\n)\nover "robot"\n{\n}\n'
    )
    (tmp_path / "isaac" / "interface.usda").write_text(
        _variants(
            "robot",
            "physx",
            {"none": "", "physx": "prepend payload = @./physx.usda@"},
            "    prepend references = @./base.usda@\n",
        )
    )
    names = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    for args in ((".",), ("--", *names)):
        run = run_cli("inspect", "--robots-only", "--width", "400", *args, cwd=tmp_path)
        rows = _rows(run.stdout)
        assert run.code == 2, run.stdout + run.stderr
        for hidden in ("robot.usda", "nest/hidden.usda"):
            assert rows[hidden] == "no report", run.stdout + run.stderr
            assert f"{hidden}: metersPerUnit is 0: lengths cannot be read" in run.stderr
        ok = {"arm.urdf", "hide.usda", "nest/root.usda", "nest/mid.usda", "isaac/interface.usda"}
        assert {r for r, status in rows.items() if status == "ok"} == ok
        assert set(rows) == {*ok, "robot.usda", "nest/hidden.usda"}
        for left in ("isaac/base.usda", "isaac/physx.usda"):
            assert left in run.stderr  # left to the root that uses it


def test_a_linked_folder_is_not_searched_and_said_so(tmp_path: Path) -> None:
    """A folder's search enters no linked folder (a link may lead anywhere, or in a
    circle), and a note names each it did not enter: nothing is skipped silently."""
    (tmp_path / "robots").mkdir()
    (tmp_path / ".store").mkdir()
    (tmp_path / ".store" / "arm.urdf").write_text((REPO / "robots" / "arm7.urdf").read_text())
    (tmp_path / "robots" / "arm").symlink_to("../.store")
    (tmp_path / "robots" / "loop").symlink_to(".")
    (tmp_path / "robots" / "ok.urdf").write_text((REPO / "robots" / "arm7.urdf").read_text())
    run = run_cli("inspect", "--format", "jsonl", "--", "robots", cwd=tmp_path)
    assert run.code == 0 and run.stdout.count("\n") == 1  # ok.urdf alone
    assert run.stderr == (
        "cspace: note: links to folders, not searched (name the folder they lead to): "
        "robots/arm, robots/loop\n"
    )


def test_a_usd_robot_composed_out_of_sight_is_still_read(tmp_path: Path) -> None:
    """A pull request cannot hide a broken USD robot behind a layer that composes it
    without using it: referenced at another prim (a partial reference), made inactive,
    defined in a variant of a layer referenced at another prim, or a layer of rigid
    bodies (no joint) named by an unselected variant, and with a bare asset path (which
    OpenUSD looks up on its search path, not beside the layer). Each layer that is a
    robot on its own is read (no report: metersPerUnit 0), as the root that hides it."""
    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    broken = physics.replace("metersPerUnit = 1", "metersPerUnit = 0")
    (tmp_path / "robot.usda").write_text(broken)  # defines /robot
    head = '#usda 1.0\n(\n    defaultPrim = "r"\n)\n'
    (tmp_path / "partial.usda").write_text(
        head + 'def Xform "r" (\n    references = @./robot.usda@</elsewhere>\n)\n{\n}\n'
    )
    (tmp_path / "off.usda").write_text(
        head + 'def Xform "r" (\n    active = false\n    references = @./inert.usda@\n)\n{\n}\n'
    )
    (tmp_path / "inert.usda").write_text(broken)
    body = physics.split('def Xform "robot"\n{\n', 1)[1].rsplit("}", 1)[0]
    (tmp_path / "chosen.usda").write_text(
        "#usda 1.0\n(\n    metersPerUnit = 0\n)\n"
        'def Xform "robot" (\n    variants = {\n        string v = "a"\n    }\n'
        '    prepend variantSets = "v"\n)\n{\n    variantSet "v" = {\n        "a" {\n'
        + body
        + "        }\n    }\n}\n"
    )
    (tmp_path / "aside.usda").write_text(
        head + 'def Xform "r" (\n    references = @./chosen.usda@</other>\n)\n{\n}\n'
    )
    (tmp_path / "bodies.usda").write_text(  # rigid bodies, no joint: floating bodies
        broken.replace("PhysicsRevoluteJoint", "PhysicsRevolutJoint")
        .replace("PhysicsPrismaticJoint", "PhysicsPrismatiJoint")
        .replace("PhysicsFixedJoint", "PhysicsFixeJoint")
        .replace('"PhysicsArticulationRootAPI"', '"NoAPI"')
    )
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "bare.usda").write_text(  # OpenUSD's search path: no file here
        _variants("r", "a", {"a": "", "b": "prepend references = @bodies.usda@"})
    )
    names = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*.usda"))
    for args in ((".",), ("--", *names)):
        run = run_cli("inspect", "--robots-only", "--width", "400", *args, cwd=tmp_path)
        rows = _rows(run.stdout)
        assert run.code == 2 and rows == {
            "aside.usda": "ok",  # composes nothing at /r: a point
            "bodies.usda": "no report",
            "sub/bare.usda": "no report",  # refused: OpenUSD's search path is no file
            "chosen.usda": "no report",
            "inert.usda": "no report",
            "off.usda": "no report",
            "partial.usda": "ok",
            "robot.usda": "no report",
        }, run.stdout + run.stderr
        for hidden in ("robot.usda", "inert.usda", "chosen.usda", "bodies.usda"):
            assert f"{hidden}: metersPerUnit is 0: lengths cannot be read" in run.stderr


def test_usd_names_in_upper_case_are_read_as_openusd_reads_them(tmp_path: Path) -> None:
    """OpenUSD tells a layer's format by its extension folded to lower case (ASCII):
    ``ARM.USDA`` and a package ``HAND.USDZ`` are robots, found in a folder and read."""
    from pxr import UsdUtils

    physics = (REPO / "tests" / "usd" / "isaac_order_fixed.usda").read_text()
    (tmp_path / "ARM.USDA").write_text(physics)
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "hand.usda").write_text(physics)
    assert UsdUtils.CreateNewUsdzPackage(
        str(tmp_path / "pkg" / "hand.usda"), str(tmp_path / "HAND.USDZ")
    )
    (tmp_path / "pkg" / "hand.usda").unlink()
    run = run_cli("inspect", "--robots-only", "--width", "400", ".", cwd=tmp_path)
    assert run.code == 0 and _rows(run.stdout) == {"ARM.USDA": "ok", "HAND.USDZ": "ok"}, (
        run.stdout + run.stderr
    )
