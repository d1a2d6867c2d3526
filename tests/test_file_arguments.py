"""Every command-line argument that names a file goes through the same rules.

The parser is walked: each argument of each command is either a file read, a file
written, a folder the user grants, or no file at all, and a new argument that is not
classified here fails the first test. Then every file read is given, in a tree an
attacker committed, a link to a secret file beside the tree, a path through a linked
folder out of the tree, and a FIFO: each is refused in one line, within the time and
memory bounds, quoting nothing of the secret, opening nothing beside the tree. Every
file written is never written through a link or over a FIFO, and never keeps an exec
bit. A control run with a good file proves each command line is otherwise valid.

The bounds are on what a file makes cspace do: the commands are measured forked
(``measured(forked=True)``), their interpreter's start-up left out.
"""

from __future__ import annotations

import argparse
import os
import shutil
import stat
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import cspace

from conftest import (
    REPO,
    ROBOTS,
    OpenWatch,
    assert_bounded_error,
    measured,
    run_cli,
)

SECRET = "TOKEN-ghp-7a1c0ffee"

READS: dict[tuple[str, str], tuple[str, str]] = {
    # (command, argument): (the command line, FILE standing for the file; a good file)
    ("inspect", "robot"): ("inspect FILE", "ok.urdf"),
    ("inspect", "srdf"): ("inspect ok.urdf --srdf FILE", "ok.srdf"),
    ("check", "srdf"): ("check ok.urdf --expect R^6×T^1 --srdf FILE", "ok.srdf"),
    ("diff", "srdf"): ("diff ok.urdf ok.urdf --srdf FILE", "ok.srdf"),
    ("sample", "srdf"): ("sample ok.urdf --srdf FILE", "ok.srdf"),
    ("distance", "srdf"): ("distance ok.urdf {} {} --partial --srdf FILE", "ok.srdf"),
    ("interpolate", "srdf"): ("interpolate ok.urdf {} {} --partial --srdf FILE", "ok.srdf"),
    ("unwrap", "srdf"): ("unwrap ok.urdf q.csv --srdf FILE", "ok.srdf"),
    ("convert", "srdf"): (
        "convert ok.urdf q.csv --from canonical --to named --srdf FILE",
        "ok.srdf",
    ),
    ("diff", "old"): ("diff FILE ok.urdf", "ok.urdf"),
    ("diff", "new"): ("diff ok.urdf FILE", "report.json"),
    ("check", "robot"): ("check FILE --dimension 7", "report.json"),
    ("check", "baseline"): ("check ok.urdf --baseline FILE", "baseline.jsonl"),
    ("sample", "robot"): ("sample FILE", "ok.urdf"),
    ("distance", "robot"): ("distance FILE {} {} --partial", "ok.urdf"),
    ("distance", "a"): ("distance ok.urdf @FILE {} --partial", "q.json"),
    ("distance", "b"): ("distance ok.urdf {} @FILE --partial", "q.json"),
    ("interpolate", "robot"): ("interpolate FILE {} {} --partial", "ok.urdf"),
    ("interpolate", "a"): ("interpolate ok.urdf @FILE {} --partial", "q.json"),
    ("interpolate", "b"): ("interpolate ok.urdf {} @FILE --partial", "q.json"),
    ("convert", "robot"): ("convert FILE q.csv --from canonical --to named", "ok.urdf"),
    ("convert", "file"): ("convert ok.urdf FILE --from canonical --to named", "q.csv"),
    ("convert", "mujoco"): (
        "convert ok.urdf q.csv --from canonical --to mujoco --mujoco FILE",
        "ok.xml",
    ),
    ("convert", "at"): (
        "convert ok.urdf v.csv --velocity --from canonical --to pinocchio --at FILE",
        "q.csv",
    ),
    ("unwrap", "robot"): ("unwrap FILE q.csv", "ok.urdf"),
    ("unwrap", "file"): ("unwrap ok.urdf FILE", "q.csv"),
    ("unwrap", "mujoco"): ("unwrap ok.urdf q.csv --convention mujoco --mujoco FILE", "ok.xml"),
    ("inspect", "limits"): ("inspect ok.urdf --limits FILE", "limits.yaml"),
    ("check", "limits"): ("check ok.urdf --expect R^6×T^1 --limits FILE", "limits.yaml"),
    ("diff", "limits"): ("diff ok.urdf ok.urdf --limits FILE", "limits.yaml"),
    ("diff", "old_limits"): ("diff ok.urdf ok.urdf --old-limits FILE", "limits.yaml"),
    ("diff", "new_limits"): ("diff ok.urdf ok.urdf --new-limits FILE", "limits.yaml"),
    ("sample", "limits"): ("sample ok.urdf --limits FILE", "limits.yaml"),
    ("distance", "limits"): ("distance ok.urdf {} {} --partial --limits FILE", "limits.yaml"),
    ("interpolate", "limits"): ("interpolate ok.urdf {} {} --partial --limits FILE", "limits.yaml"),
    ("unwrap", "limits"): ("unwrap ok.urdf q.csv --limits FILE", "limits.yaml"),
    ("convert", "limits"): (
        "convert ok.urdf q.csv --from canonical --to named --limits FILE",
        "limits.yaml",
    ),
    ("collisions", "robot"): ("collisions FILE -n 10", "ok.urdf"),
    ("collisions", "srdf"): ("collisions ok.urdf -n 10 --srdf FILE", "ok.srdf"),
}
"""Every argument that names a file cspace reads."""

WRITES: dict[tuple[str, str], str] = {
    ("sample", "output"): "sample ok.urdf -n 3 --format csv -o FILE",
    ("interpolate", "output"): "interpolate ok.urdf {} {} --partial -o FILE",
    ("collisions", "write_srdf"): "collisions ok.urdf -n 10 --write-srdf FILE",
}
"""Every argument that names a file cspace writes."""

WRITTEN = {("collisions", "write_srdf"): '<robot name="arm7">'}
"""What a file written holds, when not the joint ``shoulder_pan`` (arm7 has no collision
shapes: its SRDF names no link)."""

REFUSED = {("collisions", "limits"): "collisions ok.urdf -n 10 --limits FILE"}
"""Arguments a command's parser shares with the other commands' and refuses before any
file is read (`cspace collisions` samples the URDF's limits: no joint_limits.yaml)."""

WRITES_FOLDERS = {("inspect", "output_dir")}
"""Every argument that names a folder cspace writes files into (tested below)."""

GRANTS = {"allow_dir", "package_path"}
"""Folders the user grants (MJCF includes, xacro packages): trust, not input."""

NOT_FILES = {
    "format", "root_joint", "arg", "xacro", "xacro_unconfined", "color", "strict", "ignore",
    "hide_fixed", "jobs", "width", "tolerance", "rel_tolerance", "map", "old_root_joint",
    "new_root_joint", "expect", "dimension", "n", "seed", "bounds", "partial", "weight",
    "steps", "source", "target", "velocity", "names", "input_names", "convention", "inverse",
    "shell", "help", "robots_only", "group", "hold", "old_order", "new_order", "collisions",
}  # fmt: skip
"""Arguments that name no file."""


def _arguments() -> Iterator[tuple[str, str]]:
    from cspace._cli.main import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for command, subparser in sub.choices.items():
        for action in subparser._actions:
            yield command, action.dest


def test_every_argument_that_names_a_file_is_known() -> None:
    unknown = [
        (command, dest)
        for command, dest in _arguments()
        if (command, dest) not in READS
        and (command, dest) not in WRITES
        and (command, dest) not in WRITES_FOLDERS
        and (command, dest) not in REFUSED
        and dest not in GRANTS | NOT_FILES
    ]
    assert unknown == [], f"classify these arguments in {__file__}: {unknown}"
    every = set(_arguments())
    assert set(READS) | set(WRITES) | WRITES_FOLDERS | set(REFUSED) <= every  # none stale


@pytest.fixture(scope="module")
def generated(tmp_path_factory: pytest.TempPathFactory) -> dict[str, str]:
    """The good files that cspace writes, made once: a configuration and a velocity file,
    a saved report and a baseline of ``ok.urdf`` (its path relative: the same in any tree)."""
    root = tmp_path_factory.mktemp("generated")
    shutil.copy(ROBOTS / "arm7.urdf", root / "ok.urdf")
    space = cspace.load(ROBOTS / "arm7.urdf")
    rows = space.sample(3, np.random.default_rng(0))
    lines = "".join(",".join(map(repr, r)) + "\n" for r in rows.tolist())
    tangent = space.conventions().names("canonical", True)
    zeros = ",".join(["0.0"] * len(tangent)) + "\n"
    return {
        "q.csv": ",".join(space.names) + "\n" + lines,
        "v.csv": ",".join(tangent) + "\n" + zeros * len(rows),
        "report.json": run_cli("inspect", "ok.urdf", "--format", "json", cwd=root).stdout,
        "baseline.jsonl": run_cli("inspect", "ok.urdf", "--format", "jsonl", cwd=root).stdout,
    }


@pytest.fixture
def tree(tmp_path: Path, generated: dict[str, str]) -> Path:
    """A checkout with good files, and a folder beside it holding a secret."""
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "secret").write_text(f"{SECRET}\n")
    (outside / "target.csv").write_text("old\n")
    root = tmp_path / "tree"
    root.mkdir()
    shutil.copy(ROBOTS / "arm7.urdf", root / "ok.urdf")
    shutil.copy(REPO / "tests" / "pairs" / "arm7.xml", root / "ok.xml")
    for name, text in generated.items():
        (root / name).write_text(text)
    (root / "q.json").write_text('{"shoulder_pan": 0.25}\n')
    (root / "ok.srdf").write_text('<robot name="arm7"><group name="g"/></robot>\n')
    (root / "limits.yaml").write_text("joint_limits:\n  shoulder_pan: {max_position: 1.0}\n")
    (root / "evil").symlink_to("../outside/secret")
    (root / "data").symlink_to("../outside")
    os.mkfifo(root / "pipe")
    return root


def _command(template: str, file: str) -> list[str]:
    """The command line with ``file`` for FILE; each ``{}`` is a configuration of every
    joint at its neutral value (``--partial``)."""
    return [part.replace("FILE", file) for part in template.split()]


_VALID: set[tuple[str, str]] = set()
"""The arguments whose command line ran with a good file (in this worker)."""

HOSTILE = {
    "link out of the tree": ("evil", "outside-tree"),
    "through a linked folder": ("data/secret", "outside-tree"),
    "FIFO": ("pipe", "file-unreadable"),
}


@pytest.mark.bounded
@pytest.mark.parametrize("case", sorted(HOSTILE))
@pytest.mark.parametrize("argument", sorted(READS), ids="-".join)
def test_every_file_read_is_opened_under_the_rules(
    argument: tuple[str, str], case: str, tree: Path
) -> None:
    template, good = READS[argument]
    if argument not in _VALID:  # the command line is valid: once for each argument
        control = run_cli(*_command(template, good), cwd=tree)
        assert control.code in (0, 1), (argument, control.stderr)
        _VALID.add(argument)
    name, code = HOSTILE[case]
    watch = OpenWatch(tree.parent / "outside")
    try:
        result = measured(*_command(template, name), cwd=tree, forked=True)
        assert watch.opened() == [], "a file beside the tree was opened"
    finally:
        watch.close()
    line = assert_bounded_error(result, code)
    assert SECRET not in line and name in line


@pytest.mark.bounded
@pytest.mark.parametrize("argument", sorted(WRITES), ids="-".join)
def test_outputs_are_never_written_through_a_link_or_over_a_special_file(
    argument: tuple[str, str], tree: Path
) -> None:
    template = WRITES[argument]
    target = tree.parent / "outside" / "target.csv"
    (tree / "out.csv").symlink_to("../outside/target.csv")
    for name in ("out.csv", "data/new.csv", "pipe"):
        result = measured(*_command(template, name), cwd=tree, forked=True)
        assert name in assert_bounded_error(result, "bad-output")
        assert target.read_text() == "old\n"
        assert sorted(p.name for p in target.parent.iterdir()) == ["secret", "target.csv"]
    assert stat.S_ISFIFO((tree / "pipe").lstat().st_mode)


@pytest.mark.parametrize("argument", sorted(WRITES), ids="-".join)
def test_an_output_is_replaced_whole_and_keeps_no_exec_bit(
    argument: tuple[str, str], tree: Path
) -> None:
    out = tree / "run.sh"
    out.write_text("#!/bin/sh\necho committed\n")
    out.chmod(0o750)
    run = run_cli(*_command(WRITES[argument], "run.sh"), cwd=tree)
    assert run.code == 0, run.stderr
    assert stat.S_IMODE(out.stat().st_mode) == 0o640  # its read and write bits, no exec
    held = WRITTEN.get(argument, "shoulder_pan")
    assert "committed" not in out.read_text() and held in out.read_text()
    fresh = tree / "fresh.csv"
    umask = os.umask(0o022)
    os.umask(umask)
    assert run_cli(*_command(WRITES[argument], "fresh.csv"), cwd=tree).code == 0
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o666 & ~umask
    assert fresh.read_bytes() == out.read_bytes()
    leftovers = [p.name for p in tree.iterdir() if p.name.endswith(".tmp")]
    assert leftovers == []


@pytest.mark.bounded
@pytest.mark.parametrize("argument", sorted(REFUSED), ids="-".join)
def test_an_argument_refused_opens_nothing(argument: tuple[str, str], tree: Path) -> None:
    watch = OpenWatch(tree.parent / "outside")
    try:
        result = measured(*_command(REFUSED[argument], "evil"), cwd=tree, forked=True)
        assert watch.opened() == [], "a file beside the tree was opened"
    finally:
        watch.close()
    line = assert_bounded_error(result, "bad-argument")
    assert SECRET not in line and "does not apply" in line


OPENERS = {"open", "fdopen", "read_text", "read_bytes", "write_text", "write_bytes", "load"}
"""Calls that open a file (``open``, ``os.open``, ``Path.open``, ``np.load``, ...)."""

OTHER_OPENS = {
    "cspace/_confine/landlock.py": "an O_PATH descriptor of a granted folder, for its rule",
    "cspace/_confine/sandbox.py": "a child's own standard output and /dev/null (quiet_stdout)",
    "cspace/_confine/serving.py": "a serving child's own /proc/self/statm, before it confines",
    "cspace/_formats/usd/_layers.py": "a USD layer's bytes, in the confined child, once checked",
    "cspace/_model/native.py": "a memfd for Pinocchio's parser messages",
    "cspace/_render/html.py": "the package's own HTML templates",
    "cspace/_schema/__init__.py": "the package's own JSON Schema",
}
"""Where code opens something other than a file a user named, and what."""


def test_no_file_is_opened_but_through_cspace_files() -> None:
    """One way in and out: only cspace/files.py opens what a user names."""
    import ast

    opened = set()
    for path in (REPO / "src" / "cspace").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Call):
                func = node.func
                name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
                if name in OPENERS:
                    opened.add(str(path.relative_to(REPO / "src")))
    assert opened - {"cspace/files.py"} == set(OTHER_OPENS)


@pytest.mark.bounded
def test_an_absolute_path_below_the_current_folder_is_held_to_the_same_rules(
    tree: Path,
) -> None:
    # CI scripts name files as $GITHUB_WORKSPACE/...: the committed link is still refused.
    (tree.parent / "outside" / "traj.csv").write_text(f"{SECRET},x\n")
    args = ("convert", "ok.urdf", str(tree / "data" / "traj.csv"), "--from", "canonical")
    line = assert_bounded_error(
        measured(*args, "--to", "named", cwd=tree, forked=True), "outside-tree"
    )
    assert SECRET not in line and "the folder 'data'" in line


@pytest.mark.bounded
@pytest.mark.parametrize("option", ["--allow-dir", "--package-path"])
def test_a_granted_folder_that_is_a_committed_link_out_is_refused(option: str, tree: Path) -> None:
    (tree / "r.xacro").write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="b"/></robot>\n'
    )
    (tree / "r.xml").write_text('<mujoco><include file="data/secret"/></mujoco>\n')
    robot = "r.xml" if option == "--allow-dir" else "r.xacro"
    result = measured("inspect", option, "data", robot, cwd=tree, forked=True)
    line = assert_bounded_error(result, "outside-tree")
    assert SECRET not in line and line.startswith("cspace: error: data: ")


@pytest.mark.bounded
def test_a_chain_of_links_too_long_to_follow_is_refused(tree: Path) -> None:
    previous = "ok.urdf"
    for k in range(1200):  # Python's realpath recurses once per link
        (tree / f"l{k}").symlink_to(previous)
        previous = f"l{k}"
    assert_bounded_error(measured("inspect", previous, cwd=tree, forked=True), "outside-tree")


@pytest.mark.bounded
def test_a_pattern_match_named_like_standard_input_is_that_file(tree: Path) -> None:
    shutil.copy(tree / "ok.urdf", tree / "-")
    (tree / "evil").unlink()
    (tree / "data").unlink()
    result = measured(
        "inspect", "*.urdf", "-", "--format", "jsonl", cwd=tree, stdin=b"", forked=True
    )
    assert result.run.code == 2  # a bare `-` is standard input (empty here) ...
    (tree / "pipe").unlink()
    result = measured(
        "inspect", "[-]", "*.urdf", "--format", "jsonl", cwd=tree, stdin=b"", forked=True
    )
    reports = result.run.stdout.splitlines()  # ... but `-` matched by a pattern is the file
    assert result.run.code == 0 and len(reports) == 2, result
    assert '"path": "./-"' in reports[0]


def test_an_output_with_a_long_name_is_written(tree: Path) -> None:
    name = "o" * 250  # the file system's limit is 255: the temporary name is short
    assert run_cli("sample", "ok.urdf", "-o", name, cwd=tree).code == 0
    assert (tree / name).read_text().startswith('{"robot": "arm7"')


@pytest.mark.bounded
def test_package_manifests_are_read_within_a_budget(tree: Path) -> None:
    # identical manifests: tiny in git; 200 of a megabyte each took 25 s to parse before
    (tree / "r.xacro").write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="b"/></robot>\n'
    )
    for k, tags in enumerate([240_000] + [60_000] * 10):
        folder = tree / f"pkgs{min(k, 1)}" / f"p{k}"
        folder.mkdir(parents=True)
        (folder / "package.xml").write_text(f"<package><name>p{k}</name>{'<x/>' * tags}</package>")
    large = measured("inspect", "--package-path", "pkgs0", "r.xacro", cwd=tree, forked=True)
    assert "package.xml is 960,0" in assert_bounded_error(large, "file-unreadable")
    many = measured("inspect", "--package-path", "pkgs1", "r.xacro", cwd=tree, forked=True)
    assert "250,000 XML tags" in assert_bounded_error(many, "too-much-input")


@pytest.mark.bounded
def test_a_link_that_cannot_be_followed_is_one_files_error_in_a_pattern(tree: Path) -> None:
    (tree / "loop.urdf").symlink_to("loop.urdf")
    (tree / "x.urdf").symlink_to("ok.urdf/x")
    result = measured("inspect", "*.urdf", "--format", "jsonl", cwd=tree, forked=True)
    assert result.run.code == 2 and len(result.run.stdout.splitlines()) == 1  # ok.urdf
    errors = result.run.stderr.splitlines()
    assert [e.split(": ")[2] for e in errors] == ["loop.urdf", "x.urdf"]
    assert all(e.endswith("[file-unreadable]") for e in errors)


def _cpu_seconds(pid: int) -> float:
    """The CPU time (user + system) a running process has used, from ``/proc``; 0 once gone."""
    import os

    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


@pytest.mark.bounded
def test_an_output_cut_short_by_sigterm_leaves_the_old_file_and_nothing_beside(
    tree: Path,
) -> None:
    # a CI job cancelled or timed out gets SIGTERM: the temporary file is removed
    import subprocess
    import time

    from conftest import cspace_command

    (tree / "big.csv").write_text("old\n")
    command = [*cspace_command(), "sample", "ok.urdf", "-n", "50000000", "--format", "csv"]
    running = subprocess.Popen([*command, "-o", "big.csv"], cwd=tree, stderr=subprocess.PIPE)
    # Guards in the command's own CPU time, so that a busy machine, starting it late or
    # slowly, cannot fail the test: it starts writing within 60 s of CPU, exits on SIGTERM.
    while not list(tree.glob(".cspace-*.tmp")) and running.poll() is None:
        assert _cpu_seconds(running.pid) < 60, "the output was never started"
        time.sleep(0.05)
    assert list(tree.glob(".cspace-*.tmp")), "the output was never started"
    running.terminate()
    while running.poll() is None:
        assert _cpu_seconds(running.pid) < 90, "SIGTERM did not end the command"
        time.sleep(0.05)
    assert running.returncode == 143
    assert (tree / "big.csv").read_text() == "old\n"
    assert list(tree.glob(".cspace-*.tmp")) == []


@pytest.mark.bounded
def test_a_parent_folder_after_a_link_is_refused(tree: Path) -> None:
    # `d/ok -> .` stays in its folder, but d/ok/../../x.csv is outside the tree,
    # although it reads as x.csv
    (tree / "d").mkdir()
    (tree / "d" / "ok").symlink_to(".")
    (tree.parent / "x.csv").write_text(f"{SECRET}\n")
    for args, code in (
        (("convert", "ok.urdf", "d/ok/../../x.csv", "--from", "canonical", "--to", "named"),
         "outside-tree"),
        (("sample", "ok.urdf", "-o", "d/ok/../../x.csv"), "bad-output"),
    ):  # fmt: skip
        line = assert_bounded_error(measured(*args, cwd=tree, forked=True), code)
        assert SECRET not in line and "'..' follows the link 'd/ok'" in line
    assert (tree.parent / "x.csv").read_text() == f"{SECRET}\n"


def test_vector_chunks_are_bounded_in_numbers_and_grouped_by_set_of_names() -> None:
    # 4,096 rows of a 5,000-joint robot held 2.3 GB in one chunk; a new order of the same
    # names on every line made a chunk of each row
    import io

    from cspace._cli.vectors import CHUNK_NUMBERS, VectorReader

    wide = "".join("[" + ", ".join(["0.5"] * 5000) + "]\n" for _ in range(100))
    chunks = list(VectorReader(io.BytesIO(wide.encode()), "wide.jsonl").chunks(5000))
    assert sum(len(c.rows) for c in chunks) == 100
    assert all(c.rows.size <= CHUNK_NUMBERS for c in chunks) and len(chunks) > 1
    lines = "".join(
        '{"name": ["a", "b"], "position": [1, 2]}\n{"name": ["b", "a"], "position": [2, 1]}\n'
        for _ in range(50)
    )
    reader = VectorReader(io.BytesIO(lines.encode()), "state.jsonl")
    (chunk,) = reader.chunks(None, names=lambda names: None)
    assert chunk.names == ("a", "b") and chunk.rows.tolist() == [[1.0, 2.0]] * 100


@pytest.mark.bounded
def test_an_unclosed_csv_quote_is_refused(tree: Path) -> None:
    header = (tree / "q.csv").read_text().splitlines()[0]
    (tree / "bad.csv").write_text(header + '\n"1' + ",0" * (header.count(",")) + "\n")
    args = ("convert", "ok.urdf", "bad.csv", "--from", "canonical", "--to", "named")
    result = measured(*args, cwd=tree, forked=True)  # the header row is out before row 2 is read
    assert result.run.code == 2 and result.run.stderr.count("\n") == 1
    assert "bad.csv:2: is not a CSV row" in result.run.stderr


@pytest.mark.bounded
def test_a_folder_of_pages_is_never_written_through_a_link_or_over_a_special_file(
    tree: Path,
) -> None:
    """``inspect --output-dir``: the folder, and each page in it, as ``-o`` files are."""
    outside = tree.parent / "outside"
    before = sorted(p.name for p in outside.iterdir())
    for folder in ("data", "data/new"):  # a committed link out, and a folder made through it
        result = measured(
            "inspect", "ok.urdf", "--format", "html", "--output-dir", folder, cwd=tree, forked=True
        )
        assert folder in assert_bounded_error(result, "bad-output")
    (tree / "pages").mkdir()
    (tree / "pages" / "1-ok.urdf.html").symlink_to("../../outside/target.csv")
    os.mkfifo(tree / "pages" / "index.html")
    args = ("inspect", "ok.urdf", "--format", "html", "--output-dir", "pages")
    assert "1-ok.urdf.html" in assert_bounded_error(
        measured(*args, cwd=tree, forked=True), "bad-output"
    )
    (tree / "pages" / "1-ok.urdf.html").unlink()
    assert "index.html" in assert_bounded_error(
        measured(*args, cwd=tree, forked=True), "bad-output"
    )
    assert sorted(p.name for p in outside.iterdir()) == before
    assert (outside / "target.csv").read_text() == "old\n"
    (tree / "pages" / "index.html").unlink()
    done = run_cli(*args, cwd=tree)
    assert done.code == 0 and done.stderr.endswith(
        "cspace: note: wrote 1 page and pages/index.html\n"
    )
    assert all(stat.S_IMODE(p.stat().st_mode) & 0o111 == 0 for p in (tree / "pages").iterdir())


@pytest.mark.bounded
def test_a_link_into_a_version_control_folder_is_refused_unread(tree: Path) -> None:
    """A committed ``robot.urdf -> .git/...`` stays inside its folder, yet leads where a CI
    checkout keeps its token: refused unread, named or met in a folder's search."""
    (tree / ".git").mkdir()
    (tree / ".git" / "desc.urdf").write_text(f'<robot name="{SECRET}"><link name="a"/></robot>\n')
    (tree / "robot.urdf").symlink_to(".git/desc.urdf")
    line = assert_bounded_error(
        measured("inspect", "--", "robot.urdf", cwd=tree, forked=True), "outside-tree"
    )
    assert SECRET not in line and "version-control folder" in line
    done = measured("inspect", "--format", "jsonl", "--", ".", cwd=tree, forked=True)
    assert done.run.code == 2 and SECRET not in done.run.stdout + done.run.stderr
    assert "robot.urdf: is a link into a version-control folder" in done.run.stderr
    (tree / "robot.urdf").unlink()
    (tree / "g").symlink_to(".git")  # stays in its folder; `g/desc.urdf` is in `.git`
    line = assert_bounded_error(
        measured("inspect", "--", "g/desc.urdf", cwd=tree, forked=True), "outside-tree"
    )
    assert SECRET not in line
    assert "g/desc.urdf: a folder of this path is a link into a version-control" in line
    named = run_cli("inspect", "--", ".git/desc.urdf", cwd=tree)  # named as it is: read
    assert named.code == 0 and SECRET in named.stdout, named.stderr
