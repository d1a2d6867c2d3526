"""``cspace check --baseline`` with collisions reports: a robot's accepted self-collision matrix.

A baseline line may be ``cspace collisions ROBOT --format jsonl``'s; the check draws the
robot's samples again (the line's ``samples`` and ``seed``, its SRDF found as ``--srdf
auto`` finds it when the line had one) and compares pair by pair. The tests write such a
baseline of a copy of example-robot-data's ur5 with its SRDF and of the documentation's
arm of boxes, then change the SRDF, a box, a link's name, the file's name, and forge the
baseline's lines: each change is ``changed`` (or ``differs``) naming its pairs, at the
SRDF's line in the ``github`` format; each forged line is refused in one line, bounded,
or never makes cspace open a file it names.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import pytest

from cspace._formats.shared.erd import robots_dir

from conftest import REPO, OpenWatch, Run, run_cli

UR5 = robots_dir() / "ur_description"
UR5_URDF = "erd/robots/ur_description/urdf/ur5_robot.urdf"
UR5_SRDF = "erd/robots/ur_description/srdf/ur5.srdf"
BOXES = REPO / "docs" / "examples" / "boxes_arm.urdf"


def _ur5(tmp_path: Path) -> Path:
    """A copy of example-robot-data's ur5 (URDF, SRDF, collision meshes) in a package."""
    root = tmp_path / "erd"
    for part in ("urdf/ur5_robot.urdf", "srdf/ur5.srdf"):
        (root / "robots" / "ur_description" / part).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(UR5 / part, root / "robots" / "ur_description" / part)
    meshes = "meshes/ur5/collision"
    shutil.copytree(UR5 / meshes, root / "robots" / "ur_description" / meshes)
    (root / "package.xml").write_text("<package><name>example-robot-data</name></package>")
    return tmp_path


def _baseline(folder: Path, robot: str, *collisions: str) -> None:
    """``inspect``'s line and ``collisions``' line of ``robot``, as a user writes them."""
    inspected = run_cli("inspect", robot, "--format", "jsonl", cwd=folder)
    drawn = run_cli("collisions", robot, *collisions, "--format", "jsonl", cwd=folder)
    assert inspected.code == 0 and drawn.code in (0, 1), inspected.stderr + drawn.stderr
    assert drawn.stdout.count("\n") == 1
    (folder / "b.jsonl").write_text(inspected.stdout + drawn.stdout)


def _check(folder: Path, *args: str) -> Run:
    return run_cli("check", "--baseline", "b.jsonl", *args, cwd=folder)


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))


@pytest.fixture
def ur5(tmp_path: Path) -> Path:
    folder = _ur5(tmp_path)
    _baseline(folder, UR5_URDF, "--srdf", "auto", "-n", "300")
    return folder


@pytest.fixture
def boxes(tmp_path: Path) -> Path:
    (tmp_path / "arm").mkdir()
    shutil.copy(BOXES, tmp_path / "arm" / "boxes_arm.urdf")
    shutil.copy(BOXES.with_suffix(".srdf"), tmp_path / "arm" / "boxes_arm.srdf")
    _baseline(tmp_path, "arm/boxes_arm.urdf", "--srdf", "auto", "-n", "400", "--seed", "3")
    return tmp_path


def test_ur5_with_its_srdf_is_the_same(ur5: Path) -> None:
    run = _check(ur5, UR5_URDF)
    assert run.code == 0, run.stdout + run.stderr
    assert run.stdout.splitlines() == [
        f"same: {UR5_URDF}: R^6",
        f"same: {UR5_URDF}: self-collision: 28 pairs, classes and rules as accepted "
        "(300 samples, seed 0)",
    ]
    github = _check(ur5, UR5_URDF, "--format", "github")
    assert (github.code, github.stdout.strip()) == (0, "")


def test_the_srdf_disabling_one_more_reachable_pair_is_changed_at_its_line(ur5: Path) -> None:
    srdf = ur5 / UR5_SRDF
    _edit(
        srdf, "</robot>", '  <disable_collisions link1="base_link" link2="forearm_link"/>\n</robot>'
    )
    line = (
        srdf.read_text()
        .splitlines()
        .index('  <disable_collisions link1="base_link" link2="forearm_link"/>')
    )
    run = _check(ur5, UR5_URDF)
    assert run.code == 1, run.stderr
    assert run.stdout.splitlines()[1] == (
        f"changed: {UR5_URDF}: self-collision matrix: 'base_link'-'forearm_link' rule "
        "checked -> disabled (User) (300 samples, seed 0)"
    )
    github = _check(ur5, UR5_URDF, "--format", "github")
    assert github.code == 1
    assert github.stdout.splitlines() == [
        f"::error file={UR5_SRDF},line={line + 1},title=cspace baseline%3A self-collision "
        "rule::'base_link'-'forearm_link' rule checked -> disabled (User) (write its line "
        f"again to accept it: cspace collisions {UR5_URDF} --srdf auto -n 300 --seed 0 "
        "--format jsonl)"
    ]


def test_the_srdf_checking_a_pair_it_disabled_is_changed(ur5: Path) -> None:
    _edit(ur5 / UR5_SRDF, '<disable_collisions link1="forearm_link" link2="wrist_2_link"/>', "")
    run = _check(ur5, UR5_URDF)
    assert run.code == 1
    assert "'forearm_link'-'wrist_2_link' rule disabled (User) -> checked" in run.stdout


def test_the_srdf_gone_is_a_changed_matrix(ur5: Path) -> None:
    (ur5 / UR5_SRDF).unlink()
    run = _check(ur5, UR5_URDF)
    assert run.code == 1
    row = run.stdout.splitlines()[1]
    assert row.startswith(f"changed: {UR5_URDF}: self-collision matrix: matrix srdf -> none; ")
    assert row.endswith("; and 24 more (300 samples, seed 0)"), row  # 28 rules, 1 matrix


def test_a_box_grown_so_a_never_pair_collides_is_changed(boxes: Path) -> None:
    robot = boxes / "arm" / "boxes_arm.urdf"
    _edit(robot, '<box size="0.1 0.1 0.1"/>', '<box size="0.8 0.8 0.8"/>')  # the camera
    run = _check(boxes, "arm")
    assert run.code == 1
    assert run.stdout.splitlines() == [
        "same: arm/boxes_arm.urdf: R^3",
        "changed: arm/boxes_arm.urdf: self-collision matrix: 'camera'-'fore' class never -> "
        "sometimes (400 samples, seed 3)",
    ]
    github = _check(boxes, "arm", "--format", "github").stdout  # the SRDF disables it "Never"
    assert github.startswith("::error file=arm/boxes_arm.srdf,line=8,title=cspace baseline%3A")


def test_shares_out_of_their_interval_differ_and_within_it_are_the_same(boxes: Path) -> None:
    robot = boxes / "arm" / "boxes_arm.urdf"
    text = robot.read_text()
    _edit(robot, '<box size="0.3 0.3 0.1"/>', '<box size="0.302 0.3 0.1"/>')  # the base
    run = _check(boxes, "arm")
    assert run.code == 0 and run.stdout.splitlines()[1].startswith("same: "), run.stdout
    robot.write_text(text)
    _edit(robot, '<box size="0.3 0.3 0.1"/>', '<box size="0.5 0.5 0.1"/>')
    run = _check(boxes, "arm")
    assert run.code == 1
    row = run.stdout.splitlines()[1]
    assert row.startswith(
        "differs: arm/boxes_arm.urdf: self-collision: same classes and rules, shares moved: "
        "'base'-'fore' share "
    ), row


def test_a_link_renamed_is_pairs_gone_and_added_named_up_to_five(boxes: Path) -> None:
    robot = boxes / "arm" / "boxes_arm.urdf"
    robot.write_text(robot.read_text().replace('"camera"', '"cam"'))
    row = _check(boxes, "arm").stdout.splitlines()[1]
    assert row == (
        "changed: arm/boxes_arm.urdf: self-collision matrix: 'base'-'cam' new pair (adjacent); "
        "'cam'-'fore' new pair (never); 'cam'-'shoulder' new pair (never); 'cam'-'upper' new "
        "pair (never); 'base'-'camera' gone (was adjacent); and 3 more (400 samples, seed 3)"
    )


def test_a_robot_moved_keeps_its_matrix_and_one_gone_is_gone(boxes: Path) -> None:
    (boxes / "arm" / "boxes_arm.urdf").rename(boxes / "arm" / "arm.urdf")
    run = _check(boxes, "arm")
    assert run.code == 0, run.stdout
    assert run.stdout.splitlines() == [
        "moved: arm/arm.urdf: from arm/boxes_arm.urdf, the same R^3",
        "same: arm/arm.urdf: self-collision: 10 pairs, classes and rules as accepted "
        "(400 samples, seed 3)",
    ]
    lines = (boxes / "b.jsonl").read_text().splitlines()
    (boxes / "b.jsonl").write_text(lines[1] + "\n")  # the collisions report alone
    (boxes / "arm" / "arm.urdf").unlink()
    run = _check(boxes, "arm")
    assert (run.code, run.stdout) == (
        1,
        "gone: arm/boxes_arm.urdf: its collisions report is in the baseline, but the file "
        "is gone\n",
    )


def _lines(folder: Path) -> list[dict[str, Any]]:
    return [json.loads(line) for line in (folder / "b.jsonl").read_text().splitlines()]


def _write(folder: Path, documents: list[dict[str, Any]]) -> None:
    (folder / "b.jsonl").write_text("".join(json.dumps(d) + "\n" for d in documents))


@pytest.mark.parametrize(
    ("forge", "said"),
    [
        (lambda d: d.update(samples=10**9), "above the maximum 1000000 at /samples"),
        (lambda d: d.update(kind="collision"), "not a cspace report (no joints, no manifold)"),
        (lambda d: d["free"].update(share=float("nan")), "NaN is not a JSON number"),
        (lambda d: d["pairs"][1].update(link2="zzz"), "are not two links, sorted at /pairs/1"),
    ],
)
def test_a_forged_line_is_refused_in_one_line(boxes: Path, forge: Any, said: str) -> None:
    documents = _lines(boxes)
    forge(documents[1])
    _write(boxes, documents)
    run = _check(boxes, "arm")
    assert run.code == 2 and run.stdout == "", run.stdout
    assert run.stderr.startswith("cspace: error: b.jsonl:2: ") and run.stderr.count("\n") == 1
    assert said in run.stderr, run.stderr


def test_the_samples_of_a_baseline_are_bounded_in_all(boxes: Path) -> None:
    documents = _lines(boxes)
    bare = documents[1]
    bare.update(samples=1_000_000, links=[], pairs=[], ranges=[], poses=[], diagnostics=[])
    full = {"hits": 1_000_000, "samples": 1_000_000, "share": 1.0, "low": 0.99, "high": 1.0}
    bare.update(free=full, free_suggested=full)
    forged = [dict(bare, source=dict(bare["source"], path=f"arm/{k}.urdf")) for k in range(11)]
    _write(boxes, [documents[0], *forged])
    run = _check(boxes, "arm")
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "b.jsonl:12: collisions reports asking for more than 10,000,000 samples" in run.stderr


def test_two_collisions_reports_of_one_file_are_refused(boxes: Path) -> None:
    documents = _lines(boxes)
    twice = dict(documents[1], source=dict(documents[1]["source"], path="arm/./boxes_arm.urdf"))
    _write(boxes, [*documents, twice])
    run = _check(boxes, "arm")
    assert run.code == 2 and run.stderr.count("\n") == 1, run.stderr
    assert "a second collisions report of 'arm/boxes_arm.urdf' as 'arm/./boxes_arm.urdf'" in (
        run.stderr
    )


def test_a_forged_line_names_no_file_cspace_reads(boxes: Path) -> None:
    """Its SRDF is found as --srdf auto finds it, not at the path it gives (which is a
    changed matrix: another SRDF than the accepted one); a line of a file outside the
    folders checked is never read; a line emptied of pairs fails."""
    elsewhere = boxes / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "all.srdf").write_text(
        '<robot name="boxes_arm"><disable_default_collisions link="fore"/></robot>'
    )
    shutil.copy(BOXES, elsewhere / "boxes_arm.urdf")
    documents = _lines(boxes)
    documents[1]["srdf"] = "elsewhere/all.srdf"
    outside = dict(
        documents[1], source=dict(documents[1]["source"], path="elsewhere/boxes_arm.urdf")
    )
    _write(boxes, [*documents, outside])
    watch = OpenWatch(elsewhere)
    try:
        run = _check(boxes, "arm")
        assert watch.opened() == [], "a file the baseline names was opened"
    finally:
        watch.close()
    assert run.code == 1, run.stdout + run.stderr
    assert run.stdout.splitlines()[1:] == [
        "changed: arm/boxes_arm.urdf: self-collision matrix: matrix srdf ../elsewhere/all.srdf "
        "-> srdf boxes_arm.srdf (400 samples, seed 3)",
        "outside: elsewhere/boxes_arm.urdf: its collisions report in the baseline, but "
        "outside the folders checked: not read",
    ]
    documents[1].update(links=[], pairs=[])
    _write(boxes, documents)
    run = _check(boxes, "arm")
    assert run.code == 1 and "'base'-'camera' new pair (adjacent)" in run.stdout, run.stdout


def test_the_markdown_table_has_a_row_for_the_matrix(boxes: Path) -> None:
    run = _check(boxes, "arm", "--format", "markdown")
    assert run.code == 0
    assert run.stdout.splitlines()[-1] == (
        "| `arm/boxes_arm.urdf` | same | `self-collision: 10 pairs, classes and rules as "
        "accepted (400 samples, seed 3)` |"
    )
