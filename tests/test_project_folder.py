"""A package read whole, still safely: includes may reach the robot file's project.

The folders a robot file's includes and links may reach without flags are its
project's: the nearest folder above it holding ``.git``, ``.hg`` or a ROS
``package.xml``, or the top of the Python package it lies in (as metaworld's files
include ``../objects/...``). Never the file system's root, the home folder or above
it; a link or an include still never leaves the project; the report says when a file
came from beyond the robot file's own folder.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from conftest import run_cli

ARM = (
    '<mujoco model="arm"><worldbody><body name="upper"><joint name="shoulder" '
    'range="-1 1"/><geom size="0.1"/></body></worldbody></mujoco>'
)
SCENE = '<mujoco model="scene"><include file="../assets/arm.xml"/></mujoco>'


def _project(root: Path, marker: str) -> Path:
    """``root/proj`` marked by ``marker``, with scenes/scene.xml including ../assets."""
    project = root / "proj"
    (project / "scenes").mkdir(parents=True)
    (project / "assets").mkdir()
    (project / "assets" / "arm.xml").write_text(ARM)
    (project / "scenes" / "scene.xml").write_text(SCENE)
    if marker == ".git":
        (project / ".git").mkdir()
    elif marker == "package.xml":
        (project / "package.xml").write_text("<package><name>proj</name></package>")
    elif marker == "__init__.py":  # a Python package: every folder on the way holds one
        for folder in (project, project / "scenes", project / "assets"):
            (folder / "__init__.py").write_text("")
    return project


@pytest.mark.parametrize("marker", [".git", "package.xml", "__init__.py"])
def test_a_project_is_read_whole_and_the_report_says_from_where(
    marker: str, tmp_path: Path
) -> None:
    project = _project(tmp_path, marker)
    run = run_cli("inspect", "scenes/scene.xml", "--format", "json", cwd=project)
    assert run.code == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["manifold"]["notation"] == "R^1"
    (said,) = [d for d in report["diagnostics"] if d["code"] == "read-beyond-folder"]
    assert "'../assets/arm.xml'" in said["message"] and str(project) in said["message"]


def test_without_a_project_only_the_files_folder_is_read(tmp_path: Path) -> None:
    project = _project(tmp_path, "none")
    run = run_cli("inspect", "scenes/scene.xml", cwd=project)
    assert run.code == 2 and "[outside-tree]" in run.stderr
    assert run_cli("inspect", "scenes/scene.xml", "--allow-dir", "assets", cwd=project).code == 0


def test_an_include_never_leaves_the_project(tmp_path: Path) -> None:
    project = _project(tmp_path, ".git")
    (tmp_path / "secret.xml").write_text(ARM)
    for name in ("../../secret.xml", str(tmp_path / "secret.xml"), "/etc/passwd"):
        (project / "scenes" / "scene.xml").write_text(
            f'<mujoco model="scene"><include file="{name}"/></mujoco>'
        )
        run = run_cli("inspect", "scenes/scene.xml", cwd=project)
        assert run.code == 2 and "[outside-tree]" in run.stderr, (name, run.stderr)
        assert "shoulder" not in run.stderr + run.stdout


def test_a_link_in_the_project_never_leads_out_of_it(tmp_path: Path) -> None:
    project = _project(tmp_path, ".git")
    (tmp_path / "secret.xml").write_text(ARM)
    (project / "assets" / "arm.xml").unlink()
    (project / "assets" / "arm.xml").symlink_to(tmp_path / "secret.xml")
    run = run_cli("inspect", "scenes/scene.xml", cwd=project)
    assert run.code == 2 and "[outside-tree]" in run.stderr


def test_the_home_folder_is_never_a_project(tmp_path: Path) -> None:
    # a dotfiles repository makes the home folder a .git root: it must not open all of it
    home = tmp_path / "home"
    _project(home, "none")
    (home / ".git").mkdir()
    run = run_cli("inspect", "proj/scenes/scene.xml", cwd=home, env={"HOME": str(home)})
    assert run.code == 2 and "[outside-tree]" in run.stderr
    # nor a folder above the home folder
    (home / ".git").rmdir()
    (tmp_path / ".git").mkdir()
    run = run_cli("inspect", "proj/scenes/scene.xml", cwd=home, env={"HOME": str(home)})
    assert run.code == 2 and "[outside-tree]" in run.stderr


def test_the_nearest_project_is_the_one(tmp_path: Path) -> None:
    # a ROS package inside a repository: the package's folder, not the repository's
    (tmp_path / ".git").mkdir()
    project = _project(tmp_path / "src", "package.xml")
    (tmp_path / "outside.xml").write_text(ARM)
    (project / "scenes" / "scene.xml").write_text(
        '<mujoco model="scene"><include file="../../../outside.xml"/></mujoco>'
    )
    run = run_cli("inspect", "scenes/scene.xml", cwd=project)
    assert run.code == 2 and "[outside-tree]" in run.stderr
    assert str(project) in run.stderr


def test_nothing_in_a_version_control_folder_is_read(tmp_path: Path) -> None:
    project = _project(tmp_path, ".git")
    (project / ".git" / "config.xml").write_text(ARM)  # XML, so it would parse
    (project / "scenes" / "scene.xml").write_text(
        '<mujoco model="scene"><include file="../.git/config.xml"/></mujoco>'
    )
    run = run_cli("inspect", "scenes/scene.xml", cwd=project)
    assert run.code == 2 and "[outside-tree]" in run.stderr and "shoulder" not in run.stderr


def test_a_package_chain_stops_at_a_project_marker(tmp_path: Path) -> None:
    # a submodule (its own .git) inside a Python package: the submodule is the project
    outer = tmp_path / "outer"
    project = _project(outer, "__init__.py")  # outer/proj/{scenes,assets}, each a package
    (outer / "__init__.py").write_text("")
    (project / ".git").mkdir()
    (outer / "secret.xml").write_text(ARM)
    (project / "scenes" / "scene.xml").write_text(
        '<mujoco model="scene"><include file="../../secret.xml"/></mujoco>'
    )
    run = run_cli("inspect", "scenes/scene.xml", cwd=project)
    assert run.code == 2 and "[outside-tree]" in run.stderr


def test_links_are_not_widened_to_the_project(tmp_path: Path) -> None:
    # a robot file (or any input) that is a link still leads only into its own folder
    project = _project(tmp_path, ".git")
    (project / "scenes" / "arm.xml").symlink_to(project / "assets" / "arm.xml")
    run = run_cli("inspect", "scenes/arm.xml", cwd=project)
    assert run.code == 2 and "[outside-tree]" in run.stderr
