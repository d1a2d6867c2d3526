"""MoveIt repositories as they are laid out: an SRDF is its URDF's companion, never a robot.

A folder's search (and the Action's, ``--robots-only``; and ``check --baseline``'s) leaves
SRDF files out, told by content (a ``<robot>`` of groups, states, virtual joints and no
link, joint or xacro call outside them), or by what xacro makes of a ``.srdf.xacro``
file of macro calls, and names each in a note; one whose robot no robot file there is
gets a note of its own. A name never leaves a robot out: a ``.srdf`` file that holds
links is inspected as a URDF. Named as a robot, an SRDF is refused in one line that says
how it is read. ``--srdf auto`` finds a robot's SRDF where MoveIt and example-robot-data
lay it out (beside the URDF, ``../srdf``, ``config/``, a sibling ``*_moveit_config``
package): one naming the robot first, wherever it is, then one naming another robot
only when every link and joint it names is the robot's (a warning then names both), only
inside the folders cspace may read, and says where it looked when it finds none. The
repositories are built in ``tmp_path`` from example-robot-data's own files.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest
from test_action import Runner, _check

from cspace._formats.shared.erd import robots_dir
from cspace._model._srdf_find import MAX_LISTED, MAX_LOOKED

from conftest import OpenWatch, Run, cspace_command, run_cli

SECRET = "TOKEN-ghp-m0ve1t"
"""A group name in an SRDF outside the repository: it must never be read."""

PANDA_ARM_SRDF_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="panda">
  <xacro:include filename="$(find panda_moveit_config)/config/panda_arm.xacro"/>
  <xacro:panda_arm/>
</robot>
"""
"""MoveIt's ``panda_arm.srdf.xacro``: an SRDF that xacro makes, told by xacro's output."""

PANDA_ARM_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="panda">
  <xacro:macro name="panda_arm">
    <group name="panda_arm"><chain base_link="panda_link0" tip_link="panda_link8"/></group>
    <virtual_joint name="virtual_joint" type="fixed" parent_frame="world" child_link="panda_link0"/>
  </xacro:macro>
</robot>
"""
"""MoveIt's ``panda_arm.xacro``: the SRDF macro ``panda_arm.srdf.xacro`` calls."""

HAND_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="panda">
  <xacro:macro name="hand">
    <group name="hand">
      <link name="panda_hand"/>
      <joint name="panda_finger_joint1"/>
      <passive_joint name="panda_finger_joint2"/>
    </group>
    <disable_collisions link1="panda_hand" link2="panda_leftfinger" reason="Adjacent"/>
  </xacro:macro>
</robot>
"""
"""MoveIt's ``hand.xacro``: SRDF macros, an SRDF by its content (its joints are a group's)."""

CONTROL_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="panda_ros2_control">
    <ros2_control name="sim" type="system"><joint name="panda_joint1"/></ros2_control>
  </xacro:macro>
  <group name="not_srdf_alone"/>
</robot>
"""
"""A ``<joint>`` in a ``<ros2_control>`` block is a URDF's: no SRDF, though a group is there."""


def _erd(relative: str) -> Path:
    return robots_dir() / relative


def _moveit_repository(root: Path) -> Path:
    """A MoveIt repository: description and MoveIt configuration packages, and talos laid
    out as example-robot-data lays it out (``robots/`` next to ``srdf/``)."""
    repo = root / "repo"
    files = {
        "panda_description/urdf/panda.urdf": _erd("panda_description/urdf/panda.urdf"),
        "panda_moveit_config/config/panda.srdf": _erd("panda_description/srdf/panda.srdf"),
        "talos_data/robots/talos_reduced.urdf": _erd("talos_data/robots/talos_reduced.urdf"),
        "talos_data/srdf/talos.srdf": _erd("talos_data/srdf/talos.srdf"),
        "fanuc_moveit_config/config/fanuc.srdf": _erd("panda_description/srdf/panda.srdf"),
    }
    for name, source in files.items():
        (repo / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(source, repo / name)
    fanuc = repo / "fanuc_moveit_config/config/fanuc.srdf"
    fanuc.write_text(fanuc.read_text().replace('<robot name="panda"', '<robot name="fanuc"'))
    config = repo / "panda_moveit_config/config"
    (config / "panda_arm.srdf.xacro").write_text(PANDA_ARM_SRDF_XACRO)
    (config / "panda_arm.xacro").write_text(PANDA_ARM_XACRO)
    (config / "hand.xacro").write_text(HAND_XACRO)
    (config / "panda.ros2_control.xacro").write_text(CONTROL_XACRO)
    (repo / "panda_description/srdf").mkdir()
    (repo / "panda_description/srdf/robot.xml").write_text(  # an SRDF by its content only
        (config / "panda.srdf").read_text()
    )
    for package in ("panda_description", "panda_moveit_config", "fanuc_moveit_config"):
        (repo / package / "package.xml").write_text(f"<package><name>{package}</name></package>")
    subprocess.run(["git", "init", "-q"], cwd=repo, check=True)
    subprocess.run(["git", "add", "."], cwd=repo, check=True)
    return repo


@pytest.fixture(scope="module")
def repo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _moveit_repository(tmp_path_factory.mktemp("moveit"))


ROBOTS = ["panda_description/urdf/panda.urdf", "talos_data/robots/talos_reduced.urdf"]
SRDF = [
    "fanuc_moveit_config/config/fanuc.srdf",
    "panda_description/srdf/robot.xml",
    "panda_moveit_config/config/hand.xacro",
    "panda_moveit_config/config/panda.srdf",
    "panda_moveit_config/config/panda_arm.xacro",
    "talos_data/srdf/talos.srdf",  # HPP's <gripper> holds a <link>: an SRDF element's
]
"""The SRDF files the search is sure of, by their content."""

XACRO_SRDF = "panda_moveit_config/config/panda_arm.srdf.xacro"
"""An SRDF by what xacro makes of it: inspected by the search, a note by its reader."""


def test_the_action_passes_a_moveit_repository(repo: Path, tmp_path: Path) -> None:
    """The Action's own check step (``--robots-only``, annotations, a baseline) on it."""
    baseline = run_cli("inspect", "--format", "jsonl", ".", cwd=repo)
    assert baseline.code == 0, baseline.stderr
    assert len(baseline.stdout.splitlines()) == 2
    (repo / "cspace-baseline.jsonl").write_text(baseline.stdout)
    runner = Runner(tmp_path, Path(__file__).resolve().parent.parent)
    runner.files["GITHUB_PATH"].write_text(str(Path(cspace_command()[0]).parent) + "\n")
    done = _check(runner, repo, baseline="cspace-baseline.jsonl", html="")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "no-links" not in done.stdout + done.stderr
    annotated = sorted(
        line.split(",")[0].removeprefix("::notice file=")
        for line in done.stdout.splitlines()
        if ",title=cspace::C = " in line
    )
    assert annotated == ROBOTS, done.stdout
    assert not [line for line in done.stdout.splitlines() if line.startswith("::error")]
    said = [line for line in done.stderr.splitlines() if "SRDF files, read with" in line]
    assert said and all(s in said[0] for s in SRDF), done.stderr  # inspect's and check's
    assert "panda.ros2_control.xacro" not in said[0]  # a fragment, not an SRDF
    expanded = [line for line in done.stderr.splitlines() if XACRO_SRDF in line]
    assert expanded and all(line.startswith("cspace: note: ") for line in expanded)
    assert all(line.endswith("[srdf-not-robot]") for line in expanded), done.stderr
    summary = runner.files["GITHUB_STEP_SUMMARY"].read_text()
    assert "srdf" not in summary.lower() and summary.count("| same |") == 2, summary


def test_a_folder_names_each_srdf_and_those_of_no_robot_there(repo: Path) -> None:
    """``inspect DIR``, ``--robots-only`` with every file named (the hook's way): the
    SRDF files are notes, never rows; an SRDF whose robot no URDF here is gets a note."""
    folder = run_cli("inspect", "--format", "jsonl", "--", ".", cwd=repo)
    assert folder.code == 0, folder.stderr
    rows = [json.loads(line)["source"]["path"] for line in folder.stdout.splitlines()]
    assert sorted(rows) == ROBOTS
    unpaired = [line for line in folder.stderr.splitlines() if "whose robot no robot" in line]
    assert len(unpaired) == 1 and "fanuc.srdf (robot 'fanuc')" in unpaired[0], folder.stderr
    assert "talos.srdf" not in unpaired[0] and "panda.srdf" not in unpaired[0]
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=repo, capture_output=True, check=True)
    files = [name.decode() for name in listed.stdout.split(b"\0") if name]  # as the hook has
    named = run_cli("inspect", "--robots-only", "--format", "jsonl", "--", *files, cwd=repo)
    assert named.code == 0, named.stderr
    assert sorted(json.loads(x)["source"]["path"] for x in named.stdout.splitlines()) == ROBOTS
    assert all(s in named.stderr for s in SRDF)
    note = f"cspace: note: {XACRO_SRDF}:2: an SRDF (MoveIt's semantic description of robot "
    assert note in named.stderr and note in folder.stderr  # xacro's output tells it
    hook = ("inspect", "--strict", "--robots-only", "--", XACRO_SRDF)  # one file, as the hook
    alone_xacro = run_cli(*hook, cwd=repo)
    assert alone_xacro.code == 0 and alone_xacro.stdout == "", alone_xacro.stderr
    assert alone_xacro.stderr.startswith(note), alone_xacro.stderr
    alone = run_cli("inspect", "--", "panda_moveit_config", cwd=repo)  # a config package
    assert alone.code == 0 and "panda.srdf" in alone.stderr, alone.stdout + alone.stderr


def test_an_srdf_named_as_a_robot_is_refused_in_one_line(repo: Path) -> None:
    """By content (``panda.srdf``, ``hand.xacro``, an ``.xml``) or by what xacro makes
    of it (``.srdf.xacro``): one line each, at the file, saying how an SRDF is read,
    exit 2; never ``no-links``."""
    one = run_cli("inspect", "--", SRDF[3], cwd=repo)
    assert one.code == 2 and one.stdout == "" and one.stderr.count("\n") == 1, one.stderr
    assert one.stderr == (
        f"cspace: error: {SRDF[3]}:2: an SRDF (MoveIt's semantic description of robot "
        f"'panda'), not a robot: read it with its URDF: cspace inspect ROBOT.urdf --srdf "
        f"{SRDF[3]} (or --srdf auto) [srdf-not-robot]\n"
    )
    others = [SRDF[1], SRDF[2], XACRO_SRDF]
    many = run_cli("inspect", "--format", "jsonl", "--", *others, cwd=repo)
    assert many.code == 2 and many.stdout == ""
    errors = [line for line in many.stderr.splitlines() if line.startswith("cspace: error:")]
    assert [e.split(":")[2].strip() for e in errors] == others, many.stderr
    assert all("an SRDF (MoveIt's semantic description of robot 'panda')" in e for e in errors)
    assert all(e.endswith("[srdf-not-robot]") for e in errors)
    assert "expand it with xacro, then read it with its URDF: --srdf FILE" in errors[2]
    import cspace

    with pytest.raises(cspace.errors.NotARobotError, match="an SRDF that xacro makes") as given:
        cspace.inspect(repo / ROBOTS[0], srdf=repo / XACRO_SRDF)  # never read as written
    assert given.value.code == "srdf-format"


def test_auto_finds_the_srdf_in_the_moveit_package_and_beside_the_robots(repo: Path) -> None:
    """By file name in a sibling ``*_moveit_config`` package (the robot's own before
    another robot's), by ``<robot name>`` in example-robot-data's ``srdf/``, and then
    ``--group`` works."""
    dual = repo / "dual_arm_panda_moveit_config/config"
    dual.mkdir(parents=True)
    other = (repo / "panda_moveit_config/config/panda.srdf").read_text()
    (dual / "panda.srdf").write_text(other.replace('<group name="arm">', '<group name="dual">'))
    try:
        panda = run_cli("inspect", "--srdf", "auto", "--format", "json", ROBOTS[0], cwd=repo)
    finally:
        shutil.rmtree(dual.parent)
    document = json.loads(panda.stdout)
    found = "panda_description/urdf/../../panda_moveit_config/config/panda.srdf"
    assert document["srdf"]["path"] == found
    assert [g["name"] for g in document["srdf"]["groups"]] == ["arm", "hand", "arm_and_hand"]
    talos = run_cli("inspect", "--srdf", "auto", "--format", "json", ROBOTS[1], cwd=repo)
    assert json.loads(talos.stdout)["srdf"]["path"] == "talos_data/robots/../srdf/talos.srdf"
    group = ("inspect", "--srdf", "auto", "--group", "l_arm", "--format", "json", ROBOTS[1])
    arm = run_cli(*group, cwd=repo)
    assert arm.code == 0, arm.stderr
    assert json.loads(arm.stdout)["dimension"] == 7


def test_auto_says_where_it_looked_when_it_finds_none(tmp_path: Path) -> None:
    """No SRDF of the robot: a note (``srdf-not-found``) naming the places looked in,
    which ``--group`` repeats; two SRDF files naming the robot in one place: none."""
    project = tmp_path / "arm_description"
    (project / "urdf").mkdir(parents=True)
    (project / "package.xml").write_text("<package><name>arm_description</name></package>")
    shutil.copy(_erd("panda_description/urdf/panda.urdf"), project / "urdf" / "arm.urdf")
    (project / "config").mkdir()
    srdf = _erd("panda_description/srdf/panda.srdf").read_text()
    (project / "config" / "other.srdf").write_text(srdf.replace('name="panda"', 'name="ur5"'))
    run = run_cli("inspect", "--srdf", "auto", "--format", "json", "urdf/arm.urdf", cwd=project)
    notes = [d for d in json.loads(run.stdout)["diagnostics"] if d["code"] == "srdf-not-found"]
    assert len(notes) == 1 and notes[0]["severity"] == "info"
    assert "robot 'panda'" in notes[0]["message"] and "arm.srdf" in notes[0]["message"]
    assert "looked in urdf, urdf/../config" in notes[0]["message"]
    group = run_cli("inspect", "--srdf", "auto", "--group", "arm", "urdf/arm.urdf", cwd=project)
    assert group.code == 2 and "looked in urdf, urdf/../config" in group.stderr
    for name in ("x.srdf", "y.srdf", "a.srdf"):  # "a" begins "arm", yet not up to a "_"
        (project / "config" / name).write_text(srdf)
    run = run_cli("inspect", "--srdf", "auto", "--format", "json", "urdf/arm.urdf", cwd=project)
    document = json.loads(run.stdout)
    assert "srdf" not in document
    message = next(d["message"] for d in document["diagnostics"] if d["code"] == "srdf-not-found")
    alike = "urdf/../config/a.srdf, urdf/../config/x.srdf, urdf/../config/y.srdf"
    assert f"several SRDF files name robot 'panda': {alike}" in message


def test_auto_never_reads_outside_the_repository(tmp_path: Path) -> None:
    """A MoveIt package, a place or an SRDF that is a link out of the repository is
    neither opened nor named; a FIFO is passed over."""
    repo = _moveit_repository(tmp_path)
    outside = tmp_path / "outside"
    (outside / "config").mkdir(parents=True)
    secret = _erd("panda_description/srdf/panda.srdf").read_text()
    secret = secret.replace('<group name="panda_arm">', f'<group name="{SECRET}">')
    (outside / "config" / "panda.srdf").write_text(secret)
    shutil.rmtree(repo / "panda_moveit_config")
    (repo / "panda_moveit_config").symlink_to(outside)  # the whole package
    (repo / "panda_description" / "config").symlink_to(outside / "config")  # a place
    (repo / "panda_description" / "srdf" / "robot.xml").unlink()
    (repo / "panda_description" / "srdf" / "panda.srdf").symlink_to(outside / "config/panda.srdf")
    os.mkfifo(repo / "panda_description" / "urdf" / "panda.srdf")  # NAME.srdf, looked at first
    watch = OpenWatch(outside / "config")
    run = run_cli("inspect", "--srdf", "auto", "--format", "json", ROBOTS[0], cwd=repo, timeout=60)
    assert watch.opened() == [], "an SRDF outside the repository was opened"
    watch.close()
    document = json.loads(run.stdout)
    assert "srdf" not in document and SECRET not in run.stdout + run.stderr
    note = next(d["message"] for d in document["diagnostics"] if d["code"] == "srdf-not-found")
    assert "outside" not in note and "panda_moveit_config" not in note, note


def test_a_folder_of_many_srdf_files_is_looked_at_within_bounds(tmp_path: Path) -> None:
    """Thousands of candidates: at most `MAX_LISTED` names read of a folder and
    `MAX_LOOKED` files opened; the note says which bound was met."""
    repo = tmp_path / "repo"
    (repo / "urdf").mkdir(parents=True)
    (repo / "srdf").mkdir()
    (repo / ".git").mkdir()
    shutil.copy(_erd("panda_description/urdf/panda.urdf"), repo / "urdf" / "arm.urdf")
    srdf = _erd("panda_description/srdf/panda.srdf").read_text()
    decoy = srdf.replace('name="panda"', 'name="decoy"')
    for index in range(MAX_LISTED + 500):
        (repo / "srdf" / f"decoy_{index:05}.srdf").write_text(decoy)
    watch = OpenWatch(repo / "srdf")
    run = run_cli("inspect", "--srdf", "auto", "--format", "json", "urdf/arm.urdf", cwd=repo)
    opened = {name for name in watch.opened() if name}
    watch.close()
    assert 0 < len(opened) <= MAX_LOOKED, len(opened)
    document = json.loads(run.stdout)
    message = next(d["message"] for d in document["diagnostics"] if d["code"] == "srdf-not-found")
    assert f"read the first {MAX_LISTED:,} names of" in message
    assert f"looked at the first {MAX_LOOKED} SRDF files" in message


def test_a_robot_turned_srdf_is_gone_from_the_baseline(tmp_path: Path) -> None:
    """A baselined URDF whose file now holds an SRDF: the folder's search leaves it out,
    and ``check --baseline`` reads it all the same, as a robot gone (exit 1)."""
    (tmp_path / "robots").mkdir()
    arm = tmp_path / "robots" / "arm.urdf"
    shutil.copy(_erd("panda_description/urdf/panda.urdf"), arm)
    baseline = run_cli("inspect", "--format", "jsonl", "robots", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(baseline.stdout)
    shutil.copy(_erd("panda_description/srdf/panda.srdf"), arm)
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=tmp_path)
    assert run.code == 1, run.stdout + run.stderr
    assert "gone" in run.stdout and "now an SRDF, no robot" in run.stdout


BROKEN_URDF = """<robot name="r">
  <link name="base"/><link name="arm"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="nowhere"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
"""A broken URDF (its joint's child link does not exist), to be saved as ``.srdf``."""

XACRO_ROBOT = """<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="m">
  <xacro:macro name="arm"><link name="base"/><link name="tip"/>
    <joint name="j" type="continuous"><parent link="base"/><child link="tip"/></joint>
  </xacro:macro>
  <xacro:arm/>
</robot>
"""
"""A robot that xacro makes, to be saved as ``.srdf.xacro``."""


def test_a_robot_named_srdf_is_inspected_in_every_path(tmp_path: Path) -> None:
    """Content beats the name: a ``.srdf`` file that holds a URDF, and a ``.srdf.xacro``
    file that makes one, are robots, for the Action's folder, the hook's ``--robots-only``,
    a file named, and ``check --baseline``; a broken one fails each, with its reader's
    error, never ``srdf-not-robot``. A ``<robot>`` of neither links nor SRDF elements is
    left to its name."""
    (tmp_path / "robots").mkdir()
    arm = tmp_path / "robots" / "arm.srdf"
    arm.write_text(BROKEN_URDF.replace('"nowhere"', '"arm"'))
    (tmp_path / "robots" / "macro.srdf.xacro").write_text(XACRO_ROBOT)
    (tmp_path / "robots" / "empty.srdf").write_text('<robot name="empty"><!-- <link/> --></robot>')
    folder = run_cli("inspect", "--robots-only", "--format", "jsonl", "--", "robots", cwd=tmp_path)
    assert folder.code == 0, folder.stderr
    rows = {json.loads(row)["source"]["path"]: row for row in folder.stdout.splitlines()}
    assert sorted(rows) == ["robots/arm.srdf", "robots/macro.srdf.xacro"], folder.stderr
    assert [json.loads(rows[p])["dimension"] for p in sorted(rows)] == [1, 1]
    note = next(line for line in folder.stderr.splitlines() if "SRDF files, read with" in line)
    assert note.endswith(": robots/empty.srdf"), folder.stderr
    (tmp_path / "baseline.jsonl").write_text(folder.stdout)
    arm.write_text(BROKEN_URDF)
    runs = run_cli_many_in(
        tmp_path,
        ("inspect", "--strict", "--robots-only", "--", "robots/arm.srdf"),  # the hook
        ("inspect", "--robots-only", "--", "robots"),  # the Action
        ("inspect", "--", "robots/arm.srdf"),
        ("check", "--baseline", "baseline.jsonl", "--", "robots"),
    )
    said = "robots/arm.srdf:3: joint 'j1' names child link 'nowhere', which does not exist"
    for run in runs:
        assert run.code == 2 and f"{said} [missing-link]" in run.stderr, run.stdout + run.stderr
        assert "srdf-not-robot" not in run.stdout + run.stderr
    assert "same: robots/macro.srdf.xacro" in runs[3].stdout


@pytest.mark.parametrize(
    ("content", "srdf"),
    [
        ('<robot name="a"><group name="g"/><link name="l"/></robot>', False),
        ('<robot name="b"><!-- <link name="x"/> --></robot>', True),  # its name decides
        ('<robot name="c"><gazebo><link name="l"/></gazebo><group name="g"/></robot>', False),
        ('<robot name="d" xmlns:x="urn:x"><x:link name="l"/><group name="g"/></robot>', True),
        ('<robot name="e"><end_effector name="e" parent_link="l" group="g"/></robot>', True),
        ('<robot name="f"/>', True),
    ],
)
def test_the_search_and_the_reader_tell_an_srdf_alike(
    tmp_path: Path, content: str, srdf: bool
) -> None:
    """One rule, read from the bytes by the search and from the tree by the reader: a
    file the search leaves out as an SRDF is one its reader refuses as an SRDF, and a
    file it inspects is read as a robot (or refused for what else it is)."""
    (tmp_path / "robot.srdf").write_text(content)
    folder, named = run_cli_many_in(
        tmp_path,
        ("inspect", "--robots-only", "--format", "jsonl", "--", "."),
        ("inspect", "--format", "jsonl", "--", "robot.srdf"),
    )
    left_out = "SRDF files, read with" in folder.stderr and "robot.srdf" in folder.stderr
    assert left_out == srdf, folder.stdout + folder.stderr
    assert ("[srdf-not-robot]" in named.stderr) == srdf, named.stderr
    assert folder.stdout == named.stdout  # the same report, or none


def test_auto_takes_the_srdf_naming_the_robot_over_one_naming_another(tmp_path: Path) -> None:
    """An SRDF naming the URDF's robot wins over ``NAME.srdf`` naming another, wherever it
    is; without one, another robot's is taken only when the robot has every link and joint
    it names, and a warning (``srdf-other-robot``) names both robots, as for ``--srdf FILE``."""
    repo = tmp_path / "repo"
    for folder in ("urdf", "config", ".git"):
        (repo / folder).mkdir(parents=True)
    (repo / "urdf" / "robot.urdf").write_text(ARM_A_URDF)
    other = (
        '<robot name="arm_b">\n  <virtual_joint name="vj" type="floating" parent_frame="world" '
        'child_link="base"/>\n  <group name="arm"><joint name="j1"/><joint name="j2"/></group>\n'
        "</robot>\n"
    )
    (repo / "urdf" / "robot.srdf").write_text(other)
    own = (
        '<robot name="arm_a"><group name="arm"><joint name="j1"/><joint name="j2"/></group></robot>'
    )
    (repo / "config" / "arm_a.srdf").write_text(own)
    auto = ("inspect", "--srdf", "auto", "--format", "json", "urdf/robot.urdf")
    given = ("inspect", "--srdf", "urdf/robot.srdf", "--strict", "urdf/robot.urdf")
    right, chosen_file = run_cli_many_in(repo, auto, given)
    document = json.loads(right.stdout)
    assert document["srdf"]["path"] == "urdf/../config/arm_a.srdf"
    assert document["dimension"] == 2
    assert not [d for d in document["diagnostics"] if d["code"] == "srdf-other-robot"]
    warned = "the SRDF names robot 'arm_b', and the URDF robot 'arm_a'"
    assert chosen_file.code == 1 and warned in chosen_file.stdout, chosen_file.stdout
    (repo / "config" / "arm_a.srdf").unlink()
    document = json.loads(run_cli(*auto, cwd=repo).stdout)
    assert document["srdf"]["path"] == "urdf/robot.srdf" and document["dimension"] == 8
    (warning,) = [d for d in document["diagnostics"] if d["code"] == "srdf-other-robot"]
    assert warning["severity"] == "warning" and warned in warning["message"]
    (repo / "urdf" / "robot.srdf").write_text(other.replace('"j2"', '"j9"'))  # not arm_a's
    none = json.loads(run_cli(*auto, cwd=repo).stdout)
    assert "srdf" not in none and none["dimension"] == 2
    codes = [d["code"] for d in none["diagnostics"]]
    assert "srdf-not-found" in codes and "srdf-other-robot" not in codes
    note = next(d["message"] for d in none["diagnostics"] if d["code"] == "srdf-not-found")
    assert "urdf/robot.srdf names robot 'arm_b' and 'j9', which the robot lacks" in note


ARM_A_URDF = """<robot name="arm_a">
  <link name="base"/><link name="l1"/><link name="l2"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def run_cli_many_in(cwd: Path, *commands: tuple[str, ...]) -> list[Run]:
    """Several `cspace` commands run in ``cwd``, two at a time; results in order."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=2) as pool:
        return list(pool.map(lambda args: run_cli(*args, cwd=cwd), commands))


@pytest.mark.parametrize(
    ("urdf", "srdf", "other"),
    [
        ("talos_data/robots/talos_left_arm.urdf", "talos.srdf", None),  # <robot name> talos
        ("solo_description/robots/solo12.urdf", "solo.srdf", None),
        ("panda_description/urdf/panda_collision.urdf", "panda.srdf", None),
        ("hyq_description/robots/hyq_no_sensors.urdf", "hyq.srdf", None),
        ("baxter_description/urdf/baxter.urdf", "baxter_manipulation.srdf", None),
        ("ur_description/urdf/ur5_robot.urdf", "ur5.srdf", None),  # one of four naming ur5
        ("bolt_description/robots/bolt.urdf", "bolt.srdf", "finger_edu"),  # its parts: bolt's
        ("icub_description/robots/icub_reduced.urdf", "icub.srdf", "icub"),  # robot iCub
        ("ur_description/urdf/ur3_robot.urdf", None, None),  # ur3_gripper.srdf names ur5
        ("ur_description/urdf/ur10_robot.urdf", None, None),
        ("romeo_description/urdf/romeo_laas_small.urdf", None, None),  # romeo's joints it lacks
        ("go2_description/urdf/go2.urdf", "go2.srdf", "go2"),  # its group names root_joint
        ("ur_description/urdf/ur3_gripper.urdf", "ur3_gripper.srdf", "ur5"),  # collisions only
        ("z1_description/urdf/z1.urdf", None, None),  # z1.srdf names robot z1 and a link 'base'
    ],
)
def test_auto_pairs_example_robot_data_as_its_own_loader(
    urdf: str, srdf: str | None, other: str | None
) -> None:
    """The pairs example-robot-data's Python loader makes, and none where it makes none;
    an SRDF naming another robot than the URDF's gets a warning naming both."""
    import cspace

    report = cspace.inspect(_erd(urdf), srdf=True)
    assert (report.srdf and Path(report.srdf.path).name) == srdf or (
        srdf is None and report.srdf is None
    ), report.srdf
    notes = [d for d in report.diagnostics if d.code == "srdf-not-found"]
    assert len(notes) == (srdf is None)
    warned = [d.message for d in report.diagnostics if d.code == "srdf-other-robot"]
    both = f"the SRDF names robot '{other}', and the URDF robot '{report.robot}'"
    assert len(warned) == (other is not None) and all(both in w for w in warned), warned


def test_the_search_takes_a_file_for_an_srdf_only_when_sure(tmp_path: Path) -> None:
    """Told by content: past the first 64 KiB (PR2's SRDF is 117 kB), past a comment
    naming a link; a link after 70 kB of groups, or a ``<`` that begins nothing XML reads
    (tinyxml2 reads ``< link``), and the file is inspected (and its reader says what it
    is)."""
    pr2 = _erd("pr2_description/srdf/pr2.srdf").read_bytes()
    assert len(pr2) > 64 << 10
    (tmp_path / "big.xml").write_bytes(pr2)
    groups = "".join(f'<group name="g{i}"><joint name="j"/></group>\n' for i in range(2_000))
    files = {
        "comment.xml": '<robot name="c"><!-- <link name="x"/> --><group name="g"/></robot>',
        "late_link.xml": f'<robot name="l">{groups}<link name="base"/></robot>',
        "stray.xml": '<robot name="s"><group name="g"/>< link name="l"/></robot>',
    }
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    run = run_cli("inspect", "--format", "jsonl", "--", ".", cwd=tmp_path)
    rows = [json.loads(line)["source"]["path"] for line in run.stdout.splitlines()]
    assert rows == ["late_link.xml"], run.stderr
    assert "stray.xml" in run.stderr and "[srdf-not-robot]" not in run.stderr
    note = next(line for line in run.stderr.splitlines() if "SRDF files, read with" in line)
    assert "big.xml" in note and "comment.xml" in note and "late_link" not in note


_BROKEN_BODY = (
    '<link name="a"/><joint name="j" type="revolute"><parent link="a"/><child link="nope"/>'
    '<axis xyz="0 0 1"/></joint>'
)
"""A link and a joint whose child link does not exist: a broken robot, wherever it is read."""

MALFORMED_OR_NOT = {
    "closes_nothing.urdf": f'<robot name="r"><group name="g"/></group>{_BROKEN_BODY}</robot>',
    "after_root.urdf": f'<robot name="r"><group name="g"/></robot>{_BROKEN_BODY}',
    "nested_mismatch.urdf": f'<robot name="r"><group name="g">{_BROKEN_BODY}</chain></robot>',
    "second_root.urdf": f'<robot name="r"><group name="g"/></robot><robot>{_BROKEN_BODY}</robot>',
    "text_after.urdf": '<robot name="r"><group name="g"/></robot>\ntext\n',
    "bad_comment_after.urdf": '<robot name="r"><group name="g"/></robot><!-- a -- b -->',
    "declaration_after.urdf": '<robot name="r"><group name="g"/></robot><?xml version="1.0"?>',
    "end_tag_attribute.urdf": '<robot name="r"><group name="g"></group a="1"></robot>',
    "comment_after.urdf": f'<robot name="r"><group name="g"/></robot>\n<!-- {_BROKEN_BODY} -->\n',
    "pi_after.urdf": '<robot name="r"><group name="g"/></robot >\n<?pi x?>\n',
}
"""Robot files whose search must equal their reader's verdict: the last two are SRDFs (a
comment and a processing instruction may follow the root), the others malformed XML."""


def test_a_malformed_file_is_never_taken_for_an_srdf(tmp_path: Path) -> None:
    """An end tag that is not the open element's own, or anything but white space, comments
    and processing instructions after the root's end: the search is not sure, and the file
    is inspected, so the hook (``--strict --robots-only FILE``) and the Action fail it as
    naming it does (exit 2, its reader's ``xml-syntax`` error); a comment or a processing
    instruction after an SRDF's root leaves it an SRDF."""
    (tmp_path / "robots").mkdir()
    for name, text in MALFORMED_OR_NOT.items():
        (tmp_path / "robots" / name).write_text(text)
    files = [f"robots/{name}" for name in MALFORMED_OR_NOT]
    srdfs = ["robots/comment_after.urdf", "robots/pi_after.urdf"]
    broken = [name for name in files if name not in srdfs]
    hook = ("inspect", "--strict", "--robots-only", "--")
    runs = run_cli_many_in(
        tmp_path,
        ("inspect", "--robots-only", "--", "robots"),  # the Action
        ("inspect", "--", *files),  # each file named
        (*hook, *srdfs),
        *[(*hook, name) for name in broken],
    )
    action, named, hooked_srdfs, *hooked = runs
    for run in (action, named, *hooked):
        assert run.code == 2, run.stdout + run.stderr
    assert hooked_srdfs.code == 0, hooked_srdfs.stdout + hooked_srdfs.stderr
    for run in (action, hooked_srdfs):
        note = next(line for line in run.stderr.splitlines() if "SRDF files, read with" in line)
        assert note.endswith(f": {', '.join(srdfs)}"), run.stderr
    for name, run in zip(broken, hooked, strict=True):
        for said in (run.stderr, action.stderr, named.stderr):
            errors = [
                line for line in said.splitlines() if line.startswith(f"cspace: error: {name}:")
            ]
            assert len(errors) == 1 and errors[0].endswith("[xml-syntax]"), said
        assert "SRDF" not in run.stderr, run.stderr
    for name in srdfs:
        assert f"cspace: error: {name}:1: an SRDF" in named.stderr, named.stderr
        assert "[srdf-not-robot]" in named.stderr
