"""Depth is a documented limit, never a crash: at the limit a report, past it one line.

For every format, a kinematic tree exactly as deep as cspace reads gets a report within
the time and memory bounds, and one level deeper is refused with ``too-deep``, exit 2,
one line. So does the tree whose joints' depths add up to the most cspace reads, in the
shape that takes Pinocchio the most memory for it, and the same tree one level deeper.
MJCF bodies are counted through includes and attached models, and elements nested
through includes (frames, which are no bodies) are bounded too. The cases run the
`cspace` command forked (``conftest.measured(forked=True)``: the bounds are on what the
file makes cspace do, its interpreter's start-up left out), but for the trees at the
depth-sum limit, which come nearest the memory bound: those run the installed script as
a user runs it, start-up and all.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from cspace._formats.mjcf._prescan import MAX_BODY_DEPTH, MAX_NESTING
from cspace._formats.shared.robot_size import DOF, MAX_DEPTH, MAX_DEPTH_SUM, MAX_DOF, MAX_JOINTS
from cspace._joint_kind import JointKind

from conftest import PEAK_MIB, SECONDS, assert_bounded_error, measured

PER_FILE = 200
"""Levels an MJCF file nests before it includes the next (one file nests at most 256)."""


def _urdf_chain(folder: Path, depth: int, name: str = "snake.urdf") -> str:
    parts = ['<robot name="snake">', '<link name="l0"/>']
    parts += [
        f'<link name="l{k}"/><joint name="j{k}" type="continuous"><parent link="l{k - 1}"/>'
        f'<child link="l{k}"/></joint>'
        for k in range(1, depth + 1)
    ]
    (folder / name).write_text("\n".join([*parts, "</robot>"]))
    return name


def _xacro_chain(folder: Path, depth: int) -> str:
    return _urdf_chain(folder, depth, "snake.urdf.xacro")  # expanded by xacro, confined


def _sdf_chain(folder: Path, depth: int) -> str:
    # the chain hangs from the world: a free first link would float (one joint deeper)
    parts = ['<sdf version="1.7"><model name="snake">']
    parts += [
        f'<link name="l{k}"/><joint name="j{k}" type="continuous">'
        f"<parent>{f'l{k - 1}' if k > 1 else 'world'}</parent><child>l{k}</child></joint>"
        for k in range(1, depth + 1)
    ]
    (folder / "snake.sdf").write_text("\n".join([*parts, "</model></sdf>"]))
    return "snake.sdf"


def _mjcf_nested(folder: Path, levels: list[tuple[str, str]]) -> str:
    """``levels`` (start tag, end tag) nested inside one another in ``<worldbody>``.

    :data:`PER_FILE` levels a file, each file including the next where its levels end.
    """
    chunks = [levels[k : k + PER_FILE] for k in range(0, len(levels), PER_FILE)]
    for k, chunk in enumerate(chunks):
        inner = f'<include file="part{k + 1}.xml"/>' if k + 1 < len(chunks) else ""
        text = "".join(s for s, _ in chunk) + inner + "".join(e for _, e in reversed(chunk))
        if k == 0:
            text = f'<mujoco model="deep"><worldbody>{text}</worldbody></mujoco>'
            (folder / "deep.xml").write_text(text)
        else:
            (folder / f"part{k}.xml").write_text(f"<mujocoinclude>{text}</mujocoinclude>")
    return "deep.xml"


def _mjcf_chain(folder: Path, depth: int) -> str:
    body = '<body name="b{0}"><joint name="j{0}"/><geom size=".1"/>'
    return _mjcf_nested(folder, [(body.format(k), "</body>") for k in range(depth)])


def _mjcf_frames(folder: Path, nesting: int) -> str:
    # <mujoco> 1, <worldbody> 2, the body 3, then frames: the last nests `nesting` deep.
    body = ('<body name="b"><joint name="j"/><geom size=".1"/>', "</body>")
    return _mjcf_nested(folder, [body] + [("<frame>", "</frame>")] * (nesting - 3))


# format -> (writer, the limit, the dimension at the limit, what the refusal says)
Depth = tuple[Callable[[Path, int], str], int, int, str]
FORMATS: dict[str, Depth] = {
    "urdf": (_urdf_chain, MAX_DEPTH, MAX_DEPTH, f"more than {MAX_DEPTH} joints deep"),
    "xacro": (_xacro_chain, MAX_DEPTH, MAX_DEPTH, f"more than {MAX_DEPTH} joints deep"),
    "sdf": (_sdf_chain, MAX_DEPTH, MAX_DEPTH, f"more than {MAX_DEPTH} joints deep"),
    "mjcf bodies": (
        _mjcf_chain,
        MAX_BODY_DEPTH,
        MAX_BODY_DEPTH,
        f"bodies nested more than {MAX_BODY_DEPTH:,} deep",
    ),
    "mjcf frames": (_mjcf_frames, MAX_NESTING, 1, f"elements nested more than {MAX_NESTING:,}"),
}


def test_the_limits_are_the_documented_numbers() -> None:
    assert (MAX_DEPTH, MAX_DEPTH_SUM, MAX_BODY_DEPTH, MAX_NESTING) == (1000, 500_500, 1000, 2048)
    assert MAX_DEPTH * (MAX_DEPTH + 1) // 2 <= MAX_DEPTH_SUM  # a chain at MAX_DEPTH is read


@pytest.mark.bounded
@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_a_tree_at_the_depth_limit_gets_a_report(fmt: str, tmp_path: Path) -> None:
    write, limit, dimension, _ = FORMATS[fmt]
    args = ("inspect", "--format", "json", write(tmp_path, limit))
    result = measured(*args, cwd=tmp_path, forked=True)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    assert json.loads(result.run.stdout)["dimension"] == dimension


@pytest.mark.bounded
@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_a_tree_past_the_depth_limit_is_refused_in_one_line(fmt: str, tmp_path: Path) -> None:
    write, limit, _, said = FORMATS[fmt]
    result = measured("inspect", write(tmp_path, limit + 1), cwd=tmp_path, forked=True)
    assert said in assert_bounded_error(result, "too-deep")


@pytest.mark.bounded
def test_an_attached_model_adds_its_depth(tmp_path: Path) -> None:
    # 600 bodies here, 401 in the attached model: 1,001 on one path, as MuJoCo builds it.
    _mjcf_chain(tmp_path, 600)
    deep = (tmp_path / "deep.xml").read_text()
    (tmp_path / "deep.xml").write_text(
        deep.replace(
            "<worldbody>", '<asset><model name="arm" file="arm/arm.xml"/></asset><worldbody>'
        )
    )
    last = (tmp_path / "part2.xml").read_text()
    (tmp_path / "part2.xml").write_text(
        last.replace('<body name="b599">', '<body name="b599"><attach model="arm" prefix="a"/>')
    )
    (tmp_path / "arm").mkdir()
    _mjcf_chain(tmp_path / "arm", 401)
    (tmp_path / "arm" / "deep.xml").rename(tmp_path / "arm" / "arm.xml")
    # MuJoCo finds the files it is given by base name: the arm's parts need names of their own.
    for file in sorted((tmp_path / "arm").iterdir()):
        file.write_text(file.read_text().replace('file="part', 'file="arm_part'))
        if file.name.startswith("part"):
            file.rename(file.with_name(f"arm_{file.name}"))
    result = measured("inspect", "deep.xml", cwd=tmp_path, forked=True)
    message = assert_bounded_error(result, "too-deep")
    assert f"bodies nested more than {MAX_BODY_DEPTH:,} deep" in message
    assert "(in part2.xml, line 1)" in message


@contextlib.contextmanager
def _deep_folders(top: Path, depth: int, file: str, text: str) -> Iterator[None]:
    """``top/d/d/.../d/file`` (``depth`` folders below ``top``), made and removed by loops.

    A pull request can commit such a tree; os.makedirs, pathlib and shutil.rmtree recurse
    on it in Python 3.11, so pytest's own clean-up would fail.
    """
    folders = [str(top)] + [os.path.join(top, *["d"] * k) for k in range(1, depth + 1)]
    path = os.path.join(folders[-1], file)
    for folder in folders:
        os.mkdir(folder)
    try:
        with open(path, "w") as out:
            out.write(text)
        yield
    finally:
        if os.path.exists(path):
            os.remove(path)
        for folder in reversed(folders):
            os.rmdir(folder)


ONE_JOINT = (
    '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="a"/>'
    '<link name="b"/><joint name="j" type="continuous"><parent link="a"/>'
    '<child link="b"/></joint></robot>'
)


@pytest.mark.bounded
def test_a_deep_folder_tree_under_a_package_path_is_walked_without_recursion(
    tmp_path: Path,
) -> None:
    # 1,100 nested folders: Python 3.11's os.walk recursed once a level and died of
    # RecursionError; the search for packages is a loop now, and finds the package at
    # the bottom.
    (tmp_path / "r.urdf.xacro").write_text(ONE_JOINT)
    manifest = "<package><name>bottom</name></package>"
    with _deep_folders(tmp_path / "packages", 1100, "package.xml", manifest):
        args = ("inspect", "--format", "json", "r.urdf.xacro", "--package-path", "packages")
        result = measured(*args, cwd=tmp_path, forked=True)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    assert json.loads(result.run.stdout)["dimension"] == 1


@pytest.mark.bounded
def test_a_quoted_double_star_pattern_walks_a_deep_folder_tree_without_recursion(
    tmp_path: Path,
) -> None:
    # 1,200 nested folders under a quoted `**` pattern, as CI scripts pass them: the walk
    # recursed once a folder and ended in "internal error: RecursionError" at 1,100; it
    # is a loop now, and finds the robot at the bottom.
    with _deep_folders(tmp_path / "robots", 1200, "r.urdf", ONE_JOINT):
        args = ("inspect", "--format", "json", "robots/**/*.urdf")
        result = measured(*args, cwd=tmp_path, forked=True)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    report = json.loads(result.run.stdout)
    assert (report["source"]["path"], report["dimension"]) == (
        "robots/" + "d/" * 1200 + "r.urdf",
        1,
    )


# The tree that takes Pinocchio the most memory for a depth sum: its memory grows with the
# sum, more with the degrees of freedom on each joint's chain, and with each joint's
# degrees of freedom before it in Pinocchio's order. So: every joint cspace reads, as
# many degrees of freedom as it reads, a chain of the joints with the most (floating; in
# SDF, ball) as deep as the sum allows, and every other joint a leaf under its last link,
# as many of the same kind as the degrees of freedom allow first (names in the order of
# the file: Pinocchio visits siblings by name), the rest continuous. 100 deep with 4,900
# leaves adds up to 499,950 and took 512 MiB (xacro 517, SDF 438); the same shape 150
# deep (743,675), 546 MiB as xacro; with the floating leaves last, 100 deep, 459 MiB.
BROOM_KIND = {"urdf": "floating", "xacro": "floating", "sdf": "ball"}


def _broom_depth() -> int:
    """The deepest chain of the broom whose depths add up to at most MAX_DEPTH_SUM."""
    depth = 1
    while _broom_sum(depth + 1) <= MAX_DEPTH_SUM:
        depth += 1
    return depth


def _broom_sum(depth: int) -> int:
    return depth * (depth + 1) // 2 + (MAX_JOINTS - depth) * (depth + 1)


def _broom(folder: Path, fmt: str, depth: int) -> tuple[str, int]:
    """The broom ``depth`` deep, written to ``folder``; its file name and dimension."""
    kind = BROOM_KIND[fmt]
    dof = DOF[JointKind.SPHERICAL if kind == "ball" else JointKind.FLOATING]
    leaves = MAX_JOINTS - depth
    heavy = min(leaves, (MAX_DOF - dof * depth - leaves) // (dof - 1))
    kinds = [kind] * depth + [kind] * heavy + ["continuous"] * (leaves - heavy)
    parents = [f"l{k}" for k in range(depth)] + [f"l{depth}"] * leaves
    sdf = fmt == "sdf"
    parts = ['<sdf version="1.7"><model name="broom">' if sdf else '<robot name="broom">']
    if not sdf:
        parts.append('<link name="l0"/>')
    for k, (joint_kind, parent) in enumerate(zip(kinds, parents, strict=True), start=1):
        ends = f"<parent>{parent if parent != 'l0' else 'world'}</parent><child>l{k}</child>"
        if not sdf:
            ends = f'<parent link="{parent}"/><child link="l{k}"/>'
        joint = f'<joint name="j{k:04d}" type="{joint_kind}">{ends}</joint>'  # in name order
        parts.append(f'<link name="l{k}"/>{joint}')
    parts.append("</model></sdf>" if sdf else "</robot>")
    name = {"urdf": "broom.urdf", "xacro": "broom.urdf.xacro", "sdf": "broom.sdf"}[fmt]
    (folder / name).write_text("\n".join(parts))
    return name, dof * (depth + heavy) + leaves - heavy


@pytest.mark.bounded
@pytest.mark.parametrize("fmt", sorted(BROOM_KIND))
def test_the_worst_tree_at_the_depth_sum_limit_gets_a_report(fmt: str, tmp_path: Path) -> None:
    depth = _broom_depth()
    assert _broom_sum(depth) > MAX_DEPTH_SUM - MAX_JOINTS  # as close to the limit as it goes
    name, dimension = _broom(tmp_path, fmt, depth)
    assert dimension == MAX_DOF
    result = measured("inspect", "--format", "json", name, cwd=tmp_path)
    assert result.run.code == 0, result.run.stderr
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    assert json.loads(result.run.stdout)["dimension"] == dimension


@pytest.mark.bounded
@pytest.mark.parametrize("fmt", sorted(BROOM_KIND))
def test_a_tree_past_the_depth_sum_limit_is_refused_in_one_line(fmt: str, tmp_path: Path) -> None:
    depth = _broom_depth() + 1
    assert _broom_sum(depth) > MAX_DEPTH_SUM and depth <= MAX_DEPTH
    name, _ = _broom(tmp_path, fmt, depth)
    result = measured("inspect", name, cwd=tmp_path, forked=True)
    message = assert_bounded_error(result, "too-deep")
    assert f"depths add up to more than {MAX_DEPTH_SUM:,}" in message
