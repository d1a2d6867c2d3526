"""Hostile XML: bounded time and memory, a clear message, and no other file ever read.

Every case runs the installed `cspace` command under a small Python parent that reports
the CPU time of the child and its own children, and their peak resident memory (see
``conftest.measured``): CPU time, so a busy machine cannot fail a case. The bounds are
generous for CI machines; a case that loops, recurses without end or expands
entities would blow through them by orders of magnitude. Hostile xacro, MJCF includes
and the sandbox are in ``test_untrusted.py``.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import PEAK_MIB, SECONDS, assert_bounded_error, cspace_command, measured


def _laughs() -> str:
    levels = ['<!ENTITY l0 "lol">']
    levels += [f'<!ENTITY l{k} "{f"&l{k - 1};" * 10}">' for k in range(1, 10)]
    return (
        '<?xml version="1.0"?>\n<!DOCTYPE robot [\n'
        + "\n".join(levels)
        + '\n]>\n<robot name="&l9;"><link name="&l9;"/></robot>\n'
    )


@pytest.mark.bounded
def test_billion_laughs(tmp_path: Path) -> None:
    (tmp_path / "laughs.urdf").write_text(_laughs())
    message = assert_bounded_error(measured("inspect", "laughs.urdf", cwd=tmp_path), "xml-unsafe")
    assert "laughs.urdf:3: declares the XML entity 'l0'" in message
    assert "lollol" not in message


@pytest.fixture
def secret(tmp_path: Path) -> Path:
    path = tmp_path / "secret.txt"
    path.write_text("TOP-SECRET-7f3a9c\n")
    return path


EXTERNAL = {
    "entity-in-attribute": '<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{f}">]>\n'
    '<robot name="r"><link name="&x;"/></robot>',
    "entity-in-text": '<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{f}">]>\n'
    '<robot name="r"><link name="base"/><gazebo>&x;</gazebo></robot>',
    "parameter-entity": '<!DOCTYPE robot [<!ENTITY % x SYSTEM "file://{f}"> %x;]>\n'
    '<robot name="r"><link name="base"/></robot>',
    "passwd": '<!DOCTYPE robot [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
    '<robot name="r"><link name="&x;"/></robot>',
}


@pytest.mark.bounded
@pytest.mark.parametrize("case", sorted(EXTERNAL))
def test_external_entities_are_refused_unread(case: str, secret: Path, tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_text(EXTERNAL[case].format(f=secret))
    result = measured("inspect", "robot.urdf", cwd=tmp_path)
    message = assert_bounded_error(result, "xml-unsafe")
    assert "declares the XML entity 'x'" in message
    everything = result.run.stdout + result.run.stderr
    assert "TOP-SECRET" not in everything
    assert "root:" not in everything  # the first line of /etc/passwd


@pytest.mark.bounded
def test_an_external_dtd_or_xinclude_is_never_loaded(secret: Path, tmp_path: Path) -> None:
    (tmp_path / "robot.urdf").write_text(
        f'<!DOCTYPE robot SYSTEM "file://{secret}">\n'
        '<robot name="r" xmlns:xi="http://www.w3.org/2001/XInclude"><link name="base"/>'
        f'<xi:include href="{secret}" parse="text"/></robot>'
    )
    result = measured("inspect", "robot.urdf", "--format", "json", cwd=tmp_path)
    assert result.run.code == 0, result
    assert json.loads(result.run.stdout)["robot"] == "r"
    assert "TOP-SECRET" not in result.run.stdout + result.run.stderr


@pytest.mark.bounded
def test_a_200_mb_file_is_refused_before_it_is_read(tmp_path: Path) -> None:
    path = tmp_path / "huge.urdf"
    with path.open("wb") as handle:  # sparse: 200 MB on paper, nothing on disk
        handle.truncate(200 * 1024 * 1024)
    message = assert_bounded_error(
        measured("inspect", "huge.urdf", cwd=tmp_path), "file-unreadable"
    )
    assert "file is 209,715,200 bytes, larger than the 67,108,864-byte limit" in message


@pytest.mark.bounded
def test_a_device_is_refused_unread(tmp_path: Path) -> None:
    message = assert_bounded_error(
        measured("inspect", "/dev/zero", cwd=tmp_path), "file-unreadable"
    )
    assert "/dev/zero: is a character device, not a regular file" in message


def test_an_endless_stream_on_standard_input_is_read_only_up_to_the_limit(
    tmp_path: Path,
) -> None:
    with open("/dev/zero", "rb") as zeros:
        done = subprocess.run(
            [*cspace_command(), "inspect", "-"], stdin=zeros, capture_output=True, timeout=60
        )
    assert done.returncode == 2
    assert b"input is larger than the 67,108,864-byte limit" in done.stderr


@pytest.mark.bounded
def test_deeply_nested_xml(tmp_path: Path) -> None:
    depth = 100_000
    (tmp_path / "deep.urdf").write_text(
        '<robot name="r"><link name="a"/>' + "<x>" * depth + "</x>" * depth + "</robot>"
    )
    message = assert_bounded_error(measured("inspect", "deep.urdf", cwd=tmp_path), "xml-syntax")
    assert "Excessive depth" in message


@pytest.mark.bounded
def test_millions_of_tags(tmp_path: Path) -> None:
    (tmp_path / "tags.urdf").write_text('<robot name="r">' + "<a/>" * 3_000_000 + "</robot>")
    message = assert_bounded_error(
        measured("inspect", "tags.urdf", cwd=tmp_path), "file-unreadable"
    )
    assert "3,000,002 XML tags" in message


@pytest.mark.bounded
def test_a_huge_attribute(tmp_path: Path) -> None:
    (tmp_path / "attr.urdf").write_text(
        f'<robot name="{"x" * 20_000_000}"><link name="a"/></robot>'
    )
    assert_bounded_error(measured("inspect", "attr.urdf", cwd=tmp_path), "xml-syntax")


@pytest.mark.bounded
@pytest.mark.parametrize("tag", ["robot", "link"])
def test_hundreds_of_thousands_of_attributes_on_one_element(tmp_path: Path, tag: str) -> None:
    # lxml reads an element's attribute values, and Pinocchio parses them, in time
    # quadratic in their number: 300,000 on one element take minutes unbounded.
    many = " ".join(f'a{i}="1"' for i in range(300_000))
    document = (
        f'<robot name="r" {many}><link name="a"/></robot>'
        if tag == "robot"
        else f'<robot name="r"><link name="a" {many}/></robot>'
    )
    (tmp_path / "attributes.urdf").write_text(document)
    message = assert_bounded_error(
        measured("inspect", "attributes.urdf", cwd=tmp_path), "file-unreadable"
    )
    assert f"element <{tag}> has 300,00" in message


def _chain(joints: int) -> str:
    parts = ['<robot name="snake">', '<link name="l0"/>']
    for k in range(1, joints + 1):
        parts.append(
            f'<link name="l{k}"/><joint name="j{k}" type="revolute"><parent link="l{k - 1}"/>'
            f'<child link="l{k}"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    parts.append("</robot>")
    return "\n".join(parts)


@pytest.mark.bounded
def test_a_kinematic_chain_deep_enough_to_crash_pinocchio(tmp_path: Path) -> None:
    # Pinocchio's URDF parser recurses once per joint: 7,538 deep on a 16 MiB stack, it
    # dies of SIGSEGV; cspace stops far sooner, at 1,000 (for its memory's sake).
    (tmp_path / "snake.urdf").write_text(_chain(4900))
    message = assert_bounded_error(measured("inspect", "snake.urdf", cwd=tmp_path), "too-deep")
    assert "more than 1000 joints deep at joint 'j1001'" in message


@pytest.mark.bounded
def test_substitutions_in_every_attribute_are_not_all_collected(tmp_path: Path) -> None:
    # 510,000 attributes holding ${x}: finding the first is enough to refuse the file.
    # Keeping every match (as Python strings) took 100 MiB more than the parse itself.
    rows = (" ".join(f'a{i}="${{x}}"' for i in range(255)) for _ in range(2000))
    body = "\n".join(f"<x{k} {attrs}/>" for k, attrs in enumerate(rows))
    (tmp_path / "subst.urdf").write_text(f'<robot name="r">\n{body}\n</robot>\n')
    result = measured("inspect", "subst.urdf", cwd=tmp_path)
    message = assert_bounded_error(result, "xacro-not-requested")
    assert "still holds the substitution '${x}'" in message
    assert result.peak_mib < 210, result  # the parse of a 6 MB file: about 150 MiB


@pytest.mark.bounded
def test_many_joints_under_a_deep_chain(tmp_path: Path) -> None:
    # Pinocchio keeps every joint's chain to the root: 3,300 leaves under a 1,700-deep
    # chain (depths adding up to 7.06 million) took 628 MiB, 4,000 under a 1,000-deep
    # one (4.5 million) 510 MiB. Here 4,000 leaves are as deep as cspace reads, 1,000.
    chain = _chain(999).removesuffix("</robot>")
    leaves = "".join(
        f'<link name="f{k}"/><joint name="f{k}" type="continuous"><parent link="l999"/>'
        f'<child link="f{k}"/></joint>'
        for k in range(4000)
    )
    (tmp_path / "broom.urdf").write_text(chain + leaves + "</robot>")
    message = assert_bounded_error(measured("inspect", "broom.urdf", cwd=tmp_path), "too-deep")
    # The second leaf passes the limit (leaves are counted in order of name, as
    # Pinocchio visits them: f0, f1, f10, ...).
    assert "depths add up to more than 500,500 at joint 'f1'" in message


def test_a_deep_chain_builds_on_any_callers_thread(tmp_path: Path) -> None:
    # 1,000 deep (as deep as cspace reads): beyond what Pinocchio's parser survives on a
    # 2 MiB thread stack (937), which is what glibc gives threads under `ulimit -s
    # unlimited`. cspace builds on a thread of its own, so a caller's small thread does
    # not matter.
    (tmp_path / "snake.urdf").write_text(_chain(1000))
    script = (
        "import threading, cspace\n"
        "threading.stack_size(2 << 20)\n"
        "out = []\n"
        "t = threading.Thread(target=lambda: out.append(cspace.inspect('snake.urdf')))\n"
        "t.start(); t.join()\n"
        "print(out[0].dimension)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True, timeout=60
    )
    assert (done.returncode, done.stdout) == (0, "1000\n"), done.stderr


@pytest.mark.bounded
def test_tens_of_thousands_of_joints(tmp_path: Path) -> None:
    parts = ['<robot name="star"><link name="hub"/>']
    parts += [
        f'<link name="l{k}"/><joint name="j{k}" type="continuous"><parent link="hub"/>'
        f'<child link="l{k}"/></joint>'
        for k in range(20_000)
    ]
    (tmp_path / "star.urdf").write_text("".join([*parts, "</robot>"]))
    message = assert_bounded_error(
        measured("inspect", "star.urdf", cwd=tmp_path), "too-many-joints"
    )
    assert "20,001 links" in message


@pytest.mark.bounded
def test_meshes_and_package_paths_are_never_opened(tmp_path: Path) -> None:
    # Opening a FIFO without a writer blocks forever: if anything opened a mesh, the run
    # would hit the time bound instead of finishing.
    fifo = tmp_path / "mesh.stl"
    os.mkfifo(fifo)
    (tmp_path / "robot.urdf").write_text(
        '<robot name="r">'
        f'<link name="base"><visual><geometry><mesh filename="{fifo}"/></geometry></visual>'
        '<collision><geometry><mesh filename="package://nowhere/meshes/base.stl"/></geometry>'
        "</collision></link>"
        '<link name="arm"><visual><geometry><mesh filename="meshes/missing.dae"/></geometry>'
        '</visual><collision><geometry><mesh filename="file:///etc/passwd"/></geometry>'
        "</collision></link>"
        '<joint name="j" type="continuous"><parent link="base"/><child link="arm"/></joint>'
        "</robot>"
    )
    result = measured("inspect", "robot.urdf", "--format", "json", cwd=tmp_path)
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB
    assert result.run.code == 0, result
    assert json.loads(result.run.stdout)["manifold"]["notation"] == "S^1"
    assert "root:" not in result.run.stdout + result.run.stderr


@pytest.mark.bounded
@pytest.mark.parametrize("what", ["siblings", "mimics"])
def test_what_pinocchio_is_not_given_is_put_back_in_linear_time(tmp_path: Path, what: str) -> None:
    # The document for Pinocchio leaves out every element but links and joints (and the
    # <mimic> the report ignores) by taking them out of the tree and putting them back:
    # put back one by one at their index, 240,000 siblings took 91 s and 40,000 <mimic>
    # elements 9 s (80,000: 36 s). Each must stay within the usual bounds.
    if what == "siblings":
        extra, joint_body = "<g/>" * 240_000, ""
    else:
        extra, joint_body = "", '<mimic joint="f"/>' * 80_000
    (tmp_path / "robot.urdf").write_text(
        '<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
        '<joint name="f" type="floating"><parent link="a"/><child link="b"/></joint>'
        '<joint name="k" type="revolute"><parent link="b"/><child link="c"/>'
        f'<limit lower="-1" upper="1" effort="1" velocity="1"/>{joint_body}</joint>'
        f"{extra}</robot>"
    )
    result = measured("inspect", "robot.urdf", "--format", "json", cwd=tmp_path)
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB
    assert result.run.code in (0, 1), result
    assert json.loads(result.run.stdout)["nq"] == 8


@pytest.mark.bounded
def test_hundreds_of_misspelt_links_are_reported_within_the_bounds(tmp_path: Path) -> None:
    # "did you mean" scans every link: for the first few problems only (800 took 30 s)
    links = "".join(f'<link name="link_{k}"/>' for k in range(4200))
    joints = "".join(
        f'<joint name="j{k}" type="fixed"><parent link="lnk_{k}"/><child link="link_{k + 1}"/>'
        "</joint>"
        for k in range(800)
    )
    robot = tmp_path / "misspelt.urdf"
    robot.write_text(f'<robot name="r"><link name="link_x"/>{links}{joints}</robot>\n')
    result = measured("inspect", str(robot), cwd=tmp_path)
    assert result.cpu_seconds < SECONDS and result.peak_mib < PEAK_MIB, result
    lines = result.run.stderr.splitlines()
    assert result.run.code == 2 and len(lines) == 100
    assert "(did you mean 'link_0'?)" in lines[0] and "did you mean" not in lines[50]
