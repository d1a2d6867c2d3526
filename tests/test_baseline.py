"""``cspace check --baseline``: a repository's accepted C-spaces, and what differs from them.

The baseline is what ``cspace inspect --format jsonl`` writes; the tests write it so,
then change a limit, add a robot, delete one, and accept by writing it again. The
baseline is untrusted: a line that is no report, two reports of one file (however its
path is spelt), a file too large are refused in one line, naming the file and line; an
entry outside the folders checked is never opened nor looked for (an inotify watch sees
every open), and the output is the same whether its file exists or not.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

from conftest import REPO, OpenWatch, Run, run_cli
from conftest import cpu_of as _cpu_of

SECRET = "TOKEN-ghp-b4se1ine"
"""A secret's stand-in, the name of a joint in files outside the repository."""


@pytest.fixture(scope="module")
def bundled_baseline(tmp_path_factory: pytest.TempPathFactory) -> str:
    """What ``cspace inspect --format jsonl robots`` writes of a copy of the bundled
    robots: written once for the module (its paths are relative, the same wherever
    the copy is), and taken by each test's own copy (`_repo`)."""
    folder = tmp_path_factory.mktemp("bundled")
    shutil.copytree(REPO / "robots", folder / "robots")
    written = run_cli("inspect", "--format", "jsonl", "robots", cwd=folder)
    assert written.code == 0, written.stderr
    return written.stdout


def _repo(tmp_path: Path, baseline: str) -> Path:
    """A copy of the bundled robots, and their baseline (`bundled_baseline`) beside it."""
    shutil.copytree(REPO / "robots", tmp_path / "robots")
    (tmp_path / "baseline.jsonl").write_text(baseline)
    return tmp_path


def test_a_repository_matches_the_baseline_it_wrote(tmp_path: Path, bundled_baseline: str) -> None:
    repo = _repo(tmp_path, bundled_baseline)
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    lines = run.stdout.splitlines()
    robots = (repo / "baseline.jsonl").read_text().count("\n")
    assert run.code == 0 and len(lines) == robots >= 23
    assert all(line.startswith("same: ") for line in lines)


def test_what_differs_fails_and_accepting_it_passes(tmp_path: Path, bundled_baseline: str) -> None:
    repo = _repo(tmp_path, bundled_baseline)
    arm = repo / "robots" / "arm7.urdf"
    arm.write_text(arm.read_text().replace('upper="2.9"', 'upper="2.5"', 1))
    shutil.copy(arm, repo / "robots" / "arm8.urdf")
    (repo / "robots" / "sensor_head_fixed.urdf").unlink()
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    said = {line for line in run.stdout.splitlines() if not line.startswith("same: ")}
    assert run.code == 1
    assert said == {
        "differs: robots/arm7.urdf: R^6 × S^1, but limits differ",
        "new: robots/arm8.urdf: R^6 × S^1, not in the baseline",
        "gone: robots/sensor_head_fixed.urdf: in the baseline, but the file is gone",
    }
    markdown = run_cli(
        "check", "--baseline", "baseline.jsonl", "robots", "--format", "markdown", cwd=repo
    )
    assert markdown.code == 1 and "| `robots/arm8.urdf` | new |" in markdown.stdout
    rewritten = run_cli("inspect", "--format", "jsonl", "robots", cwd=repo)
    (repo / "baseline.jsonl").write_text(rewritten.stdout)  # the change accepted
    assert run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo).code == 0


def test_a_hostile_baseline_is_refused_in_one_line(tmp_path: Path, bundled_baseline: str) -> None:
    repo = _repo(tmp_path, bundled_baseline)
    lines = (repo / "baseline.jsonl").read_text().splitlines()
    cases = {
        "not-json.jsonl": lines[0] + "\n{not json\n",
        "twice.jsonl": lines[0] + "\n" + lines[0] + "\n",
        "not-a-report.jsonl": json.dumps({"joints": 1}) + "\n",
        "nested.jsonl": "[" * 100_000 + "]" * 100_000 + "\n",  # a JSON bomb of depth
    }
    for name, text in cases.items():
        (repo / name).write_text(text)
        run = run_cli("check", "--baseline", name, "robots", cwd=repo)
        assert run.code == 2 and run.stdout == "", run.stdout
        assert run.stderr.count("\n") == 1 and run.stderr.strip().endswith("[bad-report]"), name
        assert f"{name}:" in run.stderr
    assert (
        "a second report of 'robots/"
        in run_cli("check", "--baseline", "twice.jsonl", "robots", cwd=repo).stderr
    )
    huge = repo / "huge.jsonl"
    with open(huge, "wb") as out:  # sparse: 65 MiB of nothing on disk
        out.truncate(65 << 20)
    run = run_cli("check", "--baseline", "huge.jsonl", "robots", cwd=repo)
    assert run.code == 2 and "larger than the 67,108,864-byte limit" in run.stderr
    os.unlink(huge)


def test_several_robots_need_a_baseline() -> None:
    run = run_cli("check", "robots/arm7.urdf", "robots/arm7.urdf", "--expect", "R^7", cwd=REPO)
    assert run.code == 2 and "--baseline checks several" in run.stderr


def test_format_github_puts_each_difference_on_its_line_escaped(
    tmp_path: Path, bundled_baseline: str
) -> None:
    """A joint whose name carries a newline and ``::`` cannot start a workflow command."""
    from test_ci_formats import COMMAND

    repo = _repo(tmp_path, bundled_baseline)
    arm = repo / "robots" / "arm7.urdf"
    text = arm.read_text()
    arm.write_text(text.replace('name="elbow"', 'name="elbow&#10;::error::owned"', 1))
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", "--format", "github", cwd=repo)
    lines = run.stdout.splitlines()
    assert run.code == 1 and lines and all(COMMAND.fullmatch(line) for line in lines), lines
    added = [line for line in lines if "joint added" in line]
    assert len(added) == 1
    assert added[0].startswith("::error file=robots/arm7.urdf,line=")
    assert "::elbow\\n::error::owned: revolute (R^1), not in the baseline" in added[0]
    removed = [line for line in lines if "joint removed" in line]
    assert removed == [
        "::error file=robots/arm7.urdf,title=cspace baseline%3A joint removed::elbow: "
        "revolute (R^1) in the baseline, none now (write the baseline again to accept it)"
    ]


def test_a_file_only_renamed_is_moved_and_passes(tmp_path: Path, bundled_baseline: str) -> None:
    repo = _repo(tmp_path, bundled_baseline)
    (repo / "robots" / "arm7.urdf").rename(repo / "robots" / "arm_seven.urdf")
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    assert run.code == 0, run.stdout
    assert "moved: robots/arm_seven.urdf: from robots/arm7.urdf, the same R^6 × S^1" in run.stdout
    arm = repo / "robots" / "arm_seven.urdf"  # renamed and changed: new, and the old one gone
    arm.write_text(arm.read_text().replace('upper="2.9"', 'upper="2.5"', 1))
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    assert run.code == 1 and "new: robots/arm_seven.urdf" in run.stdout
    assert "gone: robots/arm7.urdf" in run.stdout


def test_a_fragment_named_is_left_to_its_model(tmp_path: Path, bundled_baseline: str) -> None:
    repo = _repo(tmp_path, bundled_baseline)
    fragment = "robots/mjcf_mujocoinclude/gripper.xml"
    run = run_cli("check", "--baseline", "baseline.jsonl", fragment, "robots/arm7.urdf", cwd=repo)
    assert run.code == 0 and run.stdout == "same: robots/arm7.urdf: R^6 × S^1\n"
    assert "[mjcf-fragment]" in run.stderr


def test_format_is_for_the_baseline() -> None:
    run = run_cli("check", "robots/arm7.urdf", "--expect", "R^7", "--format", "github", cwd=REPO)
    assert run.code == 2 and run.stderr.startswith("cspace: error: --format github is for")


def test_files_renamed_pair_by_name_then_in_order(tmp_path: Path) -> None:
    """Two files of one report renamed: each pairs with its own (order, or name kept)."""
    repo = tmp_path
    (repo / "robots").mkdir()
    for name in ("r1.urdf", "r2.urdf"):
        shutil.copy(REPO / "robots" / "arm7.urdf", repo / "robots" / name)
    written = run_cli("inspect", "--format", "jsonl", "robots", cwd=repo)
    (repo / "baseline.jsonl").write_text(written.stdout)
    (repo / "robots" / "r1.urdf").rename(repo / "robots" / "x1.urdf")
    (repo / "robots" / "r2.urdf").rename(repo / "robots" / "x2.urdf")
    run = run_cli(
        "check", "--baseline", "baseline.jsonl", "robots/x2.urdf", "robots/x1.urdf", cwd=repo
    )
    assert run.code == 0 and run.stdout.splitlines() == [
        "moved: robots/x2.urdf: from robots/r2.urdf, the same R^6 × S^1",
        "moved: robots/x1.urdf: from robots/r1.urdf, the same R^6 × S^1",
    ]
    (repo / "robots" / "x1.urdf").rename(repo / "robots" / "r2.urdf")  # a name kept wins
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=repo)
    assert run.code == 0 and run.stdout.splitlines() == [
        "same: robots/r2.urdf: R^6 × S^1",
        "moved: robots/x2.urdf: from robots/r1.urdf, the same R^6 × S^1",
    ]


def test_a_robot_that_became_a_fragment_is_gone(tmp_path: Path) -> None:
    """The fragment was skipped, its report never checked."""
    shutil.copy(REPO / "robots" / "mjcf_include" / "arm.xml", tmp_path / "robot.xml")
    written = run_cli("inspect", "--format", "jsonl", "robot.xml", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(written.stdout)
    robot = tmp_path / "robot.xml"
    text = robot.read_text().replace("<mujoco model=", "<mujocoinclude model=")
    robot.write_text(text.replace("</mujoco>", "</mujocoinclude>"))
    run = run_cli("check", "--baseline", "baseline.jsonl", "robot.xml", cwd=tmp_path)
    assert run.code == 1 and run.stdout == (
        "gone: robot.xml: in the baseline, but now an MJCF fragment, no robot\n"
    )


@pytest.mark.bounded
def test_many_renamed_and_changed_files_are_paired_in_linear_time(tmp_path: Path) -> None:
    """Each new file was diffed with every gone one of the same
    joints (400 files renamed and changed: 5 minutes). 500 robots renamed, each limit
    changed by less than the pairing's 4 digits but more than a diff's tolerance, against
    500 gone ones: each new file a candidate for every gone one, none moved, within a
    bound of CPU time (1.5 s measured; the quadratic pairing, 250,000 diffs, takes
    over a minute, past the bound at 300 files)."""
    from conftest import SECONDS

    count = 500
    robot = ARM.replace('upper="1"', 'upper="{}"')
    folder = tmp_path / "new"
    folder.mkdir()
    (folder / "r.urdf").write_text(robot.format(1.0))
    line = run_cli("inspect", "--format", "jsonl", "new/r.urdf", cwd=tmp_path).stdout
    (folder / "r.urdf").unlink()
    lines = [line.replace('"path": "new/r.urdf"', f'"path": "new/r{k}.urdf"') for k in range(count)]
    (tmp_path / "baseline.jsonl").write_text("".join(lines))
    for k in range(count):
        (folder / f"s{k}.urdf").write_text(robot.format(repr(1.0001 + k * 1e-8)))
    run, cpu = _cpu_of("check", "--baseline", "baseline.jsonl", "new", cwd=tmp_path)
    said = run.stdout.splitlines()
    assert run.code == 1 and len(said) == 2 * count, run.stderr[:500]
    assert sum(line.startswith("new: new/s") for line in said) == count
    assert sum(line.startswith("gone: new/r") for line in said) == count
    assert cpu < 2 * SECONDS, cpu


def test_a_baselined_file_a_folder_search_leaves_out_still_fails(tmp_path: Path) -> None:
    """Through a folder (as the Action passes it), a robot
    turned fragment, or no longer XML, was left out of the search and passed."""
    robots = tmp_path / "robots"
    robots.mkdir()
    shutil.copy(REPO / "robots" / "mjcf_include" / "arm.xml", robots / "a.xml")
    shutil.copy(REPO / "robots" / "arm7.urdf", robots / "c.urdf")
    written = run_cli("inspect", "--format", "jsonl", "robots", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(written.stdout)
    arm = robots / "a.xml"
    text = arm.read_text()
    arm.write_text(
        text.replace("<mujoco model=", "<mujocoinclude model=").replace(
            "</mujoco>", "</mujocoinclude>"
        )
    )
    for named in (["robots"], ["./robots"], ["./robots/a.xml", "robots/c.urdf"]):
        run = run_cli("check", "--baseline", "baseline.jsonl", *named, cwd=tmp_path)
        assert run.code == 1, (named, run.stdout)
        assert "but now an MJCF fragment, no robot" in run.stdout, (named, run.stdout)
    arm.write_text("not xml at all\n")
    run = run_cli("check", "--baseline", "baseline.jsonl", "robots", cwd=tmp_path)
    assert run.code == 2 and "no report: robots/a.xml: " in run.stdout, run.stdout


def test_markdown_escapes_pipes_from_paths_and_the_baseline(tmp_path: Path) -> None:
    """A `|` in a path forged table cells."""
    shutil.copy(REPO / "robots" / "arm7.urdf", tmp_path / "x|y.urdf")
    written = run_cli("inspect", "--format", "jsonl", "x|y.urdf", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(written.stdout)
    (tmp_path / "x|y.urdf").rename(tmp_path / "z|w.urdf")
    run = run_cli(
        "check", "--baseline", "baseline.jsonl", "z|w.urdf", "--format", "markdown", cwd=tmp_path
    )
    rows = run.stdout.splitlines()[2:]
    assert run.code == 0 and all(row.count(" | ") == 2 for row in rows), rows
    assert rows[-1] == "| `z\\|w.urdf` | moved | `from x\\|y.urdf, the same R^6 × S^1` |"


def test_a_rename_with_what_diff_ignores_is_still_moved(tmp_path: Path) -> None:
    """A fixed joint added and a limit moved within the tolerance: the same, so moved."""
    shutil.copy(REPO / "robots" / "arm7.urdf", tmp_path / "arm.urdf")
    written = run_cli("inspect", "--format", "jsonl", "arm.urdf", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(written.stdout)
    text = (tmp_path / "arm.urdf").read_text().replace('upper="2.9"', 'upper="2.9000001"', 1)
    camera = (
        '<link name="cam"/><joint name="cam_joint" type="fixed"><parent link="base_link"/>'
        '<child link="cam"/></joint></robot>'
    )
    (tmp_path / "arm2.urdf").write_text(text.replace("</robot>", camera))
    (tmp_path / "arm.urdf").unlink()
    run = run_cli("check", "--baseline", "baseline.jsonl", "arm2.urdf", cwd=tmp_path)
    assert run.code == 0 and run.stdout.startswith("moved: arm2.urdf: from arm.urdf"), run.stdout


def test_a_baseline_and_a_pinned_space_are_one_or_the_other() -> None:
    run = run_cli("check", "--baseline", "b.jsonl", "robots/arm7.urdf", "--expect", "R^7", cwd=REPO)
    assert run.code == 2 and "give one or the other" in run.stderr


def _two_reports(repo: Path) -> tuple[dict[str, object], dict[str, object]]:
    """arm7's report, and that of arm7 with a limit changed (as JSON documents)."""
    arm = (REPO / "robots" / "arm7.urdf").read_text()
    (repo / "changed.urdf").write_text(arm.replace('upper="2.9"', 'upper="2.5"', 1))
    (repo / "a.urdf").write_text(arm)
    run = run_cli("inspect", "--format", "jsonl", "a.urdf", "changed.urdf", cwd=repo)
    accepted, changed = (json.loads(line) for line in run.stdout.splitlines())
    (repo / "changed.urdf").unlink()
    return accepted, changed


def _line(document: dict[str, object], path: str) -> str:
    return json.dumps({**document, "source": {**document["source"], "path": path}})  # type: ignore[dict-item]


def test_two_lines_of_one_file_are_refused_naming_both(tmp_path: Path) -> None:
    """The accepted line for a.urdf and the changed report under another spelling of it:
    refused in one line naming both lines and the file, never `same` (issue 37). A link
    to a.urdf is a file of its own: its line is compared with what it reads."""
    repo = tmp_path / "repo"
    (repo / "sub").mkdir(parents=True)
    accepted, changed = _two_reports(repo)
    shutil.copy(repo / "a.urdf", repo / "sub" / "a.urdf")
    (repo / "link.urdf").symlink_to("a.urdf")
    (repo / "sub" / "up").symlink_to("..")  # a link inside the repository
    spellings = [
        ("a.urdf", "./a.urdf", "a.urdf"),
        ("sub/a.urdf", "sub//a.urdf", "sub/a.urdf"),
        ("a.urdf", "sub/../a.urdf", "a.urdf"),
        ("a.urdf", "sub/up/a.urdf", "a.urdf"),
        ("a.urdf", f"{repo}/a.urdf", "a.urdf"),
    ]
    for first, second, key in spellings:
        lines = [_line(accepted, first), "", _line(changed, second)]
        (repo / "b.jsonl").write_text("\n".join(lines) + "\n")
        run = run_cli("check", "--baseline", "b.jsonl", ".", cwd=repo)
        assert run.code == 2 and run.stdout == "", (second, run.stdout)
        assert run.stderr.count("\n") == 1 and run.stderr.endswith("[bad-report]\n")
        assert run.stderr.startswith(f"cspace: error: b.jsonl:3: a second report of '{key}'")
        assert "(the first at b.jsonl:1" in run.stderr, run.stderr
        assert second == key or f"as '{second}'" in run.stderr
    lines = [_line(accepted, "a.urdf"), _line(changed, "link.urdf"), _line(accepted, "sub/a.urdf")]
    (repo / "b.jsonl").write_text("\n".join(lines) + "\n")
    run = run_cli("check", "--baseline", "b.jsonl", ".", cwd=repo)
    assert run.code == 1 and "differs: link.urdf: R^6 × S^1, but limits differ" in run.stdout
    (repo / "b.jsonl").write_text(_line(accepted, "a.urdf") + "\n")
    for name in ("./a.urdf", "sub/../a.urdf"):  # each finds a.urdf's report
        run = run_cli("check", "--baseline", "b.jsonl", name, cwd=repo)
        assert run.code == 0 and run.stdout == f"same: {name}: R^6 × S^1\n", run.stdout
    run = run_cli("check", "--baseline", "b.jsonl", "link.urdf", cwd=repo)
    assert run.code == 1 and run.stdout == "new: link.urdf: R^6 × S^1, not in the baseline\n"


def test_a_baseline_never_reads_outside_the_folders_checked(tmp_path: Path) -> None:
    """Entries naming files outside the folder checked (by `..`, an absolute path, a
    link out of the tree; a hidden folder in it) are neither opened nor looked for, and
    the output is the same whether their files exist or not (issue 37). Each is an
    `outside` row that fails nothing and is a warning on the baseline's line, but one
    whose path lies in a folder named, there leading out through a link: that file has
    no report (exit 2), as a robot turned into such a link must not pass."""
    repo, outside = tmp_path / "repo", tmp_path / "outside"
    outside.mkdir()
    (repo / "sub").mkdir(parents=True)
    (repo / ".git").mkdir()
    accepted, _ = _two_reports(repo)
    arm = (repo / "a.urdf").read_text().replace('name="elbow"', f'name="{SECRET}"')
    (repo / "sub" / "up").symlink_to(tmp_path)  # committed: links out of the tree
    (repo / "sub" / "root").symlink_to("/")
    secrets = {
        "../outside/s1.urdf": outside / "s1.urdf",
        str(outside / "s2.urdf"): outside / "s2.urdf",
        "sub/up/outside/s3.urdf": outside / "s3.urdf",
        f"sub/root{outside}/s4.urdf": outside / "s4.urdf",
        ".git/s5.urdf": repo / ".git" / "s5.urdf",
    }
    lines = [_line(accepted, "a.urdf"), *(_line(accepted, name) for name in secrets)]
    (repo / "b.jsonl").write_text("\n".join(lines) + "\n")
    said = "in the baseline, but outside the folders checked: not read"
    linked = list(secrets)[2:4]
    hidden = (
        "outside: .git/s5.urdf: in the baseline, but hidden (a name starting with '.'): not read"
    )
    expected = {  # the folder named; the folder of a file named, only looked in
        ".": [
            "same: a.urdf: R^6 × S^1",
            *(
                f"no report: {name}: a folder of its path is a link out of the folders checked: "
                "not read"
                for name in sorted(linked)
            ),
            *(f"outside: {name}: {said}" for name in list(secrets)[:2]),
            hidden,
        ],
        "a.urdf": [
            "same: a.urdf: R^6 × S^1",
            *(f"outside: {name}: {said}" for name in list(secrets)[:2]),
            *(
                f"outside: {name}: in the baseline, but behind a link out of the folders "
                "checked: not read"
                for name in linked
            ),
            hidden,
        ],
    }
    runs = []
    for exists in (False, True):
        for file in secrets.values():
            if exists:
                file.write_text(arm)
        watches = [OpenWatch(outside), OpenWatch(repo / ".git")]
        runs.append(run_cli("check", "--baseline", "b.jsonl", ".", cwd=repo))
        runs.append(run_cli("check", "--baseline", "b.jsonl", "a.urdf", cwd=repo))
        assert [w.opened() for w in watches] == [[], []], "a file outside the tree was opened"
        for watch in watches:
            watch.close()
    for run, named in zip(runs, [".", "a.urdf"] * 2, strict=True):
        assert run.code == (2 if named == "." else 0), run.stderr
        assert run.stdout.splitlines() == expected[named], run.stdout
        assert SECRET not in run.stdout + run.stderr
        assert run.stderr.count("[outside-tree]\n") == (2 if named == "." else 0), run.stderr
    github = run_cli("check", "--baseline", "b.jsonl", "a.urdf", "--format", "github", cwd=repo)
    assert github.code == 0 and github.stdout.splitlines()[0] == (
        "::warning file=b.jsonl,line=2,title=cspace baseline%3A outside::../outside/s1.urdf: "
        f"{said} (remove the line, or check its folder)"
    )
    assert len(github.stdout.splitlines()) == 5 and SECRET not in github.stdout


@pytest.mark.bounded
def test_deep_paths_are_keyed_in_linear_time(tmp_path: Path) -> None:
    """500 baseline paths 1,900 names deep (as deep as 4,096 characters go) cost at
    most 5 times the CPU of 500 shallow ones (2.5 measured, each name looked at once;
    21 with each folder above it looked at for each name)."""
    count = 500
    robot = (
        '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute">'
        '<parent link="a"/><child link="b"/><limit lower="-1" upper="1" effort="1" '
        'velocity="1"/></joint></robot>'
    )
    (tmp_path / "r.urdf").write_text(robot)
    line = run_cli("inspect", "--format", "jsonl", "r.urdf", cwd=tmp_path).stdout
    cpu = {}
    for name, folder in (("deep", "/".join(["q"] * 1900)), ("shallow", "q")):
        lines = [
            line.replace('"path": "r.urdf"', f'"path": "{folder}/x{k}.urdf"') for k in range(count)
        ]
        (tmp_path / f"{name}.jsonl").write_text("".join(lines))
        run, cpu[name] = _cpu_of("check", "--baseline", f"{name}.jsonl", "r.urdf", cwd=tmp_path)
        assert run.code == 1 and run.stdout.count("\ngone: q/") == count - 1, run.stderr
    assert cpu["deep"] < 5 * cpu["shallow"], cpu


ARM = (
    '<robot name="arm"><link name="a"/><link name="b"/>\n<joint name="j" type="revolute">'
    '<parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" '
    'effort="1" velocity="1"/></joint></robot>'
)
"""A robot of one revolute joint (R^1), accepted into the baseline by `_accepted`."""


def _accepted(repo: Path) -> Path:
    """robots/arm.urdf (R^1) and robots/good.urdf (a point), and the baseline of robots/."""
    (repo / "robots").mkdir(parents=True, exist_ok=True)
    (repo / "robots" / "arm.urdf").write_text(ARM)
    (repo / "robots" / "good.urdf").write_text('<robot name="g"><link name="a"/></robot>')
    written = run_cli("inspect", "--format", "jsonl", "--", "robots", cwd=repo)
    assert written.code == 0, written.stderr
    (repo / "baseline.jsonl").write_text(written.stdout)
    return repo / "robots"


def _check(repo: Path, *robots: str, form: str = "text") -> Run:
    return run_cli(
        "check", "--baseline", "baseline.jsonl", "--format", form, "--", *robots, cwd=repo
    )


def test_a_robot_made_a_link_to_a_hidden_file_is_checked(tmp_path: Path) -> None:
    """A robot made continuous, moved to a hidden file and
    linked back (or its folder made hidden and linked back) passed as `outside`, unread.
    Its path is in the folder checked and not hidden as written: it is read through the
    link and compared."""
    robots = tmp_path / "robots"
    (robots / "sub").mkdir(parents=True)
    (robots / "sub" / "b.urdf").write_text(ARM)
    _accepted(tmp_path)
    continuous = ARM.replace("revolute", "continuous")
    (robots / ".arm.dat").write_text(continuous)
    (robots / "arm.urdf").unlink()
    (robots / "arm.urdf").symlink_to(".arm.dat")
    (robots / "sub").rename(robots / ".sub")
    (robots / ".sub" / "b.urdf").write_text(continuous)
    (robots / "sub").symlink_to(".sub")
    said = "R^1 -> S^1: C-space, q/v size, joint retyped, limits, q/v layout"
    run = _check(tmp_path, "./robots/")
    assert run.code == 1 and sorted(run.stdout.splitlines()) == [
        f"changed: robots/arm.urdf: {said}",
        f"changed: robots/sub/b.urdf: {said}",
        "same: robots/good.urdf: point",
    ], run.stdout
    github = _check(tmp_path, "robots", form="github")
    assert github.code == 1 and "::warning" not in github.stdout
    assert "::error file=robots/arm.urdf,line=2,title=cspace baseline%3A joint retyped::" in (
        github.stdout
    )


def test_a_robot_made_a_link_out_of_the_folder_has_no_report(tmp_path: Path) -> None:
    """A baselined robot made a link out of the folder checked
    (or a folder of its path made one) passed as `outside`. Its path is in the folder
    checked, so it is checked: the link out is refused, unread, and the robot has no
    report (exit 2); nothing outside is opened, and the output is the same whether the
    link's target exists or not."""
    robots = tmp_path / "repo" / "robots"
    (robots / "sub").mkdir(parents=True)
    (robots / "sub" / "arm.urdf").write_text(ARM)
    _accepted(tmp_path / "repo")
    vendor = tmp_path / "vendor"
    (vendor / "sub").mkdir(parents=True)
    arm = ARM.replace("revolute", "continuous").replace('name="j"', f'name="{SECRET}"')
    shutil.rmtree(robots / "sub")
    (robots / "sub").symlink_to("../../vendor/sub")
    (robots / "arm.urdf").unlink()
    (robots / "arm.urdf").symlink_to("../../vendor/arm.urdf")
    runs = []
    for exists in (False, True):
        if exists:
            for file in (vendor / "arm.urdf", vendor / "sub" / "arm.urdf"):
                file.write_text(arm)
        watches = [OpenWatch(vendor), OpenWatch(vendor / "sub")]
        runs.append(_check(tmp_path / "repo", "robots"))
        assert [w.opened() for w in watches] == [[], []], "a file outside the tree was opened"
        for watch in watches:
            watch.close()
    said = {(r.code, *(tuple(sorted(t.splitlines())) for t in (r.stdout, r.stderr))) for r in runs}
    assert len(said) == 1, said  # the same whether the links' targets exist or not
    assert runs[0].code == 2 and sorted(runs[0].stdout.splitlines()) == [
        "no report: robots/arm.urdf: robots/arm.urdf: is a link to a file outside its folder; "
        "cspace follows links only within the folder (name the target, or a wider folder "
        "with --allow-dir)",
        "no report: robots/sub/arm.urdf: a folder of its path is a link out of the folders "
        "checked: not read",
        "same: robots/good.urdf: point",
    ]
    assert SECRET not in runs[0].stdout + runs[0].stderr


def test_a_robot_made_a_link_to_another_robot_is_compared_with_its_own_line(
    tmp_path: Path,
) -> None:
    """Arm.urdf made a link to good.urdf (a link and its target
    taken as one file) had the baseline refused as holding two reports of one file. A
    link is a file of its own: each line is compared with what its path reads."""
    robots = _accepted(tmp_path)
    (robots / "arm.urdf").unlink()
    (robots / "arm.urdf").symlink_to("good.urdf")
    run = _check(tmp_path, "robots")
    assert run.code == 1 and sorted(run.stdout.splitlines()) == [
        "changed: robots/arm.urdf: R^1 -> point: C-space, q/v size, joint removed",
        "same: robots/good.urdf: point",
    ]


MJCF_ARM = (
    '<mujoco model="arm"><worldbody><body name="b"><joint name="j" type="hinge" '
    'limited="true" range="-1 1"/><geom size="0.1"/></body></worldbody></mujoco>'
)
"""An MJCF robot of one hinge (R^1): a folder's search finds it by its content only."""

JSON_IS_NO_ROBOT = (
    "is JSON, not a robot description (check --baseline reads robot files, never saved reports)"
)


def test_a_saved_report_in_a_robots_place_has_no_report(tmp_path: Path) -> None:
    """A baselined robot replaced with a line of the baseline
    (another robot's, or its own) was read as a saved report, whose `source.path` chose
    the line it was compared with: `same` (twice for the other robot's), the robot's own
    line never compared nor gone, exit 0, no annotation. With --baseline a file is read
    as a robot only, compared with its own path's line: JSON where a robot was has no
    report (exit 2, one line), found by a folder's search (`.urdf`) or not (`.xml`)."""
    robots = _accepted(tmp_path)
    (robots / "arm.xml").write_text(MJCF_ARM)
    written = run_cli("inspect", "--format", "jsonl", "--", "robots", cwd=tmp_path)
    (tmp_path / "baseline.jsonl").write_text(written.stdout)
    line = {json.loads(x)["source"]["path"]: x for x in written.stdout.splitlines()}
    (robots / "arm.xml").write_text(line["robots/good.urdf"])  # another robot's line
    (robots / "arm.urdf").write_text(line["robots/arm.urdf"])  # its own line
    expected = [
        f"no report: robots/arm.urdf: robots/arm.urdf: {JSON_IS_NO_ROBOT}",
        f"no report: robots/arm.xml: robots/arm.xml: {JSON_IS_NO_ROBOT}",
        "same: robots/good.urdf: point",
    ]
    names = ("robots/arm.xml", "robots/arm.urdf", "robots/good.urdf")
    for named in (["robots"], names):
        run = _check(tmp_path, *named)
        assert run.code == 2 and sorted(run.stdout.splitlines()) == expected, run.stdout
        assert sorted(run.stderr.splitlines()) == [
            f"cspace: error: {name}: {JSON_IS_NO_ROBOT} [not-a-robot]" for name in names[1::-1]
        ], run.stderr
    github = _check(tmp_path, "robots", form="github")
    assert github.code == 2 and sorted(github.stdout.splitlines()) == [
        f"::error file={name},title=cspace baseline%3A no report::{name}: {JSON_IS_NO_ROBOT}"
        for name in names[1::-1]
    ]


def test_a_saved_report_naming_a_baselined_path_stands_for_no_file(tmp_path: Path) -> None:
    """A committed saved report (named `x.urdf`, so a folder's
    search finds it) giving a baselined robot's path and accepted report made that path
    `same`: the robot itself, turned fragment or deleted, was never read, nor gone. The
    report is no robot (no report), and the robot's own line is compared with the robot."""
    robots = _accepted(tmp_path)
    line = (tmp_path / "baseline.jsonl").read_text().splitlines()[0]
    assert '"path": "robots/arm.urdf"' in line
    (robots / "forged.urdf").write_text(line)
    (robots / "arm.urdf").write_text("not a robot any more\n")
    run = _check(tmp_path, "robots")
    assert run.code == 2 and "no report: robots/arm.urdf: " in run.stdout, run.stdout
    assert f"no report: robots/forged.urdf: robots/forged.urdf: {JSON_IS_NO_ROBOT}" in run.stdout
    (robots / "arm.urdf").unlink()
    run = _check(tmp_path, "robots")
    assert run.code == 2 and "no report: robots/forged.urdf: " in run.stdout, run.stdout
    assert "gone: robots/arm.urdf: in the baseline, but the file is gone" in run.stdout


def test_a_line_through_a_link_into_version_control_is_hidden_unread(tmp_path: Path) -> None:
    """With `g -> .git` committed, a baseline line of `g/config`
    (not hidden as written) had `.git/config` opened and parsed. A line whose folders'
    links lead into `.git`, `.hg` or `.svn` is hidden: an `outside` row that fails
    nothing, never opened; a robot named so is refused unread (exit 2)."""
    robots = _accepted(tmp_path)
    (tmp_path / ".git").mkdir()
    for name in ("config", "HEAD"):
        (tmp_path / ".git" / name).write_text(f"[remote]\n\ttoken = {SECRET}\n")
    (tmp_path / "g").symlink_to(".git")
    (robots / "up").symlink_to("..")  # inside the tree
    lines = (tmp_path / "baseline.jsonl").read_text().splitlines()
    good = json.loads(lines[1])
    paths = ("g/config", "robots/up/g/HEAD")
    (tmp_path / "b.jsonl").write_text("\n".join([*lines, *(_line(good, p) for p in paths)]))
    watch = OpenWatch(tmp_path / ".git")
    try:
        run = run_cli("check", "--baseline", "b.jsonl", "--", ".", cwd=tmp_path)
        named = run_cli("check", "--baseline", "b.jsonl", "--", "g/config", cwd=tmp_path)
        assert watch.opened() == [], "a file in .git was opened"
    finally:
        watch.close()
    said = "in the baseline, but hidden (a link among its folders leads into .git, .hg or .svn)"
    assert run.code == 0 and sorted(run.stdout.splitlines()) == [
        *(f"outside: {p}: {said}: not read" for p in paths),
        "same: robots/arm.urdf: R^1",
        "same: robots/good.urdf: point",
    ], run.stdout
    assert named.code == 2 and named.stderr.endswith(
        "cspace: error: g/config: a folder of this path is a link into a version-control "
        "folder (.git, .hg, .svn), which cspace never reads [outside-tree]\n"
    ), named.stderr
    assert SECRET not in run.stdout + run.stderr + named.stdout + named.stderr
