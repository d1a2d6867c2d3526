"""A link in a folder's search, or among the names CI gives, that leads out of its folder.

cspace never reads through such a link. When it leads to a robot description inside
the tree being checked (the folder searched; for a list of names, the current folder and
the names' folders), the link has no report (exit 2), whatever its name: a robot
committed where the search does not look (``.store/arm.xml``, hidden) behind
``robots/arm.xml -> ../.store/arm.xml`` fails CI. A link to a file that is no robot
description, or to a file outside the tree or in ``.git``, is named in a note, and
nothing outside the tree is opened.
"""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

from test_discover import ARM, BROKEN_MJCF, listed_by_git
from test_discover import CI_OPTIONS as OPTIONS

from conftest import OpenWatch, run_cli
from conftest import summary_rows as _rows

ROBOTS = {"robots/arm.xml": "no report", "robots/stage.dat": "no report", "robots/good.urdf": "ok"}
"""The rows of the links' folder: the two links to robots in the tree, and a robot."""
NOTED = ["chain.xml", "far.xml", "part.xml", "table.csv", "vcs.xml"]
"""The links out of ``robots/`` that only a note names (their targets are no robot in
the tree: outside it, in ``.git``, a fragment, a table)."""


def _checkout(tmp_path: Path) -> Path:
    """A checkout whose ``robots/`` holds links to files out of their folder."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret.xml").write_text(BROKEN_MJCF)
    root = tmp_path / "checkout"
    store = root / ".store"  # hidden: the search does not list it
    store.mkdir(parents=True)
    (store / "arm.xml").write_text(BROKEN_MJCF)
    (store / "stage.usda").write_text('#usda 1.0\n(\n    defaultPrim = "robot"\n)\n')
    (store / "part.xml").write_text('<mujocoinclude><geom size="1"/></mujocoinclude>')
    (store / "table.csv").write_text("t,q\n0,1\n")
    (store / "hop.xml").symlink_to("../../outside/secret.xml")
    robots = root / "robots"
    robots.mkdir()
    (robots / "good.urdf").write_text(ARM)
    (robots / "arm.xml").symlink_to("../.store/arm.xml")
    (robots / "stage.dat").symlink_to("../.store/stage.usda")  # a USD layer, by its bytes
    (robots / "part.xml").symlink_to("../.store/part.xml")
    (robots / "table.csv").symlink_to("../.store/table.csv")
    (robots / "chain.xml").symlink_to("../.store/hop.xml")  # in the tree, then out of it
    (robots / "far.xml").symlink_to("../../outside/secret.xml")
    (robots / "vcs.xml").symlink_to("../.git/hidden/arm.xml")
    subprocess.run(["git", "init", "-q"], cwd=root, check=True)
    subprocess.run(["git", "add", "."], cwd=root, check=True)
    (root / ".git" / "hidden").mkdir()
    (root / ".git" / "hidden" / "arm.xml").write_text(BROKEN_MJCF)
    return root


def _noted(stderr: str) -> list[str]:
    """The file names of the links out of ``robots/`` that a note names."""
    said = "cspace: note: links that lead out of their folder, not read (name the file they "
    said += "lead to, if it is a robot file): "
    lines = [line[len(said) :] for line in stderr.splitlines() if line.startswith(said)]
    assert len(lines) == 1, stderr
    named = [os.path.split(name) for name in lines[0].split(", ")]
    return sorted(file for folder, file in named if os.path.basename(folder) == "robots")


def _unopened(root: Path, *folders: Path) -> list[OpenWatch]:
    """Watches on the folders outside the tree: ``outside``, and one in ``.git``."""
    watched = (root.parent / "outside", root / ".git" / "hidden", *folders)
    return [OpenWatch(folder) for folder in watched]


def _opened(watches: list[OpenWatch]) -> list[str]:
    try:
        return [name for watch in watches for name in watch.opened()]
    finally:
        for watch in watches:
            watch.close()


def test_a_link_to_a_robot_in_the_tree_has_no_report(tmp_path: Path) -> None:
    """In a folder's search, in ``git ls-files``'s names and in the names of the links
    alone (a commit that changes only them), and for the folder named by its absolute
    path from elsewhere: the links to robots in the tree fail, the others are noted."""
    root = _checkout(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    names = sorted(f"robots/{p.name}" for p in (root / "robots").iterdir())
    watches = _unopened(root)
    runs = {
        "folder": run_cli(*OPTIONS, ".", cwd=root),
        "listed": listed_by_git(root),
        "links": run_cli(*OPTIONS, *names, cwd=root),
        "absolute": run_cli(*OPTIONS, str(root), cwd=elsewhere),
    }
    assert _opened(watches) == []
    codes = {how: run.code for how, run in runs.items()}
    assert codes == {"folder": 2, "listed": 123, "links": 2, "absolute": 2}, runs
    for how, run in runs.items():
        rows = {
            os.path.relpath(p, root) if how == "absolute" else p: s
            for p, s in _rows(run.stdout).items()
        }
        assert {p: s for p, s in rows.items() if p.startswith("robots/")} == ROBOTS, (how, run)
        for link in ("arm.xml", "stage.dat"):
            shown = str(root / "robots" / link) if how == "absolute" else f"robots/{link}"
            assert (
                f"cspace: error: {shown}: is a link to a file outside its folder; cspace "
                "follows links only within the folder"
            ) in run.stderr, (how, run)
        assert _noted(run.stderr) == NOTED, (how, run)
    listed = _rows(runs["listed"].stdout)  # git names the hidden robot: inspected too
    assert listed[".store/arm.xml"] == "no report", runs["listed"]
    assert ".store/hop.xml" in runs["listed"].stderr  # named, and a link out: noted


def test_a_link_to_a_robot_out_of_the_folder_searched_is_noted_unread(tmp_path: Path) -> None:
    """``cspace inspect robots``: the tree is ``robots/``, so ``.store/arm.xml`` lies
    outside it, and neither it nor anything the links lead to is opened."""
    root = _checkout(tmp_path)
    watches = _unopened(root, root / ".store")
    run = run_cli(*OPTIONS, "robots", cwd=root)
    assert _opened(watches) == []
    assert run.code == 0, run
    assert _rows(run.stdout) == {"robots/good.urdf": "ok"}, run
    assert _noted(run.stderr) == sorted([*NOTED, "arm.xml", "stage.dat"]), run


def test_a_folder_named_beside_the_names_is_in_their_tree(tmp_path: Path) -> None:
    """``cspace inspect --robots-only FOLDER NAME`` from another folder: a link among the
    names that leads into the folder named (here ``.store``, to a broken robot) leads
    into the tree checked, so it has no report."""
    root = _checkout(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    run = run_cli(*OPTIONS, str(root / ".store"), str(root / "robots" / "arm.xml"), cwd=elsewhere)
    rows = _rows(run.stdout)
    assert run.code == 2 and rows[str(root / "robots" / "arm.xml")] == "no report", run
